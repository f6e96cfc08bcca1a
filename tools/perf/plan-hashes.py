#!/usr/bin/env python3
"""Path hashes of the plans issue 15's speed work must not change, for one build or two.

    python3 tools/perf/plan-hashes.py BINARY [BINARY2]

Runs `mrpp solve` on random-32-32-20 (bundled in data/movingai): H* with 100 agents on the
random-1 to random-5 scenarios, and CA*, HCA* and WHCA* with 60 agents on random-1. Prints the
sum of costs and the first 12 hex digits of the sha256 of the JSON list of paths (compact
separators), the hash docs/performance.md quotes; with two binaries, whether they agree.
`tools/perf/hstar-table1.py` does the same for the H* paper's Table I. Standard library only.
"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
path_hash = __import__("hstar-table1").path_hash

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
M = os.path.join(ROOT, "data", "movingai")
RUNS = [(f"hstar random-{k}", "hstar", k, 100) for k in range(1, 6)] + [
    (f"{p} random-1", p, 1, 60) for p in ("ca", "hca", "whca")
]


def run(binary, planner, k, agents, out):
    subprocess.run([binary, "-q", "solve", "--map", f"{M}/random-32-32-20.map", "--scen",
                    f"{M}/random-32-32-20-random-{k}.scen", "-N", str(agents), "--planner",
                    planner, "--out", out], check=False)
    with open(out) as f:
        e = json.load(f)
    return (e.get("metrics") or {}).get("sum_of_costs", "-"), path_hash(e)


def main():
    binaries = sys.argv[1:]
    if not 1 <= len(binaries) <= 2:
        sys.exit(__doc__)
    same = True
    with tempfile.TemporaryDirectory() as tmp:
        for name, planner, k, agents in RUNS:
            got = [run(b, planner, k, agents, os.path.join(tmp, f"{i}.json"))
                   for i, b in enumerate(binaries)]
            row = f"{name} | " + " | ".join(f"{soc} {h}" for soc, h in got)
            if len(got) == 2:
                row += " | " + ("same" if got[0] == got[1] else "DIFFERENT")
                same &= got[0] == got[1]
            print(row, flush=True)
    sys.exit(0 if same else 1)


if __name__ == "__main__":
    main()
