"""mrpp: multi-robot path planning, from Python.

The planners, loaders, validators and viewer are mrpp's Rust code (the ``mrpp`` command line's
library); a plan made here equals ``mrpp solve``'s for the same files, planner, parameters and seed.

    import mrpp
    problem = mrpp.Problem.grid("random-32-32-20.map", "random-32-32-20-random-1.scen", agents=50)
    result = mrpp.solve(problem, "lacam", seed=0, time_limit=10.0)
    result.solved, result.metrics["sum_of_costs"], result.paths[0]   # paths: numpy arrays
    mrpp.validate(problem, result)      # the validator's metrics, or MrppError naming the violation
    mrpp.write_view(problem, result, "plan.html")   # the animated viewer page

Families and their files (the command line's flags): grid MAPF (MovingAI ``.map``/``.scen``, the
H* paper's maps and robot files, League of Robot Runners problem JSON), single-lane trees (tree
instance JSON), formations (formation JSON over a polygon map) and continuous worlds (world JSON).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import tempfile
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np

from . import _native
from ._native import MrppError

__all__ = [
    "MrppError",
    "Planner",
    "Problem",
    "Result",
    "Simulation",
    "planners",
    "solve",
    "validate",
    "view_html",
    "write_view",
    "__version__",
]

__version__: str = _native.__version__

# A command-line flag in a message from the shared Rust core (`--time-limit`).
_FLAG = re.compile(r"(?<![\w-])--([a-z][a-z0-9]*(?:-[a-z0-9]+)*)")


def _pythonic(message: str, plan_path: Optional[str] = None) -> str:
    """A core message as a Python user reads it: flags become keyword names (``--time-limit``
    -> ``time_limit``) and a ``Result``'s temporary plan file becomes "the result's plan"."""
    if plan_path is not None:
        message = message.replace(plan_path + ":1:", "the result's plan:")
        message = message.replace(plan_path, "the result's plan")
    return _FLAG.sub(lambda m: m.group(1).replace("-", "_"), message)


@contextlib.contextmanager
def _plain_errors(plan_path: Optional[str] = None):
    """Re-raises the core's ``MrppError`` with its message made pythonic (``_pythonic``)."""
    try:
        yield
    except MrppError as e:
        raise MrppError(_pythonic(str(e), plan_path)) from None

PathLike = Union[str, "os.PathLike[str]"]


@dataclass(frozen=True)
class Planner:
    """One planner of mrpp's registry."""

    family: str
    """``grid``, ``trees``, ``formation`` or ``continuous``."""
    name: str
    about: str
    """One line: what it is and its source (paper, section)."""
    params: Dict[str, Tuple[str, str]]
    """Parameter name -> (default, doc), as passed in ``solve(..., params={name: value})``."""


def planners(family: Optional[str] = None) -> List[Planner]:
    """Every planner (of ``family`` when given), in the order ``mrpp planners`` lists them."""
    out = [
        Planner(fam, name, about, {p: (default, doc) for p, default, doc in params})
        for fam, name, about, params in _native.planners()
    ]
    if family is not None:
        known = sorted({p.family for p in out})
        if family not in known:
            raise MrppError(f"unknown family {family!r} (known: {', '.join(known)})")
        out = [p for p in out if p.family == family]
    return out


class Problem:
    """A problem named by its input files; loading checks them (``MrppError`` names file, line
    and rule). Build one with the class methods."""

    family: str
    summary: str
    num_agents: int

    def __init__(self, **inputs: Any) -> None:
        self._inputs = {k: (os.fspath(v) if isinstance(v, os.PathLike) else v)
                        for k, v in inputs.items() if v is not None and v is not False}
        self._json = json.dumps(self._inputs)
        with _plain_errors():
            self.family, self.summary, self.num_agents = _native.load(self._json)

    @classmethod
    def grid(cls, map: PathLike, scen: PathLike, agents: Optional[int] = None) -> "Problem":
        """A grid problem: a MovingAI ``.map`` or H* paper map, and a ``.scen`` or H* robot file
        (the first ``agents`` agents; all when None)."""
        return cls(map=map, scen=scen, agents=agents)

    @classmethod
    def lorr(
        cls,
        problem: PathLike,
        agents: Optional[int] = None,
        lifelong: bool = False,
        steps: Optional[int] = None,
        step_time_limit: Optional[float] = None,
        action_model: Optional[str] = None,
    ) -> "Problem":
        """A League of Robot Runners problem JSON (2023, 2024 or 2026 start-kit layout). By
        default a one-shot grid instance: agent i's goal is the first errand of task i. With
        ``lifelong=True`` the problem is run step by step as the League's start kit runs it
        (``steps``, default 1000; ``step_time_limit`` seconds per step, default 1;
        ``action_model`` ``"MAPF_T"`` (default) or ``"MAPF"``); solve it with a lifelong planner
        (``planners("lifelong")``); the result's ``envelope`` is the League's output JSON and
        ``actions`` the executed actions. See docs/lifelong.md."""
        if not lifelong and (steps is not None or step_time_limit is not None or action_model):
            raise MrppError("steps, step_time_limit and action_model need lifelong=True")
        return cls(
            lorr=problem,
            agents=agents,
            lifelong=lifelong,
            steps=steps,
            step_time_limit=step_time_limit,
            action_model=action_model,
        )

    def simulation(self) -> "Simulation":
        """A lifelong problem (``Problem.lorr(..., lifelong=True)``) at step 0, to drive step by
        step with a planner of your own (``Simulation``)."""
        return Simulation(self)

    @classmethod
    def trees(cls, instance: PathLike, following: bool = True) -> "Problem":
        """A single-lane tree instance JSON (``visit`` goals; ``following=False`` forbids
        entering a node another robot leaves in the same step)."""
        return cls(instance=instance, no_following=not following)

    @classmethod
    def formation(cls, path: PathLike) -> "Problem":
        """A formation file JSON (polygon map, robots, start and goal, cost model)."""
        return cls(formation=path)

    @classmethod
    def world(cls, path: PathLike) -> "Problem":
        """A continuous world JSON (workspace, polygon obstacles, disc robots)."""
        return cls(world=path)

    def __repr__(self) -> str:
        return f"Problem({self.family}: {self.summary})"


@dataclass
class Result:
    """A planner run: the plan envelope (``mrpp-plan/1``) with its paths as numpy arrays."""

    solved: bool
    status: str
    """``solved``, or why not (e.g. the time limit)."""
    envelope: Dict[str, Any] = field(repr=False)
    """The plan file's content, exactly what ``mrpp solve --out plan.json`` writes."""

    @property
    def _record(self) -> Dict[str, Any]:
        # A lifelong run's file is the League's output JSON with mrpp's record under "mrpp".
        return self.envelope.get("mrpp", self.envelope)

    @property
    def planner(self) -> str:
        return self._record.get("planner", "")

    @property
    def seed(self) -> int:
        return int(self._record.get("seed", 0))

    @property
    def metrics(self) -> Optional[Dict[str, Any]]:
        """The validator's metrics of a solved plan (e.g. ``sum_of_costs``, ``makespan``,
        ``sum_of_moves`` on grids; ``tasks_finished``, ``errands``, ``throughput`` in lifelong
        runs), None when not solved."""
        return self._record.get("metrics") or None

    @property
    def runtime_ms(self) -> float:
        return float(self._record.get("runtime_ms", 0.0))

    @property
    def actions(self) -> List[str]:
        """Lifelong runs: each robot's executed actions, one letter per step (``F``, ``R``,
        ``C``, ``W``, ``T`` under MAPF_T); empty for other families."""
        return [p.split(",") if p else [] for p in self.envelope.get("actualPaths") or []]

    @property
    def paths(self) -> List[np.ndarray]:
        """One array per agent, index = time step: shape (T, 2) int64 ``[x, y]`` cells on grids,
        (T,) node ids on trees and formations, (T, 2) float64 points in continuous worlds.
        Empty when not solved."""
        agents = self.envelope.get("agents") or []
        return [np.asarray(a.get("path") or []) for a in agents]

    @property
    def starts(self) -> np.ndarray:
        return np.asarray([a["start"] for a in self.envelope.get("agents") or []])

    @property
    def goals(self) -> np.ndarray:
        return np.asarray([a["goal"] for a in self.envelope.get("agents") or []])

    def to_json(self) -> str:
        """The plan envelope as JSON text."""
        return json.dumps(self.envelope)

    def save(self, path: PathLike) -> None:
        """Writes the plan file (readable by ``mrpp validate/view/render``)."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.to_json())


class Simulation:
    """A League of Robot Runners run driven from Python: each step you give one action per
    robot (and, if you like, each robot's task) and mrpp executes it under the League's rules
    (the same simulator as ``mrpp solve -P lifelong-pibt``), so a planner or learned policy of
    your own plays the League's loop::

        problem = mrpp.Problem.lorr("warehouse_small_10.json", lifelong=True, steps=100)
        sim = problem.simulation()
        while not sim.done:
            state = sim.state()                  # robots, open tasks, tasks finished
            sim.step(my_policy(state), schedule=sim.schedule("greedy"))
        sim.save("run.json")                     # the League's output JSON
        mrpp.validate(problem, "run.json")       # or mrpp view / PlanViz

    Actions are letters: under ``MAPF_T`` ``F`` (forward), ``R`` (clockwise), ``C``
    (counter-clockwise), ``W`` (wait); under ``MAPF`` ``R`` (x + 1), ``U`` (y + 1), ``L``
    (x - 1), ``D`` (y - 1), ``W`` (the League's viewer PlanViz's letters). A step that breaks a
    rule (two robots on one cell, a swap, a move into an obstacle) raises ``MrppError`` naming
    the rule and both robots, and nothing is executed. Orientation: 0 east (x + 1), 1 south
    (y + 1), 2 west, 3 north."""

    def __init__(self, problem: Problem) -> None:
        if problem.family != "lifelong":
            raise MrppError("a Simulation needs a lifelong problem: Problem.lorr(..., lifelong=True)")
        self.problem = problem
        with _plain_errors():
            self._native = _native.Simulation(problem._json)

    def state(self) -> Dict[str, Any]:
        """The state now: ``t`` (steps done), ``steps`` (the horizon), ``action_model``,
        ``robots`` (one dict per robot: ``x``, ``y``, ``orientation``, ``task`` id or None,
        ``goal`` = its task's next errand ``[x, y]`` or None), ``open_tasks`` (revealed,
        unfinished: ``id``, ``errands`` as ``[x, y]``, ``done`` errands so far, ``agent`` or
        None, ``revealed`` step), ``tasks_finished``, ``errands_done``."""
        return json.loads(self._native.state())

    def grid(self) -> np.ndarray:
        """The map as a ``(height, width)`` bool array, True on free cells (``[y, x]``)."""
        w, h, free = self._native.grid()
        return np.asarray(free, dtype=bool).reshape(h, w)

    @property
    def done(self) -> bool:
        """True once the horizon (``steps``) is reached."""
        st = self.state()
        return st["t"] >= st["steps"]

    def step(self, actions: Union[str, List[str]],
             schedule: Optional[List[Optional[int]]] = None) -> None:
        """Executes one step: ``actions`` one letter per robot (a list, or a string such as
        ``"FWWR"``); ``schedule`` each robot's task id or None (None keeps the assignment; a
        refused schedule keeps it too and is recorded, as the League does)."""
        letters = list(actions) if isinstance(actions, str) else [str(a) for a in actions]
        self._native.step(letters, None if schedule is None else list(schedule))

    def schedule(
        self, kind: str = "greedy", time_limit: float = 0.5, chain_weight: float = 1.0
    ) -> List[Optional[int]]:
        """mrpp's proposal of each robot's task: ``greedy`` (the League's start kit's: each free
        robot takes the nearest open task, never re-assigned), ``hungarian`` (a minimum-cost
        assignment of every robot not yet at its first errand) or ``matching`` (greedy matching
        of the same pairs by increasing cost, for thousands of robots). A task costs the distance
        to its next errand plus ``chain_weight`` (0 to 10) times the distances between its later
        errands: 1 is the start kit's cost, 0 the pickup distance only."""
        return self._native.schedule(kind, float(time_limit), float(chain_weight))

    def to_json(self) -> str:
        """The run so far as the League's output JSON text."""
        return self._native.to_json()

    def save(self, path: PathLike) -> None:
        """Writes the run so far as the League's output JSON (``mrpp validate --lorr P
        --plan path``, ``mrpp view`` and PlanViz read it)."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.to_json())

    def __repr__(self) -> str:
        st = self.state()
        return (f"Simulation(t={st['t']}/{st['steps']}, robots={len(st['robots'])}, "
                f"tasks_finished={st['tasks_finished']})")


def solve(
    problem: Problem,
    planner: str,
    params: Optional[Mapping[str, Any]] = None,
    seed: int = 0,
    time_limit: float = 60.0,
) -> Result:
    """Plans ``problem`` with ``planner`` (``planners()`` lists them with their ``params``),
    ``seed`` and ``time_limit`` seconds. The GIL is released while planning. A solved plan has
    passed the family's validator. Raises ``MrppError`` for an unknown planner or parameter,
    a planner of another family, or a bad time limit."""
    pairs = [(str(k), _param(v)) for k, v in (params or {}).items()]
    if not isinstance(seed, int) or seed < 0:
        raise MrppError(f"seed must be a non-negative integer, got {seed!r}")
    with _plain_errors():
        solved, status, envelope = _native.solve(
            problem._json, planner, pairs, seed, float(time_limit)
        )
    return Result(solved, status, json.loads(envelope))


def _param(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


class _PlanFile:
    """A plan as a file path: a ``Result`` goes through ``plan.json`` in a temporary folder (the
    name shows in the viewer's title)."""

    def __init__(self, plan: Union[Result, PathLike]) -> None:
        self._tmp: Optional[tempfile.TemporaryDirectory] = None
        if isinstance(plan, Result):
            self._tmp = tempfile.TemporaryDirectory(prefix="mrpp-")
            self.path = os.path.join(self._tmp.name, "plan.json")
            plan.save(self.path)
        else:
            self.path = os.fspath(plan)

    def __enter__(self) -> str:
        return self.path

    def __exit__(self, *exc: Any) -> None:
        if self._tmp is not None:
            self._tmp.cleanup()


def validate(problem: Problem, plan: Union[Result, PathLike]) -> Dict[str, Any]:
    """Checks a plan (a ``Result`` or a plan file: envelope or LaCAM text) against ``problem``
    with the family's validator, claimed metrics included. Returns the metrics; raises
    ``MrppError`` naming the first violation (agents, cell or node, time step)."""
    with _PlanFile(plan) as path, _plain_errors(path if isinstance(plan, Result) else None):
        _, metrics = _native.validate(problem._json, path)
    return json.loads(metrics)


def view_html(problem: Problem, plan: Union[Result, PathLike]) -> str:
    """The viewer's self-contained HTML page (what ``mrpp view`` writes): play, pause, step,
    scrub, the validator's first violation marked."""
    with _PlanFile(plan) as path, _plain_errors(path if isinstance(plan, Result) else None):
        return _native.view_page(problem._json, path)


def write_view(problem: Problem, plan: Union[Result, PathLike], out: PathLike) -> None:
    """Writes ``view_html(problem, plan)`` to ``out``."""
    html = view_html(problem, plan)
    with open(out, "w", encoding="utf-8") as f:
        f.write(html)
