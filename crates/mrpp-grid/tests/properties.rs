//! Property tests of the validator and the grid planners, on random small grids.
//!
//! 1. Every registered planner (plus non-default variants: H* `paper` and without completion,
//!    WHCA* with windows 1 and 2, LaCAM* and LaCAM without PIBT's tricks, LaCAM and LaCAM* with
//!    local guidance, PIBT with them), called
//!    directly through `Planner::plan`, never returns a plan the validator rejects; a plan returned
//!    by `solve` always validates; single-agent instances are always solved.
//! 2. The validator catches injected conflicts with the right kind, agent pair and time step:
//!    vertex and swap conflicts built from a solved plan with legal moves and waits only, both on the
//!    full plan (one-step injections) and on two-agent sub-plans (one agent freezes, the other walks
//!    a BFS path to it).
//! 3. `first_conflict` agrees with an independent brute-force pairwise check on random walks
//!    (agents may share cells, paths of different lengths), with following allowed or forbidden.
//!
//! A failing case prints its map as ASCII text (`#` wall, `.` free) and its agents in the H* robot
//! file format (`x,y;x,y`), so it can be replayed with the CLI.

use std::collections::VecDeque;
use std::fmt;
use std::path::Path;
use std::time::Duration;

use mrpp_core::mapf::plan::{Conflict, ConflictKind, first_conflict, position};
use mrpp_core::registry::find;
use mrpp_core::{
    Ctx, Deadline, Graph, Instance, MapfProblem, Plan, Planner, Problem, Rules, Unsolved, VertexId,
    Violation, solve,
};
use mrpp_grid::{GridMap, PLANNERS};
use proptest::prelude::*;
use proptest::sample::Index;

/// Per-call time limit of the planners.
const LIMIT: Duration = Duration::from_secs(2);

/// Per-call time limit of anytime planners and of CBS/EECBS.
const ANYTIME_LIMIT: Duration = Duration::from_millis(100);

fn opts() -> Ctx {
    Ctx::new(0, Deadline::after(LIMIT))
}

fn opts_for(label: &str) -> Ctx {
    // Anytime planners use all of their limit, and CBS runs until it on unsolvable instances.
    if label.contains("anytime=true") || label.contains("cbs") {
        Ctx::new(0, Deadline::after(ANYTIME_LIMIT))
    } else {
        opts()
    }
}

/// Rows of free (`true`) cells: width and height 3..=8, obstacle density 0..=35 %.
fn grid_rows() -> impl Strategy<Value = Vec<Vec<bool>>> {
    (3usize..=8, 3usize..=8, 0u32..=35).prop_flat_map(|(w, h, density)| {
        let p_free = 1.0 - f64::from(density) / 100.0;
        prop::collection::vec(prop::collection::vec(prop::bool::weighted(p_free), w), h).prop_map(
            |mut rows| {
                if !rows.iter().flatten().any(|&f| f) {
                    rows[0][0] = true;
                }
                rows
            },
        )
    })
}

fn map_text(rows: &[Vec<bool>]) -> String {
    rows.iter()
        .map(|r| {
            r.iter()
                .map(|&f| if f { '.' } else { '#' })
                .collect::<String>()
                + "\n"
        })
        .collect()
}

/// The map exactly as printed in failure messages.
fn parse_map(rows: &[Vec<bool>]) -> GridMap {
    GridMap::parse(&map_text(rows), Path::new("case.txt"))
        .expect("generated map parses")
        .0
}

/// Connected component (sorted vertex list) of every vertex.
fn components(g: &Graph) -> Vec<Vec<VertexId>> {
    let n = g.num_vertices();
    let mut comp_of = vec![usize::MAX; n];
    let mut comps: Vec<Vec<VertexId>> = Vec::new();
    for s in 0..n {
        if comp_of[s] != usize::MAX {
            continue;
        }
        let id = comps.len();
        let mut cells = vec![s as VertexId];
        comp_of[s] = id;
        let mut k = 0;
        while k < cells.len() {
            for &w in g.neighbors(cells[k]) {
                if comp_of[w as usize] == usize::MAX {
                    comp_of[w as usize] = id;
                    cells.push(w);
                }
            }
            k += 1;
        }
        cells.sort_unstable();
        comps.push(cells);
    }
    (0..n).map(|v| comps[comp_of[v]].clone()).collect()
}

/// Shortest path from `from` to the first vertex satisfying `is_target`, never entering `avoid`.
fn bfs_path(
    g: &Graph,
    from: VertexId,
    avoid: Option<VertexId>,
    is_target: impl Fn(VertexId) -> bool,
) -> Option<Vec<VertexId>> {
    let mut parent = vec![u32::MAX; g.num_vertices()];
    parent[from as usize] = from;
    let mut queue = VecDeque::from([from]);
    while let Some(u) = queue.pop_front() {
        if is_target(u) {
            let mut path = vec![u];
            let mut v = u;
            while v != from {
                v = parent[v as usize];
                path.push(v);
            }
            path.reverse();
            return Some(path);
        }
        for &w in g.neighbors(u) {
            if Some(w) != avoid && parent[w as usize] == u32::MAX {
                parent[w as usize] = u;
                queue.push_back(w);
            }
        }
    }
    None
}

/// A grid and an instance whose starts and goals all lie in one connected component.
#[derive(Clone)]
struct Case {
    rows: Vec<Vec<bool>>,
    starts: Vec<VertexId>,
    goals: Vec<VertexId>,
}

impl fmt::Debug for Case {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let map = parse_map(&self.rows);
        writeln!(f, "map:\n{}robots (x,y;x,y):", map_text(&self.rows))?;
        for (&s, &g) in self.starts.iter().zip(&self.goals) {
            let ((sx, sy), (gx, gy)) = (map.cell(s), map.cell(g));
            writeln!(f, "{sx},{sy};{gx},{gy}")?;
        }
        Ok(())
    }
}

impl Case {
    fn instance(&self) -> Instance {
        Instance::new(self.starts.clone(), self.goals.clone()).expect("distinct starts and goals")
    }
}

/// Picks distinct elements of `pool` with the indices in `picks`.
fn pick_distinct(pool: &[VertexId], picks: &[Index]) -> Vec<VertexId> {
    let mut pool = pool.to_vec();
    picks
        .iter()
        .map(|ix| pool.remove(ix.index(pool.len())))
        .collect()
}

/// Cases with `min_agents..=min(8, component size)` agents. The component is the one of a random
/// free cell, or the largest one when that is too small.
fn case(min_agents: usize) -> impl Strategy<Value = Case> {
    (
        grid_rows(),
        any::<Index>(),
        any::<Index>(),
        prop::collection::vec(any::<Index>(), 8),
        prop::collection::vec(any::<Index>(), 8),
    )
        .prop_filter_map(
            "connected component too small",
            move |(rows, cell, count, s, g)| {
                let map = GridMap::from_free_rows(&rows);
                let comps = components(map.graph());
                let mut cells = comps[cell.index(comps.len())].clone();
                if cells.len() < min_agents {
                    cells = comps.iter().max_by_key(|c| c.len()).cloned().unwrap();
                }
                if cells.len() < min_agents {
                    return None;
                }
                let max_agents = cells.len().min(8);
                let k = min_agents + count.index(max_agents - min_agents + 1);
                Some(Case {
                    starts: pick_distinct(&cells, &s[..k]),
                    goals: pick_distinct(&cells, &g[..k]),
                    rows,
                })
            },
        )
}

/// Every registered planner ([`PLANNERS`]) with its default parameters, plus the non-default
/// variants, each with a label in command-line terms. A planner is tested by being registered.
fn all_planners() -> Vec<(String, Box<dyn Planner<MapfProblem>>)> {
    let mut runs: Vec<(&str, Vec<(String, String)>)> =
        PLANNERS.iter().map(|e| (e.name, Vec::new())).collect();
    let kv = |k: &str, v: &str| vec![(k.to_string(), v.to_string())];
    runs.push(("hstar", kv("variant", "paper")));
    runs.push(("whca", kv("window", "1")));
    runs.push(("whca", kv("window", "2")));
    runs.push(("lacam", kv("anytime", "true")));
    runs.push(("lacam", kv("local_guidance", "3")));
    runs.push((
        "lacam",
        vec![
            ("anytime".to_string(), "true".to_string()),
            ("local_guidance".to_string(), "2".to_string()),
            ("guidance_collision_cost".to_string(), "1".to_string()),
        ],
    ));
    runs.push((
        "lacam",
        vec![
            ("swap".to_string(), "false".to_string()),
            ("hindrance".to_string(), "false".to_string()),
        ],
    ));
    runs.push((
        "pibt",
        vec![
            ("swap".to_string(), "true".to_string()),
            ("hindrance".to_string(), "true".to_string()),
        ],
    ));
    runs.push(("hstar", kv("complete", "false")));
    runs.into_iter()
        .map(|(name, params)| {
            let mut label = format!("--planner {name}");
            for (k, v) in &params {
                label += &format!(" -p {k}={v}");
            }
            let entry = find(PLANNERS, name).unwrap_or_else(|| panic!("{name} is registered"));
            let p = entry
                .instantiate(&params)
                .unwrap_or_else(|e| panic!("{label}: {e}"));
            (label, p)
        })
        .collect()
}

/// Path of `path` over steps `0..len` (padded with its last vertex).
fn prefix(path: &[VertexId], len: usize) -> Vec<VertexId> {
    (0..len).map(|t| position(path, t)).collect()
}

fn horizon(paths: &[Vec<VertexId>]) -> usize {
    paths.iter().map(Vec::len).max().unwrap_or(0)
}

fn conflict(c: Conflict) -> Result<mrpp_core::Metrics, Violation> {
    Err(Violation::Conflict(c))
}

/// A valid plan for `case` (from the first planner that solves it) with its instance; when none
/// does, the instance with goals = starts and the plan in which nobody moves.
fn base_plan(case: &Case, g: &Graph) -> (Instance, Plan) {
    let inst = case.instance();
    for name in ["hca", "hstar", "whca", "ca"] {
        let p = find(PLANNERS, name).unwrap().instantiate(&[]).unwrap();
        if let Ok(solved) = solve(
            p.as_ref(),
            &MapfProblem::on(g, &inst, Rules::default()),
            &opts(),
        ) {
            return (inst, solved.plan);
        }
    }
    let inst = Instance::new(case.starts.clone(), case.starts.clone()).unwrap();
    let plan = Plan::new(case.starts.iter().map(|&s| vec![s]).collect());
    (inst, plan)
}

/// Independent check: every conflict at the earliest step that has one.
fn brute_conflicts(paths: &[Vec<VertexId>], allow_following: bool) -> Option<Vec<Conflict>> {
    let n = paths.len();
    for t in 0..horizon(paths) {
        let mut found = Vec::new();
        for a in 0..n {
            for b in a + 1..n {
                let (pa, pb) = (&paths[a], &paths[b]);
                if position(pa, t) == position(pb, t) {
                    found.push(Conflict {
                        a,
                        b,
                        t,
                        kind: ConflictKind::Vertex { v: position(pa, t) },
                    });
                }
                if t == 0 {
                    continue;
                }
                let (a0, a1) = (position(pa, t - 1), position(pa, t));
                let (b0, b1) = (position(pb, t - 1), position(pb, t));
                if a0 != a1 && a0 == b1 && a1 == b0 {
                    found.push(Conflict {
                        a,
                        b,
                        t,
                        kind: ConflictKind::Swap { u: a0, v: a1 },
                    });
                }
                if !allow_following {
                    // One enters the cell the other just left (neither a swap nor a vertex conflict).
                    for (x0, x1, y0, y1) in [(a0, a1, b0, b1), (b0, b1, a0, a1)] {
                        if x0 != x1 && x1 == y0 && y1 != y0 && y1 != x0 {
                            found.push(Conflict {
                                a,
                                b,
                                t,
                                kind: ConflictKind::Following { v: x1 },
                            });
                        }
                    }
                }
            }
        }
        if !found.is_empty() {
            return Some(found);
        }
    }
    None
}

/// Random walks (each step: wait or move to a neighbour) from arbitrary free cells.
fn walks(
    g: &Graph,
    specs: &[(Index, usize, Vec<Index>)],
    free_cells: &[VertexId],
) -> Vec<Vec<VertexId>> {
    specs
        .iter()
        .map(|(start, len, steps)| {
            let mut v = free_cells[start.index(free_cells.len())];
            let mut path = vec![v];
            for ix in &steps[..*len] {
                let mut options = vec![v];
                options.extend_from_slice(g.neighbors(v));
                v = options[ix.index(options.len())];
                path.push(v);
            }
            path
        })
        .collect()
}

proptest! {
    // A fixed seed: the same cases on every run, so CI is deterministic.
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_122),
        ..ProptestConfig::default()
    })]

    /// Property 1: no planner returns an invalid plan, `solve` never does, one agent is always
    /// solved; the complete planners (LaCAM, H* with its default completion) solve every
    /// instance that any planner solves.
    #[test]
    fn planners_never_return_invalid_plans(case in case(1)) {
        let map = parse_map(&case.rows);
        let built = GridMap::from_free_rows(&case.rows);
        prop_assert_eq!(map.graph(), built.graph());
        let g = map.graph();
        let inst = case.instance();
        let mut solved_by = Vec::new();
        for (label, p) in &all_planners() {
            let direct = p.plan(&MapfProblem::on(g, &inst, Rules::default()), &opts_for(label));
            if let Ok(plan) = &direct {
                let v = MapfProblem::on(g, &inst, Rules::default()).validate(plan);
                prop_assert!(
                    v.is_ok(),
                    "{} returned an invalid plan: {}\npaths: {:?}",
                    label,
                    v.unwrap_err(),
                    plan.paths
                );
            }
            if inst.num_agents() == 1 {
                prop_assert!(
                    !matches!(direct, Err(Unsolved::GaveUp(_))),
                    "{} fails on a single agent: {:?}",
                    label,
                    direct
                );
            }
            if let Ok(solved) = solve(p.as_ref(), &MapfProblem::on(g, &inst, Rules::default()), &opts_for(label)) {
                let v = MapfProblem::on(g, &inst, Rules::default()).validate(&solved.plan);
                prop_assert!(
                    v.is_ok(),
                    "solve({}) returned an invalid plan: {:?}",
                    label,
                    v
                );
                solved_by.push(label.clone());
            }
        }
        if !solved_by.is_empty() {
            for complete in ["--planner lacam", "--planner hstar"] {
                prop_assert!(
                    solved_by.iter().any(|l| l == complete),
                    "{} did not solve an instance that {:?} solved",
                    complete,
                    solved_by
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Property 2, full plan: one-step vertex and swap injections into a valid plan are reported
    /// exactly (pair, step, kind); every other agent keeps its valid path.
    #[test]
    fn one_step_injections_are_reported_exactly(
        case in case(2),
        pick_vertex in any::<Index>(),
        pick_swap in any::<Index>(),
    ) {
        let map = parse_map(&case.rows);
        let g = map.graph();
        let (inst, plan) = base_plan(&case, g);
        prop_assert!(MapfProblem::on(g, &inst, Rules::default()).validate(&plan).is_ok());
        let paths = &plan.paths;
        let n = paths.len();
        let h = horizon(paths);
        let pos = |i: usize, t: usize| position(&paths[i], t);
        let near = |u: VertexId, v: VertexId| u == v || g.has_edge(u, v);

        // Vertex: j, instead of its step t, steps (or waits) onto i's cell at t and stays there.
        // Skipped when that move would also swap with some third agent k at t.
        let mut vertex_candidates = Vec::new();
        for t in 1..=h {
            for i in 0..n {
                for j in (0..n).filter(|&j| j != i) {
                    let (from, to) = (pos(j, t - 1), pos(i, t));
                    let swap_with_third = (0..n)
                        .any(|k| k != i && k != j && pos(k, t - 1) == to && pos(k, t) == from);
                    if near(from, to) && !swap_with_third {
                        vertex_candidates.push((i, j, t));
                    }
                }
            }
        }
        if !vertex_candidates.is_empty() {
            let (i, j, t) = *pick_vertex.get(&vertex_candidates);
            let mut bad = plan.clone();
            bad.paths[j] = prefix(&paths[j], t);
            bad.paths[j].push(pos(i, t));
            prop_assert_eq!(
                MapfProblem::on(g, &inst, Rules::default()).validate(&bad).map_err(|v| v.violation),
                conflict(Conflict {
                    a: i.min(j),
                    b: i.max(j),
                    t,
                    kind: ConflictKind::Vertex { v: pos(i, t) },
                }),
                "agent {} moved onto agent {} at t={}: {:?}",
                j,
                i,
                t,
                bad.paths
            );
        }

        // Swap: two agents adjacent at t - 1 exchange their cells at t and stay.
        let mut swap_candidates = Vec::new();
        for t in 1..=h {
            for i in 0..n {
                for j in i + 1..n {
                    if g.has_edge(pos(i, t - 1), pos(j, t - 1)) {
                        swap_candidates.push((i, j, t));
                    }
                }
            }
        }
        if !swap_candidates.is_empty() {
            let (i, j, t) = *pick_swap.get(&swap_candidates);
            let (ui, uj) = (pos(i, t - 1), pos(j, t - 1));
            let mut bad = plan.clone();
            bad.paths[i] = prefix(&paths[i], t);
            bad.paths[i].push(uj);
            bad.paths[j] = prefix(&paths[j], t);
            bad.paths[j].push(ui);
            prop_assert_eq!(
                MapfProblem::on(g, &inst, Rules::default()).validate(&bad).map_err(|v| v.violation),
                conflict(Conflict {
                    a: i,
                    b: j,
                    t,
                    kind: ConflictKind::Swap { u: ui, v: uj },
                }),
                "agents {} and {} swapped at t={}: {:?}",
                i,
                j,
                t,
                bad.paths
            );
        }
    }

    /// Property 2, two-agent sub-plans (always applicable): from a valid plan keep agents p < q;
    /// one freezes at its cell c from step t0 on, the other walks a shortest path to c (vertex
    /// conflict on arrival), or to the first neighbour of c it can reach without entering c, after
    /// which both exchange cells (swap conflict). These are the only conflicts of the sub-plans.
    #[test]
    fn walk_in_injections_are_reported_exactly(
        case in case(2),
        pick_p in any::<Index>(),
        pick_q in any::<Index>(),
        pick_t0 in any::<Index>(),
        lower_freezes in any::<bool>(),
    ) {
        let map = parse_map(&case.rows);
        let g = map.graph();
        let (inst, plan) = base_plan(&case, g);
        let n = plan.paths.len();
        let p = pick_p.index(n);
        let q = (p + 1 + pick_q.index(n - 1)) % n;
        let (p, q) = (p.min(q), p.max(q));
        let t0 = pick_t0.index(horizon(&plan.paths) + 2);
        let sub_inst =
            Instance::new(vec![inst.starts[p], inst.starts[q]], vec![inst.goals[p], inst.goals[q]])
                .unwrap();
        // Sub-plan index of the frozen agent and of the walker.
        let (frozen, walker) = if lower_freezes { (0, 1) } else { (1, 0) };
        let sub_paths = [&plan.paths[p], &plan.paths[q]];
        let c = position(sub_paths[frozen], t0);
        let w0 = position(sub_paths[walker], t0);
        prop_assert_ne!(c, w0);

        // Vertex conflict on arrival at c.
        let walk = bfs_path(g, w0, None, |v| v == c).expect("one component");
        let mut paths = vec![Vec::new(); 2];
        paths[frozen] = prefix(sub_paths[frozen], t0 + 1);
        paths[walker] = prefix(sub_paths[walker], t0 + 1);
        paths[walker].extend_from_slice(&walk[1..]);
        let arrival = t0 + walk.len() - 1;
        prop_assert_eq!(
            MapfProblem::on(g, &sub_inst, Rules::default()).validate(&Plan::new(paths.clone())).map_err(|v| v.violation),
            conflict(Conflict { a: 0, b: 1, t: arrival, kind: ConflictKind::Vertex { v: c } }),
            "walk-in vertex conflict: {:?}",
            paths
        );

        // Swap conflict: the walker stops next to c, then both exchange cells.
        let walk = bfs_path(g, w0, Some(c), |v| g.has_edge(v, c)).expect("c has a neighbour");
        let u = *walk.last().unwrap();
        let next_to = t0 + walk.len() - 1;
        let mut paths = vec![Vec::new(); 2];
        paths[frozen] = prefix(sub_paths[frozen], t0 + 1);
        paths[frozen].extend(std::iter::repeat_n(c, next_to - t0));
        paths[frozen].push(u);
        paths[walker] = prefix(sub_paths[walker], t0 + 1);
        paths[walker].extend_from_slice(&walk[1..]);
        paths[walker].push(c);
        let kind = if frozen == 0 {
            ConflictKind::Swap { u: c, v: u }
        } else {
            ConflictKind::Swap { u, v: c }
        };
        prop_assert_eq!(
            MapfProblem::on(g, &sub_inst, Rules::default()).validate(&Plan::new(paths.clone())).map_err(|v| v.violation),
            conflict(Conflict { a: 0, b: 1, t: next_to + 1, kind }),
            "walk-in swap conflict: {:?}",
            paths
        );
    }

    /// Property 3: `first_conflict` finds a conflict iff the brute-force check does, and then one
    /// of the brute-force conflicts at the earliest step, swaps/following before vertex conflicts.
    #[test]
    fn first_conflict_matches_brute_force(
        rows in grid_rows(),
        specs in prop::collection::vec(
            (any::<Index>(), 0usize..=11, prop::collection::vec(any::<Index>(), 11)),
            1..=6,
        ),
        allow_following in any::<bool>(),
    ) {
        let map = GridMap::from_free_rows(&rows);
        let g = map.graph();
        let free: Vec<VertexId> = (0..g.num_vertices() as VertexId).collect();
        let paths = walks(g, &specs, &free);
        let got = first_conflict(&paths, g.num_vertices(), allow_following);
        let expected = brute_conflicts(&paths, allow_following);
        prop_assert_eq!(
            got.is_none(),
            expected.is_none(),
            "first_conflict {:?}, brute force {:?}, paths {:?}",
            got,
            expected,
            paths
        );
        if let (Some(c), Some(all)) = (got, expected) {
            prop_assert!(
                all.contains(&c),
                "first_conflict {:?} is not among the earliest conflicts {:?} of {:?}",
                c,
                all,
                paths
            );
            let not_vertex = |c: &Conflict| !matches!(c.kind, ConflictKind::Vertex { .. });
            prop_assert!(
                not_vertex(&c) || !all.iter().any(not_vertex),
                "vertex conflict {:?} reported before a swap/following in {:?}",
                c,
                all
            );
        }
    }
}
