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
    rows = [line for line in run.stdout.splitlines() if line.startswith("backlash")]
    assert len(rows) == 3  # one row per backlash: 50, 100, 150 um
    # At the lightest drag torque (0.1 N m, well below the wheel's inertial torque of ~0.6 N m)
    # the flanks rattle on both sides, and a wider backlash gives longer free flights, faster
    # impacts and a larger rattle index.
    lightest = [float(row.split(":")[1].split()[0]) for row in rows]
    assert all("double-sided" in row.split(":")[1].split("J")[1] for row in rows)
    assert lightest[0] < lightest[1] < lightest[2]
