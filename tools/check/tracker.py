#!/usr/bin/env python3
"""Independent checker of MAPF Tracker result CSVs (stdlib only).

Usage: python3 tools/check/tracker.py MAP SCEN RESULT.csv
       python3 tools/check/tracker.py --self-test

Written from the tracker's published result files (http://tracker.pathfinding.ai/, the
examples PlanViz ships), not from mrpp's Rust reader, so that the two can catch each other's
mistakes:

- the map is a MovingAI `.map` (header `type`/`height`/`width`/`map`; '.', 'G', 'S', 'E' free,
  anything else blocked) or an ASCII map ('#' wall, space or '.' free);
- the scenario is a MovingAI `.scen` (`version 1`, then per agent: bucket, map, width, height,
  start x, start y, goal x, goal y, optimal length); a row with `agents` = k uses its first k
  agents;
- the CSV has a header; the columns used are `agents`, `solution_cost`, the plan
  (`solution_plan`, or `path` in the single-instance download) and, when present, `map_name`,
  `scen_type`, `type_id`, `lower_cost`. A row is checked when it names no scenario or its
  `{map_name}-{scen_type}-{type_id}` (or its `scen_type` alone) is SCEN's file name without
  `.scen`; other rows belong to other scenarios and are skipped; at least one row must be
  checked;
- the plan is one string of moves per agent, separated by newlines: `l` x - 1, `r` x + 1,
  `u` y + 1, `d` y - 1, `w` wait (x the column, y the row of the map file, y growing down it);
- every cell is on the map and free; no two agents on one cell at one step (an agent whose
  string has ended stays on its last cell); no two agents exchanging cells; every agent ends on
  its goal; its cost is the step of its last arrival there; the stated `solution_cost` must be
  the sum of costs and the sum of the strings' lengths; `lower_cost`, when given, must not
  exceed it.

Prints one JSON line, {"valid": true, "rows": .., "sum_of_costs": [..]} or
{"valid": false, "reason": "..."}, and exits 0 when valid, 1 when not (including unreadable or
malformed inputs), 2 on wrong usage.
"""

import csv
import io
import json
import os
import sys
import tempfile

# The map and scenario readers are shared with planviz.py (tools/check/gridfiles.py, stdlib only),
# found through this script's own folder wherever it is run from.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from gridfiles import Invalid, read_map, read_scen, read_text  # noqa: E402

MOVES = {"l": (-1, 0), "r": (1, 0), "u": (0, 1), "d": (0, -1), "w": (0, 0)}


def check_row(free, agents, row, where):
    """The row's sum of costs, or Invalid naming the rule."""
    try:
        k = int(row["agents"])
        stated = int(row["solution_cost"])
    except (KeyError, ValueError, TypeError):
        raise Invalid(f"{where}: `agents` and `solution_cost` must be integers")
    plan = row.get("solution_plan")
    if plan is None:
        plan = row.get("path")
    if plan is None:
        raise Invalid(f"{where}: no plan column (`solution_plan` or `path`)")
    strings = [s.strip() for s in plan.replace("\r", "").split("\n")]
    if len(strings) != k:
        raise Invalid(f"{where}: {len(strings)} move strings for agents={k}")
    if k > len(agents):
        raise Invalid(f"{where}: agents={k} but the scenario has {len(agents)}")
    paths = []
    for i, s in enumerate(strings):
        x, y = agents[i][0]
        if (x, y) not in free:
            raise Invalid(f"{where}: agent {i} starts on a blocked or off-map cell ({x},{y})")
        p = [(x, y)]
        for t, c in enumerate(s, 1):
            if c not in MOVES:
                raise Invalid(f"{where}: agent {i}, step {t}: `{c}` is not one of l r u d w")
            dx, dy = MOVES[c]
            x, y = x + dx, y + dy
            if (x, y) not in free:
                raise Invalid(f"{where}: agent {i}, step {t}: ({x},{y}) is blocked or off the map")
            p.append((x, y))
        paths.append(p)
    horizon = max(len(p) for p in paths) if paths else 0

    def at(p, t):
        return p[t] if t < len(p) else p[-1]

    for t in range(horizon):
        seen = {}
        for i, p in enumerate(paths):
            c = at(p, t)
            if c in seen:
                raise Invalid(f"{where}: agents {seen[c]} and {i} both on {c} at step {t}")
            seen[c] = i
        if t + 1 < horizon:
            moves = {}
            for i, p in enumerate(paths):
                a, b = at(p, t), at(p, t + 1)
                if a != b:
                    moves[(a, b)] = i
            for (a, b), i in moves.items():
                j = moves.get((b, a))
                if j is not None and i < j:
                    raise Invalid(f"{where}: agents {i} and {j} swap {a} and {b} at step {t + 1}")
    total = 0
    for i, p in enumerate(paths):
        goal = agents[i][1]
        if p[-1] != goal:
            raise Invalid(f"{where}: agent {i} ends on {p[-1]}, its goal is {goal}")
        cost = 0
        for t in range(len(p) - 1, -1, -1):
            if p[t] != goal:
                cost = t + 1
                break
        total += cost
    lengths = sum(len(s) for s in strings)
    if stated != total or stated != lengths:
        raise Invalid(
            f"{where}: solution_cost={stated} but the sum of costs is {total} "
            f"and the move strings' lengths sum to {lengths}"
        )
    lower = (row.get("lower_cost") or "").strip()
    if lower:
        try:
            if int(lower) > stated:
                raise Invalid(f"{where}: lower_cost={lower} exceeds solution_cost={stated}")
        except ValueError:
            raise Invalid(f"{where}: lower_cost `{lower}` is not an integer")
    return total


def check_files(map_path, scen_path, csv_path):
    try:
        free, _ = read_map(map_path)
        agents = read_scen(scen_path)
        text = read_text(csv_path)
        reader = csv.DictReader(io.StringIO(text, newline=""))
        if not reader.fieldnames or "agents" not in [f.strip() for f in reader.fieldnames]:
            raise Invalid(f"{csv_path}: no header with an `agents` column")
        stem = os.path.basename(scen_path)
        if stem.endswith(".scen"):
            stem = stem[:-5]
        costs = []
        for row in reader:
            row = {(k or "").strip(): v for k, v in row.items()}
            where = f"{csv_path}:{reader.line_num}"
            if None in row.values():
                raise Invalid(f"{where}: the row has fewer fields than the header")
            name = row.get("map_name", "")
            if name:
                full = f"{name}-{row.get('scen_type', '')}-{row.get('type_id', '')}"
                if stem not in (full, row.get("scen_type", "")):
                    continue
            costs.append(check_row(free, agents, row, where))
        if not costs:
            raise Invalid(f"{csv_path}: no row for scenario {stem}")
        return {"valid": True, "rows": len(costs), "sum_of_costs": costs}
    except Invalid as e:
        return {"valid": False, "reason": str(e)}
    except csv.Error as e:
        return {"valid": False, "reason": f"{csv_path}: malformed CSV: {e}"}


# ---------------------------------------------------------------- self-test

def self_test():
    """A valid result passes; tampered copies (a swap, a wrong cost, a wall, a wrong letter,
    a missing agent) are rejected."""
    d = tempfile.mkdtemp(prefix="tracker-check-")
    mp = os.path.join(d, "t.map")
    sp = os.path.join(d, "t-even-1.scen")
    with open(mp, "w") as f:
        f.write("type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n")
    with open(sp, "w") as f:
        f.write("version 1\n0\tt.map\t4\t3\t0\t0\t3\t0\t3\n0\tt.map\t4\t3\t3\t2\t3\t1\t1\n")
    head = "map_name,scen_type,type_id,agents,lower_cost,solution_cost,solution_plan\n"

    def run(body):
        cp = os.path.join(d, "r.csv")
        with open(cp, "w", newline="") as f:
            f.write(head + body)
        return check_files(mp, sp, cp)

    ok = run('t,even,1,2,4,5,"rrr\nwd"\n')
    assert ok["valid"] and ok["sum_of_costs"] == [5], ok
    for body, why in [
        ('t,even,1,2,4,6,"rrr\nwd"\n', "solution_cost"),
        ('t,even,1,2,4,5,"rrr\nwu"\n', "off the map"),
        ('t,even,1,2,4,5,"rrr\nwx"\n', "not one of"),
        ('t,even,1,2,4,3,"rrr"\n', "move strings"),
        ('t,even,1,2,9,5,"rrr\nwd"\n', "lower_cost"),
        ('t,even,1,2,4,6,"rrrw\nwd"\n', "lengths"),
        ('t,even,1,2,4,5,"rdr\nwd"\n', "blocked"),
        ('t,even,2,2,4,5,"rrr\nwd"\n', "no row"),
    ]:
        bad = run(body)
        assert not bad["valid"] and why in bad["reason"], (body, bad)
    # A vertex conflict and a swap.
    with open(sp, "w") as f:
        f.write("version 1\n0\tt.map\t4\t3\t0\t0\t2\t0\t2\n0\tt.map\t4\t3\t2\t0\t0\t0\t2\n")
    bad = run('t,even,1,2,4,4,"rr\nll"\n')
    assert not bad["valid"] and "both on" in bad["reason"], bad
    with open(sp, "w") as f:
        f.write("version 1\n0\tt.map\t4\t3\t0\t0\t1\t0\t1\n0\tt.map\t4\t3\t1\t0\t0\t0\t1\n")
    bad = run('t,even,1,2,2,2,"r\nl"\n')
    assert not bad["valid"] and "swap" in bad["reason"], bad
    print(json.dumps({"self_test": "ok"}))
    return 0


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    if len(argv) != 3 or any(a.startswith("-") for a in argv):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    result = check_files(*argv)
    print(json.dumps(result))
    return 0 if result["valid"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
