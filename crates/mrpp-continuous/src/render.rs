//! A picture of a continuous world and plan (like the HBMO paper's Figs. 4 and 12): the obstacles,
//! each robot's start (hollow disc) and goal (cross), its trajectory as a polyline with a dot per
//! step, and the disc at its final position with the robot's number.

use std::fmt::Write as _;

use crate::problem::Trajectories;
use crate::world::World;

const COLOURS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    "#bcbd22", "#7f7f7f",
];

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
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}">"#
    );
    let _ = writeln!(
        s,
        r##"<rect width="{w:.0}" height="{h:.0}" fill="#f7f5ef" stroke="#333" stroke-width="2"/>"##
    );
    for o in &world.obstacles {
        let _ = writeln!(s, r##"<polygon points="{}" fill="#444"/>"##, pts(o));
    }
    for (i, r) in world.robots.iter().enumerate() {
        let c = COLOURS[i % COLOURS.len()];
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
    s.push_str("</svg>\n");
    s
}
