//! Enol2023: A* with private obstacles, then cooperative co-evolution (García, Villar, Tan,
//! Sedano, Chira, ICAE 30:41–52, 2023), the baseline of the H* paper's §V-D and Table II, as
//! reconstructed from that paper and the authors' public Python code.
//!
//! Why two stages: independent A* routes are short but collide; blocking each robot's conflict
//! cells on a *private* copy of the map (so no robot constrains another) removes most collisions
//! cheaply, and whatever is left is handed to an evolutionary search over timing and small detours
//! that only has to repair a few robots. The steps, each a function named after it:
//!
//! 1. [`astar_with_private_obstacles`] (stage 1, `astar_rounds` = n_a rounds): every robot plans a
//!    4-neighbour unit-cost A* route; each round, every unsettled robot is compared with every
//!    other robot in id order, each conflict cell (never its own start or goal) becomes an
//!    obstacle on its private map and it re-plans (expansion cap 15 000; no route found = keep
//!    the old one). Every route is kept in the robot's history; a robot without conflict in a
//!    round is settled. A round without any conflict ends the planner with the A* routes.
//! 2. [`cooperative_coevolution`] (stage 2): one subpopulation per robot, seeded with its route
//!    history. Each generation: [`choose_collaborators`] (q per robot, rank-geometric tournament,
//!    p_eval), [`mutate`] every individual of every unsettled robot once and add the children
//!    ((μ+λ)), [`evaluate_fitness`] of parents and children against the collaborators, sort by
//!    `collisions × max_length + length` (invalid = worst), [`select_survivors`] (elitism k, then
//!    one rank-geometric tournament, p_sel, per slice of the rest), then the stop test.
//!
//! An individual is the move string over R, L, U, D, H (halt), stored decoded as one cell per
//! step (signed, so a route may step on a wall or off the map: such an individual is invalid and
//! sorts last, as in the authors' code).
//!
//! Choices where the spec or the authors' code leave room (each measured on the 19 Table I
//! instances, 20–100 seeds, unless said otherwise):
//! - **Conflicts** are the validator's (vertex with a finished robot staying on its last cell,
//!   swap; following allowed), checked both ways. The authors' test scans only the first route's
//!   length, so a robot passing a parked robot's goal after the first route ended went unseen.
//! - **Unsettling** (ours, `unsettle_after`, default 3; 0 = the spec): stage 1 settles robots
//!   for good, and a settled robot whose route blocks a corridor dooms the run. After 3 generations
//!   without fewer collisions among the best individuals, settled robots that collide with an
//!   unsettled robot's best route evolve again. With it, SC1 6–12 are solved in 694 of 700 runs
//!   (seeds 0–99 per row), against 682 without (docs/reproduction/hstar.md, "Unsettling on and
//!   off").
//! - **A\*** uses the Manhattan heuristic (optimal routes), via `pathfinding`'s `astar` with the
//!   cap counted in the successor closure. The authors use squared Euclidean distance
//!   (`-p astar_heuristic=squared-euclidean`; not admissible, so routes may be longer) and return
//!   a partial route when the cap is hit; a route short of its goal is useless here.
//! - **Mutation** as in the authors' code: the start point is drawn among the route cells before
//!   the collision step that lie strictly inside the window around the collision cell (half-size
//!   per axis from `window_initial` of the map width/height at generation 0, linearly to the full
//!   extent at `window_full_at` of the budget, then capped; the authors hard-code a 30×18 extent);
//!   none inside → the start. With `p_halt` a halt is inserted there. Otherwise a direction that
//!   does not undo the previous move is inserted and the old moves up to the merge point are
//!   replayed after it, so the detour is that stretch *shifted* by one cell; it rejoins the old
//!   route by one move (the opposite direction), or by a shortcut when the detour's last or
//!   second-to-last cell already lies on the route (its last occurrence; the authors take the
//!   first, which can loop back). Because the detour is a shifted copy, its end is always
//!   adjacent to the merge point: a single move always reconnects, and no path search is needed.
//!   The merge point is drawn up to and *including* the goal (the authors stop one cell short,
//!   and their draw fails when the start point is the last cell); only then can a robot re-route
//!   around a robot parked next to its own goal. On 5 seeds this turned SC2 from 0/5 solved on
//!   every row into 4, 2, 1, 3 of 5 (and SC1 10/11 from 3/5, 4/5 into 4/5, 5/5; stop depth 1).
//! - **Collision step** of an individual: its earliest true collision with any collaborator;
//!   without one, a random step. (The authors keep only the last collaborator's result, usually
//!   none, so their mutations mostly land at random places.)
//! - **Fitness of parents is re-evaluated** every generation against that generation's
//!   collaborators; the authors keep the parents' stale values. Stale values solved SC1 10/11/12
//!   in 58/41/48 of 100 seeds, fresh ones in 86/99/94 (stop depth 1).
//! - **Generation 0** is evaluated against the robots' current stage-1 routes (the authors draw
//!   one random route of each history).
//! - **Settled robots** are neither mutated nor selected (spec), but their subpopulations (their
//!   histories) are re-evaluated and re-sorted each generation like the others.
//! - **Stop test** ([`Coevolution::stop_depth`], default 3 = k): a conflict-free choice of one
//!   route per robot among the `stop_depth` best of each subpopulation, searched depth-first in
//!   rank order (so the best individuals are tried first) within `stop_node_cap` nodes; the plan
//!   is that choice. The authors' `evaluate()` enumerates exactly these combinations of the k best;
//!   `stop_depth = 1` is the literal "best individuals only" of the authors' description. Depth 3 vs 1 on 100
//!   seeds: SC1 10 solved 92 vs 86, SC1 12 95 vs 94, otherwise equal.
//! - **Inverted fitness** ([`Coevolution::inverted_fitness`]): the authors' bug, where the counter
//!   grows when a pair does *not* collide. The stop test and the validator still judge true
//!   conflicts, so it only ever returns valid plans; with it, only SC3 10 (solved by stage 1) and
//!   SC3 15 are solved.
//! - The tournaments draw again when the geometric draw falls past the end of the slice (as the
//!   authors' loop does), i.e. the geometric distribution truncated to the slice.
//!
//! Measured with the defaults (seeds 0–9, release): SC1 6–11 and SC3 10–30 solved in 10/10, SC1 12
//! in 9/10 (about 95 of 100 seeds; SC1 10 about 92 of 100), every plan valid. SC1 13–15 are
//! essentially never solved: two goals lie in one dead-end corridor and the robot bound for the
//! nearer one must wait about 16 steps for the other to pass, which single halts (each one
//! lengthening the route without removing a collision) do not build up. SC2 (four rooms joined by
//! one-cell doors) is solved in 9, 4, 4, 4 of 10. A run takes at most about 0.2 s.

use pathfinding::directed::astar::astar;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashSet;

use mrpp_core::contract::{Ctx, Deadline, Planner, Unsolved};
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::{Plan, first_conflict, position};
use mrpp_core::{MapfProblem, Param, PlannerEntry};

/// Registry name of Enol2023.
pub const NAME: &str = "coevolution";

/// Enol2023 in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "Enol2023: A* with private obstacles, then cooperative co-evolution (García et al., ICAE 30:41-52, 2023)",
    params: &[
        Param {
            name: "variant",
            default: "intended",
            doc: "intended = fewer collisions is fitter; inverted = the authors' code's inverted collision count",
        },
        Param {
            name: "astar_heuristic",
            default: "manhattan",
            doc: "stage 1's A* heuristic: manhattan (shortest routes) or squared-euclidean (the authors' code; inadmissible)",
        },
        Param {
            name: "collaborators",
            default: "1",
            doc: "q: collaborators drawn from every other robot's subpopulation (1 to 9; the authors' code enumerates every combination)",
        },
        Param {
            name: "unsettle_after",
            default: "3",
            doc: "ours: generations without fewer collisions after which a settled robot that blocks others evolves again (0 = never, as the paper)",
        },
    ],
    build: |p| {
        let collaborators: usize = p.get("collaborators")?;
        if !(1..=9).contains(&collaborators) {
            return Err(mrpp_core::Error::Param(format!(
                "collaborators={collaborators}: expected 1 to 9"
            )));
        }
        let unsettle_after: usize = p.get("unsettle_after")?;
        if unsettle_after > 1_000_000 {
            return Err(mrpp_core::Error::Param(format!(
                "unsettle_after={unsettle_after}: expected 0 to 1000000 generations"
            )));
        }
        Ok(Box::new(Coevolution {
            inverted_fitness: p.choice("variant", &["intended", "inverted"])? == 1,
            heuristic: match p.choice("astar_heuristic", &["manhattan", "squared-euclidean"])? {
                0 => AstarHeuristic::Manhattan,
                _ => AstarHeuristic::SquaredEuclidean,
            },
            collaborators,
            unsettle_after,
            ..Coevolution::default()
        }))
    },
};

/// The planner and its parameters (defaults: the published ones).
#[derive(Debug, Clone)]
pub struct Coevolution {
    /// n_a: rounds of A* with private obstacles.
    pub astar_rounds: usize,
    /// Expansion cap of every re-plan in stage 1 (the first plan of a robot is uncapped).
    pub astar_expansion_cap: usize,
    /// n_gen: generation budget of the co-evolution.
    pub generations: usize,
    /// p_size: individuals kept per subpopulation after selection.
    pub population_size: usize,
    /// q: collaborators drawn from every other robot's subpopulation.
    pub collaborators: usize,
    /// p_eval: rank-geometric tournament probability when drawing collaborators.
    pub p_eval: f64,
    /// k: elitism.
    pub elitism: usize,
    /// p_sel: rank-geometric tournament probability in selection.
    pub p_sel: f64,
    /// Probability that a mutation inserts a halt (else a move).
    pub p_halt: f64,
    /// Half-size of the mutation window at generation 0, as a fraction of the map extent.
    pub window_initial: f64,
    /// Fraction of `generations` at which the window reaches the full map extent.
    pub window_full_at: f64,
    /// Reproduce the authors' inverted collision counter (a pair counts when it does *not*
    /// collide). Plans are still only returned when truly conflict-free.
    pub inverted_fitness: bool,
    /// Stop test: a conflict-free combination of the `stop_depth` best individuals of every
    /// robot (1 = the best individuals only).
    pub stop_depth: usize,
    /// Node cap of the stop test's combination search per generation.
    pub stop_node_cap: usize,
    /// Ours, 0 = off: after this many generations without fewer collisions among the best
    /// individuals, a settled robot whose best route collides with an unsettled robot's best route
    /// is unsettled, so that it can evolve too. Stage 1 settles robots for good, and a settled
    /// robot that blocks a corridor otherwise dooms the run.
    pub unsettle_after: usize,
    /// Stage 1's A* heuristic: Manhattan (shortest routes; ours) or the authors' squared
    /// Euclidean distance (inadmissible: routes may be longer).
    pub heuristic: AstarHeuristic,
}

/// Stage 1's A* heuristic (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AstarHeuristic {
    /// Manhattan distance: admissible on a 4-neighbour grid, so routes are shortest.
    #[default]
    Manhattan,
    /// Squared Euclidean distance, as the authors' code: not admissible.
    SquaredEuclidean,
}

impl Default for Coevolution {
    fn default() -> Self {
        Coevolution {
            astar_rounds: 3,
            astar_expansion_cap: 15_000,
            generations: 100,
            population_size: 9,
            collaborators: 1,
            p_eval: 0.5,
            elitism: 3,
            p_sel: 0.35,
            p_halt: 0.6,
            window_initial: 0.1,
            window_full_at: 0.75,
            inverted_fitness: false,
            stop_depth: 3,
            stop_node_cap: 20_000,
            unsettle_after: 3,
            heuristic: AstarHeuristic::Manhattan,
        }
    }
}

impl Coevolution {
    fn check_parameters(&self) -> Result<(), Unsolved> {
        let prob = |p: f64| p > 0.0 && p <= 1.0;
        if !prob(self.p_eval) || !prob(self.p_sel) || !(0.0..=1.0).contains(&self.p_halt) {
            return Err(Unsolved::GaveUp(
                "Enol2023 parameters: p_eval and p_sel must lie in (0, 1], p_halt in [0, 1]".into(),
            ));
        }
        if self.population_size == 0 || self.window_full_at <= 0.0 {
            return Err(Unsolved::GaveUp(
                "Enol2023 parameters: population_size and window_full_at must be positive".into(),
            ));
        }
        Ok(())
    }
}

/// A grid cell `(x, y)`; individuals may step on walls or off the map, so cells are signed.
pub type Cell = (i32, i32);

/// One letter of an individual's move string.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Move {
    R,
    L,
    U,
    D,
    /// Halt: stay one step.
    H,
}

impl Move {
    pub const DIRECTIONS: [Move; 4] = [Move::R, Move::L, Move::U, Move::D];

    pub fn delta(self) -> (i32, i32) {
        match self {
            Move::R => (1, 0),
            Move::L => (-1, 0),
            Move::U => (0, -1),
            Move::D => (0, 1),
            Move::H => (0, 0),
        }
    }

    pub fn opposite(self) -> Move {
        match self {
            Move::R => Move::L,
            Move::L => Move::R,
            Move::U => Move::D,
            Move::D => Move::U,
            Move::H => Move::H,
        }
    }

    pub fn apply(self, c: Cell) -> Cell {
        let (dx, dy) = self.delta();
        (c.0 + dx, c.1 + dy)
    }

    /// The move from `a` to `b`, `None` when they are not 4-adjacent or equal.
    pub fn between(a: Cell, b: Cell) -> Option<Move> {
        [Move::R, Move::L, Move::U, Move::D, Move::H]
            .into_iter()
            .find(|m| m.apply(a) == b)
    }
}

/// The move string of a route given as cells (one cell per step).
pub fn moves_of(route: &[Cell]) -> Vec<Move> {
    route
        .windows(2)
        .map(|w| Move::between(w[0], w[1]).expect("routes are 4-connected"))
        .collect()
}

/// Which cells of the graph's grid are free, and their vertices.
#[derive(Debug, Clone)]
pub struct GridCells {
    width: i32,
    height: i32,
    vertex: Vec<VertexId>,
}

impl GridCells {
    const NONE: VertexId = VertexId::MAX;

    /// `None` when the graph carries no coordinates.
    pub fn from_graph(g: &Graph) -> Option<Self> {
        let n = g.num_vertices();
        let mut width = 0;
        let mut height = 0;
        for v in 0..n as VertexId {
            let (x, y) = g.coord(v)?;
            width = width.max(x as i32 + 1);
            height = height.max(y as i32 + 1);
        }
        let mut vertex = vec![Self::NONE; (width * height) as usize];
        for v in 0..n as VertexId {
            let (x, y) = g.coord(v)?;
            vertex[(y as i32 * width + x as i32) as usize] = v;
        }
        Some(GridCells {
            width,
            height,
            vertex,
        })
    }

    pub fn width(&self) -> i32 {
        self.width
    }

    pub fn height(&self) -> i32 {
        self.height
    }

    /// The vertex of a free cell; `None` for walls and cells off the map.
    pub fn vertex(&self, c: Cell) -> Option<VertexId> {
        let (x, y) = c;
        if x < 0 || y < 0 || x >= self.width || y >= self.height {
            return None;
        }
        let v = self.vertex[(y * self.width + x) as usize];
        (v != Self::NONE).then_some(v)
    }
}

fn cell_of(g: &Graph, v: VertexId) -> Cell {
    let (x, y) = g.coord(v).expect("grid graphs carry coordinates");
    (x as i32, y as i32)
}

/// The first step at which two routes conflict (§0): the same cell at one step, a finished route
/// staying on its last cell; or cells exchanged between the step before and this one.
pub fn route_conflict<T: Copy + Eq>(a: &[T], b: &[T]) -> Option<usize> {
    if a[0] == b[0] {
        return Some(0);
    }
    // While both move: a shared cell, or cells exchanged.
    let common = a.len().min(b.len());
    for t in 1..common {
        let (na, nb) = (a[t], b[t]);
        if na == nb || (na == b[t - 1] && nb == a[t - 1] && na != a[t - 1]) {
            return Some(t);
        }
    }
    // Then the longer route against the shorter one's last cell (an exchange with a robot that
    // stays is a shared cell).
    let (long, short) = if a.len() >= b.len() { (a, b) } else { (b, a) };
    let last = short[common - 1];
    (common..long.len()).find(|&t| long[t] == last)
}

// ---------------------------------------------------------------------------------------------
// Stage 1: A* with private obstacles
// ---------------------------------------------------------------------------------------------

/// 4-neighbour unit-cost A* (Manhattan heuristic) on a robot's private map (the map less the
/// cells in `obstacles`); the successor closure counts expansions and offers none past `cap`,
/// which ends the search without a route.
fn private_astar(
    g: &Graph,
    start: VertexId,
    goal: VertexId,
    obstacles: &FxHashSet<VertexId>,
    cap: usize,
    heuristic: AstarHeuristic,
) -> Option<Vec<VertexId>> {
    let mut expanded = 0usize;
    let h = |v: VertexId| match heuristic {
        AstarHeuristic::Manhattan => g.manhattan(v, goal),
        AstarHeuristic::SquaredEuclidean => match (g.coord(v), g.coord(goal)) {
            (Some((ax, ay)), Some((bx, by))) => {
                let (dx, dy) = (ax.abs_diff(bx), ay.abs_diff(by));
                dx.saturating_mul(dx).saturating_add(dy.saturating_mul(dy))
            }
            _ => 0,
        },
    };
    astar(
        &start,
        |&v| {
            expanded += 1;
            let open = expanded <= cap;
            g.neighbors(v)
                .iter()
                .filter(|&&w| open && !obstacles.contains(&w))
                .map(|&w| (w, 1u32))
                .collect::<Vec<_>>()
        },
        |&v| h(v),
        |&v| v == goal,
    )
    .map(|(path, _)| path)
}

/// What stage 1 leaves behind.
#[derive(Debug, Clone)]
pub struct AstarStage {
    /// The current route of every robot.
    pub routes: Vec<Vec<VertexId>>,
    /// Every route each robot was given, oldest first (the initial subpopulations).
    pub history: Vec<Vec<Vec<VertexId>>>,
    /// Robots that met no conflict in some round; they are no longer changed.
    pub settled: Vec<bool>,
    /// A round ended without any conflict: `routes` is the answer.
    pub conflict_free: bool,
    /// Rounds run.
    pub rounds: usize,
}

/// Stage 1: plan every robot alone, then for `astar_rounds` rounds block each unsettled robot's
/// conflict cells on its private map and re-plan it.
pub fn astar_with_private_obstacles(
    g: &Graph,
    inst: &Instance,
    cfg: &Coevolution,
    deadline: Deadline,
) -> Result<AstarStage, Unsolved> {
    let n = inst.num_agents();
    // Each robot's private obstacles: the few cells it was told to avoid (a set, so memory
    // follows the conflicts met, not the map's size).
    let mut obstacles: Vec<FxHashSet<VertexId>> = vec![FxHashSet::default(); n];
    let mut routes = Vec::with_capacity(n);
    for (i, private) in obstacles.iter().enumerate() {
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        match private_astar(
            g,
            inst.starts[i],
            inst.goals[i],
            private,
            usize::MAX,
            cfg.heuristic,
        ) {
            Some(r) => routes.push(r),
            None => {
                return Err(Unsolved::GaveUp(format!(
                    "agent {i} cannot reach its goal on this map"
                )));
            }
        }
    }
    let mut history: Vec<Vec<Vec<VertexId>>> = routes.iter().map(|r| vec![r.clone()]).collect();
    let mut settled = vec![false; n];
    for round in 0..cfg.astar_rounds {
        let mut any_conflict = false;
        for a in 0..n {
            if settled[a] {
                continue;
            }
            if deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            let mut met_conflict = false;
            for b in 0..n {
                if a == b {
                    continue;
                }
                let Some(t) = route_conflict(&routes[a], &routes[b]) else {
                    continue;
                };
                any_conflict = true;
                met_conflict = true;
                let cell = position(&routes[a], t);
                if cell == inst.starts[a] || cell == inst.goals[a] {
                    continue;
                }
                obstacles[a].insert(cell);
                if deadline.expired() {
                    return Err(Unsolved::TimeLimit);
                }
                if let Some(r) = private_astar(
                    g,
                    inst.starts[a],
                    inst.goals[a],
                    &obstacles[a],
                    cfg.astar_expansion_cap,
                    cfg.heuristic,
                ) {
                    routes[a] = r.clone();
                    history[a].push(r);
                }
            }
            if !met_conflict {
                settled[a] = true;
            }
        }
        if !any_conflict {
            return Ok(AstarStage {
                routes,
                history,
                settled,
                conflict_free: true,
                rounds: round + 1,
            });
        }
    }
    Ok(AstarStage {
        routes,
        history,
        settled,
        conflict_free: false,
        rounds: cfg.astar_rounds,
    })
}

// ---------------------------------------------------------------------------------------------
// Stage 2: cooperative co-evolution
// ---------------------------------------------------------------------------------------------

/// One route of a subpopulation and its fitness.
#[derive(Debug, Clone)]
pub struct Individual {
    /// One cell per step from the start (the move string, decoded).
    pub route: Vec<Cell>,
    /// The route steps on a wall or off the map, or does not end on the goal (never happens with
    /// this mutation, but such a route must never be chosen).
    pub invalid: bool,
    /// Collisions with the collaborators (inverted when `inverted_fitness`).
    pub collisions: u32,
    /// The earliest step at which it truly collides with a collaborator.
    pub collision_step: Option<usize>,
    /// Names the route within one run (copies keep it): [`Conflicts`] remembers pairs by it.
    pub id: u64,
}

impl Individual {
    fn new(route: Vec<Cell>, goal: Cell, grid: &GridCells, id: u64) -> Self {
        let invalid =
            route.last() != Some(&goal) || route.iter().any(|&c| grid.vertex(c).is_none());
        Individual {
            route,
            invalid,
            collisions: 0,
            collision_step: None,
            id,
        }
    }

    /// Length in moves, halts included.
    pub fn length(&self) -> usize {
        self.route.len() - 1
    }

    /// Invalid (wall) → worst; otherwise collisions × max_length + length.
    pub fn sort_key(&self, max_length: usize) -> u64 {
        if self.invalid {
            u64::MAX
        } else {
            self.collisions as u64 * max_length as u64 + self.length() as u64
        }
    }
}

/// Index drawn by a rank-geometric tournament over `len` sorted items: the i-th best with
/// probability p(1−p)^i, drawn again when the draw falls past the end.
pub fn rank_geometric(len: usize, p: f64, rng: &mut ChaCha8Rng) -> usize {
    assert!(len > 0 && p > 0.0);
    loop {
        let r: f64 = rng.random();
        let mut sum = 0.0;
        let mut w = p;
        for i in 0..len {
            sum += w;
            if r < sum {
                return i;
            }
            w *= 1.0 - p;
        }
    }
}

/// The ranges of `parts` consecutive slices of `len` sorted items, the last taking the rest;
/// one slice over everything when there are fewer items than slices.
fn slices(len: usize, parts: usize) -> Vec<std::ops::Range<usize>> {
    let size = len / parts.max(1);
    if size == 0 {
        return vec![0..len; parts.max(1)];
    }
    (0..parts)
        .map(|j| {
            let end = if j + 1 == parts { len } else { (j + 1) * size };
            j * size..end
        })
        .collect()
}

/// Collaborators of a robot: `q` individuals of its sorted subpopulation, one rank-geometric
/// tournament (p_eval) per consecutive slice.
pub fn choose_collaborators(
    population: &[Individual],
    cfg: &Coevolution,
    rng: &mut ChaCha8Rng,
) -> Vec<usize> {
    slices(population.len(), cfg.collaborators)
        .into_iter()
        .map(|s| s.start + rank_geometric(s.len(), cfg.p_eval, rng))
        .collect()
}

/// [`route_conflict`] of individuals, remembered by their ids: survivors and collaborators
/// persist from generation to generation, so most pairs are judged again and again.
#[derive(Default)]
pub struct Conflicts {
    known: rustc_hash::FxHashMap<(u64, u64), Option<u32>>,
    next_id: u64,
}

/// Pairs [`Conflicts`] remembers before it starts afresh (about 24 MB).
const CONFLICTS_LIMIT: usize = 1 << 20;

impl Conflicts {
    /// A fresh individual id.
    pub fn new_id(&mut self) -> u64 {
        self.next_id += 1;
        self.next_id
    }

    /// [`route_conflict`] of `a` and `b` (it is symmetric).
    pub fn between(&mut self, a: &Individual, b: &Individual) -> Option<usize> {
        let key = (a.id.min(b.id), a.id.max(b.id));
        if let Some(&hit) = self.known.get(&key) {
            return hit.map(|t| t as usize);
        }
        let hit = route_conflict(&a.route, &b.route);
        if self.known.len() >= CONFLICTS_LIMIT {
            self.known.clear();
        }
        self.known.insert(key, hit.map(|t| t as u32));
        hit
    }
}

/// Fitness of an individual of robot `me` against one set of collaborators per robot.
pub fn evaluate_fitness(
    ind: &mut Individual,
    me: usize,
    collaborators: &[Vec<Individual>],
    inverted: bool,
    conflicts: &mut Conflicts,
) {
    let mut collisions = 0;
    let mut first: Option<usize> = None;
    for (j, routes) in collaborators.iter().enumerate() {
        if j == me {
            continue;
        }
        for r in routes {
            let hit = conflicts.between(ind, r);
            if let Some(t) = hit {
                first = Some(first.map_or(t, |f| f.min(t)));
            }
            if hit.is_some() != inverted {
                collisions += 1;
            }
        }
    }
    ind.collisions = collisions;
    ind.collision_step = first;
}

/// Half-sizes of the mutation window at `generation`: from `window_initial` of the map extent,
/// growing linearly to the full extent at `window_full_at` of the generation budget.
fn window_half_size(cfg: &Coevolution, generation: usize, extent: (i32, i32)) -> (f64, f64) {
    let progress = generation as f64 / (cfg.window_full_at * cfg.generations.max(1) as f64);
    let f = (cfg.window_initial + (1.0 - cfg.window_initial) * progress).min(1.0);
    (f * extent.0 as f64, f * extent.1 as f64)
}

/// The mutation: pick a start point before the collision step inside the window around the
/// collision cell; insert a halt there, or a move followed by the old moves up to a later merge
/// point (the detour, i.e. that stretch shifted by the move), and rejoin the old route.
pub fn mutate(
    route: &[Cell],
    collision_step: Option<usize>,
    generation: usize,
    cfg: &Coevolution,
    grid: &GridCells,
    rng: &mut ChaCha8Rng,
) -> Vec<Cell> {
    let extent = (grid.width(), grid.height());
    let len = route.len() - 1;
    let c = match collision_step {
        Some(t) => t.min(len),
        None if len > 0 => rng.random_range(0..len),
        None => 0,
    };
    let centre = route[c];
    let (hx, hy) = window_half_size(cfg, generation, extent);
    let candidates: Vec<usize> = (0..c)
        .filter(|&i| {
            let (x, y) = route[i];
            ((x - centre.0).abs() as f64) < hx && ((y - centre.1).abs() as f64) < hy
        })
        .collect();
    let msp = if candidates.is_empty() {
        0
    } else {
        candidates[rng.random_range(0..candidates.len())]
    };
    let mut out: Vec<Cell> = Vec::with_capacity(route.len() + 2);
    out.extend_from_slice(&route[..=msp]);
    if rng.random_bool(cfg.p_halt) {
        out.push(route[msp]);
        out.extend_from_slice(&route[msp + 1..]);
        return out;
    }
    let previous = (msp > 0).then(|| Move::between(route[msp - 1], route[msp]));
    let allowed: Vec<Move> = Move::DIRECTIONS
        .into_iter()
        .filter(|m| previous.flatten() != Some(m.opposite()))
        .collect();
    let op = allowed[rng.random_range(0..allowed.len())];
    let merge = if msp < len {
        rng.random_range(msp + 1..=len)
    } else {
        len
    };
    let detour: Vec<Cell> = route[msp..=merge].iter().map(|&c| op.apply(c)).collect();
    let last_on_route = |cell: Cell| route.iter().rposition(|&c| c == cell);
    let k = detour.len();
    if k >= 2
        && let Some(j) = last_on_route(detour[k - 2])
    {
        // Shortcut: the detour's second-to-last cell is on the route.
        out.extend_from_slice(&detour[..k - 1]);
        out.extend_from_slice(&route[j + 1..]);
    } else if let Some(j) = last_on_route(detour[k - 1]) {
        out.extend_from_slice(&detour);
        out.extend_from_slice(&route[j + 1..]);
    } else {
        // One connecting move (the opposite of `op`) back onto the merge point.
        out.extend_from_slice(&detour);
        out.extend_from_slice(&route[merge..]);
    }
    out
}

/// Keeps the `k` best of a sorted subpopulation, then fills it up to `p_size` with one
/// rank-geometric tournament (p_sel) per consecutive slice of the sorted rest.
pub fn select_survivors(population: &mut Vec<Individual>, cfg: &Coevolution, rng: &mut ChaCha8Rng) {
    let k = cfg.elitism.min(cfg.population_size).min(population.len());
    let rest = population.split_off(k);
    let slots = cfg.population_size - k;
    if slots == 0 || rest.is_empty() {
        return;
    }
    if rest.len() < slots {
        population.extend(rest);
        return;
    }
    for s in slices(rest.len(), slots) {
        let i = s.start + rank_geometric(s.len(), cfg.p_sel, rng);
        population.push(rest[i].clone());
    }
}

fn sort_population(population: &mut [Individual]) {
    let max_length = population.iter().map(Individual::length).max().unwrap_or(0);
    population.sort_by_key(|i| i.sort_key(max_length));
}

/// How many robot pairs still collide when every robot takes its best individual.
fn colliding_best_pairs(populations: &[Vec<Individual>]) -> usize {
    let mut pairs = 0;
    for a in 0..populations.len() {
        for b in a + 1..populations.len() {
            let hit = route_conflict(&populations[a][0].route, &populations[b][0].route);
            pairs += usize::from(hit.is_some());
        }
    }
    pairs
}

/// The stop test: a conflict-free choice of one route per robot among the `depth` best
/// individuals of each subpopulation (depth 1 = the best individuals only), found by
/// depth-first search in rank order (so the bests are tried first) within `node_cap` nodes.
fn conflict_free_combination(
    populations: &[Vec<Individual>],
    depth: usize,
    node_cap: usize,
) -> Option<Vec<usize>> {
    // Candidates of all robots numbered globally: robot a's j-th is `first[a] + j`.
    let mut first = Vec::with_capacity(populations.len());
    let mut owner: Vec<(usize, usize)> = Vec::new();
    for (a, pop) in populations.iter().enumerate() {
        first.push(owner.len());
        owner.extend(
            (0..pop.len().min(depth.max(1)))
                .filter(|&i| !pop[i].invalid)
                .map(|i| (a, i)),
        );
    }
    first.push(owner.len());
    let route = |c: usize| &populations[owner[c].0][owner[c].1].route;
    // Bit d of row c: candidate d is compatible with candidate c (only d > c of another robot
    // is ever read; the others are set).
    let m = owner.len();
    let words = m.div_ceil(64).max(1);
    let mut compatible = vec![u64::MAX; m * words];
    for c in 0..m {
        for d in c + 1..m {
            if owner[c].0 != owner[d].0 && route_conflict(route(c), route(d)).is_some() {
                compatible[c * words + d / 64] &= !(1 << (d % 64));
            }
        }
    }
    let mut search = CombinationSearch {
        first: &first,
        compatible: &compatible,
        words,
        allowed: vec![u64::MAX; words],
        chosen: Vec::with_capacity(populations.len()),
        nodes: 0,
        node_cap,
    };
    search
        .extend()
        .then(|| search.chosen.iter().map(|&c| owner[c].1).collect())
}

/// Depth-first search state of [`conflict_free_combination`].
struct CombinationSearch<'a> {
    first: &'a [usize],
    /// Row-major bit matrix, `words` words per candidate.
    compatible: &'a [u64],
    words: usize,
    /// Per depth (robots `0..chosen.len()` chosen), the candidates compatible with every chosen
    /// one: `words` words each, the AND of the chosen candidates' rows.
    allowed: Vec<u64>,
    /// Global candidate ids chosen for robots `0..chosen.len()`.
    chosen: Vec<usize>,
    nodes: usize,
    node_cap: usize,
}

impl CombinationSearch<'_> {
    fn extend(&mut self) -> bool {
        let b = self.chosen.len();
        if b + 1 == self.first.len() {
            return true;
        }
        let w = self.words;
        for d in self.first[b]..self.first[b + 1] {
            self.nodes += 1;
            if self.nodes > self.node_cap {
                return false;
            }
            if self.allowed[b * w + d / 64] & (1 << (d % 64)) != 0 {
                self.chosen.push(d);
                let row = &self.compatible[d * w..(d + 1) * w];
                self.allowed.truncate((b + 1) * w);
                for (k, &bits) in row.iter().enumerate() {
                    let next = self.allowed[b * w + k] & bits;
                    self.allowed.push(next);
                }
                if self.extend() {
                    return true;
                }
                self.chosen.pop();
            }
        }
        false
    }
}

/// The stop test of a generation, with the chosen routes as vertex paths.
fn stop_test(
    populations: &[Vec<Individual>],
    cfg: &Coevolution,
    grid: &GridCells,
    num_vertices: usize,
) -> Option<Vec<Vec<VertexId>>> {
    let choice = conflict_free_combination(populations, cfg.stop_depth, cfg.stop_node_cap)?;
    let paths: Vec<Vec<VertexId>> = choice
        .iter()
        .enumerate()
        .map(|(a, &i)| {
            populations[a][i]
                .route
                .iter()
                .map(|&c| grid.vertex(c).expect("wall-free candidate"))
                .collect()
        })
        .collect();
    first_conflict(&paths, num_vertices, true)
        .is_none()
        .then_some(paths)
}

/// Stage 2: one subpopulation per robot seeded with its route history; (μ+λ) generations of
/// mutation, evaluation against collaborators and selection until the best routes of all robots
/// are conflict-free.
pub fn cooperative_coevolution(
    g: &Graph,
    grid: &GridCells,
    inst: &Instance,
    stage: &AstarStage,
    cfg: &Coevolution,
    rng: &mut ChaCha8Rng,
    ctx: &Ctx,
) -> Result<Vec<Vec<VertexId>>, Unsolved> {
    let deadline = ctx.deadline;
    let mut throttle = mrpp_core::Throttle::new();
    let nv = g.num_vertices();
    let to_cells = |r: &[VertexId]| -> Vec<Cell> { r.iter().map(|&v| cell_of(g, v)).collect() };
    let mut conflicts = Conflicts::default();
    let mut populations: Vec<Vec<Individual>> = stage
        .history
        .iter()
        .zip(&inst.goals)
        .map(|(h, &goal)| {
            h.iter()
                .map(|r| {
                    let id = conflicts.new_id();
                    Individual::new(to_cells(r), cell_of(g, goal), grid, id)
                })
                .collect()
        })
        .collect();
    // Generation 0 is judged against the robots' current stage-1 routes.
    let current: Vec<Vec<Individual>> = stage
        .routes
        .iter()
        .zip(&inst.goals)
        .map(|(r, &goal)| {
            let id = conflicts.new_id();
            vec![Individual::new(to_cells(r), cell_of(g, goal), grid, id)]
        })
        .collect();
    for (a, pop) in populations.iter_mut().enumerate() {
        for ind in pop.iter_mut() {
            evaluate_fitness(ind, a, &current, cfg.inverted_fitness, &mut conflicts);
        }
        sort_population(pop);
    }
    if let Some(paths) = stop_test(&populations, cfg, grid, nv) {
        return Ok(paths);
    }
    let mut settled = stage.settled.clone();
    let mut fewest = u32::MAX;
    let mut stalled = 0;
    for generation in 0..cfg.generations {
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        throttle.report(ctx, || mrpp_core::Progress {
            stage: "co-evolution generation",
            done: generation as u64,
            total: cfg.generations as u64,
            note: if fewest == u32::MAX {
                String::new()
            } else {
                format!("fewest collisions {fewest}")
            },
        });
        let collaborators: Vec<Vec<Individual>> = populations
            .iter()
            .map(|pop| {
                choose_collaborators(pop, cfg, rng)
                    .into_iter()
                    .map(|i| pop[i].clone())
                    .collect()
            })
            .collect();
        for (a, pop) in populations.iter_mut().enumerate() {
            if settled[a] {
                continue;
            }
            let goal = cell_of(g, inst.goals[a]);
            let children: Vec<Individual> = pop
                .iter()
                .map(|ind| {
                    let child = mutate(&ind.route, ind.collision_step, generation, cfg, grid, rng);
                    Individual::new(child, goal, grid, conflicts.new_id())
                })
                .collect();
            pop.extend(children);
        }
        for (a, pop) in populations.iter_mut().enumerate() {
            for ind in pop.iter_mut() {
                evaluate_fitness(ind, a, &collaborators, cfg.inverted_fitness, &mut conflicts);
            }
            sort_population(pop);
            if !settled[a] {
                select_survivors(pop, cfg, rng);
            }
        }
        if let Some(paths) = stop_test(&populations, cfg, grid, nv) {
            return Ok(paths);
        }
        let total: u32 = populations.iter().map(|p| p[0].collisions).sum();
        if total < fewest {
            fewest = total;
            stalled = 0;
        } else {
            stalled += 1;
        }
        if cfg.unsettle_after > 0 && stalled >= cfg.unsettle_after {
            stalled = 0;
            let n = populations.len();
            let evolving: Vec<usize> = (0..n).filter(|&a| !settled[a]).collect();
            for a in evolving {
                for b in 0..n {
                    if settled[b]
                        && route_conflict(&populations[a][0].route, &populations[b][0].route)
                            .is_some()
                    {
                        settled[b] = false;
                    }
                }
            }
        }
    }
    Err(Unsolved::GaveUp(format!(
        "co-evolution: the best routes still collide ({} robot pairs) after {} generations",
        colliding_best_pairs(&populations),
        cfg.generations
    )))
}

impl Planner<MapfProblem> for Coevolution {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&self, problem: &MapfProblem, opts: &Ctx) -> Result<Plan, Unsolved> {
        let (g, inst) = (problem.graph(), problem.instance());
        self.check_parameters()?;
        let grid = GridCells::from_graph(g).ok_or_else(|| {
            Unsolved::GaveUp("Enol2023 needs a grid graph (vertex coordinates)".into())
        })?;
        opts.report(mrpp_core::Progress {
            stage: "Enol2023 stage",
            done: 1,
            total: 2,
            note: "A* with private obstacles".into(),
        });
        let stage = astar_with_private_obstacles(g, inst, self, opts.deadline)?;
        if stage.conflict_free
            && first_conflict(&stage.routes, g.num_vertices(), true).is_none()
            && (0..inst.num_agents()).all(|i| stage.routes[i].last() == Some(&inst.goals[i]))
        {
            return Ok(Plan::new(stage.routes.clone()));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
        let paths = cooperative_coevolution(g, &grid, inst, &stage, self, &mut rng, opts)?;
        Ok(Plan::new(paths))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::GridMap;
    use mrpp_core::{Instance, Problem as _, Rules};
    use std::path::Path;

    fn load(map: &str, robots: &str) -> (GridMap, Instance) {
        let m = GridMap::parse(map, Path::new("m.txt")).unwrap().0;
        let inst = crate::scen::parse_agents(robots, Path::new("r.txt"), &m, None).unwrap();
        (m, inst)
    }

    fn run(m: &GridMap, inst: &Instance, cfg: &Coevolution, seed: u64) -> Result<Plan, Unsolved> {
        let opts = Ctx {
            seed,
            ..Ctx::default()
        };
        let r = cfg.plan(&MapfProblem::on(m.graph(), inst, Rules::default()), &opts);
        if let Ok(plan) = &r {
            MapfProblem::on(m.graph(), inst, Rules::default())
                .validate(plan)
                .unwrap();
        }
        r
    }

    #[test]
    fn route_conflicts_match_the_validator_rules() {
        // Vertex conflict at t = 1.
        assert_eq!(route_conflict(&[1, 2, 3], &[4, 2, 5]), Some(1));
        // Swap between t = 0 and t = 1.
        assert_eq!(route_conflict(&[1, 2], &[2, 1]), Some(1));
        // Following is allowed.
        assert_eq!(route_conflict(&[1, 2, 3], &[2, 3, 4]), None);
        // A finished route stays on its last cell and blocks it.
        assert_eq!(route_conflict(&[7], &[5, 6, 7, 8]), Some(2));
        assert_eq!(route_conflict(&[5, 6, 7, 8], &[7]), Some(2));
    }

    #[test]
    fn stage_one_alone_solves_an_open_room() {
        let map = "#######\n#     #\n#     #\n#     #\n#######";
        let (m, inst) = load(map, "1,1;5,1\n5,3;1,3\n3,2;3,3");
        let cfg = Coevolution::default();
        let stage = astar_with_private_obstacles(m.graph(), &inst, &cfg, Deadline::none()).unwrap();
        assert!(stage.conflict_free);
        let plan = run(&m, &inst, &cfg, 0).unwrap();
        assert_eq!(plan.paths, stage.routes);
    }

    #[test]
    fn private_obstacles_reroute_a_robot() {
        // Both cross the middle column of a 3x3 room at t = 2; stage 1 blocks the crossing cell
        // on the later robot's private map, which then goes round.
        let map = "#####\n#   #\n#   #\n#   #\n#####";
        let (m, inst) = load(map, "1,2;3,2\n2,1;2,3");
        let cfg = Coevolution::default();
        let stage = astar_with_private_obstacles(m.graph(), &inst, &cfg, Deadline::none()).unwrap();
        assert!(stage.history.iter().any(|h| h.len() > 1));
        assert!(stage.conflict_free);
        run(&m, &inst, &cfg, 0).unwrap();
    }

    #[test]
    fn a_plus_crossing_needs_the_coevolution() {
        // Centre (2,2) is the only way for both; blocking it leaves no route, so stage 1 ends with
        // the conflict and stage 2 must insert a halt.
        let map = "#####\n## ##\n#   #\n## ##\n#####";
        let (m, inst) = load(map, "1,2;3,2\n2,3;2,1");
        let cfg = Coevolution::default();
        let stage = astar_with_private_obstacles(m.graph(), &inst, &cfg, Deadline::none()).unwrap();
        assert!(!stage.conflict_free);
        for seed in 0..5 {
            let plan = run(&m, &inst, &cfg, seed).unwrap();
            let metrics = MapfProblem::on(m.graph(), &inst, Rules::default())
                .validate(&plan)
                .unwrap();
            assert!(metrics.makespan >= 3);
        }
    }

    #[test]
    fn a_head_on_corridor_is_solved_or_honestly_not() {
        // Passing needs one robot to hide in the one-cell pocket and wait: several neutral
        // mutations in a row, which the search may or may not find.
        let map = "#########\n## ######\n#       #\n#########";
        let (m, inst) = load(map, "1,2;7,2\n7,2;1,2");
        for seed in 0..3 {
            match run(&m, &inst, &Coevolution::default(), seed) {
                Ok(_) | Err(Unsolved::GaveUp(_)) => {}
                Err(e) => panic!("unexpected {e}"),
            }
        }
    }

    #[test]
    fn same_seed_same_plan() {
        let map = "#########\n#   #   #\n#       #\n#   #   #\n#########";
        let robots = "1,2;7,2\n7,2;1,2\n2,1;6,3\n6,1;2,3";
        let (m, inst) = load(map, robots);
        let cfg = Coevolution::default();
        let a = run(&m, &inst, &cfg, 7);
        let b = run(&m, &inst, &cfg, 7);
        assert_eq!(a, b);
    }

    #[test]
    fn inverted_fitness_never_returns_an_invalid_plan() {
        let map = "#####\n## ##\n#   #\n## ##\n#####";
        let (m, inst) = load(map, "1,2;3,2\n2,3;2,1");
        let cfg = Coevolution {
            inverted_fitness: true,
            ..Coevolution::default()
        };
        for seed in 0..5 {
            match run(&m, &inst, &cfg, seed) {
                Ok(_) | Err(Unsolved::GaveUp(_)) => {}
                Err(e) => panic!("unexpected {e}"),
            }
        }
    }

    #[test]
    fn mutation_keeps_routes_connected_from_start_to_goal() {
        let map = "##########\n#        #\n# ##  ## #\n#        #\n##########";
        let m = GridMap::parse(map, Path::new("m.txt")).unwrap().0;
        let grid = GridCells::from_graph(m.graph()).unwrap();
        let cfg = Coevolution::default();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let start: Cell = (1, 1);
        let goal: Cell = (8, 3);
        let mut route: Vec<Cell> = (1..=8).map(|x| (x, 1)).collect();
        route.extend([(8, 2), (8, 3)]);
        let mut valid_children = 0;
        for i in 0..2000 {
            let step = (i % 3 == 0).then_some(i % route.len());
            let child = mutate(&route, step, i % 100, &cfg, &grid, &mut rng);
            assert_eq!(child[0], start);
            assert_eq!(*child.last().unwrap(), goal);
            for w in child.windows(2) {
                assert!(Move::between(w[0], w[1]).is_some(), "{w:?} not 4-connected");
            }
            assert_eq!(moves_of(&child).len(), child.len() - 1);
            let ind = Individual::new(child.clone(), goal, &grid, 0);
            if !ind.invalid {
                valid_children += 1;
                // Keep walking through valid routes so that halts and detours accumulate.
                route = child;
            }
        }
        assert!(valid_children > 100);
    }

    #[test]
    fn selection_keeps_the_elite_and_the_size() {
        let m = GridMap::parse("#####\n#   #\n#####", Path::new("m.txt"))
            .unwrap()
            .0;
        let grid = GridCells::from_graph(m.graph()).unwrap();
        let cfg = Coevolution::default();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut pop: Vec<Individual> = (0..18)
            .map(|k| {
                let mut route = vec![(1, 1); k + 1];
                route.push((2, 1));
                Individual::new(route, (2, 1), &grid, k as u64)
            })
            .collect();
        sort_population(&mut pop);
        select_survivors(&mut pop, &cfg, &mut rng);
        assert_eq!(pop.len(), cfg.population_size);
        let lengths: Vec<usize> = pop.iter().map(Individual::length).collect();
        assert_eq!(&lengths[..3], &[1, 2, 3]);
        assert!(lengths.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn expired_deadline_is_honoured() {
        let (m, inst) = load("#######\n#     #\n#     #\n#######", "1,1;5,2\n5,1;1,2");
        let opts = Ctx::new(0, Deadline::after(std::time::Duration::ZERO));
        assert_eq!(
            Coevolution::default()
                .plan(&MapfProblem::on(m.graph(), &inst, Rules::default()), &opts),
            Err(Unsolved::TimeLimit)
        );
    }
}
