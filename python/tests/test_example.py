"""The worked example of docs/python.md (examples/python/doe_rattle.py) runs headless."""
import subprocess
import sys

from conftest import EXAMPLES


def test_doe_rattle_script_writes_its_plot(tmp_path):
    out = tmp_path / "doe.png"
    run = subprocess.run([sys.executable, str(EXAMPLES / "python" / "doe_rattle.py"), "--out",
                          str(out)], capture_output=True, text=True, env=None, timeout=300)
    assert run.returncode == 0, run.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = [l for l in run.stdout.splitlines() if l.startswith("backlash")]
    assert len(lines) == 3  # one row per backlash
