//! Large-neighbourhood search that lowers a valid plan's cost (J. Li, Z. Chen, D. Harabor,
//! P. J. Stuckey, S. Koenig, "Anytime multi-agent path finding via large neighborhood search",
//! IJCAI 2021): each step takes up to `k` agents' paths out, re-plans those agents one at a time
//! in a random order with safe-interval path planning ([`sipp`]) against everyone else's paths,
//! and keeps the new paths when their summed cost is not larger (else restores the old ones).
//! LaCAM*'s anytime phase runs it between its own search rounds (the role of the refiners of
//! lacam3, Okumura, AAMAS 2024).
//!
//! **What it lowers** ([`Lns::new`]'s `lowers`): the sum of costs, or the sum of loss (lacam3's
//! objective: each agent's steps except those it stays on its goal, so an agent that waits on its
//! goal and steps aside later is not charged for the waits). With sum of loss a step keeps the
//! new paths when their summed loss is lower, or equal with a sum of costs not larger, and the
//! re-planning searches minimise each path's loss ([`sipp_loss`], as lacam3's refiner does);
//! with sum of costs they find earliest arrivals ([`sipp`]). With the makespan (mrpp's; MAPF-LNS
//! lowers sums only) the key is (makespan, sum of costs): a step keeps new paths that arrive no
//! later than the current makespan and whose sum of costs is not larger, or that lower the
//! makespan (each compared with every other agent's latest arrival, so the whole plan's key never
//! rises); the re-planning finds earliest arrivals, and the agent-based neighbourhood starts from
//! a latest-arriving agent, drawn among them, instead of the most delayed of a sample.
//!
//! **Neighbourhoods** are MAPF-LNS's three destroy heuristics, drawn adaptively (its ALNS,
//! Sec. 4.3: each drawn with probability proportional to a weight that follows the objective
//! each of its steps removed per agent, reaction factor 0.01): *random* (uniform agents),
//! *agent-based* (the most delayed agent, objective minus goal distance, among a random sample of
//! 32, with agents whose paths visit the cells of its shortest route) and *intersection* (agents
//! visiting a random vertex of degree 3 or more and the intersections nearest it). The plan
//! stays valid after every step: the re-planned paths obey the reservation table that holds
//! every other path, with the rules of the validator (stay at the goal, following allowed).
//!
//! **Threads** ([`Lns::with_threads`]): with `t` threads, [`Lns::steps`] runs `t` chains of
//! steps at once, each on its own copy of the plan with its own seeded generator and weights, and
//! then merges them: the first chain's steps stand, and each other chain's kept steps are
//! replayed in order onto the result when none of their agents was moved by another chain and
//! their new paths fit and do not raise the key there. Every chain then restarts from the merged
//! plan. Chains replace one repair per thread in lockstep rounds, which wait for the slower of
//! their repairs (repair times vary by orders of magnitude): on den520d with 1,000 agents, 30 s,
//! lockstep rounds at two threads took 3,680 steps against 3,152 at one; chains took
//! 5,900-9,000 against 4,064 (with [`sipp_loss`]'s reused tables, which also removed allocator
//! traffic between the threads). For a seed and a thread count the result depends on the rounds
//! run, not on how the threads are scheduled.

use rand::seq::{IndexedRandom, SliceRandom};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustc_hash::{FxHashMap, FxHashSet};

use mrpp_core::mapf::search::distance::GoalDistances;
use mrpp_core::mapf::search::sipp::{sipp, sipp_loss};
use mrpp_core::mapf::search::spacetime::{Query, Reservations, Search};
use mrpp_core::{Deadline, Graph, VertexId};

use crate::lacam::Objective;

/// Steps a re-planned path may end after the current makespan (a second bound, besides the
/// group's budget).
const SLACK: u32 = 8;

/// MAPF-LNS's reaction factor `γ` of the adaptive weights (Li et al., IJCAI 2021, Sec. 4.3).
const REACTION: f64 = 0.01;

/// A plan being improved.
pub(crate) struct Lns<'a> {
    cx: Shared<'a>,
    /// The plan, and the chain the calling thread runs.
    main: Chain,
    /// The chains of the other threads (`threads - 1`), equal to `main` between rounds.
    others: Vec<Chain>,
    /// Steps that lowered the plan's key and stood (kept in a chain, and merged).
    improved: u64,
}

/// What every chain reads: the instance, its distance tables, what is lowered, the neighbourhood
/// size and the map's intersections.
struct Shared<'a> {
    graph: &'a Graph,
    goals: &'a [VertexId],
    dist: &'a GoalDistances<'a>,
    /// What the steps lower (module doc).
    lowers: Objective,
    /// Neighbourhood size.
    k: usize,
    /// The vertices of degree 3 or more (where intersection neighbourhoods start).
    intersections: Vec<VertexId>,
}

/// One thread's copy of the plan and its own search state.
#[derive(Clone)]
struct Chain {
    paths: Vec<Vec<VertexId>>,
    res: Reservations,
    /// Per vertex, the agents whose current paths visit it (each once).
    visitors: Vec<Vec<u32>>,
    rng: ChaCha8Rng,
    /// The adaptive weights of the neighbourhoods, indexed by [`Destroy`].
    weights: [f64; 3],
    steps: u64,
    /// The steps kept since the last merge: agents and their new paths.
    log: Vec<(Vec<usize>, Vec<Vec<VertexId>>)>,
}

/// MAPF-LNS's destroy heuristics ([`Chain::neighbourhood`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Destroy {
    /// Agents drawn uniformly.
    Random = 0,
    /// The most delayed agent of a sample and agents on its shortest route.
    AgentBased = 1,
    /// Agents that visit an intersection and the intersections around it, breadth first.
    Intersection = 2,
}

/// What a repair reads: the instance and the current plan.
struct View<'v> {
    graph: &'v Graph,
    goals: &'v [VertexId],
    dist: &'v GoalDistances<'v>,
    paths: &'v [Vec<VertexId>],
    lowers: Objective,
}

pub(crate) use mrpp_core::mapf::plan::path_loss;

/// A path's cost: the step of its last arrival at `goal` (its length - 1 once trailing waits on
/// the goal are cut).
fn trimmed(mut p: Vec<VertexId>) -> Vec<VertexId> {
    while p.len() > 1 && p[p.len() - 1] == p[p.len() - 2] {
        p.pop();
    }
    p
}

/// Adds `agent`, enrolled nowhere, to the visitors of the vertices of `path`. Within one call
/// only `agent` is added, so a vertex it already visited has it last in its list: a check of
/// the last entry, not a scan of the list (with 10,000 agents on warehouse-20-40-10-2-1 some 17
/// million path steps fall on 22,599 vertices, so the lists are long).
fn enrol(visitors: &mut [Vec<u32>], agent: usize, path: &[VertexId]) {
    let a = agent as u32;
    for &v in path {
        let list = &mut visitors[v as usize];
        if list.last() != Some(&a) {
            debug_assert!(!list.contains(&a), "agent {a} enrolled twice at {v}");
            list.push(a);
        }
    }
}

/// Removes `agent` from the visitors of the vertices of `path` (a wait's vertex once).
fn withdraw(visitors: &mut [Vec<u32>], agent: usize, path: &[VertexId]) {
    let a = agent as u32;
    for (k, &v) in path.iter().enumerate() {
        if k > 0 && path[k - 1] == v {
            continue;
        }
        let list = &mut visitors[v as usize];
        if let Some(i) = list.iter().position(|&x| x == a) {
            list.swap_remove(i);
        }
    }
}

impl<'a> Lns<'a> {
    /// Starts from the valid plan `paths` (one path per agent, from its start to its goal).
    pub(crate) fn new(
        graph: &'a Graph,
        goals: &'a [VertexId],
        dist: &'a GoalDistances<'a>,
        paths: Vec<Vec<VertexId>>,
        seed: u64,
        lowers: Objective,
    ) -> Self {
        let paths: Vec<Vec<VertexId>> = paths.into_iter().map(trimmed).collect();
        let mut res = Reservations::new(graph.num_vertices());
        let mut visitors = vec![Vec::new(); graph.num_vertices()];
        for (i, p) in paths.iter().enumerate() {
            res.reserve_path(p, 0, true);
            enrol(&mut visitors, i, p);
        }
        let intersections = (0..graph.num_vertices() as VertexId)
            .filter(|&v| graph.neighbors(v).len() >= 3)
            .collect();
        Lns {
            cx: Shared {
                graph,
                goals,
                dist,
                lowers,
                k: paths.len().min(8),
                intersections,
            },
            main: Chain {
                paths,
                res,
                visitors,
                rng: ChaCha8Rng::seed_from_u64(seed),
                weights: [1.0; 3],
                steps: 0,
                log: Vec::new(),
            },
            others: Vec::new(),
            improved: 0,
        }
    }

    /// Runs `threads` chains at once in [`Lns::steps`] (default 1); chain `j > 0` draws from
    /// its own generator, seeded from the first's.
    pub(crate) fn with_threads(mut self, threads: usize) -> Self {
        self.others = (1..threads.max(1))
            .map(|_| {
                let mut c = self.main.clone();
                c.rng = ChaCha8Rng::seed_from_u64(self.main.rng.random());
                c
            })
            .collect();
        self
    }

    /// The current plan's cost on what it lowers: (sum of costs, 0), (sum of loss, sum of costs)
    /// or (makespan, sum of costs); lower is better.
    pub(crate) fn key(&self) -> (u64, u64) {
        self.key_of(&self.main.paths, 0..self.main.paths.len())
    }

    /// [`Self::key`] of another plan of the same agents (e.g. the search's; trailing waits on
    /// the goals are not counted).
    pub(crate) fn key_of_plan(&self, paths: &[Vec<VertexId>]) -> (u64, u64) {
        let trimmed: Vec<Vec<VertexId>> = paths.iter().cloned().map(trimmed).collect();
        self.key_of(&trimmed, 0..trimmed.len())
    }

    /// [`Self::key`] of `paths`, the paths of `agents` in order.
    fn key_of(
        &self,
        paths: &[Vec<VertexId>],
        agents: impl IntoIterator<Item = usize>,
    ) -> (u64, u64) {
        key_of(self.cx.goals, self.cx.lowers, paths, agents, 0)
    }

    /// What it lowers.
    pub(crate) fn lowers(&self) -> Objective {
        self.cx.lowers
    }

    /// Steps taken (by every chain) and steps that lowered the plan's cost.
    pub(crate) fn counts(&self) -> (u64, u64) {
        let steps = self.main.steps + self.others.iter().map(|c| c.steps).sum::<u64>();
        (steps, self.improved)
    }

    /// The current plan.
    pub(crate) fn paths(&self) -> &[Vec<VertexId>] {
        &self.main.paths
    }

    /// Replaces the plan by `paths` (e.g. a better one found elsewhere).
    pub(crate) fn reset(&mut self, paths: Vec<Vec<VertexId>>) {
        let m = &mut self.main;
        for (i, p) in m.paths.iter().enumerate() {
            m.res.release_path(p, 0, true);
            withdraw(&mut m.visitors, i, p);
        }
        m.paths = paths.into_iter().map(trimmed).collect();
        for (i, p) in m.paths.iter().enumerate() {
            m.res.reserve_path(p, 0, true);
            enrol(&mut m.visitors, i, p);
        }
        for c in &mut self.others {
            c.paths.clone_from(&m.paths);
            c.res.clone_from(&m.res);
            c.visitors.clone_from(&m.visitors);
        }
    }

    /// `rounds` steps in each chain (module doc), then a merge; the number of steps that lowered
    /// the plan's cost and stood (with one thread, `rounds` steps, no merge). A chain stops early
    /// once `deadline` has passed. `tick(k)` runs on the calling thread after its chain's `k`-th
    /// step (for progress reports: a round of several threads can take seconds).
    pub(crate) fn steps(
        &mut self,
        rounds: usize,
        deadline: Deadline,
        mut tick: impl FnMut(usize),
    ) -> u64 {
        let cx = &self.cx;
        let run = |c: &mut Chain, tick: &mut dyn FnMut(usize)| {
            let mut lowered = 0;
            for k in 1..=rounds {
                if deadline.expired() {
                    break;
                }
                lowered += u64::from(c.step(cx, deadline));
                tick(k);
            }
            lowered
        };
        if self.others.is_empty() {
            // One chain: its steps stand as they are; nothing to merge.
            let lowered = run(&mut self.main, &mut tick);
            self.main.log.clear();
            self.improved += lowered;
            return lowered;
        }
        // Plain scoped threads, not a rayon pool: a rayon worker that waits for another pool
        // runs its own pool's queued jobs meanwhile, which in `mrpp bench` are other runs,
        // started inside this one.
        let main = &mut self.main;
        let mut lowered = std::thread::scope(|sc| {
            let handles: Vec<_> = self
                .others
                .iter_mut()
                .map(|c| sc.spawn(move || run(c, &mut |_| {})))
                .collect();
            let own = run(main, &mut tick);
            for h in handles {
                h.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
            }
            own
        });
        lowered += self.merge();
        self.improved += lowered;
        lowered
    }

    /// Merges the other chains' logged steps into the first chain's plan (module doc) and
    /// restarts every other chain from it; the number of merged steps that lowered the key.
    fn merge(&mut self) -> u64 {
        let cx = &self.cx;
        let mut lowered = 0;
        // Merge: who moved each agent this round (0: the first chain).
        let mut owner: FxHashMap<usize, usize> = FxHashMap::default();
        for (group, _) in self.main.log.drain(..) {
            for i in group {
                owner.insert(i, 0);
            }
        }
        let mut touched: Vec<Vec<usize>> = Vec::with_capacity(self.others.len());
        for (j, c) in self.others.iter_mut().enumerate() {
            let j = j + 1;
            let mut mine = Vec::new();
            for (group, new) in c.log.drain(..) {
                mine.extend_from_slice(&group);
                if group.iter().any(|i| owner.get(i).is_some_and(|&o| o != j)) {
                    continue;
                }
                let m = &mut self.main;
                let floor = floor_of(cx.lowers, &m.paths, &group);
                let old_key = key_of(
                    cx.goals,
                    cx.lowers,
                    &group
                        .iter()
                        .map(|&i| m.paths[i].clone())
                        .collect::<Vec<_>>(),
                    group.iter().copied(),
                    floor,
                );
                let new_key = key_of(cx.goals, cx.lowers, &new, group.iter().copied(), floor);
                if new_key > old_key {
                    continue;
                }
                for &i in &group {
                    m.res.release_path(&m.paths[i], 0, true);
                }
                if !fits(&mut m.res, &new) {
                    for &i in &group {
                        m.res.reserve_path(&m.paths[i], 0, true);
                    }
                    continue;
                }
                for (&i, p) in group.iter().zip(new) {
                    m.res.reserve_path(&p, 0, true);
                    withdraw(&mut m.visitors, i, &m.paths[i]);
                    enrol(&mut m.visitors, i, &p);
                    m.paths[i] = p;
                    owner.insert(i, j);
                }
                lowered += u64::from(new_key < old_key);
            }
            touched.push(mine);
        }
        // Every other chain restarts from the merged plan.
        for (c, mine) in self.others.iter_mut().zip(touched) {
            let mut diff: Vec<usize> = owner.keys().copied().chain(mine).collect();
            diff.sort_unstable();
            diff.dedup();
            diff.retain(|&i| c.paths[i] != self.main.paths[i]);
            for &i in &diff {
                c.res.release_path(&c.paths[i], 0, true);
                withdraw(&mut c.visitors, i, &c.paths[i]);
            }
            for &i in &diff {
                c.paths[i].clone_from(&self.main.paths[i]);
                c.res.reserve_path(&c.paths[i], 0, true);
                enrol(&mut c.visitors, i, &c.paths[i]);
            }
        }
        lowered
    }
}

impl Chain {
    /// The agents of the next neighbourhood and the heuristic that drew them: drawn with
    /// probability proportional to its weight (adaptive LNS, MAPF-LNS Sec. 4.3); a heuristic
    /// that finds fewer than two agents falls back to random.
    fn neighbourhood(&mut self, cx: &Shared) -> (Vec<usize>, Destroy) {
        let n = self.paths.len();
        let total: f64 = self.weights.iter().sum();
        let mut x = self.rng.random::<f64>() * total;
        let mut kind = Destroy::Intersection;
        for (k, d) in [Destroy::Random, Destroy::AgentBased]
            .into_iter()
            .enumerate()
        {
            if x < self.weights[k] {
                kind = d;
                break;
            }
            x -= self.weights[k];
        }
        let mut chosen = match kind {
            Destroy::Random => Vec::new(),
            Destroy::AgentBased => self.agent_based(cx),
            Destroy::Intersection => self.intersection(cx),
        };
        if chosen.len() < 2 {
            chosen = (0..n)
                .collect::<Vec<_>>()
                .sample(&mut self.rng, cx.k)
                .copied()
                .collect();
        }
        (chosen, kind)
    }

    /// Agent-based neighbourhood: the most delayed agent (objective minus goal distance) of a
    /// sample of 32 (with the makespan: a latest-arriving agent, drawn among them), with agents
    /// whose paths visit the cells of one of its shortest routes; empty when that agent is not
    /// delayed.
    fn agent_based(&mut self, cx: &Shared) -> Vec<usize> {
        let n = self.paths.len();
        let delay = |i: usize| {
            let p = &self.paths[i];
            let cost = match cx.lowers {
                Objective::SumOfLoss => path_loss(p, cx.goals[i]),
                Objective::SumOfCosts | Objective::Makespan => p.len() as u64 - 1,
            };
            cost.saturating_sub(u64::from(cx.dist.get(i, p[0])))
        };
        let a = if cx.lowers == Objective::Makespan {
            // A latest-arriving agent (drawn among them): only its arrival sets the makespan.
            let last = self.paths.iter().map(Vec::len).max().unwrap_or(1);
            let latest: Vec<usize> = (0..n).filter(|&i| self.paths[i].len() == last).collect();
            match latest.choose(&mut self.rng) {
                Some(&a) => a,
                None => return Vec::new(),
            }
        } else {
            let sample: Vec<usize> = (0..n)
                .collect::<Vec<_>>()
                .sample(&mut self.rng, n.min(32))
                .copied()
                .collect();
            match sample
                .iter()
                .max_by_key(|&&i| (delay(i), std::cmp::Reverse(i)))
            {
                Some(&a) => a,
                None => return Vec::new(),
            }
        };
        if delay(a) == 0 {
            return Vec::new();
        }
        // A shortest route of `a`, down its distance table, and who visits it.
        let mut others: Vec<usize> = Vec::new();
        let mut v = self.paths[a][0];
        loop {
            others.extend(self.visitors[v as usize].iter().map(|&j| j as usize));
            let d = cx.dist.get(a, v);
            if d == 0 {
                break;
            }
            v = *cx
                .graph
                .neighbors(v)
                .iter()
                .find(|&&w| cx.dist.get(a, w) + 1 == d)
                .expect("a BFS table always has a predecessor");
        }
        others.sort_unstable();
        others.dedup();
        others.retain(|&j| j != a);
        others.shuffle(&mut self.rng);
        std::iter::once(a)
            .chain(others.into_iter().take(cx.k - 1))
            .collect()
    }

    /// Intersection neighbourhood (MAPF-LNS's map-based one): the agents that visit a random
    /// intersection, then those of the intersections nearest it (breadth first over at most
    /// 1,024 vertices), up to `k`.
    fn intersection(&mut self, cx: &Shared) -> Vec<usize> {
        let Some(&root) = cx.intersections.choose(&mut self.rng) else {
            return Vec::new();
        };
        let mut chosen: Vec<usize> = Vec::new();
        let mut seen: FxHashSet<VertexId> = FxHashSet::default();
        let mut queue = std::collections::VecDeque::from([root]);
        seen.insert(root);
        while let Some(v) = queue.pop_front() {
            if cx.graph.neighbors(v).len() >= 3 {
                let mut here: Vec<usize> = self.visitors[v as usize]
                    .iter()
                    .map(|&j| j as usize)
                    .filter(|j| !chosen.contains(j))
                    .collect();
                here.sort_unstable();
                here.shuffle(&mut self.rng);
                chosen.extend(here.into_iter().take(cx.k - chosen.len()));
                if chosen.len() >= cx.k {
                    break;
                }
            }
            if seen.len() >= 1024 {
                continue;
            }
            for &w in cx.graph.neighbors(v) {
                if seen.insert(w) {
                    queue.push_back(w);
                }
            }
        }
        chosen
    }

    /// Updates the weight of `kind` after a step that lowered the objective by `gain` over
    /// `size` agents (0 when it did not): `w = γ·gain/size + (1 − γ)·w` (MAPF-LNS).
    fn learn(&mut self, kind: Destroy, gain: u64, size: usize) {
        let w = &mut self.weights[kind as usize];
        *w = REACTION * gain as f64 / size.max(1) as f64 + (1.0 - REACTION) * *w;
    }

    /// One destroy-and-repair step; true when the chain's plan's key dropped. A kept step is
    /// logged for the merge ([`Lns::steps`]).
    fn step(&mut self, cx: &Shared, deadline: Deadline) -> bool {
        self.steps += 1;
        let (mut group, kind) = self.neighbourhood(cx);
        group.shuffle(&mut self.rng);
        let view = View {
            graph: cx.graph,
            goals: cx.goals,
            dist: cx.dist,
            paths: &self.paths,
            lowers: cx.lowers,
        };
        let Some((new, improved, gain)) = view.repair(&mut self.res, &group, deadline) else {
            self.learn(kind, 0, group.len());
            return false;
        };
        self.learn(kind, gain, group.len());
        for (&i, p) in group.iter().zip(&new) {
            self.res.release_path(&self.paths[i], 0, true);
            withdraw(&mut self.visitors, i, &self.paths[i]);
            enrol(&mut self.visitors, i, p);
            self.paths[i].clone_from(p);
        }
        for &i in &group {
            self.res.reserve_path(&self.paths[i], 0, true);
        }
        self.log.push((group, new));
        improved
    }
}

/// Whether `paths` (each from time 0, parked at its end) obey `res` and each other, by the rules
/// [`sipp`] plans with; `res` is left as it was either way.
fn fits(res: &mut Reservations, paths: &[Vec<VertexId>]) -> bool {
    for (n, p) in paths.iter().enumerate() {
        let ok = (1..p.len()).all(|t| res.move_free(p[t - 1], p[t], t as u32))
            && res.free_from(p[p.len() - 1], p.len() as u32 - 1)
            && res.vertex_free(p[p.len() - 1], p.len() as u32 - 1);
        if !ok {
            for q in &paths[..n] {
                res.release_path(q, 0, true);
            }
            return false;
        }
        res.reserve_path(p, 0, true);
    }
    for q in paths {
        res.release_path(q, 0, true);
    }
    true
}

/// [`key_of`]'s `floor` for a step that re-plans `group`: with the makespan, the latest arrival
/// (trimmed path length - 1) among the agents of `paths` not in `group` (0 when there are none);
/// 0 for the other objectives.
fn floor_of(lowers: Objective, paths: &[Vec<VertexId>], group: &[usize]) -> u64 {
    if lowers != Objective::Makespan {
        return 0;
    }
    paths
        .iter()
        .enumerate()
        .filter(|(i, _)| !group.contains(i))
        .map(|(_, p)| p.len() as u64 - 1)
        .max()
        .unwrap_or(0)
}

/// The (objective, sum of costs) key of `paths`, the paths of `agents` in order ([`Lns::key`]).
/// For the makespan, the latest arrival is taken with `floor`, the latest of every other agent
/// ([`floor_of`]; 0 for the whole plan), so that comparing a group's keys compares the
/// plan's (makespan, sum of costs) before and after; the other objectives ignore `floor`.
fn key_of(
    goals: &[VertexId],
    lowers: Objective,
    paths: &[Vec<VertexId>],
    agents: impl IntoIterator<Item = usize>,
    floor: u64,
) -> (u64, u64) {
    let soc: u64 = paths.iter().map(|p| p.len() as u64 - 1).sum();
    match lowers {
        Objective::SumOfCosts => (soc, 0),
        Objective::SumOfLoss => {
            let sol = paths
                .iter()
                .zip(agents)
                .map(|(p, i)| path_loss(p, goals[i]))
                .sum();
            (sol, soc)
        }
        Objective::Makespan => {
            let makespan = paths.iter().map(|p| p.len() as u64 - 1).max();
            (makespan.unwrap_or(0).max(floor), soc)
        }
    }
}

impl View<'_> {
    /// Re-plans the agents of `group`, in its order, against `res` without their paths: their
    /// new paths, whether they lower the key and by how much its first value (the objective)
    /// dropped, when they are found and do not raise the key, else `None`. `res` is left as it
    /// was.
    fn repair(
        &self,
        res: &mut Reservations,
        group: &[usize],
        deadline: Deadline,
    ) -> Option<(Vec<Vec<VertexId>>, bool, u64)> {
        let old: Vec<&Vec<VertexId>> = group.iter().map(|&i| &self.paths[i]).collect();
        for p in &old {
            res.release_path(p, 0, true);
        }
        // The group's new paths may not cost more than its old ones, nor end more than SLACK
        // steps after the makespan: each search is bounded by what is left of that budget after
        // the paths already found and the distances of the agents still to go, so a hopeless
        // search fails fast instead of exploring every (cell, time) up to a far horizon.
        let floor = floor_of(self.lowers, self.paths, group);
        let old_key = key_of(
            self.goals,
            self.lowers,
            &old.iter().map(|p| p.to_vec()).collect::<Vec<_>>(),
            group.iter().copied(),
            floor,
        );
        // Each new path's loss is at most its cost, and its cost at most the group's old
        // objective value left after the others' lower bounds.
        let old_cost = old_key.0;
        let lower: Vec<u64> = group
            .iter()
            .map(|&i| u64::from(self.dist.get(i, self.paths[i][0])))
            .collect();
        let mut spent = 0u64;
        let makespan = self.paths.iter().map(Vec::len).max().unwrap_or(1) as u32;
        let mut new: Vec<Vec<VertexId>> = Vec::with_capacity(group.len());
        for (k, &i) in group.iter().enumerate() {
            let rest: u64 = lower[k + 1..].iter().sum();
            // The makespan bounds each path on its own (no sum to share out): none may arrive
            // after the plan's makespan (`old_cost`, taken with every other agent's latest).
            let budget = if self.lowers == Objective::Makespan {
                old_cost
            } else {
                match old_cost.checked_sub(spent + rest) {
                    Some(b) => b,
                    None => break,
                }
            };
            let dist = self.dist;
            let h = move |v: VertexId| dist.get(i, v);
            let budget = u32::try_from(budget).unwrap_or(u32::MAX);
            // A path's loss is at most its cost: the budget bounds its time only without loss.
            let q = Query {
                graph: self.graph,
                start: self.paths[i][0],
                goal: self.goals[i],
                start_time: 0,
                h: &h,
                max_time: match self.lowers {
                    Objective::SumOfLoss => makespan + SLACK,
                    Objective::SumOfCosts => budget.min(makespan + SLACK),
                    Objective::Makespan => budget,
                },
                window: None,
                deadline,
            };
            let found = match self.lowers {
                Objective::SumOfLoss => sipp_loss(&q, res, budget),
                Objective::SumOfCosts | Objective::Makespan => sipp(&q, res),
            };
            match found {
                Search::Found(p) => {
                    let p = trimmed(p);
                    spent += match self.lowers {
                        Objective::SumOfLoss => path_loss(&p, self.goals[i]),
                        Objective::SumOfCosts | Objective::Makespan => p.len() as u64 - 1,
                    };
                    res.reserve_path(&p, 0, true);
                    new.push(p);
                }
                _ => break,
            }
        }
        for p in &new {
            res.release_path(p, 0, true);
        }
        for p in &old {
            res.reserve_path(p, 0, true);
        }
        let new_key = key_of(self.goals, self.lowers, &new, group.iter().copied(), floor);
        (new.len() == group.len() && new_key <= old_key).then(|| {
            let gain = old_key.0 - new_key.0;
            (new, new_key < old_key, gain)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lacam::Lacam;
    use mrpp_core::{Ctx, MapfProblem, Plan, Planner, Problem, Rules};

    /// On both objectives, with one and with several threads: every round leaves a valid plan
    /// whose (objective, sum of costs) key never rises, the key is the validator's count, and
    /// 200 steps lower it.
    #[test]
    fn steps_keep_the_plan_valid_and_never_raise_its_cost() {
        let map = crate::GridMap::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../data/movingai/random-32-32-20.map"
        )))
        .unwrap();
        let inst = crate::map::random_instance(&map, 120, 3).unwrap();
        let g = map.graph();
        let p = MapfProblem::on(g, &inst, Rules::default());
        let plan = Lacam::default().plan(&p, &Ctx::default()).unwrap();
        let mut dist = GoalDistances::new(g, &inst.goals);
        assert!(dist.warm_up(&inst.starts, Deadline::none()));
        // The validator's sum of costs and makespan, and the sum of loss recounted from the
        // padded paths.
        let counts = |paths: &[Vec<VertexId>]| {
            let m = p.validate(&Plan::new(paths.to_vec())).unwrap();
            let (soc, makespan) = (m.sum_of_costs, m.makespan);
            let horizon = paths.iter().map(Vec::len).max().unwrap();
            let sol: u64 = paths
                .iter()
                .zip(&inst.goals)
                .map(|(q, &goal)| {
                    (0..horizon - 1)
                        .filter(|&t| {
                            let at = |t: usize| q[t.min(q.len() - 1)];
                            !(at(t) == goal && at(t + 1) == goal)
                        })
                        .count() as u64
                })
                .sum();
            (sol, soc, makespan)
        };
        use Objective::{Makespan, SumOfCosts, SumOfLoss};
        for (lowers, threads) in [
            (SumOfCosts, 1),
            (SumOfLoss, 1),
            (Makespan, 1),
            (SumOfCosts, 3),
            (SumOfLoss, 2),
            (Makespan, 2),
        ] {
            let mut lns = Lns::new(g, &inst.goals, &dist, plan.paths.clone(), 7, lowers)
                .with_threads(threads);
            let key = |paths: &[Vec<VertexId>]| {
                let (sol, soc, makespan) = counts(paths);
                match lowers {
                    SumOfCosts => (soc, 0),
                    SumOfLoss => (sol, soc),
                    Makespan => (makespan, soc),
                }
            };
            let before = key(&plan.paths);
            let mut last = lns.key();
            assert_eq!(last, before, "{lowers:?}");
            for _ in 0..200 / threads {
                lns.steps(1, Deadline::none(), |_| {});
                assert!(lns.key() <= last, "{lowers:?}");
                // Valid after every round (the validator judges the padded plan).
                p.validate(&Plan::new(lns.paths().to_vec())).unwrap();
                last = lns.key();
            }
            // The other chains restart from the merged plan: same paths, tables and visitors.
            for c in &lns.others {
                assert_eq!(c.paths, lns.main.paths);
                for v in 0..g.num_vertices() as VertexId {
                    for t in 0..40 {
                        assert_eq!(c.res.vertex_free(v, t), lns.main.res.vertex_free(v, t));
                    }
                    let mut a = c.visitors[v as usize].clone();
                    let mut b = lns.main.visitors[v as usize].clone();
                    a.sort_unstable();
                    b.sort_unstable();
                    assert_eq!(a, b);
                }
            }
            assert_eq!(key(lns.paths()), last, "{lowers:?}");
            // Rounds do not depend on how the threads were scheduled.
            let mut again = Lns::new(g, &inst.goals, &dist, plan.paths.clone(), 7, lowers)
                .with_threads(threads);
            for _ in 0..200 / threads {
                again.steps(1, Deadline::none(), |_| {});
            }
            assert_eq!(again.paths(), lns.paths(), "{lowers:?}, {threads} threads");
            assert!(last < before, "{lowers:?}: {last:?} !< {before:?}");
        }
    }
}
