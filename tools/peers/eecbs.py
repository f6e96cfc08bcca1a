#!/usr/bin/env python3
"""Run EECBS (Jiaoyang-Li/EECBS, built by hand beside mrpp) as an `mrpp bench run --peer` and write
its result as LaCAM text, the format the bench reads from peers.

    --peer 'eecbs1=python3 tools/peers/eecbs.py /path/to/EECBS/build/eecbs --out {out} -- \
        -m {map} -a {scen} -k {agents} -t {time_limit} --suboptimality 1'

Everything after `--` goes to EECBS unchanged; this script adds `-o` (its statistics CSV) and
`--outputPaths` (its paths) in a temporary folder, and `-s 0` (quiet). It writes `solved=1`,
`soc`, `makespan`, `starts`, `goals`, `comp_time` (EECBS's own runtime, ms), `solver=eecbs` and the `solution=`
lines (one configuration per step, `(x,y)` = (column, row); an agent whose path has ended
repeats its last cell), or `solved=0` when EECBS found no plan. The sums here are recounted by
`mrpp bench` from the paths. Standard library only; nothing of EECBS is copied.
"""

import csv
import os
import re
import subprocess
import sys
import tempfile


def main(argv):
    if "--" not in argv or "--out" not in argv:
        sys.exit("usage: eecbs.py EECBS_BINARY --out OUT -- EECBS_ARGS...")
    cut = argv.index("--")
    ours, theirs = argv[:cut], argv[cut + 1:]
    binary = ours[0]
    out = ours[ours.index("--out") + 1]
    with tempfile.TemporaryDirectory() as tmp:
        stats = os.path.join(tmp, "stats.csv")
        paths_file = os.path.join(tmp, "paths.txt")
        run = subprocess.run(
            [binary, *theirs, "-s", "0", "-o", stats, "--outputPaths", paths_file],
            stdout=subprocess.DEVNULL,
        )
        runtime_s = None
        if os.path.exists(stats):
            with open(stats, newline="") as f:
                rows = list(csv.DictReader(f))
            if rows:
                runtime_s = float(rows[-1]["runtime"])
        paths = []
        if run.returncode == 0 and os.path.exists(paths_file):
            with open(paths_file) as f:
                for line in f:
                    if not line.startswith("Agent "):
                        continue
                    cells = re.findall(r"\((\d+),(\d+)\)", line)
                    # EECBS writes (row, column).
                    paths.append([(int(c), int(r)) for r, c in cells])
    lines = [f"agents={len(paths)}", "solver=eecbs"]
    if runtime_s is not None:
        lines.append(f"comp_time={round(runtime_s * 1000)}")
    if not paths or any(not p for p in paths):
        lines.append("solved=0")
        lines.append("solution=")
    else:
        def cost(p):
            # Steps until the agent is on its last cell for good.
            k = len(p) - 1
            while k > 0 and p[k - 1] == p[-1]:
                k -= 1
            return k
        makespan = max(len(p) for p in paths) - 1
        lines += [
            "solved=1",
            f"soc={sum(cost(p) for p in paths)}",
            f"makespan={max(cost(p) for p in paths)}",
            "starts=" + "".join(f"({x},{y})," for x, y in (p[0] for p in paths)),
            "goals=" + "".join(f"({x},{y})," for x, y in (p[-1] for p in paths)),
            "solution=",
        ]
        for t in range(makespan + 1):
            lines.append(f"{t}:" + "".join(f"({x},{y})," for x, y in (p[min(t, len(p) - 1)] for p in paths)))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
