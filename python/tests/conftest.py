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


@pytest.fixture
def on_gpu():
    """``on_gpu(f, *args, **kw)`` is ``f(*args, backend="gpu", **kw)`` on any adapter (a
    software one included); on a machine with none, `gpu` must be a clear error, and the test
    is skipped saying so."""

    def call(f, *args, **kwargs):
        try:
            return f(*args, backend="gpu", **kwargs)
        except ValueError as e:
            assert "no GPU adapter" in str(e)
            pytest.skip(f"no GPU adapter on this machine: {e}")

    return call


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


def assert_ctrl_c_stops(call: str, cwd: Path, within_s: float, setup: str = "") -> None:
    """Runs ``setup`` once, then ``call`` (Python code using ``udc``) over and over in a child
    process, sends it Ctrl-C half a second after the calls start, and asserts that it raised
    ``KeyboardInterrupt`` within ``within_s`` seconds of the signal. The loop means the work cannot finish before the
    signal however fast the machine; Python raises a pending interrupt anyway once a call
    returns, so ``within_s`` must be shorter than one call on the test machine for the time to
    tell a cancelled call from one that ran to its end.

    The child sets its own SIGINT disposition: started from a shell that ignores SIGINT
    (``nohup … &``, cron, some CI runners) it would inherit the ignored signal, and Python
    installs no handler for a signal ignored at start. It runs in ``cwd`` so that
    ``python/udc_studio`` (without its native module) does not shadow the staged package."""
    script = "\n".join(
        ["import signal", "signal.signal(signal.SIGINT, signal.default_int_handler)",
         "import numpy as np", "import udc_studio as udc", setup, 'print("started", flush=True)',
         "for _ in range(1000):", f"    {call}", 'print("finished", flush=True)']
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, env=os.environ.copy(), cwd=cwd,
    )
    assert proc.stdout.readline().strip() == "started"
    time.sleep(0.5)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    seconds_to_stop = time.monotonic() - sent
    assert "KeyboardInterrupt" in err, err
    assert "finished" not in out and proc.returncode != 0
    assert seconds_to_stop < within_s, seconds_to_stop
