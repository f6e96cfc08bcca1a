//! Conflict-based search: CBS (Sharon, Stern, Felner, Sturtevant, "Conflict-based search for
//! optimal multi-agent pathfinding", AIJ 219, 2015) with the ICBS improvements (Boyarski et al.,
//! IJCAI 2015): conflicts prioritised by MDDs (cardinal, then semi-cardinal, then non-cardinal)
//! and bypass; and EECBS (Li, Ruml, Koenig, "EECBS: a bounded-suboptimal search for multi-agent
//! path finding", AAAI 2021): explicit estimation search at the high level over focal-search
//! low levels, with sum of costs at most `w` times the optimum. Baselines §7.
//!
//! A constraint-tree node holds one path per agent, its constraints (a chain of one constraint per
//! node back to the root), the sum of costs and the conflicts between its paths (every one of
//! each conflicting pair, as CBSH2-RTC keeps them: keeping only each pair's first hid the target
//! conflicts behind it). Expanding a node picks a conflict and makes two children, each with
//! one more constraint on one of the two agents (vertex `(i, v, t)` or edge `(i, u, v, t)`), and
//! re-plans only that agent with [`low_level::focal_search`] (space-time search under the
//! validator's rules: stay at the goal, following allowed, no vertex or swap conflicts; ties go to
//! fewer conflicts with the other agents' paths). *Bypass*: a child whose new path costs no more
//! and leaves fewer conflicts gives its path to the parent, which is expanded again instead of
//! being split.
//!
//! CBS pops the node of least sum of costs (ties: fewer conflicts) and is optimal. EECBS keeps
//! three orders over the open nodes: CLEANUP by lower bound `LB` (the sum of the low levels'
//! proven bounds), OPEN by `f̂ = cost + ĥ`, FOCAL (nodes with `f̂ <= w · f̂_min`) by number of
//! conflicts; it expands the first of FOCAL if its cost is within `w · LB_min`, else the first of
//! OPEN if within, else the first of CLEANUP, so every returned plan costs at most `w` times the
//! optimum. `ĥ` is learned online (EECBS §4.3): after each expansion the best child's one-step
//! errors in cost (`ε_h`) and in conflicts (`ε_d`) update running means, and `ĥ(n) = d(n) ·
//! ε̄_h / (1 − ε̄_d)` for `d(n)` conflicts; mrpp caps the divisor below at 0.1 (the paper leaves
//! `ε̄_d >= 1` open; its authors' code multiplies `ε̄_h` by 10 there, the same). FOCAL is kept
//! up to date as nodes and `f̂_min` change (`Lists`), so choosing a node costs `O(log n)`.
//!
//! *Disjoint splitting* (Li, Harabor, Stuckey, Ma, Koenig, ICAPS 2019; the default of both,
//! `-p splitting=standard` turns it off): a conflict of agents `a` and `b` becomes a child where
//! `a` may not be at that vertex (or take that edge) then, and one where it must be, which
//! forbids it to every other agent; the agents whose paths break that are re-planned, and the
//! low level then searches through the positive constraints as landmarks. The two children share
//! no plan. With standard splitting they share every plan in which neither agent is there, so in
//! corridors, where agents dodge each other one step at a time, the same plans are searched for
//! again down both branches: on 3-agent swaps in a 5-cell corridor with a one-cell side pocket
//! (CBS: 0.07 to 0.2 s) EECBS(1.2) ran past 1 s on 12 of 16 and EECBS(2) on 4, some past any
//! limit, and FOCAL, then rebuilt from OPEN at every expansion, slowed the search to a crawl as
//! OPEN grew; each now takes 0.15 s at most (issue 27, item 4; `tests/bounded_searches.rs`).
//! *The CG heuristic* (Felner et al., ICAPS 2018; CBS's default, `-p heuristic=none` turns it off):
//! CBS orders its nodes by sum of costs plus a minimum vertex cover of the graph of agent pairs
//! whose conflict is cardinal for both (each such pair must raise the sum of costs by one), so
//! fewer nodes of a cost level that cannot hold the optimum are expanded; on random-32-32-20
//! (random-1) it cut the expansions about 10x at 30 and at 40 agents. `-p heuristic=dg` adds the
//! pairs whose MDDs are *dependent* (no two conflict-free paths at their costs; Li, Felner,
//! Boyarski, Koenig, IJCAI 2019): there it expanded 2,058 nodes where CG expanded 2,062, in 1.8x
//! the time (the joint MDD searches), so CG stays the default. EECBS uses neither.
//! `-p heuristic=wdg` weights each dependent pair by the extra cost a two-agent CBS under the
//! node's constraints finds (at most [`PAIR_EXPANSIONS`] expansions, memoised by the pair and
//! its constraints) and takes an edge-weighted minimum vertex cover ([`min_weighted_cover`]; Li
//! et al., IJCAI 2019, the heuristic of CBSH2-RTC and of EECBS). Children's heuristics keep what
//! the parent's proved (path-max).
//!
//! *Target reasoning* (Li, Gange, Harabor, Stuckey, Ma, Koenig, ICAPS 2020; `-p target=true`, the
//! default of both): when an agent passes over another's goal after that one arrived for good,
//! the node splits on the arrived agent's cost — at most the conflict's time `t` (no agent may
//! be on that goal from `t` on) or more than `t` — instead of one vertex at one step, which left
//! the passing agent's detours and the other's later arrivals to be refuted one step at a time.
//! Among conflicts of equal cardinality a target conflict is split first, as CBSH2-RTC does.
//!
//! The low level with `w = 1` is plain A* on one binary heap ([`low_level::optimal_search`]) and
//! counts the last constraint on an agent's goal in its heuristic (the agent cannot finish
//! before it: EECBS's *holding time*); both cut CBS's time about in half on random-32-32-20.
//!
//! *Rectangle reasoning* (Li, Harabor, Stuckey, Ma, Koenig, AAAI 2019; `-p rectangle=true`, the
//! default): when a node has no cardinal conflict, a vertex conflict of two agents crossing a
//! rectangle of the grid on time is split on *barriers* (a row or column of the rectangle, each
//! cell at the time the agent would reach it), one per agent, which rules out every pair of
//! their crossing paths at once. CBSH2-RTC takes the rectangle's corners from the current paths'
//! MDD singletons, which a longer path need not pass; mrpp keeps a split only where lower bounds
//! on the agents' arrival times (distances from their starts) prove that any two paths on both
//! barriers collide ([`Search::rectangle`] has the conditions and the argument). On MovingAI
//! maps those conditions seldom hold on the whole rectangle (paths that bend around obstacles
//! can reach part of it early): on den520d with 100 agents 312 of about 13,000 conflicts tried
//! passed, none cardinal, and the search stalled at the bound 16,649. So where they fail,
//! smaller rectangles are tried, their start corner moved a third, two thirds or all the way
//! towards the conflict on each axis, largest first, and the conditions checked on each afresh
//! (the argument holds on any rectangle they hold on): den520d with 100 agents is then solved
//! at its optimum, 16,650, in 2,070 expansions (docs/performance.md; EECBS(1), whose rectangle
//! reasoning is what solves it there, takes 1,138). A rectangle split replaces the chosen
//! conflict only when it is more cardinal ([`Search::choose`]). On the 49 instances of the 60 s
//! comparison with EECBS(1) (`bench/configs/cbs-eecbs-60s.toml`) mrpp then solves every instance
//! EECBS solves and two more, in a median 0.32x EECBS's time, so it is the default.
//! `-p rectangle=mdd` takes CBSH2-RTC's conditions instead ([`Rectangle::Mdd`]): each agent's
//! corners are the points of its monotone segment farthest from the conflict where its MDD has a
//! single vertex, so every path at the current cost passes them and every conflict-free pair at the
//! current costs is kept; pairs with a longer path are the paper's claim, which
//! `tests/cbs_optimal.rs` checks against brute force and the other variants. On den520d with 100
//! agents it split 3,468 conflicts on barriers but still ended at the bound 16,649 after 60 s.
//! Corridor reasoning (Li et al., ICAPS 2020) is not implemented: on den520d no split conflict lay
//! in a corridor.
//!
//! *Unsolvable instances*: the constraint tree of an instance without a plan is infinite, and
//! CBS grew to 4.6 GB in 60 s on two agents swapping the ends of a 10-cell corridor. After 256
//! expansions, then after 4 times as many each time, the search asks LaCAM's exhaustive search
//! for a proof that no plan exists (`lacam::proven_unsolvable`: component by component, within a
//! quarter of the time run so far and 2^20 iterations), and gives up with it
//! ([`Unsolved::GaveUp`]): that swap in 7 ms, corridors of 100 and 200 cells in 0.4 and 1.2 s.
//! Beyond LaCAM's reach (a 400-cell corridor swap) the time limit ends the search, as before. A
//! proof is exact (LaCAM reports it only after expanding every reachable configuration), so an
//! instance with a plan is never given up on; instances solved before the first attempt never
//! run one.

pub mod low_level;
pub mod mdd;

use std::collections::{BTreeSet, BinaryHeap};

use rustc_hash::FxHashMap;
use std::sync::Arc;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::GridMap;
use low_level::{
    AvoidanceTable, BlockedCache, Constraint, Constraints, Found, NoPath, Query, focal_search,
};
use mdd::Mdd;
use mrpp_core::mapf::search::distance::{GoalDistances, UNREACHABLE};
use mrpp_core::{
    Ctx, GoalSemantics, MapfProblem, Param, Plan, Planner, PlannerEntry, Progress, Unsolved,
    VertexId,
};

/// Registry name of CBS.
pub const CBS_NAME: &str = "cbs";
/// Registry name of EECBS.
pub const EECBS_NAME: &str = "eecbs";

/// CBS's and EECBS's `-p rectangle` ([`Settings::rectangle`]).
const RECTANGLE_PARAM: Param = Param {
    name: "rectangle",
    default: "true",
    doc: "rectangle reasoning on grids: when no conflict is cardinal, a conflict of two agents crossing a rectangle on time, more cardinal as a rectangle than the best conflict, splits on barriers, one per agent, instead of one cell (Li et al., AAAI 2019); used with MDD prioritisation. true (the default) = under mrpp's arrival-time conditions, which keep every conflict-free pair of paths, on the rectangle or a smaller one towards the conflict (cbs/mod.rs, `Search::rectangle`; solves den520d random-1 with 100 agents, docs/performance.md); mdd = CBSH2-RTC's conditions (the rectangle's corners are singletons of the agents' MDDs: every conflict-free pair at the current costs is kept, an optimal plan by the paper's claim, tested but not proven by mrpp); false = none",
};

/// CBS in the planner registry.
pub const CBS_ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: CBS_NAME,
    about: "CBS with ICBS's MDD conflict prioritisation and bypass (Sharon et al., AIJ 2015; Boyarski et al., IJCAI 2015) and the CG heuristic (Felner et al., ICAPS 2018); optimal sum of costs",
    params: &[
        Param {
            name: "prioritize",
            default: "true",
            doc: "choose cardinal, then semi-cardinal conflicts by MDDs (false: the earliest conflict)",
        },
        Param {
            name: "heuristic",
            default: "cg",
            doc: "order the constraint tree by sum of costs + a minimum vertex cover of: wdg = the dependent pairs weighted by their extra cost (a two-agent CBS; Li et al., IJCAI 2019, as in CBSH2-RTC), dg = the pairs of dependent agents (their MDDs hold no pair of conflict-free paths; Li et al., IJCAI 2019), cg = the pairs with a cardinal conflict (Felner et al., ICAPS 2018); none = by sum of costs alone",
        },
        Param {
            name: "bypass",
            default: "true",
            doc: "adopt a child's path of equal cost with fewer conflicts instead of splitting",
        },
        Param {
            name: "splitting",
            default: "disjoint",
            doc: "disjoint = a negative and a positive constraint on one agent (Li et al., ICAPS 2019); standard = one negative constraint on each agent",
        },
        Param {
            name: "target",
            default: "true",
            doc: "target reasoning: split a conflict on an agent's goal after it arrived by that agent's cost, at most or more than the conflict's time (Li et al., ICAPS 2020)",
        },
        RECTANGLE_PARAM,
    ],
    build: |p| {
        Ok(Box::new(Cbs::new(Settings {
            w: 1.0,
            explicit_estimation: false,
            prioritize: p.choice("prioritize", &["false", "true"])? == 1,
            bypass: p.choice("bypass", &["false", "true"])? == 1,
            disjoint: p.choice("splitting", &["standard", "disjoint"])? == 1,
            target: p.choice("target", &["false", "true"])? == 1,
            rectangle: Rectangle::from_param(p)?,
            heuristic: [
                Heuristic::None,
                Heuristic::Cg,
                Heuristic::Dg,
                Heuristic::Wdg,
            ][p.choice("heuristic", &["none", "cg", "dg", "wdg"])?],
        })))
    },
};

/// EECBS in the planner registry.
pub const EECBS_ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: EECBS_NAME,
    about: "EECBS: explicit estimation CBS with focal low levels (Li, Ruml, Koenig, AAAI 2021); sum of costs <= w x optimal",
    params: &[
        Param {
            name: "w",
            default: "1.2",
            doc: "suboptimality bound (>= 1; 1 = optimal)",
        },
        Param {
            name: "bypass",
            default: "true",
            doc: "adopt a child's path of no greater cost with fewer conflicts instead of splitting",
        },
        Param {
            name: "splitting",
            default: "disjoint",
            doc: "disjoint = a negative and a positive constraint on one agent (Li et al., ICAPS 2019); standard = one negative constraint on each agent",
        },
        Param {
            name: "target",
            default: "true",
            doc: "target reasoning: split a conflict on an agent's goal after it arrived by that agent's cost, at most or more than the conflict's time (Li et al., ICAPS 2020)",
        },
        RECTANGLE_PARAM,
    ],
    build: |p| {
        let w: f64 = p.get_in("w", 1.0..=1000.0)?;
        Ok(Box::new(Cbs::new(Settings {
            w,
            explicit_estimation: true,
            prioritize: w == 1.0,
            bypass: p.choice("bypass", &["false", "true"])? == 1,
            disjoint: p.choice("splitting", &["standard", "disjoint"])? == 1,
            target: p.choice("target", &["false", "true"])? == 1,
            rectangle: Rectangle::from_param(p)?,
            heuristic: Heuristic::None,
        })))
    },
};

/// How the search runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Suboptimality bound (1 = optimal).
    pub w: f64,
    /// EECBS's three-list selection (false: CBS's best-first order).
    pub explicit_estimation: bool,
    /// MDD-based conflict prioritisation (only meaningful with optimal low levels, `w = 1`).
    pub prioritize: bool,
    pub bypass: bool,
    /// Disjoint splitting (Li et al., ICAPS 2019); false: standard splitting.
    pub disjoint: bool,
    /// Target reasoning (Li et al., ICAPS 2020; [`Search::split`]).
    pub target: bool,
    /// Rectangle reasoning on grids (Li et al., AAAI 2019; [`Search::rectangle`]) and its
    /// conditions; used with `prioritize` only (it needs the MDDs).
    pub rectangle: Rectangle,
    /// CBS: the heuristic added to each node's sum of costs in the best-first order (ignored
    /// by EECBS).
    pub heuristic: Heuristic,
}

/// Rectangle reasoning's conditions (`-p rectangle`; [`Search::rectangle`]): when a rectangle
/// conflict may be split on barriers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rectangle {
    /// No rectangle reasoning (`false`).
    Off,
    /// mrpp's conditions (`true`, the default): lower bounds on the agents' arrival times prove
    /// that every pair of conflict-free paths, of any costs, stays in a child.
    Proven,
    /// CBSH2-RTC's (`mdd`; Li, Harabor, Stuckey, Ma, Koenig, AAAI 2019, and AIJ 2021, rectangle
    /// reasoning with MDDs): the rectangle's corners are points of the current paths where the
    /// agents' MDDs have one vertex, so every pair of conflict-free paths at the current costs
    /// stays in a child. Pairs where an agent takes a longer path are not covered by that
    /// argument; that an optimal plan survives them is the paper's claim, which mrpp tests
    /// (`crates/mrpp-grid/tests/cbs_optimal.rs`) but does not prove.
    Mdd,
}

impl Rectangle {
    fn from_param(p: &mrpp_core::Params) -> mrpp_core::error::Result<Self> {
        Ok([Rectangle::Off, Rectangle::Proven, Rectangle::Mdd]
            [p.choice("rectangle", &["false", "true", "mdd"])?])
    }
}

/// CBS's admissible heuristics over the constraint tree (module doc): a minimum vertex cover of
/// a graph of agent pairs, each of which must raise the sum of costs by one between them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Heuristic {
    /// None (nodes by sum of costs).
    None,
    /// CG: the pairs whose conflict is cardinal for both (Felner et al., ICAPS 2018).
    Cg,
    /// DG: those and the pairs whose MDDs are dependent ([`mdd::dependent`]; Li, Felner,
    /// Boyarski, Koenig, IJCAI 2019).
    Dg,
    /// WDG: the DG's pairs, each weighted by how much the two agents' sum of costs must rise for
    /// them to stop conflicting (a two-agent CBS under the node's constraints, at most
    /// [`PAIR_EXPANSIONS`] expansions), and an edge-weighted minimum vertex cover of them (Li,
    /// Felner, Boyarski, Koenig, IJCAI 2019, §4; the heuristic of CBSH2-RTC, Li et al., AIJ 2021).
    Wdg,
}

/// CBS or EECBS, by [`Settings`].
#[derive(Debug)]
pub struct Cbs {
    pub settings: Settings,
    last: Mutex<Option<Report>>,
}

/// What a run reports beside its plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report {
    pub expanded: u64,
    pub generated: u64,
    /// Proven lower bound on the optimal sum of costs when the plan was found (or when the run
    /// ended without one).
    pub lower_bound: u64,
    /// WDG: two-agent searches run (not answered by the memo).
    pub pair_searches: u64,
    /// Rectangle reasoning: conflicts split on barriers.
    pub rectangles: u64,
    /// Rectangle reasoning: conflicts tried as rectangles.
    pub rectangle_tries: u64,
}

impl Cbs {
    pub fn new(settings: Settings) -> Self {
        Cbs {
            settings,
            last: Mutex::new(None),
        }
    }

    /// CBS at the registry's defaults: ICBS's prioritisation and bypass, disjoint splitting,
    /// target and rectangle reasoning, the CG heuristic.
    pub fn optimal() -> Self {
        Cbs::new(Settings {
            w: 1.0,
            explicit_estimation: false,
            prioritize: true,
            bypass: true,
            disjoint: true,
            target: true,
            rectangle: Rectangle::Proven,
            heuristic: Heuristic::Cg,
        })
    }

    /// EECBS with weight `w` (disjoint splitting, bypass, target reasoning; rectangle reasoning
    /// at `w = 1`, where it prioritises conflicts).
    pub fn eecbs(w: f64) -> Self {
        Cbs::new(Settings {
            w,
            explicit_estimation: true,
            prioritize: w == 1.0,
            bypass: true,
            disjoint: true,
            target: true,
            rectangle: Rectangle::Proven,
            heuristic: Heuristic::None,
        })
    }

    /// The report of the last run that got past its root (solved or not: then its lower bound
    /// is the best the search proved).
    pub fn report(&self) -> Option<Report> {
        *self.last.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Planner<MapfProblem> for Cbs {
    fn name(&self) -> &str {
        if self.settings.explicit_estimation {
            EECBS_NAME
        } else {
            CBS_NAME
        }
    }

    fn plan(&self, problem: &MapfProblem, ctx: &Ctx) -> Result<Plan, Unsolved> {
        let rules = problem.rules();
        if rules.semantics != GoalSemantics::Stay || !rules.allow_following {
            return Err(Unsolved::GaveUp(
                "CBS handles the grid rules only (stay at the goal, following allowed)".into(),
            ));
        }
        let mut search = Search::new(problem, self.settings, ctx)?;
        let outcome = search.run();
        *self.last.lock().unwrap_or_else(|e| e.into_inner()) = Some(search.report());
        search.free_in_background();
        let paths = outcome?;
        Ok(Plan {
            paths: paths.iter().map(|p| p.to_vec()).collect(),
        })
    }

    /// `expanded`, `generated` (constraint-tree nodes) and `lower_bound` of the last run, solved
    /// or not (a run that ran out of time proved that bound on the optimal sum of costs).
    fn notes(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut m = serde_json::Map::new();
        if let Some(r) = self.report() {
            m.insert("expanded".into(), r.expanded.into());
            m.insert("generated".into(), r.generated.into());
            m.insert("lower_bound".into(), r.lower_bound.into());
            if self.settings.heuristic == Heuristic::Wdg {
                m.insert("pair_searches".into(), r.pair_searches.into());
            }
            if self.settings.rectangle != Rectangle::Off && self.settings.prioritize {
                m.insert("rectangles".into(), r.rectangles.into());
                m.insert("rectangle_tries".into(), r.rectangle_tries.into());
            }
        }
        m
    }
}

/// A shared path.
type Path = Arc<Vec<VertexId>>;

/// A conflict between agents `a < b` at step `t`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Conflict {
    a: usize,
    b: usize,
    t: u32,
    kind: Kind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Vertex(VertexId),
    /// `a` moves `u -> v` while `b` moves `v -> u`.
    Edge(VertexId, VertexId),
}

fn at(path: &[VertexId], t: usize) -> VertexId {
    path[t.min(path.len() - 1)]
}

/// The conflicts between the paths of `a < b`, earliest first: at every step where they meet
/// (including an agent passing over the other's goal after it arrived) or swap.
fn conflicts_between(a: usize, pa: &[VertexId], b: usize, pb: &[VertexId]) -> Vec<Conflict> {
    let horizon = pa.len().max(pb.len());
    let mut out = Vec::new();
    for t in 0..horizon {
        let (va, vb) = (at(pa, t), at(pb, t));
        let kind = if va == vb {
            Kind::Vertex(va)
        } else if t > 0 && va == at(pb, t - 1) && vb == at(pa, t - 1) {
            Kind::Edge(vb, va)
        } else {
            continue;
        };
        out.push(Conflict {
            a,
            b,
            t: t as u32,
            kind,
        });
    }
    out
}

/// The earliest conflict between the paths of `a < b`.
fn first_conflict(a: usize, pa: &[VertexId], b: usize, pb: &[VertexId]) -> Option<Conflict> {
    conflicts_between(a, pa, b, pb).into_iter().next()
}

/// A constraint-tree node.
struct Node {
    parent: u32,
    /// The constraint this node added (none at the root).
    added: Option<(usize, Constraint)>,
    paths: Vec<Path>,
    lbs: Vec<u64>,
    cost: u64,
    lb: u64,
    /// Every conflict between its paths, pair by pair, each pair's earliest first (the choice
    /// of conflict and the heuristics' pairs; CBSH2-RTC keeps all of them too).
    conflicts: Vec<Conflict>,
    h_hat: f64,
    /// CBS's admissible heuristic (the CG heuristic; 0 without it).
    h: u64,
    mdds: Vec<Option<Arc<Mdd>>>,
}

impl Node {
    fn f_hat(&self) -> f64 {
        self.cost as f64 + self.h_hat
    }

    /// Frees what only an open node needs (its paths, bounds, conflicts and MDDs); its
    /// constraint and parent link stay, for its descendants' constraint chains.
    fn release(&mut self) {
        self.paths = Vec::new();
        self.lbs = Vec::new();
        self.conflicts = Vec::new();
        self.mdds = Vec::new();
    }
}

/// One run's state.
struct Search<'a> {
    problem: &'a MapfProblem,
    settings: Settings,
    ctx: &'a Ctx,
    /// Goal distances, grown lazily (memory per agent follows what its searches touch).
    dist: GoalDistances<'a>,
    nodes: Vec<Node>,
    expanded: u64,
    /// Running sums of EECBS's one-step errors, and their count.
    err_h: f64,
    err_d: f64,
    err_n: f64,
    /// Expansions at which the search next asks LaCAM for a proof that no plan exists.
    next_check: u64,
    began: Instant,
    /// WDG: the extra cost of a pair of agents under their constraints ([`Search::pair_delta`];
    /// `None`: no pair of conflict-free paths), by the pair and their sorted constraint lists.
    pair_memo: FxHashMap<PairKey, Option<u64>>,
    /// WDG: two-agent searches run (memo misses).
    pair_searches: u64,
    /// Conflicts split on rectangle barriers.
    rectangles: u64,
    /// Conflicts tried as rectangles.
    rectangle_tries: u64,
    /// The best lower bound on the optimal sum of costs proven so far.
    lower_bound: u64,
    /// Low-level distance tables around walls, shared between calls.
    blocked: std::cell::RefCell<BlockedCache>,
    /// Rectangle reasoning: the graph's grid ([`grid_of`], built on first use).
    grid: std::cell::OnceCell<Option<GridMap>>,
    /// Rectangle reasoning: distances from each agent's start (built on first use, within
    /// [`START_TABLE_BYTES`] in all).
    start_dist: Vec<Option<Arc<Vec<u32>>>>,
    start_dist_bytes: usize,
    /// The split [`Search::choose`] found by rectangle reasoning for the conflict it returned.
    rectangle_split: Option<Split>,
}

/// The two children of a split: a constraint on an agent each.
type Split = [(usize, Constraint); 2];

/// Most bytes of start-distance tables rectangle reasoning keeps (agents past it get none, so
/// their conflicts are not tried as rectangles).
const START_TABLE_BYTES: usize = 512 << 20;

/// Constraint-tree nodes from which [`Search::free_in_background`] frees them on a thread.
const BACKGROUND_FREE_NODES: usize = 10_000;

/// Most non-cardinal conflicts of a node tried as rectangles when it has no cardinal one.
const RECTANGLE_TRIES: usize = 64;

/// The grid of a graph whose vertices carry cells: the [`GridMap`] of those cells, when it
/// numbers them as the graph does (so [`GridMap::vertex_at`] answers for the graph); `None` for
/// graphs not made from a grid.
fn grid_of(graph: &mrpp_core::Graph) -> Option<GridMap> {
    let cells: Vec<(u32, u32)> = (0..graph.num_vertices() as VertexId)
        .map(|v| graph.coord(v))
        .collect::<Option<_>>()?;
    let width = cells.iter().map(|c| c.0 + 1).max()? as usize;
    let height = cells.iter().map(|c| c.1 + 1).max()? as usize;
    let mut rows = vec![vec![false; width]; height];
    for &(x, y) in &cells {
        rows[y as usize][x as usize] = true;
    }
    let map = GridMap::from_free_rows(&rows);
    let sorted = |n: &[VertexId]| {
        let mut n = n.to_vec();
        n.sort_unstable();
        n
    };
    let same = cells.iter().enumerate().all(|(v, &(x, y))| {
        let v = v as VertexId;
        map.vertex_at(i64::from(x), i64::from(y)) == Some(v)
            && sorted(map.graph().neighbors(v)) == sorted(graph.neighbors(v))
    });
    same.then_some(map)
}

/// Agents `a < b` and their sorted constraint lists.
type PairKey = (usize, usize, Vec<Constraint>, Vec<Constraint>);

/// Expansions a WDG pair's two-agent CBS may make; past them its least open sum of costs stands
/// for the pair's (a lower bound, so the heuristic stays admissible). CBSH2-RTC's sub-solver
/// stops at 4 (`CBSHeuristic::node_limit` in Jiaoyang-Li/CBSH2-RTC); mrpp uses the same.
pub const PAIR_EXPANSIONS: u64 = 4;

/// Most entries of the WDG memo before it is emptied (about 100 bytes each plus the lists).
const PAIR_MEMO_CAP: usize = 1 << 20;

/// Expansions before the first proof that no plan exists is attempted (a few milliseconds of
/// search on small instances; instances solved sooner never attempt one).
const FIRST_CHECK: u64 = 256;
/// Each attempt comes after this many times the expansions of the one before.
const CHECK_GROWTH: u64 = 4;
/// An attempt may take this fraction of the time the search has run so far, or
/// [`CHECK_MIN_TIME`] if that is more (with [`CHECK_GROWTH`], the attempts together take about a
/// third of the search's time at most, beyond the first milliseconds), and at most
/// [`CHECK_ITERATIONS`] LaCAM iterations: about 100 MB at LaCAM's 100 bytes per iteration on
/// corridors, freed when the attempt ends. Attempts on solvable instances usually end at once,
/// LaCAM finding a plan.
const CHECK_TIME_SHARE: u32 = 4;
const CHECK_MIN_TIME: Duration = Duration::from_millis(5);
const CHECK_ITERATIONS: u64 = 1 << 20;

/// What rectangle reasoning found on one rectangle ([`Search::rectangle_at`]).
enum Barriers {
    /// The split, and how many of its two barriers raise their agent's cost.
    Split(u8, Split),
    /// mrpp's conditions fail on this rectangle, or it is out of range; a smaller one may pass.
    Unproven,
    /// Neither this rectangle nor a smaller one (whose barriers are parts of these): the
    /// current paths are not both on their barriers, or a distance table is missing.
    Never,
}

/// A child that could not be made.
enum Child {
    Made(Node),
    Infeasible,
}

impl<'a> Search<'a> {
    fn new(problem: &'a MapfProblem, settings: Settings, ctx: &'a Ctx) -> Result<Self, Unsolved> {
        let inst = problem.instance();
        let mut dist = GoalDistances::new(problem.graph(), &inst.goals);
        if !dist.warm_up(&inst.starts, ctx.deadline) {
            return Err(Unsolved::TimeLimit);
        }
        if let Some(i) =
            (0..inst.num_agents()).find(|&i| dist.get(i, inst.starts[i]) == UNREACHABLE)
        {
            return Err(Unsolved::GaveUp(format!("agent {i} cannot reach its goal")));
        }
        Ok(Search {
            problem,
            settings,
            ctx,
            dist,
            nodes: Vec::new(),
            expanded: 0,
            err_h: 0.0,
            err_d: 0.0,
            err_n: 0.0,
            next_check: FIRST_CHECK,
            began: Instant::now(),
            pair_memo: FxHashMap::default(),
            pair_searches: 0,
            rectangles: 0,
            rectangle_tries: 0,
            lower_bound: 0,
            blocked: Default::default(),
            grid: std::cell::OnceCell::new(),
            start_dist: vec![None; inst.num_agents()],
            start_dist_bytes: 0,
            rectangle_split: None,
        })
    }

    fn n(&self) -> usize {
        self.problem.instance().num_agents()
    }

    /// The constraints on agent `i` at node `k` (the chain back to the root), with the negative
    /// constraints that other agents' positive ones imply.
    fn constraints_of(&self, mut k: u32, i: usize) -> Vec<Constraint> {
        let mut out = Vec::new();
        while k != u32::MAX {
            let node = &self.nodes[k as usize];
            match node.added {
                Some((j, c)) if j == i => out.extend(self.vertex_form(c)),
                Some((_, c)) => out.extend(c.implied_for_others()),
                None => {}
            }
            k = node.parent;
        }
        out
    }

    /// `c` as the searches take it: a [`Constraint::Barrier`] as its vertex constraints (the
    /// cells of it on the grid), anything else as itself.
    fn vertex_form(&self, c: Constraint) -> Vec<Constraint> {
        if !matches!(c, Constraint::Barrier { .. }) {
            return vec![c];
        }
        let Some(grid) = self.grid.get().and_then(Option::as_ref) else {
            return Vec::new();
        };
        c.barrier_cells()
            .into_iter()
            .filter_map(|(x, y, t)| {
                grid.vertex_at(i64::from(x), i64::from(y))
                    .map(|v| Constraint::Vertex { v, t })
            })
            .collect()
    }

    /// Plans agent `i` under `list` against `paths` (the other agents' paths for tie-breaking).
    fn plan_agent(
        &self,
        i: usize,
        list: &[Constraint],
        paths: &[Path],
    ) -> Result<Option<Found>, Unsolved> {
        self.plan_agent_avoiding(i, list, &AvoidanceTable::new(paths, i))
    }

    /// Plans agent `i` under `list`, ties going to fewer conflicts with `avoid`.
    fn plan_agent_avoiding(
        &self,
        i: usize,
        list: &[Constraint],
        avoid: &AvoidanceTable,
    ) -> Result<Option<Found>, Unsolved> {
        let inst = self.problem.instance();
        let constraints = Constraints::new(inst.goals[i], list);
        let d = &self.dist;
        let h = |v: VertexId| d.get(i, v);
        match focal_search(&Query {
            graph: self.problem.graph(),
            start: inst.starts[i],
            goal: inst.goals[i],
            h: &h,
            constraints: &constraints,
            avoid,
            w: self.settings.w,
            deadline: self.ctx.deadline,
            blocked: Some(&self.blocked),
        }) {
            Ok(found) => Ok(Some(found)),
            Err(NoPath::None) => Ok(None),
            Err(NoPath::TimedOut) => Err(Unsolved::TimeLimit),
        }
    }

    fn root(&mut self) -> Result<Node, Unsolved> {
        let n = self.n();
        let mut paths: Vec<Path> = (0..n).map(|_| Arc::new(Vec::new())).collect();
        let mut lbs = vec![0u64; n];
        for i in 0..n {
            // Each agent's avoidance table reads every path so far: thousands of agents make
            // the root itself long, so the limit is checked per agent.
            if self.ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            let found = self
                .plan_agent(i, &[], &paths)?
                .ok_or_else(|| Unsolved::GaveUp(format!("agent {i} cannot reach its goal")))?;
            paths[i] = Arc::new(found.path);
            lbs[i] = found.lower_bound;
        }
        let mut conflicts = Vec::new();
        for a in 0..n {
            if self.ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            for b in a + 1..n {
                conflicts.extend(conflicts_between(a, &paths[a], b, &paths[b]));
            }
        }
        let cost = paths.iter().map(|p| p.len() as u64 - 1).sum();
        let lb = lbs.iter().sum();
        Ok(Node {
            parent: u32::MAX,
            added: None,
            paths,
            lbs,
            cost,
            lb,
            h_hat: 0.0,
            h: 0,
            conflicts,
            mdds: vec![None; n],
        })
    }

    /// The child of node `k` with constraint `c` on agent `i`: agent `i` re-planned when its
    /// path breaks `c`, and (for a positive `c`) every other agent whose path breaks what `c`
    /// implies for it.
    fn child(&self, k: u32, i: usize, c: Constraint) -> Result<Child, Unsolved> {
        let parent = &self.nodes[k as usize];
        let mut paths = parent.paths.clone();
        let mut lbs = parent.lbs.clone();
        let implied = c.implied_for_others();
        let own = self.vertex_form(c);
        let mut changed = Vec::new();
        for j in 0..paths.len() {
            let broken = if j == i {
                own.iter().any(|x| !x.holds_on(&paths[j]))
            } else {
                implied.iter().any(|x| !x.holds_on(&paths[j]))
            };
            if !broken {
                continue;
            }
            let mut list = self.constraints_of(k, j);
            if j == i {
                list.extend(own.iter().copied());
            } else {
                list.extend(implied.iter().copied());
            }
            let Some(found) = self.plan_agent(j, &list, &paths)? else {
                return Ok(Child::Infeasible);
            };
            paths[j] = Arc::new(found.path);
            // A node's bound never drops below its parent's for this agent.
            lbs[j] = found.lower_bound.max(parent.lbs[j]);
            changed.push(j);
        }
        let mut conflicts: Vec<Conflict> = parent
            .conflicts
            .iter()
            .copied()
            .filter(|x| !changed.contains(&x.a) && !changed.contains(&x.b))
            .collect();
        for &i in &changed {
            for j in (0..paths.len()).filter(|j| *j != i && !(changed.contains(j) && *j < i)) {
                let (a, b) = (i.min(j), i.max(j));
                conflicts.extend(conflicts_between(a, &paths[a], b, &paths[b]));
            }
        }
        let cost = paths.iter().map(|p| p.len() as u64 - 1).sum();
        let lb = lbs.iter().sum();
        // An MDD depends on the agent's constraints and cost: agent i's and every re-planned
        // agent's are rebuilt, and with a positive constraint those of the others whose MDD
        // holds a vertex or edge the implied negative constraints forbid.
        let goals = &self.problem.instance().goals;
        let mut mdds = parent.mdds.clone();
        mdds[i] = None;
        for &j in &changed {
            mdds[j] = None;
        }
        if !implied.is_empty() {
            for (j, m) in mdds.iter_mut().enumerate() {
                if m.as_ref()
                    .is_some_and(|m| implied.iter().any(|x| m.touched_by(x, goals[j])))
                {
                    *m = None;
                }
            }
        }
        Ok(Child::Made(Node {
            parent: k,
            added: Some((i, c)),
            paths,
            lbs,
            cost,
            lb,
            conflicts,
            h_hat: 0.0,
            h: 0,
            mdds,
        }))
    }

    /// The MDD of agent `i` at node `k` (built on first use).
    fn mdd(&mut self, k: u32, i: usize) -> Arc<Mdd> {
        if let Some(m) = &self.nodes[k as usize].mdds[i] {
            return m.clone();
        }
        let inst = self.problem.instance();
        let list = self.constraints_of(k, i);
        let constraints = Constraints::new(inst.goals[i], &list);
        let cost = self.nodes[k as usize].paths[i].len() as u32 - 1;
        let d = &self.dist;
        let m = Arc::new(Mdd::build(
            self.problem.graph(),
            inst.starts[i],
            inst.goals[i],
            cost,
            &|v| d.get(i, v),
            &constraints,
        ));
        self.nodes[k as usize].mdds[i] = Some(m.clone());
        m
    }

    /// Whether agent `x` of conflict `c` at node `k` cannot avoid it without a higher cost.
    fn cardinal_for(&mut self, k: u32, c: &Conflict, x: usize) -> bool {
        let cost = self.nodes[k as usize].paths[x].len() as u32 - 1;
        let mdd = self.mdd(k, x);
        match c.kind {
            Kind::Vertex(_) => c.t >= cost || mdd.singleton(c.t),
            Kind::Edge(..) => mdd.singleton(c.t - 1) && mdd.singleton(c.t),
        }
    }

    /// The CG, DG or WDG heuristic of node `k` (Felner, Li, Boyarski, Ma, Cohen, Kumar, Koenig,
    /// "Adding heuristics to conflict-based search for multi-agent path finding", ICAPS 2018):
    /// every pair of agents with a conflict that is cardinal for both must raise the sum of
    /// costs by at least one between them, so a minimum vertex cover of the graph of those pairs
    /// is a lower bound on what resolving the node's conflicts adds ([`min_vertex_cover`]).
    ///
    /// With [`Heuristic::Dg`] a pair also counts when its agents' MDDs are dependent
    /// ([`mdd::dependent`]): no two conflict-free paths at their current costs. With
    /// [`Heuristic::Wdg`] each such pair is weighted by its extra cost ([`Search::pair_delta`])
    /// and the cover is an edge-weighted one ([`min_weighted_cover`]). `Ok(None)`: some pair has
    /// no conflict-free paths under the node's constraints, so no plan lies below the node.
    fn cover_heuristic(&mut self, k: u32) -> Result<Option<u64>, Unsolved> {
        let conflicts = self.nodes[k as usize].conflicts.clone();
        let mut edges = Vec::new();
        // One edge per pair: the pair's conflicts are consecutive in the list.
        for pair in conflicts.chunk_by(|x, y| (x.a, x.b) == (y.a, y.b)) {
            let mut cardinal = None;
            for c in pair {
                if self.cardinal_for(k, c, c.a) && self.cardinal_for(k, c, c.b) {
                    cardinal = Some(*c);
                    break;
                }
            }
            let weight = if self.settings.heuristic == Heuristic::Wdg {
                match self.pair_delta(k, &pair[0], cardinal.is_some())? {
                    Some(d) => d,
                    None => return Ok(None),
                }
            } else {
                u64::from(
                    cardinal.is_some()
                        || (self.settings.heuristic == Heuristic::Dg
                            && self.dependent(k, &pair[0])),
                )
            };
            if weight > 0 {
                edges.push((pair[0].a, pair[0].b, weight));
            }
        }
        Ok(Some(min_weighted_cover(&edges)))
    }

    /// Whether the MDDs of conflict `c`'s agents at node `k` are dependent ([`mdd::dependent`]).
    fn dependent(&mut self, k: u32, c: &Conflict) -> bool {
        let (ma, mb) = (self.mdd(k, c.a), self.mdd(k, c.b));
        mdd::dependent(self.problem.graph(), &ma, &mb)
    }

    /// How much the agents `a < b` of conflict `c` at node `k` must raise their sum of costs
    /// between them to have paths free of conflicts with each other under their constraints at
    /// `k`. 0 when no conflict of theirs is `cardinal` and their MDDs are not dependent; else a
    /// CBS over the two (standard splitting, target reasoning when the search has it, optimal
    /// low levels, best-first by sum of costs), stopped after [`PAIR_EXPANSIONS`] expansions with
    /// its least open sum of costs, which bounds the pair's from below; at least 1 for a
    /// dependent pair. `None` when every branch runs out of paths (no pair of paths
    /// exists). Memoised by the pair and its constraint lists, which siblings and cousins share
    /// (WDG, Li et al., IJCAI 2019, §4.2).
    fn pair_delta(
        &mut self,
        k: u32,
        c: &Conflict,
        cardinal: bool,
    ) -> Result<Option<u64>, Unsolved> {
        let (a, b) = (c.a, c.b);
        let sorted = |mut l: Vec<Constraint>| {
            l.sort_unstable();
            l.dedup();
            l
        };
        let key: PairKey = (
            a,
            b,
            sorted(self.constraints_of(k, a)),
            sorted(self.constraints_of(k, b)),
        );
        if let Some(&d) = self.pair_memo.get(&key) {
            return Ok(d);
        }
        if !cardinal && !self.dependent(k, c) {
            self.remember(key, Some(0));
            return Ok(Some(0));
        }
        self.pair_searches += 1;
        let node = &self.nodes[k as usize];
        let base_paths = [node.paths[a].clone(), node.paths[b].clone()];
        let base = base_paths.iter().map(|p| p.len() as u64 - 1).sum::<u64>();
        let agents = [a, b];
        // A sub-node: the constraints it added to each agent, their paths and sum of costs.
        struct Sub {
            added: [Vec<Constraint>; 2],
            paths: [Path; 2],
        }
        let count_conflicts = |p: &[Path; 2]| conflicts_between(0, &p[0], 1, &p[1]).len();
        let mut subs = vec![Sub {
            added: [Vec::new(), Vec::new()],
            paths: base_paths,
        }];
        let mut open = BinaryHeap::from([std::cmp::Reverse((
            base,
            count_conflicts(&subs[0].paths),
            0usize,
        ))]);
        let mut expansions = 0;
        let delta = loop {
            let Some(std::cmp::Reverse((cost, _, id))) = open.pop() else {
                break None;
            };
            let Some(c) = first_conflict(0, &subs[id].paths[0], 1, &subs[id].paths[1]) else {
                break Some(cost - base);
            };
            if expansions >= PAIR_EXPANSIONS {
                break Some(cost - base);
            }
            expansions += 1;
            // Each child's new constraint on each side: one agent's vertex or edge, or with
            // target reasoning the arrived agent's cost (at most t, the other kept off its goal
            // from t on; or more than t).
            let t = c.t;
            let goals = &self.problem.instance().goals;
            let holder = match c.kind {
                Kind::Vertex(v) if self.settings.target => (0..2)
                    .find(|&x| goals[agents[x]] == v && t as usize >= subs[id].paths[x].len() - 1),
                _ => None,
            };
            let children: [[Option<Constraint>; 2]; 2] = match (c.kind, holder) {
                (Kind::Vertex(v), Some(x)) => {
                    let (mut by, mut after) = ([None; 2], [None; 2]);
                    by[x] = Some(Constraint::FinishBy { goal: v, t });
                    by[1 - x] = Some(Constraint::VertexFrom { v, t });
                    after[x] = Some(Constraint::FinishAfter { t });
                    [by, after]
                }
                (Kind::Vertex(v), None) => [
                    [Some(Constraint::Vertex { v, t }), None],
                    [None, Some(Constraint::Vertex { v, t })],
                ],
                (Kind::Edge(u, v), _) => [
                    [Some(Constraint::Edge { u, v, t }), None],
                    [None, Some(Constraint::Edge { u: v, v: u, t })],
                ],
            };
            'child: for child in children {
                let mut added = subs[id].added.clone();
                let mut paths = subs[id].paths.clone();
                for side in 0..2 {
                    let Some(x) = child[side] else {
                        continue;
                    };
                    added[side].push(x);
                    if x.holds_on(&paths[side]) {
                        continue;
                    }
                    let list: Vec<Constraint> = key_list(&key, side)
                        .iter()
                        .chain(&added[side])
                        .copied()
                        .collect();
                    let other = paths[1 - side].clone();
                    let avoid = AvoidanceTable::new(std::slice::from_ref(&other), usize::MAX);
                    let Some(found) = self.plan_agent_avoiding(agents[side], &list, &avoid)? else {
                        continue 'child;
                    };
                    paths[side] = Arc::new(found.path);
                }
                let cost = paths.iter().map(|p| p.len() as u64 - 1).sum::<u64>();
                let key = (cost, count_conflicts(&paths), subs.len());
                subs.push(Sub { added, paths });
                open.push(std::cmp::Reverse(key));
            }
        };
        let delta = delta.map(|d| d.max(1));
        self.remember(key, delta);
        Ok(delta)
    }

    /// Stores a pair's extra cost in the WDG memo, emptying it first when full.
    fn remember(&mut self, key: PairKey, delta: Option<u64>) {
        if self.pair_memo.len() >= PAIR_MEMO_CAP {
            self.pair_memo.clear();
        }
        self.pair_memo.insert(key, delta);
    }

    /// The conflict to split at node `k`: cardinal, then semi-cardinal, then any; among equals a
    /// target conflict ([`Search::split`]) first, as CBSH2-RTC does, then the earliest. Without
    /// prioritisation simply the earliest.
    fn choose(&mut self, k: u32) -> Conflict {
        self.rectangle_split = None;
        let mut conflicts = self.nodes[k as usize].conflicts.clone();
        conflicts.sort_by_key(|c| (c.t, c.a, c.b));
        if !self.settings.prioritize {
            return conflicts[0];
        }
        let mut best: Option<((u8, bool), Conflict)> = None;
        for &c in &conflicts {
            let cardinality = 2
                - u8::from(self.cardinal_for(k, &c, c.a))
                - u8::from(self.cardinal_for(k, &c, c.b));
            let rank = (cardinality, self.target_holder(k, &c).is_none());
            if best.is_none_or(|(r, _)| rank < r) {
                best = Some((rank, c));
                if rank == (0, false) || (rank.0 == 0 && !self.settings.target) {
                    break;
                }
            }
        }
        let (rank, chosen) = best.expect("a node with conflicts");
        if self.settings.rectangle == Rectangle::Off || rank.0 == 0 {
            return chosen;
        }
        // No cardinal conflict: a rectangle conflict more cardinal than the best conflict is
        // split on barriers instead. CBSH2-RTC also takes one as cardinal as the best; here
        // that tripled the expansions on random-32-32-20 random-4 with 50 agents (9,632 against
        // 3,710 without rectangles; 2,486 with this rule) and made den520d with 100 agents take
        // 2,756 expansions instead of 2,070.
        let mut found: Option<(u8, Conflict, Split)> = None;
        for c in conflicts
            .iter()
            .filter(|c| matches!(c.kind, Kind::Vertex(_)))
            .take(RECTANGLE_TRIES)
        {
            if self.target_holder(k, c).is_some() {
                continue;
            }
            // Each try may build two breadth-first tables over the whole map.
            if self.ctx.deadline.expired() {
                break;
            }
            if let Some((cardinal, split)) = self.rectangle(k, c) {
                let r = 2 - cardinal;
                if r < rank.0 && found.as_ref().is_none_or(|(fr, ..)| r < *fr) {
                    found = Some((r, *c, split));
                    if r == 0 {
                        break;
                    }
                }
            }
        }
        match found {
            Some((_, c, split)) => {
                self.rectangle_split = Some(split);
                c
            }
            None => chosen,
        }
    }

    /// Distances from agent `i`'s start (`None` past [`START_TABLE_BYTES`] of tables).
    fn start_distances(&mut self, i: usize) -> Option<Arc<Vec<u32>>> {
        if let Some(d) = &self.start_dist[i] {
            return Some(d.clone());
        }
        let graph = self.problem.graph();
        let bytes = graph.num_vertices() * 4;
        if self.start_dist_bytes + bytes > START_TABLE_BYTES {
            return None;
        }
        self.start_dist_bytes += bytes;
        let d = Arc::new(mrpp_core::mapf::search::distance::bfs_distances(
            graph,
            self.problem.instance().starts[i],
        ));
        self.start_dist[i] = Some(d.clone());
        Some(d)
    }

    /// Rectangle reasoning for vertex conflict `c` at node `k` (Li, Harabor, Stuckey, Ma,
    /// Koenig, "Symmetry-breaking constraints for grid-based multi-agent path finding", AAAI
    /// 2019; CBSH2-RTC, Li et al., AIJ 2021): the number of agents (0-2) whose cost each barrier
    /// raises, and the split: a barrier on each agent. `None` when the conflict is not a
    /// rectangle conflict by the conditions below.
    ///
    /// `x` and `y` are the grid coordinates of [`mrpp_core::Graph::coord`]; "top", "row" and
    /// "column" below name the sides of the picture with `x` down and `y` across.
    ///
    /// Around the conflict at `c0`, `t0`, each agent's path is followed back and forth while it
    /// moves without waiting and without turning back on either axis; turned so that both move
    /// towards `+x` and `+y`, the segments run from `s_i` to `g_i`, and the rectangle `R` runs
    /// from `Rs = max(s1, s2)` to `Rg = min(g1, g2)` (componentwise). On the *plane* `t = K + x +
    /// y` (`K = t0 - c0.x - c0.y`) both agents are at `c0` together. The agent entering `R` from
    /// the top (`x`) gets the barrier of `R`'s bottom row, each cell at its plane time; the one
    /// from the left the barrier of `R`'s right column.
    ///
    /// The split must keep every pair of conflict-free paths in a child: a pair on both
    /// barriers must collide. CBSH2-RTC's rectangle starts and ends are points of the current
    /// paths, which a longer path need not pass; here it is ensured instead by lower bounds on
    /// arrival times (`d`, breadth-first distances from the agent's start). For the agent from
    /// the top, with `p(v) = K + x + y`: (i) `d(v) >= p(v)` on every cell of `R` (it is never
    /// early inside `R`); (ii) `d(v) > p(v)` on the column left of `R` (it cannot enter `R` from
    /// the left on the plane); (iii) `d(v) >= p(v) - 1` on the row below and the column right of
    /// `R` (it cannot step back into `R` onto the plane); (iv) its start is outside `R` or on
    /// its top row. The agent from the left: the same with rows and columns swapped. Then `t -
    /// x - y` never falls along a path, so a path at a barrier cell at its plane time was on the
    /// plane all the while it was in `R`, on a monotone staircase that entered `R` through its
    /// top side (the other's through its left side); the two staircases cross at a cell, where
    /// both are at the same plane time. The split is kept only when both current paths are on
    /// their barriers. When the conditions fail on `R`, rectangles from a start corner moved
    /// towards the conflict (a third, two thirds or all the way on each axis; `Rg` and so the
    /// barriers' lines stay) are tried, largest first, each with (i)-(iv) checked on it: the
    /// argument above needs nothing of `R` but the conditions. A barrier raises its agent's cost
    /// when every path of its MDD meets it.
    ///
    /// With [`Rectangle::Mdd`] (CBSH2-RTC's conditions) each segment is first shortened to its
    /// points farthest from the conflict where the agent's MDD has one vertex, and (i)-(iv) are
    /// not checked: every path at the current cost runs between those points as a staircase, so
    /// pairs at the current costs on both barriers collide; longer paths are not covered.
    fn rectangle(&mut self, k: u32, c: &Conflict) -> Option<(u8, Split)> {
        let Kind::Vertex(v0) = c.kind else {
            return None;
        };
        self.rectangle_tries += 1;
        let graph = self.problem.graph();
        self.grid.get_or_init(|| grid_of(graph)).as_ref()?;
        let t0 = c.t as usize;
        let agents = [c.a, c.b];
        let paths = [
            self.nodes[k as usize].paths[c.a].clone(),
            self.nodes[k as usize].paths[c.b].clone(),
        ];
        if paths.iter().any(|p| t0 >= p.len()) {
            return None;
        }
        let coord = |v: VertexId| {
            let (x, y) = graph.coord(v).expect("a grid graph");
            (i64::from(x), i64::from(y))
        };
        // The monotone segment around t0 and its signs on both axes (0: no move on that axis).
        let segment = |p: &[VertexId]| {
            let (mut sx, mut sy) = (0i64, 0i64);
            let mut fits = |t: usize| {
                let (a, b) = (coord(p[t - 1]), coord(p[t]));
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                if dx.abs() + dy.abs() != 1 {
                    return false;
                }
                for (d, s) in [(dx, &mut sx), (dy, &mut sy)] {
                    if d != 0 {
                        if *s == 0 {
                            *s = d;
                        } else if *s != d {
                            return false;
                        }
                    }
                }
                true
            };
            let mut ts = t0;
            while ts > 0 && fits(ts) {
                ts -= 1;
            }
            let mut tg = t0;
            while tg + 1 < p.len() && fits(tg + 1) {
                tg += 1;
            }
            (ts, tg, sx, sy)
        };
        let (mut s1t, mut g1t, sx1, sy1) = segment(&paths[0]);
        let (mut s2t, mut g2t, sx2, sy2) = segment(&paths[1]);
        let mdd_corners = self.settings.rectangle == Rectangle::Mdd;
        if mdd_corners {
            // CBSH2-RTC's corners: the segment's points nearest its ends where the agent's MDD
            // has one vertex, so every path at the current cost passes them at those times.
            for (side, ts, tg) in [(0, &mut s1t, &mut g1t), (1, &mut s2t, &mut g2t)] {
                let mdd = self.mdd(k, agents[side]);
                while *ts < t0 && !mdd.singleton(*ts as u32) {
                    *ts += 1;
                }
                while *tg > t0 && !mdd.singleton(*tg as u32) {
                    *tg -= 1;
                }
                if !mdd.singleton(*ts as u32) || !mdd.singleton(*tg as u32) {
                    return None;
                }
            }
        }
        let combine = |a: i64, b: i64| match (a, b) {
            (0, 0) => None,
            (0, b) => Some(b),
            (a, 0) => Some(a),
            (a, b) => (a == b).then_some(a),
        };
        let (sx, sy) = (combine(sx1, sx2)?, combine(sy1, sy2)?);
        let tr = |v: VertexId| {
            let (x, y) = coord(v);
            (sx * x, sy * y)
        };
        let (s1, g1) = (tr(paths[0][s1t]), tr(paths[0][g1t]));
        let (s2, g2) = (tr(paths[1][s2t]), tr(paths[1][g2t]));
        let rs = (s1.0.max(s2.0), s1.1.max(s2.1));
        let rg = (g1.0.min(g2.0), g1.1.min(g2.1));
        if rs.0 > rg.0 || rs.1 > rg.1 || rs == rg {
            return None;
        }
        if (rg.0 - rs.0 + 1) * (rg.1 - rs.1 + 1) > 10_000 {
            return None;
        }
        let (top, left) = if s1.0 <= s2.0 && s1.1 >= s2.1 {
            (0, 1)
        } else if s2.0 <= s1.0 && s2.1 >= s1.1 {
            (1, 0)
        } else {
            return None;
        };
        let c0 = tr(v0);
        let kk = t0 as i64 - c0.0 - c0.1;
        // The rectangle's start corner: with mrpp's conditions, Rs and, when they fail there,
        // corners moved towards the conflict (a smaller rectangle, where the conditions are
        // checked afresh: the argument holds for any rectangle they hold on), largest first.
        let mut corners = vec![rs];
        if !mdd_corners {
            let steps = |lo: i64, hi: i64| {
                let d = hi - lo;
                let mut v = vec![lo, lo + (d + 2) / 3, lo + (2 * d + 2) / 3, hi];
                v.dedup();
                v
            };
            for x in steps(rs.0, c0.0.clamp(rs.0, rg.0)) {
                for y in steps(rs.1, c0.1.clamp(rs.1, rg.1)) {
                    if (x, y) != rs && (x, y) != rg {
                        corners.push((x, y));
                    }
                }
            }
            corners[1..].sort_by_key(|&(x, y)| std::cmp::Reverse((rg.0 - x + 1) * (rg.1 - y + 1)));
        }
        let starts = &self.problem.instance().starts;
        let starts = [tr(starts[agents[0]]), tr(starts[agents[1]])];
        for rs in corners {
            match self.rectangle_at(k, agents, &paths, starts, (top, left), rs, rg, (sx, sy), kk) {
                Barriers::Split(cardinal, split) => return Some((cardinal, split)),
                Barriers::Unproven => {}
                Barriers::Never => return None,
            }
        }
        None
    }

    /// [`Search::rectangle`] on the rectangle from `rs` to `rg` (turned coordinates, signs
    /// `sx`, `sy`, in which the agents' starts are `starts`; plane offset `kk`): see
    /// [`Barriers`].
    #[allow(clippy::too_many_arguments)]
    fn rectangle_at(
        &mut self,
        k: u32,
        agents: [usize; 2],
        paths: &[Path; 2],
        starts: [(i64, i64); 2],
        (top, left): (usize, usize),
        rs: (i64, i64),
        rg: (i64, i64),
        (sx, sy): (i64, i64),
        kk: i64,
    ) -> Barriers {
        if kk + rs.0 + rs.1 < 0 {
            return Barriers::Unproven;
        }
        let top_len = rg.1 - rs.1 + 1;
        let left_len = rg.0 - rs.0 + 1;
        if top_len > i64::from(u16::MAX) || left_len > i64::from(u16::MAX) {
            return Barriers::Unproven;
        }
        let plane = |p: (i64, i64)| kk + p.0 + p.1;
        let barrier = |from: (i64, i64), along_x: bool, len: i64| Constraint::Barrier {
            x: (sx * from.0) as u32,
            y: (sy * from.1) as u32,
            t: plane(from) as u32,
            len: len as u16,
            dir: match (along_x, if along_x { sx } else { sy } > 0) {
                (true, true) => 0,
                (true, false) => 1,
                (false, true) => 2,
                (false, false) => 3,
            },
        };
        let split = [
            (agents[top], barrier((rg.0, rs.1), false, top_len)),
            (agents[left], barrier((rs.0, rg.1), true, left_len)),
        ];
        // Each barrier's (vertex, time) cells, as the searches will take them; the split is of
        // use only when both current paths are on their barriers (checked first: it is cheap).
        let cells = |c: Constraint| -> Vec<(VertexId, u32)> {
            self.vertex_form(c)
                .into_iter()
                .filter_map(|x| match x {
                    Constraint::Vertex { v, t } => Some((v, t)),
                    _ => None,
                })
                .collect()
        };
        let (top_cells, left_cells) = (cells(split[0].1), cells(split[1].1));
        let on = |p: &[VertexId], cells: &[(VertexId, u32)]| {
            cells.iter().any(|&(v, t)| at(p, t as usize) == v)
        };
        if !on(&paths[top], &top_cells) || !on(&paths[left], &left_cells) {
            return Barriers::Never;
        }
        // mrpp's conditions (`Rectangle::Proven`, above).
        if self.settings.rectangle != Rectangle::Mdd {
            let (Some(d0), Some(d1)) = (
                self.start_distances(agents[0]),
                self.start_distances(agents[1]),
            ) else {
                return Barriers::Never;
            };
            let dists = [d0, d1];
            let Some(grid) = self.grid.get().and_then(Option::as_ref) else {
                return Barriers::Never;
            };
            let vertex = |p: (i64, i64)| grid.vertex_at(sx * p.0, sy * p.1);
            let sound = |side: usize, from_top: bool| {
                let d = &dists[side];
                let early = |p: (i64, i64), slack: i64| {
                    vertex(p).is_some_and(|v| {
                        let dv = d[v as usize];
                        dv != UNREACHABLE && i64::from(dv) < plane(p) + slack
                    })
                };
                for x in rs.0..=rg.0 {
                    for y in rs.1..=rg.1 {
                        if early((x, y), 0) {
                            return false;
                        }
                    }
                }
                let side_in = if from_top {
                    (rs.0..=rg.0).any(|x| early((x, rs.1 - 1), 1))
                } else {
                    (rs.1..=rg.1).any(|y| early((rs.0 - 1, y), 1))
                };
                if side_in
                    || (rs.1..=rg.1).any(|y| early((rg.0 + 1, y), -1))
                    || (rs.0..=rg.0).any(|x| early((x, rg.1 + 1), -1))
                {
                    return false;
                }
                let st = starts[side];
                let inside = (rs.0..=rg.0).contains(&st.0) && (rs.1..=rg.1).contains(&st.1);
                !inside || (from_top && st.0 == rs.0) || (!from_top && st.1 == rs.1)
            };
            if !sound(top, true) || !sound(left, false) {
                return Barriers::Unproven;
            }
        }
        let mut cardinal = 0;
        for (side, cells) in [(top, &top_cells), (left, &left_cells)] {
            let mdd = self.mdd(k, agents[side]);
            if mdd.blocked_by(self.problem.graph(), cells) {
                cardinal += 1;
            }
        }
        Barriers::Split(cardinal, split)
    }

    /// The agent of a *target conflict* `c` at node `k`: the one already on its goal for good
    /// where the other passes at `c.t` (`None` for other conflicts, or without target
    /// reasoning).
    fn target_holder(&self, k: u32, c: &Conflict) -> Option<usize> {
        let Kind::Vertex(v) = c.kind else {
            return None;
        };
        if !self.settings.target {
            return None;
        }
        let goals = &self.problem.instance().goals;
        let paths = &self.nodes[k as usize].paths;
        [c.a, c.b]
            .into_iter()
            .find(|&x| goals[x] == v && c.t as usize >= paths[x].len() - 1)
    }

    /// The two constraints that split conflict `c` of node `k`: one on each agent, or with
    /// disjoint splitting (Li et al., ICAPS 2019) a negative and a positive one on agent `a`,
    /// whose children share no solution. With target reasoning a *target conflict* (one agent
    /// `x` already on its goal for good, the other passing over it at `t`) splits on `x`'s cost:
    /// at most `t` (then no agent may be on that goal from `t` on) or more than `t` (Li, Gange,
    /// Harabor, Stuckey, Ma, Koenig, "New techniques for pairwise symmetry breaking in
    /// multi-agent path finding", ICAPS 2020, §5), so the other agent's detours and `x`'s later
    /// arrivals are not searched one time step at a time.
    fn split(&self, k: u32, c: &Conflict) -> Split {
        let t = c.t;
        if let Some(x) = self.target_holder(k, c) {
            let goal = self.problem.instance().goals[x];
            return [
                (x, Constraint::FinishBy { goal, t }),
                (x, Constraint::FinishAfter { t }),
            ];
        }
        match (c.kind, self.settings.disjoint) {
            (Kind::Vertex(v), false) => [
                (c.a, Constraint::Vertex { v, t }),
                (c.b, Constraint::Vertex { v, t }),
            ],
            (Kind::Edge(u, v), false) => [
                (c.a, Constraint::Edge { u, v, t }),
                (c.b, Constraint::Edge { u: v, v: u, t }),
            ],
            (Kind::Vertex(v), true) => [
                (c.a, Constraint::Vertex { v, t }),
                (c.a, Constraint::AtVertex { v, t }),
            ],
            (Kind::Edge(u, v), true) => [
                (c.a, Constraint::Edge { u, v, t }),
                (c.a, Constraint::Traverses { u, v, t }),
            ],
        }
    }

    /// Expands node `k`: its children (after any bypasses, which change `k` in place), or
    /// `Ok(None)` when a bypass left `k` without conflicts (a solution).
    fn expand(&mut self, k: u32) -> Result<Option<Vec<Node>>, Unsolved> {
        'again: loop {
            if self.nodes[k as usize].conflicts.is_empty() {
                return Ok(None);
            }
            self.expanded += 1;
            let c = self.choose(k);
            let split = match self.rectangle_split.take() {
                Some(split) => {
                    self.rectangles += 1;
                    split
                }
                None => self.split(k, &c),
            };
            let mut children = Vec::new();
            for (i, constraint) in split {
                let Child::Made(child) = self.child(k, i, constraint)? else {
                    continue;
                };
                let parent = &self.nodes[k as usize];
                if self.settings.bypass
                    && child.cost <= parent.cost
                    && child.conflicts.len() < parent.conflicts.len()
                {
                    let parent = &mut self.nodes[k as usize];
                    for j in 0..child.paths.len() {
                        if !Arc::ptr_eq(&parent.paths[j], &child.paths[j]) {
                            parent.paths[j] = child.paths[j].clone();
                            parent.mdds[j] = None;
                        }
                    }
                    parent.cost = child.cost;
                    parent.conflicts = child.conflicts;
                    continue 'again;
                }
                children.push(child);
            }
            return Ok(Some(children));
        }
    }

    /// A proof by LaCAM's exhaustive search that no plan exists
    /// ([`crate::lacam::proven_unsolvable`]), within a share of the time run so far
    /// ([`CHECK_TIME_SHARE`]). The constraint tree of an unsolvable instance is infinite: without
    /// it a 10-cell corridor swap grew CBS to 4.6 GB by its 60 s limit (issue 27, item 4).
    fn proven_unsolvable(&self) -> Option<String> {
        let inst = self.problem.instance();
        let until = Instant::now() + (self.began.elapsed() / CHECK_TIME_SHARE).max(CHECK_MIN_TIME);
        crate::lacam::proven_unsolvable(
            self.problem.graph(),
            &inst.starts,
            &inst.goals,
            self.ctx,
            CHECK_ITERATIONS,
            until,
        )
    }

    /// EECBS's online estimate for a node with `d` conflicts.
    fn h_hat(&self, d: usize) -> f64 {
        if self.err_n == 0.0 {
            return 0.0;
        }
        let (eh, ed) = (self.err_h / self.err_n, self.err_d / self.err_n);
        d as f64 * eh.max(0.0) / (1.0 - ed).max(0.1)
    }

    /// Hands a long search's constraint tree and WDG memo to a thread that frees them, so that
    /// the run ends at its time limit: freeing them takes seconds (the open nodes' paths and MDDs;
    /// 0.93 s after a 30 s run on random-32-32-20 with 70 agents, 68,000 open nodes). Short
    /// searches (fewer than [`BACKGROUND_FREE_NODES`] nodes), or when no thread can be started,
    /// free them here.
    fn free_in_background(&mut self) {
        if self.nodes.len() < BACKGROUND_FREE_NODES {
            return;
        }
        let nodes = std::mem::take(&mut self.nodes);
        let memo = std::mem::take(&mut self.pair_memo);
        // On failure the closure, and with it what it holds, is dropped here.
        let _ = std::thread::Builder::new()
            .name("cbs-free".into())
            .spawn(move || drop((nodes, memo)));
    }

    /// What the search has done so far.
    fn report(&self) -> Report {
        Report {
            expanded: self.expanded,
            generated: self.nodes.len() as u64,
            lower_bound: self.lower_bound,
            pair_searches: self.pair_searches,
            rectangles: self.rectangles,
            rectangle_tries: self.rectangle_tries,
        }
    }

    /// The search: the optimal (or `w`-bounded) paths, or why there are none.
    fn run(&mut self) -> Result<Vec<Path>, Unsolved> {
        let root = self.root()?;
        self.nodes.push(root);
        // CBS: min-heap on (cost, conflicts, id). EECBS: its three lists.
        let mut heap: BinaryHeap<std::cmp::Reverse<(u64, usize, u32)>> = BinaryHeap::new();
        let mut lists = Lists::new(self.settings.w);
        let push = |s: &Self, id: u32, heap: &mut BinaryHeap<_>, lists: &mut Lists| {
            let n = &s.nodes[id as usize];
            if s.settings.explicit_estimation {
                lists.insert(&s.nodes, id);
            } else {
                heap.push(std::cmp::Reverse((n.cost + n.h, n.conflicts.len(), id)));
            }
        };
        push(self, 0, &mut heap, &mut lists);
        loop {
            if self.ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            if self.expanded >= self.next_check {
                self.next_check = self.expanded.saturating_mul(CHECK_GROWTH);
                if let Some(why) = self.proven_unsolvable() {
                    return Err(Unsolved::GaveUp(why));
                }
            }
            let k = if self.settings.explicit_estimation {
                let Some(k) = lists.select(&self.nodes) else {
                    break;
                };
                lists.remove(&self.nodes, k);
                k
            } else {
                let Some(std::cmp::Reverse((_, _, k))) = heap.pop() else {
                    break;
                };
                k
            };
            // The proven bound: the least LB of the open nodes (k's included) for EECBS, the
            // popped cost for CBS.
            let lower_bound = if self.settings.explicit_estimation {
                lists.lb_min().map_or(self.nodes[k as usize].lb, |lb| {
                    lb.min(self.nodes[k as usize].lb)
                })
            } else {
                self.nodes[k as usize].cost + self.nodes[k as usize].h
            };
            if self.expanded.is_multiple_of(256) {
                self.ctx.report(Progress {
                    stage: "constraint-tree nodes",
                    done: self.expanded,
                    total: 0,
                    note: format!("sum of costs >= {lower_bound}"),
                });
            }
            self.lower_bound = self.lower_bound.max(lower_bound);
            let Some(children) = self.expand(k)? else {
                self.lower_bound = lower_bound;
                return Ok(self.nodes[k as usize].paths.clone());
            };
            if self.settings.explicit_estimation
                && let Some(best) = children.iter().min_by_key(|c| (c.cost, c.conflicts.len()))
            {
                let parent = &self.nodes[k as usize];
                self.err_h += best.cost as f64 - parent.cost as f64;
                self.err_d += best.conflicts.len() as f64 - (parent.conflicts.len() as f64 - 1.0);
                self.err_n += 1.0;
            }
            let (parent_cost, parent_h) = {
                let p = &self.nodes[k as usize];
                (p.cost, p.h)
            };
            for mut child in children {
                child.h_hat = self.h_hat(child.conflicts.len());
                let id = self.nodes.len() as u32;
                self.nodes.push(child);
                if self.settings.heuristic != Heuristic::None && !self.settings.explicit_estimation
                {
                    let Some(h) = self.cover_heuristic(id)? else {
                        // No plan below this node: it is never opened, so it keeps nothing
                        // but its place in the tree.
                        self.nodes[id as usize].release();
                        continue;
                    };
                    // Path-max: what the parent's heuristic proved still holds below it, less
                    // what the child's cost has already paid of it.
                    let child = &mut self.nodes[id as usize];
                    let paid = child.cost.saturating_sub(parent_cost);
                    child.h = h.max(parent_h.saturating_sub(paid));
                }
                push(self, id, &mut heap, &mut lists);
            }
            // An expanded node is never expanded again and its children hold what they need
            // (their own paths, bounds, conflicts and shared MDDs); only its constraint and
            // parent link stay, for its descendants' constraint chains. This halves the memory of
            // a long search (as many expanded nodes as open ones).
            self.nodes[k as usize].release();
        }
        Err(Unsolved::GaveUp(
            "every constraint set was refuted: the instance has no solution".into(),
        ))
    }
}

/// The constraint list of side `0` (agent `a`) or `1` (agent `b`) of a pair's memo key.
fn key_list(key: &PairKey, side: usize) -> &[Constraint] {
    if side == 0 { &key.2 } else { &key.3 }
}

/// Most agents of one connected component [`min_weighted_cover`] covers exactly.
const EXACT_WEIGHTED_AGENTS: usize = 8;

/// The least `Σ x_i` over whole numbers `x_i >= 0`, one per agent, with `x_a + x_b >= w` for
/// every edge `(a, b, w)`: the edge-weighted minimum vertex cover of the WDG heuristic (Li et
/// al., IJCAI 2019, §4.3). Each connected component is solved on its own: exactly by branch
/// and bound up to [`EXACT_WEIGHTED_AGENTS`] agents (each agent's value from what its earlier
/// neighbours leave uncovered up to its heaviest edge), above that by the larger of two lower
/// bounds, a greedy matching's weight and the unweighted minimum cover ([`min_vertex_cover`];
/// every edge weighs at least 1), so the heuristic stays admissible. With every weight 1 it is
/// [`min_vertex_cover`].
fn min_weighted_cover(edges: &[(usize, usize, u64)]) -> u64 {
    // Components by union-find over the agents that appear.
    let mut agents: Vec<usize> = edges.iter().flat_map(|&(a, b, _)| [a, b]).collect();
    agents.sort_unstable();
    agents.dedup();
    let index = |x: usize| agents.binary_search(&x).expect("an agent of an edge");
    let mut parent: Vec<usize> = (0..agents.len()).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for &(a, b, _) in edges {
        let (ra, rb) = (find(&mut parent, index(a)), find(&mut parent, index(b)));
        parent[ra] = rb;
    }
    let mut components: FxHashMap<usize, Vec<(usize, usize, u64)>> = FxHashMap::default();
    for &(a, b, w) in edges {
        let r = find(&mut parent, index(a));
        components
            .entry(r)
            .or_default()
            .push((index(a), index(b), w));
    }
    let mut total = 0;
    let mut roots: Vec<usize> = components.keys().copied().collect();
    roots.sort_unstable();
    for r in roots {
        let comp = &components[&r];
        let mut members: Vec<usize> = comp.iter().flat_map(|&(a, b, _)| [a, b]).collect();
        members.sort_unstable();
        members.dedup();
        total += if members.len() <= EXACT_WEIGHTED_AGENTS {
            exact_weighted_cover(&members, comp)
        } else {
            let unit: Vec<(usize, usize)> = comp.iter().map(|&(a, b, _)| (a, b)).collect();
            let mut by_weight = comp.clone();
            by_weight.sort_by_key(|&(a, b, w)| (std::cmp::Reverse(w), a, b));
            let mut used = BTreeSet::new();
            let mut matched = 0;
            for (a, b, w) in by_weight {
                if !used.contains(&a) && !used.contains(&b) {
                    used.insert(a);
                    used.insert(b);
                    matched += w;
                }
            }
            matched.max(min_vertex_cover(&unit))
        };
    }
    total
}

/// [`min_weighted_cover`] of one small component, exactly: `members` its agents, `edges` its
/// edges.
fn exact_weighted_cover(members: &[usize], edges: &[(usize, usize, u64)]) -> u64 {
    let n = members.len();
    let at = |x: usize| members.binary_search(&x).expect("a member");
    let mut w = vec![vec![0u64; n]; n];
    for &(a, b, wt) in edges {
        let (i, j) = (at(a), at(b));
        w[i][j] = w[i][j].max(wt);
        w[j][i] = w[i][j];
    }
    let heaviest: Vec<u64> = w.iter().map(|r| *r.iter().max().expect("n > 0")).collect();
    fn search(i: usize, sum: u64, x: &mut Vec<u64>, w: &[Vec<u64>], top: &[u64], best: &mut u64) {
        if sum >= *best {
            return;
        }
        if i == w.len() {
            *best = sum;
            return;
        }
        let need = (0..i)
            .map(|j| w[i][j].saturating_sub(x[j]))
            .max()
            .unwrap_or(0);
        for value in need..=top[i].max(need) {
            x[i] = value;
            search(i + 1, sum + value, x, w, top, best);
        }
    }
    // Giving every agent its heaviest edge covers everything.
    let mut best = heaviest.iter().sum();
    search(0, 0, &mut vec![0; n], &w, &heaviest, &mut best);
    best
}

/// Largest number of edges [`min_vertex_cover`] covers exactly; above it, a maximal matching's
/// size (also a lower bound).
const EXACT_COVER_EDGES: usize = 40;

/// The size of a minimum vertex cover of the graph of `edges` (agent pairs), exactly up to
/// [`EXACT_COVER_EDGES`] edges (branching on a vertex of largest degree: take it, or take all its
/// neighbours), else the size of a greedy maximal matching, which no cover is smaller than.
fn min_vertex_cover(edges: &[(usize, usize)]) -> u64 {
    fn matching(edges: &[(usize, usize)]) -> u64 {
        let mut used = BTreeSet::new();
        let mut m = 0;
        for &(a, b) in edges {
            if !used.contains(&a) && !used.contains(&b) {
                used.insert(a);
                used.insert(b);
                m += 1;
            }
        }
        m
    }
    fn exact(edges: &[(usize, usize)], best: u64) -> u64 {
        if edges.is_empty() {
            return 0;
        }
        let lower = matching(edges);
        if lower >= best {
            return best;
        }
        let mut degree: FxHashMap<usize, usize> = FxHashMap::default();
        for &(a, b) in edges {
            *degree.entry(a).or_default() += 1;
            *degree.entry(b).or_default() += 1;
        }
        let (&v, _) = degree
            .iter()
            .max_by_key(|&(&v, &d)| (d, std::cmp::Reverse(v)))
            .expect("edges");
        // Take v.
        let rest: Vec<(usize, usize)> = edges
            .iter()
            .copied()
            .filter(|&(a, b)| a != v && b != v)
            .collect();
        let mut best = best.min(1 + exact(&rest, best.saturating_sub(1)));
        // Or take every neighbour of v.
        let nbrs: BTreeSet<usize> = edges
            .iter()
            .filter_map(|&(a, b)| {
                if a == v {
                    Some(b)
                } else if b == v {
                    Some(a)
                } else {
                    None
                }
            })
            .collect();
        let k = nbrs.len() as u64;
        if k < best {
            let rest: Vec<(usize, usize)> = edges
                .iter()
                .copied()
                .filter(|&(a, b)| !nbrs.contains(&a) && !nbrs.contains(&b))
                .collect();
            best = best.min(k + exact(&rest, best - k));
        }
        best
    }
    if edges.len() > EXACT_COVER_EDGES {
        return matching(edges);
    }
    exact(edges, edges.len() as u64)
}

/// EECBS's three lists over the open constraint-tree nodes (EECBS §4.2): CLEANUP by lower bound
/// `LB`, OPEN by `f̂`, and FOCAL, the open nodes with `f̂ <= w · f̂_min`, by conflicts (then `f̂`,
/// then id). FOCAL is kept up to date as nodes come and go and as `f̂_min` moves (the strip of
/// OPEN between the old and the new bound joins or leaves it), so choosing a node costs
/// `O(log n)`: rebuilding FOCAL from OPEN at every expansion cost `O(|OPEN|)`, which slowed the
/// search to a crawl as OPEN grew (issue 27, item 4).
///
/// `f̂` is never negative, so the order of its bit patterns is its numeric order.
struct Lists {
    w: f64,
    /// (LB, id).
    cleanup: BTreeSet<(u64, u32)>,
    /// (f̂ bits, id).
    open: BTreeSet<(u64, u32)>,
    /// (conflicts, f̂ bits, id) of the open nodes with `f̂ <= bound`.
    focal: BTreeSet<(usize, u64, u32)>,
    /// Bits of `w · f̂_min + 1e-9` (the tolerance of the float product), `None` while OPEN is
    /// empty.
    bound: Option<u64>,
}

impl Lists {
    fn new(w: f64) -> Self {
        Lists {
            w,
            cleanup: BTreeSet::new(),
            open: BTreeSet::new(),
            focal: BTreeSet::new(),
            bound: None,
        }
    }

    fn focal_key(nodes: &[Node], id: u32) -> (usize, u64, u32) {
        let n = &nodes[id as usize];
        (n.conflicts.len(), n.f_hat().to_bits(), id)
    }

    fn insert(&mut self, nodes: &[Node], id: u32) {
        let n = &nodes[id as usize];
        let f = n.f_hat().to_bits();
        self.cleanup.insert((n.lb, id));
        self.open.insert((f, id));
        if self.bound.is_some_and(|b| f <= b) {
            self.focal.insert(Self::focal_key(nodes, id));
        }
        self.rebound(nodes);
    }

    fn remove(&mut self, nodes: &[Node], id: u32) {
        let n = &nodes[id as usize];
        self.cleanup.remove(&(n.lb, id));
        self.open.remove(&(n.f_hat().to_bits(), id));
        self.focal.remove(&Self::focal_key(nodes, id));
        self.rebound(nodes);
    }

    /// Moves FOCAL's bound to `w · f̂_min` of the current OPEN.
    fn rebound(&mut self, nodes: &[Node]) {
        use std::ops::Bound::{Excluded, Included, Unbounded};
        let new = self
            .open
            .first()
            .map(|&(f, _)| (f64::from_bits(f) * self.w + 1e-9).to_bits());
        match (self.bound, new) {
            (old, Some(new)) if old.is_none_or(|old| new > old) => {
                let from = old.map_or(Unbounded, |old| Excluded((old, u32::MAX)));
                for &(_, id) in self.open.range((from, Included((new, u32::MAX)))) {
                    self.focal.insert(Self::focal_key(nodes, id));
                }
            }
            (Some(old), Some(new)) if new < old => {
                let strip = (Excluded((new, u32::MAX)), Included((old, u32::MAX)));
                for &(_, id) in self.open.range(strip) {
                    self.focal.remove(&Self::focal_key(nodes, id));
                }
            }
            (_, None) => debug_assert!(self.focal.is_empty()),
            _ => {}
        }
        self.bound = new;
    }

    /// The least LB of the open nodes.
    fn lb_min(&self) -> Option<u64> {
        self.cleanup.first().map(|&(lb, _)| lb)
    }

    /// EECBS's choice: the first of FOCAL if its cost is within `w · LB_min`, else the first of
    /// OPEN if within, else the first of CLEANUP; `None` when no node is open.
    fn select(&self, nodes: &[Node]) -> Option<u32> {
        let &(lb_min, best_lb) = self.cleanup.first()?;
        let &(_, best_f) = self.open.first().expect("same nodes as CLEANUP");
        let &(_, _, best_d) = self.focal.first().expect("the first of OPEN is in FOCAL");
        let within = |id: u32| nodes[id as usize].cost as f64 <= self.w * lb_min as f64 + 1e-9;
        Some(if within(best_d) {
            best_d
        } else if within(best_f) {
            best_f
        } else {
            best_lb
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::mapf::graph::Graph;
    use mrpp_core::{Deadline, Instance, Rules, solve};

    #[test]
    fn plus_needs_one_split_and_costs_five() {
        // Baselines §7: the plus, centre 0, W=1 E=2 N=3 S=4; W->E and S->N.
        let g = Graph::from_edges(5, &[(0, 1), (0, 2), (0, 3), (0, 4)]);
        let inst = Instance::new(vec![1, 4], vec![2, 3]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        for planner in [Cbs::optimal(), Cbs::eecbs(1.0), Cbs::eecbs(1.5)] {
            let s = solve(&planner, &p, &Ctx::new(0, Deadline::none())).unwrap();
            assert_eq!(s.metrics.sum_of_costs, 5, "{}", planner.name());
        }
        let cbs = Cbs::optimal();
        solve(&cbs, &p, &Ctx::default()).unwrap();
        assert_eq!(cbs.report().unwrap().expanded, 1);
    }
}

#[cfg(test)]
mod cover_tests {
    use super::{min_vertex_cover, min_weighted_cover};

    #[test]
    fn minimum_vertex_covers_of_small_graphs() {
        assert_eq!(min_vertex_cover(&[]), 0);
        assert_eq!(min_vertex_cover(&[(0, 1)]), 1);
        assert_eq!(min_vertex_cover(&[(0, 1), (1, 2), (0, 2)]), 2); // triangle
        assert_eq!(min_vertex_cover(&[(0, 1), (0, 2), (0, 3), (0, 4)]), 1); // star
        assert_eq!(min_vertex_cover(&[(0, 1), (1, 2), (2, 3), (3, 4)]), 2); // path
        assert_eq!(min_vertex_cover(&[(0, 1), (2, 3)]), 2);
        // A 5-cycle needs 3; K4 needs 3.
        assert_eq!(
            min_vertex_cover(&[(0, 1), (1, 2), (2, 3), (3, 4), (4, 0)]),
            3
        );
        let k4: Vec<(usize, usize)> = (0..4)
            .flat_map(|a| (a + 1..4).map(move |b| (a, b)))
            .collect();
        assert_eq!(min_vertex_cover(&k4), 3);
        // Above the exact size, a maximal matching: never more than the cover.
        let many: Vec<(usize, usize)> = (0..50).map(|i| (i, i + 100)).collect();
        assert_eq!(min_vertex_cover(&many), 50);
    }

    #[test]
    fn weighted_covers_of_small_graphs() {
        assert_eq!(min_weighted_cover(&[]), 0);
        assert_eq!(min_weighted_cover(&[(3, 7, 2)]), 2);
        // A path a-b-c weighted 2 and 3: b takes 3 (2 + 1 would leave c's edge short).
        assert_eq!(min_weighted_cover(&[(0, 1, 2), (1, 2, 3)]), 3);
        // A triangle of 2s: 1 each.
        assert_eq!(min_weighted_cover(&[(0, 1, 2), (1, 2, 2), (0, 2, 2)]), 3);
        // A star of 1s with one heavy spoke: the centre takes 1, the heavy leaf 4.
        assert_eq!(
            min_weighted_cover(&[(0, 1, 1), (0, 2, 1), (0, 3, 5), (0, 4, 1)]),
            5
        );
        // Two components add up.
        assert_eq!(min_weighted_cover(&[(0, 1, 2), (5, 6, 3)]), 5);
        // Unit weights: the unweighted cover, exact or not.
        let cycle = [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 4, 1), (4, 0, 1)];
        assert_eq!(min_weighted_cover(&cycle), 3);
        let path: Vec<(usize, usize, u64)> = (0..12).map(|i| (i, i + 1, 1)).collect();
        assert_eq!(min_weighted_cover(&path), 6);
        // Above the exact size the bound never exceeds the optimum: a 12-agent path of 2s
        // needs 12 (x = 2 on every other agent); the matching of 6 edges gives 12.
        let heavy: Vec<(usize, usize, u64)> = (0..11).map(|i| (i, i + 1, 2)).collect();
        assert!(min_weighted_cover(&heavy) <= 12);
        assert!(min_weighted_cover(&heavy) >= 10);
    }

    /// The exact cover is the least sum over every assignment of 0..=3 to 5 agents, on random
    /// weighted graphs.
    #[test]
    fn the_exact_weighted_cover_is_the_brute_force_one() {
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            seed >> 33
        };
        for _ in 0..200 {
            let mut edges = Vec::new();
            for a in 0..5 {
                for b in a + 1..5 {
                    if next() % 2 == 0 {
                        edges.push((a, b, 1 + next() % 3));
                    }
                }
            }
            let mut best = u64::MAX;
            for code in 0..4u64.pow(5) {
                let x: Vec<u64> = (0..5).map(|i| (code / 4u64.pow(i)) % 4).collect();
                if edges.iter().all(|&(a, b, w)| x[a] + x[b] >= w) {
                    best = best.min(x.iter().sum());
                }
            }
            assert_eq!(min_weighted_cover(&edges), best, "{edges:?}");
        }
    }
}
