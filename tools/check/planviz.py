#!/usr/bin/env python3
"""Independent checker of one-shot grid plans in PlanViz's LoRR JSON (stdlib only).

Usage: python3 tools/check/planviz.py MAP PLAN.json [SCEN]
       python3 tools/check/planviz.py --self-test

Written from what PlanViz's 2024 loader reads (MAPF-Competition/PlanViz commit c03a1d6,
`script/run.py`, `script/plan_config.py` `PlanConfig2024`, `script/util.py`), not from mrpp's
Rust writer, so that the two can catch each other's mistakes. `tools/check/lifelong.py` judges
lifelong LoRR runs; this judges a one-shot MAPF plan drawn by PlanViz:

- what the loader needs: `version` "2024 LoRR" (else PlanViz falls back to its 2023 loader),
  `actionModel` "MAPF", integer `teamSize` and `makespan`, `start` with `teamSize` entries
  [row, col, direction] (integers; direction one of E N W S N/A), `actualPaths` and
  `plannerPaths` with `teamSize` strings of comma-separated letters U L R D W T, a non-empty
  `tasks` list of [id, t, [row, col, ...]], `actualSchedule` with a non-empty "t:task,..."
  string per agent naming listed tasks, `events` of [t, agent, task, errands done];
- moves as PlanViz draws them (`state_transition_mapf`): U row + 1, D row - 1, L col - 1,
  R col + 1, W and T wait;
- the map is a MovingAI `.map` ('.', 'G', 'S', 'E' free) or ASCII ('#' wall, space or '.' free);
  every cell on the map and free, no two agents on one cell, no two agents exchanging cells;
- agent i's goal is the last errand of task i; it ends there; its cost is its last arrival;
  every path is `makespan` letters long; `numTaskFinished` = `teamSize`; agent i's event for
  task i is at its cost; with SCEN (a MovingAI `.scen`), the starts and goals are its first
  `teamSize` agents'.

Prints one JSON line, {"valid": true, "sum_of_costs": .., "makespan": ..} or
{"valid": false, "reason": "..."}, and exits 0 when valid, 1 when not (including unreadable or
malformed inputs), 2 on wrong usage.
"""

import json
import os
import sys
import tempfile

# The map and scenario readers are shared with tracker.py (tools/check/gridfiles.py, stdlib only),
# found through this script's own folder wherever it is run from.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from gridfiles import Invalid, read_map, read_scen, read_text  # noqa: E402

STEP = {"U": (1, 0), "D": (-1, 0), "L": (0, -1), "R": (0, 1), "W": (0, 0), "T": (0, 0)}
DIRECTIONS = {"E", "N", "W", "S", "N/A"}


def need(d, key, kind):
    if key not in d:
        raise Invalid(f"no `{key}`")
    v = d[key]
    if kind is int and (not isinstance(v, int) or isinstance(v, bool)):
        raise Invalid(f"`{key}` is not an integer")
    if kind is not int and not isinstance(v, kind):
        raise Invalid(f"`{key}` is not a {kind.__name__}")
    return v


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def check(free, d, scen):
    if not isinstance(d, dict):
        raise Invalid("not a JSON object")
    if d.get("version") != "2024 LoRR":
        raise Invalid("`version` is not \"2024 LoRR\" (PlanViz would use its 2023 loader)")
    if need(d, "actionModel", str) != "MAPF":
        raise Invalid("`actionModel` is not \"MAPF\"")
    n = need(d, "teamSize", int)
    makespan = need(d, "makespan", int)
    starts = need(d, "start", list)
    if len(starts) != n:
        raise Invalid(f"`start` has {len(starts)} entries, teamSize is {n}")
    for i, s in enumerate(starts):
        if not (isinstance(s, list) and len(s) >= 3 and is_int(s[0]) and is_int(s[1])
                and s[2] in DIRECTIONS):
            raise Invalid(f"`start`[{i}] is not [row, col, direction]")
    tasks = need(d, "tasks", list)
    if not tasks:
        raise Invalid("`tasks` is empty (PlanViz asserts there is one)")
    ids = set()
    for k, t in enumerate(tasks):
        if not (isinstance(t, list) and len(t) == 3 and is_int(t[0]) and is_int(t[1])
                and isinstance(t[2], list) and len(t[2]) >= 2 and len(t[2]) % 2 == 0
                and all(is_int(x) for x in t[2])):
            raise Invalid(f"`tasks`[{k}] is not [id, t, [row, col, ...]]")
        ids.add(t[0])
    if len(tasks) < n:
        raise Invalid(f"{len(tasks)} tasks for {n} agents")
    schedule = need(d, "actualSchedule", list)
    if len(schedule) != n:
        raise Invalid(f"`actualSchedule` has {len(schedule)} entries, teamSize is {n}")
    for i, s in enumerate(schedule):
        if not isinstance(s, str) or not s:
            raise Invalid(f"`actualSchedule`[{i}] is not a non-empty string")
        for e in s.split(","):
            parts = e.split(":")
            try:
                t, task = int(parts[0]), int(parts[1])
            except (ValueError, IndexError):
                raise Invalid(f"`actualSchedule`[{i}]: `{e}` is not t:task")
            if len(parts) != 2 or (task != -1 and task not in ids):
                raise Invalid(f"`actualSchedule`[{i}]: `{e}` names no listed task")
    events = need(d, "events", list)
    for k, e in enumerate(events):
        if not (isinstance(e, list) and len(e) == 4 and all(is_int(x) for x in e)):
            raise Invalid(f"`events`[{k}] is not [t, agent, task, errands done]")
        if e[2] not in ids:
            raise Invalid(f"`events`[{k}] names task {e[2]}, not listed")
    paths = []
    for key in ("actualPaths", "plannerPaths"):
        lst = need(d, key, list)
        if len(lst) != n or not all(isinstance(s, str) for s in lst):
            raise Invalid(f"`{key}` is not {n} strings")
    for i, (s, st) in enumerate(zip(d["actualPaths"], starts)):
        letters = [x.strip() for x in s.split(",") if x.strip()]
        if len(letters) != makespan:
            raise Invalid(f"`actualPaths`[{i}] has {len(letters)} steps, makespan is {makespan}")
        r, c = st[0], st[1]
        if (r, c) not in free:
            raise Invalid(f"agent {i} starts on ({r},{c}), not a free cell")
        p = [(r, c)]
        for t, m in enumerate(letters, 1):
            if m not in STEP:
                raise Invalid(f"`actualPaths`[{i}], step {t}: `{m}` is not a MAPF letter")
            r, c = r + STEP[m][0], c + STEP[m][1]
            if (r, c) not in free:
                raise Invalid(f"agent {i}, step {t}: row {r}, column {c} is blocked or off the map")
            p.append((r, c))
        paths.append(p)
    for t in range(makespan + 1):
        seen = {}
        for i, p in enumerate(paths):
            if p[t] in seen:
                raise Invalid(f"agents {seen[p[t]]} and {i} both on {p[t]} at step {t}")
            seen[p[t]] = i
        if t < makespan:
            moves = {(p[t], p[t + 1]): i for i, p in enumerate(paths) if p[t] != p[t + 1]}
            for (a, b), i in moves.items():
                j = moves.get((b, a))
                if j is not None and i < j:
                    raise Invalid(f"agents {i} and {j} swap {a} and {b} at step {t + 1}")
    finished = {(e[1], e[2]): e[0] for e in events}
    total, longest = 0, 0
    by_id = {t[0]: t for t in tasks}
    for i, p in enumerate(paths):
        task = by_id.get(i)
        if task is None:
            raise Invalid(f"no task {i} (agent {i}'s goal)")
        goal = (task[2][-2], task[2][-1])
        if p[-1] != goal:
            raise Invalid(f"agent {i} ends on {p[-1]}, its goal (task {i}) is {goal}")
        cost = next((t + 1 for t in range(len(p) - 1, -1, -1) if p[t] != goal), 0)
        if finished.get((i, i)) != cost:
            raise Invalid(f"agent {i} last arrives at step {cost}, its event says {finished.get((i, i))}")
        total += cost
        longest = max(longest, cost)
        if scen is not None:
            if i >= len(scen):
                raise Invalid(f"the scenario has only {len(scen)} agents")
            if (paths[i][0], goal) != scen[i]:
                raise Invalid(f"agent {i}: start {paths[i][0]} and goal {goal} are not the scenario's {scen[i]}")
    if need(d, "numTaskFinished", int) != n:
        raise Invalid(f"numTaskFinished is {d['numTaskFinished']}, every one of {n} agents finishes")
    return {"valid": True, "sum_of_costs": total, "makespan": longest}


def check_files(map_path, plan_path, scen_path=None):
    try:
        # PlanViz's cells are (row, col); the readers' are (x, y).
        free = {(y, x) for x, y in read_map(map_path)[0]}
        scen = None
        if scen_path:
            scen = [((sy, sx), (gy, gx)) for (sx, sy), (gx, gy) in read_scen(scen_path)]
        try:
            d = json.loads(read_text(plan_path))
        except json.JSONDecodeError as e:
            raise Invalid(f"{plan_path}: not JSON: {e}")
        try:
            return check(free, d, scen)
        except Invalid as e:
            raise Invalid(f"{plan_path}: {e}")
    except Invalid as e:
        return {"valid": False, "reason": str(e)}


# ---------------------------------------------------------------- self-test

def self_test():
    """A valid file passes; tampered copies are rejected."""
    d = tempfile.mkdtemp(prefix="planviz-check-")
    mp = os.path.join(d, "t.map")
    with open(mp, "w") as f:
        f.write("type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n")
    good = {
        "actionModel": "MAPF", "version": "2024 LoRR", "teamSize": 2, "numTaskFinished": 2,
        "makespan": 3, "start": [[0, 0, "E"], [2, 3, "E"]],
        "actualPaths": ["R,R,R", "W,D,W"], "plannerPaths": ["R,R,R", "W,D,W"],
        "plannerTimes": [], "errors": [], "actualSchedule": ["0:0", "0:1"],
        "plannerSchedule": ["0:0", "0:1"], "scheduleErrors": [],
        "events": [[3, 0, 0, 1], [2, 1, 1, 1]], "tasks": [[0, 0, [0, 3]], [1, 0, [1, 3]]],
    }

    def run(change):
        plan = json.loads(json.dumps(good))
        change(plan)
        pp = os.path.join(d, "p.json")
        with open(pp, "w") as f:
            json.dump(plan, f)
        return check_files(mp, pp)

    ok = run(lambda p: None)
    assert ok["valid"] and ok["sum_of_costs"] == 5, ok
    cases = [
        (lambda p: p.update(version="2023 LoRR"), "version"),
        (lambda p: p["actualPaths"].__setitem__(1, "W,U,W"), "off the map"),
        (lambda p: p["actualPaths"].__setitem__(0, "R,D,R"), "off the map"),
        (lambda p: p["actualPaths"].__setitem__(0, "R,R,X"), "not a MAPF letter"),
        (lambda p: p["actualPaths"].__setitem__(0, "R,R"), "steps"),
        (lambda p: p["tasks"].__setitem__(1, [1, 0, [2, 3]]), "goal"),
        (lambda p: p["events"].__setitem__(0, [2, 0, 0, 1]), "event"),
        (lambda p: p["actualSchedule"].__setitem__(0, ""), "non-empty"),
        (lambda p: p["start"].__setitem__(0, [0, 0, "X"]), "direction"),
        (lambda p: p.update(tasks=[]), "empty"),
        (lambda p: p.update(numTaskFinished=1), "numTaskFinished"),
    ]
    for change, why in cases:
        bad = run(change)
        assert not bad["valid"] and why in bad["reason"], (why, bad)
    # A swap: two agents exchanging cells on the top row.
    swap = {"start": [[0, 0, "E"], [0, 1, "E"]], "actualPaths": ["R", "L"], "plannerPaths": ["R", "L"],
            "makespan": 1, "events": [[1, 0, 0, 1], [1, 1, 1, 1]],
            "tasks": [[0, 0, [0, 1]], [1, 0, [0, 0]]]}
    bad = run(lambda p: p.update(swap))
    assert not bad["valid"] and "swap" in bad["reason"], bad
    print(json.dumps({"self_test": "ok"}))
    return 0


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    if len(argv) not in (2, 3) or any(a.startswith("-") for a in argv):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    result = check_files(*argv)
    print(json.dumps(result))
    return 0 if result["valid"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
