//! Issue 27, item 2: the grid readers agree, and no planner ever sees an instance its validator
//! would refuse at t = 0.
//!
//! Random small maps and random agent lists (cells off the map, on walls, shared starts, shared
//! goals included) are written in the three formats mrpp reads grid agents from: a MovingAI
//! `.scen`, an H* robot file (`x,y;x,y`) and a League of Robot Runners problem (agents file, task
//! file of single errands). Properties:
//!
//! 1. The `.scen` and robot-file readers accept exactly the same lists, giving the same instance,
//!    and refuse the others naming the same line; the LoRR reader agrees with them whenever its own
//!    rules do not differ (every cell on the map and distinct goals: LoRR passes over a task whose
//!    first errand is already a goal instead of refusing it).
//! 2. Every accepted instance obeys the instance rules (`Problem::instance_rules`), and every
//!    registered grid planner, run through `mrpp_core::solve` under a tiny time limit (debug builds
//!    assert the rules at its entry), returns a valid plan or an honest "not solved", never an
//!    invalid plan.

use std::path::{Path, PathBuf};
use std::time::Duration;

use mrpp_core::{Ctx, Deadline, Problem as _, Unsolved, solve};
use mrpp_grid::{GridMap, PLANNERS, lorr, scen};
use proptest::prelude::*;

/// A random case: free cells (`true`) by row, and `(start, goal)` cells per agent, some off the
/// map by one cell.
#[derive(Debug, Clone)]
struct Case {
    rows: Vec<Vec<bool>>,
    agents: Vec<((i64, i64), (i64, i64))>,
}

fn case() -> impl Strategy<Value = Case> {
    (3usize..=6, 3usize..=6).prop_flat_map(|(w, h)| {
        let cell = (0..=w as i64, 0..=h as i64 - 1);
        (
            prop::collection::vec(prop::collection::vec(prop::bool::weighted(0.8), w), h),
            prop::collection::vec((cell.clone(), cell), 1..=4),
        )
            .prop_map(|(rows, agents)| Case { rows, agents })
    })
}

impl Case {
    fn width(&self) -> i64 {
        self.rows[0].len() as i64
    }
    fn map_text(&self) -> String {
        let mut t = format!(
            "type octile\nheight {}\nwidth {}\nmap\n",
            self.rows.len(),
            self.width()
        );
        for r in &self.rows {
            t.extend(r.iter().map(|&f| if f { '.' } else { '@' }));
            t.push('\n');
        }
        t
    }
    fn scen_text(&self) -> String {
        let (w, h) = (self.width(), self.rows.len());
        let mut t = "version 1\n".to_string();
        for ((sx, sy), (gx, gy)) in &self.agents {
            t += &format!("0\tm.map\t{w}\t{h}\t{sx}\t{sy}\t{gx}\t{gy}\t1\n");
        }
        t
    }
    fn robot_text(&self) -> String {
        self.agents
            .iter()
            .map(|((sx, sy), (gx, gy))| format!("{sx},{sy};{gx},{gy}\n"))
            .collect()
    }
    /// Whether every cell is on the map and the goals are distinct (where LoRR's rules and the
    /// other readers' coincide).
    fn lorr_comparable(&self) -> bool {
        let on = |&(x, y): &(i64, i64)| x < self.width() && y < self.rows.len() as i64;
        let mut goals: Vec<_> = self.agents.iter().map(|a| a.1).collect();
        goals.sort_unstable();
        goals.dedup();
        goals.len() == self.agents.len() && self.agents.iter().all(|(s, g)| on(s) && on(g))
    }
    /// The LoRR problem's files: `(problem JSON, read)`.
    fn lorr_files(&self) -> (String, impl Fn(&Path) -> mrpp_core::Result<String>) {
        let w = self.width();
        let loc = |(x, y): (i64, i64)| y * w + x;
        let agents = format!(
            "{}\n{}",
            self.agents.len(),
            self.agents
                .iter()
                .map(|a| format!("{}\n", loc(a.0)))
                .collect::<String>()
        );
        let tasks = format!(
            "{}\n{}",
            self.agents.len(),
            self.agents
                .iter()
                .map(|a| format!("{}\n", loc(a.1)))
                .collect::<String>()
        );
        let map = self.map_text();
        let json = format!(
            r#"{{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": {}}}"#,
            self.agents.len()
        );
        let read = move |p: &Path| -> mrpp_core::Result<String> {
            Ok(match p.file_name().and_then(|n| n.to_str()) {
                Some("m.map") => map.clone(),
                Some("a.agents") => agents.clone(),
                _ => tasks.clone(),
            })
        };
        (json, read)
    }
}

/// The line number of a reader's error (`file:line: ...`), if it names one.
fn line_of(err: &str) -> Option<usize> {
    err.split(':').nth(1)?.trim().parse().ok()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn readers_agree_and_planners_only_see_valid_instances(c in case()) {
        let (map, _) = GridMap::parse(&c.map_text(), Path::new("m.map")).unwrap();
        let from_scen = scen::parse_agents(&c.scen_text(), Path::new("a.scen"), &map, None)
            .map_err(|e| e.to_string());
        let from_robots = scen::parse_agents(&c.robot_text(), Path::new("a.txt"), &map, None)
            .map_err(|e| e.to_string());
        match (&from_scen, &from_robots) {
            (Ok(a), Ok(b)) => prop_assert_eq!(a, b),
            (Err(a), Err(b)) => {
                // The scen file's agents start on line 2 (after `version 1`).
                prop_assert_eq!(line_of(a).map(|l| l - 1), line_of(b), "{} / {}", a, b);
            }
            _ => prop_assert!(false, "readers disagree: {:?} / {:?}", from_scen, from_robots),
        }
        if c.lorr_comparable() {
            let (json, read) = c.lorr_files();
            let from_lorr = lorr::parse_with(&json, &PathBuf::from("p.json"), &read)
                .map(|p| p.instance)
                .map_err(|e| e.to_string());
            prop_assert_eq!(
                from_lorr.is_ok(),
                from_scen.is_ok(),
                "LoRR {:?} / scen {:?}",
                from_lorr,
                from_scen
            );
            if let (Ok(a), Ok(b)) = (&from_lorr, &from_scen) {
                prop_assert_eq!(a, b);
            }
        }
        let Ok(inst) = from_scen else {
            return Ok(());
        };
        let problem = mrpp_grid::problem_on(&map, inst);
        prop_assert_eq!(problem.instance_rules(), Ok(()));
        for entry in PLANNERS {
            let planner = entry.instantiate(&[]).unwrap();
            let ctx = Ctx::new(1, Deadline::after(Duration::from_millis(30)));
            match solve(planner.as_ref(), &problem, &ctx) {
                Ok(_)
                | Err(
                    Unsolved::TimeLimit
                    | Unsolved::MemoryLimit
                    | Unsolved::Interrupted
                    | Unsolved::GaveUp(_),
                ) => {}
                Err(Unsolved::Invalid(why)) => {
                    prop_assert!(false, "{} returned an invalid plan: {}", entry.name, why)
                }
            }
        }
    }
}
