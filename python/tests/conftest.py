"""Finds the package under test and the CLI it is compared with.

An installed ``udc_studio`` (``pip install ./python``) is used as it is. Otherwise the package
is staged from this checkout: the Python sources of ``python/udc_studio`` beside the native
module that ``cargo build`` wrote (``target/debug/lib_native.so``, or ``$UDC_NATIVE_LIB``).
The CLI is ``target/debug/udc-studio`` (or ``$UDC_CLI``).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
TARGET = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))


def _stage() -> None:
    native = Path(os.environ.get("UDC_NATIVE_LIB", TARGET / "debug" / "lib_native.so"))
    if not native.is_file():
        raise RuntimeError(
            f"{native} is missing: build it with `cargo build -p udc-studio-python` "
            "or install the package with `pip install ./python`"
        )
    stage = Path(tempfile.mkdtemp(prefix="udc-studio-py-"))
    package = stage / "udc_studio"
    package.mkdir()
    for source in (REPO / "python" / "udc_studio").iterdir():
        if source.suffix in (".py", ".pyi") or source.name == "py.typed":
            (package / source.name).symlink_to(source)
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    shutil.copy(native, package / f"_native{suffix}")
    sys.path.insert(0, str(stage))
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(stage), *filter(None, [os.environ.get("PYTHONPATH")])]
    )


if os.environ.get("UDC_TEST_INSTALLED") != "1":
    _stage()


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `udc-studio` binary of the same checkout."""
    path = Path(os.environ.get("UDC_CLI", TARGET / "debug" / "udc-studio"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: build it with `cargo build`")
    return path


def run_cli(cli: Path, *args: str) -> subprocess.CompletedProcess:
    """Runs the CLI and returns the finished process (stdout and stderr as text)."""
    return subprocess.run([str(cli), *args], capture_output=True, text=True, check=False)
