//! Algorithm 1 of the paper: `i_r` runs of `i_g` generations over a population of `|P|` decision
//! trees, fitness (1) on the fitness set X under the time budget τ_B (§4.3), fitness-proportionate
//! selection with β_k = 1/(1 + F_k) and the next generation made by reproduction, crossover and
//! mutation in the proportions p_a, p_c, p_m (§4.4). ψ* is the program that solved all of X in the
//! fewest total time steps τ_B; it survives across runs.
//!
//! Choices where the paper is silent:
//! - **τ_B within a generation.** Algorithm 1 lowers τ_B while it walks the population, so later
//!   programs of the same generation get the tighter budget. Here a whole generation is evaluated
//!   (in parallel) with the τ_B it started with; then lines 8–10 run over the results in index
//!   order. The outcome does not depend on the thread count.
//! - **The budget over several examples.** A program gets τ_B steps in total: the examples run in
//!   order, each with the cap min(M, τ_B − steps used so far) (the paper: "a total of τ_B time
//!   steps to solve all of the examples"). Before any program solves X, τ_B = ∞ and each example
//!   gets its own M.
//! - **Initial population** ([`Init`]): ramped half-and-half by default (depths 1..=2 in turn,
//!   full and grow alternately); the authors' code uses full trees of depth 2 ([`Init::Full`]).
//! - **Depth bounds.** Depth counts edges (a lone action has depth 0). A crossover or mutation child
//!   outside `min_depth..=max_depth` is redrawn with new points up to 8 times, then the parent is
//!   copied instead. Mutation grows the new subtree with depth at most `mutation_depth`.
//! - **Operators.** Points are uniform over all nodes. ⌊p_a·|P|⌉ programs are copied, ⌊p_c·|P|⌉
//!   children come from crossovers (two per pair; an odd count keeps one child of the last pair),
//!   the rest from mutations, each parent drawn by roulette with α_k = β_k / Σβ.
//! - **Early stop.** No program can solve an example in fewer steps than its longest start–goal
//!   distance; once τ_B equals the sum of these bounds, ψ* can no longer change and the search
//!   stops ([`GpParams::stop_at_lower_bound`]).
//!
//! Reproducibility: every random draw comes from a `ChaCha8Rng` seeded by [`derive_seed`] from
//! the seed and a key naming the run, generation and individual or operation (`gp/init/r/k`,
//! `gp/breed/r/g/o`); fitness runs use no randomness. Results are therefore bit-for-bit equal
//! whatever the number of rayon threads.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use crate::gp::program::{Action, Gene, Program};
use crate::gp::simulate::{Problem, SimOptions, Stop, run_program_marking};
use mrpp_core::contract::Deadline;
use mrpp_core::error::{Error, Result};
use mrpp_core::seeds::derive_seed;

/// How the first population of each run is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Init {
    /// Every tree full to `init_depth` (the authors' code: EpochX's FullInitialiser).
    Full,
    /// Koza's grow method up to `init_depth`.
    Grow,
    /// Depths `min_depth..=init_depth` in turn, full and grow alternately. Default.
    #[default]
    RampedHalfAndHalf,
}

/// Parameters of Algorithm 1.
#[derive(Debug, Clone, PartialEq)]
pub struct GpParams {
    /// |P|.
    pub population: usize,
    /// i_g: generations per run.
    pub generations: usize,
    /// i_r: runs (each starts from a fresh population; ψ* and τ_B carry over).
    pub runs: usize,
    /// p_a: share of the next generation copied by reproduction.
    pub p_reproduction: f64,
    /// p_c: share made by crossover.
    pub p_crossover: f64,
    /// p_m: share made by mutation.
    pub p_mutation: f64,
    pub init: Init,
    /// Maximum depth of the initial programs (paper: 2).
    pub init_depth: usize,
    /// Depth bounds of every program (paper: 1 and 50).
    pub min_depth: usize,
    pub max_depth: usize,
    /// Maximum depth of the subtree a mutation grows.
    pub mutation_depth: usize,
    pub sim: SimOptions,
    /// Stop once τ_B reaches the lower bound (ψ* cannot improve any more).
    pub stop_at_lower_bound: bool,
    /// Per-example step cap during evolution: min(M, factor·|N|); `None` = the paper's
    /// M = |N|²·|R|². Programs that never solve mostly fall into short cycles, which are cut
    /// exactly, but some (robots touring every branch node in turn, say) have joint periods of
    /// millions of steps, and M reaches 10⁷–10⁹ on the paper's larger trees, so one such program
    /// costs minutes and one generation hours. The default factor 20 (PSW needs 4.6·|N| steps on
    /// average and at most 6·|N| on 200 of the paper's problems) changes the fitness only of
    /// programs slower than that. A cap that grows with |N|·|R| instead left the largest problems
    /// (≈1000 nodes, 250–500 robots) at seconds per program.
    pub cap_factor: Option<u64>,
}

impl GpParams {
    /// The paper's §7 settings: |P| = 2000, i_r = 5 runs of i_g = 400 generations, p_a = 0.1,
    /// p_c = 0.8, p_m = 0.1, initial depth 2, depths 1..=50, ρ = 2, step cap M.
    pub fn paper() -> Self {
        GpParams {
            population: 2000,
            generations: 400,
            runs: 5,
            cap_factor: None,
            ..GpParams::default()
        }
    }

    /// Checks ranges; the three proportions must sum to 1 (±1e-9).
    pub fn check(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Param(m));
        if self.population < 2 {
            return bad(format!(
                "the population needs at least 2 programs, got {}",
                self.population
            ));
        }
        if self.generations == 0 || self.runs == 0 {
            return bad("at least one run of one generation is needed".into());
        }
        let ps = [self.p_reproduction, self.p_crossover, self.p_mutation];
        if ps.iter().any(|p| !(0.0..=1.0).contains(p))
            || (ps.iter().sum::<f64>() - 1.0).abs() > 1e-9
        {
            return bad(format!(
                "p_a, p_c and p_m must lie in [0, 1] and sum to 1, got {}, {}, {}",
                self.p_reproduction, self.p_crossover, self.p_mutation
            ));
        }
        if self.min_depth > self.init_depth || self.init_depth > self.max_depth {
            return bad(format!(
                "depths must satisfy min ≤ initial ≤ max, got {} ≤ {} ≤ {}",
                self.min_depth, self.init_depth, self.max_depth
            ));
        }
        if self.sim.radius > 16 {
            return bad(format!(
                "a communication radius of {} hops is too large (≤ 16; paper: 2)",
                self.sim.radius
            ));
        }
        if self.max_depth > 1000 {
            return bad(format!(
                "a maximum depth of {} is too large (≤ 1000)",
                self.max_depth
            ));
        }
        Ok(())
    }

    /// The step cap of example `p` during evolution (before τ_B tightens it).
    pub fn example_cap(&self, p: &Problem) -> u64 {
        let m = p.step_cap();
        match self.cap_factor {
            Some(f) => m.min(f.saturating_mul(p.graph().num_vertices() as u64)),
            None => m,
        }
    }
}

impl Default for GpParams {
    /// A scaled-down setting: |P| = 200, 2 runs of 25 generations, evolution step cap 20·|N|;
    /// everything else as in [`GpParams::paper`]. Seconds per problem on small trees, minutes on
    /// the largest of the paper's problems.
    fn default() -> Self {
        GpParams {
            population: 200,
            generations: 25,
            runs: 2,
            p_reproduction: 0.1,
            p_crossover: 0.8,
            p_mutation: 0.1,
            init: Init::RampedHalfAndHalf,
            init_depth: 2,
            min_depth: 1,
            max_depth: 50,
            mutation_depth: 2,
            sim: SimOptions::default(),
            stop_at_lower_bound: true,
            cap_factor: Some(20),
        }
    }
}

/// Fitness of one program on the fitness set X.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Evaluation {
    /// F_k = Σ_i f_{k,i} (equation (1)); 0 iff every example is solved.
    pub fitness: u64,
    /// Σ_i τ_{k,i}: steps used (the solve time of a solved example, the cap of an unsolved one).
    pub steps: u64,
}

impl Evaluation {
    pub fn solved(&self) -> bool {
        self.fitness == 0
    }
}

/// `calculateFitness(ψ_k, X)` (Algorithm 1 line 7) under the budget `tau_b` (§4.3; `None` = ∞):
/// example `n` runs for at most min(cap_n, τ_B − steps used so far), where cap_n is
/// [`GpParams::example_cap`]. `None` when `deadline` passed during a run (it is polled inside
/// the simulation, every few hundred robot decisions): an interrupted evaluation has no fitness,
/// and the remaining examples are not run.
pub fn calculate_fitness(
    program: &Program,
    problems: &[Problem],
    params: &GpParams,
    tau_b: Option<u64>,
    deadline: Deadline,
) -> Option<Evaluation> {
    calculate_fitness_marking(program, problems, params, tau_b, deadline, &mut [])
}

/// [`calculate_fitness`], also setting in `reached` the program's nodes that some decision passed
/// through on some example (a bitset over node indices; see [`run_program_marking`]; empty: no
/// marking). `None` when the deadline interrupted a run (`reached` is then meaningless).
fn calculate_fitness_marking(
    program: &Program,
    problems: &[Problem],
    params: &GpParams,
    tau_b: Option<u64>,
    deadline: Deadline,
    reached: &mut [u64],
) -> Option<Evaluation> {
    let mut e = Evaluation {
        fitness: 0,
        steps: 0,
    };
    for p in problems {
        let own = params.example_cap(p);
        let cap = match tau_b {
            Some(b) => own.min(b.saturating_sub(e.steps)),
            None => own,
        };
        let out = run_program_marking(program, p, &params.sim, cap, deadline, reached);
        if out.stop == Stop::TimeLimit {
            return None;
        }
        e.fitness = e.fitness.saturating_add(out.fitness);
        e.steps = e.steps.saturating_add(out.steps);
    }
    Some(e)
}

/// Reported after each evaluated generation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpProgress {
    /// 0-based run and generation within the run.
    pub run: usize,
    pub generation: usize,
    /// Generations evaluated so far over all runs, and how many there are in all.
    pub done: usize,
    pub total: usize,
    /// The lowest F_k of this generation.
    pub best_fitness: u64,
    /// τ_B so far (None while no program has solved X).
    pub best_steps: Option<u64>,
}

/// Why the evolution ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GpStop {
    /// All runs and generations done.
    Finished,
    /// τ_B reached the lower bound.
    LowerBound,
    TimeLimit,
}

/// What Algorithm 1 returns, and a little more.
#[derive(Debug, Clone, PartialEq)]
pub struct GpResult {
    /// ψ*: the program that solved X in the fewest total steps.
    pub best: Option<Program>,
    /// τ_B: its total steps.
    pub best_steps: Option<u64>,
    /// The program with the lowest fitness ever evaluated (first found), solved or not.
    pub champion: Program,
    pub champion_fitness: u64,
    /// Generations evaluated (over all runs).
    pub generations: usize,
    /// Simulations of a whole fitness set run (duplicates within a generation and programs seen
    /// before under the same τ_B are looked up instead).
    pub evaluations: u64,
    /// Children that took their parent's fitness without a simulation: the subtree that
    /// crossover or mutation replaced was never reached by any decision of the parent's runs
    /// (under the same τ_B), so the child's runs are the parent's, step for step.
    pub inherited: u64,
    pub stop: GpStop,
}

/// Algorithm 1 on the fitness set `problems`. `progress` is called from the calling thread after
/// every generation. Stops early at the deadline (keeping ψ* so far; a generation in which the
/// deadline interrupted any simulation is dropped whole, so no interrupted evaluation is ever
/// taken for a fitness) and, when
/// [`GpParams::stop_at_lower_bound`] is set, once ψ* is provably best.
pub fn evolve(
    problems: &[Problem],
    params: &GpParams,
    seed: u64,
    deadline: Deadline,
    progress: &mut dyn FnMut(&GpProgress),
) -> Result<GpResult> {
    params.check()?;
    if problems.is_empty() {
        return Err(Error::Param("the fitness set X is empty".into()));
    }
    let lower_bound: u64 = problems.iter().map(Problem::lower_bound).sum();
    let total = params.runs * params.generations;
    let mut tau_b: Option<u64> = None;
    let mut best: Option<Program> = None;
    let mut champion: Option<(Program, u64)> = None;
    let mut cache: Cache = FxHashMap::default();
    let mut done = 0usize;
    let (mut evaluations, mut inherited) = (0u64, 0u64);
    let mut stop = GpStop::Finished;
    'runs: for run in 0..params.runs {
        let mut pop = initial_population(params, seed, run);
        let mut origins = vec![Origin::New; pop.len()];
        let mut parents: Option<(Evaluated, Vec<Program>)> = None;
        for generation in 0..params.generations {
            if deadline.expired() {
                stop = GpStop::TimeLimit;
                break 'runs;
            }
            let Some((gen_eval, fresh, heirs)) = evaluate_population(
                &pop,
                &origins,
                parents.as_ref().map(|(g, p)| (g, &p[..])),
                problems,
                params,
                tau_b,
                &mut cache,
                deadline,
            ) else {
                // A run cut by the deadline has no fitness: drop this generation.
                stop = GpStop::TimeLimit;
                break 'runs;
            };
            evaluations += fresh;
            inherited += heirs;
            let evals = &gen_eval.evals;
            done += 1;
            // Lines 8-10.
            let mut gen_best = u64::MAX;
            for (k, e) in evals.iter().enumerate() {
                gen_best = gen_best.min(e.fitness);
                if e.solved() && tau_b.is_none_or(|b| e.steps < b) {
                    tau_b = Some(e.steps);
                    best = Some(pop[k].clone());
                    cache.clear();
                }
                if champion.as_ref().is_none_or(|(_, f)| e.fitness < *f) {
                    champion = Some((pop[k].clone(), e.fitness));
                }
            }
            progress(&GpProgress {
                run,
                generation,
                done,
                total,
                best_fitness: gen_best,
                best_steps: tau_b,
            });
            if params.stop_at_lower_bound && tau_b.is_some_and(|b| b <= lower_bound) {
                stop = GpStop::LowerBound;
                break 'runs;
            }
            if generation + 1 < params.generations {
                let (children, o) = breed(&pop, evals, params, seed, run, generation);
                origins = o;
                parents = Some((gen_eval, std::mem::replace(&mut pop, children)));
            }
        }
    }
    let (champion, champion_fitness) = match champion {
        Some(c) => c,
        // Only when the deadline struck before the first generation was evaluated.
        None => (initial_population(params, seed, 0).swap_remove(0), u64::MAX),
    };
    Ok(GpResult {
        best,
        best_steps: tau_b,
        champion,
        champion_fitness,
        generations: done,
        evaluations,
        inherited,
        stop,
    })
}

/// The random stream of one job, named by its key.
fn stream(seed: u64, key: &str) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(derive_seed(seed, key))
}

/// `getInitialPopulation(|P|)` (line 4).
pub fn initial_population(params: &GpParams, seed: u64, run: usize) -> Vec<Program> {
    let depths = params.min_depth.max(1)..=params.init_depth.max(1);
    let span = depths.end() - depths.start() + 1;
    (0..params.population)
        .into_par_iter()
        .map(|k| {
            let mut rng = stream(seed, &format!("gp/init/{run}/{k}"));
            match params.init {
                Init::Full => Program::full(&mut rng, params.init_depth),
                Init::Grow => Program::grow(&mut rng, params.init_depth),
                Init::RampedHalfAndHalf => {
                    let d = depths.start() + (k / 2) % span;
                    if k % 2 == 0 {
                        Program::full(&mut rng, d)
                    } else {
                        Program::grow(&mut rng, d)
                    }
                }
            }
        })
        .collect()
}

/// Evaluations seen before, by program, under the current τ_B: the evaluation and the program's
/// reached nodes (see [`run_program_marking`]).
type Cache = FxHashMap<Vec<Gene>, (Evaluation, Arc<[u64]>)>;

/// Where a program of a generation came from: what lets a child take its parent's fitness
/// without a simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Origin {
    /// Drawn at random (a first generation).
    New,
    /// A copy of parent `k` (reproduction, or an operation that fell back to its parent).
    Copy(usize),
    /// Parent `parent` with one subtree replaced.
    Edit { parent: usize, edit: Edit },
}

/// A subtree replacement: the subtree at node `at`, of `removed` nodes, became `inserted` nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Edit {
    at: usize,
    removed: usize,
    inserted: usize,
}

/// One evaluated generation: evaluations and reached-node bitsets in population order, and the
/// τ_B they were made under.
struct Evaluated {
    evals: Vec<Evaluation>,
    reached: Vec<Arc<[u64]>>,
    tau_b: Option<u64>,
}

/// A parent's reached nodes carried over to a child made by `edit`, which lies in unreached
/// code or swapped a subtree for an equal one: nodes before the subtree keep their index, nodes
/// after it move by the size change.
fn carry_reached(reached: &[u64], edit: Edit, child_len: usize) -> Arc<[u64]> {
    let mut out = vec![0u64; child_len.div_ceil(64)];
    for (w, &word) in reached.iter().enumerate() {
        let mut bits = word;
        while bits != 0 {
            let k = w * 64 + bits.trailing_zeros() as usize;
            bits &= bits - 1;
            // Nodes inside the subtree are reached only when it was swapped for an equal one.
            debug_assert!(
                k < edit.at || k >= edit.at + edit.removed || edit.removed == edit.inserted
            );
            let to = if k < edit.at {
                k
            } else {
                k + edit.inserted - edit.removed
            };
            out[to / 64] |= 1 << (to % 64);
        }
    }
    out.into()
}

/// Line 7 for the whole population, in parallel. Each distinct program is simulated once per
/// τ_B, and a child whose edit lies in code its parent never reached (under the same τ_B), or
/// swapped a subtree for an equal one, takes the parent's evaluation: its runs are the
/// parent's, decision for decision. Returns the
/// evaluations, the number of fresh simulations and the number of inherited evaluations, or
/// `None` when the deadline interrupted a simulation (the remaining ones are not started, and
/// nothing of this generation enters the cache).
#[allow(clippy::too_many_arguments)]
fn evaluate_population(
    pop: &[Program],
    origins: &[Origin],
    parents: Option<(&Evaluated, &[Program])>,
    problems: &[Problem],
    params: &GpParams,
    tau_b: Option<u64>,
    cache: &mut Cache,
    deadline: Deadline,
) -> Option<(Evaluated, u64, u64)> {
    // Bound the cache's memory (it only saves time; clearing it changes no result).
    if cache.len() > 200_000 {
        cache.clear();
    }
    let parents = parents.filter(|(g, _)| g.tau_b == tau_b);
    let mut inherited = 0u64;
    // Distinct programs neither in the cache nor heirs, in order of first appearance.
    let mut todo: Vec<usize> = Vec::new();
    let mut first: FxHashMap<&[Gene], usize> = FxHashMap::default();
    let mut slots: Vec<Option<(Evaluation, Arc<[u64]>)>> = vec![None; pop.len()];
    for (k, p) in pop.iter().enumerate() {
        let heir = parents.and_then(|(g, old)| match origins[k] {
            Origin::Copy(parent) => Some((g.evals[parent], g.reached[parent].clone())),
            Origin::Edit { parent, edit } => {
                let r = &g.reached[parent];
                let unreached = r[edit.at / 64] >> (edit.at % 64) & 1 == 0;
                // A subtree swapped for an equal one leaves the parent as it was.
                let inherits = unreached
                    || (edit.removed == edit.inserted
                        && p.genes()[edit.at..edit.at + edit.inserted]
                            == old[parent].genes()[edit.at..edit.at + edit.removed]);
                inherits.then(|| (g.evals[parent], carry_reached(r, edit, p.len())))
            }
            Origin::New => None,
        });
        if heir.is_some() {
            inherited += 1;
            slots[k] = heir;
        } else if let Some(v) = cache.get(p.genes()) {
            slots[k] = Some(v.clone());
        } else if !first.contains_key(p.genes()) {
            first.insert(p.genes(), k);
            todo.push(k);
        }
    }
    // Collecting into an Option stops the other threads' work at the first `None`.
    let fresh: Vec<(Evaluation, Arc<[u64]>)> = todo
        .par_iter()
        .map(|&k| {
            let mut reached = vec![0u64; pop[k].len().div_ceil(64)];
            let e = calculate_fitness_marking(
                &pop[k],
                problems,
                params,
                tau_b,
                deadline,
                &mut reached,
            )?;
            Some((e, reached.into()))
        })
        .collect::<Option<_>>()?;
    let simulated = fresh.len() as u64;
    for (&k, v) in todo.iter().zip(fresh) {
        cache.insert(pop[k].genes().to_vec(), v);
    }
    let (evals, reached) = slots
        .into_iter()
        .zip(pop)
        .map(|(slot, p)| slot.unwrap_or_else(|| cache[p.genes()].clone()))
        .unzip();
    Some((
        Evaluated {
            evals,
            reached,
            tau_b,
        },
        simulated,
        inherited,
    ))
}

/// Roulette over α_k = β_k / Σβ with β_k = 1 / (1 + F_k).
struct Roulette {
    cumulative: Vec<f64>,
}

impl Roulette {
    fn new(evals: &[Evaluation]) -> Self {
        let mut sum = 0.0;
        let cumulative = evals
            .iter()
            .map(|e| {
                sum += 1.0 / (1.0 + e.fitness as f64);
                sum
            })
            .collect();
        Roulette { cumulative }
    }

    fn pick(&self, rng: &mut ChaCha8Rng) -> usize {
        let total = *self.cumulative.last().expect("non-empty population");
        let r = rng.random::<f64>() * total;
        self.cumulative
            .partition_point(|&c| c <= r)
            .min(self.cumulative.len() - 1)
    }
}

/// Lines 13-16: P_a ∪ P_c ∪ P_m. Every operation draws from its own stream (run, generation,
/// operation index), so the operations run in parallel with a fixed result.
pub fn next_generation(
    pop: &[Program],
    evals: &[Evaluation],
    params: &GpParams,
    seed: u64,
    run: usize,
    generation: usize,
) -> Vec<Program> {
    breed(pop, evals, params, seed, run, generation).0
}

/// [`next_generation`] with the origin of every child.
fn breed(
    pop: &[Program],
    evals: &[Evaluation],
    params: &GpParams,
    seed: u64,
    run: usize,
    generation: usize,
) -> (Vec<Program>, Vec<Origin>) {
    #[derive(Clone, Copy)]
    enum Op {
        Copy,
        Cross(usize),
        Mutate,
    }
    let n = pop.len();
    let n_a = ((params.p_reproduction * n as f64).round() as usize).min(n);
    let n_c = ((params.p_crossover * n as f64).round() as usize).min(n - n_a);
    let n_m = n - n_a - n_c;
    let mut ops = vec![Op::Copy; n_a];
    let mut left = n_c;
    while left > 0 {
        let k = left.min(2);
        ops.push(Op::Cross(k));
        left -= k;
    }
    ops.extend(std::iter::repeat_n(Op::Mutate, n_m));
    let wheel = Roulette::new(evals);
    let origin = |parent: usize, edit: Option<Edit>| match edit {
        Some(edit) => Origin::Edit { parent, edit },
        None => Origin::Copy(parent),
    };
    let children: Vec<Vec<(Program, Origin)>> = ops
        .par_iter()
        .enumerate()
        .map(|(o, op)| {
            let mut rng = stream(seed, &format!("gp/breed/{run}/{generation}/{o}"));
            match *op {
                Op::Copy => {
                    let a = wheel.pick(&mut rng);
                    vec![(pop[a].clone(), Origin::Copy(a))]
                }
                Op::Cross(k) => {
                    let a = wheel.pick(&mut rng);
                    let b = wheel.pick(&mut rng);
                    let ((c, ec), (d, ed)) =
                        crossover_edits(&pop[a], &pop[b], params, &mut rng, &mut Vec::new());
                    let mut kids = vec![(c, origin(a, ec))];
                    if k == 2 {
                        kids.push((d, origin(b, ed)));
                    }
                    kids
                }
                Op::Mutate => {
                    let a = wheel.pick(&mut rng);
                    let (c, e) = mutation_edit(&pop[a], params, &mut rng);
                    vec![(c, origin(a, e))]
                }
            }
        })
        .collect();
    children.into_iter().flatten().unzip()
}

/// Redraws of crossover or mutation points before a parent is copied instead.
const TRIES: usize = 8;

/// Whether `a` with its subtree at `i` replaced by a tree of depth `h` lies within the depth
/// bounds, for a parent `a` within them, without building it: the child's depth is
/// max(deepest node outside the subtree, depth of `i` + `h`), and the first term is at most
/// `a`'s depth, so only a child below the lower bound needs the outside depth (one walk).
fn child_depth_ok(a: &Program, i: usize, h: usize, params: &GpParams) -> bool {
    debug_assert!((params.min_depth..=params.max_depth).contains(&a.depth()));
    let inside = a.node_depth(i) + h;
    if inside > params.max_depth {
        return false;
    }
    if inside >= params.min_depth {
        return true;
    }
    let stub = a.replace_subtree(i, &[Gene::Do(Action::Stay)]);
    stub.depth() >= params.min_depth
}

/// Subtree crossover (§4.4): a uniform node in each parent, the subtrees swapped; each child that
/// breaks the depth bounds is redrawn, then replaced by a copy of its parent.
pub fn genetic_crossover(
    a: &Program,
    b: &Program,
    params: &GpParams,
    rng: &mut ChaCha8Rng,
) -> (Program, Program) {
    let ((c, _), (d, _)) = crossover_edits(a, b, params, rng, &mut Vec::new());
    (c, d)
}

/// A child and the edit that made it from its parent (`None`: a copy of the parent).
type Child = (Program, Option<Edit>);

/// [`genetic_crossover`] with each child's edit of its own parent. Each child is only built once
/// its depth is known to lie within the bounds ([`child_depth_ok`]); the parents must lie within
/// them. `open` is scratch.
fn crossover_edits(
    a: &Program,
    b: &Program,
    params: &GpParams,
    rng: &mut ChaCha8Rng,
    open: &mut Vec<u8>,
) -> (Child, Child) {
    let mut c = None;
    let mut d = None;
    for _ in 0..TRIES {
        let i = rng.random_range(0..a.len());
        let j = rng.random_range(0..b.len());
        let (ei, hi) = a.subtree_extent(i, open);
        let (ej, hj) = b.subtree_extent(j, open);
        if c.is_none() && child_depth_ok(a, i, hj, params) {
            c = Some(swap_in(a, (i, ei), b, (j, ej)));
        }
        if d.is_none() && child_depth_ok(b, j, hi, params) {
            d = Some(swap_in(b, (j, ej), a, (i, ei)));
        }
        if c.is_some() && d.is_some() {
            break;
        }
    }
    (
        c.unwrap_or_else(|| (a.clone(), None)),
        d.unwrap_or_else(|| (b.clone(), None)),
    )
}

/// `a` with its subtree `i..ei` replaced by `b`'s subtree `j..ej`, and that edit.
fn swap_in(a: &Program, (i, ei): (usize, usize), b: &Program, (j, ej): (usize, usize)) -> Child {
    let edit = Edit {
        at: i,
        removed: ei - i,
        inserted: ej - j,
    };
    (a.splice((i, ei), b, (j, ej)), Some(edit))
}

/// Subtree mutation (§4.4): a uniform node and its subtree replaced by a grown random subtree.
pub fn mutation(a: &Program, params: &GpParams, rng: &mut ChaCha8Rng) -> Program {
    mutation_edit(a, params, rng).0
}

/// [`mutation`] with the child's edit of its parent (which must lie within the depth bounds).
fn mutation_edit(a: &Program, params: &GpParams, rng: &mut ChaCha8Rng) -> Child {
    for _ in 0..TRIES {
        let i = rng.random_range(0..a.len());
        let fresh = Program::grow_subtree(rng, params.mutation_depth);
        if child_depth_ok(a, i, fresh.depth(), params) {
            return swap_in(a, (i, a.subtree_end(i)), &fresh, (0, fresh.len()));
        }
    }
    (a.clone(), None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generator::{ProblemSpec, RobotCount, generate_problem};
    use mrpp_core::mapf::graph::Graph;
    use mrpp_core::mapf::instance::Instance;

    #[test]
    fn fitness_is_equation_one_under_the_budget() {
        // Path 0-1-2-3-4; robot 0 from 0 to 4, robot 1 from 4 to 2 (head-on, no branch).
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (3, 4)]);
        let inst = Instance::new(vec![0, 4], vec![4, 2]).unwrap();
        let p = Problem::new(&g, &inst).unwrap();
        let prog = Program::action(Action::MoveTowardObjective);
        let sim = GpParams {
            cap_factor: None,
            ..GpParams::default()
        };
        // Step 1: r0 0->1, r1 4->3. Step 2: r0 1->2, r1 3->2 blocked. Then stuck for ever:
        // r0 at 2 (2 from its goal 4), r1 at 3 (1 from its goal 2): F = 2² + 1² = 5.
        let e = calculate_fitness(
            &prog,
            std::slice::from_ref(&p),
            &sim,
            None,
            Deadline::none(),
        )
        .unwrap();
        assert_eq!(e.fitness, 5);
        assert_eq!(e.steps, p.step_cap());
        // With a budget of 1 step: r0 at 1 (3 away), r1 at 3 (1 away): 9 + 1 = 10.
        let e1 = calculate_fitness(
            &prog,
            std::slice::from_ref(&p),
            &sim,
            Some(1),
            Deadline::none(),
        )
        .unwrap();
        assert_eq!(
            e1,
            Evaluation {
                fitness: 10,
                steps: 1
            }
        );
        // A solvable instance: fitness 0, steps = τ.
        let inst2 = Instance::new(vec![0, 3], vec![2, 4]).unwrap();
        let p2 = Problem::new(&g, &inst2).unwrap();
        let e2 = calculate_fitness(
            &prog,
            std::slice::from_ref(&p2),
            &sim,
            None,
            Deadline::none(),
        )
        .unwrap();
        assert_eq!(
            e2,
            Evaluation {
                fitness: 0,
                steps: 2
            }
        );
        // Two examples share the budget: 2 + 2 = 4 fits, 3 does not.
        let both = [p2.clone(), p2];
        assert!(
            calculate_fitness(&prog, &both, &sim, Some(4), Deadline::none())
                .unwrap()
                .solved()
        );
        assert!(
            !calculate_fitness(&prog, &both, &sim, Some(3), Deadline::none())
                .unwrap()
                .solved()
        );
    }

    /// Issue 27 A: an evaluation whose deadline has passed reports that it was interrupted
    /// instead of a fitness (before, it returned a made-up fitness of at least 1, or 0 for a
    /// program that solved within the 256 steps between polls), and an evolution under such a
    /// deadline evaluates no generation and finds no program.
    #[test]
    fn an_evaluation_past_its_deadline_has_no_fitness() {
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (3, 4)]);
        let inst = Instance::new(vec![0, 3], vec![2, 4]).unwrap();
        let p = Problem::new(&g, &inst).unwrap();
        let problems = std::slice::from_ref(&p);
        let prog = Program::action(Action::MoveTowardObjective);
        let params = GpParams::default();
        let expired = Deadline::after(std::time::Duration::ZERO);
        assert_eq!(
            calculate_fitness(&prog, problems, &params, None, expired),
            None
        );
        assert!(
            calculate_fitness(&prog, problems, &params, None, Deadline::none())
                .unwrap()
                .solved()
        );
        let r = evolve(problems, &params, 1, expired, &mut |_| {
            panic!("no generation is complete")
        })
        .unwrap();
        assert_eq!(r.stop, GpStop::TimeLimit);
        assert_eq!((r.best, r.generations, r.evaluations), (None, 0, 0));
        // Cut inside the first generation's evaluations: the generation is dropped whole.
        let mut cache = Cache::default();
        let pop = initial_population(&params, 1, 0);
        let origins = vec![Origin::New; pop.len()];
        let cut = evaluate_population(
            &pop, &origins, None, problems, &params, None, &mut cache, expired,
        );
        assert!(cut.is_none());
        assert!(cache.is_empty(), "nothing interrupted is cached");
    }

    fn small_params() -> GpParams {
        GpParams {
            population: 60,
            generations: 6,
            runs: 2,
            stop_at_lower_bound: false,
            ..GpParams::default()
        }
    }

    #[test]
    fn same_result_with_one_and_two_threads() {
        let spec = ProblemSpec::paper(5, RobotCount::LeavesMinusOne);
        let t = generate_problem(&spec, 11).unwrap();
        let problems = [Problem::from_tree_instance(&t)];
        let params = small_params();
        let go = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut trace = Vec::new();
                let r = evolve(&problems, &params, 42, Deadline::none(), &mut |g| {
                    trace.push(*g)
                })
                .unwrap();
                let last = initial_population(&params, 42, 1);
                (r, trace, last)
            })
        };
        let one = go(1);
        let two = go(2);
        assert_eq!(one.0, two.0);
        assert_eq!(one.1, two.1);
        assert_eq!(one.2, two.2);
        assert_eq!(one.1.len(), 12);
        // Another seed gives another search.
        let other = evolve(&problems, &params, 43, Deadline::none(), &mut |_| {}).unwrap();
        assert!(other.evaluations != one.0.evaluations || other.champion != one.0.champion);
    }

    #[test]
    fn operators_respect_depth_bounds_and_proportions() {
        let params = GpParams {
            population: 50,
            max_depth: 4,
            ..GpParams::default()
        };
        let mut pop = initial_population(&params, 1, 0);
        assert!(pop.iter().all(|p| (1..=2).contains(&p.depth())));
        let evals: Vec<Evaluation> = (0..50)
            .map(|k| Evaluation {
                fitness: k as u64,
                steps: 0,
            })
            .collect();
        for g in 0..20 {
            pop = next_generation(&pop, &evals, &params, 1, 0, g);
            assert_eq!(pop.len(), 50);
            assert!(pop.iter().all(|p| (1..=4).contains(&p.depth())));
        }
        assert!(
            GpParams {
                p_mutation: 0.2,
                ..GpParams::default()
            }
            .check()
            .is_err()
        );
        assert!(
            GpParams {
                population: 1,
                ..GpParams::default()
            }
            .check()
            .is_err()
        );
        assert!(GpParams::paper().check().is_ok());
    }

    #[test]
    fn child_depths_are_judged_without_building_the_child() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut open = Vec::new();
        for (min_depth, max_depth) in [(1, 50), (1, 5), (3, 6), (4, 4)] {
            let params = GpParams {
                min_depth,
                max_depth,
                init_depth: min_depth,
                ..GpParams::default()
            };
            let mut tried = 0;
            while tried < 15 {
                let (a, b) = (Program::grow(&mut rng, 5), Program::grow(&mut rng, 4));
                if !(min_depth..=max_depth).contains(&a.depth()) {
                    continue;
                }
                tried += 1;
                for i in 0..a.len() {
                    assert_eq!(a.subtree_extent(i, &mut open).0, a.subtree_end(i));
                    for j in 0..b.len() {
                        let (ej, hj) = b.subtree_extent(j, &mut open);
                        let child = a.replace_subtree(i, b.subtree(j));
                        let ok = (min_depth..=max_depth).contains(&child.depth());
                        assert_eq!(child_depth_ok(&a, i, hj, &params), ok);
                        assert_eq!(a.splice((i, a.subtree_end(i)), &b, (j, ej)), child);
                    }
                }
            }
        }
    }

    /// The inheritance rule of `evaluate_population`: a child edited only in code its parent's
    /// runs never reached has the parent's evaluation and (carried) reached set, as a fresh
    /// simulation confirms; bloated programs make such edits common.
    #[test]
    fn children_edited_in_unreached_code_run_like_their_parent() {
        let spec = ProblemSpec::paper(5, RobotCount::LeavesMinusOne);
        let t = generate_problem(&spec, 3).unwrap();
        let problems = [Problem::from_tree_instance(&t)];
        let params = GpParams::default();
        let run = |p: &Program, tau| {
            let mut reached = vec![0u64; p.len().div_ceil(64)];
            let e = calculate_fitness_marking(
                p,
                &problems,
                &params,
                tau,
                Deadline::none(),
                &mut reached,
            )
            .unwrap();
            (e, reached)
        };
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut checked = 0;
        for round in 0..60 {
            let parent = Program::full(&mut rng, 4);
            let tau = (round % 2 == 0).then_some(30);
            let (e, reached) = run(&parent, tau);
            let unreached: Vec<usize> = (0..parent.len())
                .filter(|&k| reached[k / 64] >> (k % 64) & 1 == 0)
                .collect();
            if unreached.is_empty() {
                continue;
            }
            let at = unreached[rng.random_range(0..unreached.len())];
            let fresh = Program::grow_subtree(&mut rng, 3);
            let end = parent.subtree_end(at);
            let child = parent.replace_subtree(at, fresh.genes());
            let edit = Edit {
                at,
                removed: end - at,
                inserted: fresh.len(),
            };
            let (ce, creached) = run(&child, tau);
            assert_eq!(ce, e, "round {round}");
            assert_eq!(&*carry_reached(&reached, edit, child.len()), &creached[..]);
            checked += 1;
        }
        assert!(checked >= 20, "only {checked} programs had unreached code");
    }
}
