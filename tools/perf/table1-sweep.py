#!/usr/bin/env python3
"""One planner with one set of parameters on every instance of the H* paper's Table I, seeds 0-9.

    python3 tools/perf/table1-sweep.py [--planner P] [--seeds N] BINARY [-p KEY=VALUE ...]

Prints how many of the 19 x N runs were solved and the mean and largest `runtime_ms` of the
runs, for the option sweeps quoted in module docs (e.g. NSGA-III's `generations`). Standard
library only; the instances are those of `tools/perf/hstar-table1.py`.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
table1 = __import__("hstar-table1")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--planner", default="nsga3")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("-p", "--param", action="append", default=[])
    ap.add_argument("binary")
    a = ap.parse_args()
    solved, times = 0, []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "plan.json")
        for _, map_, scen in table1.instances():
            for seed in range(a.seeds):
                cmd = [a.binary, "-q", "solve", "--map", map_, "--scen", scen, "--planner",
                       a.planner, "--seed", str(seed), "--out", out]
                for p in a.param:
                    cmd += ["-p", p]
                subprocess.run(cmd, check=False)
                with open(out) as f:
                    e = json.load(f)
                solved += bool(e.get("solved"))
                times.append(e.get("runtime_ms", float("nan")))
    runs = len(times)
    print(f"{a.planner} {' '.join(a.param) or '(defaults)'}: solved {solved} of {runs}, "
          f"runtime mean {statistics.mean(times):.1f} ms, max {max(times):.1f} ms")


if __name__ == "__main__":
    main()
