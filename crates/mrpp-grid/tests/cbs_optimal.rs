//! CBS and EECBS against brute force on 120 seeded tiny random grids: whenever CBS or EECBS(w = 1)
//! (each with disjoint and with standard splitting for CBS) returns, its sum of costs equals that of an exhaustive search over joint configurations;
//! EECBS(1.5) stays within 1.5 times it; every plan passes the validator (`solve`); and CBS and
//! EECBS(1) each solve at least 90 % of the solvable cases within 0.5 s.
//!
//! The brute force is independent of the planners: Dijkstra over (configuration, set of agents that
//! have stopped for good). Each step, every agent that has not stopped moves or waits (no two on a
//! vertex, no swaps; stopped agents stay on their goals) and pays 1; an agent on its goal may stop.
//! An agent's cost is then the step from which it stays on its goal, the validator's definition.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::time::Duration;

use mrpp_core::{Ctx, Deadline, Graph, Instance, MapfProblem, Rules, Unsolved, VertexId, solve};
use mrpp_grid::GridMap;
use mrpp_grid::cbs::Cbs;
use rand::seq::IndexedRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Every joint move of the not-stopped agents from `config`.
fn successors(g: &Graph, config: &[VertexId], stopped: u32) -> Vec<Vec<VertexId>> {
    let mut out = vec![Vec::new()];
    for (i, &v) in config.iter().enumerate() {
        let options: Vec<VertexId> = if stopped & (1 << i) != 0 {
            vec![v]
        } else {
            std::iter::once(v)
                .chain(g.neighbors(v).iter().copied())
                .collect()
        };
        out = out
            .into_iter()
            .flat_map(|prefix: Vec<VertexId>| {
                options.iter().map(move |&w| {
                    let mut p = prefix.clone();
                    p.push(w);
                    p
                })
            })
            .collect();
    }
    out.retain(|next| {
        let n = next.len();
        (0..n).all(|a| {
            (a + 1..n)
                .all(|b| next[a] != next[b] && !(next[a] == config[b] && next[b] == config[a]))
        })
    });
    out
}

/// The optimal sum of costs, or `None` when no plan exists.
fn brute_force(g: &Graph, inst: &Instance) -> Option<u64> {
    let n = inst.num_agents();
    let all = (1u32 << n) - 1;
    let on_goal = |c: &[VertexId]| -> u32 {
        (0..n)
            .filter(|&i| c[i] == inst.goals[i])
            .fold(0, |m, i| m | (1 << i))
    };
    let mut best: HashMap<(Vec<VertexId>, u32), u64> = HashMap::new();
    let mut heap = BinaryHeap::new();
    // Any subset of the agents already on their goals may stop at time 0.
    let at_goal = on_goal(&inst.starts);
    let mut sub = at_goal;
    loop {
        heap.push(Reverse((0u64, inst.starts.clone(), sub)));
        best.insert((inst.starts.clone(), sub), 0);
        if sub == 0 {
            break;
        }
        sub = (sub - 1) & at_goal;
    }
    while let Some(Reverse((d, config, stopped))) = heap.pop() {
        if stopped == all {
            return Some(d);
        }
        if best.get(&(config.clone(), stopped)).is_some_and(|&b| b < d) {
            continue;
        }
        let step = u64::from(n as u32 - stopped.count_ones());
        for next in successors(g, &config, stopped) {
            let may_stop = on_goal(&next) & !stopped;
            let mut sub = may_stop;
            loop {
                let key = (next.clone(), stopped | sub);
                let nd = d + step;
                if best.get(&key).is_none_or(|&b| nd < b) {
                    best.insert(key.clone(), nd);
                    heap.push(Reverse((nd, key.0, key.1)));
                }
                if sub == 0 {
                    break;
                }
                sub = (sub - 1) & may_stop;
            }
        }
    }
    None
}

/// Per-call limit: CBS is exponential in corridors (one 8-cell case of the random draw needs
/// 135 000 constraint-tree nodes), so a run that hits it is counted, not failed.
fn ctx() -> Ctx {
    Ctx::new(0, Deadline::after(Duration::from_millis(500)))
}

/// A random instance: a grid of width and height 2..=4 with 20 % walls, 1..=3 agents.
fn draw(rng: &mut ChaCha8Rng) -> Option<(GridMap, Instance)> {
    let (w, h) = (rng.random_range(2..=4usize), rng.random_range(2..=4usize));
    let rows: Vec<Vec<bool>> = (0..h)
        .map(|_| (0..w).map(|_| rng.random_bool(0.8)).collect())
        .collect();
    let map = GridMap::from_free_rows(&rows);
    let cells: Vec<VertexId> = (0..map.graph().num_vertices() as VertexId).collect();
    let agents = rng.random_range(1..=3usize);
    if cells.len() < agents {
        return None;
    }
    let starts: Vec<VertexId> = cells.sample(rng, agents).copied().collect();
    let goals: Vec<VertexId> = cells.sample(rng, agents).copied().collect();
    Some((map, Instance::new(starts, goals).unwrap()))
}

#[test]
fn cbs_and_eecbs_match_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(20_261_130);
    let (mut solvable, mut cbs_solved, mut e1_solved) = (0, 0, 0);
    for case in 0..120 {
        let Some((map, inst)) = draw(&mut rng) else {
            continue;
        };
        let g = map.graph();
        let Some(optimum) = brute_force(g, &inst) else {
            continue;
        };
        solvable += 1;
        let problem = MapfProblem::on(g, &inst, Rules::default());
        let mut costs = Vec::new();
        let standard = Cbs::new(mrpp_grid::cbs::Settings {
            disjoint: false,
            ..Cbs::optimal().settings
        });
        let plain = Cbs::new(mrpp_grid::cbs::Settings {
            heuristic: mrpp_grid::cbs::Heuristic::None,
            ..Cbs::optimal().settings
        });
        let cg = Cbs::new(mrpp_grid::cbs::Settings {
            heuristic: mrpp_grid::cbs::Heuristic::Cg,
            ..Cbs::optimal().settings
        });
        let wdg = Cbs::new(mrpp_grid::cbs::Settings {
            heuristic: mrpp_grid::cbs::Heuristic::Wdg,
            ..Cbs::optimal().settings
        });
        let dg = Cbs::new(mrpp_grid::cbs::Settings {
            heuristic: mrpp_grid::cbs::Heuristic::Dg,
            ..Cbs::optimal().settings
        });
        let no_target = Cbs::new(mrpp_grid::cbs::Settings {
            target: false,
            ..Cbs::optimal().settings
        });
        let standard_wdg = Cbs::new(mrpp_grid::cbs::Settings {
            disjoint: false,
            heuristic: mrpp_grid::cbs::Heuristic::Wdg,
            ..Cbs::optimal().settings
        });
        // `Cbs::optimal()` has mrpp's rectangle conditions (the default).
        let no_rectangle = Cbs::new(mrpp_grid::cbs::Settings {
            rectangle: mrpp_grid::cbs::Rectangle::Off,
            ..Cbs::optimal().settings
        });
        let rectangle_mdd = Cbs::new(mrpp_grid::cbs::Settings {
            rectangle: mrpp_grid::cbs::Rectangle::Mdd,
            ..Cbs::optimal().settings
        });
        for (name, planner) in [
            ("cbs", Cbs::optimal()),
            ("cbs without a heuristic", plain),
            ("cbs with the CG heuristic", cg),
            ("cbs with the DG heuristic", dg),
            ("cbs with the WDG heuristic", wdg),
            ("cbs without target reasoning", no_target),
            ("cbs standard splitting", standard),
            ("cbs standard splitting, WDG", standard_wdg),
            ("cbs without rectangle reasoning", no_rectangle),
            ("cbs with CBSH2-RTC's rectangle reasoning", rectangle_mdd),
            ("eecbs(1)", Cbs::eecbs(1.0)),
        ] {
            match solve(&planner, &problem, &ctx()) {
                Ok(s) => {
                    assert_eq!(
                        s.metrics.sum_of_costs, optimum,
                        "case {case}: {name} on {inst:?}"
                    );
                    costs.push(name);
                }
                Err(Unsolved::TimeLimit) => {}
                Err(e) => panic!("case {case}: {name} on {inst:?}: {e}"),
            }
        }
        cbs_solved += usize::from(costs.contains(&"cbs"));
        e1_solved += usize::from(costs.contains(&"eecbs(1)"));
        match solve(&Cbs::eecbs(1.5), &problem, &ctx()) {
            Ok(s) => assert!(
                s.metrics.sum_of_costs as f64 <= 1.5 * optimum as f64,
                "case {case}: eecbs(1.5) on {inst:?}: {} > 1.5 x {optimum}",
                s.metrics.sum_of_costs
            ),
            Err(Unsolved::TimeLimit) => {}
            Err(e) => panic!("case {case}: eecbs(1.5) on {inst:?}: {e}"),
        }
    }
    eprintln!("{solvable} solvable cases: CBS solved {cbs_solved}, EECBS(1) {e1_solved}");
    assert!(solvable >= 60, "only {solvable} solvable cases drawn");
    assert!(
        cbs_solved * 10 >= solvable * 9,
        "CBS solved {cbs_solved} of {solvable}"
    );
    assert!(
        e1_solved * 10 >= solvable * 9,
        "EECBS(1) solved {e1_solved} of {solvable}"
    );
}

/// Beyond brute force's reach: on 24 seeded 7 x 7 grids with 20 % walls and 6..=14 agents, every
/// optimal variant (heuristic none, CG, WDG; target reasoning on and off; disjoint and standard
/// splitting; all with mrpp's rectangle conditions, the default, and with none and CG also
/// without rectangle reasoning and with CBSH2-RTC's; EECBS(1)) that returns within 1 s returns
/// the same sum of costs, and the default solves at least 80 % of them.
#[test]
fn optimal_variants_agree_on_larger_grids() {
    use mrpp_grid::cbs::{Heuristic, Rectangle, Settings};
    let mut rng = ChaCha8Rng::seed_from_u64(20_261_205);
    let (mut cases, mut default_solved) = (0, 0);
    for case in 0..24 {
        let rows: Vec<Vec<bool>> = (0..7)
            .map(|_| (0..7).map(|_| rng.random_bool(0.8)).collect())
            .collect();
        let map = GridMap::from_free_rows(&rows);
        let g = map.graph();
        // The largest connected part, so every instance is solvable unless agents block it.
        let cells: Vec<VertexId> = {
            let n = g.num_vertices();
            let mut best: Vec<VertexId> = Vec::new();
            let mut seen = vec![false; n];
            for s in 0..n {
                if seen[s] {
                    continue;
                }
                let mut part = vec![s as VertexId];
                seen[s] = true;
                let mut k = 0;
                while k < part.len() {
                    for &v in g.neighbors(part[k]) {
                        if !seen[v as usize] {
                            seen[v as usize] = true;
                            part.push(v);
                        }
                    }
                    k += 1;
                }
                if part.len() > best.len() {
                    best = part;
                }
            }
            best
        };
        let agents = rng.random_range(6..=14usize);
        if cells.len() < agents + 4 {
            continue;
        }
        let starts: Vec<VertexId> = cells.sample(&mut rng, agents).copied().collect();
        let goals: Vec<VertexId> = cells.sample(&mut rng, agents).copied().collect();
        let inst = Instance::new(starts, goals).unwrap();
        let problem = MapfProblem::on(g, &inst, Rules::default());
        cases += 1;
        let base = Cbs::optimal().settings;
        let mut variants: Vec<(String, Cbs)> = Vec::new();
        for heuristic in [Heuristic::None, Heuristic::Cg, Heuristic::Wdg] {
            for target in [true, false] {
                for disjoint in [true, false] {
                    let s = Settings {
                        heuristic,
                        target,
                        disjoint,
                        ..base
                    };
                    variants.push((format!("{s:?}"), Cbs::new(s)));
                }
            }
        }
        for heuristic in [Heuristic::None, Heuristic::Cg] {
            // The base has Rectangle::Proven (the default).
            for rectangle in [Rectangle::Off, Rectangle::Mdd] {
                let s = Settings {
                    heuristic,
                    rectangle,
                    ..base
                };
                variants.push((format!("{s:?}"), Cbs::new(s)));
            }
        }
        variants.push(("eecbs(1)".into(), Cbs::eecbs(1.0)));
        let mut agreed: Option<(u64, String)> = None;
        for (name, planner) in &variants {
            let ctx = Ctx::new(0, Deadline::after(Duration::from_secs(1)));
            match solve(planner, &problem, &ctx) {
                Ok(s) => {
                    let cost = s.metrics.sum_of_costs;
                    if let Some((c, first)) = &agreed {
                        assert_eq!(cost, *c, "case {case}: {name} against {first} on {inst:?}");
                    } else {
                        agreed = Some((cost, name.clone()));
                    }
                    if name == &format!("{base:?}") {
                        default_solved += 1;
                    }
                }
                Err(Unsolved::TimeLimit) => {}
                Err(Unsolved::GaveUp(why)) => {
                    assert!(
                        agreed.is_none(),
                        "case {case}: {name} gave up ({why}) on a solved instance"
                    );
                }
                Err(e) => panic!("case {case}: {name} on {inst:?}: {e}"),
            }
        }
    }
    eprintln!("{cases} cases; the default solved {default_solved}");
    assert!(cases >= 18, "only {cases} cases drawn");
    assert!(
        default_solved * 10 >= cases * 8,
        "the default solved {default_solved} of {cases}"
    );
}

/// Rectangle reasoning where it fires: on 30 seeded instances on an open 9 x 9 grid with 8..=16
/// agents, CBS with it (mrpp's conditions and CBSH2-RTC's) and without it (CG and WDG
/// heuristics, EECBS(1)) returns the same sum of costs whenever both return within 1 s, and each
/// kind splits on barriers in some of them.
#[test]
fn rectangle_reasoning_keeps_costs_optimal_on_open_grids() {
    use mrpp_grid::cbs::{Heuristic, Rectangle, Settings};
    let mut rng = ChaCha8Rng::seed_from_u64(202_612_059);
    // Runs with barrier splits: mrpp's conditions, CBSH2-RTC's.
    let (mut compared, mut with_rectangles) = (0, [0, 0]);
    for case in 0..30 {
        let map = GridMap::from_free_rows(&vec![vec![true; 9]; 9]);
        let g = map.graph();
        let cells: Vec<VertexId> = (0..g.num_vertices() as VertexId).collect();
        let agents = rng.random_range(8..=16usize);
        let starts: Vec<VertexId> = cells.sample(&mut rng, agents).copied().collect();
        let goals: Vec<VertexId> = cells.sample(&mut rng, agents).copied().collect();
        let inst = Instance::new(starts, goals).unwrap();
        let problem = MapfProblem::on(g, &inst, Rules::default());
        let base = Cbs::optimal().settings;
        let mut agreed: Option<(u64, String)> = None;
        for heuristic in [Heuristic::Cg, Heuristic::Wdg] {
            for rectangle in [Rectangle::Proven, Rectangle::Mdd, Rectangle::Off] {
                let s = Settings {
                    heuristic,
                    rectangle,
                    ..base
                };
                let planner = Cbs::new(s);
                let ctx = Ctx::new(0, Deadline::after(Duration::from_secs(1)));
                match solve(&planner, &problem, &ctx) {
                    Ok(run) => {
                        let cost = run.metrics.sum_of_costs;
                        let name = format!("{s:?}");
                        if let Some((c, first)) = &agreed {
                            assert_eq!(cost, *c, "case {case}: {name} against {first} on {inst:?}");
                        } else {
                            agreed = Some((cost, name));
                        }
                        if rectangle != Rectangle::Off
                            && planner.report().is_some_and(|r| r.rectangles > 0)
                        {
                            with_rectangles[usize::from(rectangle == Rectangle::Mdd)] += 1;
                        }
                    }
                    Err(Unsolved::TimeLimit) => {}
                    Err(e) => panic!("case {case}: {s:?} on {inst:?}: {e}"),
                }
            }
        }
        if let Ok(run) = solve(
            &Cbs::eecbs(1.0),
            &problem,
            &Ctx::new(0, Deadline::after(Duration::from_secs(1))),
        ) && let Some((c, first)) = &agreed
        {
            assert_eq!(
                run.metrics.sum_of_costs, *c,
                "case {case}: eecbs(1) against {first}"
            );
        }
        compared += usize::from(agreed.is_some());
    }
    assert!(compared >= 20, "only {compared} of 30 open grids solved");
    assert!(
        with_rectangles.iter().all(|&n| n >= 5),
        "rectangle splits in only {with_rectangles:?} runs"
    );
}
