"""Shared fixtures: the source tree, the command-line binary and the bundled examples."""
import contextlib
import os
import pathlib
import signal
import threading

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("GEARNVH_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE_DIR / "examples"
IDLE_RATTLE = EXAMPLES / "idle_rattle.yaml"


@pytest.fixture(scope="session")
def gearnvh_exe():
    exe = os.environ.get("GEARNVH_EXE", str(SOURCE_DIR / "build" / "app" / "gearnvh"))
    if not os.path.exists(exe):
        pytest.fail(f"the gearnvh command is not built: {exe}")
    return exe


@contextlib.contextmanager
def interrupted_after(seconds):
    """Sends this process SIGINT (Ctrl-C) after `seconds` and expects KeyboardInterrupt from the
    body; skips when not on the main thread (signals reach only it)."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signals reach the main thread only")
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            yield
    finally:
        timer.cancel()
