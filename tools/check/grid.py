#!/usr/bin/env python3
"""Independent checker of mrpp JSON plans on grid maps (stdlib only).

Usage: python3 tools/check/grid.py [--bounds] MAP PLAN.json
       python3 tools/check/grid.py [--bounds] LORR_PROBLEM.json PLAN.json

Written from the rules in docs/design.md, not from the Rust validator, so that the two can
catch each other's mistakes:

- the map is a MovingAI `.map` (header `type`/`height`/`width`/`map`; '.', 'G', 'S' free, and
  the League of Robot Runners' 'E'; '@', 'O', 'T', 'W' blocked) or an ASCII map ('#' wall, space free; CRLF accepted; a row shorter
  than the longest is free beyond its end);
- cells are [x, y] with x the column and y the row, from 0 at the top-left;
- path index = time step, path[0] = the agent's start; a path that ends early leaves the agent
  on its last cell (where it still occupies the cell);
- every step is a move to a 4-neighbour or a wait; every cell is on the map and free;
- no two agents on one cell at one step (vertex conflict), no two agents exchanging cells between
  two steps (swap conflict); following an agent into a cell it is leaving is allowed unless the
  plan's rules say `"following": false`;
- goal semantics `stay` (default): every agent ends on its goal; its cost is the step of its last
  arrival there (index of its last cell off the goal + 1, 0 if it never leaves it);
  `visit`: every agent stands on its goal at least once; its cost is the first such step;
- a League of Robot Runners problem JSON (its `mapFile`, `agentFile`, `taskFile`, `teamSize`,
  paths relative to the JSON; agent and task files: `#` comments, a count line, then one
  location `row * width + col` per agent, one comma-separated errand list per task) fixes the
  starts (the first `teamSize` agents, or the plan's agent count if smaller) and the goals: tasks
  go out in file order, agent i takes task i unless its first errand is already a goal, then the
  first task from index teamSize on that is unused with a first errand not yet a goal;
- sum of costs = sum over agents, makespan = the maximum, sum of moves = steps where an agent's
  cell changes; sum of loss = per agent, the steps except those from its goal to its goal
  (waits on the goal), summed (LaCAM*'s objective);
- with `--bounds`, also the lower bounds any plan meets: `lower_bound`, the sum over agents of
  the breadth-first distance from start to goal alone on the map (it bounds the sum of costs
  and the sum of loss), and `makespan_lower_bound`, the largest of those distances.

The plan is mrpp's plan envelope (`"format": "mrpp-plan/1"`, rules in `"rules": {"goal", "following"}`)
or an older mrpp JSON plan (`"goal_semantics"` at the top level). When the file reports metrics
(not null), they must equal the recomputed ones.

Prints one JSON line, {"valid": true, "sum_of_costs": .., "makespan": .., "sum_of_moves": ..,
"sum_of_loss": .. [, "lower_bound": .., "makespan_lower_bound": ..]}
or {"valid": false, "reason": "..."}, and exits 0 when valid, 1 when not (including unreadable
or malformed inputs), 2 on wrong usage.
"""

import json
import sys

MOVINGAI_FREE = set(".GSE")
MOVINGAI_BLOCKED = set("@OTW")


class Invalid(Exception):
    """The plan (or an input it depends on) breaks a rule; the message says which."""


def read_text(path):
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise Invalid(f"cannot read {path}: {e.strerror}")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise Invalid(f"{path} is not UTF-8 text")


def load_map(path):
    """Returns (width, height, free) where free is a set of (x, y)."""
    text = read_text(path)
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    first = next((l for l in lines if l.strip()), "")
    if first.strip().startswith("type "):
        return parse_movingai(lines, path)
    return parse_ascii(lines, path)


def parse_movingai(lines, path):
    height = width = None
    i = 0
    while True:
        if i >= len(lines):
            raise Invalid(f"{path}: header has no 'map' line")
        words = lines[i].split()
        i += 1
        if not words or words[0] == "type":
            continue
        if words[0] == "map" and len(words) == 1:
            break
        if words[0] in ("height", "width") and len(words) == 2:
            try:
                value = int(words[1])
            except ValueError:
                raise Invalid(f"{path}:{i}: bad {words[0]} {words[1]!r}")
            if words[0] == "height":
                height = value
            else:
                width = value
            continue
        raise Invalid(f"{path}:{i}: unexpected header line {lines[i - 1]!r}")
    if height is None or width is None or height <= 0 or width <= 0:
        raise Invalid(f"{path}: header lacks a positive height and width")
    free = set()
    for y in range(height):
        if i + y >= len(lines):
            raise Invalid(f"{path}: only {y} of {height} map rows")
        row = lines[i + y]
        if len(row) != width:
            raise Invalid(f"{path}:{i + y + 1}: row has {len(row)} cells, expected {width}")
        for x, ch in enumerate(row):
            if ch in MOVINGAI_FREE:
                free.add((x, y))
            elif ch not in MOVINGAI_BLOCKED:
                raise Invalid(f"{path}:{i + y + 1}: unknown map character {ch!r}")
    return width, height, free


def parse_ascii(lines, path):
    while lines and lines[-1] == "":
        lines = lines[:-1]
    if not lines:
        raise Invalid(f"{path}: empty map")
    width = max(len(l) for l in lines)
    height = len(lines)
    free = set()
    for y, row in enumerate(lines):
        row = row.ljust(width)  # short rows are free beyond their end
        for x, ch in enumerate(row):
            if ch in " .":
                free.add((x, y))
            elif ch != "#":
                raise Invalid(f"{path}:{y + 1}: unexpected map character {ch!r}")
    return width, height, free


def as_cell(value, what):
    if (
        isinstance(value, list)
        and len(value) == 2
        and all(isinstance(c, int) and not isinstance(c, bool) for c in value)
    ):
        return (value[0], value[1])
    raise Invalid(f"{what} is {json.dumps(value)}, not an [x, y] pair of integers")


def check_cell(cell, grid, what):
    width, height, free = grid
    x, y = cell
    if not (0 <= x < width and 0 <= y < height):
        raise Invalid(f"{what} ({x},{y}) is off the {width}x{height} map")
    if cell not in free:
        raise Invalid(f"{what} ({x},{y}) is a wall")


def load_plan(path):
    text = read_text(path)
    try:
        plan = json.loads(text)
    except json.JSONDecodeError as e:
        raise Invalid(f"{path}:{e.lineno}: not JSON: {e.msg}")
    if not isinstance(plan, dict):
        raise Invalid(f"{path}: the plan is not a JSON object")
    return plan


def check(grid, plan):
    """Returns the metrics dict of a valid plan; raises Invalid otherwise."""
    family = plan.get("family", "")
    if family not in ("", "grid"):
        raise Invalid(f"this is a {family} plan, not a grid plan")
    if plan.get("solved") is not True:
        raise Invalid("the file does not hold a solved plan (solved is not true)")
    rules = plan.get("rules")
    if not isinstance(rules, dict):
        rules = {}
    semantics = rules.get("goal", plan.get("goal_semantics", "stay"))
    if semantics not in ("stay", "visit"):
        raise Invalid(f"unknown goal semantics {semantics!r}")
    following = rules.get("following", True)
    if not isinstance(following, bool):
        raise Invalid(f"rules.following must be true or false, not {following!r}")
    agents = plan.get("agents")
    if not isinstance(agents, list) or not agents:
        raise Invalid("no agents")

    starts, goals, paths = [], [], []
    for i, a in enumerate(agents):
        if not isinstance(a, dict):
            raise Invalid(f"agent {i} is not an object")
        start = as_cell(a.get("start"), f"agent {i} start")
        goal = as_cell(a.get("goal"), f"agent {i} goal")
        check_cell(start, grid, f"agent {i} start")
        check_cell(goal, grid, f"agent {i} goal")
        raw = a.get("path")
        if not isinstance(raw, list) or not raw:
            raise Invalid(f"agent {i} has no path")
        path = [as_cell(c, f"agent {i} cell at t={t}") for t, c in enumerate(raw)]
        for t, c in enumerate(path):
            check_cell(c, grid, f"agent {i} at t={t}: cell")
        if path[0] != start:
            raise Invalid(f"agent {i} path starts at {fmt(path[0])}, not at its start {fmt(start)}")
        for t in range(1, len(path)):
            (px, py), (x, y) = path[t - 1], path[t]
            if abs(px - x) + abs(py - y) > 1:
                raise Invalid(
                    f"agent {i} jumps from {fmt(path[t - 1])} to {fmt(path[t])} "
                    f"between t={t - 1} and t={t}"
                )
        starts.append(start)
        goals.append(goal)
        paths.append(path)

    for what, cells in (("start", starts), ("goal", goals)):
        seen = {}
        for i, c in enumerate(cells):
            if c in seen:
                raise Invalid(f"agents {seen[c]} and {i} share the {what} {fmt(c)}")
            seen[c] = i

    def at(i, t):
        p = paths[i]
        return p[t] if t < len(p) else p[-1]

    horizon = max(len(p) for p in paths)
    for t in range(horizon):
        occupied = {}
        for i in range(len(paths)):
            c = at(i, t)
            if c in occupied:
                raise Invalid(
                    f"vertex conflict: agents {occupied[c]} and {i} both at {fmt(c)} at t={t}"
                )
            occupied[c] = i
        if t == 0:
            continue
        moves = {}
        for i in range(len(paths)):
            a, b = at(i, t - 1), at(i, t)
            if a != b:
                moves[(a, b)] = i
        for (a, b), i in moves.items():
            j = moves.get((b, a))
            if j is not None and i < j:
                raise Invalid(
                    f"swap conflict: agents {i} and {j} exchange {fmt(a)} and {fmt(b)} "
                    f"between t={t - 1} and t={t}"
                )
        if not following:
            before = {at(j, t - 1): j for j in range(len(paths))}
            for (a, b), i in moves.items():
                j = before.get(b)
                if j is not None and j != i:
                    raise Invalid(
                        f"following conflict: agent {i} enters {fmt(b)} that agent {j} "
                        f"leaves between t={t - 1} and t={t}"
                    )

    sum_of_costs = makespan = sum_of_moves = sum_of_loss = 0
    for i, (p, goal) in enumerate(zip(paths, goals)):
        sum_of_loss += sum(1 for t in range(1, len(p)) if not (p[t - 1] == goal and p[t] == goal))
        if semantics == "stay":
            if p[-1] != goal:
                raise Invalid(f"agent {i} ends at {fmt(p[-1])}, not on its goal {fmt(goal)}")
            off = [t for t, c in enumerate(p) if c != goal]
            cost = off[-1] + 1 if off else 0
        else:
            on = [t for t, c in enumerate(p) if c == goal]
            if not on:
                raise Invalid(f"agent {i} never stands on its goal {fmt(goal)}")
            cost = on[0]
        sum_of_costs += cost
        makespan = max(makespan, cost)
        sum_of_moves += sum(1 for t in range(1, len(p)) if p[t] != p[t - 1])
    result = {"sum_of_costs": sum_of_costs, "makespan": makespan, "sum_of_moves": sum_of_moves}

    reported = plan.get("metrics")
    if isinstance(reported, dict):
        for key, value in result.items():
            if reported.get(key) is not None and reported.get(key) != value:
                raise Invalid(f"the file reports {key}={reported.get(key)} but the plan's is {value}")
    result["sum_of_loss"] = sum_of_loss
    result["starts_goals"] = [(p[0], g) for p, g in zip(paths, goals)]
    return result


def lower_bounds(grid, starts_goals):
    """(sum, max) over agents of the breadth-first distance from start to goal on the grid."""
    _, _, free = grid
    total = longest = 0
    for start, goal in starts_goals:
        dist = {start: 0}
        frontier = [start]
        while frontier and goal not in dist:
            nxt = []
            for x, y in frontier:
                for c in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                    if c in free and c not in dist:
                        dist[c] = dist[(x, y)] + 1
                        nxt.append(c)
            frontier = nxt
        if goal not in dist:
            raise Invalid(f"goal {fmt(goal)} cannot be reached from {fmt(start)}")
        total += dist[goal]
        longest = max(longest, dist[goal])
    return total, longest


def lorr_problem(path):
    """(map path, starts, goals) of a League of Robot Runners problem JSON, cells as (x, y)."""
    import os

    try:
        with open(path, encoding="utf-8-sig") as f:
            spec = json.load(f)
        base = os.path.dirname(path)
        map_path = os.path.join(base, spec["mapFile"])
        team = int(spec["teamSize"])

        def entries(name):
            with open(os.path.join(base, spec[name]), encoding="utf-8-sig") as f:
                lines = [l.strip() for l in f if l.strip() and not l.strip().startswith("#")]
            if int(lines[0]) != len(lines) - 1:
                raise Invalid(f"{spec[name]}: count {lines[0]} but {len(lines) - 1} entries")
            return lines[1:]

        agents = [int(l) for l in entries("agentFile")][:team]
        tasks = [[int(x) for x in l.split(",")] for l in entries("taskFile")]
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        raise Invalid(f"{path}: not a readable League of Robot Runners problem ({e})")
    goals, used = [], set()
    for i in range(team):
        if i < len(tasks) and tasks[i][0] not in goals:
            pick = i
        else:
            free = [t for t in range(team, len(tasks)) if t not in used and tasks[t][0] not in goals]
            if not free:
                raise Invalid(f"{path}: too few tasks with distinct first errands")
            pick = free[0]
        used.add(pick)
        goals.append(tasks[pick][0])
    return map_path, agents, goals


def check_lorr(problem, grid, plan):
    """The plan's starts and goals must be the League of Robot Runners problem's."""
    map_path, agents, goals = problem
    width = grid[0]

    def cell(loc):
        return [loc % width, loc // width]

    listed = plan.get("agents") or []
    if len(listed) > len(agents):
        raise Invalid(f"the plan has {len(listed)} agents but the problem has {len(agents)}")
    for i, a in enumerate(listed):
        for what, loc in (("start", agents[i]), ("goal", goals[i])):
            if a.get(what) != cell(loc):
                raise Invalid(f"agent {i} {what} is {a.get(what)} but the problem says {cell(loc)}")


def fmt(cell):
    return f"({cell[0]},{cell[1]})"


def main(argv):
    bounds = "--bounds" in argv[1:]
    argv = [a for a in argv if a != "--bounds"]
    if len(argv) != 3:
        print(f"usage: {argv[0]} [--bounds] MAP|LORR_PROBLEM.json PLAN.json", file=sys.stderr)
        return 2
    try:
        if argv[1].endswith(".json"):
            problem = lorr_problem(argv[1])
            grid = load_map(problem[0])
            plan = load_plan(argv[2])
            check_lorr(problem, grid, plan)
        else:
            grid = load_map(argv[1])
            plan = load_plan(argv[2])
        result = check(grid, plan)
        starts_goals = result.pop("starts_goals")
        if bounds:
            result["lower_bound"], result["makespan_lower_bound"] = lower_bounds(grid, starts_goals)
    except Invalid as e:
        print(json.dumps({"valid": False, "reason": str(e)}))
        return 1
    print(json.dumps({"valid": True, **result}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
