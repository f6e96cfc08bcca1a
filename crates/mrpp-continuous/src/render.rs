//! A picture of a continuous world and plan (like the HBMO paper's Figs. 4 and 12): the obstacles,
//! each robot's start (hollow disc) and goal (cross), its trajectory as a polyline with a dot per
//! step, and the disc at its final position with the robot's number. A robot that stands still
//! for some steps before its last move gets a ring there, wider for longer waits, with the steps
//! in the tooltip. A legend band under the workspace names each mark.

use std::fmt::Write as _;

use mrpp_core::picture::{agent_colour, wait_runs};

use crate::problem::Trajectories;
use crate::world::World;

/// SVG text of the world and (when given) the trajectories.
pub fn render_svg(world: &World, plan: Option<&Trajectories>) -> String {
    let [x0, y0, x1, y1] = world.workspace;
    let scale = 800.0 / (x1 - x0).max(y1 - y0).max(1e-9);
    let (w, h) = ((x1 - x0) * scale, (y1 - y0) * scale);
    let xy = |q: [f64; 2]| ((q[0] - x0) * scale, (y1 - q[1]) * scale);
    let pts = |vs: &[[f64; 2]]| {
        vs.iter()
            .map(|&q| {
                let (x, y) = xy(q);
                format!("{x:.2},{y:.2}")
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{:.0}" viewBox="0 0 {w:.0} {:.0}">"#,
        h + LEGEND_PX,
        h + LEGEND_PX
    );
    let _ = writeln!(
        s,
        r##"<rect width="{w:.0}" height="{h:.0}" fill="#f7f5ef" stroke="#333" stroke-width="2"/>"##
    );
    for o in &world.obstacles {
        let _ = writeln!(s, r##"<polygon points="{}" fill="#444"/>"##, pts(o));
    }
    for (i, r) in world.robots.iter().enumerate() {
        let c = agent_colour(i);
        let rad = r.radius * scale;
        let (sx, sy) = xy(r.start);
        let (gx, gy) = xy(r.goal);
        let _ = writeln!(
            s,
            r##"<circle cx="{sx:.2}" cy="{sy:.2}" r="{rad:.2}" fill="none" stroke="{c}" stroke-width="1.5"/>"##
        );
        let _ = writeln!(
            s,
            r##"<path d="M{:.2},{:.2} L{:.2},{:.2} M{:.2},{:.2} L{:.2},{:.2}" stroke="{c}" stroke-width="2"/>"##,
            gx - rad,
            gy - rad,
            gx + rad,
            gy + rad,
            gx - rad,
            gy + rad,
            gx + rad,
            gy - rad
        );
        if let Some(path) = plan.and_then(|p| p.positions.get(i)) {
            let _ = writeln!(
                s,
                r##"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.5" stroke-opacity="0.8"/>"##,
                pts(path)
            );
            for &q in path.iter() {
                let (x, y) = xy(q);
                let _ = writeln!(
                    s,
                    r##"<circle cx="{x:.2}" cy="{y:.2}" r="1.5" fill="{c}"/>"##
                );
            }
            for (from, steps) in wait_runs(path) {
                let (x, y) = xy(path[from]);
                let _ = writeln!(
                    s,
                    r##"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="none" stroke="{c}" stroke-width="1.5"><title>robot {i} waits {steps} step(s) from step {from}</title></circle>"##,
                    rad * 0.5 + (steps as f64).min(8.0)
                );
            }
            if let Some(&end) = path.last() {
                let (x, y) = xy(end);
                let _ = writeln!(
                    s,
                    r##"<circle cx="{x:.2}" cy="{y:.2}" r="{rad:.2}" fill="{c}" fill-opacity="0.6" stroke="{c}"/>"##
                );
                let _ = writeln!(
                    s,
                    r##"<text x="{x:.2}" y="{:.2}" font-size="{:.1}" text-anchor="middle" font-family="sans-serif" fill="#000">{i}</text>"##,
                    y + rad * 0.4,
                    (rad * 1.2).max(8.0)
                );
            }
        } else {
            let _ = writeln!(
                s,
                r##"<text x="{sx:.2}" y="{:.2}" font-size="{:.1}" text-anchor="middle" font-family="sans-serif" fill="{c}">{i}</text>"##,
                sy - rad - 2.0,
                (rad * 1.2).max(8.0)
            );
        }
    }
    // Legend band under the workspace.
    let y = h + LEGEND_PX / 2.0;
    let _ = writeln!(
        s,
        r##"<g font-family="sans-serif" font-size="11" fill="#333" stroke-width="1.5"><rect x="0" y="{h:.2}" width="{w:.2}" height="{LEGEND_PX}" fill="#fff" stroke="none"/><circle cx="13" cy="{y:.2}" r="5" fill="none" stroke="#666"/><text x="22" y="{:.2}">start</text><path d="M55,{:.2} L63,{:.2} M55,{:.2} L63,{:.2}" stroke="#666"/><text x="68" y="{:.2}">goal</text><line x1="100" y1="{y:.2}" x2="122" y2="{y:.2}" stroke="#666"/><circle cx="111" cy="{y:.2}" r="1.5" fill="#666"/><text x="128" y="{:.2}">one dot per step</text><circle cx="238" cy="{y:.2}" r="5" fill="#666" fill-opacity="0.6"/><text x="247" y="{:.2}">end (id)</text><circle cx="310" cy="{y:.2}" r="5" fill="none" stroke="#666"/><text x="319" y="{:.2}">wait</text></g>"##,
        y + 4.0,
        y - 4.0,
        y + 4.0,
        y + 4.0,
        y - 4.0,
        y + 4.0,
        y + 4.0,
        y + 4.0,
        y + 4.0,
    );
    s.push_str("</svg>\n");
    s
}

/// Height of the legend band under the workspace, in pixels.
const LEGEND_PX: f64 = 22.0;
