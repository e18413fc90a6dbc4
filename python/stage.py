"""Stages the package from this checkout, without installing it: the Python sources of
``python/udc_studio`` (as links) beside the native module that ``cargo build`` wrote
(``target/debug/lib_native.so``, or ``$UDC_NATIVE_LIB``), in a temporary folder put first on
``sys.path`` and ``PYTHONPATH``, removed when the process ends. The tests (``tests/conftest.py``) and
``benches/python_peers.py`` use it.
"""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import sysconfig
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TARGET = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))


def stage() -> Path:
    """Stages the package; returns the native module it used. ``RuntimeError`` if unbuilt."""
    native = Path(os.environ.get("UDC_NATIVE_LIB", TARGET / "debug" / "lib_native.so"))
    if not native.is_file():
        raise RuntimeError(
            f"{native} is missing: build it with `cargo build -p udc-studio-python` "
            "or install the package with `pip install ./python`"
        )
    folder = Path(tempfile.mkdtemp(prefix="udc-studio-py-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    package = folder / "udc_studio"
    package.mkdir()
    for source in (REPO / "python" / "udc_studio").iterdir():
        if source.suffix in (".py", ".pyi") or source.name == "py.typed":
            (package / source.name).symlink_to(source)
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    shutil.copy(native, package / f"_native{suffix}")
    sys.path.insert(0, str(folder))
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(folder), *filter(None, [os.environ.get("PYTHONPATH")])]
    )
    return native
