"""Tests of the Python package `mrpp` (run from anywhere: data paths come from this file's place).

The CLI comparison runs the `mrpp` binary named by MRPP_BIN (default: the repository's
target/release/mrpp, which `cargo build --release` makes); it is skipped only when neither exists.
"""

import json
import os
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import mrpp

ROOT = Path(__file__).resolve().parents[3]
DATA = ROOT / "data"
WAREHOUSE_MAP = DATA / "hstar-paper/scenario3/scenery_warehouse.txt"
WAREHOUSE_ROBOTS = DATA / "hstar-paper/scenario3/30warehouse"
RANDOM_MAP = DATA / "movingai/random-32-32-20.map"
RANDOM_SCEN = DATA / "movingai/random-32-32-20-random-1.scen"


def mrpp_bin():
    path = os.environ.get("MRPP_BIN") or str(ROOT / "target/release/mrpp")
    if not os.path.exists(path):
        pytest.skip(f"no mrpp binary at {path} (cargo build --release, or set MRPP_BIN)")
    return path


def test_readme_demo_solves_and_validates():
    problem = mrpp.Problem.grid(WAREHOUSE_MAP, WAREHOUSE_ROBOTS)
    assert (problem.family, problem.num_agents) == ("grid", 30)
    result = mrpp.solve(problem, "hstar")
    assert result.solved and result.status == "solved"
    metrics = mrpp.validate(problem, result)
    assert metrics["sum_of_costs"] == result.metrics["sum_of_costs"] > 0
    def cost(path):  # the step of the last arrival on the goal
        off = [t for t, c in enumerate(path.tolist()) if c != path[-1].tolist()]
        return off[-1] + 1 if off else 0

    assert metrics["makespan"] == max(cost(p) for p in result.paths)
    assert metrics["sum_of_costs"] == sum(cost(p) for p in result.paths)
    assert len(result.paths) == 30
    for path, start, goal in zip(result.paths, result.starts, result.goals):
        assert path.ndim == 2 and path.shape[1] == 2 and path.dtype.kind == "i"
        assert (path[0] == start).all() and (path[-1] == goal).all()
        steps = np.abs(np.diff(path, axis=0)).sum(axis=1)
        assert (steps <= 1).all(), "grid moves are to a 4-neighbour or waits"


def test_plans_equal_the_command_lines_for_the_same_seed(tmp_path):
    binary = mrpp_bin()
    cases = [
        (mrpp.Problem.grid(RANDOM_MAP, RANDOM_SCEN, agents=40),
         ["--map", RANDOM_MAP, "--scen", RANDOM_SCEN, "--agents", "40"], "lacam", {}, 3),
        (mrpp.Problem.grid(WAREHOUSE_MAP, WAREHOUSE_ROBOTS),
         ["--map", WAREHOUSE_MAP, "--scen", WAREHOUSE_ROBOTS], "whca", {"window": 8}, 0),
        (mrpp.Problem.grid(RANDOM_MAP, RANDOM_SCEN, agents=8),
         ["--map", RANDOM_MAP, "--scen", RANDOM_SCEN, "--agents", "8"], "nsga3",
         {"routes_per_robot": 6}, 7),
        (mrpp.Problem.trees(DATA / "trees/example.json"),
         ["--instance", DATA / "trees/example.json"], "psw", {}, 0),
        (mrpp.Problem.formation(DATA / "formation/var_density2-3.json"),
         ["--formation", DATA / "formation/var_density2-3.json"], "ga", {}, 5),
        (mrpp.Problem.world(DATA / "continuous/six-robots-four-obstacles.json"),
         ["--world", DATA / "continuous/six-robots-four-obstacles.json"], "de", {}, 1),
    ]
    for problem, flags, planner, params, seed in cases:
        result = mrpp.solve(problem, planner, params=params, seed=seed, time_limit=30)
        assert result.solved, (planner, result.status)
        out = tmp_path / f"{planner}.json"
        cmd = [binary, "solve", *map(str, flags), "--planner", planner, "--seed", str(seed),
               "--time-limit", "30", "--out", str(out)]
        for k, v in params.items():
            cmd += ["-p", f"{k}={v}"]
        subprocess.run(cmd, check=True, capture_output=True)
        cli = json.loads(out.read_text())
        assert [a["path"] for a in cli["agents"]] == [a["path"] for a in result.envelope["agents"]], planner
        assert cli["metrics"] == result.metrics, planner
        assert mrpp.validate(problem, out) == result.metrics


def test_league_of_robot_runners_problem():
    problem = mrpp.Problem.lorr(DATA / "robot-runners/lorr2026-maze/maze-example_40.json")
    assert problem.num_agents == 40 and "one-shot" in problem.summary
    result = mrpp.solve(problem, "lacam", seed=0, time_limit=10)
    assert result.solved
    assert mrpp.validate(problem, result)["sum_of_costs"] == result.metrics["sum_of_costs"]


def test_lifelong_league_of_robot_runners_run():
    path = DATA / "robot-runners/lorr2026-maze/maze-example_40.json"
    problem = mrpp.Problem.lorr(path, lifelong=True, steps=200)
    assert problem.family == "lifelong" and problem.num_agents == 40
    assert [p.name for p in mrpp.planners("lifelong")] == ["lifelong-pibt", "lifelong-lns"]
    result = mrpp.solve(problem, "lifelong-pibt", {"scheduler": "hungarian"}, seed=3)
    assert result.solved and result.planner == "lifelong-pibt" and result.seed == 3
    finished = result.metrics["tasks_finished"]
    assert finished > 0 and result.envelope["numTaskFinished"] == finished
    assert len(result.actions) == 40 and all(len(a) == 200 for a in result.actions)
    assert mrpp.validate(problem, result)["tasks_finished"] == finished
    with pytest.raises(mrpp.MrppError, match="lifelong=True"):
        mrpp.Problem.lorr(path, steps=10)


def test_a_lifelong_run_driven_step_by_step_from_python(tmp_path):
    path = DATA / "robot-runners/lorr2026-maze/maze-example_40.json"
    problem = mrpp.Problem.lorr(path, lifelong=True, steps=120)
    # mrpp's own planner, then the same actions and greedy schedules fed one step at a time:
    # the Python-driven run is the same run.
    result = mrpp.solve(problem, "lifelong-pibt", {"scheduler": "greedy"}, seed=5)
    sim = problem.simulation()
    assert sim.state()["t"] == 0 and len(sim.state()["robots"]) == 40
    for t in range(120):
        sim.step([a[t] for a in result.actions], schedule=sim.schedule("greedy"))
    assert sim.done
    state = sim.state()
    assert state["tasks_finished"] == result.metrics["tasks_finished"] > 0
    out = tmp_path / "run.json"
    sim.save(out)
    assert mrpp.validate(problem, out)["tasks_finished"] == state["tasks_finished"]
    with pytest.raises(mrpp.MrppError, match="horizon"):
        sim.step("W" * 40)

    # A policy of one's own under MAPF: step towards the goal onto a free cell no robot is on
    # or heads for (a toy); it never proposes an illegal step.
    problem = mrpp.Problem.lorr(path, lifelong=True, steps=60, action_model="MAPF")
    sim = problem.simulation()
    free = sim.grid()
    moves = {"R": (1, 0), "U": (0, 1), "L": (-1, 0), "D": (0, -1)}
    while not sim.done:
        state = sim.state()
        taken = {(r["x"], r["y"]) for r in state["robots"]}
        actions = []
        for r in state["robots"]:
            choice = "W"
            if r["goal"] is not None:
                gx, gy = r["goal"]
                for letter, (dx, dy) in moves.items():
                    x, y = r["x"] + dx, r["y"] + dy
                    inside = 0 <= y < free.shape[0] and 0 <= x < free.shape[1]
                    if (inside and free[y, x] and (x, y) not in taken
                            and abs(x - gx) + abs(y - gy) < abs(r["x"] - gx) + abs(r["y"] - gy)):
                        choice = letter
                        taken.add((x, y))
                        break
            actions.append(choice)
        sim.step(actions, schedule=sim.schedule("hungarian"))
    assert sim.state()["errands_done"] > 0
    sim.save(out)
    assert mrpp.validate(problem, out)["steps"] == 60

    # Refused steps name the rule and the robots, and execute nothing.
    sim = problem.simulation()
    first = sim.state()["robots"]
    i, wall = next((i, letter) for i, a in enumerate(first)
                   for letter, (dx, dy) in moves.items()
                   if not (0 <= a["y"] + dy < free.shape[0] and 0 <= a["x"] + dx < free.shape[1]
                           and free[a["y"] + dy, a["x"] + dx]))
    with pytest.raises(mrpp.MrppError, match=rf"unallowed move \(robot {i}\)"):
        sim.step(["W"] * i + [wall] + ["W"] * (39 - i))
    with pytest.raises(mrpp.MrppError, match="is not an action of the MAPF model"):
        sim.step(["F"] + ["W"] * 39)
    with pytest.raises(mrpp.MrppError, match="one each"):
        sim.step(["W"] * 39)
    assert sim.state()["t"] == 0 and sim.state()["robots"] == first


def test_the_gil_is_released_while_planning():
    problem = mrpp.Problem.grid(RANDOM_MAP, RANDOM_SCEN, agents=100)
    done = {}
    worker = threading.Thread(
        target=lambda: done.update(r=mrpp.solve(problem, "lacam", params={"anytime": True},
                                                 time_limit=0.6)))
    worker.start()
    ticks = 0
    started = time.perf_counter()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    elapsed = time.perf_counter() - started
    worker.join()
    assert done["r"].solved
    assert elapsed > 0.4, "LaCAM* runs until its time limit"
    assert ticks > 50, f"the main thread ran only {ticks} times in {elapsed:.2f} s: GIL held"


def test_other_families_give_numpy_paths():
    trees = mrpp.solve(mrpp.Problem.trees(DATA / "trees/example.json"), "psw")
    assert trees.solved and all(p.ndim == 1 and p.dtype.kind == "i" for p in trees.paths)
    world = mrpp.Problem.world(DATA / "continuous/six-robots-four-obstacles.json")
    cont = mrpp.solve(world, "orca")
    assert cont.solved and all(p.ndim == 2 and p.dtype.kind == "f" for p in cont.paths)


def test_viewer_page(tmp_path):
    problem = mrpp.Problem.grid(WAREHOUSE_MAP, WAREHOUSE_ROBOTS)
    result = mrpp.solve(problem, "whca")
    html = mrpp.view_html(problem, result)
    assert html.lower().startswith("<!doctype html>") and '"family":"grid"' in html
    out = tmp_path / "plan.html"
    mrpp.write_view(problem, result, out)
    assert out.read_text() == html


def test_planner_registry():
    names = {(p.family, p.name) for p in mrpp.planners()}
    for fp in [("grid", "hstar"), ("grid", "lacam"), ("trees", "gp"), ("formation", "exact"),
               ("continuous", "hbmo")]:
        assert fp in names
    whca = next(p for p in mrpp.planners("grid") if p.name == "whca")
    assert whca.params["window"][0] == "8"
    with pytest.raises(mrpp.MrppError, match="unknown family"):
        mrpp.planners("nope")


def test_errors_name_the_file_line_and_rule(tmp_path):
    bad = tmp_path / "bad.map"
    bad.write_text("type octile\nheight 2\nwidth 2\nmap\n..\n.x\n")
    with pytest.raises(mrpp.MrppError, match=r"bad.map:6: unknown map character `x`"):
        mrpp.Problem.grid(bad, RANDOM_SCEN)
    problem = mrpp.Problem.grid(WAREHOUSE_MAP, WAREHOUSE_ROBOTS)
    with pytest.raises(mrpp.MrppError, match="unknown planner `nope`"):
        mrpp.solve(problem, "nope")
    with pytest.raises(mrpp.MrppError, match="plans trees problems"):
        mrpp.solve(problem, "psw")
    with pytest.raises(mrpp.MrppError, match="time_limit must be more than 0"):
        mrpp.solve(problem, "hstar", time_limit=0)
    with pytest.raises(mrpp.MrppError, match="seed must be a non-negative integer"):
        mrpp.solve(problem, "hstar", seed=-1)
    # A plan with a conflict injected: agent 1 copies agent 0's path.
    result = mrpp.solve(problem, "hstar")
    broken = json.loads(result.to_json())
    broken["agents"][1]["path"] = broken["agents"][0]["path"]
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(broken))
    with pytest.raises(mrpp.MrppError, match="invalid plan"):
        mrpp.validate(problem, path)


def test_errors_speak_python_not_command_lines():
    """Messages name keyword arguments, not the command line's flags, and a ``Result``'s plan,
    not the temporary file it passes through (issue 30 item 8)."""
    problem = mrpp.Problem.grid(WAREHOUSE_MAP, WAREHOUSE_ROBOTS)
    with pytest.raises(mrpp.MrppError) as e:
        mrpp.solve(problem, "hstar", time_limit=0)
    assert "time_limit must be more than 0" in str(e.value)
    assert "--" not in str(e.value)
    result = mrpp.solve(problem, "hstar")
    envelope = json.loads(result.to_json())
    envelope["agents"][1]["path"] = envelope["agents"][0]["path"]
    broken = mrpp.Result(solved=True, status="solved", envelope=envelope)
    with pytest.raises(mrpp.MrppError) as e:
        mrpp.validate(problem, broken)
    message = str(e.value)
    assert message.startswith("the result's plan: invalid plan"), message
    assert "mrpp-" not in message and ".json" not in message, message
