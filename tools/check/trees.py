#!/usr/bin/env python3
"""Independent checker for mrpp tree plans (Python 3 standard library only).

Usage:  python3 tools/check/trees.py INSTANCE.json PLAN.json
        python3 tools/check/trees.py --self-test

Prints one JSON line: {"valid": true, "sum_of_costs": .., "makespan": ..,
"sum_of_moves": ..} (exit 0) or {"valid": false, "reason": "..."} (exit 1,
also for unreadable or malformed inputs). Wrong usage exits 2.

This file was written from the rules below, NOT from mrpp's code; it shares
no code with mrpp, so it can serve as a second opinion on mrpp's validator.

Instance: {"nodes": N, "edges": [[u, v], ...], "robots": [{"start", "goal"}]}.
  Node ids are 0..N-1; the edges form a tree (N-1 edges, connected, no
  self-loops or duplicates); starts are unique, goals are unique.
Plan ("plan envelope"): "solved" must be true; "format" (if present) is
  "mrpp-plan/1"; "family" (if present) is "trees"; "rules" is
  {"goal": "visit"|"stay", "following": bool}, or when absent/null the legacy
  top-level "goal_semantics" (default "visit") and "allow_following" (default
  true). "agents" is [{"start", "goal", "path"}]; other keys are ignored.
Rules:
  * exactly one agent per robot; agent i's start and goal equal robot i's.
  * each path is non-empty, path[0] = start, all ids in range; index = time
    step; after its path ends a robot stays on (and occupies) its last node.
  * each step is a wait or a move along a tree edge.
  * no vertex conflict (two robots on one node at one step) and no swap
    conflict (two robots exchanging nodes between t-1 and t). If following
    is false, a robot may not enter at t a node another robot held at t-1.
  * goal "visit": each robot is on its goal at some step; cost = first such
    step. "stay": each robot ends on its goal; cost = (index of its last
    node off the goal) + 1, or 0 if never off it.
  * sum_of_costs = sum of costs, makespan = max cost, sum_of_moves = number
    of steps where a robot's node changes. If "metrics" reports any of these
    three (not null), it must equal the recomputed value.
"""
import json
import os
import subprocess
import sys
import tempfile

METRIC_KEYS = ("sum_of_costs", "makespan", "sum_of_moves")


class Invalid(Exception):
    pass


def is_int(x):
    return isinstance(x, int) and not isinstance(x, bool)


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except json.JSONDecodeError as e:
        raise Invalid(f"{path}: invalid JSON at line {e.lineno}, column {e.colno}: {e.msg}")
    except (OSError, UnicodeDecodeError) as e:
        raise Invalid(f"{path}: cannot read: {e}")


def check_instance(inst, name):
    """Validate the tree instance; return (n, adjacency sets, robots)."""
    if not isinstance(inst, dict):
        raise Invalid(f"{name}: instance is not a JSON object")
    n, edges, robots = inst.get("nodes"), inst.get("edges"), inst.get("robots")
    if not is_int(n) or n < 1:
        raise Invalid(f"{name}: 'nodes' must be a positive integer")
    if not isinstance(edges, list) or not isinstance(robots, list):
        raise Invalid(f"{name}: 'edges' and 'robots' must be lists")
    if len(edges) != n - 1:
        raise Invalid(f"{name}: a tree on {n} nodes needs {n - 1} edges, found {len(edges)}")
    adj = [set() for _ in range(n)]
    for k, e in enumerate(edges):
        if not (isinstance(e, list) and len(e) == 2 and all(is_int(x) and 0 <= x < n for x in e)):
            raise Invalid(f"{name}: edge {k} {e!r} is not a pair of node ids in 0..{n - 1}")
        u, v = e
        if u == v:
            raise Invalid(f"{name}: edge {k} is a self-loop at node {u}")
        if v in adj[u]:
            raise Invalid(f"{name}: edge {k} duplicates edge {u}-{v}")
        adj[u].add(v)
        adj[v].add(u)
    seen, stack = {0}, [0]
    while stack:
        for w in adj[stack.pop()]:
            if w not in seen:
                seen.add(w)
                stack.append(w)
    if len(seen) != n:
        missing = min(set(range(n)) - seen)
        raise Invalid(f"{name}: edges do not form a tree (node {missing} not connected to node 0)")
    starts, goals = {}, {}
    for i, r in enumerate(robots):
        if not isinstance(r, dict):
            raise Invalid(f"{name}: robot {i} is not an object")
        for key, used in (("start", starts), ("goal", goals)):
            x = r.get(key)
            if not (is_int(x) and 0 <= x < n):
                raise Invalid(f"{name}: robot {i} {key} {x!r} is not a node id in 0..{n - 1}")
            if x in used:
                raise Invalid(f"{name}: robots {used[x]} and {i} share {key} node {x}")
            used[x] = i
    return n, adj, [(r["start"], r["goal"]) for r in robots]


def plan_rules(plan, name):
    rules = plan.get("rules")
    if rules is None:
        goal = plan.get("goal_semantics", "visit")
        following = plan.get("allow_following", True)
    elif isinstance(rules, dict):
        goal, following = rules.get("goal", "visit"), rules.get("following", True)
    else:
        raise Invalid(f"{name}: 'rules' is not an object")
    if goal not in ("visit", "stay"):
        raise Invalid(f"{name}: unknown goal semantics {goal!r}")
    if not isinstance(following, bool):
        raise Invalid(f"{name}: 'following' must be true or false, got {following!r}")
    return goal, following


def check_plan(inst, plan, name):
    """Check the plan against the instance; return the recomputed metrics."""
    n, adj, robots = inst
    if not isinstance(plan, dict):
        raise Invalid(f"{name}: plan is not a JSON object")
    if plan.get("format", "mrpp-plan/1") != "mrpp-plan/1":
        raise Invalid(f"{name}: unsupported plan format {plan.get('format')!r}")
    if plan.get("family", "trees") != "trees":
        raise Invalid(f"{name}: plan family is {plan.get('family')!r}, not 'trees'")
    if plan.get("solved") is not True:
        raise Invalid(f"{name} holds no solved plan (status: {plan.get('status')!r})")
    goal_rule, following = plan_rules(plan, name)
    agents = plan.get("agents")
    if not isinstance(agents, list):
        raise Invalid(f"{name}: 'agents' is not a list")
    if len(agents) != len(robots):
        raise Invalid(f"plan has {len(agents)} agents but the instance has {len(robots)} robots")

    paths, costs, moves = [], [], 0
    for i, (a, (start, goal)) in enumerate(zip(agents, robots)):
        if not isinstance(a, dict):
            raise Invalid(f"{name}: agent {i} is not an object")
        if a.get("start") != start or a.get("goal") != goal:
            raise Invalid(f"agent {i} has start {a.get('start')!r} / goal {a.get('goal')!r}, "
                          f"but robot {i} has start {start} / goal {goal}")
        path = a.get("path")
        if not isinstance(path, list) or not path:
            raise Invalid(f"agent {i}: path is missing or empty")
        for t, v in enumerate(path):
            if not (is_int(v) and 0 <= v < n):
                raise Invalid(f"agent {i}: {v!r} at t={t} is not a node id in 0..{n - 1}")
        if path[0] != start:
            raise Invalid(f"agent {i}: path begins at node {path[0]}, not at its start {start}")
        for t in range(1, len(path)):
            u, v = path[t - 1], path[t]
            if u != v:
                if v not in adj[u]:
                    raise Invalid(f"agent {i}: jump from node {u} to node {v} at t={t} "
                                  f"is not along a tree edge")
                moves += 1
        if goal_rule == "visit":
            if goal not in path:
                raise Invalid(f"agent {i} never visits its goal node {goal}")
            costs.append(path.index(goal))
        else:
            if path[-1] != goal:
                raise Invalid(f"agent {i} ends on node {path[-1]}, not on its goal node {goal}")
            off = [t for t, v in enumerate(path) if v != goal]
            costs.append(off[-1] + 1 if off else 0)
        paths.append(path)

    def at(i, t):
        p = paths[i]
        return p[t] if t < len(p) else p[-1]

    horizon = max((len(p) for p in paths), default=1)
    prev = None  # node -> agent at t-1
    for t in range(horizon):
        occ = {}
        for i in range(len(paths)):
            v = at(i, t)
            if v in occ:
                raise Invalid(f"vertex conflict: agents {occ[v]} and {i} both at node {v} at t={t}")
            occ[v] = i
        if prev is not None:
            for i in range(len(paths)):
                u, v = at(i, t - 1), at(i, t)
                j = prev.get(v)
                if u == v or j is None or j == i:
                    continue
                if at(j, t) == u:
                    if i < j:
                        raise Invalid(f"swap conflict: agents {i} and {j} exchange nodes "
                                      f"{u} and {v} between t={t - 1} and t={t}")
                elif not following:
                    raise Invalid(f"following conflict: agent {i} enters node {v} at t={t}, "
                                  f"which agent {j} occupied at t={t - 1}")
        prev = occ

    result = {"sum_of_costs": sum(costs), "makespan": max(costs, default=0),
              "sum_of_moves": moves}
    metrics = plan.get("metrics")
    if isinstance(metrics, dict):
        for key in METRIC_KEYS:
            reported = metrics.get(key)
            if reported is not None and (not is_int(reported) or reported != result[key]):
                raise Invalid(f"metric {key}: the file reports {reported!r}, "
                              f"recomputed {result[key]}")
    elif metrics is not None:
        raise Invalid(f"{name}: 'metrics' is not an object")
    return result


def check_files(instance_path, plan_path):
    try:
        inst = check_instance(load_json(instance_path), instance_path)
        return dict(valid=True, **check_plan(inst, load_json(plan_path), plan_path))
    except Invalid as e:
        return {"valid": False, "reason": str(e)}


# ---------------------------------------------------------------- self-test

T_TREE = {"nodes": 4, "edges": [[0, 1], [1, 2], [1, 3]],
          "robots": [{"start": 2, "goal": 3}, {"start": 3, "goal": 0}]}


def t_plan(paths, following=True, goal="visit", **extra):
    plan = {"format": "mrpp-plan/1", "family": "trees", "solved": True,
            "status": "solved", "rules": {"goal": goal, "following": following},
            "metrics": {"runtime_ms": 1}, "program": "ignored",
            "agents": [{"start": p[0], "goal": r["goal"], "path": p}
                       for p, r in zip(paths, T_TREE["robots"])]}
    plan.update(extra)
    return plan


BASE = [[2, 2, 1, 3], [3, 1, 0]]
GOOD = {"sum_of_costs": 5, "makespan": 3, "sum_of_moves": 4}
LEGACY = {k: v for k, v in t_plan(BASE).items() if k not in ("rules", "format")}
CASES = [  # (name, instance, plan or raw text, expected metrics or reason fragment)
    ("valid, following allowed", T_TREE, t_plan(BASE), GOOD),
    ("valid, stay semantics", T_TREE, t_plan(BASE, goal="stay"), GOOD),
    ("metrics agree, nulls ignored", T_TREE,
     t_plan(BASE, metrics={"sum_of_costs": 5, "makespan": None, "time_steps": 9}), GOOD),
    ("legacy keys, defaults", T_TREE, LEGACY, GOOD),
    ("following forbidden", T_TREE, t_plan(BASE, following=False),
     "following conflict: agent 0 enters node 1 at t=2"),
    ("legacy allow_following false", T_TREE, dict(LEGACY, allow_following=False),
     "following conflict"),
    ("vertex conflict", T_TREE, t_plan([[2, 1, 3], [3, 1, 0]]),
     "vertex conflict: agents 0 and 1 both at node 1 at t=1"),
    ("swap conflict", T_TREE, t_plan([[2, 1, 3], [3, 3, 1, 0]]),
     "swap conflict: agents 0 and 1 exchange nodes 1 and 3 between t=1 and t=2"),
    ("non-edge jump", T_TREE, t_plan([[2, 3], [3, 1, 0]]),
     "jump from node 2 to node 3 at t=1"),
    ("wrong start", T_TREE, t_plan([[1, 3], [3, 1, 0]]), "robot 0 has start 2"),
    ("goal never visited", T_TREE, t_plan([[2, 2, 1], [3, 1, 0]]),
     "agent 0 never visits its goal node 3"),
    ("visit then leave: ok for visit", T_TREE, t_plan([[2, 2, 1, 3, 1], [3, 1, 0]]),
     {"sum_of_costs": 5, "makespan": 3, "sum_of_moves": 5}),
    ("visit then leave: bad for stay", T_TREE,
     t_plan([[2, 2, 1, 3, 1], [3, 1, 0]], goal="stay"), "agent 0 ends on node 1"),
    ("disputed metric", T_TREE, t_plan(BASE, metrics={"sum_of_costs": 6, "makespan": 3}),
     "metric sum_of_costs: the file reports 6, recomputed 5"),
    ("unsolved", T_TREE, t_plan(BASE, solved=False), "holds no solved plan"),
    ("agent count", T_TREE, t_plan(BASE[:1]), "1 agents but the instance has 2 robots"),
    ("node out of range", T_TREE, t_plan([[2, 2, 1, 3], [3, 1, 7]]), "7 at t=2"),
    ("not a tree", dict(T_TREE, edges=[[0, 1], [1, 2], [2, 0]]), t_plan(BASE),
     "do not form a tree"),
    ("malformed plan JSON", T_TREE, '{"solved": true,\n "agents": [}', "line 2"),
]


def self_test():
    passed = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, inst, plan, expect) in enumerate(CASES):
            ipath, ppath = os.path.join(tmp, f"i{k}.json"), os.path.join(tmp, f"p{k}.json")
            with open(ipath, "w") as f:
                json.dump(inst, f)
            with open(ppath, "w") as f:
                f.write(plan if isinstance(plan, str) else json.dumps(plan, indent=1))
            run = subprocess.run([sys.executable, __file__, ipath, ppath],
                                 capture_output=True, text=True)
            try:
                out = json.loads(run.stdout)
            except json.JSONDecodeError:
                out = {"valid": None, "stdout": run.stdout, "stderr": run.stderr}
            if isinstance(expect, dict):
                ok = out == dict(valid=True, **expect) and run.returncode == 0
            else:
                ok = (out.get("valid") is False and expect in out.get("reason", "")
                      and run.returncode == 1)
            passed, failed = passed + ok, failed + (not ok)
            if not ok:
                print(f"FAIL {name}: expected {expect!r}, got {out!r} (exit {run.returncode})")
        usage = subprocess.run([sys.executable, __file__], capture_output=True, text=True)
        ok = usage.returncode == 2
        passed, failed = passed + ok, failed + (not ok)
        if not ok:
            print(f"FAIL usage: expected exit 2, got {usage.returncode}")
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


def main(argv):
    if argv == ["--self-test"]:
        return self_test()
    if len(argv) != 2 or argv[0].startswith("-") or argv[1].startswith("-"):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    result = check_files(argv[0], argv[1])
    print(json.dumps(result))
    return 0 if result["valid"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
