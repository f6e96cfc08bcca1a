//! The one set of rules every grid instance obeys, checked in one place for every reader
//! (MovingAI `.scen`, the H* paper's robot files, League of Robot Runners agents and tasks of
//! every layout, and so the Python API, which reads through them): every start and goal is a cell
//! of the map, a free one, no two agents share a start and no two share a goal. A violation names
//! the file and line the start or goal was read from, and the earlier line it clashes with.
//!
//! Reachability (a goal in another connected component than its start) is not a rule of the
//! instance: such an instance is well formed and unsolvable, which planners report (exit 3).

use std::path::Path;

use rustc_hash::FxHashMap;

use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;

use crate::map::GridMap;

/// A start or goal as read: the cell `(x, y)` (column, row from the top-left, in cells) and the
/// file and 1-based line it came from.
#[derive(Debug, Clone, Copy)]
pub struct Spot<'a> {
    pub cell: (i64, i64),
    pub file: &'a Path,
    pub line: usize,
}

/// The instance of `agents` (`(start, goal)` per agent, agent `i` the `i`-th) on `map`.
///
/// # Errors
/// [`Error::Parse`] at the offending spot's file and line: a start or goal off the map or on a
/// wall, or a start (goal) that is also an earlier agent's start (goal), naming that agent's line
/// (and file, when it is another).
pub fn checked_instance(map: &GridMap, agents: &[(Spot<'_>, Spot<'_>)]) -> Result<Instance> {
    let mut starts = Vec::with_capacity(agents.len());
    let mut goals = Vec::with_capacity(agents.len());
    let mut start_at: FxHashMap<VertexId, Spot<'_>> = FxHashMap::default();
    let mut goal_at: FxHashMap<VertexId, Spot<'_>> = FxHashMap::default();
    for (start, goal) in agents {
        starts.push(place(map, "start", start, &mut start_at)?);
        goals.push(place(map, "goal", goal, &mut goal_at)?);
    }
    Ok(Instance { starts, goals })
}

/// The start vertices of `starts` (robot `i` the `i`-th) on `map`, for problems whose goals come
/// later (the League of Robot Runners' lifelong problems, whose errands may repeat).
///
/// # Errors
/// As [`checked_instance`] for starts: off the map, on a wall, or an earlier robot's start.
pub fn checked_starts(map: &GridMap, starts: &[Spot<'_>]) -> Result<Vec<VertexId>> {
    let mut start_at: FxHashMap<VertexId, Spot<'_>> = FxHashMap::default();
    starts
        .iter()
        .map(|spot| place(map, "start", spot, &mut start_at))
        .collect()
}

/// The vertex of `spot` (a `what`: start or goal), which no earlier spot in `seen` holds.
fn place<'a>(
    map: &GridMap,
    what: &str,
    spot: &Spot<'a>,
    seen: &mut FxHashMap<VertexId, Spot<'a>>,
) -> Result<VertexId> {
    let (x, y) = spot.cell;
    let v = map.vertex_at(x, y).ok_or_else(|| {
        Error::parse(
            spot.file,
            spot.line,
            format!("{what} {}", map.cell_problem(x, y).unwrap_or_default()),
        )
    })?;
    if let Some(prev) = seen.insert(v, *spot) {
        let where_ = if prev.file == spot.file {
            format!("line {}", prev.line)
        } else {
            format!("{} line {}", prev.file.display(), prev.line)
        };
        return Err(Error::parse(
            spot.file,
            spot.line,
            format!("{what} ({x},{y}) is also the {what} on {where_}"),
        ));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map() -> GridMap {
        GridMap::parse("...\n.#.\n...", Path::new("m.txt"))
            .unwrap()
            .0
    }

    fn spot(x: i64, y: i64, file: &Path, line: usize) -> Spot<'_> {
        Spot {
            cell: (x, y),
            file,
            line,
        }
    }

    #[test]
    fn every_rule_names_file_and_line() {
        let (a, t) = (Path::new("a.agents"), Path::new("t.tasks"));
        let m = map();
        let ok = checked_instance(
            &m,
            &[
                (spot(0, 0, a, 2), spot(2, 2, t, 2)),
                (spot(2, 2, a, 3), spot(0, 0, t, 3)),
            ],
        )
        .unwrap();
        assert_eq!(ok.num_agents(), 2);
        let err =
            |agents: &[(Spot<'_>, Spot<'_>)]| checked_instance(&m, agents).unwrap_err().to_string();
        assert_eq!(
            err(&[
                (spot(0, 0, a, 2), spot(2, 2, t, 2)),
                (spot(0, 0, a, 3), spot(0, 2, t, 3)),
            ]),
            "a.agents:3: start (0,0) is also the start on line 2"
        );
        assert_eq!(
            err(&[
                (spot(0, 0, a, 2), spot(2, 2, t, 2)),
                (spot(1, 0, a, 3), spot(2, 2, a, 3)),
            ]),
            "a.agents:3: goal (2,2) is also the goal on t.tasks line 2"
        );
        assert!(err(&[(spot(1, 1, a, 2), spot(0, 0, t, 2))]).starts_with("a.agents:2: start"));
        assert!(err(&[(spot(0, 0, a, 2), spot(5, 0, t, 7))]).starts_with("t.tasks:7: goal"));
    }
}
