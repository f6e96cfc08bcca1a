#!/usr/bin/env python3
"""Independent checker of League of Robot Runners (LoRR) lifelong runs (stdlib only).

Usage:  python3 tools/check/lifelong.py [--json] PROBLEM.json OUTPUT.json
        python3 tools/check/lifelong.py --self-test

PROBLEM.json is a LoRR problem (keys mapFile, agentFile, taskFile, teamSize, numTasksReveal;
other keys are ignored, so the 2023 and 2026 problem layouts are read too). OUTPUT.json is a run in
the 2024 start kit's output layout (`"version": "2024 LoRR"`, written by Start-Kit v2.1.2 with
`--outputScreen 1`, or by mrpp). Prints one line, `valid: S steps, N agents, F tasks finished
(numTaskFinished F)` and exits 0, or `invalid: RULE: message naming the step and the agents` and
exits 1 (also for unreadable or malformed input). Wrong usage exits 2. With --json the line is
{"valid": bool, "steps": S, "tasks_finished": F, "error": str|null} (on a refusal S and F are
what had been read and counted before the first broken rule, 0 if nothing). --self-test runs the
embedded cases, prints "N passed, M failed" and exits 0 iff all pass.

Written from docs/lorr-semantics.md and the start kit's code (Start-Kit tag v2.1.2, "K2"), NOT
from mrpp's code, and shares no code with mrpp, so it can serve as a second opinion on mrpp.

Problem (K2 src/driver.cpp, src/Grid.cpp, inc/common.h):
  * paths in the problem JSON are relative to its folder; numTasksReveal defaults to 1.
  * map: a first line starting with 't' is a MovingAI header (line 2 `height R`, line 3
    `width C`, line 4 `map`), otherwise the first line is `R,C`; then R rows of which the first
    C characters count: '@' and 'T' are obstacles, every other character is free.
    A location is row * C + col.
  * agent and task files: lines starting with '#' are skipped anywhere; the first line's first
    comma-separated field is a count; then one line per entry. Agents: count >= teamSize, the
    first teamSize lines, first field = start location; every start is east-facing and free.
    Tasks: `count` lines, each a comma-separated errand list; task id k uses line k mod count
    (the file is cycled).
  * the open-task pool is int(numTasksReveal * teamSize) computed in single precision, as the kit
    does (float * int in C++): e.g. 0.29 x 100 is 29 there (28 in double precision).
Output rules (names as printed):
  * version: "version" is "2024 LoRR"; "actionModel" is "MAPF_T" or "MAPF".
  * teamSize: equals the problem's; start, actualPaths (and plannerPaths, actualSchedule when
    present) have one entry per agent.
  * start: start[i] = [row, col, "E"] of agent i's location (for MAPF any orientation PlanViz
    knows, E/N/W/S/N/A, since MAPF agents have none).
  * paths: comma-separated letters, all paths of one length = the number of steps S.
    MAPF_T: F forward in the facing direction (0 east = col+1, 1 south = row+1, 2 west = col-1,
    3 north = row-1), R clockwise (o+1), C counter-clockwise (o+3), W wait, T (timeout / no
    action) = wait. MAPF, letters as PlanViz reads them (PlanViz v2.1.0 to v3.1.0,
    script/util.py state_transition_mapf): U = row+1 (down on screen), D = row-1 (up on
    screen), L = col-1, R = col+1, W and T wait. (PlanViz v1.3.5-v2.0.0 had U and D the other
    way round.)
  * unallowed move: every position stays on the map (F off the east or west edge does not wrap
    to the next row) and never enters an obstacle.
  * vertex conflict: no two agents on one cell after a step (nor at the start).
  * edge conflict: no two agents swap cells in one step. Following (entering a cell its occupant
    leaves in the same step) and rotating cycles (of 4 or more agents) are allowed, as in K2.
  * rejected step (when plannerPaths is present): at every step the executed actions equal the
    proposed ones, or all executed actions are W, the proposal is indeed invalid (a move breaking
    a rule above, or a T = missing action in a step that is not a timeout) and the step has an
    entry in `errors` ([agent1, agent2, step, message]); `errors` has one entry per such step.
  * Timeouts: a step in which every agent's action is T is a timeout step, in which the kit does
    no task update (no schedule, errand or reveal), unless the output shows an update at that
    step (an event, a schedule entry or a task revealed then). numEntryTimeouts is at most the
    number of all-T steps.
  * The task update after each other step t (t = steps executed so far, the clock of events,
    schedules and reveals), in the kit's order:
    schedule: each actualSchedule entry "t:task" (per agent, "t:task,t:task,...", -1 = none)
      applies at update t; the assigned task must be open (revealed at an earlier update, not
      finished); no two agents hold a task at once; an agent that has done an errand of its task
      keeps that task until it is finished. Finishing a task frees its agent (-1) without a
      schedule entry. Without actualSchedule, the assignment is taken from the events (an
      agent takes a task with its first errand) and the same rules are checked on it.
    events: every agent holding a task that stands on the task's next errand completes it:
      the event [t, agent, task, idx] with idx = number of errands done (1-based), at most one
      errand per agent per step, errands in order. The output's events at t must be exactly
      these (any order within a step; events in time order, 1 <= t <= S): an event that
      is not earned is refused (wrong place, wrong errand index, task not the agent's, a second
      errand in one step, task worked on by two agents); an earned one that is missing is a
      "missed completion".
    reveal: "tasks" lists [id, t_revealed, [r1, c1, r2, c2, ...]] for ids 0, 1, 2, ... in order;
      task k's errands are the task file's line k mod count; at t = 0 the pool is filled and
      after every update as many tasks are revealed (t_revealed = t) as have finished, so the
      pool of open tasks stays at int(numTasksReveal * teamSize); no task is listed that was not
      revealed.
  * numTaskFinished: the events whose idx equals their task's errand count (tasks finished)
    number numTaskFinished.
  * makespan: an integer, 0 <= makespan <= S. numPlannerErrors = len(errors) and
    numScheduleErrors = len(scheduleErrors) when present.
"""

import copy
import json
import os
import struct
import subprocess
import sys
import tempfile

VERSION = "2024 LoRR"
# MAPF_T orientation o: 0 east, 1 south, 2 west, 3 north -> (d_row, d_col)
FORWARD = ((0, 1), (1, 0), (0, -1), (-1, 0))
# PlanViz v2.1.0+ (script/util.py state_transition_mapf): U row+1, D row-1, L col-1, R col+1
MAPF_MOVES = {"U": (1, 0), "D": (-1, 0), "L": (0, -1), "R": (0, 1), "W": (0, 0), "T": (0, 0)}
MAPF_T_LETTERS = set("FRCWT")
PLANVIZ_DIRECTIONS = ("E", "N", "W", "S", "N/A")
ORI_NAME = ("east", "south", "west", "north")


class Invalid(Exception):
    """A broken rule: `rule` names it, the message says where (step, agents, cells)."""

    def __init__(self, rule, message):
        super().__init__(f"{rule}: {message}")
        self.rule = rule


def is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


# ------------------------------------------------------------------ problem files


def read_lines(path, what):
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise Invalid("problem", f"cannot read the {what} {path}: {e.strerror}")
    text = data.decode("utf-8", errors="replace")
    return [line.rstrip("\r") for line in text.split("\n")]


def load_map(path):
    """(rows, cols, blocked bytearray indexed by row * cols + col), as K2 src/Grid.cpp reads it."""
    lines = read_lines(path, "map")
    first = lines[0] if lines else ""
    if first[:1] == "t":
        if len(lines) < 4:
            raise Invalid("problem", f"{path}: MovingAI header is cut short")
        h, w = lines[1].split(), lines[2].split()
        # The kit takes line 2 as the row count and line 3 as the column count whatever they say.
        if len(h) < 2 or len(w) < 2 or h[0] != "height" or w[0] != "width":
            raise Invalid("problem", f"{path}: header lines 2-3 must be 'height R' and 'width C'")
        try:
            rows, cols = int(h[1]), int(w[1])
        except ValueError:
            raise Invalid("problem", f"{path}: bad height/width {h[1]!r}/{w[1]!r}")
        body = 4
    else:
        fields = first.split(",")
        try:
            rows, cols = int(fields[0]), int(fields[1])
        except (ValueError, IndexError):
            raise Invalid("problem", f"{path}:1: neither a MovingAI header nor 'rows,cols'")
        body = 1
    if rows <= 0 or cols <= 0:
        raise Invalid("problem", f"{path}: map size {rows}x{cols} is empty")
    blocked = bytearray(rows * cols)
    for r in range(rows):
        if body + r >= len(lines):
            raise Invalid("problem", f"{path}: only {r} of {rows} map rows")
        line = lines[body + r]
        if len(line) < cols:
            raise Invalid("problem", f"{path}:{body + r + 1}: row has {len(line)} cells, expected {cols}")
        for c in range(cols):
            if line[c] in "@T":
                blocked[r * cols + c] = 1
    return rows, cols, blocked


def entry_lines(path, what):
    """[(line number, text)] of the lines that are not comments, as K2 inc/common.h reads them."""
    return [(n + 1, l) for n, l in enumerate(read_lines(path, what)) if l[:1] != "#"]


def parse_int(text, path, lineno):
    try:
        return int(text.strip())
    except ValueError:
        raise Invalid("problem", f"{path}:{lineno}: {text.strip()!r} is not an integer")


def load_problem(path):
    try:
        with open(path, encoding="utf-8-sig") as f:
            spec = json.load(f)
    except OSError as e:
        raise Invalid("problem", f"cannot read {path}: {e.strerror}")
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise Invalid("problem", f"{path} is not JSON: {e}")
    if not isinstance(spec, dict):
        raise Invalid("problem", f"{path} is not a JSON object")
    for key in ("mapFile", "agentFile", "taskFile"):
        if not isinstance(spec.get(key), str):
            raise Invalid("problem", f"{path}: missing property {key}")
    team = spec.get("teamSize")
    if not is_int(team) or team < 0:
        raise Invalid("problem", f"{path}: teamSize {team!r} is not a non-negative integer")
    reveal = spec.get("numTasksReveal", 1)
    if not isinstance(reveal, (int, float)) or isinstance(reveal, bool):
        raise Invalid("problem", f"{path}: numTasksReveal {reveal!r} is not a number")
    base = os.path.dirname(path)
    rows, cols, blocked = load_map(os.path.join(base, spec["mapFile"]))

    apath = os.path.join(base, spec["agentFile"])
    alines = entry_lines(apath, "agent file")
    if not alines:
        raise Invalid("problem", f"{apath}: empty")
    count = parse_int(alines[0][1].split(",")[0], apath, alines[0][0])
    if count < team or len(alines) - 1 < team:
        raise Invalid("problem", f"{apath}: {max(0, min(count, len(alines) - 1))} agents, teamSize is {team}")
    starts = []
    for i in range(team):
        n, text = alines[1 + i]
        loc = parse_int(text.split(",")[0], apath, n)
        if not 0 <= loc < rows * cols:
            raise Invalid("problem", f"{apath}:{n}: agent {i}'s start {loc} is off the {rows}x{cols} map")
        if blocked[loc]:
            raise Invalid("problem", f"{apath}:{n}: agent {i}'s start ({loc // cols},{loc % cols}) is an obstacle")
        starts.append(loc)

    tpath = os.path.join(base, spec["taskFile"])
    tlines = entry_lines(tpath, "task file")
    if not tlines:
        raise Invalid("problem", f"{tpath}: empty")
    m = parse_int(tlines[0][1].split(",")[0], tpath, tlines[0][0])
    if m <= 0 or len(tlines) - 1 < m:
        raise Invalid("problem", f"{tpath}: the count says {m} tasks, the file has {len(tlines) - 1}")
    pool = int(f32(f32(float(reveal)) * f32(float(team))))
    return {
        "path": path, "rows": rows, "cols": cols, "blocked": blocked, "team": team,
        "starts": starts, "task_lines": tlines[1:m + 1], "m": m, "task_path": tpath,
        "pool": pool, "cache": {},
    }


def task_errands(problem, k):
    """Errand locations of task id k: the task file's line k mod m."""
    cache = problem["cache"]
    i = k % problem["m"]
    if i not in cache:
        n, text = problem["task_lines"][i]
        fields = [f for f in text.split(",")]
        if not text.strip():
            raise Invalid("problem", f"{problem['task_path']}:{n}: task line {i} is blank")
        locs = [parse_int(f, problem["task_path"], n) for f in fields]
        cells = problem["rows"] * problem["cols"]
        for loc in locs:
            if not 0 <= loc < cells:
                raise Invalid("problem", f"{problem['task_path']}:{n}: errand {loc} is off the map")
        cache[i] = locs
    return cache[i]


# ------------------------------------------------------------------ the output


def cell(problem, loc):
    return f"({loc // problem['cols']},{loc % problem['cols']})"


def split_path(s, what):
    if not isinstance(s, str):
        raise Invalid("paths", f"{what} is not a string")
    return [] if s == "" else s.split(",")


def parse_schedule(s, agent):
    if not isinstance(s, str):
        raise Invalid("schedule", f"actualSchedule of agent {agent} is not a string")
    out = []
    if s == "":
        return out
    for item in s.split(","):
        parts = item.split(":")
        try:
            t, task = int(parts[0]), int(parts[1])
            if len(parts) != 2:
                raise ValueError
        except (ValueError, IndexError):
            raise Invalid("schedule", f"actualSchedule of agent {agent}: {item!r} is not 't:task'")
        if out and t <= out[-1][0]:
            raise Invalid("schedule", f"actualSchedule of agent {agent}: times not increasing at {item!r}")
        out.append((t, task))
    return out


def check(problem, out):
    """Checks the run `out` (a parsed output JSON) against `problem`; returns the summary dict.
    Raises Invalid; the exception carries `partial` = (steps, tasks finished so far)."""
    state = {"steps": 0, "finished": 0}
    try:
        _check(problem, out, state)
    except Invalid as e:
        e.partial = (state["steps"], state["finished"])
        raise
    return {"steps": state["steps"], "agents": problem["team"], "tasks_finished": state["finished"],
            "numTaskFinished": out["numTaskFinished"]}


def _check(problem, out, state):
    rows, cols, blocked = problem["rows"], problem["cols"], problem["blocked"]
    n = problem["team"]
    if not isinstance(out, dict):
        raise Invalid("version", "the output is not a JSON object")
    if out.get("version") != VERSION:
        raise Invalid("version", f"version is {out.get('version')!r}, not {VERSION!r}")
    model = out.get("actionModel")
    if model not in ("MAPF_T", "MAPF"):
        raise Invalid("version", f"actionModel is {model!r}, not 'MAPF_T' or 'MAPF'")
    if out.get("teamSize") != n:
        raise Invalid("teamSize", f"teamSize is {out.get('teamSize')!r}, the problem has {n} agents")
    for key in ("start", "actualPaths"):
        if not isinstance(out.get(key), list) or len(out[key]) != n:
            got = len(out[key]) if isinstance(out.get(key), list) else "no"
            raise Invalid("teamSize", f"{key} has {got} entries for {n} agents")
    for key in ("plannerPaths", "actualSchedule"):
        if key in out and (not isinstance(out[key], list) or len(out[key]) != n):
            raise Invalid("teamSize", f"{key} does not have one entry per agent ({n})")
    for key in ("events", "tasks"):
        if not isinstance(out.get(key), list):
            raise Invalid(key, f"the output has no {key} list (run the kit with --outputScreen 1)")
    if not is_int(out.get("numTaskFinished")):
        raise Invalid("numTaskFinished", "numTaskFinished is missing or not an integer")

    # start
    for i, s in enumerate(out["start"]):
        want = [problem["starts"][i] // cols, problem["starts"][i] % cols]
        ok = isinstance(s, list) and len(s) == 3 and s[:2] == want
        if not (ok and (s[2] == "E" if model == "MAPF_T" else s[2] in PLANVIZ_DIRECTIONS)):
            raise Invalid("start", f"agent {i} starts at {json.dumps(s)}, the problem says "
                          f"{json.dumps(want + ['E'])}")

    # paths
    letters = MAPF_T_LETTERS if model == "MAPF_T" else set(MAPF_MOVES)
    paths = [split_path(p, f"actualPaths[{i}]") for i, p in enumerate(out["actualPaths"])]
    steps = len(paths[0]) if paths else 0
    planned = None
    if "plannerPaths" in out:
        planned = [split_path(p, f"plannerPaths[{i}]") for i, p in enumerate(out["plannerPaths"])]
    for name, ps in (("actualPaths", paths), ("plannerPaths", planned)):
        for i, p in enumerate(ps or []):
            if len(p) != steps:
                raise Invalid("paths", f"{name}[{i}] has {len(p)} actions, actualPaths[0] has {steps}")
            for t, a in enumerate(p):
                if a not in letters:
                    raise Invalid("paths", f"{name}[{i}] step {t + 1}: {a!r} is not a {model} action "
                                  f"({', '.join(sorted(letters))})")
    state["steps"] = steps

    # errors / rejected steps bookkeeping
    errors = out.get("errors")
    error_steps = {}
    if isinstance(errors, list):
        for e in errors:
            if not (isinstance(e, list) and len(e) >= 3 and is_int(e[2])):
                raise Invalid("rejected step", f"errors entry {json.dumps(e)} is not [agent1, agent2, step, message]")
            error_steps[e[2]] = error_steps.get(e[2], 0) + 1
        if is_int(out.get("numPlannerErrors")) and out["numPlannerErrors"] != len(errors):
            raise Invalid("rejected step", f"numPlannerErrors is {out['numPlannerErrors']} but errors lists {len(errors)}")
    serrors = out.get("scheduleErrors")
    if isinstance(serrors, list) and is_int(out.get("numScheduleErrors")) and out["numScheduleErrors"] != len(serrors):
        raise Invalid("schedule", f"numScheduleErrors is {out['numScheduleErrors']} but scheduleErrors lists {len(serrors)}")

    # events, indexed by step
    events_at = {}
    last_t = 0
    for e in out["events"]:
        if not (isinstance(e, list) and len(e) == 4 and all(is_int(x) for x in e)):
            raise Invalid("events", f"event {json.dumps(e)} is not [step, agent, task, idx]")
        t, a, x, idx = e
        if t < last_t:
            raise Invalid("events", f"event {e} comes after events of step {last_t} (not in time order)")
        if not 1 <= t <= steps:
            raise Invalid("events", f"event {e} is at step {t}, outside 1..{steps}")
        if not 0 <= a < n:
            raise Invalid("events", f"event {e} names agent {a}, the team has {n}")
        last_t = t
        events_at.setdefault(t, []).append((a, x, idx))

    # tasks listed
    tasks = out["tasks"]
    for k, entry in enumerate(tasks):
        if not (isinstance(entry, list) and len(entry) == 3 and is_int(entry[0]) and is_int(entry[1])
                and isinstance(entry[2], list) and all(is_int(v) for v in entry[2])):
            raise Invalid("tasks", f"tasks[{k}] = {json.dumps(entry)} is not [id, t_revealed, [r1, c1, ...]]")
        if entry[0] != k:
            raise Invalid("tasks", f"tasks[{k}] has id {entry[0]}; ids must be 0, 1, 2, ... in order")
        want = []
        for loc in task_errands(problem, k):
            want += [loc // cols, loc % cols]
        if entry[2] != want:
            raise Invalid("tasks", f"task {k}'s errands are {entry[2]}, the task file's line "
                          f"{k % problem['m']} (id {k} mod {problem['m']}) gives {want}")
    revealed_at = {}
    for entry in tasks:
        revealed_at.setdefault(entry[1], 0)
        revealed_at[entry[1]] += 1

    # schedule
    schedule_at = {}
    have_schedule = "actualSchedule" in out
    if have_schedule:
        for a, s in enumerate(out["actualSchedule"]):
            for t, x in parse_schedule(s, a):
                if not 1 <= t <= steps:
                    raise Invalid("schedule", f"agent {a} is assigned task {x} at step {t}, outside 1..{steps}")
                if x < -1:
                    raise Invalid("schedule", f"agent {a} is assigned task {x} at step {t}")
                schedule_at.setdefault(t, []).append((a, x))

    # ---- simulation
    loc = list(problem["starts"])
    ori = [0] * n
    seen = {}
    for i, l in enumerate(loc):
        if l in seen:
            raise Invalid("vertex conflict", f"agents {seen[l]} and {i} both start at {cell(problem, l)}")
        seen[l] = i
    progress = {}        # open task -> errands done
    holder = {}          # task -> agent holding it
    assign = [-1] * n
    next_id = 0
    pool = problem["pool"]
    all_t = 0
    rejected = 0

    def reveal(t):
        nonlocal next_id
        while len(progress) < pool:
            k = next_id
            if k >= len(tasks):
                raise Invalid("reveal", f"task {k} should be revealed at step {t} (pool of {pool} open tasks) "
                              f"but the output lists only {len(tasks)} tasks")
            if tasks[k][1] != t:
                raise Invalid("reveal", f"task {k} is listed as revealed at step {tasks[k][1]}, the pool "
                              f"of {pool} open tasks reveals it at step {t}")
            progress[k] = 0
            next_id += 1

    def step_result(acts, i):
        """Agent i's (loc, ori) after action acts[i], or raises with what went wrong."""
        a = acts[i]
        r, c = divmod(loc[i], cols)
        o = ori[i]
        if model == "MAPF_T":
            if a == "F":
                dr, dc = FORWARD[o]
                how = f"F facing {ORI_NAME[o]}"
            else:
                if a == "R":
                    o = (o + 1) % 4
                elif a == "C":
                    o = (o + 3) % 4
                return loc[i], o
        else:
            dr, dc = MAPF_MOVES[a]
            how = a
        nr, nc = r + dr, c + dc
        if not (0 <= nr < rows and 0 <= nc < cols):
            return None, f"agent {i} leaves the {rows}x{cols} map from ({r},{c}) by {how}"
        nl = nr * cols + nc
        if blocked[nl]:
            return None, f"agent {i} enters the obstacle ({nr},{nc}) from ({r},{c}) by {how}"
        return nl, o

    def joint(acts, t):
        """Next (locs, oris) of a joint action, or (rule, message) of its first violation."""
        nlocs, noris = [], []
        occupied = {}
        moves = {}
        for i in range(n):
            nl, no = step_result(acts, i)
            if nl is None:
                return None, ("unallowed move", f"{no} at step {t}")
            if nl in occupied:
                return None, ("vertex conflict", f"agents {occupied[nl]} and {i} both at "
                              f"{cell(problem, nl)} after step {t}")
            occupied[nl] = i
            if nl != loc[i]:
                j = moves.get((nl, loc[i]))
                if j is not None:
                    return None, ("edge conflict", f"agents {j} and {i} swap {cell(problem, loc[i])} "
                                  f"and {cell(problem, nl)} at step {t}")
                moves[(loc[i], nl)] = i
            nlocs.append(nl)
            noris.append(no)
        return (nlocs, noris), None

    reveal(0)
    for t in range(1, steps + 1):
        acts = [p[t - 1] for p in paths]
        timeout = all(a == "T" for a in acts)
        all_t += timeout
        if planned is not None:
            proposal = [p[t - 1] for p in planned]
            if proposal != acts:
                if not all(a == "W" for a in acts):
                    i = next(i for i in range(n) if proposal[i] != acts[i])
                    raise Invalid("rejected step", f"at step {t} agent {i} executed {acts[i]} but the "
                                  f"planner proposed {proposal[i]} (only a rejected proposal, all W, may differ)")
                if "T" not in proposal:
                    ok, _ = joint(proposal, t)
                    if ok is not None:
                        raise Invalid("rejected step", f"step {t}: every agent waits but the proposed joint "
                                      f"action is valid")
                if errors is not None and error_steps.get(t, 0) != 1:
                    raise Invalid("rejected step", f"step {t} was rejected (all W) but errors has "
                                  f"{error_steps.get(t, 0)} entries for it")
                rejected += 1
        nxt, bad = joint(acts, t)
        if bad:
            raise Invalid(*bad)
        loc, ori = nxt

        update = (not timeout) or t in events_at or t in schedule_at or revealed_at.get(t, 0) > 0
        if not update:
            continue

        # schedule (or the assignment the events imply)
        if have_schedule:
            for a, x in schedule_at.get(t, []):
                y = assign[a]
                if y == x:
                    continue
                if y != -1 and progress.get(y, 0) > 0:
                    raise Invalid("schedule", f"agent {a} leaves task {y} at step {t} after doing "
                                  f"{progress[y]} of its errands (an opened task stays with its agent)")
                if x != -1 and x not in progress:
                    why = "not revealed yet" if x >= next_id else "already finished"
                    raise Invalid("schedule", f"agent {a} is assigned task {x} at step {t}, {why}")
                if y != -1 and holder.get(y) == a:
                    del holder[y]
                assign[a] = x
            for a, x in schedule_at.get(t, []):
                if x != -1 and assign[a] == x:
                    b = holder.get(x)
                    if b is not None and b != a and assign[b] == x:
                        raise Invalid("schedule", f"task {x} is held by agents {b} and {a} at step {t}")
                    holder[x] = a
        else:
            for a, x, idx in events_at.get(t, []):
                if idx != 1 or assign[a] == x:
                    continue
                if x not in progress:
                    why = "not revealed yet" if x >= next_id else "already finished"
                    raise Invalid("events", f"event [{t}, {a}, {x}, 1]: task {x} is {why}")
                y = assign[a]
                if y != -1 and progress.get(y, 0) > 0:
                    raise Invalid("events", f"event [{t}, {a}, {x}, 1]: agent {a} starts task {x} while "
                                  f"task {y} is opened ({progress[y]} errands done)")
                b = holder.get(x)
                if b is not None and b != a:
                    if progress[x] > 0:
                        raise Invalid("events", f"event [{t}, {a}, {x}, 1]: task {x} is worked on by agents "
                                      f"{b} and {a}")
                    assign[b] = -1
                if y != -1:
                    holder.pop(y, None)
                assign[a] = x
                holder[x] = a

        # errands earned at this update
        expected = {}
        for a in range(n):
            x = assign[a]
            if x != -1:
                errands = task_errands(problem, x)
                if loc[a] == errands[progress[x]]:
                    expected[a] = (x, progress[x] + 1)
        written = events_at.get(t, [])
        got = {}
        for a, x, idx in written:
            if a in got:
                raise Invalid("events", f"agent {a} has two events at step {t}: {[t, a] + list(got[a])} and "
                              f"{[t, a, x, idx]} (at most one errand per agent per step)")
            got[a] = (x, idx)
            if expected.get(a) == (x, idx):
                continue
            ev = [t, a, x, idx]
            if x not in progress:
                why = "not revealed yet" if x >= next_id else "already finished"
                raise Invalid("events", f"event {ev}: task {x} is {why}")
            if assign[a] != x:
                b = holder.get(x)
                who = f"agent {b}" if b is not None and assign[b] == x else "no agent"
                src = "actualSchedule" if have_schedule else "its earlier events"
                raise Invalid("events", f"event {ev}: agent {a} holds task {assign[a]} at step {t} "
                              f"(from {src}), task {x} is held by {who}")
            if idx != progress[x] + 1:
                raise Invalid("events", f"event {ev}: task {x} has {progress[x]} errands done, so its next "
                              f"event has idx {progress[x] + 1} (errands in order)")
            errand = task_errands(problem, x)[idx - 1]
            raise Invalid("events", f"event {ev}: agent {a} is at {cell(problem, loc[a])} after step {t}, "
                          f"errand {idx - 1} of task {x} is at {cell(problem, errand)}")
        for a, (x, idx) in sorted(expected.items()):
            if a not in got:
                errand = task_errands(problem, x)[idx - 1]
                raise Invalid("missed completion", f"agent {a} stands on errand {idx - 1} "
                              f"{cell(problem, errand)} of its task {x} after step {t} but no event "
                              f"[{t}, {a}, {x}, {idx}] was written")
        for a, (x, idx) in expected.items():
            progress[x] = idx
            if idx == len(task_errands(problem, x)):
                del progress[x]
                holder.pop(x, None)
                assign[a] = -1
                state["finished"] += 1
        reveal(t)

    if len(tasks) > next_id:
        raise Invalid("reveal", f"the output lists {len(tasks)} tasks but only {next_id} were revealed "
                      f"(task {next_id} at step {tasks[next_id][1]} is extra)")
    if errors is not None and planned is not None and len(errors) != rejected:
        raise Invalid("rejected step", f"errors lists {len(errors)} entries but {rejected} steps were rejected")
    if is_int(out.get("numEntryTimeouts")) and out["numEntryTimeouts"] > all_t:
        raise Invalid("paths", f"numEntryTimeouts is {out['numEntryTimeouts']} but only {all_t} steps are all T")
    if out["numTaskFinished"] != state["finished"]:
        raise Invalid("numTaskFinished", f"numTaskFinished is {out['numTaskFinished']}, the events finish "
                      f"{state['finished']} tasks")
    ms = out.get("makespan")
    if not is_int(ms) or not 0 <= ms <= steps:
        raise Invalid("makespan", f"makespan {ms!r} is not an integer in 0..{steps} (the path length)")


def check_files(problem_path, output_path):
    """{"valid", "steps", "tasks_finished", "error"} plus "agents"/"numTaskFinished" when valid."""
    try:
        problem = load_problem(problem_path)
        try:
            with open(output_path, encoding="utf-8") as f:
                out = json.load(f)
        except OSError as e:
            raise Invalid("version", f"cannot read {output_path}: {e.strerror}")
        except (json.JSONDecodeError, UnicodeDecodeError) as e:
            raise Invalid("version", f"{output_path} is not JSON: {e}")
        r = check(problem, out)
    except Invalid as e:
        steps, finished = getattr(e, "partial", (0, 0))
        return {"valid": False, "steps": steps, "tasks_finished": finished, "error": str(e)}
    return {"valid": True, "steps": r["steps"], "tasks_finished": r["tasks_finished"], "error": None,
            "agents": r["agents"], "numTaskFinished": r["numTaskFinished"]}


# ------------------------------------------------------------------ self-test
# A tiny stand-in for the start kit (greedy scheduler, greedy one-step planner) writes valid runs
# in the kit's layout on a small hand-made problem; each broken variant must be refused by the
# rule it breaks.

SELF_MAP = "type octile\nheight 5\nwidth 6\nmap\n......\n.@@.@.\n......\n.@..T.\n......\n"
# agents at (1,0) [east of it an obstacle], (0,3), (0,4); a fourth line unused
SELF_AGENTS = "# agents\n4\n6\n3\n4\n29\n"
# tasks: two-errand, one-errand, repeated errand (13,13), three-errand, ...
SELF_TASKS = "# tasks\n7\n12,2\n24\n13,13\n0,17,26\n# comment\n20,9\n27,5\n15,14,25\n"


def write_problem(tmp, name, reveal=1.5, team=3, map_text=SELF_MAP, agents=SELF_AGENTS, tasks=SELF_TASKS):
    d = os.path.join(tmp, name)
    os.makedirs(d, exist_ok=True)
    for fname, text in (("m.map", map_text), ("a.agents", agents), ("t.tasks", tasks)):
        with open(os.path.join(d, fname), "w") as f:
            f.write(text)
    spec = {"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": team,
            "numTasksReveal": reveal, "version": VERSION}
    p = os.path.join(d, "problem.json")
    with open(p, "w") as f:
        json.dump(spec, f)
    return p


def emulate(problem, model, steps, timeouts=(), reject=(), policy="greedy"):
    """A run in the kit's output layout (greedy scheduler, one greedy step per call)."""
    rows, cols, blocked = problem["rows"], problem["cols"], problem["blocked"]
    n = problem["team"]
    loc, ori = list(problem["starts"]), [0] * n
    progress, assign, tasks = {}, [-1] * n, []
    actual, planned = [[] for _ in range(n)], [[] for _ in range(n)]
    sched = [[] for _ in range(n)]
    events, errors, finished, t = [], [], 0, 0
    cost = [0] * n

    def reveal(t):
        while len(progress) < problem["pool"]:
            k = len(tasks)
            tasks.append([k, t, sum(([l // cols, l % cols] for l in task_errands(problem, k)), [])])
            progress[k] = 0

    def dist_to(goal):
        d = {goal: 0}
        frontier = [goal]
        while frontier:
            nxt = []
            for l in frontier:
                r, c = divmod(l, cols)
                for dr, dc in FORWARD:
                    nr, nc = r + dr, c + dc
                    if 0 <= nr < rows and 0 <= nc < cols and not blocked[nr * cols + nc] and nr * cols + nc not in d:
                        d[nr * cols + nc] = d[l] + 1
                        nxt.append(nr * cols + nc)
            frontier = nxt
        return d

    reveal(0)
    while t < steps:
        # scheduler: free agents take the lowest open unassigned task
        proposal = list(assign)
        held = {x for x in proposal if x != -1}
        for a in range(n):
            if proposal[a] == -1:
                free = [x for x in sorted(progress) if x not in held]
                if free:
                    proposal[a] = free[0]
                    held.add(free[0])
        # planner: one step toward the next errand, no following, no shared target
        acts = ["W"] * n
        taken = set()
        for a in range(n):
            x = proposal[a]
            if policy != "greedy" or x == -1:
                continue
            d = dist_to(task_errands(problem, x)[progress[x]])
            r, c = divmod(loc[a], cols)
            best = None
            for o, (dr, dc) in enumerate(FORWARD):
                nr, nc = r + dr, c + dc
                nl = nr * cols + nc
                if 0 <= nr < rows and 0 <= nc < cols and nl in d and d[nl] < d.get(loc[a], 1 << 30):
                    best = (o, nl) if best is None else best
            if best is None:
                continue
            o, nl = best
            if model == "MAPF":
                if nl not in loc and nl not in taken:
                    acts[a] = {(1, 0): "U", (-1, 0): "D", (0, -1): "L", (0, 1): "R"}[FORWARD[o]]
                    taken.add(nl)
            elif o != ori[a]:
                acts[a] = "R" if (o - ori[a]) % 4 in (1, 2) else "C"
            elif nl not in loc and nl not in taken:
                acts[a] = "F"
                taken.add(nl)
        for a in range(n):
            cost[a] += proposal[a] != -1
        if t + 1 in timeouts:       # one timeout step before this call's answer
            for a in range(n):
                actual[a].append("T")
                planned[a].append("T")
            t += 1
            continue
        prop = list(acts)
        if t + 1 in reject:          # the planner's answer misses the last agent's action
            prop[-1] = "T"
            acts = ["W"] * n
            errors.append([-1, -1, t + 1, "incorrect vector size"])
        for a in range(n):
            planned[a].append(prop[a])
            actual[a].append(acts[a])
            if model == "MAPF":
                dr, dc = MAPF_MOVES[acts[a]]
                loc[a] += dr * cols + dc
            elif acts[a] == "F":
                dr, dc = FORWARD[ori[a]]
                loc[a] += dr * cols + dc
            elif acts[a] in "RC":
                ori[a] = (ori[a] + (1 if acts[a] == "R" else 3)) % 4
        t += 1
        # update: schedule, errands, reveal
        for a in range(n):
            if not sched[a] or sched[a][-1][1] != proposal[a]:
                sched[a].append((t, proposal[a]))
        assign = proposal
        for a in range(n):
            x = assign[a]
            if x != -1 and loc[a] == task_errands(problem, x)[progress[x]]:
                progress[x] += 1
                events.append([t, a, x, progress[x]])
                if progress[x] == len(task_errands(problem, x)):
                    del progress[x]
                    assign[a] = -1
                    finished += 1
        reveal(t)
    return {
        "actionModel": model, "version": VERSION, "teamSize": n, "numTaskFinished": finished,
        "makespan": max(cost) if cost else 0, "numPlannerErrors": len(errors), "numScheduleErrors": 0,
        "numEntryTimeouts": len(timeouts),
        "start": [[l // cols, l % cols, "E"] for l in problem["starts"]],
        "actualPaths": [",".join(p) for p in actual], "plannerPaths": [",".join(p) for p in planned],
        "plannerTimes": [0.001] * steps, "errors": errors,
        "actualSchedule": [",".join(f"{t}:{x}" for t, x in s) for s in sched],
        "plannerSchedule": [",".join(f"{t}:{x}" for t, x in s) for s in sched],
        "scheduleErrors": [], "events": events, "tasks": tasks,
    }


def set_action(out, agent, step, letter, key="actualPaths", both=True):
    for k in (("actualPaths", "plannerPaths") if both else (key,)):
        if k in out:
            p = out[k][agent].split(",")
            p[step - 1] = letter
            out[k][agent] = ",".join(p)


def self_test():
    passed = failed = 0

    def expect(name, problem, out, rule=None, finished=None):
        nonlocal passed, failed
        try:
            r = check(problem, out)
            ok = rule is None and (finished is None or r["tasks_finished"] == finished)
            got = f"valid, {r['tasks_finished']} finished"
        except Invalid as e:
            ok = rule is not None and e.rule == rule
            got = str(e)
        passed, failed = passed + ok, failed + (not ok)
        if not ok:
            print(f"FAIL {name}: expected {rule or 'valid'}, got {got}")

    with tempfile.TemporaryDirectory() as tmp:
        ppath = write_problem(tmp, "p")
        prob = load_problem(ppath)
        base = {}
        for model in ("MAPF_T", "MAPF"):
            run = emulate(prob, model, 60, timeouts={7, 8, 31}, reject={12, 40})
            base[model] = run
            fin = run["numTaskFinished"]
            sane = fin >= 3 and any(e[3] == 2 for e in run["events"]) and run["numPlannerErrors"] == 2
            passed, failed = passed + sane, failed + (not sane)
            if not sane:
                print(f"FAIL emulator {model}: {fin} finished, events {run['events']}")
            expect(f"{model} greedy run", prob, run, finished=fin)
            no_sched = copy.deepcopy(run)
            for k in ("actualSchedule", "plannerSchedule", "plannerPaths", "errors"):
                del no_sched[k]
            expect(f"{model} without schedule and planner paths", prob, no_sched, finished=fin)
        run = base["MAPF_T"]

        # problem reading: rows,cols header, reveal pool in single precision
        p2 = write_problem(tmp, "p2", map_text="5,6\n......\n.@@.@.\n......\n.@..T.\n......\n")
        expect("rows,cols map header", load_problem(p2), run, finished=run["numTaskFinished"])
        ok = load_problem(write_problem(tmp, "p3", reveal=0.29, team=100,
                                        agents="100\n" + "0\n" * 100))["pool"] == 29
        passed, failed = passed + ok, failed + (not ok)
        if not ok:
            print("FAIL pool 0.29 x 100 should be 29 (single precision, as the kit)")

        # a 2x3 free map, 4 agents in a 2x2 block, MAPF model
        p4 = write_problem(tmp, "p4", map_text="2,3\n...\n...\n", team=4, reveal=0.5,
                           agents="4\n0\n1\n4\n3\n", tasks="2\n2,5\n5,2\n")
        prob4 = load_problem(p4)

        def small(paths, model="MAPF"):
            return {"actionModel": model, "version": VERSION, "teamSize": 4, "numTaskFinished": 0,
                    "makespan": 0, "start": [[0, 0, "E"], [0, 1, "E"], [1, 1, "E"], [1, 0, "E"]],
                    "actualPaths": paths, "events": [],
                    "tasks": [[0, 0, [0, 2, 1, 2]], [1, 0, [1, 2, 0, 2]]]}
        # step 1 rotates all four (a 4-cycle); step 2: agent 0 steps out, agent 1 follows it
        expect("rotating 4-cycle and following", prob4, small(["R,R", "U,W", "L,W", "D,W"]))
        expect("edge conflict (swap)", prob4, small(["R", "L", "W", "W"]), "edge conflict")
        expect("vertex conflict", prob4, small(["R", "W", "W", "W"]), "vertex conflict")
        expect("off the map (MAPF)", prob4, small(["D", "W", "W", "W"]), "unallowed move")
        expect("MAPF_T F wraps east edge", prob4,
               small(["W,W", "F,F", "W,W", "W,W"], "MAPF_T"), "unallowed move")
        expect("bad MAPF letter", prob4, small(["F", "W", "W", "W"]), "paths")
        bad = small(["R,R", "U,W", "L,W", "D,W"])
        bad["tasks"][1][1] = 1
        expect("reveal time", prob4, bad, "reveal")

        # the greedy base with hand-set first actions: all agents wait in the first steps
        idle = emulate(prob, "MAPF_T", 10, policy="wait")
        expect("idle run", prob, idle, finished=0)
        for name, edits, rule in (
            ("obstacle", [(0, 1, "F")], "unallowed move"),
            ("vertex conflict at step 1", [(1, 1, "F")], "vertex conflict"),
            ("off the map", [(2, 1, "F"), (2, 2, "F"), (2, 3, "F")], "unallowed move"),
            ("bad MAPF_T letter", [(0, 2, "U")], "paths"),
        ):
            b = copy.deepcopy(idle)
            for a, s, letter in edits:
                set_action(b, a, s, letter)
            expect(name, prob, b, rule)
        b = copy.deepcopy(base["MAPF"])
        set_action(b, 1, 1, "R")
        set_action(b, 2, 1, "L")
        expect("MAPF swap", prob, b, "edge conflict")

        def mutate(name, rule, fn, src=None):
            b = copy.deepcopy(src or run)
            fn(b)
            expect(name, prob, b, rule)

        ev = run["events"]
        fin_ev = next(e for e in ev if e[3] == 2)
        mutate("version", "version", lambda b: b.update(version="2023 LoRR"))
        mutate("action model", "version", lambda b: b.update(actionModel="MAPF_R"))
        mutate("teamSize", "teamSize", lambda b: b.update(teamSize=4))
        mutate("start cell", "start", lambda b: b["start"][0].__setitem__(1, 1))
        mutate("start orientation", "start", lambda b: b["start"][0].__setitem__(2, "N"))
        mutate("path length", "paths", lambda b: b["actualPaths"].__setitem__(0, b["actualPaths"][0][:-2]))
        mutate("numTaskFinished", "numTaskFinished", lambda b: b.update(numTaskFinished=b["numTaskFinished"] + 1))
        mutate("makespan", "makespan", lambda b: b.update(makespan=61))
        mutate("task errands", "tasks", lambda b: b["tasks"][2][2].__setitem__(0, 4))
        mutate("task id order", "tasks", lambda b: b["tasks"].insert(0, b["tasks"].pop(1)))
        mutate("extra task", "reveal", lambda b: b["tasks"].append([len(b["tasks"]), 60, b["tasks"][len(b["tasks"]) % 7][2]]))
        mutate("missing task", "reveal", lambda b: b["tasks"].pop())
        later = next(k for k, e in enumerate(run["tasks"]) if e[1] > 0)
        mutate("reveal time", "reveal", lambda b: b["tasks"][later].__setitem__(1, b["tasks"][later][1] + 1))
        mutate("dropped event (missed completion)", "missed completion", lambda b: b["events"].remove(fin_ev))
        mutate("event idx", "events", lambda b: b["events"][ev.index(fin_ev)].__setitem__(3, 3))
        mutate("event agent", "events", lambda b: b["events"][ev.index(fin_ev)].__setitem__(1, (fin_ev[1] + 1) % 3))
        def late(b):
            b["events"][ev.index(fin_ev)][0] += 1
            b["events"].sort(key=lambda e: e[0])
        mutate("event late", "missed completion", late)
        mutate("duplicate event", "events", lambda b: b["events"].insert(ev.index(fin_ev), list(fin_ev)))
        mutate("event out of time order", "events", lambda b: b["events"].append(list(ev[0])))
        at7 = next(k for k, e in enumerate(ev) if e[0] > 7)
        mutate("event at a timeout step", "events", lambda b: b["events"].insert(at7, [7, 0, 0, 1]))

        def first_entry(b, agent, entry):
            s = b["actualSchedule"][agent].split(",")
            b["actualSchedule"][agent] = ",".join([entry] + s[1:])
        mutate("schedule: unrevealed task", "schedule", lambda b: first_entry(b, 0, "1:50"))
        mutate("schedule: one task, two agents", "schedule",
               lambda b: first_entry(b, 1, b["actualSchedule"][0].split(",")[0]))

        def leave_opened(b):
            a, x = fin_ev[1], fin_ev[2]
            first = next(e for e in ev if e[2] == x and e[3] == 1)
            s = [tuple(map(int, i.split(":"))) for i in b["actualSchedule"][a].split(",")]
            s = [i for i in s if i[0] != first[0] + 1] + [(first[0] + 1, -1)]
            b["actualSchedule"][a] = ",".join(f"{t}:{x}" for t, x in sorted(s))
        mutate("schedule: agent leaves an opened task", "schedule", leave_opened)
        moving = next(t + 1 for t, a in enumerate(run["actualPaths"][0].split(",")) if a not in "WT")
        mutate("executed differs from proposed", "rejected step", lambda b: set_action(b, 0, moving, "W", both=False))
        mutate("rejected step without error", "rejected step",
               lambda b: (b["errors"].pop(), b.update(numPlannerErrors=1)))
        mutate("valid proposal rejected", "rejected step",
               lambda b: set_action(b, 2, 12, "W", key="plannerPaths", both=False))
        mutate("numPlannerErrors", "rejected step", lambda b: b.update(numPlannerErrors=3))
        mutate("numEntryTimeouts", "paths", lambda b: b.update(numEntryTimeouts=4))

        def no_sched(fn):
            def f(b):
                for k in ("actualSchedule", "plannerSchedule"):
                    del b[k]
                fn(b)
            return f
        mutate("no schedule: dropped event", "missed completion", no_sched(lambda b: b["events"].remove(fin_ev)))
        mutate("no schedule: event agent", "events",
               no_sched(lambda b: b["events"][ev.index(fin_ev)].__setitem__(1, (fin_ev[1] + 1) % 3)))
        # agent a opens task x; before finishing it, an event claims a first errand of another task
        first = next(e for e in ev if e[2] == fin_ev[2] and e[3] == 1)
        other = next(e for e in ev if e[3] == 1 and e[1] != fin_ev[1] and first[0] < e[0] < fin_ev[0] + 20)

        def second_task(b):
            b["events"][ev.index(other)][1] = fin_ev[1]
        mutate("no schedule: second task while one is opened", "events", no_sched(second_task))

        # the command line: exit codes and --json
        opath = os.path.join(tmp, "run.json")
        with open(opath, "w") as f:
            json.dump(run, f)
        bpath = os.path.join(tmp, "bad.json")
        b = copy.deepcopy(run)
        b["numTaskFinished"] += 1
        with open(bpath, "w") as f:
            json.dump(b, f)
        for args, code, check_out in (
            ([ppath, opath], 0, lambda o: o.startswith("valid: 60 steps, 3 agents")),
            (["--json", ppath, opath], 0,
             lambda o: json.loads(o) == {"valid": True, "steps": 60, "tasks_finished": run["numTaskFinished"], "error": None}),
            ([ppath, bpath], 1, lambda o: o.startswith("invalid: numTaskFinished")),
            ([ppath, bpath, "--json"], 1, lambda o: json.loads(o)["valid"] is False and json.loads(o)["steps"] == 60),
            ([ppath, os.path.join(tmp, "none.json")], 1, lambda o: o.startswith("invalid:")),
            ([ppath], 2, lambda o: True),
            (["--json"], 2, lambda o: True),
        ):
            r = subprocess.run([sys.executable, __file__] + args, capture_output=True, text=True)
            ok = r.returncode == code and check_out(r.stdout.strip())
            passed, failed = passed + ok, failed + (not ok)
            if not ok:
                print(f"FAIL command line {args[-2:]}: exit {r.returncode}, {r.stdout.strip()!r} {r.stderr.strip()!r}")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    as_json = "--json" in argv
    rest = [a for a in argv if a != "--json"]
    if len(rest) != 2 or any(a.startswith("-") for a in rest):
        print("usage: lifelong.py [--json] PROBLEM.json OUTPUT.json | --self-test", file=sys.stderr)
        return 2
    result = check_files(rest[0], rest[1])
    if as_json:
        print(json.dumps({k: result[k] for k in ("valid", "steps", "tasks_finished", "error")}))
    elif result["valid"]:
        print(f"valid: {result['steps']} steps, {result['agents']} agents, {result['tasks_finished']} tasks "
              f"finished (numTaskFinished {result['numTaskFinished']})")
    else:
        print(f"invalid: {result['error']}")
    return 0 if result["valid"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
