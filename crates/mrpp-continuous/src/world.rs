//! The continuous world file: a rectangular workspace, polygon obstacles (any vertex order,
//! convex or not), and circular robots with radius, speed, start and goal.
//!
//! ```json
//! {"workspace": [0, 0, 500, 400],
//!  "obstacles": [[[100, 100], [160, 100], [160, 180], [100, 180]]],
//!  "robots": [{"start": [20, 20], "goal": [460, 360], "radius": 6, "speed": 16}],
//!  "epsilon": 1.0, "step_limit": 500, "source": "how the file was made (optional)"}
//! ```
//! `workspace` is `[x_min, y_min, x_max, y_max]`; an obstacle's ring closes itself, and one
//! written closed (its last vertex repeating its first) has that repeated closing vertex dropped,
//! once, before any check ([`drop_closing_vertex`]: the one ring rule, which the formation
//! family's polygon map reader, `mrpp_formation::polymap`, applies too); units are the paper's
//! pixels (robot radius 6,
//! speeds 4–20 per step). `epsilon` (default 1.0) is the arrival threshold: a robot within it of
//! its goal stops (the paper's ε); `step_limit` (default 1000) ends a run. Loading checks every
//! rule below and names the file and the item that breaks it (`robots[2]: start inside
//! obstacles[1]`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::geometry::{Point, dist, point_polygon, self_intersects, signed_area2};
use mrpp_core::error::{Error, Result, read_file};

/// One robot: a disc of `radius` moving at most `speed` per step from `start` to `goal`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Robot {
    pub start: Point,
    pub goal: Point,
    pub radius: f64,
    pub speed: f64,
}

/// A continuous world (see the module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct World {
    pub workspace: [f64; 4],
    #[serde(default)]
    pub obstacles: Vec<Vec<Point>>,
    pub robots: Vec<Robot>,
    #[serde(default = "default_epsilon")]
    pub epsilon: f64,
    #[serde(default = "default_step_limit")]
    pub step_limit: usize,
    /// How the file was made (e.g. the `mrpp gen continuous` command with its seed); informative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
}

fn default_epsilon() -> f64 {
    1.0
}

fn default_step_limit() -> usize {
    1000
}

/// The largest absolute coordinate, radius, speed or epsilon a world may hold (beyond it f32
/// libraries such as ORCA's and the spatial grids lose meaning).
pub const MAX_COORDINATE: f64 = 1e7;

/// Most steps a world may ask for.
pub const MAX_STEP_LIMIT: usize = 1_000_000;

impl World {
    /// Reads and checks a world file.
    pub fn load(path: &Path) -> Result<World> {
        let text = read_file(path)?;
        World::parse(&text, path)
    }

    /// Parses and checks world JSON (`path` names it in errors).
    pub fn parse(text: &str, path: &Path) -> Result<World> {
        let mut w: World = serde_json::from_str(text)
            .map_err(|e| Error::parse(path, e.line(), format!("not a continuous world: {e}")))?;
        for poly in &mut w.obstacles {
            drop_closing_vertex(poly);
        }
        w.check().map_err(|msg| Error::invalid(path, msg))?;
        Ok(w)
    }

    /// The first rule the world breaks, as `item: rule`.
    pub fn check(&self) -> std::result::Result<(), String> {
        let [x0, y0, x1, y1] = self.workspace;
        if !self.workspace.iter().all(|v| v.abs() <= MAX_COORDINATE) || x0 >= x1 || y0 >= y1 {
            return Err(format!(
                "workspace: must be [x_min, y_min, x_max, y_max] with min < max and |values| <= {MAX_COORDINATE:e}"
            ));
        }
        if !(self.epsilon > 0.0 && self.epsilon <= MAX_COORDINATE) {
            return Err(format!(
                "epsilon: must be > 0 and at most {MAX_COORDINATE:e}, got {:e}",
                self.epsilon
            ));
        }
        if self.step_limit == 0 || self.step_limit > MAX_STEP_LIMIT {
            return Err(format!(
                "step_limit: must be 1 to {MAX_STEP_LIMIT}, got {}",
                self.step_limit
            ));
        }
        for (k, poly) in self.obstacles.iter().enumerate() {
            let item = format!("obstacles[{k}]");
            if poly.len() < 3 {
                return Err(format!(
                    "{item}: needs at least 3 vertices, has {}",
                    poly.len()
                ));
            }
            if poly
                .iter()
                .flatten()
                .any(|v| v.abs() > MAX_COORDINATE || v.is_nan())
            {
                return Err(format!(
                    "{item}: coordinates must be numbers of at most {MAX_COORDINATE:e}"
                ));
            }
            if self_intersects(poly) {
                return Err(format!("{item}: edges cross each other"));
            }
            if signed_area2(poly).abs() <= 1e-12 {
                return Err(format!("{item}: has no area"));
            }
        }
        if self.robots.is_empty() {
            return Err("robots: at least one robot is needed".into());
        }
        for (i, r) in self.robots.iter().enumerate() {
            self.check_robot(i, r)?;
        }
        for i in 0..self.robots.len() {
            for j in i + 1..self.robots.len() {
                let (a, b) = (&self.robots[i], &self.robots[j]);
                if dist(a.start, b.start) < a.radius + b.radius {
                    return Err(format!("robots[{i}] and robots[{j}]: starts overlap"));
                }
                if dist(a.goal, b.goal) < a.radius + b.radius {
                    return Err(format!("robots[{i}] and robots[{j}]: goals overlap"));
                }
            }
        }
        Ok(())
    }

    fn check_robot(&self, i: usize, r: &Robot) -> std::result::Result<(), String> {
        let item = format!("robots[{i}]");
        if !(r.radius > 0.0 && r.radius <= MAX_COORDINATE) {
            return Err(format!(
                "{item}: radius must be > 0 and at most {MAX_COORDINATE:e}, got {:e}",
                r.radius
            ));
        }
        if !(r.speed > 0.0 && r.speed <= MAX_COORDINATE) {
            return Err(format!(
                "{item}: speed must be > 0 and at most {MAX_COORDINATE:e}, got {:e}",
                r.speed
            ));
        }
        for (what, p) in [("start", r.start), ("goal", r.goal)] {
            if !p.iter().all(|v| v.is_finite()) {
                return Err(format!("{item}: {what} must be finite"));
            }
            if !self.disc_in_workspace(p, r.radius) {
                return Err(format!(
                    "{item}: {what} {p:?} is not inside the workspace (radius {})",
                    r.radius
                ));
            }
            if let Some(k) = self.obstacle_within(p, r.radius) {
                return Err(format!(
                    "{item}: {what} {p:?} inside or touching obstacles[{k}]"
                ));
            }
        }
        Ok(())
    }

    /// Whether a disc at `p` lies inside the workspace.
    pub fn disc_in_workspace(&self, p: Point, radius: f64) -> bool {
        let [x0, y0, x1, y1] = self.workspace;
        p[0] - radius >= x0 && p[0] + radius <= x1 && p[1] - radius >= y0 && p[1] + radius <= y1
    }

    /// The first obstacle closer than `radius` to `p` (the disc overlaps it).
    pub fn obstacle_within(&self, p: Point, radius: f64) -> Option<usize> {
        self.obstacles
            .iter()
            .position(|poly| point_polygon(p, poly) < radius)
    }
}

/// The one ring rule for polygons: a ring whose last vertex repeats its first (written closed)
/// is the ring without that repeat, so `[a, b, c, a]` is the triangle `[a, b, c]` and `[a, b, a]`
/// the two vertices `[a, b]` (which the checks then refuse as too few). Only one closing vertex
/// is dropped: a ring that still repeats its first vertex after that is left for the checks.
/// Returns whether a vertex was dropped.
///
/// The formation family's polygon map reader (`mrpp_formation::polymap::drop_closing_vertex`)
/// holds a copy of these three lines, tested alike: the two families share no crate but
/// `mrpp-core`, which has no geometry.
pub fn drop_closing_vertex(ring: &mut Vec<Point>) -> bool {
    let closed = ring.len() >= 2 && ring.first() == ring.last();
    if closed {
        ring.pop();
    }
    closed
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 27 C: the one ring rule, as in the formation polygon map reader.
    #[test]
    fn a_repeated_closing_vertex_is_dropped_once() {
        let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
        let mut ring = vec![a, b, c, a];
        assert!(drop_closing_vertex(&mut ring));
        assert_eq!(ring, vec![a, b, c]);
        assert!(!drop_closing_vertex(&mut ring));
        let mut twice = vec![a, b, c, a, a];
        assert!(drop_closing_vertex(&mut twice));
        assert_eq!(twice, vec![a, b, c, a]);
        let mut short = vec![a, b, a];
        drop_closing_vertex(&mut short);
        assert_eq!(short, vec![a, b]);
        let mut empty: Vec<Point> = Vec::new();
        assert!(!drop_closing_vertex(&mut empty));

        // In a world: a closed square and a closed triangle are the open ones.
        let p = Path::new("w.json");
        let with = |obstacle: &str| {
            format!(
                r#"{{"workspace": [0, 0, 100, 100], "obstacles": [{obstacle}],
                   "robots": [{{"start": [10, 10], "goal": [90, 90], "radius": 5, "speed": 4}}]}}"#
            )
        };
        for (open, closed) in [
            (
                "[[40, 40], [60, 40], [60, 60], [40, 60]]",
                "[[40, 40], [60, 40], [60, 60], [40, 60], [40, 40]]",
            ),
            (
                "[[40, 40], [60, 40], [50, 60]]",
                "[[40, 40], [60, 40], [50, 60], [40, 40]]",
            ),
        ] {
            let o = World::parse(&with(open), p).unwrap();
            let c = World::parse(&with(closed), p).unwrap();
            assert_eq!(o, c, "{closed}");
        }
        // A closed "triangle" of two distinct vertices is too few.
        let e = World::parse(&with("[[40, 40], [60, 40], [40, 40]]"), p)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("obstacles[0]: needs at least 3 vertices, has 2"),
            "{e}"
        );
    }

    fn world(extra: &str) -> String {
        format!(
            r#"{{"workspace": [0, 0, 100, 100], "obstacles": [[[40, 40], [60, 40], [60, 60], [40, 60]]],
               "robots": [{{"start": [10, 10], "goal": [90, 90], "radius": 5, "speed": 4}}{extra}]}}"#
        )
    }

    #[test]
    fn bad_worlds_name_the_item() {
        let p = Path::new("w.json");
        assert!(World::parse(&world(""), p).is_ok());
        let cases = [
            (
                r#", {"start": [12, 12], "goal": [80, 20], "radius": 5, "speed": 4}"#,
                "starts overlap",
            ),
            (
                r#", {"start": [50, 50], "goal": [80, 20], "radius": 5, "speed": 4}"#,
                "robots[1]: start [50.0, 50.0] inside or touching obstacles[0]",
            ),
            (
                r#", {"start": [80, 20], "goal": [20, 80], "radius": -1, "speed": 4}"#,
                "robots[1]: radius must be > 0",
            ),
            (
                r#", {"start": [80, 20], "goal": [20, 80], "radius": 5, "speed": 0}"#,
                "speed must be > 0",
            ),
            (
                r#", {"start": [80, 20], "goal": [99, 80], "radius": 5, "speed": 1}"#,
                "goal [99.0, 80.0] is not inside the workspace",
            ),
        ];
        for (extra, want) in cases {
            let e = World::parse(&world(extra), p).unwrap_err().to_string();
            assert!(e.contains(want) && e.contains("w.json"), "{e}");
        }
        let e = World::parse("{\"workspace\": [0, 0, 1, 1],", p)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("w.json") && e.contains("not a continuous world"),
            "{e}"
        );
        let bow = r#"{"workspace": [0, 0, 100, 100], "obstacles": [[[0, 0], [20, 20], [20, 0], [0, 20]]], "robots": [{"start": [50, 50], "goal": [90, 90], "radius": 5, "speed": 4}]}"#;
        let e = World::parse(bow, p).unwrap_err().to_string();
        assert!(e.contains("obstacles[0]: edges cross"), "{e}");
    }
}
