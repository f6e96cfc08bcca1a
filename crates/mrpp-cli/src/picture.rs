//! Pictures of a plan drawn from the viewer's scene ([`crate::view`]), as SVG: one frame at a
//! time step (what `render --gif` animates) or the whole plan (every agent's route, starts as
//! discs, goals as squares; the static picture of families without their own, e.g. trees). The
//! colours are the page's. Lifelong runs draw what the page draws: under `MAPF_T` a heading tick
//! on each disc, the task id above each errand when there is room, and the scene's series (tasks
//! finished over the steps) as a small chart in the bottom-right corner, the frame's step marked.

use mrpp_core::picture::{agent_colour as colour, wait_runs};
use serde_json::Value;

/// Width of pictures in pixels (the height follows the world's aspect ratio).
const WIDTH: f64 = 800.0;

/// Height of the whole-plan picture's legend band, in pixels.
const LEGEND_PX: f64 = 22.0;

fn point(v: &Value) -> [f64; 2] {
    [v[0].as_f64().unwrap_or(0.0), v[1].as_f64().unwrap_or(0.0)]
}

/// Agent `a`'s point at step `k` (resting on its last one), from `path` or grid `cells`.
fn at(scene: &Value, a: &Value, k: usize) -> Option<[f64; 2]> {
    if let Some(cells) = a["cells"].as_array() {
        let w = scene["cells"]["width"].as_u64()?.max(1);
        let c = cells.get(k.min(cells.len().checked_sub(1)?))?.as_u64()?;
        return Some([(c % w) as f64 + 0.5, (c / w) as f64 + 0.5]);
    }
    let path = a["path"].as_array()?;
    Some(point(path.get(k.min(path.len().checked_sub(1)?))?))
}

/// Steps of the scene's plan.
pub(crate) fn steps(scene: &Value) -> usize {
    scene["agents"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|x| {
                    x["cells"]
                        .as_array()
                        .or(x["path"].as_array())
                        .map_or(1, Vec::len)
                })
                .max()
                .unwrap_or(1)
        })
        .unwrap_or(1)
        .saturating_sub(1)
}

/// One frame of the scene at step `t` as SVG.
#[cfg(any(feature = "raster", test))]
pub(crate) fn frame_svg(scene: &Value, t: usize) -> String {
    draw(scene, Some(t))
}

/// Agent `a`'s goal at step `t` (`None`: the whole plan): its `goal`, or in a lifelong run's
/// frame the entry of its `goals` change list in force at `t` (`None` when it has no task).
fn goal_at(scene: &Value, a: &Value, t: Option<usize>) -> Option<[f64; 2]> {
    let (Some(t), Some(_)) = (t, a["goals"].as_array()) else {
        return Some(point(&a["goal"]));
    };
    let cell = change_at(a, "goals", t)?
        .get(1)?
        .as_i64()
        .filter(|&c| c >= 0)?;
    let w = scene["cells"]["width"].as_i64().filter(|&w| w > 0)?;
    Some([(cell % w) as f64 + 0.5, (cell / w) as f64 + 0.5])
}

/// The entry of agent `a`'s change list `key` (`goals`, `headings`) in force at step `t`.
/// The list is in step order, so a binary search finds it (a frame of a long run looks up every
/// agent).
fn change_at<'a>(a: &'a Value, key: &str, t: usize) -> Option<&'a Vec<Value>> {
    let list = a[key].as_array()?;
    let n = list.partition_point(|c| c[0].as_u64().is_some_and(|s| s as usize <= t));
    list.get(n.checked_sub(1)?)?.as_array()
}

/// Agent `a`'s heading at step `t` in a lifelong run under `MAPF_T` as a unit step on the
/// screen's grid (0 east, 1 south, 2 west, 3 north; rows grow down), or `None`.
fn heading_at(a: &Value, t: usize) -> Option<[f64; 2]> {
    let h = change_at(a, "headings", t)?.get(1)?.as_u64()?;
    [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]]
        .get(h as usize)
        .copied()
}

/// Agent `a`'s task id at step `t` in a lifelong run, or `None` (no task, or not lifelong).
fn task_at(a: &Value, t: usize) -> Option<i64> {
    change_at(a, "goals", t)?
        .get(2)?
        .as_i64()
        .filter(|&k| k >= 0)
}

/// The scene's series (lifelong: tasks finished after each step) as a 240 x 110 px chart in the
/// bottom-right corner of a `w` x `h` px world, step `t` marked (none: the whole run).
fn series_svg(scene: &Value, t: Option<usize>, w: f64, h: f64) -> String {
    use std::fmt::Write as _;
    let Some(values) = scene["series"]["values"].as_array() else {
        return String::new();
    };
    let v: Vec<f64> = values.iter().map(|x| x.as_f64().unwrap_or(0.0)).collect();
    if v.len() < 2 || w < 260.0 || h < 130.0 {
        return String::new();
    }
    let name = scene["series"]["name"].as_str().unwrap_or("");
    let unit = scene["unit"].as_str().unwrap_or("step");
    let (cw, ch, pad) = (240.0, 110.0, 28.0);
    let (x0, y0) = (w - cw - 10.0, h - ch - 10.0);
    let top = v.iter().copied().fold(1.0, f64::max);
    let last = v.len() - 1;
    let px = |k: usize| x0 + pad + (cw - pad - 8.0) * k as f64 / last as f64;
    let py = |y: f64| y0 + ch - 16.0 - (ch - 42.0) * y / top;
    let stride = (v.len() / 400).max(1);
    let line: Vec<String> = (0..v.len())
        .step_by(stride)
        .chain(std::iter::once(last))
        .map(|k| format!("{:.1},{:.1}", px(k), py(v[k])))
        .collect();
    let mut s = String::new();
    let _ = write!(
        s,
        r##"<g font-family="sans-serif" font-size="10" fill="#333"><rect x="{x0:.1}" y="{y0:.1}" width="{cw}" height="{ch}" fill="#fff" fill-opacity="0.92" stroke="#999"/><path d="M{:.1},{:.1}H{:.1}M{:.1},{:.1}V{:.1}" stroke="#999" fill="none"/><text x="{:.1}" y="{:.1}" text-anchor="end">0</text><text x="{:.1}" y="{:.1}" text-anchor="end">{top}</text><text x="{:.1}" y="{:.1}" text-anchor="middle">{unit}</text><text x="{:.1}" y="{:.1}" text-anchor="middle">{last}</text><polyline points="{}" fill="none" stroke="#1565c0" stroke-width="1.5"/>"##,
        px(0),
        py(0.0),
        px(last),
        px(0),
        py(0.0),
        py(top),
        px(0) - 3.0,
        py(0.0) + 3.0,
        px(0) - 3.0,
        py(top) + 3.0,
        (px(0) + px(last)) / 2.0,
        py(0.0) + 12.0,
        px(last),
        py(0.0) + 12.0,
        line.join(" ")
    );
    let (k, label) = match t {
        Some(t) => {
            let k = t.min(last);
            (Some(k), format!("{name}: {} at {unit} {k}", v[k]))
        }
        None => (None, format!("{name}: {} after {last} {unit}s", v[last])),
    };
    if let Some(k) = k {
        let _ = write!(
            s,
            r##"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}" stroke="#d00"/>"##,
            px(k),
            py(0.0),
            py(top)
        );
    }
    let _ = write!(
        s,
        r##"<text x="{:.1}" y="{:.1}" font-size="11" fill="#111">{label}</text></g>"##,
        x0 + 6.0,
        y0 + 14.0
    );
    s
}

/// The whole plan as SVG: routes, starts and goals.
pub(crate) fn paths_svg(scene: &Value) -> String {
    draw(scene, None)
}

/// A frame at step `t`, or (`None`) the whole plan.
fn draw(scene: &Value, t: Option<usize>) -> String {
    use std::fmt::Write as _;
    let b = &scene["bounds"];
    let (x0, y0, x1, y1) = (
        b[0].as_f64().unwrap_or(0.0),
        b[1].as_f64().unwrap_or(0.0),
        b[2].as_f64().unwrap_or(1.0),
        b[3].as_f64().unwrap_or(1.0),
    );
    let y_up = scene["y_up"].as_bool().unwrap_or(false);
    let scale = WIDTH / (x1 - x0).max(1e-9);
    let (w, h) = (WIDTH, ((y1 - y0) * scale).max(1.0));
    let xy = |p: [f64; 2]| {
        let y = if y_up { y1 - p[1] } else { p[1] - y0 };
        ((p[0] - x0) * scale, y * scale)
    };
    let mut s = String::new();
    // A legend band under the world: what the marks mean, and a frame's time step (dark on
    // white, where a label on the map could sit on a wall).
    let band = LEGEND_PX;
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{:.0}" viewBox="0 0 {w:.0} {:.0}"><rect width="100%" height="100%" fill="#fff"/>"##,
        h + band,
        h + band
    );
    if let Some(rows) = scene["cells"]["rows"].as_array() {
        for (y, row) in rows.iter().enumerate() {
            for (x, c) in row.as_str().unwrap_or("").chars().enumerate() {
                if c == '#' {
                    let (sx, sy) = xy([x as f64, y as f64]);
                    let _ = write!(
                        s,
                        r##"<rect x="{sx:.2}" y="{sy:.2}" width="{:.2}" height="{:.2}" fill="#282828"/>"##,
                        scale + 0.3,
                        scale + 0.3
                    );
                }
            }
        }
    }
    for poly in scene["polygons"].as_array().into_iter().flatten() {
        let pts: Vec<String> = poly
            .as_array()
            .into_iter()
            .flatten()
            .map(|p| {
                let (x, y) = xy(point(p));
                format!("{x:.2},{y:.2}")
            })
            .collect();
        let _ = write!(s, r##"<polygon points="{}" fill="#555"/>"##, pts.join(" "));
    }
    for seg in scene["segments"].as_array().into_iter().flatten() {
        let ((ax, ay), (bx, by)) = (xy(point(&seg[0])), xy(point(&seg[1])));
        let _ = write!(
            s,
            r##"<line x1="{ax:.2}" y1="{ay:.2}" x2="{bx:.2}" y2="{by:.2}" stroke="#999" stroke-width="{:.2}"/>"##,
            (scale * 0.12).max(1.0)
        );
    }
    // Graph nodes (trees): a small grey dot each, so a path that ends on an empty node ends on
    // something.
    for node in scene["nodes"].as_array().into_iter().flatten() {
        let (x, y) = xy(point(node));
        let _ = write!(
            s,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="#bbb"/>"##,
            (scale * 0.14).max(2.0)
        );
    }
    let agents = scene["agents"].as_array().cloned().unwrap_or_default();
    for (i, a) in agents.iter().enumerate() {
        let r = a["radius"].as_f64().unwrap_or(0.4) * scale;
        let Some(goal) = goal_at(scene, a, t) else {
            continue;
        };
        let (gx, gy) = xy(goal);
        let g = (r * 0.9).max(1.5);
        let _ = write!(
            s,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="{}" stroke-width="{:.2}"/>"##,
            gx - g,
            gy - g,
            2.0 * g,
            2.0 * g,
            colour(i),
            (scale * 0.08).max(1.0)
        );
        if let Some(task) = t.and_then(|t| task_at(a, t)).filter(|_| g >= 6.0) {
            let _ = write!(
                s,
                r##"<text x="{gx:.2}" y="{:.2}" font-size="{:.1}" font-family="sans-serif" text-anchor="middle" fill="{}">task {task}</text>"##,
                gy - g - 2.0,
                g.min(12.0),
                colour(i)
            );
        }
    }
    if t.is_none() {
        // Every agent's route, under the discs.
        for (i, a) in agents.iter().enumerate() {
            let n = a["cells"]
                .as_array()
                .or(a["path"].as_array())
                .map_or(0, Vec::len);
            let pts: Vec<String> = (0..n)
                .filter_map(|k| at(scene, a, k))
                .map(|p| {
                    let (x, y) = xy(p);
                    format!("{x:.2},{y:.2}")
                })
                .collect();
            let _ = write!(
                s,
                r##"<polyline points="{}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-opacity="0.7"/>"##,
                pts.join(" "),
                colour(i),
                (scale * 0.12).max(1.0)
            );
        }
        // Waits: a ring where an agent stands still before its last move.
        for (i, a) in agents.iter().enumerate() {
            let n = a["cells"]
                .as_array()
                .or(a["path"].as_array())
                .map_or(0, Vec::len);
            let points: Vec<[f64; 2]> = (0..n).filter_map(|k| at(scene, a, k)).collect();
            let r = (a["radius"].as_f64().unwrap_or(0.4) * scale).max(1.5) * 1.3;
            for (from, steps) in wait_runs(&points) {
                let (x, y) = xy(points[from]);
                let _ = write!(
                    s,
                    r##"<circle cx="{x:.2}" cy="{y:.2}" r="{r:.2}" fill="none" stroke="{}" stroke-width="{:.2}"><title>agent {i} waits {steps} step(s) at t={from}</title></circle>"##,
                    colour(i),
                    (1.0 + (steps as f64).ln()).min(4.0)
                );
            }
        }
    }
    // Agents on one point (a formation's robots at Q_ini or on a roadmap vertex) are drawn
    // around it, each at its own angle, so three robots do not look like one.
    let points: Vec<Option<[f64; 2]>> = agents
        .iter()
        .map(|a| at(scene, a, t.unwrap_or(0)))
        .collect();
    let same = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9;
    for (i, a) in agents.iter().enumerate() {
        let Some(p) = points[i] else {
            continue;
        };
        let r = (a["radius"].as_f64().unwrap_or(0.4) * scale).max(1.5);
        let (mut sx, mut sy) = xy(p);
        let here: Vec<usize> = (0..agents.len())
            .filter(|&j| points[j].is_some_and(|q| same(p, q)))
            .collect();
        if here.len() > 1 {
            let k = here.iter().position(|&j| j == i).unwrap_or(0) as f64;
            let angle = std::f64::consts::TAU * k / here.len() as f64;
            sx += r * 1.1 * angle.cos();
            sy += r * 1.1 * angle.sin();
        }
        let _ = write!(
            s,
            r##"<circle cx="{sx:.2}" cy="{sy:.2}" r="{r:.2}" fill="{}"/>"##,
            colour(i)
        );
        if let Some([dx, dy]) = heading_at(a, t.unwrap_or(0)).filter(|_| r >= 3.0) {
            // Headings are in the grid's rows-grow-down frame; a y-up scene turns them over.
            let dy = if y_up { -dy } else { dy };
            let _ = write!(
                s,
                r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#111" stroke-width="{:.2}"/>"##,
                sx + dx * r * 0.35,
                sy + dy * r * 0.35,
                sx + dx * r * 1.15,
                sy + dy * r * 1.15,
                (r * 0.3).max(1.5)
            );
        }
        if r >= 7.0 {
            let _ = write!(
                s,
                r##"<text x="{sx:.2}" y="{:.2}" font-size="{:.1}" font-family="sans-serif" text-anchor="middle" fill="#fff">{i}</text>"##,
                sy + r.min(14.0) * 0.35,
                r.min(14.0)
            );
        }
    }
    s.push_str(&series_svg(scene, t, w, h));
    if let Some(t) = t {
        let y = h + band / 2.0;
        let _ = write!(
            s,
            r##"<g font-family="sans-serif" font-size="12" fill="#222"><text x="8" y="{:.2}" font-weight="bold">t = {t} of {}</text><circle cx="112" cy="{y:.2}" r="5" fill="#666"/><text x="121" y="{:.2}">agent (id)</text><rect x="190" y="{:.2}" width="10" height="10" fill="none" stroke="#666" stroke-width="1.5"/><text x="206" y="{:.2}">goal</text><text x="248" y="{:.2}">{} agents, one colour each</text></g>"##,
            y + 4.0,
            steps(scene),
            y + 4.0,
            y - 5.0,
            y + 4.0,
            y + 4.0,
            agents.len()
        );
    } else {
        let y = h + band / 2.0;
        let _ = write!(
            s,
            r##"<g font-family="sans-serif" font-size="11" fill="#333"><circle cx="13" cy="{y:.2}" r="5" fill="#666"/><text x="22" y="{:.2}">start (id)</text><rect x="84" y="{:.2}" width="10" height="10" fill="none" stroke="#666" stroke-width="1.5"/><text x="100" y="{:.2}">goal</text><circle cx="142" cy="{y:.2}" r="5" fill="none" stroke="#666" stroke-width="1.5"/><text x="152" y="{:.2}">wait</text><text x="196" y="{:.2}">{} agents, one colour each</text></g>"##,
            y + 4.0,
            y - 5.0,
            y + 4.0,
            y + 4.0,
            y + 4.0,
            agents.len()
        );
    }
    s.push_str("</svg>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_whole_plan_picture_has_a_route_per_agent() {
        let scene = serde_json::json!({
            "bounds": [0.0, 0.0, 3.0, 1.0],
            "agents": [
                {"radius": 0.4, "start": [0.5, 0.5], "goal": [2.5, 0.5], "path": [[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]]},
                {"radius": 0.4, "start": [2.5, 0.5], "goal": [0.5, 0.5], "path": [[2.5, 0.5]]}
            ]
        });
        let svg = paths_svg(&scene);
        assert_eq!(svg.matches("<polyline").count(), 2);
        // Two discs and the legend's start and wait marks.
        assert_eq!(svg.matches("<circle").count(), 4);
        assert!(svg.contains(">2 agents, one colour each</text>"));
        let waiting = serde_json::json!({
            "bounds": [0.0, 0.0, 3.0, 1.0],
            "agents": [{"radius": 0.4, "start": [0.5, 0.5], "goal": [2.5, 0.5],
                "path": [[0.5, 0.5], [1.5, 0.5], [1.5, 0.5], [1.5, 0.5], [2.5, 0.5]]}]
        });
        assert!(paths_svg(&waiting).contains("<title>agent 0 waits 2 step(s) at t=1</title>"));
        let tree = serde_json::json!({
            "bounds": [0.0, 0.0, 3.0, 1.0],
            "nodes": [[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]],
            "segments": [[[0.5, 0.5], [1.5, 0.5]], [[1.5, 0.5], [2.5, 0.5]]],
            "agents": [{"radius": 0.4, "start": [0.5, 0.5], "goal": [1.5, 0.5], "path": [[0.5, 0.5], [1.5, 0.5]]}]
        });
        // Every node is drawn, the empty ones too (paths ended in mid-air).
        assert_eq!(paths_svg(&tree).matches(r##"fill="#bbb""##).count(), 3);
        // Three robots on one point are three discs at three places.
        let group = serde_json::json!({
            "bounds": [0.0, 0.0, 3.0, 1.0],
            "agents": (0..3).map(|_| serde_json::json!({"radius": 0.2, "start": [1.5, 0.5],
                "goal": [2.5, 0.5], "path": [[1.5, 0.5]]})).collect::<Vec<_>>()
        });
        let svg = frame_svg(&group, 0);
        let centres: std::collections::BTreeSet<String> = svg
            .split("<circle cx=\"")
            .skip(1)
            .filter(|c| !c.contains("fill=\"#666\""))
            .map(|c| c.split("\" r=").next().unwrap().to_string())
            .collect();
        assert_eq!(centres.len(), 3, "{svg}");
        let frame = frame_svg(&scene, 1);
        assert!(frame.contains(">t = 1 of 2</text>"), "{frame}");
        assert!(frame.contains(">2 agents, one colour each</text>"));
    }

    #[test]
    fn a_lifelong_frame_draws_the_goal_in_force_at_its_step() {
        // A 3 x 1 grid; the robot has no task until step 2, then its errand is cell 2.
        let scene = serde_json::json!({
            "bounds": [0.0, 0.0, 3.0, 1.0],
            "cells": {"width": 3, "height": 1, "rows": ["..."]},
            "agents": [{"radius": 0.4, "start": [0.5, 0.5], "goal": [0.5, 0.5],
                "cells": [0, 0, 1, 2], "goals": [[0, -1, -1], [2, 2, 7]]}]
        });
        // The legend draws one goal square of its own.
        let squares = |t| frame_svg(&scene, t).matches("<rect x=").count();
        let before = squares(1);
        assert_eq!(squares(2), before + 1);
        assert!(
            frame_svg(&scene, 3).contains(r#"<rect x="#),
            "a goal is drawn at step 3"
        );
        let at = |t| goal_at(&scene, &scene["agents"][0], Some(t));
        assert_eq!(
            (at(0), at(1), at(2), at(3)),
            (None, None, Some([2.5, 0.5]), Some([2.5, 0.5]))
        );
        assert_eq!(goal_at(&scene, &scene["agents"][0], None), Some([0.5, 0.5]));
    }

    #[test]
    fn a_lifelong_frame_draws_headings_task_ids_and_the_tasks_finished_chart() {
        // A 10 x 5 grid (80 px cells): the robot faces east, then south from step 1; its task
        // 7 is on cell 9 from step 0; 0, 0, 1 tasks finished after steps 0-2.
        let scene = serde_json::json!({
            "bounds": [0.0, 0.0, 10.0, 5.0],
            "cells": {"width": 10, "height": 5, "rows": vec![".........."; 5]},
            "series": {"name": "tasks finished", "values": [0, 0, 1]},
            "agents": [{"radius": 0.4, "start": [0.5, 0.5], "goal": [0.5, 0.5],
                "cells": [0, 0, 10], "goals": [[0, 9, 7], [2, -1, -1]],
                "headings": [[0, 0], [1, 1]]}]
        });
        let tick = |t| {
            let svg = frame_svg(&scene, t);
            let l = svg.split(r##"<line x1=""##).nth(1).unwrap().to_string();
            let n: Vec<f64> = l
                .split('"')
                .filter_map(|x| x.parse().ok())
                .take(4)
                .collect();
            (n[2] - n[0], n[3] - n[1])
        };
        // Disc at (40, 40), radius 32: the tick runs from 0.35 r to 1.15 r along the heading.
        let (dx, dy) = tick(0);
        assert!(
            (dx - 25.6).abs() < 0.1 && dy.abs() < 1e-9,
            "east: {dx} {dy}"
        );
        let (dx, dy) = tick(1);
        assert!(
            dx.abs() < 1e-9 && (dy - 25.6).abs() < 0.1,
            "south: {dx} {dy}"
        );
        assert!(frame_svg(&scene, 1).contains(">task 7</text>"));
        assert!(
            !frame_svg(&scene, 2).contains(">task "),
            "no task at step 2"
        );
        assert!(frame_svg(&scene, 2).contains(">tasks finished: 1 at step 2</text>"));
        assert!(paths_svg(&scene).contains(">tasks finished: 1 after 2 steps</text>"));
        // A scene without headings or series draws neither.
        let plain = serde_json::json!({"bounds": [0.0, 0.0, 10.0, 5.0],
            "agents": [{"radius": 0.4, "start": [0.5, 0.5], "goal": [0.5, 0.5], "path": [[0.5, 0.5]]}]});
        let svg = frame_svg(&plain, 0);
        assert!(
            !svg.contains("<line") && !svg.contains("<polyline"),
            "{svg}"
        );
    }
}
