#!/usr/bin/env python3
"""Per 100-step window of a LoRR output JSON (MAPF_T, one action per step): errands finished and
the shares of forward / wait / turn actions over all robot-steps, plus the share of robot-steps
without a task. Standard library only. docs/performance.md, "Why the warehouse slows down".

usage: python3 tools/lifelong_shares.py out.json [out2.json ...]
"""
import collections
import json
import sys


def shares(path):
    d = json.load(open(path))
    n, steps = d["teamSize"], d["makespan"]
    errands = collections.Counter(t // 100 for t, _agent, _task, _done in d["events"])
    acts = collections.Counter()
    no_task = collections.Counter()
    for r in range(n):
        sched = d["actualSchedule"][r]
        assigned = [tuple(map(int, x.split(":"))) for x in sched.split(",") if x] if sched else []
        task, j = -1, 0
        for t, a in enumerate(d["actualPaths"][r].split(",")[:steps]):
            while j < len(assigned) and assigned[j][0] <= t:
                task = assigned[j][1]
                j += 1
            kind = "forward" if a == "F" else ("turn" if a in ("R", "C") else "wait")
            acts[(t // 100, kind)] += 1
            no_task[t // 100] += task == -1
    print(f"{path}: {d['numTaskFinished']} tasks, {d['numEntryTimeouts']} late steps")
    print("steps      errands  forward%  wait%  turn%  no task%")
    for w in range((steps + 99) // 100):
        total = sum(acts[(w, k)] for k in ("forward", "wait", "turn")) or 1
        print(
            f"{w * 100:4d}-{w * 100 + 99:<4d} {errands[w]:8d} "
            + " ".join(f"{100 * acts[(w, k)] / total:6.1f}" for k in ("forward", "wait", "turn"))
            + f" {100 * no_task[w] / total:8.1f}"
        )


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for p in sys.argv[1:]:
        shares(p)
