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
# A train whose tiers 2 and 3 stop out of range (shared with the C++ tests).
STRONG_RATTLE_TRAIN = SOURCE_DIR / "tests" / "data" / "strong_rattle_train.yaml"


def strong_rattle_file(tmp_path):
    """examples/flexible_shafts.yaml at the strong-rattle point (7548 rpm, 20 N m, order 15.5 of
    2e5 rad/s^2), whose tiers 2 and 3 grow without bound and stop out of range
    (tests/support/example_variant.h, kStrongRattlePoint)."""
    text = (EXAMPLES / "flexible_shafts.yaml").read_text()
    point = "  speed: 3000 rpm\n  torque: 200 N*m\n"
    assert point in text
    path = tmp_path / "strong_rattle.yaml"
    path.write_text(text.replace(point, "  speed: 7548.387097 rpm\n  torque: 20 N*m\n"
                                        "  excitation:\n"
                                        "    - {order: 15.5, amplitude: 200000 rad/s^2, "
                                        "phase: 0 deg}\n"))
    return path


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
