//! League of Robot Runners (LoRR) problem files as the start kit reads them, for every family that
//! plans on them: the one-shot grid family (`mrpp-grid`'s `lorr`) and the lifelong family
//! (`mrpp-lifelong`).
//!
//! A LoRR problem is a JSON file naming a map, an agent file and a task file (paths relative to
//! the JSON's folder), as in the competition's start kit (GitHub `MAPF-Competition/Start-Kit`,
//! `Input_Output_Format.md` and `src/driver.cpp`; MIT licence). Keys read: `mapFile`,
//! `agentFile`, `taskFile`, `teamSize` (required), `numTasksReveal` (default 1), `version`
//! (absent in the 2023 layout). The map is a MovingAI map whose cells may also be `E` (emitter)
//! and `S` (service), both traversable ([`crate::map`]); locations are linearised,
//! `loc = row * width + col`.
//!
//! Agent and task files: `#` comment lines are skipped wherever they are, then a count line, then
//! exactly that many lines. An agent line's first comma-separated field is its start location
//! (the first `teamSize` agents are used); a task line is a comma-separated sequence of errand
//! locations (one location in the 2023 layout).
//!
//! Stricter than the kit, where the kit's behaviour is undefined or silent: every location must be
//! a free cell of the map (the kit checks only starts, and exits 0 on one), no two robots may
//! start on one cell (the kit does not check), the count line must match the lines that follow,
//! and `numTasksReveal x teamSize` must be at least one task. Each error names the file, the line
//! and the rule.

use std::path::{Path, PathBuf};

use serde_json::Value;

use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::graph::VertexId;

use crate::instance_rules::{Spot, checked_starts};
use crate::map::GridMap;

/// A LoRR problem's files, read and checked (module doc).
#[derive(Debug, Clone)]
pub struct LorrFiles {
    /// The problem JSON.
    pub path: PathBuf,
    /// The map file (resolved against the JSON's folder).
    pub map_path: PathBuf,
    /// The agent file.
    pub agent_path: PathBuf,
    /// The task file.
    pub task_path: PathBuf,
    /// The map.
    pub map: GridMap,
    /// Start vertex of each of the `teamSize` robots, distinct.
    pub starts: Vec<VertexId>,
    /// 1-based line of the agent file each start was read from.
    pub start_lines: Vec<usize>,
    /// Every task of the task file in file order, each a non-empty sequence of errand vertices.
    pub tasks: Vec<Vec<VertexId>>,
    /// 1-based line of the task file each task was read from.
    pub task_lines: Vec<usize>,
    /// `numTasksReveal` (default 1): the kit keeps `(numTasksReveal x teamSize)` tasks open
    /// (truncated), at least 1 here.
    pub num_tasks_reveal: f64,
    /// `version` (`"2024 LoRR"`, `"2026 LoRR"`), `"2023"` when absent.
    pub version: String,
    /// The whole problem JSON, for keys a family reads itself (`agentCounter`, `delayConfig`).
    pub json: Value,
}

impl LorrFiles {
    /// The robots a problem has (`teamSize`).
    pub fn team_size(&self) -> usize {
        self.starts.len()
    }

    /// Tasks the kit keeps open at once: `(numTasksReveal x teamSize)` truncated, computed in
    /// single precision as the kit computes it (a C++ `float`: 0.29 x 100 is 29 there, 28 in
    /// double precision).
    pub fn reveal_pool(&self) -> usize {
        (self.num_tasks_reveal as f32 * self.team_size() as f32) as usize
    }
}

/// Reads a LoRR problem JSON and the map, agent and task files it names.
///
/// # Errors
/// The file, line and rule (module doc).
pub fn load(path: &Path) -> Result<LorrFiles> {
    parse_with(&read_file(path)?, path, &|p: &Path| read_file(p))
}

/// [`load`] with the problem JSON given as `text` and the files it names read through `read`
/// (given each file's path, resolved against `path`'s folder).
///
/// # Errors
/// As [`load`], and whatever `read` returns.
pub fn parse_with(
    text: &str,
    path: &Path,
    read: &dyn Fn(&Path) -> Result<String>,
) -> Result<LorrFiles> {
    let json: Value = serde_json::from_str(text.trim_start_matches('\u{feff}')).map_err(|e| {
        Error::parse(
            path,
            e.line(),
            format!("not a League of Robot Runners problem JSON: {e}"),
        )
    })?;
    let [map_path, agent_path, task_path] = named_files(&json, path)?;
    let team = json
        .get("teamSize")
        .and_then(Value::as_u64)
        .filter(|&n| n > 0)
        .ok_or_else(|| Error::invalid(path, "`teamSize` must be a positive integer"))?
        as usize;
    let num_tasks_reveal = match json.get("numTasksReveal") {
        None => 1.0,
        Some(v) => v
            .as_f64()
            .filter(|r| r.is_finite() && (*r as f32 * team as f32) as usize >= 1)
            .ok_or_else(|| {
                Error::invalid(
                    path,
                    format!(
                        "`numTasksReveal` is {v}: numTasksReveal x teamSize ({team}) must be at \
                         least one task"
                    ),
                )
            })?,
    };
    let version = json
        .get("version")
        .and_then(Value::as_str)
        .unwrap_or("2023")
        .to_string();

    let map = GridMap::parse(&read(&map_path)?, &map_path)?.0;
    let w = i64::from(map.width());
    let cells = w * i64::from(map.height());
    let cell = |loc: i64, file: &Path, line: usize| -> Result<(i64, i64)> {
        if !(0..cells).contains(&loc) {
            return Err(Error::parse(
                file,
                line,
                format!("location {loc} is off the map (0..{cells})"),
            ));
        }
        Ok((loc % w, loc / w))
    };
    let vertex = |loc: i64, file: &Path, line: usize| -> Result<VertexId> {
        let (x, y) = cell(loc, file, line)?;
        map.vertex_at(x, y).ok_or_else(|| {
            Error::parse(
                file,
                line,
                format!("location {loc} is cell ({x},{y}), a wall"),
            )
        })
    };

    let agent_lines = counted_lines(&read(&agent_path)?, &agent_path)?;
    if agent_lines.len() < team {
        return Err(Error::invalid(
            &agent_path,
            format!(
                "`teamSize` is {team} but the file has only {} agents",
                agent_lines.len()
            ),
        ));
    }
    let mut spots = Vec::with_capacity(team);
    for (no, line) in &agent_lines[..team] {
        let first = line.split(',').next().unwrap_or_default();
        let loc = int(first, &agent_path, *no)?;
        vertex(loc, &agent_path, *no)?;
        spots.push(Spot {
            cell: cell(loc, &agent_path, *no)?,
            file: agent_path.as_path(),
            line: *no,
        });
    }
    let starts = checked_starts(&map, &spots)?;
    let start_lines = spots.iter().map(|s| s.line).collect();

    let mut tasks = Vec::new();
    let mut task_lines = Vec::new();
    for (no, line) in counted_lines(&read(&task_path)?, &task_path)? {
        let errands = line
            .split(',')
            .map(|f| vertex(int(f, &task_path, no)?, &task_path, no))
            .collect::<Result<Vec<_>>>()?;
        tasks.push(errands);
        task_lines.push(no);
    }
    if tasks.is_empty() {
        return Err(Error::invalid(&task_path, "the file holds no task"));
    }
    Ok(LorrFiles {
        path: path.to_path_buf(),
        map_path,
        agent_path,
        task_path,
        map,
        starts,
        start_lines,
        tasks,
        task_lines,
        num_tasks_reveal,
        version,
        json,
    })
}

/// The map, agent and task files a LoRR problem JSON at `path` names, resolved against its
/// folder as [`load`] resolves them (so that outputs can refuse to overwrite them).
///
/// # Errors
/// The JSON cannot be read or parsed, or names no such file.
pub fn referenced_files(path: &Path) -> Result<Vec<PathBuf>> {
    let text = read_file(path)?;
    let json: Value = serde_json::from_str(&text)
        .map_err(|e| Error::parse(path, e.line(), format!("not JSON: {e}")))?;
    Ok(named_files(&json, path)?.to_vec())
}

/// `[mapFile, agentFile, taskFile]` of a problem JSON, each joined to the JSON's folder.
fn named_files(json: &Value, path: &Path) -> Result<[PathBuf; 3]> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let file = |key: &str| -> Result<PathBuf> {
        json.get(key)
            .and_then(Value::as_str)
            .map(|f| dir.join(f))
            .ok_or_else(|| Error::invalid(path, format!("no `{key}` (a file name) in the problem")))
    };
    Ok([file("mapFile")?, file("agentFile")?, file("taskFile")?])
}

fn int(field: &str, path: &Path, line: usize) -> Result<i64> {
    field.trim().parse::<i64>().map_err(|_| {
        Error::parse(
            path,
            line,
            format!("`{}` is not a location (an integer)", field.trim()),
        )
    })
}

/// The entries of a LoRR agent or task file: `#` comment lines skipped, then a count line, then
/// exactly that many non-empty lines, each returned with its 1-based line number.
fn counted_lines(text: &str, path: &Path) -> Result<Vec<(usize, String)>> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            (
                i + 1,
                l.trim_matches(|c: char| c.is_whitespace() || c == '\u{feff}'),
            )
        })
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (no, count) = lines
        .next()
        .ok_or_else(|| Error::invalid(path, "empty file: expected a count line"))?;
    let count: usize = count.parse().map_err(|_| {
        Error::parse(
            path,
            no,
            format!("expected the number of entries, found `{count}`"),
        )
    })?;
    let entries: Vec<(usize, String)> = lines.map(|(n, l)| (n, l.to_string())).collect();
    if entries.len() != count {
        return Err(Error::parse(
            path,
            no,
            format!(
                "count line says {count} but {} entries follow",
                entries.len()
            ),
        ));
    }
    Ok(entries)
}
