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


def test_the_worked_example_in_the_docs_runs(tmp_path, monkeypatch):
    """The first Python block of docs/python.md, as printed, from a folder holding examples/."""
    import re
    from conftest import SOURCE_DIR
    text = (SOURCE_DIR / "docs" / "python.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    (tmp_path / "examples").symlink_to(EXAMPLES)
    monkeypatch.chdir(tmp_path)
    namespace = {}
    exec(compile(code, "docs/python.md", "exec"), namespace)
    assert (tmp_path / "rattle_doe.png").read_bytes()[:4] == b"\x89PNG"
    index = namespace["index"]
    assert index.shape == (3, 3)
    # Same grid as the script: double-sided rattle at the lightest drag grows with the backlash.
    assert index[0, 0] < index[1, 0] < index[2, 0]
