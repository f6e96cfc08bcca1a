//! League of Robot Runners (LoRR) problems as one-shot MAPF instances.
//!
//! A LoRR problem is a JSON file naming a map, an agent file and a task file, as in the
//! competition's start kit (GitHub `MAPF-Competition/Start-Kit`; MIT licence); the files are read
//! by `mrpp_mapf::lorr_files`, shared with the lifelong family. Both layouts are read:
//!
//! - **2023** (start kit 1.1.2, the `r2024` branch despite its name): `mapFile`, `agentFile`,
//!   `teamSize`, `taskFile`, `numTasksReveal`, `taskAssignmentStrategy`; task lines hold one
//!   location.
//! - **2024** (tags v2.x) and **2026** (v3.x, `main`): the same keys plus `version`, and in 2026
//!   `agentCounter`, `agentSize`, `delayConfig`; the agent and task files may hold `#` comment
//!   lines and a task line is a comma-separated sequence of errand locations (`203,453`),
//!   visited in order. `docs/lorr-semantics.md` has the kit's semantics in full.
//!
//! **One-shot instance** (mrpp's choice; the start kit itself only runs lifelong problems): agent
//! `i` (the first `teamSize` lines of the agent file) starts at its location and its goal is the
//! first errand of its first task. Tasks are handed out in file order, so agent `i` gets task `i`
//! as under the start kit's round robin, except that a task whose first errand is already another
//! agent's goal is passed over (two agents cannot both finish on one cell) and the next unused
//! task in file order is taken instead; [`LorrProblem::skipped_tasks`] counts those. The whole
//! task list is kept in [`LorrProblem::tasks`] for a lifelong run.

use std::path::{Path, PathBuf};

use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;
use mrpp_mapf::lorr_files::{self, LorrFiles};

use crate::instance_rules::{Spot, checked_instance};
use crate::map::GridMap;

pub use mrpp_mapf::lorr_files::referenced_files;

/// A League of Robot Runners problem, read from its JSON and the three files it names.
#[derive(Debug, Clone)]
pub struct LorrProblem {
    /// The map file (resolved against the JSON's folder).
    pub map_path: PathBuf,
    /// The map.
    pub map: GridMap,
    /// The one-shot instance: `teamSize` agents, goals as described in the module doc.
    pub instance: Instance,
    /// Every task of the task file in file order, each a sequence of errand vertices.
    pub tasks: Vec<Vec<VertexId>>,
    /// Index into [`Self::tasks`] of the task each agent's goal came from.
    pub assigned: Vec<usize>,
    /// Tasks passed over because their first errand was already another agent's goal.
    pub skipped_tasks: usize,
    /// `"2026 LoRR"` for the 2026 layout, `"2023"` otherwise (no `version` key).
    pub version: String,
}

/// Reads a LoRR problem JSON and the map, agent and task files it names.
///
/// # Errors
/// The file and rule: unreadable or malformed JSON, a missing key, a count line that disagrees
/// with the lines that follow, a location off the map or on a wall (file and line), fewer agents
/// than `teamSize`, or fewer usable tasks than agents.
pub fn load(path: &Path) -> Result<LorrProblem> {
    parse_with(&read_file(path)?, path, &|p: &Path| read_file(p))
}

/// [`load`] with the problem JSON given as `text` and the map, agent and task files it names
/// read through `read` (given each file's path, resolved against `path`'s folder).
///
/// # Errors
/// As [`load`], and whatever `read` returns.
pub fn parse_with(
    text: &str,
    path: &Path,
    read: &dyn Fn(&Path) -> Result<String>,
) -> Result<LorrProblem> {
    one_shot(lorr_files::parse_with(text, path, read)?)
}

/// The one-shot instance of a LoRR problem's files (module doc).
///
/// # Errors
/// Fewer tasks with distinct first errands than robots; a start or goal clash (file and line).
pub fn one_shot(files: LorrFiles) -> Result<LorrProblem> {
    let team = files.team_size();
    let (_, assigned, skipped_tasks) = first_tasks(&files.tasks, team).ok_or_else(|| {
        Error::invalid(
            &files.task_path,
            format!("{team} agents need {team} tasks with distinct first errands"),
        )
    })?;
    // The grid instance rules, checked where every grid reader checks them.
    let map = &files.map;
    fn spot<'a>(map: &GridMap, v: VertexId, file: &'a Path, line: usize) -> Spot<'a> {
        let (x, y) = map.cell(v);
        Spot {
            cell: (i64::from(x), i64::from(y)),
            file,
            line,
        }
    }
    let agents: Vec<(Spot<'_>, Spot<'_>)> = (0..team)
        .map(|i| {
            let task = assigned[i];
            (
                spot(
                    map,
                    files.starts[i],
                    &files.agent_path,
                    files.start_lines[i],
                ),
                spot(
                    map,
                    files.tasks[task][0],
                    &files.task_path,
                    files.task_lines[task],
                ),
            )
        })
        .collect();
    let instance = checked_instance(map, &agents)?;
    Ok(LorrProblem {
        map_path: files.map_path,
        map: files.map,
        instance,
        tasks: files.tasks,
        assigned,
        skipped_tasks,
        version: files.version,
    })
}

/// Hands tasks out in file order (module doc): `(goals, task index per agent, tasks skipped)`,
/// or `None` when too few tasks have distinct first errands.
fn first_tasks(tasks: &[Vec<VertexId>], team: usize) -> Option<(Vec<VertexId>, Vec<usize>, usize)> {
    let mut taken = rustc_hash::FxHashSet::default();
    let mut goals = Vec::with_capacity(team);
    let mut assigned = Vec::with_capacity(team);
    let mut used = vec![false; tasks.len()];
    let mut skipped = 0;
    for i in 0..team {
        let pick = if i < tasks.len() && !taken.contains(&tasks[i][0]) {
            Some(i)
        } else {
            skipped += 1;
            (0..tasks.len()).find(|&t| !used[t] && t >= team && !taken.contains(&tasks[t][0]))
        }?;
        used[pick] = true;
        taken.insert(tasks[pick][0]);
        goals.push(tasks[pick][0]);
        assigned.push(pick);
    }
    Some((goals, assigned, skipped))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data(rel: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/robot-runners")
            .join(rel)
    }

    #[test]
    fn reads_the_2023_warehouse_example() {
        let p = load(&data("lorr2023-warehouse_small/warehouse_small_10.json")).unwrap();
        assert_eq!((p.map.width(), p.map.height()), (57, 33));
        assert_eq!(p.instance.num_agents(), 10);
        assert_eq!(p.tasks.len(), 20000);
        assert_eq!(p.assigned, (0..10).collect::<Vec<_>>());
        assert_eq!(p.skipped_tasks, 0);
        assert_eq!(p.version, "2023");
        // agent 0 starts at location 1032 = row 18, column 6; its goal is task 0, location 1298.
        assert_eq!(p.map.cell(p.instance.starts[0]), (1032 % 57, 1032 / 57));
        assert_eq!(p.map.cell(p.instance.goals[0]), (1298 % 57, 1298 / 57));
    }

    #[test]
    fn reads_the_2026_maze_example_and_passes_over_a_shared_first_errand() {
        let p = load(&data("lorr2026-maze/maze-example_40.json")).unwrap();
        assert_eq!(p.instance.num_agents(), 40);
        assert_eq!(p.tasks.len(), 160);
        assert!(
            p.tasks.iter().all(|t| t.len() >= 2),
            "2026 tasks are errand sequences"
        );
        // Among the first 40 tasks two share a first errand: one agent takes task 40 instead.
        assert_eq!(p.skipped_tasks, 1);
        assert_eq!(p.assigned.iter().filter(|&&t| t >= 40).count(), 1);
        let mut goals = p.instance.goals.clone();
        goals.sort_unstable();
        goals.dedup();
        assert_eq!(goals.len(), 40);
        assert_eq!(p.version, "2026 LoRR");
    }

    #[test]
    fn hand_out_order() {
        let tasks = vec![vec![1], vec![1, 5], vec![2], vec![3], vec![1]];
        let (goals, assigned, skipped) = first_tasks(&tasks, 3).unwrap();
        assert_eq!(
            (goals, assigned, skipped),
            (vec![1, 3, 2], vec![0, 3, 2], 1)
        );
        assert!(first_tasks(&[vec![1], vec![1]], 2).is_none());
    }

    #[test]
    fn errors_name_file_line_and_rule() {
        let dir = std::env::temp_dir().join(format!("mrpp-lorr-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("maps")).unwrap();
        std::fs::write(
            dir.join("maps/m.map"),
            "type octile\nheight 2\nwidth 3\nmap\n.E@\nS..\n",
        )
        .unwrap();
        std::fs::write(dir.join("a.agents"), "2\n0\n1\n").unwrap();
        let problem = |team: u32, tasks: &str| {
            std::fs::write(dir.join("t.tasks"), tasks).unwrap();
            std::fs::write(
                dir.join("p.json"),
                format!(
                    r#"{{"mapFile": "maps/m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": {team}}}"#
                ),
            )
            .unwrap();
            load(&dir.join("p.json"))
                .map(|p| p.instance)
                .map_err(|e| e.to_string())
        };
        let ok = problem(2, "2\n3\n4\n").unwrap();
        assert_eq!((ok.starts.len(), ok.goals.len()), (2, 2));
        let wall = problem(2, "2\n3\n2\n").unwrap_err();
        assert!(
            wall.ends_with("t.tasks:3: location 2 is cell (2,0), a wall"),
            "{wall}"
        );
        let off = problem(2, "2\n3\n9\n").unwrap_err();
        assert!(
            off.contains("t.tasks:3: location 9 is off the map (0..6)"),
            "{off}"
        );
        let count = problem(2, "3\n3\n4\n").unwrap_err();
        assert!(
            count.contains("t.tasks:1: count line says 3 but 2 entries follow"),
            "{count}"
        );
        let team = problem(3, "2\n3\n4\n").unwrap_err();
        assert!(
            team.contains("`teamSize` is 3 but the file has only 2 agents"),
            "{team}"
        );
        // Two robots on one start cell: named like the other grid readers name it.
        std::fs::write(dir.join("a.agents"), "# 2026 comment\n2\n4\n4\n").unwrap();
        let twice = problem(2, "2\n3\n5\n").unwrap_err();
        assert!(
            twice.ends_with("a.agents:4: start (1,1) is also the start on line 3"),
            "{twice}"
        );
        std::fs::write(dir.join("a.agents"), "2\n0\n1\n").unwrap();
        let same = problem(2, "2\n3\n3\n").unwrap_err();
        assert!(
            same.contains("2 agents need 2 tasks with distinct first errands"),
            "{same}"
        );
        std::fs::write(dir.join("bad.json"), "{\"mapFile\": 3").unwrap();
        let json = load(&dir.join("bad.json")).unwrap_err().to_string();
        assert!(
            json.contains("bad.json:1: not a League of Robot Runners problem JSON"),
            "{json}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
