//! A picture of a continuous world and plan (like the HBMO paper's Figs. 4 and 12): the obstacles,
//! each robot's start (a filled disc with its number) and goal (a hollow square round its disc
//! there), as on grid pictures; its trajectory as a polyline with a dot per step, and a dashed
//! ring where it ends. A robot that stands still for some steps before its last move gets a solid
//! ring there, wider for longer waits, with the steps in the tooltip. A legend band under the
//! workspace names each mark.

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
        // The goal: a hollow square around the robot's disc there (as on grid pictures).
        let _ = writeln!(
            s,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="{c}" stroke-width="1.5"><title>robot {i}'s goal</title></rect>"##,
            gx - rad,
            gy - rad,
            2.0 * rad,
            2.0 * rad
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
                    r##"<circle cx="{x:.2}" cy="{y:.2}" r="{rad:.2}" fill="none" stroke="{c}" stroke-width="1.5" stroke-dasharray="3 2"><title>robot {i} at the end</title></circle>"##
                );
            }
        }
        // The start: a filled disc with the robot's number (as on grid pictures), drawn last so
        // that no path hides it.
        let _ = writeln!(
            s,
            r##"<circle cx="{sx:.2}" cy="{sy:.2}" r="{rad:.2}" fill="{c}" fill-opacity="0.75" stroke="{c}"><title>robot {i}'s start</title></circle>"##
        );
        let _ = writeln!(
            s,
            r##"<text x="{sx:.2}" y="{:.2}" font-size="{:.1}" text-anchor="middle" font-family="sans-serif" fill="#000">{i}</text>"##,
            sy + rad * 0.4,
            (rad * 1.2).max(8.0)
        );
    }
    // Legend band under the workspace.
    let y = h + LEGEND_PX / 2.0;
    let _ = writeln!(
        s,
        r##"<g font-family="sans-serif" font-size="11" fill="#333" stroke-width="1.5"><rect x="0" y="{h:.2}" width="{w:.2}" height="{LEGEND_PX}" fill="#fff" stroke="none"/><circle cx="13" cy="{y:.2}" r="5" fill="#666" fill-opacity="0.75"/><text x="22" y="{t:.2}">start (id)</text><rect x="78" y="{:.2}" width="10" height="10" fill="none" stroke="#666"/><text x="93" y="{t:.2}">goal</text><line x1="125" y1="{y:.2}" x2="147" y2="{y:.2}" stroke="#666"/><circle cx="136" cy="{y:.2}" r="1.5" fill="#666"/><text x="153" y="{t:.2}">one dot per step</text><circle cx="263" cy="{y:.2}" r="5" fill="none" stroke="#666"/><text x="272" y="{t:.2}">wait</text><circle cx="312" cy="{y:.2}" r="5" fill="none" stroke="#666" stroke-dasharray="3 2"/><text x="321" y="{t:.2}">end</text></g>"##,
        y - 5.0,
        t = y + 4.0,
    );
    s.push_str("</svg>\n");
    s
}

/// Height of the legend band under the workspace, in pixels.
const LEGEND_PX: f64 = 22.0;

#[cfg(test)]
mod tests {
    use super::*;

    /// Start, wait and end are three different marks (issue 30 item 9: start and wait were both
    /// hollow rings, and a filled numbered disc meant the start on grids but the end here).
    #[test]
    fn start_wait_and_end_look_different_and_the_start_is_as_on_grids() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/continuous/six-robots-four-obstacles.json");
        let world = World::load(&path).unwrap();
        let positions: Vec<Vec<[f64; 2]>> = world
            .robots
            .iter()
            .map(|r| vec![r.start, r.start, r.start, r.goal])
            .collect();
        let svg = render_svg(&world, Some(&Trajectories { positions }));
        let mark = |title: &str| {
            let at = svg.find(title).unwrap_or_else(|| panic!("{title} missing"));
            let open = svg[..at].rfind('<').unwrap();
            svg[open..at].to_string()
        };
        let start = mark("<title>robot 0's start</title>");
        let wait = mark("<title>robot 0 waits 2 step(s) from step 0</title>");
        let end = mark("<title>robot 0 at the end</title>");
        let goal = mark("<title>robot 0's goal</title>");
        assert!(
            start.starts_with("<circle") && !start.contains(r#"fill="none""#),
            "{start}"
        );
        assert!(
            wait.contains(r#"fill="none""#) && !wait.contains("dasharray"),
            "{wait}"
        );
        assert!(
            end.contains(r#"fill="none""#) && end.contains("dasharray"),
            "{end}"
        );
        assert!(goal.starts_with("<rect"), "{goal}");
        for legend in [
            ">start (id)</text>",
            ">goal</text>",
            ">wait</text>",
            ">end</text>",
        ] {
            assert!(svg.contains(legend), "{legend}");
        }
        // Without a plan the starts still carry their numbers.
        let bare = render_svg(&world, None);
        assert!(bare.contains("robot 5's start") && bare.contains(">5</text>"));
    }
}
