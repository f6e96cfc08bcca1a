//! A static SVG picture of a grid instance and (optionally) its plan, for a person to look at.
//!
//! Walls are dark, free cells light with thin grid lines when cells are large enough to see them.
//! Each agent gets its own colour from a golden-angle hue wheel (neighbouring ids get far-apart
//! hues); its start is a filled circle (with its id when there is room), its goal a square outline
//! in the same colour, and its path a polyline through cell centres. Polylines are shifted a little
//! per agent (diagonally, so both horizontal and vertical overlaps separate) to keep paths that
//! share cells visible side by side.
//!
//! Waits are rings in the agent's colour on the cell where it waits (thicker for longer waits;
//! its hover title gives the steps), before its last arrival. A band under the map is the legend:
//! start, goal, wait.
//!
//! The SVG is written by hand (no extra crate): the output is small and the elements few.

use std::fmt::Write as _;

use crate::map::GridMap;
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::Plan;
use mrpp_core::picture::{agent_colour, wait_runs};

/// Cell size in pixels for maps small enough to afford it.
pub const CELL_PX: f64 = 16.0;
/// Largest width or height of the picture; bigger maps get smaller cells.
pub const MAX_SIDE_PX: f64 = 2000.0;

const WALL: &str = "#2f3136";
const FREE: &str = "#f3f1ea";
const GRID_LINE: &str = "#d9d6cc";

/// Renders the map, the agents' starts and goals, and the plan's paths (when given) as SVG text.
pub fn render_svg(map: &GridMap, inst: &Instance, plan: Option<&Plan>) -> String {
    let (w, h) = (map.width(), map.height());
    let cs = cell_size(w, h);
    let (pw, ph) = (w as f64 * cs, h as f64 * cs);
    let n = inst.num_agents();
    let band = LEGEND_PX;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}">"#,
        num(pw),
        num(ph + band),
        num(pw),
        num(ph + band)
    );
    let _ = writeln!(
        s,
        "<title>mrpp: {w}x{h} map, {n} agents{}</title>",
        if plan.is_some() { ", with plan" } else { "" }
    );

    // Map: one light background, grid lines, then each horizontal run of walls as one rectangle
    // over them (keeps big maps' files small and avoids hairline seams between wall cells).
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="{}" height="{}" fill="{FREE}"/>"#,
        num(pw),
        num(ph)
    );
    if cs >= 6.0 {
        let mut d = String::new();
        for x in 1..w {
            let _ = write!(d, "M{} 0V{}", num(x as f64 * cs), num(ph));
        }
        for y in 1..h {
            let _ = write!(d, "M0 {}H{}", num(y as f64 * cs), num(pw));
        }
        if !d.is_empty() {
            let _ = writeln!(
                s,
                r#"<path d="{d}" stroke="{GRID_LINE}" stroke-width="0.5" fill="none"/>"#
            );
        }
    }

    let _ = writeln!(s, r#"<g fill="{WALL}" shape-rendering="crispEdges">"#);
    for y in 0..h {
        let mut x = 0;
        while x < w {
            if map.is_free(x, y) {
                x += 1;
                continue;
            }
            let x0 = x;
            while x < w && !map.is_free(x, y) {
                x += 1;
            }
            let _ = writeln!(
                s,
                r#"<rect x="{}" y="{}" width="{}" height="{}"/>"#,
                num(x0 as f64 * cs),
                num(y as f64 * cs),
                num((x - x0) as f64 * cs),
                num(cs)
            );
        }
    }
    s.push_str("</g>\n");
    let centre = |v: VertexId| {
        let (x, y) = map.cell(v);
        ((x as f64 + 0.5) * cs, (y as f64 + 0.5) * cs)
    };
    let stroke = (cs * 0.14).max(0.6);

    // Paths under the markers, so starts and goals stay readable where paths cross them.
    if let Some(plan) = plan {
        let _ = writeln!(
            s,
            r#"<g fill="none" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round" stroke-opacity="0.85">"#,
            num(stroke)
        );
        for (i, p) in plan.paths.iter().enumerate() {
            let off = path_offset(i) * cs;
            let mut pts = String::new();
            let mut last = None;
            for &v in p {
                if last == Some(v) {
                    continue; // a wait adds no point
                }
                last = Some(v);
                let (cx, cy) = centre(v);
                if !pts.is_empty() {
                    pts.push(' ');
                }
                let _ = write!(pts, "{},{}", num(cx + off), num(cy + off));
            }
            let _ = writeln!(
                s,
                r#"<polyline stroke="{}" points="{pts}"><title>agent {i}: {} steps</title></polyline>"#,
                agent_colour(i),
                p.len().saturating_sub(1)
            );
        }
        s.push_str("</g>\n");
    }

    // Waits: a ring where an agent stands still, before its last arrival.
    if let Some(plan) = plan {
        let _ = writeln!(s, r#"<g fill="none">"#);
        for (i, p) in plan.paths.iter().enumerate() {
            for (from, steps) in wait_runs(p) {
                let (cx, cy) = centre(p[from]);
                let _ = writeln!(
                    s,
                    r#"<circle cx="{}" cy="{}" r="{}" stroke="{}" stroke-width="{}"><title>agent {i} waits {steps} step(s) at t={}</title></circle>"#,
                    num(cx),
                    num(cy),
                    num(cs * 0.42),
                    agent_colour(i),
                    num((stroke * (1.0 + (steps as f64).ln())).min(cs * 0.2)),
                    from
                );
            }
        }
        s.push_str("</g>\n");
    }

    // Goals: square outlines.
    let side = cs * 0.72;
    let _ = writeln!(s, r#"<g fill="none" stroke-width="{}">"#, num(stroke));
    for (i, &g) in inst.goals.iter().enumerate() {
        let (cx, cy) = centre(g);
        let _ = writeln!(
            s,
            r#"<rect x="{}" y="{}" width="{}" height="{}" stroke="{}"><title>agent {i} goal</title></rect>"#,
            num(cx - side / 2.0),
            num(cy - side / 2.0),
            num(side),
            num(side),
            agent_colour(i)
        );
    }
    s.push_str("</g>\n");

    // Starts: filled circles, numbered when the cells are big enough for a legible digit.
    let r = cs * 0.32;
    let _ = writeln!(
        s,
        r#"<g stroke="{FREE}" stroke-width="{}">"#,
        num((cs * 0.04).max(0.3))
    );
    for (i, &v) in inst.starts.iter().enumerate() {
        let (cx, cy) = centre(v);
        let _ = writeln!(
            s,
            r#"<circle cx="{}" cy="{}" r="{}" fill="{}"><title>agent {i} start</title></circle>"#,
            num(cx),
            num(cy),
            num(r),
            agent_colour(i)
        );
    }
    s.push_str("</g>\n");
    if cs >= 12.0 {
        let digits = n.saturating_sub(1).to_string().len().max(1) as f64;
        let font = (cs * 0.42).min(cs * 0.9 / digits);
        let _ = writeln!(
            s,
            r#"<g fill="white" font-family="sans-serif" font-weight="bold" font-size="{}" text-anchor="middle">"#,
            num(font)
        );
        for (i, &v) in inst.starts.iter().enumerate() {
            let (cx, cy) = centre(v);
            // Baseline a third of the font size below the centre: vertically centred digits
            // without relying on `dominant-baseline`, which some renderers ignore.
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}">{i}</text>"#,
                num(cx),
                num(cy + font * 0.35)
            );
        }
        s.push_str("</g>\n");
    }
    // Legend band under the map.
    let (lx, ly, lr) = (8.0, ph + band / 2.0, 5.0);
    let _ = writeln!(
        s,
        r##"<g font-family="sans-serif" font-size="11" fill="#333"><rect x="0" y="{}" width="{}" height="{}" fill="#fff"/><circle cx="{}" cy="{}" r="{lr}" fill="#666"/><text x="{}" y="{}">start (id)</text><rect x="{}" y="{}" width="10" height="10" fill="none" stroke="#666" stroke-width="1.5"/><text x="{}" y="{}">goal</text><circle cx="{}" cy="{}" r="{lr}" fill="none" stroke="#666" stroke-width="1.5"/><text x="{}" y="{}">wait</text><text x="{}" y="{}">{n} agents, one colour each</text></g>"##,
        num(ph),
        num(pw),
        num(band),
        num(lx + lr),
        num(ly),
        num(lx + 14.0),
        num(ly + 4.0),
        num(lx + 80.0),
        num(ly - 5.0),
        num(lx + 96.0),
        num(ly + 4.0),
        num(lx + 140.0 + lr),
        num(ly),
        num(lx + 154.0),
        num(ly + 4.0),
        num(lx + 200.0),
        num(ly + 4.0)
    );
    s.push_str("</svg>\n");
    s
}

/// Height of the legend band under the map, in pixels.
const LEGEND_PX: f64 = 22.0;

/// Cell size: [`CELL_PX`], scaled down so neither side exceeds [`MAX_SIDE_PX`].
fn cell_size(w: u32, h: u32) -> f64 {
    let side = w.max(h).max(1) as f64;
    CELL_PX.min(MAX_SIDE_PX / side)
}

/// Offset of agent `i`'s polyline, as a fraction of the cell size: five lanes in
/// `-0.2..=0.2`, so paths sharing a corridor run side by side and stay inside their cells.
fn path_offset(i: usize) -> f64 {
    ((i % 5) as f64 - 2.0) * 0.1
}

/// A coordinate with at most two decimals and no trailing zeros (`12`, `12.5`, `0.33`).
fn num(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use mrpp_core::{MapfProblem, Problem as _, Rules};

    /// A 10x7 room with a pillar and a wall stub; four agents, two of which share a corridor.
    const ROOM: &str = "##########\n\
                        #        #\n\
                        #  ##    #\n\
                        #  ##  # #\n\
                        #      # #\n\
                        #        #\n\
                        ##########\n";

    fn demo() -> (GridMap, Instance, Plan) {
        let m = GridMap::parse(ROOM, Path::new("room.map")).unwrap().0;
        let cells = |cs: &[(i64, i64)]| -> Vec<VertexId> {
            cs.iter()
                .map(|&(x, y)| m.vertex_at(x, y).unwrap())
                .collect()
        };
        let row = |y: i64, xs: std::ops::RangeInclusive<i64>| xs.map(move |x| (x, y));
        let mut p0: Vec<_> = row(1, 1..=8).collect();
        p0.extend((2..=5).map(|y| (8, y)));
        let mut p1: Vec<_> = row(5, 1..=6).collect();
        p1.extend((1..=4).rev().map(|y| (6, y)));
        let p2 = vec![(5, 3), (5, 4), (4, 4), (3, 4), (2, 4), (2, 3), (1, 3)];
        let mut p3 = vec![(2, 2), (2, 2), (2, 2)];
        p3.extend(row(1, 2..=7));
        p3.push((7, 2));
        let paths = [p0, p1, p2, p3];
        let inst = Instance::new(
            paths.iter().map(|p| cells(&p[..1])[0]).collect(),
            paths.iter().map(|p| cells(&p[p.len() - 1..])[0]).collect(),
        )
        .unwrap();
        let plan = Plan::new(paths.iter().map(|p| cells(p)).collect());
        MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        (m, inst, plan)
    }

    /// Checks that every element opened is closed in order (enough to catch broken output).
    fn assert_balanced(svg: &str) {
        let mut stack: Vec<&str> = Vec::new();
        let mut rest = svg;
        while let Some(i) = rest.find('<') {
            let end = rest[i..].find('>').expect("unclosed tag") + i;
            let tag = &rest[i + 1..end];
            if let Some(name) = tag.strip_prefix('/') {
                assert_eq!(stack.pop(), Some(name), "mismatched </{name}>");
            } else if !tag.ends_with('/') {
                stack.push(tag.split_whitespace().next().unwrap());
            }
            rest = &rest[end + 1..];
        }
        assert!(stack.is_empty(), "unclosed {stack:?}");
    }

    #[test]
    fn svg_is_well_formed_with_one_polyline_per_agent() {
        let (m, inst, plan) = demo();
        let svg = render_svg(&m, &inst, Some(&plan));
        assert!(svg.starts_with("<svg "), "{svg}");
        assert!(svg.trim_end().ends_with("</svg>"));
        assert_balanced(&svg);
        assert_eq!(svg.matches("<polyline ").count(), 4);
        assert_eq!(svg.matches(" start</title>").count(), 4);
        // One ring per run of waits before an agent's last arrival, and the legend.
        let runs: usize = plan
            .paths
            .iter()
            .zip(&inst.goals)
            .map(|(p, &g)| {
                let end = p.iter().rposition(|&v| v != g).map_or(0, |k| k + 1);
                (1..end)
                    .filter(|&k| p[k] == p[k - 1] && (k < 2 || p[k - 1] != p[k - 2]))
                    .count()
            })
            .sum();
        assert_eq!(svg.matches(" step(s) at t=").count(), runs);
        assert!(
            svg.contains(">start (id)</text>")
                && svg.contains(">goal</text>")
                && svg.contains(">wait</text>")
        );
        assert!(
            svg.contains(r#"width="160" height="134""#),
            "16 px cells and the legend"
        );
        // Agent 0's polyline: offset -0.2 cells = -3.2 px, waits dropped, 12 points.
        let line = svg.lines().find(|l| l.contains("agent 0:")).unwrap();
        assert!(line.contains(r#"points="20.8,20.8 36.8,20.8 "#), "{line}");
        let points = line
            .split("points=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        assert_eq!(points.split(' ').count(), 12, "{points}");

        let bare = render_svg(&m, &inst, None);
        assert_balanced(&bare);
        assert_eq!(bare.matches("<polyline").count(), 0);
        assert_eq!(bare.matches(" start</title>").count(), 4);
        assert_eq!(bare.matches(" step(s) at t=").count(), 0);
    }

    #[test]
    fn big_maps_are_scaled_down() {
        let row = ".".repeat(500);
        let text = format!(
            "type octile\nheight 300\nwidth 500\nmap\n{}",
            format!("{row}\n").repeat(300)
        );
        let m = GridMap::parse(&text, Path::new("big.map")).unwrap().0;
        let inst = Instance::new(vec![0], vec![1]).unwrap();
        let svg = render_svg(&m, &inst, Some(&Plan::new(vec![vec![0, 1]])));
        assert!(
            svg.contains(r#"width="2000" height="1222""#),
            "{}",
            &svg[..200]
        );
        assert!(
            !svg.contains(r#"font-weight="bold""#),
            "no labels on 4 px cells"
        );
        assert_balanced(&svg);
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(3.0), "3");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(20.8), "20.8");
    }

    /// Writes the demo picture when `MRPP_RENDER_DEMO` names an output file, so a person can look
    /// at it (e.g. `rsvg-convert -o demo.png demo.svg`); does nothing otherwise.
    #[test]
    fn demo_picture_on_request() {
        if let Some(out) = std::env::var_os("MRPP_RENDER_DEMO") {
            let (m, inst, plan) = demo();
            std::fs::write(out, render_svg(&m, &inst, Some(&plan))).unwrap();
        }
    }
}
