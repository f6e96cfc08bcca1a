#!/usr/bin/env python3
"""Independent checker of executed runs (stdlib only): mrpp's own records (`mrpp execute`, format
mrpp-execution/1) and League of Robot Runners 2026 outputs (`"version": "2026 LoRR"`, written by
the start kit v3.1.0).

Usage: python3 tools/check/execution.py MAP PLAN.json TRACE.json     (mrpp-execution/1)
       python3 tools/check/execution.py PROBLEM.json OUTPUT.json     (dispatches on OUTPUT's
                                                                      `version`: "2026 LoRR")

## mrpp-execution/1

Written from the rules in docs/execution.md, not from mrpp's Rust code:

- MAP is a MovingAI `.map` ('.', 'G', 'S', 'E' free; '@', 'O', 'T', 'W' blocked); cells are
  [x, y], x the column, y the row from the top;
- PLAN is mrpp's plan envelope (`agents[i].path`, a list of [x, y] per step); a robot's moves
  are the steps where its cell changes (waits dropped), each to a 4-neighbour on a free cell;
- the record's `agents[i].moves` are [first tick, tick after, from, to]: they must be the plan's
  moves, in order, each starting no earlier than the one before ended; a record whose `replans`
  list is not empty (re-planning on drift: later plans took over) must instead start on the
  plan's start, move to a 4-neighbour on a free cell each time, each move from where the last
  ended, and end on the plan's goal (its path's last cell);
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

## 2026 LoRR (see check_lorr2026 for the rules)

Written from docs/lorr-semantics.md and the start kit v3.1.0's C++ (ActionModel.cpp result_state
and step, Counter.h, Simulator.cpp, TaskManager.cpp, CompetitionSystem.cpp), sharing no code with
mrpp. Prints {"valid": true, "format": "2026 LoRR", "ticks": .., "tasks_finished": .., ...} or
{"valid": false, "reason": "..."} naming the tick, agent(s) and rule of the first violation.
"""

import bisect
import json
import math
import os
import re
import struct
import sys


def fail(reason):
    print(json.dumps({"valid": False, "reason": reason}))
    sys.exit(1)


_fail = fail


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
    replanned = bool(trace.get("replans"))
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
        if not replanned and len(moves) != len(planned[i]):
            fail(f"robot {i}: {len(moves)} moves executed, its plan has {len(planned[i])}")
        if tuple(agent["start"]) != tuple(paths[i][0]):
            fail(f"robot {i}: starts on {agent['start']}, its plan on {paths[i][0]}")
        last = 0
        at = tuple(paths[i][0])
        for k, (a, b, frm, to) in enumerate(moves):
            if replanned:
                if tuple(frm) != at or abs(frm[0] - to[0]) + abs(frm[1] - to[1]) != 1 or not free(*to):
                    fail(f"robot {i}, move {k}: {frm} -> {to} does not go on from {list(at)} "
                         f"to a free neighbour")
                at = tuple(to)
            elif (tuple(frm), tuple(to)) != planned[i][k]:
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
        if replanned and at != tuple(paths[i][-1]):
            fail(f"robot {i}: ends on {list(at)}, its plan's goal is {paths[i][-1]}")
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


# ---------------------------------------------------------------------------------------------
# League of Robot Runners 2026 ("2026 LoRR", start kit v3.1.0)
# ---------------------------------------------------------------------------------------------

LORR_2026 = "2026 LoRR"
HEADINGS = "ESWN"                              # orientation 0 = east, 1 = south, 2 = west, 3 = north
STEP = ((0, 1), (1, 0), (0, -1), (-1, 0))      # (d row, d col) of an F for each orientation
ACTIONS = "FRCWT"                              # forward, clockwise, counter-clockwise, wait, no action
EPS = 1e-6                                     # the kit's overlap tolerance
CELL_EPS = 1e-9                                # for enumerating the cells a footprint touches
SEGMENT = re.compile(r"\[\((-?\d+),(-?\d+),(-?\d+),(-?\d+),(-?\d+)\):\(([^)]*)\)\]")
RUN = re.compile(r"([A-Z]) (\d+)")


def read_lorr_map(path):
    """The kit's Grid: a MovingAI header (`type`, `height`, `width`, `map`) or a `rows,cols` line,
    then `rows` lines read for `cols` characters; '@' and 'T' are blocked, anything else free.
    Returns (rows, cols, set of blocked (row, col))."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if not lines:
        fail(f"{path}: empty map")
    if lines[0][:1] == "t":
        rows, cols, body = int(lines[1].split()[1]), int(lines[2].split()[1]), lines[4:]
    else:
        head = lines[0].split(",")
        rows, cols, body = int(head[0]), int(head[1]), lines[1:]
    if len(body) < rows:
        fail(f"{path}: {len(body)} map rows, the header says {rows}")
    blocked = set()
    for r in range(rows):
        if len(body[r]) < cols:
            fail(f"{path}: map row {r} has {len(body[r])} characters, the header says {cols}")
        for c in range(cols):
            if body[r][c] in "@T":
                blocked.add((r, c))
    return rows, cols, blocked


def read_lorr_list(path):
    """An agent or task file: '#' lines skipped anywhere; the first line's first field is a count,
    then that many lines of comma-separated integers. Returns the count and the lines."""
    with open(path, encoding="utf-8") as f:
        lines = [l for l in f.read().splitlines() if l.strip() and not l.startswith("#")]
    if not lines:
        fail(f"{path}: no count line")
    count = int(lines[0].split(",")[0])
    if len(lines) - 1 < count:
        fail(f"{path}: announces {count} lines, has {len(lines) - 1}")
    return count, [[int(x) for x in l.split(",") if x.strip()] for l in lines[1:count + 1]]


def float32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def read_lorr_problem(path):
    with open(path, encoding="utf-8") as f:
        prob = json.load(f)
    base = os.path.dirname(os.path.abspath(path))
    for key in ("mapFile", "agentFile", "taskFile", "teamSize"):
        if key not in prob:
            fail(f"{path}: missing property {key}")
    rows, cols, blocked = read_lorr_map(os.path.join(base, prob["mapFile"]))
    n = prob["teamSize"]
    count, agent_lines = read_lorr_list(os.path.join(base, prob["agentFile"]))
    if count < n:
        fail(f"{path}: the agent file has {count} agents, teamSize is {n}")
    starts = [line[0] for line in agent_lines[:n]]
    _, task_lines = read_lorr_list(os.path.join(base, prob["taskFile"]))
    if not task_lines:
        fail(f"{path}: the task file has no task")
    # TaskManager: int num_tasks_reveal = (float numTasksReveal) * teamSize, in float arithmetic
    reveal = int(float32(float32(prob.get("numTasksReveal", 1)) * n))
    counter = prob.get("agentCounter", 10)
    size = float(prob.get("agentSize", 1.0))
    if counter <= 0 or size <= 0:
        fail(f"{path}: agentCounter {counter} and agentSize {size} must be positive")
    return {"rows": rows, "cols": cols, "blocked": blocked, "n": n, "starts": starts,
            "tasks": task_lines, "reveal": reveal, "counter": counter, "size": size}


def parse_lorr_path(text, seg_size, key, agent):
    """One agent's `[(t0,row,col,ori,counter):(A n,A n,...)]...` string. Returns the headers
    (t0 and the 4-field state) and the actions, one letter per recorded tick."""
    if not isinstance(text, str):
        fail(f"{key}[{agent}] is not a string")
    pos, headers, actions, sizes = 0, [], [], []
    for m in SEGMENT.finditer(text):
        if m.start() != pos:
            break
        pos = m.end()
        t0, row, col, ori, cnt = (int(m.group(k)) for k in range(1, 6))
        if t0 != len(headers) * seg_size:
            fail(f"{key}[{agent}]: segment {len(headers)} starts at {t0}, not {len(headers) * seg_size}")
        headers.append((t0, (row, col, ori, cnt)))
        body, got = m.group(6), 0
        if body:
            for run in body.split(","):
                rm = RUN.fullmatch(run)
                if not rm or rm.group(1) not in ACTIONS or int(rm.group(2)) < 1:
                    fail(f"{key}[{agent}], segment {len(headers) - 1}: bad run {run!r}")
                actions.append(rm.group(1) * int(rm.group(2)))
                got += int(rm.group(2))
        if got > seg_size:
            fail(f"{key}[{agent}], segment {len(headers) - 1}: {got} ticks, more than {seg_size}")
        sizes.append(got)
    if pos != len(text):
        fail(f"{key}[{agent}]: unreadable from character {pos}: {text[pos:pos + 40]!r}")
    last = max((k for k, z in enumerate(sizes) if z), default=-1)
    for k in range(last):
        if sizes[k] != seg_size:
            fail(f"{key}[{agent}]: segment {k} has {sizes[k]} ticks but a later segment is not empty")
    return headers, "".join(actions)


def open_interval(d0, dv, lower, upper):
    """The kit's intersect_open_linear_interval: times in [0, 1] at which d0 + dv*t lies in
    (lower, upper) shrunk by EPS; None if there are none."""
    if -EPS < dv < EPS:
        return (0.0, 1.0) if lower + EPS < d0 < upper - EPS else None
    t0, t1 = (lower - d0) / dv, (upper - d0) / dv
    if t0 > t1:
        t0, t1 = t1, t0
    teps = EPS / abs(dv)
    t0, t1 = max(0.0, t0 + teps), min(1.0, t1 - teps)
    return (t0, t1) if t0 <= t1 else None


def boxes_collide(a, sa, b, sb):
    """The kit's moving_boxes_collide: squares of sides sa, sb whose top-left corners move
    linearly from (a[0], a[1]) to (a[2], a[3]) and (b[0], b[1]) to (b[2], b[3]) during one tick
    overlap with positive area at some instant (touching, within EPS, is not a collision)."""
    if not (min(a[0], a[2]) < max(b[0], b[2]) + sb and max(a[0], a[2]) + sa > min(b[0], b[2])
            and min(a[1], a[3]) < max(b[1], b[3]) + sb and max(a[1], a[3]) + sa > min(b[1], b[3])):
        return False
    ix = open_interval(a[0] - b[0], (a[2] - a[0]) - (b[2] - b[0]), -sa, sb)
    iy = open_interval(a[1] - b[1], (a[3] - a[1]) - (b[3] - b[1]), -sa, sb)
    return ix is not None and iy is not None and max(ix[0], iy[0]) <= min(ix[1], iy[1])


def touched_cells(m, size):
    """Cells (row, col) a swept footprint overlaps with positive area."""
    x0, x1 = min(m[0], m[2]), max(m[0], m[2]) + size
    y0, y1 = min(m[1], m[3]), max(m[1], m[3]) + size
    return [(r, c)
            for r in range(math.floor(y0 + CELL_EPS), math.ceil(y1 - CELL_EPS))
            for c in range(math.floor(x0 + CELL_EPS), math.ceil(x1 - CELL_EPS))]


def check_lorr2026(problem_path, output_path):
    """Check a LoRR 2026 output against its problem.

    Ticks: the recorded actions of each agent are numbered 0..L-1; tick r moves the robots from
    time r to time r+1. Events, schedules and reveals carry the kit's tick counter after a tick,
    which is r+1 plus any unrecorded ticks before it (the kit's move_all_wait when the initial
    plan or the executor's process_new_plan overruns; then L < makespan, docs §5).

    Movement (ActionModelWithRotate::result_state, Counter.h): a state is (cell, orientation,
    counter, action in progress); robots start on the agent file's cells facing east, counter 0.
    An F, R or C ticks the counter; at agentCounter it takes effect (cell or orientation changes)
    and the counter resets. Once started, W pauses the action and any other letter (T too)
    continues the action in progress. The footprint is a square of side agentSize whose top-left
    corner is at (col, row), shifted by counter/agentCounter cells along the heading during an F.
    Checked every tick, as swept motions (which is stronger than the kit's end-of-tick sanity
    check, and includes it): no footprint leaves [0, cols] x [0, rows], none overlaps a blocked
    cell, and no two overlap with positive area at any instant of the tick (the kit's
    moving_boxes_collide, touching within 1e-6 allowed); the start state is checked too.
    A robot inside one of its delayIntervals [start, end) (ticks start..end-1) must record W.
    With plannerPaths, each recorded action is the planner's or W; a tick where every agent's
    planner action is T is an executor-timeout tick (all W, no task update follows it).

    Tasks (TaskManager.cpp, CompetitionSystem.cpp): tasks are revealed at time 0 and after each
    task update while fewer than int(numTasksReveal x teamSize) are open, task k taking task-file
    line k mod m. With actualSchedule, each agent's first entry is the first applied assignment
    (its time is the kit's uninitialised curr_timestep, so it is ignored); a later entry `t:x`
    takes effect at the first task update after time t. The applied assignment must hold only
    open tasks, no task twice, and keep every opened task with its opener. After each tick
    (except executor-timeout ticks), in agent order, an agent whose task's next errand is its
    cell (the origin cell during an F) completes that errand (one per update); after the last
    the task is finished and the agent unassigned. events, tasks and numTaskFinished must equal
    the recount. Unrecorded ticks are placed by matching the file's events (they can only lie
    between the kit's updates). Without actualSchedule (outputScreen 2) the file's events are
    checked for consistency instead: each event's agent stands on that errand at that time,
    each task's errands are done in order by one agent, and numTaskFinished counts its
    finishing events. Known kit bugs accepted (docs §5): segment headers may all carry the
    segment-0 state; paths may be shorter than makespan; errors/numPlannerErrors are not
    recounted."""
    P = read_lorr_problem(problem_path)
    with open(output_path, encoding="utf-8") as f:
        out = json.load(f)
    if out.get("version") != LORR_2026:
        fail(f"{output_path}: version {out.get('version')!r}, not {LORR_2026!r}")
    if out.get("actionModel", "MAPF_T") != "MAPF_T":
        fail(f"actionModel {out.get('actionModel')!r}, the 2026 kit writes MAPF_T")
    n, rows, cols, blocked = P["n"], P["rows"], P["cols"], P["blocked"]
    K, size = P["counter"], P["size"]
    if out.get("teamSize") != n:
        fail(f"teamSize {out.get('teamSize')}, the problem's is {n}")
    if out.get("agentMaxCounter", K) != K:
        fail(f"agentMaxCounter {out['agentMaxCounter']}, the problem's agentCounter is {K}")
    makespan = out["makespan"]
    seg_size = out.get("outputSegmentSize", 100)
    for key in ("start", "actualPaths"):
        if key not in out:
            fail(f"no `{key}` (written at outputScreen 1 or 2)")

    # --- start ---
    start = out["start"]
    if len(start) != n:
        fail(f"`start` has {len(start)} agents, teamSize is {n}")
    row, col, ori = [0] * n, [0] * n, [0] * n
    for i, s in enumerate(start):
        if len(s) != 3 or s[2] not in HEADINGS:
            fail(f"start[{i}] = {s} is not [row, col, E|S|W|N]")
        want = divmod(P["starts"][i], cols)
        if (s[0], s[1]) != want:
            fail(f"agent {i} starts on {s[:2]}, the agent file says {list(want)}")
        if s[2] != "E":
            fail(f"agent {i} starts facing {s[2]}, the kit always starts robots facing E")
        row[i], col[i], ori[i] = s[0], s[1], 0
    cnt, cur = [0] * n, [None] * n

    # --- paths ---
    headers, acts = [], []
    for i, text in enumerate(out["actualPaths"]):
        h, a = parse_lorr_path(text, seg_size, "actualPaths", i)
        headers.append(h)
        acts.append(a)
    if len(acts) != n:
        fail(f"actualPaths has {len(acts)} agents, teamSize is {n}")
    L = len(acts[0]) if acts else 0
    for i, a in enumerate(acts):
        if len(a) != L:
            fail(f"agent {i} has {len(a)} recorded ticks, agent 0 has {L}")
    if L > makespan:
        fail(f"{L} recorded ticks, more than makespan {makespan}")
    if n and len(headers[0]) * seg_size < L:
        fail(f"{len(headers[0])} segments of {seg_size} ticks cannot hold {L} ticks")
    unrecorded = makespan - L
    planned = None
    if "plannerPaths" in out:
        planned = [parse_lorr_path(t, seg_size, "plannerPaths", i)[1]
                   for i, t in enumerate(out["plannerPaths"])]
        if len(planned) != n or any(len(p) != L for p in planned):
            fail(f"plannerPaths do not have {n} agents of {L} ticks like actualPaths")
    timeout_tick = [bool(planned) and all(p[r] == "T" for p in planned) for r in range(L)]

    # --- delays ---
    delays = out.get("delayIntervals", [[] for _ in range(n)])
    if len(delays) != n:
        fail(f"delayIntervals has {len(delays)} agents, teamSize is {n}")
    delayed = [set() for _ in range(n)]
    for i, spans in enumerate(delays):
        prev_end = 0
        for span in spans:
            if len(span) != 2 or not span[0] < span[1] or span[0] < prev_end:
                fail(f"agent {i}: delay interval {span} is empty or overlaps the one before")
            prev_end = span[1]
            delayed[i].update(range(span[0], min(span[1], L)))

    # --- replay ---
    def corner(i):
        x, y = float(col[i]), float(row[i])
        if cur[i] == "F" and cnt[i] > 0:
            dr, dc = STEP[ori[i]]
            x, y = x + dc * cnt[i] / K, y + dr * cnt[i] / K
        return x, y

    def state(i):
        return (row[i], col[i], ori[i], cnt[i])

    def check_tick(motions, when):
        """Border, obstacles and pairwise collisions of one tick's swept motions."""
        cells = {}
        for i, m in enumerate(motions):
            if (min(m[0], m[2]) < -1e-9 or min(m[1], m[3]) < -1e-9
                    or max(m[0], m[2]) + size > cols + 1e-9 or max(m[1], m[3]) + size > rows + 1e-9):
                fail(f"{when}, agent {i}: its footprint leaves the map "
                     f"(corner ({m[1]:.3f}, {m[0]:.3f}) -> ({m[3]:.3f}, {m[2]:.3f}), row/col)")
            for cell in touched_cells(m, size):
                if cell in blocked and boxes_collide(m, size, (cell[1], cell[0]) * 2, 1.0):
                    fail(f"{when}, agent {i}: its footprint overlaps obstacle cell {list(cell)} "
                         f"(corner ({m[1]:.3f}, {m[0]:.3f}) -> ({m[3]:.3f}, {m[2]:.3f}), row/col)")
                cells.setdefault(cell, []).append(i)
        seen = set()
        for group in cells.values():
            for x in range(len(group)):
                for y in range(x + 1, len(group)):
                    i, j = group[x], group[y]
                    if (i, j) in seen:
                        continue
                    seen.add((i, j))
                    if boxes_collide(motions[i], size, motions[j], size):
                        a, b = motions[i], motions[j]
                        at_end = boxes_collide(a[2:] * 2, size, b[2:] * 2, size)
                        fail(f"{when}, agents {i} and {j}: footprints "
                             f"{'overlap after the tick' if at_end else 'collide during the tick'} "
                             f"(corners ({a[3]:.3f}, {a[2]:.3f}) and ({b[3]:.3f}, {b[2]:.3f}), row/col)")

    bounds = [divmod(s, cols) for s in P["starts"]]
    if any(not (0 <= r < rows and 0 <= c < cols) for r, c in bounds):
        fail("an agent file location is outside the map")
    check_tick([corner(i) * 2 for i in range(n)], "at the start")
    seg_states = {0: [state(i) for i in range(n)]}
    changes = []          # per tick: [(agent, new cell)] of robots whose cell changed
    for r in range(L):
        motions, moved = [], []
        for i in range(n):
            a = acts[i][r]
            if a != "W":
                if r in delayed[i]:
                    fail(f"tick {r}, agent {i}: records {a} while delayed (delayIntervals)")
                if timeout_tick[r]:
                    fail(f"tick {r}, agent {i}: records {a} on an executor-timeout tick "
                         f"(every planner action is T), the kit records W")
                if planned and planned[i][r] != a:
                    fail(f"tick {r}, agent {i}: records {a}, its planner action was {planned[i][r]} "
                         f"(the executed action is the planner's or W)")
            x0, y0 = corner(i)
            ex = a
            if cnt[i] > 0 and cur[i] is not None:
                if a == "W":
                    motions.append((x0, y0, x0, y0))
                    continue
                ex = cur[i]
            if ex in "FRC":
                cnt[i] += 1
                if cnt[i] >= K:
                    cnt[i], cur[i] = 0, None
                    if ex == "F":
                        dr, dc = STEP[ori[i]]
                        row[i], col[i] = row[i] + dr, col[i] + dc
                        moved.append((i, row[i] * cols + col[i]))
                    else:
                        ori[i] = (ori[i] + (1 if ex == "R" else 3)) % 4
                else:
                    cur[i] = ex
            else:
                cur[i] = None
            motions.append((x0, y0) + corner(i))
        check_tick(motions, f"tick {r}")
        changes.append(moved)
        if (r + 1) % seg_size == 0:
            seg_states[r + 1] = [state(i) for i in range(n)]
    final = [state(i) for i in range(n)]
    for i in range(n):
        for t0, h in headers[i]:
            true = seg_states.get(t0, final)[i] if t0 <= L else final[i]
            if h != seg_states[0][i] and h != true:
                fail(f"actualPaths[{i}]: segment header at {t0} is {list(h)}, neither the state at "
                     f"tick {t0} {list(true)} nor the start state {list(seg_states[0][i])} "
                     f"(the kit's header bug)")

    # --- tasks ---
    tasks = P["tasks"]
    file_tasks = out.get("tasks", [])
    for k, t in enumerate(file_tasks):
        want = [x for loc in tasks[k % len(tasks)] for x in divmod(loc, cols)]
        if len(t) != 3 or t[0] != k or t[2] != want:
            fail(f"tasks[{k}] = {t}: expected id {k} with errands {want} (task-file line "
                 f"{k % len(tasks)})")
    events = out.get("events", [])
    claimed = out["numTaskFinished"]
    if "actualSchedule" in out:
        times = place_unrecorded_ticks(P, out, L, changes, timeout_tick, unrecorded)
        finished = recount_lorr_tasks(P, out, L, changes, times)
        mode = "recounted"
    else:
        finished = check_lorr_events(P, out, L, changes, unrecorded)
        mode = "events checked (no actualSchedule)"
    if finished != claimed:
        fail(f"numTaskFinished is {claimed}, the {'recount gives' if mode == 'recounted' else 'events give'} "
             f"{finished}")
    return {"valid": True, "format": LORR_2026, "agents": n, "ticks": L, "makespan": makespan,
            "unrecorded_ticks": unrecorded, "executor_timeout_ticks": sum(timeout_tick),
            "delays": sum(len(d) for d in delays), "tasks_finished": finished, "tasks": mode,
            "events": len(events)}


def parse_lorr_schedule(text, agent):
    entries = []
    for item in text.split(",") if text else []:
        m = re.fullmatch(r"(-?\d+):(-?\d+)", item.strip())
        if not m:
            fail(f"actualSchedule[{agent}]: bad entry {item!r}")
        entries.append((int(m.group(1)), int(m.group(2))))
    return entries


def recount_lorr_tasks(P, out, L, changes, times, note=""):
    """Replays the task manager, with the task update after tick r at time times[r] (None for
    an executor-timeout tick, which has no update); returns the number of tasks finished.
    See check_lorr2026; note prefixes the messages."""
    def fail(reason):
        _fail(note + reason)

    n, cols, tasks, pool = P["n"], P["cols"], P["tasks"], P["reveal"]
    entries = lorr_schedule(out, n)
    file_events = [tuple(e) for e in out.get("events", [])]
    file_tasks = out.get("tasks", [])
    locs = list(P["starts"])
    errands = {}          # open task -> list of cells
    progress = {}         # open task -> errands done
    opener = {}           # opened task -> agent
    revealed = []         # (id, time)
    assign = [-1] * n
    recount = []
    finished = 0

    def reveal(t):
        while len(errands) < pool:
            k = len(revealed)
            errands[k] = tasks[k % len(tasks)]
            progress[k] = 0
            revealed.append((k, t))

    def apply(group, label):
        """Applies one application point's entries [(agent, task)] to assign, checking them."""
        for a, x in group:
            old = assign[a]
            if old != -1 and old in progress and progress[old] > 0 and x != old:
                fail(f"{label}: actualSchedule moves agent {a} from task {old}, which it has opened, "
                     f"to {x} (an opened task stays with its agent)")
            if x != -1:
                if x not in errands:
                    fail(f"{label}: actualSchedule gives agent {a} task {x}, which is not open "
                         f"(finished or not revealed)")
                if progress[x] > 0 and opener[x] != a:
                    fail(f"{label}: actualSchedule gives agent {a} task {x}, opened by agent {opener[x]}")
            assign[a] = x
        holders = {}
        for a, x in enumerate(assign):
            if x != -1:
                if x in holders:
                    fail(f"{label}: actualSchedule gives task {x} to agents {holders[x]} and {a}")
                holders[x] = a

    reveal(0)
    apply([(a, entries[a][0][1]) for a in range(n)], "first assignment")
    pending = sorted((t, a, x) for a in range(n) for t, x in entries[a][1:])
    p = 0                 # next pending entry
    e = 0                 # next file event
    for r in range(L):
        for a, loc in changes[r]:
            locs[a] = loc
        s = times[r]
        if s is None:
            continue
        while p < len(pending) and pending[p][0] < s:
            t, group = pending[p][0], []
            while p < len(pending) and pending[p][0] == t:
                group.append(pending[p][1:])
                p += 1
            apply(group, f"time {t}")
        for a in range(n):
            x = assign[a]
            if x == -1 or locs[a] != errands[x][progress[x]]:
                continue
            progress[x] += 1
            if progress[x] == 1:
                opener[x] = a
            recount.append((s, a, x, progress[x]))
            if progress[x] == len(errands[x]):
                del errands[x]
                del progress[x]
                assign[a] = -1
                finished += 1
        reveal(s)
        # compare with the file as we go, for a message at the first difference
        while e < len(file_events) and len(recount) > e:
            if file_events[e] != recount[e]:
                fail(f"time {recount[e][0]}: the recount's event {e} is {list(recount[e])} "
                     f"[time, agent, task, errands done], the file's is {list(file_events[e])}")
            e += 1
        if e < len(file_events) and file_events[e][0] <= s:
            ev = file_events[e]
            fail(f"time {ev[0]}: the file's event {e} {list(ev)} does not happen in the recount "
                 f"(agent {ev[1]} is on cell {list(divmod(locs[ev[1]], cols))}, holds task "
                 f"{assign[ev[1]]})")
    if e < len(file_events):
        fail(f"the file's event {e} {list(file_events[e])} does not happen in the recount")
    for k, (tid, t) in enumerate(revealed):
        if k >= len(file_tasks):
            fail(f"time {t}: the recount reveals task {tid}, the file's tasks end before")
        if file_tasks[k][1] != t:
            fail(f"task {tid} is revealed at time {file_tasks[k][1]} in the file, at {t} in the recount")
    if len(file_tasks) > len(revealed):
        fail(f"the file lists {len(file_tasks)} tasks, the recount reveals {len(revealed)}")
    return finished


def lorr_schedule(out, n):
    sched = out["actualSchedule"]
    if len(sched) != n:
        fail(f"actualSchedule has {len(sched)} agents, teamSize is {n}")
    entries = []
    for a, text in enumerate(sched):
        items = []
        for item in text.split(",") if text else []:
            m = re.fullmatch(r"(-?\d+):(-?\d+)", item.strip())
            if not m:
                fail(f"actualSchedule[{a}]: bad entry {item!r}")
            items.append((int(m.group(1)), int(m.group(2))))
        if not items:
            fail(f"actualSchedule[{a}] is empty (the kit writes every agent's first assignment)")
        ts = [t for t, _ in items[1:]]
        if ts != sorted(ts):
            fail(f"actualSchedule[{a}]: entry times {ts} are not in order")
        entries.append(items)
    return entries


def place_unrecorded_ticks(P, out, L, changes, timeout_tick, unrecorded):
    """The kit's tick counter after each recorded tick r: r+1 plus the unrecorded ticks before
    it (None for executor-timeout ticks, which have no task update). Unrecorded ticks are not in
    the output; this finds a placement (at most `unrecorded` in all, never undone) under which
    every event and schedule time is the time of a task update and the completions computed from
    the movement and the file's own schedule and events are exactly the file's events at each
    update; the caller then recounts independently with it."""
    real = [r for r in range(L) if not timeout_tick[r]]
    if not unrecorded:
        return [None if timeout_tick[r] else r + 1 for r in range(L)]
    n, tasks = P["n"], P["tasks"]
    entries = lorr_schedule(out, n)
    events = [tuple(e) for e in out.get("events", [])]
    by_time = {}
    for t, a, x, idx in events:
        by_time.setdefault(t, []).append((a, x, idx))
    anchors = sorted(set(by_time) | {t for es in entries for t, _ in es[1:]})
    # what each agent must stand on to complete an errand at an update of time s, from the
    # file's schedule and events: (from time, to time, cell, task, errands done after)
    moments = {}
    for t, a, x, idx in events:
        moments.setdefault(t, ([], []))[0].append((a, x, idx))
    for a, es in enumerate(entries):
        for t, x in es[1:]:
            moments.setdefault(t, ([], []))[1].append((a, x))
    assign = [es[0][1] for es in entries]
    progress = {}
    want = [[] for _ in range(n)]

    def set_want(a, s_from):
        x = assign[a]
        if want[a] and want[a][-1][1] is None:
            want[a][-1][1] = s_from
        if x != -1 and x >= 0:
            errs = tasks[x % len(tasks)]
            k = progress.get(x, 0)
            if k < len(errs):
                want[a].append([s_from, None, errs[k], x, k + 1])

    for a in range(n):
        set_want(a, 1)
    for t in sorted(moments):
        evs, ens = moments[t]
        touched = set()
        for a, x, idx in evs:
            progress[x] = idx
            if idx >= len(tasks[x % len(tasks)]) and assign[a] == x:
                assign[a] = -1
            touched.add(a)
        for a, x in ens:
            assign[a] = x
            touched.add(a)
        for a in touched:
            set_want(a, t + 1)
    # cells each agent stands on, per tick range
    stays = [{} for _ in range(n)]      # agent -> cell -> [(first tick, last tick)]
    since = [0] * n
    locs = list(P["starts"])
    for r in range(L):
        for a, loc in changes[r]:
            stays[a].setdefault(locs[a], []).append((since[a], r - 1))
            locs[a], since[a] = loc, r
    for a in range(n):
        stays[a].setdefault(locs[a], []).append((since[a], L - 1))
    hits = {}                           # tick -> [(first time, last time, agent, task, done)]
    for a in range(n):
        for s0, s1, cell, x, idx in want[a]:
            s1 = float("inf") if s1 is None else s1 - 1
            for r0, r1 in stays[a].get(cell, ()):
                for r in range(max(r0, s0 - 1 - unrecorded), min(r1, s1 - 1) + 1):
                    hits.setdefault(r, []).append((max(s0, r + 1), min(s1, r + 1 + unrecorded), a, x, idx))

    def below(s):
        k = bisect.bisect_left(anchors, s)
        return anchors[k - 1] if k else None

    back, prev_r, prev = {}, None, None
    for r in real:
        cur = {}
        for s in range(r + 1, r + 2 + unrecorded):
            done = sorted((a, x, idx) for lo, hi, a, x, idx in hits.get(r, ()) if lo <= s <= hi)
            if done != sorted(by_time.get(s, [])):
                continue
            low = below(s)
            if prev_r is None:
                if low is None or low <= 0:
                    cur[s] = None
                continue
            top = s - (r - prev_r)
            k = bisect.bisect_right(prev, top)
            if k and (low is None or prev[k - 1] >= low):
                cur[s] = prev[k - 1]
        if not cur:
            # recount with the placement that got furthest, for a message naming the difference
            times, s = [None] * L, max(prev) if prev else None
            for q in reversed([q for q in real if q < r]):
                times[q] = s
                s = back[q][s]
            shift = (max(prev) - prev_r - 1) if prev else 0
            for q in real:
                if q >= r:
                    times[q] = q + 1 + shift
            recount_lorr_tasks(P, out, L, changes, times, note=(
                f"no placement of the {unrecorded} unrecorded ticks (makespan {out['makespan']}, "
                f"{L} recorded) reproduces the file's events beyond tick {r}; with the best one, "))
            fail(f"tick {r}: no placement of the {unrecorded} unrecorded ticks (makespan "
                 f"{out['makespan']}, {L} recorded) makes the task updates reproduce the file's "
                 f"events up to here")
        back[r] = cur
        prev_r, prev = r, sorted(cur)
    ends = [s for s in prev or [] if not anchors or anchors[-1] <= s]
    if real and not ends:
        fail(f"the file has event or schedule times up to {anchors[-1]}, after the last task "
             f"update that any placement of the unrecorded ticks allows")
    times = [None] * L
    s = ends[-1] if real else None
    for r in reversed(real):
        times[r] = s
        s = back[r][s]
    return times


def check_lorr_events(P, out, L, changes, unrecorded):
    """Without actualSchedule: the file's events must be consistent with the movement; returns
    the number of finishing events. See check_lorr2026."""
    n, cols, tasks = P["n"], P["cols"], P["tasks"]
    file_tasks = out.get("tasks", [])
    timeline = [[(-1, s)] for s in P["starts"]]      # per agent: (first tick after which, cell)
    for r, moved in enumerate(changes):
        for a, loc in moved:
            timeline[a].append((r, loc))

    def cell_at(a, r):
        return timeline[a][bisect.bisect_right(timeline[a], (r, float("inf"))) - 1][1]

    done, owner, last_t, finished = {}, {}, {}, 0
    prev = None
    for k, ev in enumerate(out.get("events", [])):
        if len(ev) != 4:
            fail(f"event {k} {ev} is not [time, agent, task, errands done]")
        t, a, x, idx = ev
        if prev is not None and t < prev:
            fail(f"event {k} {ev} is earlier than the event before")
        prev = t
        if not 0 <= a < n or not 0 <= x < len(file_tasks):
            fail(f"event {k} {ev}: no agent {a} or task {x} in the file")
        if file_tasks[x][1] > t:
            fail(f"event {k} {ev}: task {x} is revealed at {file_tasks[x][1]}")
        if idx != done.get(x, 0) + 1:
            fail(f"time {t}, agent {a}: event {ev} completes errand {idx} of task {x}, "
                 f"{done.get(x, 0)} were done before")
        if owner.setdefault(x, a) != a:
            fail(f"time {t}, agent {a}: works on task {x}, opened by agent {owner[x]}")
        if last_t.get(a) == t:
            fail(f"time {t}, agent {a}: completes two errands at one task update")
        errand = tasks[x % len(tasks)][idx - 1]
        # the update at time t follows tick t-1, or an earlier one if unrecorded ticks intervene
        ticks = range(max(0, t - 1 - unrecorded), min(t - 1, L - 1) + 1)
        if not any(cell_at(a, r) == errand for r in ticks):
            fail(f"time {t}, agent {a}: event {ev} but the agent is on cell "
                 f"{list(divmod(cell_at(a, min(t - 1, L - 1)), cols))}, the errand is "
                 f"{list(divmod(errand, cols))}")
        done[x], last_t[a] = idx, t
        if idx == len(tasks[x % len(tasks)]):
            finished += 1
    return finished


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    try:
        if len(sys.argv) == 4:
            print(json.dumps(check(*sys.argv[1:])))
            return
        with open(sys.argv[2], encoding="utf-8") as f:
            version = json.load(f).get("version")
        if version != LORR_2026:
            fail(f"{sys.argv[2]}: version {version!r}; with two arguments the checker reads "
                 f"{LORR_2026!r} outputs (give MAP PLAN TRACE for mrpp-execution/1)")
        print(json.dumps(check_lorr2026(*sys.argv[1:])))
    except (OSError, ValueError, KeyError, IndexError, TypeError) as e:
        fail(f"unreadable input: {e}")


if __name__ == "__main__":
    main()
