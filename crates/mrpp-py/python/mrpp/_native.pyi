"""Type stubs of mrpp's Rust extension (``mrpp._native``); use the ``mrpp`` package's API."""

from typing import List, Tuple

__version__: str

class MrppError(ValueError):
    """A bad input, parameter or plan; the message names the file, line and rule."""

def planners() -> List[Tuple[str, str, str, List[Tuple[str, str, str]]]]:
    """Every planner: (family, name, about, [(param, default, doc)])."""

def load(inputs_json: str) -> Tuple[str, str, int]:
    """Loads a problem named by its input files: (family, summary, number of agents)."""

def solve(
    inputs_json: str,
    planner: str,
    params: List[Tuple[str, str]],
    seed: int,
    time_limit: float,
) -> Tuple[bool, str, str]:
    """Plans without the GIL: (solved, status, plan envelope JSON)."""

def validate(inputs_json: str, plan_path: str) -> Tuple[int, str]:
    """Validates a plan file: (agents, metrics JSON); raises MrppError naming the violation."""

def view_page(inputs_json: str, plan_path: str) -> str:
    """The viewer's HTML page for a plan file."""
