//! Agents of grid instances: they come from MovingAI `.scen` files (the first N lines are agents 0..N) or from the
//! H* paper's robot files (`x,y;x,y` per line, `#` comments); the format is detected from the
//! content. The instance rules (cells on the map and free, distinct starts, distinct goals) are
//! [`crate::instance_rules`]'s, as for every grid reader.

use std::path::Path;

use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::instance::Instance;
pub use mrpp_mapf::map::random_instance;

use crate::instance_rules::{Spot, checked_instance};
use crate::map::GridMap;

/// Reads a `.scen` or robot file for `map`, keeping the first `agents` entries (all when `None`).
pub fn load_agents(path: &Path, map: &GridMap, agents: Option<usize>) -> Result<Instance> {
    let text = read_file(path)?;
    parse_agents(&text, path, map, agents)
}

/// Parses agent text (`.scen` or robot file, detected from the content); `path` only names the
/// source in errors.
pub fn parse_agents(
    text: &str,
    path: &Path,
    map: &GridMap,
    agents: Option<usize>,
) -> Result<Instance> {
    // A `.scen` starts with `version 1` (or `version 1.0`), or, without it, with a line of at
    // least 8 fields (bucket, map, width, height, start x, y, goal x, y, ...); a robot file's
    // lines are `x,y;x,y`.
    let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
    let scen_line = first.contains('\t') || first.split_whitespace().count() >= 8;
    let entries = if first.trim_start().starts_with("version") || scen_line {
        parse_scen(text, path, map)?
    } else {
        parse_robots(text, path)?
    };
    if entries.is_empty() {
        return Err(Error::invalid(path, "no agents in file"));
    }
    let n = match agents {
        Some(0) => return Err(Error::Param("--agents must be at least 1".into())),
        Some(n) if n > entries.len() => {
            return Err(Error::invalid(
                path,
                format!(
                    "asked for {n} agents but the file has only {}",
                    entries.len()
                ),
            ));
        }
        Some(n) => n,
        None => entries.len(),
    };
    let agents: Vec<(Spot<'_>, Spot<'_>)> = entries[..n]
        .iter()
        .map(|e| {
            let at = |cell| Spot {
                cell,
                file: path,
                line: e.line,
            };
            (at(e.start), at(e.goal))
        })
        .collect();
    checked_instance(map, &agents)
}

struct Entry {
    line: usize,
    start: (i64, i64),
    goal: (i64, i64),
}

fn int(field: &str, path: &Path, line: usize, what: &str) -> Result<i64> {
    field.trim().parse::<i64>().map_err(|_| {
        Error::parse(
            path,
            line,
            format!("{what} `{}` is not an integer", field.trim()),
        )
    })
}

fn parse_scen(text: &str, path: &Path, map: &GridMap) -> Result<Vec<Entry>> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let no = i + 1;
        let line = raw.trim_end_matches('\r');
        if line.trim().is_empty() || line.trim_start().starts_with("version") {
            continue;
        }
        let f: Vec<&str> = if line.contains('\t') {
            line.split('\t').collect()
        } else {
            line.split_whitespace().collect()
        };
        if f.len() < 8 {
            return Err(Error::parse(
                path,
                no,
                format!("expected 9 fields, found {}", f.len()),
            ));
        }
        let (w, h) = (
            int(f[2], path, no, "width")?,
            int(f[3], path, no, "height")?,
        );
        if w != map.width() as i64 || h != map.height() as i64 {
            return Err(Error::parse(
                path,
                no,
                format!(
                    "scenario is for a {w}x{h} map but the map is {}x{}",
                    map.width(),
                    map.height()
                ),
            ));
        }
        out.push(Entry {
            line: no,
            start: (
                int(f[4], path, no, "start x")?,
                int(f[5], path, no, "start y")?,
            ),
            goal: (
                int(f[6], path, no, "goal x")?,
                int(f[7], path, no, "goal y")?,
            ),
        });
    }
    Ok(out)
}

fn parse_robots(text: &str, path: &Path) -> Result<Vec<Entry>> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let no = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let bad = || Error::parse(path, no, format!("expected `x,y;x,y`, found `{line}`"));
        let (s, g) = line.split_once(';').ok_or_else(bad)?;
        let pair = |p: &str| -> Result<(i64, i64)> {
            let (x, y) = p.split_once(',').ok_or_else(bad)?;
            Ok((int(x, path, no, "x")?, int(y, path, no, "y")?))
        };
        out.push(Entry {
            line: no,
            start: pair(s)?,
            goal: pair(g)?,
        });
    }
    Ok(out)
}

/// A random MovingAI map (`type octile`; what `mrpp gen map` writes): `width` x `height` cells,
/// each an obstacle (`@`) with probability `obstacles`, independently (seeded), else free (`.`),
/// like MovingAI's `random-*` maps. Agents are then placed in its largest connected area by
/// [`random_instance`].
///
/// # Errors
/// A message when a side is not in 1..=10 000 or `obstacles` is not in 0..=0.9.
pub fn random_map_text(
    width: usize,
    height: usize,
    obstacles: f64,
    seed: u64,
) -> std::result::Result<String, String> {
    use rand::{RngExt, SeedableRng};
    if !(1..=10_000).contains(&width) || !(1..=10_000).contains(&height) {
        return Err(format!(
            "width and height must be 1 to 10000 cells, got {width} x {height}"
        ));
    }
    if !(0.0..=0.9).contains(&obstacles) {
        return Err(format!(
            "obstacles must be a fraction from 0 to 0.9, got {obstacles}"
        ));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut s = format!("type octile\nheight {height}\nwidth {width}\nmap\n");
    s.reserve((width + 1) * height);
    for _ in 0..height {
        for _ in 0..width {
            s.push(if rng.random::<f64>() < obstacles {
                '@'
            } else {
                '.'
            });
        }
        s.push('\n');
    }
    Ok(s)
}

/// `inst` as a MovingAI `.scen` (`version 1`; bucket = distance / 4; the last field is the
/// 4-connected shortest distance, where MovingAI's own files give the octile one; `u32::MAX` when
/// the goal cannot be reached). Each distance is one A* search
/// ([`mrpp_core::mapf::search::distance::shortest_distance`]; a breadth-first search over the
/// whole map per agent took 67 s for 2,000 agents on a 1000 x 1000 map).
pub fn scen_text(map: &GridMap, map_file: &str, inst: &Instance) -> String {
    use std::fmt::Write as _;
    let g = map.graph();
    let mut s = String::from("version 1\n");
    for (&a, &b) in inst.starts.iter().zip(&inst.goals) {
        let d = mrpp_core::mapf::search::distance::shortest_distance(g, a, b).unwrap_or(u32::MAX);
        let ((sx, sy), (gx, gy)) = (map.cell(a), map.cell(b));
        let _ = writeln!(
            s,
            "{}\t{map_file}\t{}\t{}\t{sx}\t{sy}\t{gx}\t{gy}\t{d}",
            d / 4,
            map.width(),
            map.height()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::mapf::graph::VertexId;

    #[test]
    fn scen_distances_are_the_breadth_first_ones() {
        for seed in 0..5 {
            let text = random_map_text(30, 20, 0.3, seed).unwrap();
            let (m, _) = GridMap::parse(&text, Path::new("r.map")).unwrap();
            // Starts and goals anywhere, so some goals cannot be reached.
            let free: Vec<VertexId> = (0..m.graph().num_vertices() as VertexId).collect();
            let k = free.len().min(40);
            let inst = Instance::new(
                free[..k].to_vec(),
                free[free.len() - k..].iter().rev().copied().collect(),
            )
            .unwrap();
            let scen = scen_text(&m, "r.map", &inst);
            for (line, (&a, &b)) in scen
                .lines()
                .skip(1)
                .zip(inst.starts.iter().zip(&inst.goals))
            {
                let d = mrpp_core::mapf::search::distance::bfs_distances(m.graph(), b)[a as usize];
                assert_eq!(
                    line.rsplit('\t').next().unwrap(),
                    d.to_string(),
                    "seed {seed}: {line}"
                );
            }
        }
    }

    #[test]
    fn random_maps_are_seeded_and_checked() {
        let a = random_map_text(7, 3, 0.3, 5).unwrap();
        assert_eq!(a, random_map_text(7, 3, 0.3, 5).unwrap());
        assert_ne!(a, random_map_text(7, 3, 0.3, 6).unwrap());
        let (m, _) = GridMap::parse(&a, Path::new("r.map")).unwrap();
        assert_eq!((m.width(), m.height()), (7, 3));
        assert!(random_map_text(0, 3, 0.1, 0).is_err());
        assert!(random_map_text(3, 3, 0.95, 0).is_err());
        assert!(random_map_text(3, 3, f64::NAN, 0).is_err());
        assert!(!random_map_text(9, 9, 0.0, 0).unwrap().contains('@'));
    }

    fn map() -> GridMap {
        GridMap::parse("#####\n#   #\n# # #\n#   #\n#####", Path::new("m.txt"))
            .unwrap()
            .0
    }

    #[test]
    fn robot_file_parses_with_comments() {
        let m = map();
        let inst = parse_agents(
            "# Room 0\r\n1,1;3,3\r\n\r\n3,1;1,3",
            Path::new("r.txt"),
            &m,
            None,
        )
        .unwrap();
        assert_eq!(inst.num_agents(), 2);
        assert_eq!(m.cell(inst.starts[1]), (3, 1));
        assert_eq!(m.cell(inst.goals[0]), (3, 3));
    }

    #[test]
    fn scen_with_version_1_0_or_no_version_line() {
        let m = map();
        let body = "0\tm.map\t5\t5\t1\t1\t3\t3\t4\n0\tm.map\t5\t5\t3\t1\t1\t3\t4\n";
        let want =
            parse_agents(&format!("version 1\n{body}"), Path::new("a.scen"), &m, None).unwrap();
        for text in [
            format!("version 1.0\n{body}"),
            body.to_string(),
            body.replace('\t', " "),
        ] {
            let got = parse_agents(&text, Path::new("a.scen"), &m, None).unwrap();
            assert_eq!(got, want, "{text}");
        }
    }

    #[test]
    fn scen_takes_first_n() {
        let m = map();
        let text = "version 1\n0\tm.map\t5\t5\t1\t1\t3\t3\t4\n0\tm.map\t5\t5\t3\t1\t1\t3\t4\n";
        let inst = parse_agents(text, Path::new("s.scen"), &m, Some(1)).unwrap();
        assert_eq!(inst.num_agents(), 1);
        let err = parse_agents(text, Path::new("s.scen"), &m, Some(3))
            .unwrap_err()
            .to_string();
        assert!(err.contains("only 2"), "{err}");
    }

    #[test]
    fn wall_off_map_and_duplicates_are_named() {
        let m = map();
        let e = parse_agents("1,1;2,2", Path::new("r.txt"), &m, None)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("r.txt:1:") && e.contains("wall"), "{e}");
        let e = parse_agents("1,1;3,3\n9,1;1,3", Path::new("r.txt"), &m, None)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("r.txt:2:") && e.contains("off"), "{e}");
        let e = parse_agents("1,1;3,3\n1,1;1,3", Path::new("r.txt"), &m, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1"), "{e}");
        let e = parse_agents("1,1;3,3\n1;1,3", Path::new("r.txt"), &m, None)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("r.txt:2:"), "{e}");
    }
}
