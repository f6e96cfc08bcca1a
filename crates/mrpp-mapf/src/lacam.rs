//! LaCAM and LaCAM*: lazy constraints addition search for MAPF (K. Okumura, "LaCAM: search-based
//! algorithm for quick multi-agent pathfinding", AAAI 2023; "Improving LaCAM for scalable
//! eventually optimal multi-agent pathfinding", IJCAI 2023), baselines §7, with [`crate::pibt`]
//! as the configuration generator.
//!
//! A depth-first search over configurations (one vertex per agent). Each configuration node keeps
//! agent priorities (distance / agents at the start, +1 per step off the goal, back to the
//! fractional part on it), the agent order they give, and a queue of low-level constraint nodes,
//! each fixing the next vertices of the first `d` agents of that order. Taking a constraint node
//! from the top configuration expands its children (the next agent in the order, at each of its
//! neighbours and its own vertex, in a seeded random order) and asks PIBT for a successor
//! configuration that obeys the constraint. mrpp leaves out the children whose own agents
//! collide (two on one vertex, or a swap; `-p prune=true`, the default): every extension of
//! such a constraint fails before PIBT runs, yet LaCAM as published (and lacam0) queues them
//! and spends an iteration on each, 5^d of them at depth d on a grid. On maze-128-128-1 (a tree
//! of one-cell corridors) with 700 agents, they were 97-100% of the iterations once the search
//! stalled; pruning them raised the runs solved within 30 s with 700-1,000 agents, seeds 0-5,
//! from 7 to 11 of 42 (docs/benchmark.md). A successor seen before is pushed again instead of
//! being created, or, with probability `restart_rate` (0.001), the start configuration is pushed
//! instead (a random restart, as in the authors' lacam0 and LaCAM*, IJCAI 2023: the search then
//! tries the start's other successors with the random stream where it is, which cuts LaCAM's
//! heavy-tailed runtimes short: room-32-32-4 with 341 agents took over 30 s with seed 1 and 38 ms
//! with seed 0 when only LaCAM* restarted; with restarts 8 seeds of 8 solved it, in 15-473 ms,
//! docs/benchmark.md). A configuration whose constraint queue runs dry leaves the stack.
//!
//! mrpp's *stall restarts* (`-p stall_restart=500`, the default; `0` = never, as published):
//! before the first plan, once that many iterations in a row have created no configuration, the
//! search starts again from the start configuration with every configuration forgotten (the
//! random stream goes on, so the new search differs), and the limit doubles. On maze-128-128-1
//! (one-cell corridors) the seeds that solve do so mostly within seconds and those that stall
//! stay stalled (with 750 agents, 13 of 24 seeds solved within 6 s, 3 of 6 within 30 s); with
//! restarts each stall becomes a fresh try: 750 agents, seeds 0-5, 30 s, 6 of 6 solved at limits
//! 100, 500 and 2,000, and 750-850 agents together 6 of 18 without, 9, 11 and 7 of 18 at those
//! limits; 700-850 agents 11 of 24 without, 17 of 24 at 500 (docs/benchmark.md). The slice of
//! the MovingAI benchmark went from 510 to 512 of 516 instances solved. A stall of 500
//! iterations lasts about 10 ms there (some 40,000 failed generations a second); elsewhere a
//! run seldom meets one (the slice's other plans stayed the same).
//!
//! LaCAM is complete: on a solvable instance it finds a plan (given time), and on an unsolvable
//! one it reports so once every configuration is exhausted; stall restarts keep that, since the
//! doubling limit eventually exceeds the iterations an exhaustive search needs.
//!
//! With `anytime` ([`Lacam::anytime`], `-p anytime=true`) the search is LaCAM*: after the first
//! plan it keeps searching, drops nodes whose `f = g + h` is not below the best plan's cost,
//! links every generated configuration to its predecessor (`neighbors`), propagates lower `g`
//! values Dijkstra-style through those links when a known configuration is reached again, and
//! re-pushes the known node, or (with probability `restart_rate`) the start node. It stops at the
//! time limit with the best plan found, or earlier with a proof of optimality when the stack runs
//! dry. The objective ([`Objective`]) is sum of loss (edge cost = agents not staying on their
//! goals; `h` = sum of distances; lacam3's), makespan (edge cost 1; `h` = the largest distance),
//! or sum of costs (mrpp's: the search runs on sum of loss, which bounds it from below, and
//! keeps the plan of least sum of costs it reached; a sum-of-loss optimum is not claimed as a
//! sum-of-costs one). Costs are reported on the objective, so a comparison with a peer can be
//! stated on the peer's own (`-p objective=sum_of_loss` against lacam3). The
//! first-solution time, its cost, the final cost and whether it is proven optimal are the
//! planner's notes (kept in the plan file).
//!
//! mrpp's extension (`-p refine`): LaCAM* alone improves large instances slowly, so between its
//! search rounds (every 8 iterations) the best plan also goes through 16 steps of
//! large-neighbourhood search ([`crate::lns`], MAPF-LNS; with `threads`, 256 steps of each
//! thread's chain, merged); a LaCAM* plan better on the LNS's measure replaces the LNS plan. The
//! returned plan is the better of the two on the objective (sum of loss and makespan: ties to the
//! lower sum of costs), and `final_cost` is its value. With the makespan the LNS lowers
//! (makespan, sum of costs) and gets at most half the time since the first plan: the search's
//! bound there (the longest distance) is often tight, and it then proves the optimum within
//! seconds, which an LNS taking every other turn delayed (lak303d with 500 agents: proven at 464
//! in 2.3 s alone; 468, unproven, after 10 s with the LNS taking its turns; 2.6 s with half the
//! time, docs/benchmark.md). An LNS plan at that bound ends the run, proven optimal.
//! lacam3 refines its plans the same way (Engineering LaCAM*, AAMAS 2024). `refine=lns` makes
//! the LNS lower the sum of costs; `refine=lns_loss` keeps only its steps that lower the sum of
//! loss (its re-planned paths minimise their own loss, as lacam3's refiner's do; until
//! 2026-12-06 they were earliest-arrival ones, when the measurements below were made). Neither
//! wins everywhere (measured after 30 s, docs/benchmark.md): on random-32-32-20 and den312d with
//! 400 agents (16-49% of the vertices covered) `lns` ended 14-24% lower in sum of loss, while
//! on den520d, warehouse-20-40-10-2-1 and Paris_1_256 with 700-1,000 agents (1.5-4.1% covered)
//! `lns_loss` ended lower in sum of loss: there an LNS step re-plans long paths (656 steps in
//! 30 s on den520d with 1,000 agents against 28,592 on random-32-32-20 with 400), too few for
//! the sum-of-costs LNS to move the sum of loss at all. So the default, `refine=auto`, takes
//! `lns_loss` with the sum-of-loss objective below [`AUTO_LOSS_BELOW`] (8%) of the vertices
//! covered, `lns` otherwise.
//! `-p refine=none` is LaCAM* as published.
//!
//! Scatter (`-p scatter`, [`crate::scatter`]; lacam3's, Engineering LaCAM*, AAMAS 2024): before
//! the search, each agent gets a space-utilisation path (at most `scatter_margin` steps over its
//! shortest, crossing the others' as seldom as possible; Han & Yu, ICRA 2022), and PIBT tries the
//! path's next vertex first while the agent is on it. It costs time before the first plan (2.1 s
//! on den520d with 1,000 agents) and makes that plan far cheaper (sum of loss 179,118 -> 170,547
//! there, the bound being 167,907), so `auto` (the default) turns it on for LaCAM* and off for
//! LaCAM, whose point is the first plan's speed. It gets at most half the time limit.
//!
//! Threads (`-p threads`): the search runs on one thread; with `threads = N` the LNS repairs N
//! neighbourhoods at once on N threads and keeps them in the order drawn ([`crate::lns`]), so a
//! run depends on the seed and N, not on the machine's cores.
//!
//! Where the papers are silent: priorities tie by agent id; the deadline is checked before every
//! expansion; without a deadline an anytime search runs until it proves optimality.

use std::collections::VecDeque;
use std::hash::{Hash, Hasher};
use std::sync::Mutex;
use std::time::Instant;

use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustc_hash::{FxHashMap, FxHasher};

use crate::lns::Lns;
use crate::pibt::{NIL, Step, Tricks};
use mrpp_core::mapf::plan::path_cost;
use mrpp_core::mapf::search::distance::{GoalDistances, UNREACHABLE};
use mrpp_core::{
    Ctx, GoalSemantics, Graph, MapfProblem, Param, Plan, Planner, PlannerEntry, Progress, Unsolved,
    VertexId,
};

/// Registry name.
pub const NAME: &str = "lacam";

/// LaCAM / LaCAM* in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "LaCAM (Okumura, AAAI 2023), with -p anytime=true LaCAM* (IJCAI 2023): search over configurations with PIBT as generator; complete, LaCAM* eventually optimal",
    params: &[
        Param {
            name: "anytime",
            default: "false",
            doc: "true = LaCAM*: after the first plan, improve it until the time limit or a proof of optimality",
        },
        Param {
            name: "objective",
            default: "sum_of_loss",
            doc: "what LaCAM* minimises and reports: sum_of_loss (steps agents spend off their goals; lacam3's), sum_of_costs (steps until each agent's last arrival; the search runs on sum of loss, the refinement and the choice of plan on sum of costs) or makespan",
        },
        Param {
            name: "swap",
            default: "true",
            doc: "PIBT generator with the swap technique (Engineering LaCAM*, AAMAS 2024)",
        },
        Param {
            name: "hindrance",
            default: "true",
            doc: "PIBT generator breaks ties by hindrance (Engineering LaCAM*)",
        },
        Param {
            name: "refine",
            default: "auto",
            doc: "LaCAM*: lns = also improve the best plan's sum of costs by large-neighbourhood search (MAPF-LNS, IJCAI 2021); with objective=makespan every setting but none makes the LNS lower (makespan, sum of costs), starting from a latest-arriving agent, in at most half the time after the first plan; lns_loss = LNS that re-plans paths of least loss and keeps only steps lowering the sum of loss (with objective=sum_of_loss); auto = lns_loss with objective=sum_of_loss when the agents cover less than 8% of the vertices, else lns (measured after 30 s: lns_loss lower in sum of loss on den520d, warehouse-20-40-10-2-1 and Paris_1_256 with 400-1,000 agents, 0.8-4.1% covered; 14-24% higher sum of loss on den312d and random-32-32-20 with 400, 16-49% covered; docs/benchmark.md); none = LaCAM* alone",
        },
        Param {
            name: "scatter",
            default: "auto",
            doc: "PIBT follows each agent's space-utilisation path when on it (SUO, Han & Yu, ICRA 2022; lacam3's scatter, Engineering LaCAM*, AAMAS 2024): paths at most scatter_margin steps longer than the shortest, crossing the others' as seldom as possible, computed before the search in at most half the time limit; auto = on for LaCAM* (anytime=true), off for LaCAM (its first plan comes sooner without); on; off",
        },
        Param {
            name: "scatter_margin",
            default: "10",
            doc: "scatter: steps a preferred path may be longer than the agent's shortest (0-1000)",
        },
        Param {
            name: "local_guidance",
            default: "0",
            doc: "steps of local guidance (Arita & Okumura, AAAI 2026): before PIBT generates a configuration's successors, each agent plans a space-time path this many steps long that avoids those of the agents before it in the configuration's order, and PIBT tries its first step first; 0 = off (0-64)",
        },
        Param {
            name: "guidance_collision_cost",
            default: "4",
            doc: "local guidance: what one collision with an earlier agent's guidance path costs, in steps (1-1000; of 1, 4, 10 and 100, 4 was the only one within 4% of the lowest sum of costs on random-32-32-20, den312d, warehouse-10-20-10-2-1 and room-64-64-8 with 400-800 agents, docs/performance.md)",
        },
        Param {
            name: "threads",
            default: "1",
            doc: "LaCAM* with refine: LNS chains run at once, one per thread (1-64), each on its own copy of the plan, merged in a fixed order; the result depends on this number and the seed, not on the machine's cores (docs/planners.md)",
        },
        Param {
            name: "restart_rate",
            default: "0.001",
            doc: "probability of pushing the start configuration instead of a re-reached one (a random restart; LaCAM and LaCAM*, as lacam0)",
        },
        Param {
            name: "prune",
            default: "true",
            doc: "mrpp's: the low-level search queues no constraint that puts two of its agents on one vertex or swaps them (every extension of one fails as well; LaCAM as published and lacam0 queue them and fail each in turn); false = as published",
        },
        Param {
            name: "stall_restart",
            default: "500",
            doc: "mrpp's: before the first plan, after this many iterations in a row without a new configuration the search starts again from the start configuration with its explored configurations forgotten (the random stream goes on); the limit doubles at each restart, so the search stays complete; 0 = never, as published (0-1000000000)",
        },
    ],
    build: |p| {
        let anytime = [false, true][p.choice("anytime", &["false", "true"])?];
        let objective = [
            Objective::SumOfLoss,
            Objective::SumOfCosts,
            Objective::Makespan,
        ][p.choice("objective", &["sum_of_loss", "sum_of_costs", "makespan"])?];
        let restart_rate: f64 = p.get_in("restart_rate", 0.0..=1.0)?;
        let refine = [Refine::Cost, Refine::None, Refine::Loss, Refine::Auto]
            [p.choice("refine", &["lns", "none", "lns_loss", "auto"])?];
        let scatter = [Scatter::Auto, Scatter::On, Scatter::Off]
            [p.choice("scatter", &["auto", "on", "off"])?];
        let scatter_margin: u32 = p.get_in("scatter_margin", 0..=1000)?;
        let threads: usize = p.get_in("threads", 1..=64)?;
        let local_guidance: u32 = p.get_in("local_guidance", 0..=64)?;
        let guidance_collision_cost: u32 = p.get_in("guidance_collision_cost", 1..=1000)?;
        let prune = [true, false][p.choice("prune", &["true", "false"])?];
        let stall_restart: u64 = p.get_in("stall_restart", 0..=1_000_000_000)?;
        Ok(Box::new(Lacam {
            prune,
            stall_restart,
            local_guidance,
            guidance_collision_cost,
            anytime,
            objective,
            restart_rate,
            tricks: Tricks::from_params(p)?,
            refine,
            scatter,
            scatter_margin,
            threads,
            ..Lacam::default()
        }))
    },
};

/// What LaCAM* minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objective {
    /// Steps agents spend off their goals (an agent resting on its goal costs nothing).
    #[default]
    SumOfLoss,
    /// Steps until each agent's last arrival at its goal, summed. Not a sum of edge costs over
    /// configurations (an agent that leaves its goal later costs the steps it rested there), so
    /// the configuration search runs on sum of loss (a lower bound of it), and the refinement
    /// and the choice of the returned plan on sum of costs.
    SumOfCosts,
    /// The number of steps.
    Makespan,
}

impl Objective {
    /// The objective's parameter value (`sum_of_loss`, `sum_of_costs`, `makespan`).
    pub fn name(self) -> &'static str {
        match self {
            Objective::SumOfLoss => "sum_of_loss",
            Objective::SumOfCosts => "sum_of_costs",
            Objective::Makespan => "makespan",
        }
    }
}

/// The LaCAM planner (LaCAM* with `anytime`).
#[derive(Debug)]
pub struct Lacam {
    /// Keep improving after the first plan (LaCAM*).
    pub anytime: bool,
    pub objective: Objective,
    /// Probability of restarting from the start node when a known node is reached (LaCAM and
    /// LaCAM*).
    pub restart_rate: f64,
    /// The low-level search leaves out constraints whose own agents collide ([`consistent`]).
    pub prune: bool,
    /// Before the first plan: iterations in a row without a new configuration after which the
    /// search starts afresh from the start configuration, doubling at each restart; 0 = never.
    pub stall_restart: u64,
    /// Refinements of the PIBT generator.
    pub tricks: Tricks,
    /// LaCAM*: how the best plan is improved between search rounds ([`Refine`]).
    pub refine: Refine,
    /// Whether PIBT follows space-utilisation paths ([`Scatter`]).
    pub scatter: Scatter,
    /// Steps a space-utilisation path may be longer than the agent's shortest.
    pub scatter_margin: u32,
    /// LaCAM* with refinement: LNS chains run at once, one per thread, merged in a fixed order
    /// ([`crate::lns`]'s `steps`).
    pub threads: usize,
    /// Steps of local guidance ([`crate::guidance`]); 0 = none.
    pub local_guidance: u32,
    /// Local guidance: the cost of one collision with an earlier agent's guidance path, in steps.
    pub guidance_collision_cost: u32,
    last: Mutex<Option<Report>>,
}

/// Whether LaCAM's PIBT follows space-utilisation paths (`-p scatter`; [`crate::scatter`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scatter {
    /// On for LaCAM* (`anytime`), off for LaCAM, whose first plan comes sooner without (`auto`,
    /// the default).
    Auto,
    On,
    Off,
}

/// LaCAM*'s refinement between search rounds (`-p refine`; module doc): large-neighbourhood
/// search ([`crate::lns`]) on the plan found so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refine {
    /// LaCAM* as published (`none`).
    None,
    /// An LNS that lowers the sum of costs (`lns`); with the makespan objective, one that lowers
    /// (makespan, sum of costs), as every setting but [`Refine::None`].
    Cost,
    /// With the sum-of-loss objective, an LNS that keeps only steps lowering the sum of loss
    /// (`lns_loss`); with the others as [`Refine::Cost`].
    Loss,
    /// [`Refine::Loss`] with the sum-of-loss objective when the agents cover less than
    /// [`AUTO_LOSS_BELOW`] of the vertices, else [`Refine::Cost`] (`auto`, the default).
    Auto,
}

/// `refine=auto`'s line: below this share of the vertices covered by agents the LNS lowers the
/// sum of loss. Measured on either side of it (docs/benchmark.md): at 0.8-4.1% the
/// sum-of-loss LNS ended lower in sum of loss on all nine instances tried, at 16% and 49% the
/// sum-of-costs LNS ended 14-24% lower in sum of loss; between the two nothing was measured.
pub const AUTO_LOSS_BELOW: f64 = 0.08;

impl Default for Lacam {
    /// LaCAM (first plan), sum of loss, restart rate 0.001, swap and hindrance on.
    fn default() -> Self {
        Lacam {
            anytime: false,
            objective: Objective::SumOfLoss,
            restart_rate: 0.001,
            prune: true,
            stall_restart: STALL_RESTART,
            tricks: Tricks {
                swap: true,
                hindrance: true,
            },
            refine: Refine::Auto,
            scatter: Scatter::Auto,
            scatter_margin: 10,
            threads: 1,
            local_guidance: 0,
            guidance_collision_cost: 4,
            last: Mutex::new(None),
        }
    }
}

/// What a LaCAM run reports beside its plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report {
    /// Seconds from the start of the search to the first plan.
    pub first_solution_secs: f64,
    /// The objective's value of the first plan and of the returned one.
    pub first_cost: u64,
    pub final_cost: u64,
    /// The search ran dry with a plan: no plan has a lower objective value.
    pub proven_optimal: bool,
    /// Configurations generated (since the last stall restart).
    pub configurations: usize,
    /// Stall restarts before the first plan ([`Lacam::stall_restart`]).
    pub restarts: u64,
    /// The best objective value the configuration search itself reached (with refinement the
    /// returned plan may be the refined one).
    pub search_cost: u64,
    /// LNS steps taken, and those that lowered what it lowers (0 without refinement).
    pub lns_steps: u64,
    pub lns_improvements: u64,
    /// What the LNS lowered, when there was one: the sum of loss (`refine=lns_loss`, or `auto`
    /// on a sparse instance), the makespan (`objective=makespan`) or the sum of costs.
    pub lns_lowers: Option<Objective>,
    /// With scatter: seconds it took, and collisions left among its paths.
    pub scatter: Option<(f64, u64)>,
}

impl Lacam {
    /// LaCAM* (anytime) minimising `objective`, other settings as [`Lacam::default`].
    pub fn star(objective: Objective) -> Self {
        Lacam {
            anytime: true,
            objective,
            ..Lacam::default()
        }
    }

    /// The report of the last successful run.
    pub fn report(&self) -> Option<Report> {
        *self.last.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Planner<MapfProblem> for Lacam {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&self, problem: &MapfProblem, ctx: &Ctx) -> Result<Plan, Unsolved> {
        let inst = problem.instance();
        let (configs, report) = search(self, problem.graph(), &inst.starts, &inst.goals, ctx)?;
        *self.last.lock().unwrap_or_else(|e| e.into_inner()) = Some(report);
        let n = inst.num_agents();
        Ok(Plan {
            paths: (0..n)
                .map(|i| configs.iter().map(|c| c[i]).collect())
                .collect(),
        })
    }

    /// `first_solution_ms`, `first_cost`, `final_cost`, `objective`, `proven_optimal`,
    /// `configurations`, `restarts`, and with refinement `search_cost`, `lns_steps`,
    /// `lns_improvements` and `lns_lowers` (`sum_of_loss`, `sum_of_costs` or `makespan`), of
    /// the last plan.
    fn notes(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut m = serde_json::Map::new();
        if let Some(r) = self.report() {
            let ms = (r.first_solution_secs * 1e6).round() / 1e3;
            m.insert("first_solution_ms".into(), ms.into());
            m.insert("objective".into(), self.objective.name().into());
            m.insert("first_cost".into(), r.first_cost.into());
            m.insert("final_cost".into(), r.final_cost.into());
            m.insert("proven_optimal".into(), r.proven_optimal.into());
            m.insert("configurations".into(), r.configurations.into());
            m.insert("restarts".into(), r.restarts.into());
            if r.lns_steps > 0 {
                m.insert("search_cost".into(), r.search_cost.into());
                m.insert("lns_steps".into(), r.lns_steps.into());
                m.insert("lns_improvements".into(), r.lns_improvements.into());
                if let Some(o) = r.lns_lowers {
                    m.insert("lns_lowers".into(), o.name().into());
                }
            }
            if let Some((secs, collisions)) = r.scatter {
                m.insert("scatter_ms".into(), ((secs * 1e6).round() / 1e3).into());
                m.insert("scatter_collisions".into(), collisions.into());
            }
        }
        m
    }
}

/// The default of [`Lacam::stall_restart`] (`-p stall_restart`).
pub const STALL_RESTART: u64 = 500;

/// No node.
const NONE: u32 = u32::MAX;

/// A low-level node: the next vertices of the first agents of the configuration's order.
struct Constraint {
    who: Vec<u32>,
    at: Vec<VertexId>,
}

/// A high-level node: a configuration.
struct Node {
    config: Box<[VertexId]>,
    parent: u32,
    /// Configurations generated from this one (LaCAM*'s graph of known transitions).
    neighbors: Vec<u32>,
    g: u64,
    h: u64,
    priorities: Box<[f32]>,
    order: Box<[u32]>,
    tree: VecDeque<Constraint>,
    /// With local guidance: each agent's guidance, once the node generated a successor.
    guide: Option<Box<[VertexId]>>,
    /// Next node with the same configuration hash.
    same_hash: u32,
}

impl Node {
    fn f(&self) -> u64 {
        self.g + self.h
    }
}

/// The search state shared by its steps.
struct Search<'a> {
    lacam: &'a Lacam,
    graph: &'a Graph,
    goals: &'a [VertexId],
    dist: &'a GoalDistances<'a>,
    scatter: Option<&'a crate::scatter::Scatter>,
    guidance: Option<crate::guidance::Guidance>,
    /// The run's context (local guidance polls its deadline and reports progress).
    ctx: &'a Ctx,
    nodes: Vec<Node>,
    by_hash: FxHashMap<u64, u32>,
    occupied_now: Vec<usize>,
    occupied_next: Vec<usize>,
    next: Vec<VertexId>,
    rng: ChaCha8Rng,
}

/// Runs LaCAM (LaCAM* with `lacam.anytime`) from `starts` to `goals` on `graph`: the plan as one
/// configuration per step, from `starts` to `goals`, and the run's [`Report`].
///
/// # Errors
/// [`Unsolved::GaveUp`] when an agent cannot reach its goal or every configuration was explored
/// without reaching the goals (no solution exists); [`Unsolved::TimeLimit`] when the deadline
/// passes before the first plan.
pub fn search(
    lacam: &Lacam,
    graph: &Graph,
    starts: &[VertexId],
    goals: &[VertexId],
    ctx: &Ctx,
) -> Result<(Vec<Vec<VertexId>>, Report), Unsolved> {
    search_within(lacam, graph, starts, goals, ctx, u64::MAX, None)
}

/// [`search`] that also stops after `max_iterations` iterations (constraint nodes taken from the
/// stack) or at `until`, as at the deadline: [`Unsolved::TimeLimit`] unless a plan was found.
fn search_within(
    lacam: &Lacam,
    graph: &Graph,
    starts: &[VertexId],
    goals: &[VertexId],
    ctx: &Ctx,
    max_iterations: u64,
    until: Option<Instant>,
) -> Result<(Vec<Vec<VertexId>>, Report), Unsolved> {
    let began = Instant::now();
    let n = starts.len();
    let mut dist = GoalDistances::new(graph, goals);
    // LaCAM's first plan looks near the agents' shortest paths: its tables need not cover the
    // whole map (LaCAM* and its refinement look everywhere).
    let warmed = if lacam.anytime {
        dist.warm_up(starts, ctx.deadline)
    } else {
        dist.warm_up_near(starts, WARM_UP_MARGIN, ctx.deadline)
    };
    if !warmed {
        return Err(Unsolved::TimeLimit);
    }
    if let Some(i) = (0..n).find(|&i| dist.get(i, starts[i]) == UNREACHABLE) {
        return Err(Unsolved::GaveUp(format!("agent {i} cannot reach its goal")));
    }
    let scatter = match lacam.scatter {
        Scatter::On => true,
        Scatter::Off => false,
        Scatter::Auto => lacam.anytime,
    }
    .then(|| {
        let began = Instant::now();
        let s = crate::scatter::Scatter::build(
            graph,
            starts,
            goals,
            &dist,
            lacam.scatter_margin,
            mrpp_core::seeds::derive_seed(ctx.seed, "scatter"),
            ctx.deadline.share(0.5),
        );
        (s, began.elapsed().as_secs_f64())
    });
    let mut s = Search {
        lacam,
        graph,
        scatter: scatter.as_ref().map(|s| &s.0),
        guidance: (lacam.local_guidance > 0).then(|| {
            crate::guidance::Guidance::new(
                graph,
                lacam.local_guidance,
                lacam.guidance_collision_cost,
            )
        }),
        goals,
        dist: &dist,
        ctx,
        nodes: Vec::new(),
        by_hash: FxHashMap::default(),
        occupied_now: vec![NIL; graph.num_vertices()],
        occupied_next: vec![NIL; graph.num_vertices()],
        next: vec![VertexId::MAX; n],
        rng: ChaCha8Rng::seed_from_u64(ctx.seed),
    };
    let mut root = s.create(starts.to_vec().into_boxed_slice(), NONE, 0);
    let mut open = vec![root];
    // Stall restarts (before the first plan): the iteration that last created a node, the
    // current limit and the restarts so far.
    let mut last_new = 0u64;
    let mut stall_limit = lacam.stall_restart;
    let mut restarts = 0u64;
    let mut goal = NONE;
    let mut first: Option<(f64, u64)> = None;
    // Sum of costs: the search's plan of least sum of costs so far (its best on sum of loss
    // need not be).
    let mut best_soc: Option<(u64, Vec<Vec<VertexId>>)> = None;
    let refine = lacam.anytime && lacam.refine != Refine::None;
    let soc = lacam.objective == Objective::SumOfCosts;
    let mut lns: Option<Lns> = None;
    // Makespan: the LNS's time so far, when it began, the makespan's lower bound (the longest
    // distance, set with the LNS) and whether the LNS's plan reached it, which proves it optimal.
    let mut lns_spent = std::time::Duration::ZERO;
    let mut lns_began = Instant::now();
    let mut makespan_bound = 0;
    let mut lns_optimal = false;
    let mut iterations = 0u64;
    let mut throttle = mrpp_core::Throttle::new();
    while let Some(&top) = open.last() {
        if ctx.deadline.expired()
            || iterations >= max_iterations
            || until.is_some_and(|u| Instant::now() >= u)
        {
            break;
        }
        iterations += 1;
        if first.is_none() && stall_limit > 0 && iterations - last_new > stall_limit {
            // Start afresh: forget every configuration (the random stream goes on).
            s.nodes.clear();
            s.by_hash.clear();
            root = s.create(starts.to_vec().into_boxed_slice(), NONE, 0);
            open.clear();
            open.push(root);
            last_new = iterations;
            stall_limit = stall_limit.saturating_mul(2);
            restarts += 1;
            continue;
        }
        if first.is_none() {
            let configurations = s.nodes.len();
            throttle.report(ctx, || Progress {
                stage: "LaCAM search",
                done: iterations,
                total: 0,
                note: format!("{configurations} configurations, {restarts} restarts, no plan yet"),
            });
        }
        // With the makespan the search often proves the optimum soon (its bound, the longest
        // distance, is tight), so the LNS gets at most half the time since the first plan.
        if let Some(l) = lns.as_mut()
            && iterations.is_multiple_of(LNS_EVERY)
            && (lacam.objective != Objective::Makespan || 2 * lns_spent <= lns_began.elapsed())
        {
            {
                let round_began = Instant::now();
                let rounds = if lacam.threads > 1 {
                    LNS_STEPS * LNS_CHAIN_FACTOR
                } else {
                    LNS_STEPS
                };
                // A round of several chains can take seconds on large maps.
                let tick = |k: usize| {
                    throttle.report(ctx, || Progress {
                        stage: "LaCAM* LNS round",
                        done: k as u64,
                        total: rounds as u64,
                        note: format!("{k} of {rounds} steps of the first chain"),
                    })
                };
                if l.steps(rounds, ctx.deadline, tick) > 0 {
                    // What the LNS lowers (its key's first value), named as such.
                    let cost = l.key().0;
                    let what = l.lowers().name().replace('_', " ");
                    ctx.report(Progress {
                        stage: "LaCAM* cost",
                        done: cost,
                        total: 0,
                        note: format!("LNS, {what} {cost}"),
                    });
                }
                lns_spent += round_began.elapsed();
                if lacam.objective == Objective::Makespan && l.key().0 <= makespan_bound {
                    lns_optimal = true;
                    break;
                }
            }
        }
        if s.nodes[top as usize].tree.is_empty() {
            open.pop();
            continue;
        }
        if goal != NONE && s.nodes[top as usize].f() >= s.nodes[goal as usize].f() {
            open.pop();
            continue;
        }
        if goal == NONE && *s.nodes[top as usize].config == *goals {
            goal = top;
            let cost = if soc {
                let paths = s.paths_to(goal);
                let c = sum_of_costs(&paths, goals);
                best_soc = Some((c, paths));
                c
            } else {
                s.nodes[top as usize].g
            };
            first = Some((began.elapsed().as_secs_f64(), cost));
            if !lacam.anytime {
                break;
            }
            if refine {
                let sparse = (goals.len() as f64) < AUTO_LOSS_BELOW * graph.num_vertices() as f64;
                let lowers = match (lacam.objective, lacam.refine) {
                    (Objective::Makespan, _) => Objective::Makespan,
                    (Objective::SumOfLoss, Refine::Loss) => Objective::SumOfLoss,
                    (Objective::SumOfLoss, Refine::Auto) if sparse => Objective::SumOfLoss,
                    _ => Objective::SumOfCosts,
                };
                lns = Some(
                    Lns::new(graph, goals, &dist, s.paths_to(goal), ctx.seed, lowers)
                        .with_threads(lacam.threads),
                );
                lns_began = Instant::now();
                makespan_bound = (0..goals.len())
                    .map(|i| u64::from(dist.get(i, starts[i])))
                    .max()
                    .unwrap_or(0);
            }
            ctx.report(Progress {
                stage: "LaCAM* cost",
                done: cost,
                total: 0,
                note: format!("first plan, {} {cost}", lacam.objective.name()),
            });
            continue;
        }
        let c = s.nodes[top as usize]
            .tree
            .pop_front()
            .expect("checked non-empty");
        s.expand_low_level(top, &c);
        if !s.generate(top, &c) {
            continue;
        }
        let hash = config_hash(&s.next);
        if let Some(known) = s.find(hash) {
            let before = (goal != NONE).then(|| s.nodes[goal as usize].g);
            s.rewrite(top, known, goal, &mut open);
            if let Some(b) = before
                && s.nodes[goal as usize].g < b
            {
                if let Some(l) = lns.as_mut() {
                    let paths = s.paths_to(goal);
                    if l.key_of_plan(&paths) < l.key() {
                        l.reset(paths);
                    }
                }
                if soc {
                    let paths = s.paths_to(goal);
                    let c = sum_of_costs(&paths, goals);
                    if best_soc.as_ref().is_none_or(|b| c < b.0) {
                        best_soc = Some((c, paths));
                    }
                }
                let cost = s.nodes[goal as usize].g;
                ctx.report(Progress {
                    stage: "LaCAM* cost",
                    done: cost,
                    total: 0,
                    note: format!("improved, {} {cost}", lacam.objective.name()),
                });
            }
            let restart = s.rng.random::<f64>() < lacam.restart_rate;
            let push = if restart { root } else { known };
            if goal == NONE || s.nodes[push as usize].f() < s.nodes[goal as usize].f() {
                open.push(push);
            }
        } else {
            let config = s.next.clone().into_boxed_slice();
            let g = s.nodes[top as usize].g + s.edge_cost(&s.nodes[top as usize].config, &config);
            let id = s.create(config, top, g);
            last_new = iterations;
            s.nodes[top as usize].neighbors.push(id);
            s.link(hash, id);
            if goal == NONE || s.nodes[id as usize].f() < s.nodes[goal as usize].f() {
                open.push(id);
            }
        }
    }
    if goal == NONE {
        return Err(if open.is_empty() {
            Unsolved::GaveUp(
                "LaCAM exhausted every reachable configuration: the instance has no solution"
                    .into(),
            )
        } else {
            Unsolved::TimeLimit
        });
    }
    let (first_solution_secs, first_cost) = first.expect("set with the goal");
    // The search proves sum-of-loss (or makespan) optimality; a sum-of-loss optimum need not be
    // one of sum of costs, so that objective never claims it.
    let proven_optimal = lacam.anytime && (open.is_empty() || lns_optimal) && !soc;
    let mut paths = s.paths_to(goal);
    let search_cost = match best_soc {
        Some((c, p)) if soc => {
            paths = p;
            c
        }
        _ => s.nodes[goal as usize].g,
    };
    // The refined plan replaces the search's when it is better on the objective (sum of loss:
    // ties to the lower sum of costs).
    if let Some(l) = &lns
        && (!proven_optimal || lns_optimal)
    {
        let key = |p: &[Vec<VertexId>]| {
            let c = sum_of_costs(p, goals);
            match lacam.objective {
                Objective::SumOfCosts => (c, 0),
                Objective::SumOfLoss => (s.edge_costs_of(p), c),
                Objective::Makespan => (p.iter().map(|q| q.len() as u64 - 1).max().unwrap_or(0), c),
            }
        };
        if key(l.paths()) < key(&paths) {
            paths = l.paths().to_vec();
        }
    }
    let configs = configs_of(&paths);
    let final_cost = match lacam.objective {
        Objective::Makespan => configs.len() as u64 - 1,
        Objective::SumOfLoss => configs.windows(2).map(|w| s.edge_cost(&w[0], &w[1])).sum(),
        Objective::SumOfCosts => sum_of_costs(&paths, goals),
    };
    let report = Report {
        first_solution_secs,
        first_cost,
        final_cost,
        proven_optimal,
        configurations: s.nodes.len(),
        restarts,
        search_cost,
        lns_steps: lns.as_ref().map_or(0, |l| l.counts().0),
        lns_improvements: lns.as_ref().map_or(0, |l| l.counts().1),
        lns_lowers: lns.as_ref().map(|l| l.lowers()),
        scatter: scatter.as_ref().map(|(s, secs)| (*secs, s.counts().0)),
    };
    Ok((configs, report))
}

/// LaCAM (first plan): the goal-distance tables are grown until they know every vertex within
/// this many steps beyond each agent's start ([`GoalDistances::warm_up_near`]). Side by side on
/// five MovingAI instances (Berlin_1_256 1,000 agents, den520d, ost003d, maze-128-128-2 500,
/// random-64-64-10 300; `mrpp solve -m M.map -i M-random-1.scen -N N -P lacam -t 30`, its
/// `first_solution_ms`): the first plan came 11-32% sooner than with complete tables, with the
/// same plans. Margins 0, 4 and 16 (compared with a temporary build that read the margin from the
/// environment, not in the repository) were within 5% of each other.
const WARM_UP_MARGIN: u32 = 4;

/// Cells a component may have for [`proven_unsolvable`] to search it (larger ones are not
/// explored to their end: one breadth-first search of at most this many cells per agent).
const EXHAUST_CELLS: usize = 1024;

/// A proof that the instance `starts -> goals` on `graph` has no plan, by LaCAM's exhaustive
/// search (complete: it reports so only once every reachable configuration was expanded; see the
/// module doc), or `None` when no proof was found: a plan exists, the deadline passed, the budget
/// ran out or a component is too large.
///
/// Agents in different connected components never meet, so the instance has a plan iff every
/// component's agents have one among themselves: each component of at most [`EXHAUST_CELLS`]
/// cells holding two agents or more is searched alone, for at most `max_iterations` iterations
/// (constraint nodes taken from LaCAM's stack; a configuration costs at most `1 + 5 + 5^2 + ...`
/// of them on a grid, up to its number of agents) and until `until` at the latest (the components
/// together; the deadline of `ctx` applies as well); a component with one agent has a plan iff
/// its goal is there. Rules: the validator's grid rules (stay at the goal, following allowed),
/// which are LaCAM's successor rules.
///
/// Cost, measured on corridors where two agents must swap (about `L^2 / 2` configurations, at
/// most 13 iterations each): 0.14-0.16 s and 30 MB to exhaust 200 cells, 0.7-0.8 s and 99 MB for
/// 400 (LaCAM's own run on them, `mrpp solve -m CORRIDOR.map -i SWAP.scen -P lacam` on a
/// one-row map, peak resident set, with and without `prune`, 2026-12-06), about 100 bytes per
/// iteration; so the caller bounds the iterations (memory) and the time in proportion to the
/// work it has already done. Used by CBS and EECBS
/// ([`crate::cbs`]), which cannot tell an unsolvable instance from a hard one (issue 27, item 4:
/// a 10-cell corridor swap grew CBS to 4.6 GB in 60 s).
pub(crate) fn proven_unsolvable(
    graph: &Graph,
    starts: &[VertexId],
    goals: &[VertexId],
    ctx: &Ctx,
    max_iterations: u64,
    until: Instant,
) -> Option<String> {
    let n = starts.len();
    if n < 2 {
        return None;
    }
    let by_start: FxHashMap<VertexId, usize> =
        starts.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    let mut done = vec![false; n];
    // The component being explored: its cells in breadth-first order, and each one's index there.
    let mut cells: Vec<VertexId> = Vec::new();
    let mut local: FxHashMap<VertexId, VertexId> = FxHashMap::default();
    for first in 0..n {
        if done[first] {
            continue;
        }
        if ctx.deadline.expired() || Instant::now() >= until {
            return None;
        }
        cells.clear();
        local.clear();
        cells.push(starts[first]);
        local.insert(starts[first], 0);
        let mut head = 0;
        while head < cells.len() && cells.len() <= EXHAUST_CELLS {
            let u = cells[head];
            head += 1;
            for &v in graph.neighbors(u) {
                if let std::collections::hash_map::Entry::Vacant(e) = local.entry(v) {
                    e.insert(cells.len() as VertexId);
                    cells.push(v);
                }
            }
        }
        let mut agents: Vec<usize> = cells
            .iter()
            .filter_map(|v| by_start.get(v).copied())
            .collect();
        agents.sort_unstable();
        for &i in &agents {
            done[i] = true;
        }
        // Too large: not explored to its end.
        if cells.len() > EXHAUST_CELLS {
            continue;
        }
        let mut sub_goals = Vec::with_capacity(agents.len());
        for &i in &agents {
            match local.get(&goals[i]) {
                Some(&g) => sub_goals.push(g),
                None => return Some(format!("agent {i} cannot reach its goal")),
            }
        }
        if agents.len() < 2 {
            continue;
        }
        let sub_starts: Vec<VertexId> = agents.iter().map(|&i| local[&starts[i]]).collect();
        let adjacency: Vec<Vec<VertexId>> = cells
            .iter()
            .map(|&u| graph.neighbors(u).iter().map(|v| local[v]).collect())
            .collect();
        let sub = Graph::from_adjacency(&adjacency, None);
        // No stall restarts: the proof needs one uninterrupted exhaustive run.
        let lacam = Lacam {
            stall_restart: 0,
            ..Lacam::default()
        };
        if let Err(Unsolved::GaveUp(_)) = search_within(
            &lacam,
            &sub,
            &sub_starts,
            &sub_goals,
            ctx,
            max_iterations,
            Some(until),
        ) {
            let names: Vec<String> = agents.iter().map(usize::to_string).collect();
            let (last, rest) = names.split_last().expect("two agents or more");
            return Some(format!(
                "no plan exists: agents {} and {last} share a component of {} cells, and LaCAM \
                 exhausted every configuration they can reach there without reaching their goals",
                rest.join(", "),
                cells.len()
            ));
        }
    }
    None
}

/// LaCAM* iterations between two LNS rounds, and LNS steps per round.
/// (random-32-32-20 with 200-400 agents, 10 s: a round every 8 iterations ends 0.4-8% lower than
/// one every 64; a round every iteration was no better.)
const LNS_EVERY: u64 = 8;
const LNS_STEPS: usize = 16;
/// With several threads, each LNS chain runs this many times `LNS_STEPS` steps between two
/// merges: the threads wait for the slowest chain at a merge, and step times vary widely. On
/// den520d with 1,000 agents (`mrpp solve ... -P lacam -p anytime=true -p threads=2 -s S -t 30`,
/// seeds 0-2, one run at a time, quiet machine, 2026-12-06) one thread waited 16-27% of the LNS's
/// time at 16 steps per chain and 12-17% at 64 (a temporary timer); the chains took 5,900-6,300
/// steps in all at 16, 6,400-9,000 at 64, 7,680-9,728 at 256; the sums of loss, means of the three
/// seeds: 169,651 at 16, 169,633 at 64, 169,595 at 256, 169,600 at 1,024 (lacam3 with two
/// threads: 169,607, three runs).
const LNS_CHAIN_FACTOR: usize = 16;

/// Whether constraint `c` extended by the agent now at `v` going to `u` keeps its agents apart:
/// `u` is no other constrained agent's next vertex, and no constrained agent moves from `u` to
/// `v` (a swap). `c` itself is consistent (the root's empty constraint is, and only consistent
/// children are queued), so an inconsistent extension and all its own extensions would make
/// [`Search::generate`] fail before PIBT runs: leaving them out removes no successor. On
/// maze-128-128-1 (a tree of one-cell corridors) with 700 agents, 97-100% of LaCAM's iterations
/// were such constraints once the search stalled, before they were left out (a temporary trace,
/// not in the repository).
fn consistent(config: &[VertexId], c: &Constraint, v: VertexId, u: VertexId) -> bool {
    c.who
        .iter()
        .zip(&c.at)
        .all(|(&j, &w)| w != u && !(w == v && config[j as usize] == u))
}

/// Sum of costs of `paths` (each ends on its goal), by the validator's definition.
fn sum_of_costs(paths: &[Vec<VertexId>], goals: &[VertexId]) -> u64 {
    paths
        .iter()
        .zip(goals)
        .map(|(p, &g)| path_cost(p, g, GoalSemantics::Stay).unwrap_or(p.len() - 1) as u64)
        .sum()
}

/// The configurations of `paths`, one per step, each path held at its end up to the longest.
fn configs_of(paths: &[Vec<VertexId>]) -> Vec<Vec<VertexId>> {
    let horizon = paths.iter().map(Vec::len).max().unwrap_or(1);
    (0..horizon)
        .map(|t| paths.iter().map(|p| p[t.min(p.len() - 1)]).collect())
        .collect()
}

/// FxHash of a configuration.
fn config_hash(config: &[VertexId]) -> u64 {
    let mut h = FxHasher::default();
    config.hash(&mut h);
    h.finish()
}

impl Search<'_> {
    /// The plan from the root to node `id`, one path per agent.
    fn paths_to(&self, id: u32) -> Vec<Vec<VertexId>> {
        let mut configs = Vec::new();
        let mut k = id;
        while k != NONE {
            configs.push(&self.nodes[k as usize].config);
            k = self.nodes[k as usize].parent;
        }
        configs.reverse();
        (0..self.goals.len())
            .map(|i| configs.iter().map(|c| c[i]).collect())
            .collect()
    }

    /// A new node for `config` reached from `parent` at cost `g` (the root: `parent` = NONE);
    /// registered under its hash when it is the root (children are linked by the caller).
    fn create(&mut self, config: Box<[VertexId]>, parent: u32, g: u64) -> u32 {
        let n = config.len();
        let priorities: Box<[f32]> = if parent == NONE {
            (0..n)
                .map(|i| self.dist.get(i, config[i]) as f32 / n as f32)
                .collect()
        } else {
            let before = &self.nodes[parent as usize].priorities;
            (0..n)
                .map(|i| {
                    if config[i] == self.goals[i] {
                        before[i].fract()
                    } else {
                        before[i] + 1.0
                    }
                })
                .collect()
        };
        let mut order: Box<[u32]> = (0..n as u32).collect();
        order.sort_by(|&a, &b| priorities[b as usize].total_cmp(&priorities[a as usize]));
        let h = self.heuristic(&config);
        let id = self.nodes.len() as u32;
        if parent == NONE {
            let hash = config_hash(&config);
            self.by_hash.insert(hash, id);
        }
        self.nodes.push(Node {
            config,
            parent,
            neighbors: Vec::new(),
            g,
            h,
            priorities,
            order,
            tree: VecDeque::from([Constraint {
                who: Vec::new(),
                at: Vec::new(),
            }]),
            guide: None,
            same_hash: NONE,
        });
        id
    }

    /// Registers node `id` under `hash`.
    fn link(&mut self, hash: u64, id: u32) {
        let head = self.by_hash.insert(hash, id).unwrap_or(NONE);
        self.nodes[id as usize].same_hash = head;
    }

    /// The node whose configuration is `self.next`, if any.
    fn find(&self, hash: u64) -> Option<u32> {
        let mut k = *self.by_hash.get(&hash)?;
        while k != NONE {
            if *self.nodes[k as usize].config == *self.next {
                return Some(k);
            }
            k = self.nodes[k as usize].same_hash;
        }
        None
    }

    /// Lower bound of the cost from `config` to the goals.
    fn heuristic(&self, config: &[VertexId]) -> u64 {
        let d = (0..config.len()).map(|i| u64::from(self.dist.get(i, config[i])));
        match self.lacam.objective {
            Objective::SumOfLoss | Objective::SumOfCosts => d.sum(),
            Objective::Makespan => d.max().unwrap_or(0),
        }
    }

    /// The sum of loss of `paths` (valid paths ending on their goals): the edge costs of their
    /// configurations summed, counted per path ([`crate::lns::path_loss`]).
    fn edge_costs_of(&self, paths: &[Vec<VertexId>]) -> u64 {
        paths
            .iter()
            .zip(self.goals)
            .map(|(p, &g)| crate::lns::path_loss(p, g))
            .sum()
    }

    /// Cost of the step from configuration `a` to `b`.
    fn edge_cost(&self, a: &[VertexId], b: &[VertexId]) -> u64 {
        match self.lacam.objective {
            Objective::Makespan => 1,
            Objective::SumOfLoss | Objective::SumOfCosts => (0..a.len())
                .filter(|&i| !(a[i] == self.goals[i] && b[i] == self.goals[i]))
                .count() as u64,
        }
    }

    /// Queues the children of constraint `c` of node `id`: the next agent of the order at each
    /// of its candidates, shuffled, except candidates that collide with `c`'s own agents (see
    /// [`consistent`]).
    fn expand_low_level(&mut self, id: u32, c: &Constraint) {
        let node = &self.nodes[id as usize];
        if c.who.len() >= node.config.len() {
            return;
        }
        let i = node.order[c.who.len()];
        let v = node.config[i as usize];
        let mut cands: Vec<VertexId> = std::iter::once(v)
            .chain(self.graph.neighbors(v).iter().copied())
            .collect();
        cands.shuffle(&mut self.rng);
        if self.lacam.prune {
            cands.retain(|&u| consistent(&node.config, c, v, u));
        }
        let node = &mut self.nodes[id as usize];
        for u in cands {
            let mut who = Vec::with_capacity(c.who.len() + 1);
            who.extend_from_slice(&c.who);
            who.push(i);
            let mut at = Vec::with_capacity(c.at.len() + 1);
            at.extend_from_slice(&c.at);
            at.push(u);
            node.tree.push_back(Constraint { who, at });
        }
    }

    /// PIBT's successor of node `id`'s configuration under constraint `c`, into `self.next`;
    /// false when the constraint itself breaks a rule (two agents on one vertex, a swap) or the
    /// generator leaves a conflict.
    fn generate(&mut self, id: u32, c: &Constraint) -> bool {
        if let Some(gd) = self.guidance.as_mut()
            && self.nodes[id as usize].guide.is_none()
        {
            let node = &self.nodes[id as usize];
            let guide = gd.plan(
                self.graph,
                self.dist,
                self.goals,
                &node.config,
                &node.order,
                self.ctx,
            );
            self.nodes[id as usize].guide = Some(guide);
        }
        let node = &self.nodes[id as usize];
        let now = &node.config;
        for (i, &v) in now.iter().enumerate() {
            self.occupied_now[v as usize] = i;
        }
        self.next.fill(VertexId::MAX);
        let mut st = Step {
            graph: self.graph,
            dist: self.dist,
            goals: self.goals,
            tricks: self.lacam.tricks,
            now,
            next: &mut self.next,
            occupied_now: &self.occupied_now,
            occupied_next: &mut self.occupied_next,
            rng: &mut self.rng,
            scatter: self.scatter,
            guide: node.guide.as_deref(),
        };
        let mut ok = true;
        for (&i, &u) in c.who.iter().zip(&c.at) {
            let i = i as usize;
            let j = st.occupied_now[u as usize];
            if st.occupied_next[u as usize] != NIL || (j != NIL && j != i && st.next[j] == now[i]) {
                ok = false;
                break;
            }
            st.next[i] = u;
            st.occupied_next[u as usize] = i;
        }
        if ok {
            for &i in node.order.iter() {
                let i = i as usize;
                if st.next[i] == VertexId::MAX && !st.assign(i) {
                    ok = false;
                    break;
                }
            }
        }
        // The generator may leave an agent where an earlier one is bound (its own vertex, when
        // it could not move): only a conflict-free successor counts.
        for (i, &v) in self.next.iter().enumerate() {
            if v == VertexId::MAX {
                ok = false;
                continue;
            }
            if self.occupied_next[v as usize] != i {
                ok = false;
            }
            let j = self.occupied_now[v as usize];
            if j != NIL && j != i && self.next[j] == now[i] {
                ok = false;
            }
        }
        for &v in self.next.iter() {
            if v != VertexId::MAX {
                self.occupied_next[v as usize] = NIL;
            }
        }
        for &v in now.iter() {
            self.occupied_now[v as usize] = NIL;
        }
        ok
    }

    /// LaCAM*'s rewrite: records `to` as a successor of `from` and propagates lower `g` values
    /// through the known transitions (Dijkstra-style), pushing improved nodes that can still
    /// beat the best plan.
    fn rewrite(&mut self, from: u32, to: u32, goal: u32, open: &mut Vec<u32>) {
        if !self.nodes[from as usize].neighbors.contains(&to) {
            self.nodes[from as usize].neighbors.push(to);
        }
        if !self.lacam.anytime {
            return;
        }
        let mut queue = VecDeque::from([from]);
        while let Some(a) = queue.pop_front() {
            for k in 0..self.nodes[a as usize].neighbors.len() {
                let b = self.nodes[a as usize].neighbors[k];
                let g = self.nodes[a as usize].g
                    + self.edge_cost(
                        &self.nodes[a as usize].config,
                        &self.nodes[b as usize].config,
                    );
                if g < self.nodes[b as usize].g {
                    let nb = &mut self.nodes[b as usize];
                    nb.g = g;
                    nb.parent = a;
                    queue.push_back(b);
                    if goal != NONE && nb.f() < self.nodes[goal as usize].f() {
                        open.push(b);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::mapf::graph::Graph;
    use mrpp_core::{Deadline, Instance, Rules, solve};

    #[test]
    fn solves_a_corridor_swap_that_needs_a_side_pocket() {
        // 0-1-2-3 with a pocket 4 off vertex 1: two agents swap ends.
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (1, 4)]);
        let inst = Instance::new(vec![0, 3], vec![3, 0]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        let s = solve(&Lacam::default(), &p, &Ctx::default()).unwrap();
        assert!(s.metrics.makespan >= 4);
        // Without the pocket there is no solution, and LaCAM says so.
        let g = Graph::from_edges(4, &[(0, 1), (1, 2), (2, 3)]);
        let p = MapfProblem::on(&g, &inst, Rules::default());
        assert!(matches!(
            solve(&Lacam::default(), &p, &Ctx::default()),
            Err(Unsolved::GaveUp(_))
        ));
    }

    #[test]
    fn stall_restarts_keep_the_search_complete() {
        // A limit of one iteration without a new configuration restarts the search often; the
        // limit doubles, so it still solves a corridor where one agent must wait in a side
        // pocket (0-1-2-3-4-5, pocket 6 off vertex 2) and exhausts a corridor reversal.
        let lacam = Lacam {
            stall_restart: 1,
            ..Lacam::default()
        };
        let g = Graph::from_edges(7, &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (2, 6)]);
        let inst = Instance::new(vec![0, 1, 5], vec![5, 4, 0]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        let s = solve(&lacam, &p, &Ctx::default()).unwrap();
        assert!(s.metrics.makespan >= 5);
        let restarts = lacam.report().unwrap().restarts;
        assert!(restarts > 0, "{restarts}");
        let g = Graph::from_edges(8, &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 6), (6, 7)]);
        let inst = Instance::new(vec![0, 1, 2], vec![7, 6, 5]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        assert!(matches!(
            solve(&lacam, &p, &Ctx::default()),
            Err(Unsolved::GaveUp(_))
        ));
    }

    #[test]
    fn extensions_that_collide_with_the_constrained_agents_are_inconsistent() {
        // Agents 0 and 1 at vertices 10 and 11; the constraint moves agent 0 to 11.
        let config = [10, 11, 12];
        let c = Constraint {
            who: vec![0],
            at: vec![11],
        };
        // Agent 1 (at 11) onto 11 too: a vertex collision; onto 10: a swap with agent 0.
        assert!(!consistent(&config, &c, 11, 11));
        assert!(!consistent(&config, &c, 11, 10));
        // Onto 12, or agent 2 (at 12) onto 13 or staying: no collision among them.
        assert!(consistent(&config, &c, 11, 12));
        assert!(consistent(&config, &c, 12, 13));
        assert!(consistent(&config, &c, 12, 12));
        // The root's empty constraint admits anything.
        let root = Constraint {
            who: Vec::new(),
            at: Vec::new(),
        };
        assert!(consistent(&config, &root, 10, 11));
    }

    #[test]
    fn pruning_exhausts_an_unsolvable_instance_in_fewer_iterations() {
        // A corridor 0-1-...-7: three agents reverse their order, which has no plan, so LaCAM
        // must exhaust it.
        let g = Graph::from_edges(8, &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 6), (6, 7)]);
        let (starts, goals) = (vec![0, 1, 2], vec![7, 6, 5]);
        let ctx = Ctx::default();
        // The fewest iterations after which the search has exhausted it (the search is the same
        // up to its budget, so whether it exhausts is monotone in the budget).
        let budget = |prune: bool| {
            let lacam = Lacam {
                prune,
                restart_rate: 0.0,
                stall_restart: 0,
                ..Lacam::default()
            };
            let exhausts = |b| {
                matches!(
                    search_within(&lacam, &g, &starts, &goals, &ctx, b, None),
                    Err(Unsolved::GaveUp(_))
                )
            };
            let (mut lo, mut hi) = (0u64, 1u64 << 20);
            assert!(exhausts(hi));
            while hi - lo > 1 {
                let mid = (lo + hi) / 2;
                if exhausts(mid) { hi = mid } else { lo = mid }
            }
            hi
        };
        let (pruned, published) = (budget(true), budget(false));
        assert!(pruned < published, "{pruned} vs {published}");
    }

    #[test]
    fn unsolvability_is_proven_component_by_component() {
        // A corridor 0-1-2-3 (component A) and a plus 4..=8 centred on 4 (component B).
        let g = Graph::from_edges(9, &[(0, 1), (1, 2), (2, 3), (4, 5), (4, 6), (4, 7), (4, 8)]);
        let ctx = Ctx::default();
        let later = Instant::now() + std::time::Duration::from_secs(30);
        let proof = |starts: Vec<VertexId>, goals: Vec<VertexId>| {
            proven_unsolvable(&g, &starts, &goals, &ctx, u64::MAX, later)
        };
        // Two agents swap the corridor's ends: no plan, whatever the others do on the plus.
        let why = proof(vec![5, 0, 6, 3], vec![6, 3, 5, 0]).expect("a proof");
        assert!(
            why.contains("agents 1 and 3 share a component of 4 cells"),
            "{why}"
        );
        // The swap on the plus has a plan, and so has the corridor when its agents keep order.
        assert_eq!(proof(vec![5, 0, 6, 3], vec![6, 1, 5, 2]), None);
        // A goal in another component.
        let why = proof(vec![0, 5], vec![1, 2]).expect("a proof");
        assert!(why.contains("agent 1 cannot reach its goal"), "{why}");
        // One agent per component: nothing to search.
        assert_eq!(proof(vec![0, 5], vec![3, 6]), None);
        // No budget (or no time): no proof.
        let (starts, goals) = (vec![0, 3], vec![3, 0]);
        assert_eq!(proven_unsolvable(&g, &starts, &goals, &ctx, 1, later), None);
        assert_eq!(
            proven_unsolvable(&g, &starts, &goals, &ctx, u64::MAX, Instant::now()),
            None
        );
    }

    /// The T-tree of baselines §1: A-B-C, C-D, C-E (0..=4); r1: A -> B, r2: B -> A.
    fn t_tree() -> (Graph, Instance) {
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (2, 4)]);
        (g, Instance::new(vec![0, 1], vec![1, 0]).unwrap())
    }

    #[test]
    fn lacam_star_converges_on_the_t_tree() {
        let (g, inst) = t_tree();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        for (objective, want) in [(Objective::Makespan, 5), (Objective::SumOfLoss, 10)] {
            for seed in 0..5 {
                let planner = Lacam {
                    anytime: true,
                    objective,
                    restart_rate: 0.001,
                    ..Lacam::default()
                };
                let s = solve(&planner, &p, &Ctx::new(seed, Deadline::none())).unwrap();
                let r = planner.report().unwrap();
                assert!(r.proven_optimal, "{objective:?} seed {seed}: {r:?}");
                assert_eq!(r.final_cost, want, "{objective:?} seed {seed}: {r:?}");
                assert!(r.first_cost >= r.final_cost);
                if objective == Objective::Makespan {
                    assert_eq!(s.metrics.makespan, want);
                }
            }
        }
    }

    /// Each objective's costs are what the returned plan measures on it, and the sum-of-costs
    /// objective returns no plan of higher sum of costs than the sum-of-loss one's first plan
    /// (it keeps the search's plan of least sum of costs, and the refinement only lowers it).
    #[test]
    fn costs_are_reported_on_the_objective_asked_for() {
        // A 12 x 12 open grid, 40 agents on a seeded shuffle of the cells.
        let w = 12u32;
        let mut edges = Vec::new();
        for y in 0..w {
            for x in 0..w {
                let v = y * w + x;
                if x + 1 < w {
                    edges.push((v, v + 1));
                }
                if y + 1 < w {
                    edges.push((v, v + w));
                }
            }
        }
        let g = Graph::from_edges((w * w) as usize, &edges);
        let mut cells: Vec<VertexId> = (0..w * w).collect();
        cells.shuffle(&mut ChaCha8Rng::seed_from_u64(3));
        let inst = Instance::new(cells[..40].to_vec(), cells[40..80].to_vec()).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        let loss = |plan: &Plan| plan.sum_of_loss(&inst.goals);
        for refine in [Refine::Cost, Refine::None, Refine::Loss, Refine::Auto] {
            for objective in [
                Objective::SumOfLoss,
                Objective::SumOfCosts,
                Objective::Makespan,
            ] {
                let planner = Lacam {
                    refine,
                    ..Lacam::star(objective)
                };
                let ctx = Ctx::new(1, Deadline::after(std::time::Duration::from_millis(300)));
                let s = solve(&planner, &p, &ctx).unwrap();
                let r = planner.report().unwrap();
                let what = format!("{objective:?}, refine {refine:?}: {r:?}");
                let measured = match objective {
                    Objective::SumOfCosts => s.metrics.sum_of_costs,
                    Objective::Makespan => s.metrics.makespan,
                    Objective::SumOfLoss => loss(&s.plan),
                };
                assert_eq!(r.final_cost, measured, "{what}");
                assert!(r.first_cost >= r.final_cost, "{what}");
                if objective == Objective::SumOfCosts {
                    assert!(!r.proven_optimal, "{what}");
                    assert!(r.search_cost >= r.final_cost, "{what}");
                }
                // With the makespan every refinement setting but `none` lowers the makespan.
                if objective == Objective::Makespan {
                    let want = (refine != Refine::None).then_some(Objective::Makespan);
                    assert_eq!(r.lns_lowers, want, "{what}");
                }
            }
        }
    }

    /// `refine=auto` lowers the sum of loss on a sparse instance (8 agents on a 12 x 12 grid,
    /// 5.6% covered) and the sum of costs on a dense one (40 agents, 28%); the notes say which.
    #[test]
    fn auto_refinement_follows_the_share_of_vertices_covered() {
        let w = 12u32;
        let mut edges = Vec::new();
        for y in 0..w {
            for x in 0..w {
                let v = y * w + x;
                if x + 1 < w {
                    edges.push((v, v + 1));
                }
                if y + 1 < w {
                    edges.push((v, v + w));
                }
            }
        }
        let g = Graph::from_edges((w * w) as usize, &edges);
        let mut cells: Vec<VertexId> = (0..w * w).collect();
        cells.shuffle(&mut ChaCha8Rng::seed_from_u64(3));
        for (n, lowers_loss) in [(8usize, true), (40, false)] {
            let inst = Instance::new(cells[..n].to_vec(), cells[n..2 * n].to_vec()).unwrap();
            let p = MapfProblem::on(&g, &inst, Rules::default());
            let planner = Lacam {
                restart_rate: 0.0,
                ..Lacam::star(Objective::SumOfLoss)
            };
            let ctx = Ctx::new(1, Deadline::after(std::time::Duration::from_millis(200)));
            solve(&planner, &p, &ctx).unwrap();
            // The LNS is set up at the first plan, whatever comes after.
            let r = planner.report().unwrap();
            let want = if lowers_loss {
                Objective::SumOfLoss
            } else {
                Objective::SumOfCosts
            };
            assert_eq!(r.lns_lowers, Some(want), "{n} agents: {r:?}");
            if r.lns_steps > 0 {
                assert_eq!(planner.notes()["lns_lowers"], want.name());
            }
        }
    }
}
