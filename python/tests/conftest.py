"""Finds the package under test and the CLI it is compared with.

The package is staged from this checkout (``python/stage.py``): the Python sources of
``python/udc_studio`` beside the native module that ``cargo build`` wrote
(``target/debug/lib_native.so``, or ``$UDC_NATIVE_LIB``). With ``UDC_TEST_INSTALLED=1`` the
installed package (``pip install ./python``) is tested instead.
The CLI is ``target/debug/udc-studio`` (or ``$UDC_CLI``).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

# The staging module sits in python/, which must not stay on the path: its udc_studio folder
# (without the native module) would shadow the staged or installed package.
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from stage import REPO, TARGET, stage  # noqa: E402

sys.path.pop(0)

if os.environ.get("UDC_TEST_INSTALLED") != "1":
    stage()


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


def interrupted(script: str, cwd: Path) -> subprocess.CompletedProcess:
    """Runs a Python script that prints "started" before a long call, sends it Ctrl-C half a
    second later, and returns the finished process (stdout and stderr as text, and
    ``seconds_to_stop``, from the signal to the process's end). The script runs
    in ``cwd`` so that ``python/udc_studio`` (without its native module) does not shadow the
    staged package."""
    proc = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, env=os.environ.copy(), cwd=cwd,
    )
    assert proc.stdout.readline().strip() == "started"
    time.sleep(0.5)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    done = subprocess.CompletedProcess(proc.args, proc.returncode, "started\n" + out, err)
    # How long the call took to stop: Python raises a pending KeyboardInterrupt only when the
    # call returns, so a call that ignored Ctrl-C would run to its end first.
    done.seconds_to_stop = time.monotonic() - sent
    return done
