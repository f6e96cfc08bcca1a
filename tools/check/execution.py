#!/usr/bin/env python3
"""Independent checker of mrpp's executed records (`mrpp execute`, format mrpp-execution/1;
stdlib only).

Usage: python3 tools/check/execution.py MAP PLAN.json TRACE.json

Written from the rules in docs/execution.md, not from mrpp's Rust code:

- MAP is a MovingAI `.map` ('.', 'G', 'S', 'E' free; '@', 'O', 'T', 'W' blocked); cells are
  [x, y], x the column, y the row from the top;
- PLAN is mrpp's plan envelope (`agents[i].path`, a list of [x, y] per step); a robot's moves
  are the steps where its cell changes (waits dropped), each to a 4-neighbour on a free cell;
- the record's `agents[i].moves` are [first tick, tick after, from, to]: they must be the plan's
  moves, in order, each starting no earlier than the one before ended;
- a move lasts exactly `ticks_per_move` ticks of progress: ticks within it on which its robot is
  held by one of its `delays` ([first tick, tick after]) do not count, and it cannot start on
  such a tick; a robot of a ring in `rings` (pairs [robot, move]) progresses only on ticks when
  no robot of its ring is held, and the ring's moves share their ticks;
- at the end of each tick a robot stands at its cell centre, or mid-move at from + (to - from) x
  progress / ticks_per_move; two robots collide when their squares of side `agent_size` overlap
  (each side's gap below the size); the number of collisions must equal `metrics.collisions`;
- `metrics.makespan` is the latest tick after a robot's last move, `metrics.sum_of_costs` their
  sum.

Prints one JSON line, {"valid": true, "collisions": .., "makespan": .., "sum_of_costs": ..} or
{"valid": false, "reason": "..."}; exits 0 when valid, 1 when not, 2 on wrong usage.
"""

import json
import sys


def fail(reason):
    print(json.dumps({"valid": False, "reason": reason}))
    sys.exit(1)


def read_map(path):
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    try:
        start = next(i for i, l in enumerate(lines) if l.strip() == "map") + 1
    except StopIteration:
        fail(f"{path}: no `map` line")
    grid = lines[start:]
    return lambda x, y: 0 <= y < len(grid) and 0 <= x < len(grid[y]) and grid[y][x] in ".GSE"


def held_ticks(delays, a, b):
    return sum(max(0, min(b, d[1]) - max(a, d[0])) for d in delays)


def check(map_path, plan_path, trace_path):
    free = read_map(map_path)
    with open(plan_path, encoding="utf-8") as f:
        plan = json.load(f)
    with open(trace_path, encoding="utf-8") as f:
        trace = json.load(f)
    if trace.get("format") != "mrpp-execution/1":
        fail(f"{trace_path}: not an mrpp-execution/1 record")
    c = trace["ticks_per_move"]
    size = trace["agent_size"]
    paths = [a["path"] for a in plan["agents"]]
    agents = trace["agents"]
    if len(agents) != len(paths):
        fail(f"{len(agents)} robots executed, the plan has {len(paths)}")
    planned = []
    for i, path in enumerate(paths):
        moves = []
        for a, b in zip(path, path[1:]):
            if a == b:
                continue
            if abs(a[0] - b[0]) + abs(a[1] - b[1]) != 1 or not free(*b):
                fail(f"robot {i}: the plan moves from {a} to {b}")
            moves.append((tuple(a), tuple(b)))
        planned.append(moves)
    ring_of = {}
    for g, ring in enumerate(trace.get("rings", [])):
        for robot, move in ring:
            ring_of[(robot, move)] = g

    def stopped(i, k, a, b):
        """Ticks in [a, b) on which robot i's move k makes no progress."""
        g = ring_of.get((i, k))
        if g is None:
            return held_ticks(agents[i]["delays"], a, b)
        members = trace["rings"][g]
        return sum(
            1 for t in range(a, b)
            if any(held_ticks(agents[r]["delays"], t, t + 1) for r, _ in members)
        )

    finish = []
    for i, agent in enumerate(agents):
        moves = agent["moves"]
        if len(moves) != len(planned[i]):
            fail(f"robot {i}: {len(moves)} moves executed, its plan has {len(planned[i])}")
        if tuple(agent["start"]) != tuple(paths[i][0]):
            fail(f"robot {i}: starts on {agent['start']}, its plan on {paths[i][0]}")
        last = 0
        for k, (a, b, frm, to) in enumerate(moves):
            if (tuple(frm), tuple(to)) != planned[i][k]:
                fail(f"robot {i}, move {k}: {frm} -> {to}, the plan's is {planned[i][k]}")
            if a < last or b <= a:
                fail(f"robot {i}, move {k}: ticks [{a}, {b}) overlap the move before")
            if held_ticks(agent["delays"], a, a + 1):
                fail(f"robot {i}, move {k}: starts at tick {a} while held")
            if (b - a) - stopped(i, k, a, b) != c:
                fail(f"robot {i}, move {k}: not {c} ticks of progress in [{a}, {b})")
            g = ring_of.get((i, k))
            if g is not None:
                r, m = trace["rings"][g][0]
                if agents[r]["moves"][m][:2] != [a, b]:
                    fail(f"robot {i}, move {k}: its ring's moves do not share their ticks")
            last = b
        finish.append(last)
    ticks = trace["ticks"]
    collisions = 0
    for t in range(ticks):
        points = []
        for i, agent in enumerate(agents):
            moves = agent["moves"]
            point = [paths[i][0][0] + 0.5, paths[i][0][1] + 0.5]
            for k, (a, b, frm, to) in enumerate(moves):
                if b <= t + 1:
                    point = [to[0] + 0.5, to[1] + 0.5]
                elif a <= t:
                    p = (t + 1 - a) - stopped(i, k, a, t + 1)
                    f = p / c
                    point = [frm[0] + 0.5 + (to[0] - frm[0]) * f, frm[1] + 0.5 + (to[1] - frm[1]) * f]
                    break
                else:
                    break
            points.append(point)
        buckets = {}
        for i, p in enumerate(points):
            buckets.setdefault((int(p[0] // 1), int(p[1] // 1)), []).append(i)
        for i, p in enumerate(points):
            bx, by = int(p[0] // 1), int(p[1] // 1)
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for j in buckets.get((bx + dx, by + dy), []):
                        q = points[j]
                        if j > i and abs(p[0] - q[0]) < size - 1e-9 and abs(p[1] - q[1]) < size - 1e-9:
                            collisions += 1
    m = trace["metrics"]
    if collisions != m["collisions"]:
        fail(f"the record claims {m['collisions']} collisions, the replay finds {collisions}")
    makespan, soc = max(finish, default=0), sum(finish)
    if (m["makespan"], m["sum_of_costs"]) != (makespan, soc):
        fail(f"the record claims makespan {m['makespan']} and sum of costs {m['sum_of_costs']}, "
             f"the replay {makespan} and {soc}")
    return {"valid": True, "collisions": collisions, "makespan": makespan, "sum_of_costs": soc}


def main():
    if len(sys.argv) != 4:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    try:
        print(json.dumps(check(*sys.argv[1:])))
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        fail(f"unreadable input: {e}")


if __name__ == "__main__":
    main()
