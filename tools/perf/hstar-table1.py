#!/usr/bin/env python3
"""H* on every instance of the H* paper's Table I (issue 15), for one build or two side by side.

    python3 tools/perf/hstar-table1.py [--repeat N] [--planner P] BINARY [BINARY2]

For each instance: sum of costs, makespan, the planner's wall time (the plan file's
`runtime_ms`, median of N runs, default 3) and a hash of the paths, so two builds can be compared
on one machine in one run (their runs are interleaved, so load affects both alike) and plans
checked identical (same hash). Standard library only.
"""
import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
D = os.path.join(ROOT, "data", "hstar-paper")


def instances():
    for n in range(6, 16):
        yield f"1-{n}", f"{D}/scenario1/scenery.txt", f"{D}/scenario1/{n}coordinates.txt"
    for n in range(3, 7):
        yield f"2-{n}x4", f"{D}/scenario2/scenery_4rooms_B.txt", f"{D}/scenario2/{n}robots-per-room.txt"
    for n in (10, 15, 20, 25, 30):
        yield f"3-{n}", f"{D}/scenario3/scenery_warehouse.txt", f"{D}/scenario3/{n}warehouse"


def run(binary, planner, map_, scen, out):
    subprocess.run([binary, "-q", "solve", "--map", map_, "--scen", scen, "--planner", planner,
                    "--out", out], check=False)
    with open(out) as f:
        e = json.load(f)
    m = e.get("metrics") or {}
    return (m.get("sum_of_costs", "-"), m.get("makespan", "-"), e.get("runtime_ms", float("nan")),
            path_hash(e))


def path_hash(plan):
    """First 12 hex digits of the sha256 of a plan file's paths as compact JSON."""
    paths = json.dumps([a.get("path") for a in plan.get("agents", [])], separators=(",", ":"))
    return hashlib.sha256(paths.encode()).hexdigest()[:12]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--planner", default="hstar")
    ap.add_argument("binaries", nargs="+")
    a = ap.parse_args()
    if len(a.binaries) > 2:
        sys.exit("at most two binaries")
    head = "instance"
    for k, _ in enumerate(a.binaries):
        head += f" | soc{k + 1} | mksp{k + 1} | ms{k + 1} | paths{k + 1}"
    print(head + (" | same plan" if len(a.binaries) == 2 else ""))
    with tempfile.TemporaryDirectory() as tmp:
        for name, map_, scen in instances():
            results = {b: [] for b in a.binaries}
            for _ in range(a.repeat):
                for k, b in enumerate(a.binaries):
                    results[b].append(run(b, a.planner, map_, scen, os.path.join(tmp, f"{k}.json")))
            row = name
            for b in a.binaries:
                soc, mk, _, h = results[b][0]
                ms = statistics.median(r[2] for r in results[b])
                row += f" | {soc} | {mk} | {ms:.1f} | {h}"
            if len(a.binaries) == 2:
                row += " | " + ("yes" if results[a.binaries[0]][0][3] == results[a.binaries[1]][0][3] else "NO")
            print(row, flush=True)


if __name__ == "__main__":
    main()
