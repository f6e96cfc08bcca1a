#!/usr/bin/env python3
"""Independent checker for mrpp continuous plans (Python 3 standard library only).

Usage:  python3 tools/check/continuous.py WORLD.json PLAN.json
        python3 tools/check/continuous.py --self-test

Prints one JSON line: {"valid": true, "steps": T, "total_path": .., "mean_utd":
.., "min_clearance": ..} (exit 0) or {"valid": false, "reason": "..."} (exit 1,
also for unreadable or malformed input, the reason then naming the file).
Wrong usage exits 2. --self-test runs the embedded cases, prints "N passed, M
failed" and exits 0 iff all pass.

This file was written from the rules below, NOT from mrpp's code; it shares
no code with mrpp, so it can serve as a second opinion on mrpp's validator.

World: {"workspace": [x_min, y_min, x_max, y_max] (x_min <= x_max, y_min <=
  y_max), "obstacles": [[[x, y], ...], ...] (optional, default []; closed
  polygons given as vertex rings of >= 3 vertices, any orientation, convex or
  not; "inside" is the even-odd rule), "robots": [{"start": [x, y], "goal":
  [x, y], "radius": r >= 0, "speed": v >= 0}] (at least one), "epsilon": e >= 0
  (default 1.0), "step_limit": n >= 0 (default 1000), "source" (optional)}.
  All numbers must be finite (NaN / Infinity literals are refused).
Plan ("plan envelope"): "format" (if present) is "mrpp-plan/1"; "family" (if
  present) is "continuous"; "solved" must be true; "metrics" (optional, an
  object or null) may claim metrics; "agents" is [{"start", "goal", "path":
  [[x, y], ...]}], agents[i] belonging to robots[i]; an agent's "start" and
  "goal" must be [x, y] points but are not compared with its robot's (rule 2
  compares the path with the world).
  Other keys ("rules", "utd", "world", ...) are ignored.
Rules (TOL = 1e-9 on every distance rule):
  1. as many agents as robots; every path non-empty, all paths of one length
     L (T = L - 1 steps, dt = 1); every coordinate a finite number.
  2. path[0] is within TOL of the robot's start; the last position is within
     epsilon + TOL of its goal.
  3. arrival freezes: let a be the first index whose position is within
     epsilon of the goal (distance <= epsilon, no TOL); every later position
     equals path[a] exactly (no TOL: a robot that has arrived does not move;
     the spec says "within TOL" for rule 2 but "equals" here). A path whose
     last position is only within epsilon + TOL has no arrival to freeze.
  4. speed: every step's length <= speed + TOL.
  5. workspace: every position p keeps the disc inside: x_min <= p.x - r + TOL,
     p.x + r <= x_max + TOL, likewise for y.
  6. obstacles, swept: for every step, the segment p(t-1) -> p(t) keeps a
     distance >= r - TOL from every obstacle; that distance is 0 if an
     endpoint is inside the polygon or the segment meets an edge, else the
     least distance between the segment and the polygon's edges.
  7. robots, swept: for every step and every pair (a, b) moving linearly over
     the step, the least centre distance during the step (distance from the
     origin to the segment (a(t-1) - b(t-1)) -> (a(t) - b(t))) is >= r_a + r_b
     - TOL.
  Rules 6 and 7 only look at steps: a plan with T = 0 (every robot already
  within epsilon of its goal) is not checked against obstacles or other
  robots at all. "step_limit" is read (and must be well formed) but T is NOT
  compared with it: the rules above do not ask for that. The world itself is
  only checked for form: starts or goals outside the workspace, inside
  obstacles or overlapping, and self-crossing polygons are not refused; the
  plan is judged by rules 1-7 alone.
Metrics of a valid plan: steps = T; total_path = sum over robots of the sum of
  their step lengths; mean_utd = mean over t = 0..T of sum_i |goal_i - p_i(t)|;
  min_clearance = least of (rule-6 distance - r) over robots, steps and
  obstacles and (rule-7 distance - r_a - r_b) over pairs and steps; when there
  is nothing to measure (T = 0, or one robot and no obstacles) it is +infinity
  and printed as null (a claimed number is then a mismatch; a claimed null
  is, as always, not compared).
  Claimed metrics (not null) "steps", "total_path", "mean_utd",
  "min_clearance" must match: steps exactly (26 or 26.0), floats to relative
  1e-9 (absolute 1e-9 near zero); a mismatch makes the plan invalid, naming
  the metric. Every other claimed metric is ignored, notably
  "total_deviation" (needs an ideal-path computation this checker does not
  do) and "runtime_ms".
"""
import json
import math
import os
import subprocess
import sys
import tempfile

TOL = 1e-9


class Invalid(Exception):
    pass


def is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def is_num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def is_point(p):
    return isinstance(p, list) and len(p) == 2 and all(is_num(c) for c in p)


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        raise Invalid(f"{path}: invalid JSON at line {e.lineno}, column {e.colno}: {e.msg}")
    except (OSError, UnicodeDecodeError) as e:
        raise Invalid(f"{path}: cannot read: {e}")


def fmt(p):
    return "(" + ", ".join(f"{c:.9g}" for c in p) + ")"


# ---------------------------------------------------------------- geometry

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1])


def dist(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


def cross(o, a, b):
    """(a - o) x (b - o): > 0 when o, a, b turn left."""
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def point_segment_distance(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    len2 = dx * dx + dy * dy
    if len2 == 0.0:
        return dist(p, a)
    t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2
    t = min(1.0, max(0.0, t))
    return math.hypot(p[0] - (a[0] + t * dx), p[1] - (a[1] + t * dy))


def in_box(a, b, p):
    """p (collinear with a-b) lies within the bounding box of a-b."""
    return (min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
            and min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


def segments_meet(p1, p2, q1, q2):
    d1, d2 = cross(q1, q2, p1), cross(q1, q2, p2)
    d3, d4 = cross(p1, p2, q1), cross(p1, p2, q2)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    return ((d1 == 0 and in_box(q1, q2, p1)) or (d2 == 0 and in_box(q1, q2, p2))
            or (d3 == 0 and in_box(p1, p2, q1)) or (d4 == 0 and in_box(p1, p2, q2)))


def segment_segment_distance(p1, p2, q1, q2):
    if segments_meet(p1, p2, q1, q2):
        return 0.0
    return min(point_segment_distance(p1, q1, q2), point_segment_distance(p2, q1, q2),
               point_segment_distance(q1, p1, p2), point_segment_distance(q2, p1, p2))


def inside_polygon(p, ring):
    """Even-odd rule (points on the boundary may go either way; their edge distance is 0)."""
    x, y = p
    inside = False
    j = len(ring) - 1
    for i in range(len(ring)):
        (xi, yi), (xj, yj) = ring[i], ring[j]
        if (yi > y) != (yj > y):
            xc = xi + (y - yi) * (xj - xi) / (yj - yi)
            if x < xc:
                inside = not inside
        j = i
    return inside


def segment_polygon_distance(a, b, ring):
    if inside_polygon(a, ring) or inside_polygon(b, ring):
        return 0.0
    return min(segment_segment_distance(a, b, ring[i - 1], ring[i]) for i in range(len(ring)))


def swept_pair_distance(a0, a1, b0, b1):
    """Least distance between two points moving linearly a0->a1 and b0->b1 over one step."""
    return point_segment_distance((0.0, 0.0), sub(a0, b0), sub(a1, b1))


# ---------------------------------------------------------------- input

def read_world(world, name):
    if not isinstance(world, dict):
        raise Invalid(f"{name}: world is not a JSON object")
    ws = world.get("workspace")
    if not (isinstance(ws, list) and len(ws) == 4 and all(is_num(c) for c in ws)
            and ws[0] <= ws[2] and ws[1] <= ws[3]):
        raise Invalid(f"{name}: 'workspace' must be [x_min, y_min, x_max, y_max] "
                      f"with x_min <= x_max and y_min <= y_max, got {ws!r}")
    obstacles = world.get("obstacles", [])
    if obstacles is None:
        obstacles = []
    if not isinstance(obstacles, list):
        raise Invalid(f"{name}: 'obstacles' is not a list")
    rings = []
    for k, poly in enumerate(obstacles):
        if not (isinstance(poly, list) and len(poly) >= 3 and all(is_point(p) for p in poly)):
            raise Invalid(f"{name}: obstacle {k} is not a list of at least 3 [x, y] points")
        rings.append([tuple(p) for p in poly])
    robots = world.get("robots")
    if not isinstance(robots, list) or not robots:
        raise Invalid(f"{name}: 'robots' must be a non-empty list")
    parsed = []
    for i, r in enumerate(robots):
        if not isinstance(r, dict):
            raise Invalid(f"{name}: robot {i} is not an object")
        for key in ("start", "goal"):
            if not is_point(r.get(key)):
                raise Invalid(f"{name}: robot {i}: '{key}' must be [x, y], got {r.get(key)!r}")
        for key in ("radius", "speed"):
            if not (is_num(r.get(key)) and r[key] >= 0):
                raise Invalid(f"{name}: robot {i}: '{key}' must be a non-negative number, "
                              f"got {r.get(key)!r}")
        parsed.append({"start": tuple(r["start"]), "goal": tuple(r["goal"]),
                       "radius": r["radius"], "speed": r["speed"]})
    eps = world.get("epsilon", 1.0)
    if not (is_num(eps) and eps >= 0):
        raise Invalid(f"{name}: 'epsilon' must be a non-negative number, got {eps!r}")
    limit = world.get("step_limit", 1000)
    if not (is_int(limit) and limit >= 0):
        raise Invalid(f"{name}: 'step_limit' must be a non-negative integer, got {limit!r}")
    return {"workspace": ws, "obstacles": rings, "robots": parsed, "epsilon": eps}


def read_plan(plan, name, robots):
    if not isinstance(plan, dict):
        raise Invalid(f"{name}: plan is not a JSON object")
    if "format" in plan and plan["format"] != "mrpp-plan/1":
        raise Invalid(f"{name}: unsupported plan format {plan['format']!r}")
    if "family" in plan and plan["family"] != "continuous":
        raise Invalid(f"{name}: plan family is {plan['family']!r}, not 'continuous'")
    if plan.get("solved") is not True:
        raise Invalid(f"{name} holds no solved plan (status: {plan.get('status')!r})")
    metrics = plan.get("metrics")
    if metrics is not None and not isinstance(metrics, dict):
        raise Invalid(f"{name}: 'metrics' is not an object")
    agents = plan.get("agents")
    if not isinstance(agents, list) or not all(isinstance(a, dict) for a in agents):
        raise Invalid(f"{name}: 'agents' is not a list of objects")
    if len(agents) != len(robots):
        raise Invalid(f"{name}: plan has {len(agents)} agents but the world has "
                      f"{len(robots)} robots")
    paths = []
    for i, a in enumerate(agents):
        for key in ("start", "goal"):
            if not is_point(a.get(key)):
                raise Invalid(f"{name}: agent {i}: '{key}' must be [x, y], got {a.get(key)!r}")
        path = a.get("path")
        if not isinstance(path, list) or not path:
            raise Invalid(f"{name}: agent {i}: path is missing or empty")
        for k, p in enumerate(path):
            if not is_point(p):
                raise Invalid(f"{name}: agent {i}: position {k} {p!r} is not [x, y] "
                              f"with finite numbers")
        if len(path) != len(paths[0] if paths else path):
            raise Invalid(f"{name}: agent {i}'s path has {len(path)} positions, "
                          f"agent 0's has {len(paths[0])}")
        paths.append([tuple(p) for p in path])
    return paths, metrics or {}


# ---------------------------------------------------------------- rules

def check(world, paths, metrics):
    """Check the rules; return the recomputed metrics."""
    robots, rings, eps = world["robots"], world["obstacles"], world["epsilon"]
    x_min, y_min, x_max, y_max = world["workspace"]
    steps = len(paths[0]) - 1
    total_path = 0.0
    for i, (path, r) in enumerate(zip(paths, robots)):
        goal, rad = r["goal"], r["radius"]
        if dist(path[0], r["start"]) > TOL:
            raise Invalid(f"agent {i}: path starts at {fmt(path[0])}, not at its start "
                          f"{fmt(r['start'])}")
        if dist(path[-1], goal) > eps + TOL:
            raise Invalid(f"agent {i}: path ends at {fmt(path[-1])}, "
                          f"{dist(path[-1], goal):.9g} from its goal {fmt(goal)} "
                          f"(epsilon {eps:.9g})")
        arrive = next((t for t, p in enumerate(path) if dist(p, goal) <= eps), len(path))
        for t in range(arrive + 1, len(path)):
            if path[t] != path[arrive]:
                raise Invalid(f"agent {i}: arrived (within epsilon of its goal) at t={arrive} "
                              f"at {fmt(path[arrive])} but is at {fmt(path[t])} at t={t}")
        for t in range(1, len(path)):
            d = dist(path[t - 1], path[t])
            if d > r["speed"] + TOL:
                raise Invalid(f"agent {i}: step t={t - 1}->{t} is {d:.9g} long, "
                              f"more than its speed {r['speed']:.9g}")
            total_path += d
        for t, (x, y) in enumerate(path):
            if not (x_min <= x - rad + TOL and x + rad <= x_max + TOL
                    and y_min <= y - rad + TOL and y + rad <= y_max + TOL):
                raise Invalid(f"agent {i}: its disc (radius {rad:.9g}) at {fmt((x, y))} at t={t} "
                              f"leaves the workspace {fmt(world['workspace'])}")

    min_clear = math.inf
    for t in range(1, steps + 1):
        for i, (path, r) in enumerate(zip(paths, robots)):
            for k, ring in enumerate(rings):
                d = segment_polygon_distance(path[t - 1], path[t], ring)
                if d < r["radius"] - TOL:
                    what = "touches or enters" if d == 0 else f"comes within {d:.9g} of"
                    raise Invalid(f"agent {i}: step t={t - 1}->{t} from {fmt(path[t - 1])} to "
                                  f"{fmt(path[t])} {what} obstacle {k} "
                                  f"(radius {r['radius']:.9g})")
                min_clear = min(min_clear, d - r["radius"])
        for a in range(len(paths)):
            for b in range(a + 1, len(paths)):
                pa, pb = paths[a], paths[b]
                d = swept_pair_distance(pa[t - 1], pa[t], pb[t - 1], pb[t])
                need = robots[a]["radius"] + robots[b]["radius"]
                if d < need - TOL:
                    raise Invalid(f"agents {a} and {b} collide during step t={t - 1}->{t}: "
                                  f"least centre distance {d:.9g} < sum of radii {need:.9g} "
                                  f"({fmt(pa[t - 1])}->{fmt(pa[t])} vs "
                                  f"{fmt(pb[t - 1])}->{fmt(pb[t])})")
                min_clear = min(min_clear, d - need)

    utd = [sum(dist(r["goal"], path[t]) for path, r in zip(paths, robots))
           for t in range(steps + 1)]
    result = {"steps": steps, "total_path": total_path, "mean_utd": sum(utd) / len(utd),
              "min_clearance": min_clear if math.isfinite(min_clear) else None}
    for key, value in result.items():
        claimed = metrics.get(key)
        if claimed is None:
            continue
        if key == "steps":
            ok = is_num(claimed) and claimed == value  # 26.0 is 26 exactly
        else:
            ok = (value is not None and is_num(claimed)
                  and math.isclose(claimed, value, rel_tol=1e-9, abs_tol=1e-9))
        if not ok:
            shown = "+infinity (nothing to measure)" if value is None else repr(value)
            raise Invalid(f"metric {key}: the plan claims {claimed!r}, recomputed {shown}")
    return result


def check_files(world_path, plan_path):
    try:
        world = read_world(load_json(world_path), world_path)
        paths, metrics = read_plan(load_json(plan_path), plan_path, world["robots"])
        return dict(valid=True, **check(world, paths, metrics))
    except Invalid as e:
        return {"valid": False, "reason": str(e)}


# ---------------------------------------------------------------- self-test

def w_make(robots, obstacles=(), workspace=(0, 0, 10, 10), **extra):
    world = {"workspace": list(workspace), "obstacles": [list(map(list, o)) for o in obstacles],
             "robots": [{"start": s, "goal": g, "radius": r, "speed": v} for s, g, r, v in robots]}
    world.update(extra)
    return world


def p_make(world, paths, drop=(), **extra):
    """A plan envelope for world; agents[i] takes robot i's start and goal (if it has one)."""
    agents = [{"path": p} for p in paths]
    for a, r in zip(agents, world["robots"]):
        a.update(start=r["start"], goal=r["goal"])
    plan = {"format": "mrpp-plan/1", "family": "continuous", "solved": True, "status": "solved",
            "planner": "hand", "rules": {"dt": 1.0}, "utd": [0], "agents": agents}
    plan.update(extra)
    for key in drop:
        del plan[key]
    return plan


SQUARE = [(4, 4), (6, 4), (6, 6), (4, 6)]
# An L: the square 2..8 x 2..8 without its top-right quarter 5..8 x 5..8 (clockwise ring)
ELL = [(2, 2), (2, 8), (5, 8), (5, 5), (8, 5), (8, 2)]

# Valid: robot 0 goes (1,1)->(1,5)->(1,9) past the square's left side (x=4, distance 3,
# radius 1: clearance 2); robot 1 waits at (9,9) where it already is (its goal).
# Pair distances: t0->1: a-b from (-8,-8) to (-8,-4): 8; t1->2: (-8,-4)->(-8,0): 8 -> 6.5.
VALID_W = w_make([([1, 1], [1, 9], 1, 4), ([9, 9], [9, 9], 0.5, 1)], [SQUARE])
VALID_P = [[[1, 1], [1, 5], [1, 9]], [[9, 9], [9, 9], [9, 9]]]
VALID_M = {"steps": 2, "total_path": 8.0, "mean_utd": (8 + 4 + 0) / 3, "min_clearance": 2.0}
# Robot 0 slides along y = 1.5 under the square (bottom at y = 4): distance 2.5, radius 1.
SLIDE_W = w_make([([1, 1.5], [9, 1.5], 1, 8)], [SQUARE])
# Robot 0 goes up inside the L's notch, (6.5,6.5) -> (6.5,9), both outside the L; the
# nearest part of the L is the notch's inner edge x = 5 (distance 1.5, radius 0.5).
NOTCH_W = w_make([([6.5, 6.5], [6.5, 9], 0.5, 3)], [ELL])
# Two robots swap places head-on: a from (2,5) to (8,5), b from (8,5) to (2,5).
SWAP_W = w_make([([2, 5], [8, 5], 1, 6), ([8, 5], [2, 5], 1, 6)])
# Perpendicular crossing: a (3,5)->(7,5), b (5,3)->(5,7): both at (5,5) at mid-step.
CROSS_W = w_make([([3, 5], [7, 5], 0.5, 4), ([5, 3], [5, 7], 0.5, 4)])
# Parallel passing lanes 2 apart, radii 1: touching exactly (clearance 0) is allowed.
PASS_W = w_make([([2, 4], [8, 4], 1, 6), ([8, 6], [2, 6], 1, 6)])
# One robot already within epsilon of its goal: T = 0, nothing to measure.
STILL_W = w_make([([2, 2], [2, 2.5], 1, 1)], [SQUARE])
# One robot, no obstacles, epsilon 0.5, its disc touching the workspace's bottom.
EPS_W = w_make([([1, 0.5], [5, 0.5], 0.5, 2)], epsilon=0.5)
# A robot that goes down into the L (t=1 inside it) and out again.
DIVE_W = w_make([([3.5, 9.5], [6.5, 9.5], 0.1, 5)], [ELL])
# A robot that starts (and waits) inside the square.
INSIDE_W = w_make([([5, 5], [5, 9], 0.1, 5)], [SQUARE])

CASES = [  # (name, world, plan, expected metrics dict or reason fragment)
    ("valid, two robots, one obstacle", VALID_W, p_make(VALID_W, VALID_P), VALID_M),
    ("valid, claimed metrics agree; others and nulls ignored", VALID_W, p_make(
        VALID_W, VALID_P, metrics={"steps": 2, "total_path": 8.0 + 1e-12, "mean_utd": 4.0,
                                   "min_clearance": None, "total_deviation": 123.0,
                                   "runtime_ms": 5}), VALID_M),
    ("valid, no format/family/status/metrics keys", VALID_W,
     p_make(VALID_W, VALID_P, drop=("format", "family", "status")), VALID_M),
    ("valid, sliding under a square", SLIDE_W, p_make(SLIDE_W, [[[1, 1.5], [9, 1.5]]]),
     {"steps": 1, "total_path": 8.0, "mean_utd": 4.0, "min_clearance": 1.5}),
    ("valid, up the notch of an L", NOTCH_W, p_make(NOTCH_W, [[[6.5, 6.5], [6.5, 9]]]),
     {"steps": 1, "total_path": 2.5, "mean_utd": 1.25, "min_clearance": 1.0}),
    ("valid, touching discs pass (clearance 0)", PASS_W,
     p_make(PASS_W, [[[2, 4], [8, 4]], [[8, 6], [2, 6]]]),
     {"steps": 1, "total_path": 12.0, "mean_utd": 6.0, "min_clearance": 0.0}),
    ("valid, T = 0: min_clearance null", STILL_W, p_make(STILL_W, [[[2, 2]]], metrics={
        "steps": 0}), {"steps": 0, "total_path": 0.0, "mean_utd": 0.5, "min_clearance": None}),
    ("valid, ends within epsilon then frozen; TOL on start, speed, workspace", EPS_W,
     p_make(EPS_W, [[[1 + 0.5e-9, 0.5], [3 + 1e-9, 0.5], [4.6, 0.5 - 0.5e-9],
                    [4.6, 0.5 - 0.5e-9]]]),
     {"steps": 3, "total_path": 3.6 - 0.5e-9, "min_clearance": None,
      "mean_utd": (4 - 0.5e-9 + (2 - 1e-9) + 0.4 + 0.4) / 4}),
    ("valid, ends at epsilon + TOL/2: not arrived before, no freeze", EPS_W,
     p_make(EPS_W, [[[1, 0.5], [3, 0.5], [4.5 - 0.5e-9, 0.5]]]),
     {"steps": 2, "total_path": 3.5 - 0.5e-9, "mean_utd": (4 + 2 + 0.5 + 0.5e-9) / 3,
      "min_clearance": None}),
    ("valid, steps claimed as 2.0; agent start/goal keys not compared", VALID_W,
     p_make(VALID_W, VALID_P, metrics={"steps": 2.0}, agents=[
         {"start": [1, 2], "goal": [0, 0], "path": VALID_P[0]},
         {"start": [9, 9], "goal": [9, 9], "path": VALID_P[1]}]), VALID_M),
    # rule 1
    ("agent count", VALID_W, p_make(VALID_W, VALID_P[:1]),
     "plan has 1 agents but the world has 2 robots"),
    ("empty path", VALID_W, p_make(VALID_W, [VALID_P[0], []]), "agent 1: path is missing or empty"),
    ("path lengths differ", VALID_W, p_make(VALID_W, [VALID_P[0], [[9, 9], [9, 9]]]),
     "agent 1's path has 2 positions, agent 0's has 3"),
    ("non-numeric coordinate", VALID_W, p_make(VALID_W, [VALID_P[0], [[9, 9], [9, "9"], [9, 9]]]),
     "agent 1: position 1"),
    ("NaN coordinate", VALID_W,
     json.dumps(p_make(VALID_W, VALID_P)).replace("[1, 5]", "[1, NaN]"), "agent 0: position 1"),
    ("agent without start", VALID_W,
     p_make(VALID_W, VALID_P, agents=[{"path": p} for p in VALID_P]),
     "agent 0: 'start' must be [x, y], got None"),
    # rule 2
    ("wrong start", VALID_W, p_make(VALID_W, [[[1, 1.5], [1, 5], [1, 9]], VALID_P[1]]),
     "agent 0: path starts at (1, 1.5)"),
    ("ends off goal", VALID_W, p_make(VALID_W, [[[1, 1], [1, 5], [1, 7.9]], VALID_P[1]]),
     "agent 0: path ends at (1, 7.9)"),
    # rule 3
    ("moves after arriving", EPS_W, p_make(EPS_W, [[[1, 0.5], [3, 0.5], [5, 0.5], [4.9, 0.5]]]),
     "agent 0: arrived (within epsilon of its goal) at t=2"),
    ("moves 1e-12 after arriving within epsilon", EPS_W,
     p_make(EPS_W, [[[1, 0.5], [3, 0.5], [4.6, 0.5], [4.6, 0.5 + 1e-12]]]),
     "agent 0: arrived (within epsilon of its goal) at t=2 at (4.6, 0.5)"),
    # rule 4
    ("too fast", VALID_W, p_make(VALID_W, [[[1, 1], [1, 5.1], [1, 9]], VALID_P[1]]),
     "agent 0: step t=0->1 is 4.1 long, more than its speed 4"),
    # rule 5
    ("disc leaves the workspace", w_make([([1.5, 2], [1.5, 8], 1, 4)]),
     p_make(w_make([([1.5, 2], [1.5, 8], 1, 4)]), [[[1.5, 2], [0.5, 5], [1.5, 8]]]),
     "agent 0: its disc (radius 1) at (0.5, 5) at t=1 leaves the workspace"),
    # rule 6
    ("corner cut of a square, both ends outside", w_make([([3, 5.5], [5.5, 3], 0.1, 5)], [SQUARE]),
     p_make(w_make([([3, 5.5], [5.5, 3], 0.1, 5)]), [[[3, 5.5], [5.5, 3]]]),
     "agent 0: step t=0->1 from (3, 5.5) to (5.5, 3) touches or enters obstacle 0"),
    ("passing too close to a square", w_make([([1, 3.5], [9, 3.5], 1, 8)], [SQUARE]),
     p_make(w_make([([1, 3.5], [9, 3.5], 1, 8)]), [[[1, 3.5], [9, 3.5]]]),
     "comes within 0.5 of obstacle 0 (radius 1)"),
    ("a position inside a non-convex polygon", DIVE_W,
     p_make(DIVE_W, [[[3.5, 9.5], [3.5, 6], [6.5, 9.5]]]),
     "step t=0->1 from (3.5, 9.5) to (3.5, 6) touches or enters obstacle 0"),
    ("wait inside a polygon", INSIDE_W, p_make(INSIDE_W, [[[5, 5], [5, 5], [5, 9]]]),
     "step t=0->1 from (5, 5) to (5, 5) touches or enters obstacle 0"),
    ("through a non-convex polygon, both ends outside", w_make([([6.5, 5.5], [4, 8.5], 0.1, 5)],
     [ELL]), p_make(w_make([([6.5, 5.5], [4, 8.5], 0.1, 5)]), [[[6.5, 5.5], [4, 8.5]]]),
     "touches or enters obstacle 0"),
    ("too close to a non-convex polygon's corner", w_make([([6.5, 7], [4, 9.5], 0.5, 4)], [ELL]),
     p_make(w_make([([6.5, 7], [4, 9.5], 0.5, 4)]), [[[6.5, 7], [4, 9.5]]]),
     "comes within 0.353553391 of obstacle 0 (radius 0.5)"),
    # rule 7
    ("head-on swap in one step", SWAP_W, p_make(SWAP_W, [[[2, 5], [8, 5]], [[8, 5], [2, 5]]]),
     "agents 0 and 1 collide during step t=0->1: least centre distance 0 < sum of radii 2"),
    ("perpendicular crossing", CROSS_W, p_make(CROSS_W, [[[3, 5], [7, 5]], [[5, 3], [5, 7]]]),
     "agents 0 and 1 collide during step t=0->1"),
    ("overlap at the end of a step", SWAP_W, p_make(SWAP_W, [[[2, 5], [4, 5], [8, 5]],
                                                              [[8, 5], [5.5, 5], [2, 5]]]),
     "least centre distance 1.5 < sum of radii 2"),
    # claimed metrics
    ("claimed steps", VALID_W, p_make(VALID_W, VALID_P, metrics={"steps": 3}),
     "metric steps: the plan claims 3, recomputed 2"),
    ("claimed steps as float", VALID_W, p_make(VALID_W, VALID_P, metrics={"steps": 2.5}),
     "metric steps"),
    ("claimed total_path", VALID_W, p_make(VALID_W, VALID_P, metrics={"total_path": 8.00001}),
     "metric total_path: the plan claims 8.00001, recomputed 8.0"),
    ("claimed mean_utd", VALID_W, p_make(VALID_W, VALID_P, metrics={"mean_utd": 4.1}),
     "metric mean_utd"),
    ("claimed min_clearance", VALID_W, p_make(VALID_W, VALID_P, metrics={"min_clearance": 2.001}),
     "metric min_clearance: the plan claims 2.001, recomputed 2.0"),
    ("claimed min_clearance with nothing to measure", STILL_W,
     p_make(STILL_W, [[[2, 2]]], metrics={"min_clearance": 1e300}), "recomputed +infinity"),
    # envelope and malformed files
    ("unsolved", VALID_W, p_make(VALID_W, VALID_P, solved=False, status="deadlock"),
     "holds no solved plan (status: 'deadlock')"),
    ("family grid", VALID_W, p_make(VALID_W, VALID_P, family="grid"), "plan family is 'grid'"),
    ("format", VALID_W, p_make(VALID_W, VALID_P, format="mrpp-plan/2"), "unsupported plan format"),
    ("metrics not an object", VALID_W, p_make(VALID_W, VALID_P, metrics=[1]),
     "'metrics' is not an object"),
    ("malformed plan JSON", VALID_W, '{"solved": true,\n "agents": [}', "line 2"),
    ("malformed world JSON", '{"workspace": [0, 0, 1, 1],\n\n "robots": ]',
     p_make(VALID_W, VALID_P), "line 3"),
    ("world without robots", w_make([]), p_make(w_make([]), []),
     "'robots' must be a non-empty list"),
    ("world with a bad obstacle", w_make([([1, 1], [1, 1], 1, 1)], [[(0, 0), (1, 1)]]),
     p_make(w_make([([1, 1], [1, 1], 1, 1)]), [[[1, 1]]]),
     "obstacle 0 is not a list of at least 3"),
    ("world with a negative radius", w_make([([1, 1], [1, 1], -1, 1)]),
     p_make(w_make([([1, 1], [1, 1], -1, 1)]), [[[1, 1]]]),
     "robot 0: 'radius' must be a non-negative number"),
    ("world with a bad workspace", w_make([([1, 1], [1, 1], 1, 1)], workspace=(0, 0, 10)),
     p_make(w_make([([1, 1], [1, 1], 1, 1)]), [[[1, 1]]]), "'workspace' must be"),
]


def self_test():
    passed = failed = 0

    def record(ok, what):
        nonlocal passed, failed
        passed, failed = passed + ok, failed + (not ok)
        if not ok:
            print(f"FAIL {what}")

    def run(*args):
        r = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True)
        try:
            return json.loads(r.stdout), r.returncode
        except json.JSONDecodeError:
            return {"valid": None, "stdout": r.stdout, "stderr": r.stderr}, r.returncode

    def close(a, b):
        if isinstance(a, float) or isinstance(b, float):
            return (a is not None and b is not None
                    and math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12))
        return a == b and type(a) is type(b)

    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, world, plan, expect) in enumerate(CASES):
            wpath, ppath = os.path.join(tmp, f"w{k}.json"), os.path.join(tmp, f"p{k}.json")
            for path, data in ((wpath, world), (ppath, plan)):
                with open(path, "w") as f:
                    f.write(data if isinstance(data, str) else json.dumps(data))
            out, rc = run(wpath, ppath)
            if isinstance(expect, dict):
                ok = (rc == 0 and out.get("valid") is True and set(out) == {"valid", *expect}
                      and all(close(out[key], v) for key, v in expect.items()))
            else:  # a malformed file must be named in the reason
                reason = str(out.get("reason", ""))
                bad_file = (wpath if isinstance(world, str)
                            else ppath if isinstance(plan, str) else None)
                ok = (out.get("valid") is False and expect in reason and rc == 1
                      and (bad_file is None or bad_file in reason))
            record(ok, f"{name}: expected {expect!r}, got {out!r} (exit {rc})")
        wpath = os.path.join(tmp, "w0.json")
        missing = os.path.join(tmp, "missing.json")
        out, rc = run(wpath, missing)
        record(rc == 1 and out.get("valid") is False and missing in out.get("reason", ""),
               f"missing plan file: got {out!r} (exit {rc})")
        out, rc = run(missing, wpath)
        record(rc == 1 and out.get("valid") is False and missing in out.get("reason", ""),
               f"missing world file: got {out!r} (exit {rc})")
        for args in ([], [wpath], [wpath, wpath, wpath], ["-x", wpath], [wpath, "--self-test"]):
            r = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True)
            record(r.returncode == 2 and r.stdout == "",
                   f"usage {args}: expected exit 2, got {r.returncode}")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    if len(argv) != 2 or any(a.startswith("-") for a in argv):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    result = check_files(*argv)
    print(json.dumps(result))
    return 0 if result["valid"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
