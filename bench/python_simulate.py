#!/usr/bin/env python3
"""Python overhead on a simulate call: `gearnvh simulate --json` against gearnvh.simulate().

    PYTHONPATH=build/python python3 bench/python_simulate.py [--cycles N] [--repeat K]

Both run app::AnalyseOperatingPoint from the same static library on the same spec. Reported per
repetition (best of K): the solver's own wall time (summary.wall_s) through each path, and the
end-to-end time of the call (process start, YAML load and JSON print for the command line; model,
reduction, tables and result objects for the module). Nothing is asserted: a report, not a test.
"""
import argparse
import json
import os
import pathlib
import subprocess
import time

import gearnvh

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default=str(ROOT / "examples" / "idle_rattle.yaml"))
    parser.add_argument("--exe", default=os.environ.get("GEARNVH_EXE",
                                                         str(ROOT / "build" / "app" / "gearnvh")))
    parser.add_argument("--cycles", type=int, default=2000)
    parser.add_argument("--transient", type=int, default=500)
    parser.add_argument("--tier", default="1")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    cli_solver, cli_total, py_solver, py_total = [], [], [], []
    gb = gearnvh.load(args.file)
    for _ in range(args.repeat):
        start = time.perf_counter()
        out = subprocess.run([args.exe, "simulate", args.file, "--tier", args.tier, "--cycles",
                              str(args.cycles), "--transient", str(args.transient), "--json"],
                             check=True, capture_output=True, text=True).stdout
        cli_total.append(time.perf_counter() - start)
        cli_solver.append(json.loads(out)["summary"]["wall_s"])
        start = time.perf_counter()
        r = gearnvh.simulate(gb, tier=args.tier, cycles=args.cycles, transient=args.transient)
        py_total.append(time.perf_counter() - start)
        py_solver.append(r.summary.wall_s)
    print(f"simulate {args.file}, tier {args.tier}, {args.transient} + {args.cycles} cycles, "
          f"best of {args.repeat}")
    print(f"  {'':28}{'command line':>14}{'Python':>14}{'Python/CLI':>12}")
    for label, cli, py in (("solver wall time (s)", cli_solver, py_solver),
                           ("whole call (s)", cli_total, py_total)):
        print(f"  {label:28}{min(cli):14.4f}{min(py):14.4f}{min(py) / min(cli):12.3f}")


if __name__ == "__main__":
    main()
