//! A picture of a formation plan (like the GA paper's Figs. 1a and 5): the map's obstacles, the
//! roadmap's corridors (thicker = wider), Q_ini and Q_goal, and each distinct path of the plan
//! in its own colour with the number of robots on it (the line is wider for more robots). Waits
//! (a group that reaches a vertex before the group's event time there, under the timing of
//! [`FormationProblem::schedule`]) are rings in the path's colour on that vertex, wider for longer
//! waits, with the time in the tooltip. A legend band under the map names each mark.

use std::fmt::Write as _;

use mrpp_core::picture::agent_colour;

use crate::polymap::PolygonMap;
use crate::problem::{FormationPlan, FormationProblem};

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
    let (pw, ph) = (w * scale, h * scale);
    // At least as wide as the legend, for tall narrow maps.
    let sw = pw.max(600.0);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{sw:.0}" height="{:.0}" viewBox="0 0 {sw:.0} {:.0}">"#,
        ph + LEGEND_PX,
        ph + LEGEND_PX,
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
            let colour = agent_colour(k);
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="{:.1}" stroke-opacity="0.8"><title>{n} robot(s)</title></polyline>"#,
                poly(&pts),
                2.0 + *n as f64
            );
        }
        // Waits: robots on one path share its schedule, so one robot's is the group's.
        if let Ok(schedule) = p.schedule(&plan.paths) {
            for (k, (path, n)) in distinct.iter().enumerate() {
                let Some(i) = plan.paths.iter().position(|q| q == *path) else {
                    continue;
                };
                let colour = agent_colour(k);
                for (j, leg) in schedule[i].windows(2).enumerate() {
                    let wait = leg[1].0 - leg[0].1;
                    if wait <= 1e-9 {
                        continue;
                    }
                    let v = path[j + 1];
                    let (x, y) = xy(p.roadmap().points[v as usize]);
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{x:.2}" cy="{y:.2}" r="{:.1}" fill="none" stroke="{colour}" stroke-width="2"><title>{n} robot(s) wait {wait:.2} at vertex {v}, from {:.2} to {:.2}</title></circle>"#,
                        7.0 + (wait * scale * 0.05).min(8.0),
                        leg[0].1,
                        leg[1].0
                    );
                }
            }
        }
    }
    for (v, label) in [(p.start(), "Q_ini"), (p.goal(), "Q_goal")] {
        let (x, y) = xy(p.roadmap().points[v as usize]);
        // The label beside the dot, turned inwards near the picture's right and top edges.
        let (tx, anchor) = if x + 70.0 > pw {
            (x - 8.0, "end")
        } else {
            (x + 8.0, "start")
        };
        let ty = if y < 20.0 { y + 20.0 } else { y - 8.0 };
        let _ = writeln!(
            s,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="6" fill="#000"/><text x="{tx:.2}" y="{ty:.2}" text-anchor="{anchor}" font-size="14" font-family="sans-serif">{label}</text>"##
        );
    }
    // Legend band under the map.
    let y = ph + LEGEND_PX / 2.0;
    let _ = writeln!(
        s,
        r##"<g font-family="sans-serif" font-size="11" fill="#333"><rect x="0" y="{ph:.2}" width="{sw:.2}" height="{LEGEND_PX}" fill="#fff"/><circle cx="13" cy="{y:.2}" r="5" fill="#000"/><text x="22" y="{:.2}">Q_ini / Q_goal</text><line x1="112" y1="{y:.2}" x2="134" y2="{y:.2}" stroke="{}" stroke-width="4"/><text x="140" y="{:.2}">a path (wider = more robots)</text><circle cx="318" cy="{y:.2}" r="6" fill="none" stroke="{}" stroke-width="2"/><text x="330" y="{:.2}">wait</text><line x1="372" y1="{y:.2}" x2="394" y2="{y:.2}" stroke="#bbb" stroke-width="3"/><text x="400" y="{:.2}">corridor (wider = more room)</text></g>"##,
        y + 4.0,
        agent_colour(0),
        y + 4.0,
        agent_colour(0),
        y + 4.0,
        y + 4.0,
    );
    s.push_str("</svg>\n");
    s
}

/// Height of the legend band under the map, in pixels.
const LEGEND_PX: f64 = 22.0;

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::cost::CostModel;
    use crate::polymap::Polygon;
    use crate::roadmap::Roadmap;

    #[test]
    fn a_group_that_waits_at_a_merge_gets_a_ring_and_the_legend_names_it() {
        // S=0 splits to A=1 (1 + 1 to M) and B=2 (1.5 + 1.5 to M); both go on M=3 -> G=4. The
        // robot via A reaches M at 2 and waits for the pair via B until 3.
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [0.75, 1.0], [2.0, 0.0], [3.0, 0.0]];
        let segments = [
            (0, 1, 1.5),
            (1, 3, 1.5),
            (0, 2, 1.5),
            (2, 3, 1.5),
            (3, 4, 1.5),
        ];
        let mut r = Roadmap::from_segments(pts, &segments);
        for (e, len) in [(0, 1.0), (1, 1.0), (2, 1.5), (3, 1.5), (4, 1.0)] {
            r.edges[e].length = len;
        }
        let p = FormationProblem::new(Arc::new(r), 3, 0, 4, CostModel::Hard, 0.4).unwrap();
        let plan = FormationPlan {
            paths: vec![vec![0, 1, 3, 4], vec![0, 2, 3, 4], vec![0, 2, 3, 4]],
        };
        let square = |a: f64, b: f64| Polygon {
            vertices: vec![[a, a], [b, a], [b, b], [a, b]],
            line: 1,
        };
        let map = PolygonMap {
            scale: 1.0,
            border: square(-1.0, 4.0),
            obstacles: vec![],
        };
        let svg = render_svg(&map, &p, Some(&plan));
        assert_eq!(svg.matches("wait 1.00 at vertex 3").count(), 1, "{svg}");
        assert!(svg.contains("1 robot(s) wait 1.00 at vertex 3, from 2.00 to 3.00"));
        assert!(svg.contains(">wait</text>") && svg.contains(">Q_ini / Q_goal</text>"));
        // The legend band lies below the map (800 px square here).
        assert!(svg.contains(r#"height="822""#));
    }
}
