//! The executed-record validator: replays an [`Execution`]'s record (each move's first and last
//! tick, each delay) against the plan, without the executor's logic, and recounts its collisions.
//!
//! Rules: every robot makes exactly its plan's moves (waits dropped), in order, one at a time;
//! a move lasts exactly `ticks_per_move` ticks in which its robot is not held by a delay (a held
//! robot does not progress, and never starts a move); a robot's delays do not overlap. A ring
//! executed jointly must be a ring of the plan (moves at one step, each into the cell the next
//! leaves); its moves share their ticks and progress on the ticks no member is held. Positions
//! and footprints are those of [`crate::execute()`]; the collisions found must be the ones recorded.

use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::plan::Plan;
use mrpp_mapf::GridMap;

use crate::execute::{Collision, Execution};

/// Robots' points at the end of a tick, from an execution's record (the module's rules).
pub struct Replay<'a> {
    pub map: &'a GridMap,
    /// Each robot's start.
    pub starts: &'a [VertexId],
    /// Each robot's moves, `(from, to)`, waits dropped.
    pub moves: &'a [Vec<(VertexId, VertexId)>],
    /// Each robot's executed moves `[first tick, tick after]` ([`Execution::moves`]).
    pub ticks: &'a [Vec<[u64; 2]>],
    /// Each robot's delays ([`Execution::delays`]).
    pub delays: &'a [Vec<[u64; 2]>],
    /// Rings executed jointly ([`Execution::rotations`]).
    pub rings: &'a [Vec<(usize, usize)>],
    /// The ring of each `(robot, move)` executed jointly (index into `rings`).
    pub ring_of: std::collections::HashMap<(usize, usize), usize>,
    /// Ticks per move.
    pub c: u64,
}

impl Replay<'_> {
    /// Ticks in `[a, b)` on which some robot of ring `g` is held.
    pub fn ring_held(&self, g: usize, a: u64, b: u64) -> u64 {
        (a..b)
            .filter(|&t| {
                self.rings[g]
                    .iter()
                    .any(|&(j, _)| held(&self.delays[j], t, t + 1) > 0)
            })
            .count() as u64
    }

    /// Whether robot `i` is held during tick `t`.
    pub fn held_at(&self, i: usize, t: u64) -> bool {
        held(&self.delays[i], t, t + 1) > 0
    }

    /// Every robot's point (cell centres, `[x, y]`) at the end of tick `tick`.
    pub fn at(&self, tick: u64) -> Vec<[f64; 2]> {
        let centre = |v: VertexId| {
            let (x, y) = self.map.cell(v);
            [f64::from(x) + 0.5, f64::from(y) + 0.5]
        };
        (0..self.starts.len())
            .map(|i| {
                let rec = &self.ticks[i];
                // Moves finished by the end of this tick, and the one under way.
                let finished = rec.partition_point(|m| m[1] <= tick + 1);
                match rec.get(finished).filter(|m| m[0] <= tick) {
                    Some(&[a, _]) => {
                        let stopped = match self.ring_of.get(&(i, finished)) {
                            Some(&g) => self.ring_held(g, a, tick + 1),
                            None => held(&self.delays[i], a, tick + 1),
                        };
                        let p = (tick + 1 - a) - stopped;
                        let (from, to) = self.moves[i][finished];
                        let (s, e) = (centre(from), centre(to));
                        let f = p as f64 / self.c as f64;
                        [s[0] + (e[0] - s[0]) * f, s[1] + (e[1] - s[1]) * f]
                    }
                    None if finished == 0 => centre(self.starts[i]),
                    None => centre(self.moves[i][finished - 1].1),
                }
            })
            .collect()
    }
}

/// Held ticks of `delays` (sorted, disjoint) within `[a, b)`.
fn held(delays: &[[u64; 2]], a: u64, b: u64) -> u64 {
    delays
        .iter()
        .map(|d| d[1].min(b).saturating_sub(d[0].max(a)))
        .sum()
}

/// Checks `exec` against `plan` (module doc); returns the collisions of the replay.
///
/// # Errors
/// The first rule broken, naming the robot, the move and the tick.
pub fn check(
    map: &GridMap,
    plan: &Plan,
    exec: &Execution,
    ticks_per_move: u32,
    agent_size: f64,
) -> Result<Vec<Collision>, String> {
    let c = u64::from(ticks_per_move.max(1));
    let n = plan.paths.len();
    if exec.moves.len() != n || exec.delays.len() != n {
        return Err(format!(
            "the record has {} robots' moves and {} robots' delays, the plan {n} robots",
            exec.moves.len(),
            exec.delays.len()
        ));
    }
    let moves: Vec<Vec<(VertexId, VertexId)>> = plan
        .paths
        .iter()
        .map(|p| {
            p.windows(2)
                .filter(|w| w[0] != w[1])
                .map(|w| (w[0], w[1]))
                .collect()
        })
        .collect();
    let steps: Vec<Vec<usize>> = plan
        .paths
        .iter()
        .map(|p| {
            (0..p.len().saturating_sub(1))
                .filter(|&t| p[t] != p[t + 1])
                .collect()
        })
        .collect();
    // Rings: each a ring of the plan; the ticks on which any member is held.
    let mut ring_of = std::collections::HashMap::new();
    for (g, members) in exec.rotations.iter().enumerate() {
        for (t, &(i, k)) in members.iter().enumerate() {
            let (j, m) = members[(t + 1) % members.len()];
            let ok = i < n
                && j < n
                && k < moves[i].len()
                && m < moves[j].len()
                && moves[i][k].1 == moves[j][m].0
                && steps[i][k] == steps[j][m];
            if !ok || members.len() < 2 {
                return Err(format!("ring {g} ({members:?}) is not a ring of the plan"));
            }
            ring_of.insert((i, k), g);
        }
    }
    let starts: Vec<VertexId> = plan.paths.iter().map(|p| p[0]).collect();
    let replay = Replay {
        map,
        starts: &starts,
        moves: &moves,
        ticks: &exec.moves,
        delays: &exec.delays,
        rings: &exec.rotations,
        ring_of: ring_of.clone(),
        c,
    };
    let ring_held = |g: usize, a: u64, b: u64| replay.ring_held(g, a, b);
    for (i, (rec, dl)) in exec.moves.iter().zip(&exec.delays).enumerate() {
        for w in dl.windows(2) {
            if w[1][0] < w[0][1] {
                return Err(format!(
                    "robot {i}: delays {:?} and {:?} overlap",
                    w[0], w[1]
                ));
            }
        }
        if rec.len() > moves[i].len() {
            return Err(format!(
                "robot {i}: {} moves executed, its plan has {}",
                rec.len(),
                moves[i].len()
            ));
        }
        let mut free_from = 0;
        for (k, &[a, b]) in rec.iter().enumerate() {
            if a < free_from || b <= a {
                return Err(format!(
                    "robot {i}, move {k}: ticks [{a}, {b}) overlap its move before or are empty"
                ));
            }
            if held(dl, a, a + 1) > 0 {
                return Err(format!(
                    "robot {i}, move {k}: starts at tick {a} while held"
                ));
            }
            let progress = match ring_of.get(&(i, k)) {
                Some(&g) => {
                    let first = exec.rotations[g][0];
                    if exec.moves[first.0].get(first.1) != Some(&[a, b]) {
                        return Err(format!(
                            "robot {i}, move {k}: its ring's moves do not share their ticks"
                        ));
                    }
                    (b - a) - ring_held(g, a, b)
                }
                None => (b - a) - held(dl, a, b),
            };
            if progress != c {
                return Err(format!(
                    "robot {i}, move {k}: {progress} ticks of progress in [{a}, {b}), a move takes {c}"
                ));
            }
            free_from = b;
        }
    }
    if exec.ending == crate::execute::Ending::Finished
        && let Some(i) = (0..n).find(|&i| exec.moves[i].len() != moves[i].len())
    {
        return Err(format!(
            "robot {i}: the execution says finished after {} of its {} moves",
            exec.moves[i].len(),
            moves[i].len()
        ));
    }
    let mut found = Vec::new();
    let mut grid = OverlapGrid::new(map.width(), map.height());
    for tick in 0..exec.ticks {
        let points = replay.at(tick);
        grid.overlaps(&points, agent_size, tick, &mut found);
    }
    let key = |c: &Collision| (c.tick, c.robots);
    let mut recorded: Vec<_> = exec.collisions.iter().map(key).collect();
    let mut replayed: Vec<_> = found.iter().map(key).collect();
    recorded.sort_unstable();
    replayed.sort_unstable();
    if recorded != replayed {
        return Err(format!(
            "the record claims {} collisions, the replay finds {}",
            recorded.len(),
            replayed.len()
        ));
    }
    Ok(found)
}

/// Buckets of points by the unit cell holding them (clamped to a `width x height` grid), kept
/// from one call to the next, for [`OverlapGrid::overlaps`].
#[derive(Debug, Clone)]
pub(crate) struct OverlapGrid {
    width: i64,
    height: i64,
    /// Per cell, the first point in it (`NONE`: none), then `next` links.
    head: Vec<u32>,
    next: Vec<u32>,
    cell: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl OverlapGrid {
    /// Buckets for a `width x height` map.
    pub(crate) fn new(width: u32, height: u32) -> Self {
        OverlapGrid {
            width: i64::from(width.max(1)),
            height: i64::from(height.max(1)),
            head: vec![NONE; (width.max(1) as usize) * (height.max(1) as usize)],
            next: Vec::new(),
            cell: Vec::new(),
        }
    }

    fn key(&self, x: i64, y: i64) -> usize {
        (y.clamp(0, self.height - 1) * self.width + x.clamp(0, self.width - 1)) as usize
    }

    /// Appends the pairs `(i, j)`, `i < j`, of squares of side `size` (at most 1) centred on
    /// `points` that overlap with positive area, at `tick`, in robot order. Two points closer
    /// than one cell on both axes lie in the same or adjacent buckets (clamping a point outside
    /// the grid to its border keeps that), so only those are compared.
    pub(crate) fn overlaps(
        &mut self,
        points: &[[f64; 2]],
        size: f64,
        tick: u64,
        out: &mut Vec<Collision>,
    ) {
        self.next.clear();
        self.next.resize(points.len(), NONE);
        self.cell.clear();
        for (i, p) in points.iter().enumerate() {
            let k = self.key(p[0].floor() as i64, p[1].floor() as i64);
            self.next[i] = self.head[k];
            self.head[k] = i as u32;
            self.cell.push(k as u32);
        }
        let eps = 1e-9;
        let mut pairs = Vec::new();
        let close = |p: [f64; 2], q: [f64; 2]| {
            (p[0] - q[0]).abs() < size - eps && (p[1] - q[1]).abs() < size - eps
        };
        for (i, p) in points.iter().enumerate() {
            // The point's own bucket (later points only), then four of its eight neighbours
            // (every point): each close pair is met exactly once.
            let own = self.cell[i] as usize;
            let mut j = self.head[own];
            while j != NONE {
                if (j as usize) > i && close(*p, points[j as usize]) {
                    pairs.push((i, j as usize));
                }
                j = self.next[j as usize];
            }
            let (bx, by) = (own as i64 % self.width, own as i64 / self.width);
            for (dx, dy) in [(1, -1), (1, 0), (1, 1), (0, 1)] {
                let (x, y) = (bx + dx, by + dy);
                if x < 0 || y < 0 || x >= self.width || y >= self.height {
                    continue;
                }
                let mut j = self.head[(y * self.width + x) as usize];
                while j != NONE {
                    let k = j as usize;
                    if close(*p, points[k]) {
                        pairs.push((i.min(k), i.max(k)));
                    }
                    j = self.next[k];
                }
            }
        }
        // Pairs in robot order, as the old bucket walk found them (each once).
        pairs.sort_unstable();
        for (i, j) in pairs {
            out.push(Collision {
                tick,
                robots: [i, j],
                at: [points[i], points[j]],
            });
        }
        for &k in &self.cell {
            self.head[k as usize] = NONE;
        }
    }
}
