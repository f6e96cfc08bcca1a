//! The GA paper's genetic algorithm (§2.2, Algorithm 2), with every choice the paper leaves open
//! written down:
//!
//! - **Chromosome** (§2.2.2): R alleles, one roadmap path per robot.
//! - **Initial population** (§2.2.1): the sequential planner's plan, then diverse valid variants:
//!   the sequential planner on edge weights scaled by U[1, 1 + `noise`] (different splits), and
//!   "all robots on the k-th shortest path" for k = 1, 2, … (Yen's order), alternating, until the
//!   population is full (duplicates allowed when the roadmap offers too few). The paper seeds
//!   its population with the sequential planner and says this needs fewer generations than a
//!   random start; `-p initial=random` is that random start, for comparison: every robot of
//!   every individual on its own shortest path under edge lengths scaled by U[1, 11], drawn
//!   per robot ([`RANDOM_SPREAD`]), so the sequential plan is in it only by chance.
//! - **Fitness** (§2.2.3): `F = C − c_max`, where `C` is the cost of the whole formation on one
//!   path (the best single path under `c_e(R)`). Roulette selection needs non-negative weights, so
//!   an individual is drawn with probability proportional to `F − F_min + ε` (ε = 1e-9 · |C|, so a
//!   uniform population is drawn uniformly); an invalid individual has `c_max = ∞` and is never
//!   drawn. **Elitism**: the best individual is copied into the next generation unchanged.
//! - **Crossover** (probability `p_c`; path level or edge level with equal chance):
//!   *path level*: of the two parents' 2R paths (each with its cost in its parent), the first child
//!   takes the R cheapest, the second the rest; *edge level*: each path of the first parent is
//!   combined with the first path of the second parent (in random order) that shares an
//!   intermediate edge with it — prefix of one up to that edge, suffix of the other — and loops are
//!   cut.
//! - **Mutation** (probability `p_m` per child; edge level or path level with equal chance):
//!   *edge level*: for every path, one random edge is removed and the path is re-routed by Dijkstra
//!   (edge lengths) from that edge's first vertex to `Q_goal`; *path level*: one random path is
//!   copied over the R − 1 others (the formation on one path).
//! - **Stop**: after `generations` generations (the paper: 100) or at the deadline; the best plan
//!   found is returned, unless its cost is not finite (every individual over a corridor's
//!   capacity under the `hard` model, say): then the GA gives up, naming the corridors that hold
//!   the formation back ([`crate::capacity`]) or, when a plan within capacity exists, the best
//!   individual's first violation. Children are evaluated exactly ([`FormationProblem::evaluate`]); a child
//!   that breaks a rule stays in the population with `c_max = ∞`.
//!
//! Defaults are the paper's (§3): population 20, `p_c` 0.9, `p_m` 0.3, 100 generations. The run is
//! sequential and seeded, so a seed gives one result whatever the thread count.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use mrpp_core::{Ctx, Param, Planner, PlannerEntry, Unsolved};

use crate::paths::{dijkstra, eliminate_loops, k_shortest_paths};
use crate::planners::sequential_paths;
use crate::problem::{FormationPlan, FormationProblem};

/// `-p initial=random`: each robot's edge lengths are scaled by U[1, 1 + this] (module doc).
pub const RANDOM_SPREAD: f64 = 10.0;

/// Registry name of the GA.
pub const NAME: &str = "ga";

/// The GA in the registry.
pub const ENTRY: PlannerEntry<FormationProblem> = PlannerEntry {
    name: NAME,
    about: "genetic algorithm seeded by the sequential planner, path/edge crossover and mutation (Pereyra et al., the GA formation paper)",
    params: &[
        Param {
            name: "population",
            default: "20",
            doc: "individuals per generation (paper 20)",
        },
        Param {
            name: "p_c",
            default: "0.9",
            doc: "crossover probability (paper 0.9)",
        },
        Param {
            name: "p_m",
            default: "0.3",
            doc: "mutation probability per child (paper 0.3)",
        },
        Param {
            name: "generations",
            default: "100",
            doc: "generations (paper 100)",
        },
        Param {
            name: "noise",
            default: "0.5",
            doc: "initial variants: edge weights scaled by U[1, 1 + noise]",
        },
        Param {
            name: "initial",
            default: "sequential",
            doc: "initial population: sequential = the sequential plan and its variants (the paper's); random = each robot on its own shortest path under edge lengths scaled by U[1, 11] (the random start the paper compares against)",
        },
    ],
    build: |p| {
        Ok(Box::new(Ga {
            population: p.get_in("population", 2..=100_000)?,
            p_c: p.get_in("p_c", 0.0..=1.0)?,
            p_m: p.get_in("p_m", 0.0..=1.0)?,
            generations: p.get_in("generations", 0..=10_000_000)?,
            noise: p.get_in("noise", 0.0..=100.0)?,
            random_start: p.choice("initial", &["sequential", "random"])? == 1,
        }))
    },
};

/// The GA's parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ga {
    pub population: usize,
    pub p_c: f64,
    pub p_m: f64,
    pub generations: usize,
    pub noise: f64,
    /// `-p initial=random`: a random initial population instead of the sequential plan's
    /// (module doc).
    pub random_start: bool,
}

impl Default for Ga {
    fn default() -> Self {
        Ga {
            population: 20,
            p_c: 0.9,
            p_m: 0.3,
            generations: 100,
            noise: 0.5,
            random_start: false,
        }
    }
}

/// An individual: its paths, each path's cost, and `c_max` (∞ when invalid).
#[derive(Debug, Clone)]
struct Individual {
    paths: Vec<Vec<u32>>,
    per_robot: Vec<f64>,
    c_max: f64,
}

impl Individual {
    fn new(p: &FormationProblem, paths: Vec<Vec<u32>>) -> Self {
        match p.evaluate(&paths) {
            Ok(ev) => Individual {
                paths,
                per_robot: ev.per_robot,
                c_max: ev.c_max,
            },
            Err(_) => {
                let n = paths.len();
                Individual {
                    paths,
                    per_robot: vec![f64::INFINITY; n],
                    c_max: f64::INFINITY,
                }
            }
        }
    }
}

/// What a GA run gives besides the plan.
#[derive(Debug, Clone, PartialEq)]
pub struct GaRun {
    pub plan: FormationPlan,
    pub c_max: f64,
    /// The first generation (0 = the initial population) whose best reached the final `c_max`.
    pub generation_of_best: usize,
    pub generations: usize,
}

impl Ga {
    /// Runs the GA; `None` when Q_goal cannot be reached.
    pub fn run(&self, p: &FormationProblem, ctx: &Ctx) -> Option<GaRun> {
        let mut rng = ChaCha8Rng::seed_from_u64(ctx.seed);
        let mut pop = self.initial_population(p, &mut rng)?;
        let c = formation_on_one_path(p);
        let mut best = pop
            .iter()
            .min_by(|a, b| a.c_max.total_cmp(&b.c_max))?
            .clone();
        let (mut at, mut done) = (0, 0);
        let mut throttle = mrpp_core::Throttle::new();
        for g in 1..=self.generations {
            if ctx.deadline.expired() {
                break;
            }
            throttle.report(ctx, || mrpp_core::Progress {
                stage: "GA generation",
                done: g as u64 - 1,
                total: self.generations as u64,
                note: format!("best c_max {:.2}", best.c_max),
            });
            pop = self.next_generation(p, &pop, &best, c, &mut rng);
            done = g;
            let gen_best = pop.iter().min_by(|a, b| a.c_max.total_cmp(&b.c_max))?;
            if gen_best.c_max < best.c_max {
                best = gen_best.clone();
                at = g;
            }
        }
        Some(GaRun {
            c_max: best.c_max,
            plan: FormationPlan { paths: best.paths },
            generation_of_best: at,
            generations: done,
        })
    }

    fn initial_population(
        &self,
        p: &FormationProblem,
        rng: &mut ChaCha8Rng,
    ) -> Option<Vec<Individual>> {
        let seq = sequential_paths(p, &|_| 1.0);
        if seq.len() < p.robots() {
            return None;
        }
        if self.random_start {
            let r = p.roadmap();
            let banned = vec![false; r.num_vertices()];
            let random_path = |rng: &mut ChaCha8Rng| {
                let scale: Vec<f64> = (0..r.edges.len())
                    .map(|_| 1.0 + RANDOM_SPREAD * rng.random::<f64>())
                    .collect();
                let len = |e: u32, _: u32, _: u32| r.edges[e as usize].length * scale[e as usize];
                crate::paths::dijkstra(r, p.start(), p.goal(), &banned, &len).map(|(path, _)| path)
            };
            let mut pop = Vec::with_capacity(self.population);
            for _ in 0..self.population {
                let paths: Option<Vec<Vec<u32>>> =
                    (0..p.robots()).map(|_| random_path(rng)).collect();
                pop.push(Individual::new(p, paths?));
            }
            return Some(pop);
        }
        let mut pop = vec![Individual::new(p, seq)];
        let shortest = k_shortest_paths(p.roadmap(), p.start(), p.goal(), self.population);
        let mut k = 0;
        while pop.len() < self.population {
            let paths = if pop.len() % 2 == 1 || k >= shortest.len() {
                let m = p.roadmap().edges.len();
                let scale: Vec<f64> = (0..m)
                    .map(|_| 1.0 + self.noise * rng.random::<f64>())
                    .collect();
                sequential_paths(p, &|e| scale[e as usize])
            } else {
                k += 1;
                vec![shortest[k - 1].0.clone(); p.robots()]
            };
            pop.push(Individual::new(p, paths));
        }
        Some(pop)
    }

    fn next_generation(
        &self,
        p: &FormationProblem,
        pop: &[Individual],
        best: &Individual,
        c: f64,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Individual> {
        let fit: Vec<f64> = pop.iter().map(|i| c - i.c_max).collect();
        let min = fit
            .iter()
            .copied()
            .filter(|f| f.is_finite())
            .fold(f64::INFINITY, f64::min);
        let eps = 1e-9 * c.abs().max(1.0);
        let weights: Vec<f64> = fit
            .iter()
            .map(|f| if f.is_finite() { f - min + eps } else { 0.0 })
            .collect();
        let mut next = vec![best.clone()];
        while next.len() < self.population {
            let (a, b) = (&pop[roulette(&weights, rng)], &pop[roulette(&weights, rng)]);
            let (mut x, mut y) = (a.paths.clone(), b.paths.clone());
            if rng.random::<f64>() < self.p_c {
                (x, y) = if rng.random::<bool>() {
                    path_crossover(a, b)
                } else {
                    edge_crossover(&x, &y, p, rng)
                };
            }
            for child in [x, y] {
                let child = if rng.random::<f64>() < self.p_m {
                    mutate(child, p, rng)
                } else {
                    child
                };
                if next.len() < self.population {
                    next.push(Individual::new(p, child));
                }
            }
        }
        next
    }
}

/// Roulette: an index drawn with probability proportional to its weight (uniform when all are 0).
fn roulette(weights: &[f64], rng: &mut ChaCha8Rng) -> usize {
    let total: f64 = weights.iter().sum();
    if total <= 0.0 || !total.is_finite() {
        return rng.random_range(0..weights.len());
    }
    let mut x = rng.random::<f64>() * total;
    for (i, w) in weights.iter().enumerate() {
        if x < *w {
            return i;
        }
        x -= w;
    }
    weights.len() - 1
}

/// `C`: the whole formation on the best single path (weights `c_e(R)`).
fn formation_on_one_path(p: &FormationProblem) -> f64 {
    let r = p.robots();
    let banned = vec![false; p.roadmap().num_vertices()];
    dijkstra(p.roadmap(), p.start(), p.goal(), &banned, &|e, _, _| {
        p.edge_cost(e, r)
    })
    .map_or(f64::INFINITY, |(_, c)| c)
}

/// Path-level crossover: the R cheapest of both parents' paths, and the rest.
fn path_crossover(a: &Individual, b: &Individual) -> (Vec<Vec<u32>>, Vec<Vec<u32>>) {
    let mut pool: Vec<(f64, &Vec<u32>)> = a
        .per_robot
        .iter()
        .copied()
        .zip(&a.paths)
        .chain(b.per_robot.iter().copied().zip(&b.paths))
        .collect();
    pool.sort_by(|x, y| x.0.total_cmp(&y.0));
    let r = a.paths.len();
    (
        pool[..r].iter().map(|(_, q)| (*q).clone()).collect(),
        pool[r..].iter().map(|(_, q)| (*q).clone()).collect(),
    )
}

/// Edge-level crossover: each path of `a` exchanges tails with a path of `b` sharing an
/// intermediate edge with it.
fn edge_crossover(
    a: &[Vec<u32>],
    b: &[Vec<u32>],
    p: &FormationProblem,
    rng: &mut ChaCha8Rng,
) -> (Vec<Vec<u32>>, Vec<Vec<u32>>) {
    let (mut x, mut y) = (a.to_vec(), b.to_vec());
    for xi_path in x.iter_mut() {
        let mut order: Vec<usize> = (0..y.len()).collect();
        for k in (1..order.len()).rev() {
            order.swap(k, rng.random_range(0..=k));
        }
        for j in order {
            if let Some((ia, jb)) = shared_inner_edge(xi_path, &y[j], p) {
                let xi: Vec<u32> = xi_path[..=ia]
                    .iter()
                    .chain(&y[j][jb + 1..])
                    .copied()
                    .collect();
                let yj: Vec<u32> = y[j][..=jb]
                    .iter()
                    .chain(&xi_path[ia + 1..])
                    .copied()
                    .collect();
                *xi_path = eliminate_loops(&xi);
                y[j] = eliminate_loops(&yj);
                break;
            }
        }
    }
    (x, y)
}

/// The first edge `(q[ia], q[ia+1]) = (r[jb], r[jb+1])` that is neither path's first or last edge.
fn shared_inner_edge(q: &[u32], r: &[u32], _p: &FormationProblem) -> Option<(usize, usize)> {
    for ia in 1..q.len().saturating_sub(2) {
        for jb in 1..r.len().saturating_sub(2) {
            if q[ia] == r[jb] && q[ia + 1] == r[jb + 1] {
                return Some((ia, jb));
            }
        }
    }
    None
}

/// Edge-level or path-level mutation.
fn mutate(mut paths: Vec<Vec<u32>>, p: &FormationProblem, rng: &mut ChaCha8Rng) -> Vec<Vec<u32>> {
    if rng.random::<bool>() {
        let r = p.roadmap();
        let banned = vec![false; r.num_vertices()];
        for q in paths.iter_mut() {
            if q.len() < 2 {
                continue;
            }
            let k = rng.random_range(0..q.len() - 1);
            let cut = r.edge_between(q[k], q[k + 1]);
            let len = |e: u32, _: u32, _: u32| {
                if Some(e) == cut {
                    f64::INFINITY
                } else {
                    r.edges[e as usize].length
                }
            };
            if let Some((tail, _)) = dijkstra(r, q[k], p.goal(), &banned, &len) {
                let joined: Vec<u32> = q[..k].iter().chain(&tail).copied().collect();
                *q = eliminate_loops(&joined);
            }
        }
    } else if !paths.is_empty() {
        let keep = paths[rng.random_range(0..paths.len())].clone();
        for q in paths.iter_mut() {
            *q = keep.clone();
        }
    }
    paths
}

impl Planner<FormationProblem> for Ga {
    fn name(&self) -> &str {
        NAME
    }
    /// # Errors
    /// [`Unsolved::GaveUp`] when `Q_goal` cannot be reached, or when no individual found has a
    /// finite cost (naming the corridors over capacity: a minimum cut when no plan fits, else
    /// the best individual's first violation).
    fn plan(&self, p: &FormationProblem, ctx: &Ctx) -> Result<FormationPlan, Unsolved> {
        match self.run(p, ctx) {
            Some(run) if run.c_max.is_finite() => Ok(run.plan),
            Some(run) => Err(crate::planners::no_finite_plan(p, NAME, &run.plan.paths)),
            None => Err(Unsolved::GaveUp(
                "Q_goal cannot be reached from Q_ini on the roadmap".into(),
            )),
        }
    }
}
