//! A picture of a formation plan (like the GA paper's Figs. 1a and 5): the map's obstacles, the
//! roadmap's corridors (thicker = wider), Q_ini and Q_goal, and each distinct path of the plan
//! in its own colour with the number of robots on it.

use std::fmt::Write as _;

use crate::polymap::PolygonMap;
use crate::problem::{FormationPlan, FormationProblem};

const COLOURS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// SVG text of the map, the roadmap and (when given) the plan's paths.
pub fn render_svg(map: &PolygonMap, p: &FormationProblem, plan: Option<&FormationPlan>) -> String {
    let (lo, hi) = map.bounds();
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    let scale = 800.0 / w.max(h).max(1e-9);
    // y grows downwards in SVG: flip.
    let xy = |q: [f64; 2]| ((q[0] - lo[0]) * scale, (hi[1] - q[1]) * scale);
    let poly = |vs: &[[f64; 2]]| {
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
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {:.0} {:.0}">"#,
        w * scale,
        h * scale,
        w * scale,
        h * scale
    );
    let _ = writeln!(
        s,
        r##"<polygon points="{}" fill="#f7f5ef" stroke="#333" stroke-width="2"/>"##,
        poly(&map.border.vertices)
    );
    for o in &map.obstacles {
        let _ = writeln!(
            s,
            r##"<polygon points="{}" fill="#555"/>"##,
            poly(&o.vertices)
        );
    }
    for e in &p.roadmap().edges {
        let width = (e.width() * scale * 0.15).clamp(0.5, 4.0);
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#bbb" stroke-width="{width:.2}"/>"##,
            poly(&e.polyline)
        );
    }
    if let Some(plan) = plan {
        let mut distinct: Vec<(&Vec<u32>, usize)> = Vec::new();
        for q in &plan.paths {
            match distinct.iter_mut().find(|(d, _)| *d == q) {
                Some(d) => d.1 += 1,
                None => distinct.push((q, 1)),
            }
        }
        for (k, (path, n)) in distinct.iter().enumerate() {
            let mut pts = Vec::new();
            for w in path.windows(2) {
                let Some(e) = p.roadmap().edge_between(w[0], w[1]) else {
                    continue;
                };
                let mut line = p.roadmap().edges[e as usize].polyline.clone();
                if p.roadmap().edges[e as usize].u != w[0] {
                    line.reverse();
                }
                pts.extend(line);
            }
            let colour = COLOURS[k % COLOURS.len()];
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="{:.1}" stroke-opacity="0.8"><title>{n} robot(s)</title></polyline>"#,
                poly(&pts),
                2.0 + *n as f64
            );
        }
    }
    for (v, label) in [(p.start(), "Q_ini"), (p.goal(), "Q_goal")] {
        let (x, y) = xy(p.roadmap().points[v as usize]);
        let _ = writeln!(
            s,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="6" fill="#000"/><text x="{:.2}" y="{:.2}" font-size="14" font-family="sans-serif">{label}</text>"##,
            x + 8.0,
            y - 8.0
        );
    }
    s.push_str("</svg>\n");
    s
}
