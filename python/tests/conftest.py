"""Shared fixtures: the source tree, the command-line binary and the bundled examples."""
import os
import pathlib

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
