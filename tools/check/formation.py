#!/usr/bin/env python3
"""Independent checker for mrpp formation plans (Python 3 standard library only).

Usage:  python3 tools/check/formation.py PLAN.json [PLAN.json ...]
        python3 tools/check/formation.py --self-test

Prints one JSON line per plan: {"valid": true, "c_max": .., "sum_of_costs":
.., "distinct_paths": ..} or {"valid": false, "reason": "..."} (also for
unreadable or malformed input), with a leading "file" key when given several
plans. Exit 0 when every plan is valid, 1 otherwise; wrong usage exits 2.

This file was written from the rules below, NOT from mrpp's code; it shares
no code with mrpp, so it can serve as a second opinion on mrpp's validator.

Plan ("plan envelope", problem data embedded): "solved" must be true;
  "format" (if present) is "mrpp-plan/1"; "family" (if present) is
  "formation"; "robots" is R >= 1; "radius" is rho > 0; "cost" is
  {"model": "lanes", "kappa": k (default 0.5)} | {"model": "waves"} |
  {"model": "hard"}; "roadmap" is {"points": [[x, y], ...], "edges":
  [[u, v, length, clearance], ...]} (undirected; ids index "points"; if several
  edges join one pair, the first listed is used); "agents" is
  [{"start", "goal", "path"}]; "metrics" (optional) may report "c_max",
  "sum_of_costs", "distinct_paths". Other keys are ignored.
Rules:
  * exactly R agents, all with the same start S and the same goal G.
  * each path is non-empty, starts at S, ends at G, follows roadmap edges and
    visits no vertex twice.
  * no two robots cross one edge in opposite directions; n_e = number of
    robots whose path uses edge e.
  * cost of edge e for r robots: pitch = 2*rho + rho/2, cap = max(1,
    floor(2*clearance / pitch)), k = ceil(r / cap); lanes: length*(1 +
    kappa*(k-1)); waves: length + (k-1)*pitch; hard: length if r <= cap else
    infinity. (The floor is taken literally, with no tolerance.)
  * the arcs u->v used by the paths must form a DAG (else "circular wait").
    T(S) = 0, T(v) = max over used arcs u->v of T(u) + c_e(n_e). Robot i's
    cost is T(u) + c_e(n_e) for its last arc u->G, or 0 for the path [S] when
    S = G. c_max = max cost, sum_of_costs = sum of costs, distinct_paths =
    number of distinct paths.
  * every arc's cost c_e(n_e) must be finite: a corridor over capacity under
    the hard model (or a cost that overflows) makes the plan invalid, naming
    the first such arc u->v along agent 0's path, then agent 1's, ... (checked
    after the circular wait); c_max and sum_of_costs must be finite too.
  * metrics reported (not null) must match: floats to relative 1e-9 (absolute
    1e-12 near zero), distinct_paths exactly.
  * kappa (lanes) must be a number >= 0 (costs never fall as r grows).
"""
import json
import math
import os
import subprocess
import sys
import tempfile


class Invalid(Exception):
    pass


def is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def is_num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        raise Invalid(f"{path}: invalid JSON at line {e.lineno}, column {e.colno}: {e.msg}")
    except (OSError, UnicodeDecodeError) as e:
        raise Invalid(f"{path}: cannot read: {e}")


def read_problem(plan, name):
    """Validate the envelope and embedded problem; return (R, cost_fn, n, edge map)."""
    if not isinstance(plan, dict):
        raise Invalid(f"{name}: plan is not a JSON object")
    if plan.get("format", "mrpp-plan/1") != "mrpp-plan/1":
        raise Invalid(f"{name}: unsupported plan format {plan.get('format')!r}")
    if plan.get("family", "formation") != "formation":
        raise Invalid(f"{name}: plan family is {plan.get('family')!r}, not 'formation'")
    if plan.get("solved") is not True:
        raise Invalid(f"{name} holds no solved plan (status: {plan.get('status')!r})")
    robots, rho, cost = plan.get("robots"), plan.get("radius"), plan.get("cost")
    if not is_int(robots) or robots < 1:
        raise Invalid(f"{name}: 'robots' must be a positive integer, got {robots!r}")
    if not is_num(rho) or rho <= 0:
        raise Invalid(f"{name}: 'radius' must be a positive number, got {rho!r}")
    if not isinstance(cost, dict) or cost.get("model") not in ("lanes", "waves", "hard"):
        raise Invalid(f"{name}: 'cost' must be an object with model lanes, waves or hard")
    model, kappa = cost["model"], cost.get("kappa", 0.5)
    if model == "lanes" and not (is_num(kappa) and kappa >= 0):
        raise Invalid(f"{name}: 'kappa' must be a number >= 0, got {kappa!r}")
    pitch = 2 * rho + rho / 2

    def cap_fn(clearance):
        return max(1, math.floor(2 * clearance / pitch))

    def cost_fn(length, clearance, r):
        cap = cap_fn(clearance)
        k = -(-r // cap)
        if model == "lanes":
            return length * (1 + kappa * (k - 1))
        if model == "waves":
            return length + (k - 1) * pitch
        return length if r <= cap else math.inf

    roadmap = plan.get("roadmap")
    if not isinstance(roadmap, dict):
        raise Invalid(f"{name}: 'roadmap' is not an object")
    points, edges = roadmap.get("points"), roadmap.get("edges")
    if not isinstance(points, list) or not isinstance(edges, list):
        raise Invalid(f"{name}: roadmap 'points' and 'edges' must be lists")
    for k, p in enumerate(points):
        if not (isinstance(p, list) and len(p) == 2 and all(is_num(x) for x in p)):
            raise Invalid(f"{name}: point {k} {p!r} is not [x, y]")
    n = len(points)
    emap = {}  # frozenset({u, v}) -> (length, clearance), first listed edge wins
    for k, e in enumerate(edges):
        if not (isinstance(e, list) and len(e) == 4 and all(is_int(x) and 0 <= x < n for x in e[:2])
                and all(is_num(x) and x >= 0 for x in e[2:])):
            raise Invalid(f"{name}: edge {k} {e!r} is not [u, v, length, clearance] "
                          f"with ids in 0..{n - 1} and non-negative numbers")
        emap.setdefault(frozenset(e[:2]), (e[2], e[3]))
    return robots, cost_fn, cap_fn, n, emap


def check_plan(plan, name):
    """Check the plan; return the recomputed metrics."""
    robots, cost_fn, cap_fn, n, emap = read_problem(plan, name)
    agents = plan.get("agents")
    if not isinstance(agents, list) or not all(isinstance(a, dict) for a in agents):
        raise Invalid(f"{name}: 'agents' is not a list of objects")
    if len(agents) != robots:
        raise Invalid(f"plan has {len(agents)} agents but 'robots' is {robots}")
    s, g = agents[0].get("start"), agents[0].get("goal")
    for x in (s, g):
        if not (is_int(x) and 0 <= x < n):
            raise Invalid(f"agent 0: start/goal {x!r} is not a vertex id in 0..{n - 1}")
    paths = []
    for i, a in enumerate(agents):
        if a.get("start") != s or a.get("goal") != g:
            raise Invalid(f"agent {i} has start {a.get('start')!r} / goal {a.get('goal')!r}, "
                          f"but agent 0 has start {s} / goal {g}")
        path = a.get("path")
        if not isinstance(path, list) or not path:
            raise Invalid(f"agent {i}: path is missing or empty")
        for k, v in enumerate(path):
            if not (is_int(v) and 0 <= v < n):
                raise Invalid(f"agent {i}: {v!r} at position {k} is not a vertex id in 0..{n - 1}")
        if path[0] != s or path[-1] != g:
            raise Invalid(f"agent {i}: path runs {path[0]} -> {path[-1]}, not {s} -> {g}")
        for k in range(1, len(path)):
            if frozenset(path[k - 1:k + 1]) not in emap:
                raise Invalid(f"agent {i}: jump from vertex {path[k - 1]} to {path[k]} "
                              f"at position {k} is not along a roadmap edge")
        if len(set(path)) != len(path):
            v = next(v for k, v in enumerate(path) if v in path[:k])
            raise Invalid(f"agent {i}: path visits vertex {v} twice")
        paths.append(path)

    arc_owner, n_e = {}, {}  # arc (u, v) -> first robot using it; edge -> robots using it
    for i, path in enumerate(paths):
        for u, v in zip(path, path[1:]):
            if (v, u) in arc_owner:
                raise Invalid(f"robots {arc_owner[(v, u)]} and {i} cross the edge {v}-{u} "
                              f"in opposite directions")
            arc_owner.setdefault((u, v), i)
            n_e[frozenset((u, v))] = n_e.get(frozenset((u, v)), 0) + 1

    def arc_cost(u, v):
        e = frozenset((u, v))
        return cost_fn(*emap[e], n_e[e])

    succ, pred, indeg = {}, {}, {}
    for u, v in arc_owner:
        succ.setdefault(u, []).append(v)
        pred.setdefault(v, []).append(u)
        indeg[v] = indeg.get(v, 0) + 1
        indeg.setdefault(u, 0)
    T = {s: 0.0}
    ready = [v for v, d in indeg.items() if d == 0]  # only S: no path re-enters S
    while ready:
        u = ready.pop()
        for v in succ.get(u, []):
            T[v] = max(T.get(v, -math.inf), T[u] + arc_cost(u, v))
            indeg[v] -= 1
            if indeg[v] == 0:
                ready.append(v)
    stuck = {v for v, d in indeg.items() if d > 0}
    if stuck:  # every stuck vertex has a stuck predecessor: walk back to a cycle
        walk, v = [], min(stuck)
        while v not in walk:
            walk.append(v)
            v = next(w for w in pred[v] if w in stuck)
        cycle = [v] + walk[walk.index(v):][::-1]
        raise Invalid("circular wait: the arcs used by the paths form the cycle "
                      + " -> ".join(map(str, cycle)))

    for path in paths:
        for u, v in zip(path, path[1:]):
            if not math.isfinite(arc_cost(u, v)):
                e = frozenset((u, v))
                raise Invalid(f"corridor {u}-{v} is over capacity: {n_e[e]} robots cross it "
                              f"together but it holds {cap_fn(emap[e][1])} side by side, so "
                              f"the crossing never ends (infinite cost)")
    costs = [0.0 if len(p) == 1 else T[p[-2]] + arc_cost(p[-2], p[-1]) for p in paths]
    c_max, soc = max(costs), sum(costs)
    for key, value in (("c_max", c_max), ("sum of costs", soc)):
        if not math.isfinite(value):
            raise Invalid(f"the plan's {key} is not a finite number")
    result = {"c_max": c_max, "sum_of_costs": soc,
              "distinct_paths": len({tuple(p) for p in paths})}
    metrics = plan.get("metrics")
    if metrics is not None and not isinstance(metrics, dict):
        raise Invalid(f"{name}: 'metrics' is not an object")
    for key, value in result.items():
        reported = (metrics or {}).get(key)
        if reported is None:
            continue
        if key == "distinct_paths":
            ok = is_int(reported) and reported == value
        else:
            ok = is_num(reported) and math.isclose(reported, value, rel_tol=1e-9, abs_tol=1e-12)
        if not ok:
            raise Invalid(f"metric {key}: the file reports {reported!r}, recomputed {value!r}")
    return result


def check_file(path):
    try:
        return dict(valid=True, **check_plan(load_json(path), path))
    except Invalid as e:
        return {"valid": False, "reason": str(e)}


# ---------------------------------------------------------------- self-test

DIAMOND = {"points": [[0, 0], [1, 0], [0.75, 1], [2, 0]],
           "edges": [[0, 1, 1.0, 0.5], [1, 3, 1.0, 0.5], [0, 2, 1.5, 1.5], [2, 3, 1.5, 1.5]]}
# square 0-1-2-3 with diagonal 1-3 (for opposite directions)
SQUARE = {"points": [[0, 0], [1, 0], [1, 1], [0, 1]],
          "edges": [[0, 1, 1, 1], [1, 2, 1, 1], [2, 3, 1, 1], [3, 0, 1, 1], [1, 3, 1.4, 1]]}
# S=0, a=1, b=2, c=3, G=4; S->a->b->G and S->b->c->a->G wait on each other
CYCLE = {"points": [[0, 0], [1, 1], [1, -1], [2, -2], [3, 0]],
         "edges": [[0, 1, 1, 1], [1, 2, 1, 1], [2, 4, 1, 1], [0, 2, 1, 1],
                   [2, 3, 1, 1], [3, 1, 1, 1], [1, 4, 1, 1]]}


def f_plan(paths, model="hard", roadmap=DIAMOND, **extra):
    plan = {"format": "mrpp-plan/1", "family": "formation", "solved": True,
            "status": "solved", "metrics": {"runtime_ms": 1}, "program": "ignored",
            "robots": len(paths), "radius": 0.4, "cost": {"model": model},
            "roadmap": roadmap,
            "agents": [{"start": p[0], "goal": p[-1], "path": p} for p in paths]}
    plan.update(extra)
    return plan


HARD = [[0, 1, 3], [0, 2, 3], [0, 2, 3]]
HARD_AGENT = {"start": 0, "goal": 3, "path": [0, 1, 3]}
GOOD = {"c_max": 3.0, "sum_of_costs": 8.0, "distinct_paths": 2}
DUP = dict(DIAMOND, edges=DIAMOND["edges"] + [[3, 1, 9.0, 0.1]])
CASES = [  # (name, plan or raw text, expected metrics or reason fragment)
    ("diamond, hard", f_plan(HARD), GOOD),
    ("metrics agree, nulls ignored", f_plan(HARD, metrics={
        "c_max": 3.0, "sum_of_costs": 8.0 + 1e-12, "distinct_paths": None}), GOOD),
    ("duplicate edge: first wins", f_plan(HARD, roadmap=DUP), GOOD),
    ("lanes, 3 waves on one lane", f_plan([[0, 1, 3]] * 3, "lanes"),
     {"c_max": 4.0, "sum_of_costs": 12.0, "distinct_paths": 1}),
    ("lanes, kappa 1", f_plan([[0, 1, 3]] * 3, cost={"model": "lanes", "kappa": 1}),
     {"c_max": 6.0, "sum_of_costs": 18.0, "distinct_paths": 1}),
    ("waves", f_plan([[0, 1, 3]] * 3, "waves"),
     {"c_max": 6.0, "sum_of_costs": 18.0, "distinct_paths": 1}),
    ("hard over capacity", f_plan([[0, 1, 3]] * 3, metrics={
        "c_max": None, "sum_of_costs": None, "distinct_paths": 1}),
     "corridor 0-1 is over capacity: 3 robots cross it together but it holds 1 side by side"),
    ("hard, two over capacity on the second path", f_plan([[0, 2, 3], [0, 1, 3], [0, 1, 3]]),
     "corridor 0-1 is over capacity: 2 robots cross it together but it holds 1"),
    ("hard, within capacity, reported null", f_plan([[0, 2, 3], [0, 2, 3], [0, 1, 3]], metrics={
        "c_max": None}), {"c_max": 3.0, "sum_of_costs": 8.0, "distinct_paths": 2}),
    ("lanes, a cost that overflows", f_plan([[0, 1, 3]] * 3, cost={
        "model": "lanes", "kappa": 1e308}), "corridor 0-1 is over capacity"),
    ("negative kappa", f_plan(HARD, cost={"model": "lanes", "kappa": -0.5}),
     "'kappa' must be a number >= 0"),
    ("start is goal", f_plan([[2], [2]]), {"c_max": 0.0, "sum_of_costs": 0.0, "distinct_paths": 1}),
    ("wrong agent count", f_plan(HARD, robots=4), "3 agents but 'robots' is 4"),
    ("wrong start", f_plan([[0, 1, 3], [1, 3]]), "agent 1 has start 1 / goal 3"),
    ("path misses goal", f_plan([[0, 1, 3], [0, 2, 3]], agents=[HARD_AGENT, dict(
        HARD_AGENT, path=[0, 2])]), "agent 1: path runs 0 -> 2, not 0 -> 3"),
    ("non-edge jump", f_plan([[0, 3], [0, 2, 3]]), "jump from vertex 0 to 3 at position 1"),
    ("revisit", f_plan([[0, 1, 0, 2, 3], [0, 2, 3]]), "agent 0: path visits vertex 0 twice"),
    ("opposite directions", f_plan([[0, 1, 3, 2], [0, 3, 1, 2]], roadmap=SQUARE),
     "robots 0 and 1 cross the edge 1-3 in opposite directions"),
    ("circular wait", f_plan([[0, 1, 2, 4], [0, 2, 3, 1, 4]], roadmap=CYCLE),
     "circular wait: the arcs used by the paths form the cycle 1 -> 2 -> 3 -> 1"),
    ("disputed metric", f_plan(HARD, metrics={"c_max": 2.5}),
     "metric c_max: the file reports 2.5, recomputed 3.0"),
    ("disputed distinct_paths", f_plan(HARD, metrics={"distinct_paths": 3}),
     "metric distinct_paths: the file reports 3, recomputed 2"),
    ("unsolved", f_plan(HARD, solved=False), "holds no solved plan"),
    ("family grid", f_plan(HARD, family="grid"), "plan family is 'grid', not 'formation'"),
    ("bad cost model", f_plan(HARD, "soft"), "model lanes, waves or hard"),
    ("malformed JSON", '{"solved": true,\n "agents": [}', "line 2"),
]


def self_test():
    passed = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, plan, expect) in enumerate(CASES):
            ppath = os.path.join(tmp, f"p{k}.json")
            with open(ppath, "w") as f:
                f.write(plan if isinstance(plan, str) else json.dumps(plan, indent=1))
            run = subprocess.run([sys.executable, __file__, ppath], capture_output=True, text=True)
            try:
                out = json.loads(run.stdout)
            except json.JSONDecodeError:
                out = {"valid": None, "stdout": run.stdout, "stderr": run.stderr}
            if isinstance(expect, dict):
                ok = out == dict(valid=True, **expect) and run.returncode == 0
            else:  # raw-text cases must also name the file in the reason
                reason = str(out.get("reason", ""))
                ok = (out.get("valid") is False and expect in reason and run.returncode == 1
                      and (not isinstance(plan, str) or ppath in reason))
            passed, failed = passed + ok, failed + (not ok)
            if not ok:
                print(f"FAIL {name}: expected {expect!r}, got {out!r} (exit {run.returncode})")
        many = subprocess.run([sys.executable, __file__, "no-a.json", "no-b.json"],
                              capture_output=True, text=True)
        lines = [json.loads(x) for x in many.stdout.splitlines()]
        ok = (many.returncode == 1 and [x.get("file") for x in lines] == ["no-a.json", "no-b.json"]
              and all(x["valid"] is False for x in lines))
        passed, failed = passed + ok, failed + (not ok)
        if not ok:
            print(f"FAIL several plans: got {many.stdout!r} (exit {many.returncode})")
        for args in ([], ["a.json", "-x"], ["-x"]):
            usage = subprocess.run([sys.executable, __file__] + args, capture_output=True, text=True)
            ok = usage.returncode == 2
            passed, failed = passed + ok, failed + (not ok)
            if not ok:
                print(f"FAIL usage {args}: expected exit 2, got {usage.returncode}")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    if not argv or any(a.startswith("-") for a in argv):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    ok = True
    for path in argv:
        result = check_file(path)
        if len(argv) > 1:
            result = {"file": path, **result}
        print(json.dumps(result))
        ok = ok and result["valid"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
