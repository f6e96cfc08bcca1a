//! NSGA-III's conflict count (f1) assembled from remembered robot pairs.
//!
//! The stepwise count of [`super::count_conflicts_stepwise`] is, except in one corner, a sum over
//! robot pairs: its vertex conflicts count `k(k-1)/2` for `k` robots on a vertex, one per pair, and
//! it counts a swap of robots `a < b` once, unless some robot with an index below `b` stands on
//! `b`'s vertex at the step before the swap (the count looks for the swap partner through the
//! first robot recorded on that vertex). A pair's conflicts depend only on the two routes and on
//! the *difference* of the two start delays: before both delays the robots wait on their starts
//! and after both arrivals they stand on their goals, and with distinct starts and distinct goals
//! neither stretch holds a conflict. So the table keeps one entry per (pair, route pair, delay
//! difference) — 8 × 8 × 81 per pair with the defaults — and an evaluation is a few hundred table
//! reads instead of a walk over every robot and step.
//!
//! A route pair's entries for all delay differences are filled at once, the first time a genome
//! picks that route pair ([`pair_profile`]): every index pair `(x, y)` with `X[x] = Y[y]` is a
//! vertex conflict at one delay difference (both robots under way), or at a range of them (one
//! robot waiting on its start or standing on its goal), and every reversed edge a swap at one. The
//! step-by-step walk [`pair_conflicts`] is the reference it is tested against.
//!
//! The corner: when some robot `b` has both a swap with a lower robot `a` and a vertex conflict
//! with a lower robot, the pair sum may count a swap the stepwise count leaves out. Each entry
//! keeps the step of its pair's first swap, so such a swap is checked directly (is a lower robot
//! on `b`'s vertex the step before?) and taken out (a pair that swaps more than once is walked
//! from its first swap on). The tests
//! `pair_table_counts_like_the_stepwise_count` and
//! `pair_table_leaves_out_the_swaps_the_stepwise_count_leaves_out` compare the two counts, and
//! debug builds compare them on every evaluation.
//!
//! The table is used only where the pair sum is exact and the counts fit: starts pairwise
//! distinct, goals pairwise distinct, every pair's counts below 2^15, `max_delay` below 2048. A
//! route pair's row keeps only the delay differences from its first to its last with a conflict,
//! and rows are allocated as route pairs are first met, up to [`MAX_ENTRIES`] entries (32 MB);
//! after that, genomes that need a new row are counted stepwise. Instances with more than
//! [`MAX_ROUTE_PAIRS`] route pairs of robots whose routes meet are counted stepwise throughout.

use mrpp_core::mapf::graph::VertexId;

use super::Choice;

/// Most entries (8 bytes each) a table fills.
pub const MAX_ENTRIES: usize = 1 << 22;

/// Most route pairs (8 bytes each, 32 MB) a table indexes.
pub const MAX_ROUTE_PAIRS: usize = 1 << 22;

/// [`PairTable::rows`] of a route pair: entries not filled yet.
const UNKNOWN: u64 = 0;
/// The routes never conflict, whatever the delays: no entries read.
const APART: u64 = 1;
/// Offsets of rows in [`PairTable::rows`] count from here.
const FIRST_OFFSET: u64 = 2;

/// Remembered pair conflicts of one route selection.
pub struct PairTable<'a> {
    /// `routes[i]` = robot `i`'s candidate routes.
    routes: &'a [Vec<Vec<VertexId>>],
    /// Pairs `(i, j)`, `i < j`, whose candidate routes share a vertex; the others never conflict.
    blocks: Vec<Block>,
    /// Per (block, route of i, route of j): [`UNKNOWN`], [`APART`], or its row as
    /// `(FIRST_OFFSET + offset) << 24 | len << 12 | lo`: the entries of delay differences
    /// `lo..lo + len` start at `entries[offset]`, the others are zero.
    rows: Vec<u64>,
    /// A route pair's row for all delay differences, before it is trimmed.
    row: Vec<u64>,
    /// Whether a row did not fit in [`MAX_ENTRIES`] (then no row is filled any more).
    full: bool,
    /// Rows of entries, one per delay difference `d_i - d_j + max_delay`: `vertex
    /// conflicts << 32 | swaps << 16 | step of the first swap`, the step counted from the earlier of
    /// the two start delays (0 when there is no swap).
    entries: Vec<u64>,
    /// Per robot and route: its `(vertex, index)` pairs, sorted.
    indexed: Vec<Vec<Vec<(VertexId, u32)>>>,
    max_delay: u32,
    /// Per robot, for one evaluation: bit 0 = a vertex conflict with a lower robot, bit 1 = a swap
    /// with a lower robot.
    marks: Vec<u8>,
    /// For one evaluation: the pairs `(k, b)` with a vertex conflict, and the swaps
    /// `(a, b, swaps, step of the first)`.
    touching: Vec<(u32, u32)>,
    swapping: Vec<(u32, u32, u32, usize)>,
}

#[derive(Clone, Copy)]
/// One interacting pair's block of [`PairTable::rows`].
struct Block {
    i: u32,
    j: u32,
    /// Candidate routes of `j` (the block's row length in route pairs).
    routes_j: u32,
    /// Index of the block's first route pair.
    first: usize,
}

impl<'a> PairTable<'a> {
    /// The table for `routes` (`routes[i]` = robot `i`'s candidates) and start delays
    /// `0..=max_delay`, or `None` when the pair sum would not be exact or the table too large.
    pub fn new(routes: &'a [Vec<Vec<VertexId>>], max_delay: u32) -> Option<Self> {
        let n = routes.len();
        if n < 2
            || routes
                .iter()
                .any(|r| r.is_empty() || r.iter().any(Vec::is_empty))
        {
            return None;
        }
        let distinct = |pick: fn(&[VertexId]) -> VertexId| -> Option<()> {
            let mut all = Vec::with_capacity(n);
            for r in routes {
                let first = pick(&r[0]);
                if r.iter().any(|route| pick(route) != first) {
                    return None;
                }
                all.push(first);
            }
            all.sort_unstable();
            all.windows(2).all(|w| w[0] != w[1]).then_some(())
        };
        distinct(|r| r[0])?;
        distinct(|r| r[r.len() - 1])?;
        let longest = routes.iter().flatten().map(Vec::len).max()?;
        if longest + max_delay as usize >= 1 << 15 || max_delay >= 2048 {
            return None;
        }
        let indexed: Vec<Vec<Vec<(VertexId, u32)>>> = routes
            .iter()
            .map(|r| {
                r.iter()
                    .map(|route| {
                        let mut c: Vec<(VertexId, u32)> =
                            route.iter().zip(0..).map(|(&v, k)| (v, k)).collect();
                        c.sort_unstable();
                        c
                    })
                    .collect()
            })
            .collect();
        let cells: Vec<Vec<VertexId>> = routes
            .iter()
            .map(|r| {
                let mut c: Vec<VertexId> = r.iter().flatten().copied().collect();
                c.sort_unstable();
                c.dedup();
                c
            })
            .collect();
        let mut blocks = Vec::new();
        let mut pairs = 0usize;
        for i in 0..n {
            for j in i + 1..n {
                if !share_a_vertex(&cells[i], &cells[j]) {
                    continue;
                }
                blocks.push(Block {
                    i: i as u32,
                    j: j as u32,
                    routes_j: routes[j].len() as u32,
                    first: pairs,
                });
                pairs += routes[i].len() * routes[j].len();
                if pairs > MAX_ROUTE_PAIRS {
                    return None;
                }
            }
        }
        Some(PairTable {
            routes,
            blocks,
            rows: vec![UNKNOWN; pairs],
            row: vec![0; 2 * max_delay as usize + 1],
            full: false,
            entries: Vec::new(),
            indexed,
            max_delay,
            marks: vec![0; n],
            touching: Vec::new(),
            swapping: Vec::new(),
        })
    }

    /// f1 of `genome` (robot `i` takes `routes[i][genome[i].route]` after `genome[i].delay`
    /// waits), or `None` for the caller to count stepwise: a genome of another length, a delay
    /// above `max_delay`, or a full table.
    pub fn count(&mut self, genome: &[Choice]) -> Option<u64> {
        if genome.len() != self.marks.len() || genome.iter().any(|c| c.delay > self.max_delay) {
            return None;
        }
        self.marks.fill(0);
        self.touching.clear();
        self.swapping.clear();
        let mut total = 0u64;
        for n in 0..self.blocks.len() {
            let b = self.blocks[n];
            let (ci, cj) = (genome[b.i as usize], genome[b.j as usize]);
            let pair = b.first + (ci.route * b.routes_j + cj.route) as usize;
            let row = match self.rows[pair] {
                UNKNOWN => self.fill(n, ci.route, cj.route)?,
                row => row,
            };
            if row == APART {
                continue;
            }
            let k = u64::from(ci.delay + self.max_delay - cj.delay).wrapping_sub(row & 0xfff);
            if k >= (row >> 12) & 0xfff {
                continue;
            }
            let e = self.entries[((row >> 24) - FIRST_OFFSET + k) as usize];
            if e == 0 {
                continue;
            }
            let (v, s) = ((e >> 32) as u32, (e >> 16) as u32 & 0xffff);
            total += u64::from(v + s);
            if v > 0 {
                self.marks[b.j as usize] |= 1;
                self.touching.push((b.i, b.j));
            }
            if s > 0 {
                self.marks[b.j as usize] |= 2;
                let first = ci.delay.min(cj.delay) as usize + (e & 0xffff) as usize;
                self.swapping.push((b.i, b.j, s, first));
            }
        }
        // A swap of a < b at t - 1 -> t is counted stepwise only when no robot below b stands on
        // b's vertex at t - 1: take out the others.
        let routes = self.routes;
        let pos = |r: u32, t: usize| {
            let c = genome[r as usize];
            at(&routes[r as usize][c.route as usize], c.delay as usize, t)
        };
        let uncounted = |b: u32, t: usize| {
            let p = pos(b, t - 1);
            self.touching
                .iter()
                .any(|&(k, kb)| kb == b && pos(k, t - 1) == p)
        };
        for &(a, b, s, first) in &self.swapping {
            if self.marks[b as usize] != 3 {
                continue;
            }
            if s == 1 {
                total -= u64::from(uncounted(b, first));
                continue;
            }
            let (ca, cb) = (genome[a as usize], genome[b as usize]);
            let (ra, rb) = (
                &routes[a as usize][ca.route as usize],
                &routes[b as usize][cb.route as usize],
            );
            let (da, db) = (ca.delay as usize, cb.delay as usize);
            let end = (da + ra.len()).max(db + rb.len());
            for t in first..end {
                let (pa, qa) = (at(ra, da, t - 1), at(ra, da, t));
                if pa != qa && qa == at(rb, db, t - 1) && at(rb, db, t) == pa {
                    total -= u64::from(uncounted(b, t));
                }
            }
        }
        Some(total)
    }

    /// Fills the entries of block `n`'s route pair `(ri, rj)` and returns its [`PairTable::rows`]
    /// value, or `None` when the table is full.
    #[cold]
    #[inline(never)]
    fn fill(&mut self, n: usize, ri: u32, rj: u32) -> Option<u64> {
        if self.full {
            return None;
        }
        let b = &self.blocks[n];
        let (i, j, ri, rj) = (b.i as usize, b.j as usize, ri as usize, rj as usize);
        let pair = b.first + ri * b.routes_j as usize + rj;
        let met = pair_profile(
            (&self.routes[i][ri], &self.indexed[i][ri]),
            (&self.routes[j][rj], &self.indexed[j][rj]),
            self.max_delay,
            &mut self.row,
        );
        let lo = self.row.iter().position(|&e| e != 0).filter(|_| met);
        let row = match lo {
            None => APART,
            Some(lo) => {
                let hi = self.row.iter().rposition(|&e| e != 0).expect("a conflict");
                let offset = self.entries.len();
                if offset + hi + 1 - lo > MAX_ENTRIES {
                    self.full = true;
                    return None;
                }
                self.entries.extend_from_slice(&self.row[lo..=hi]);
                (FIRST_OFFSET + offset as u64) << 24 | ((hi + 1 - lo) as u64) << 12 | lo as u64
            }
        };
        self.rows[pair] = row;
        Some(row)
    }
}

/// Where a robot on `route` after `delay` waits stands at step `t` (on the last vertex once there).
#[inline]
fn at(route: &[VertexId], delay: usize, t: usize) -> VertexId {
    route[t.saturating_sub(delay).min(route.len() - 1)]
}

/// Whether two sorted vertex lists share a vertex.
fn share_a_vertex(a: &[VertexId], b: &[VertexId]) -> bool {
    let (mut x, mut y) = (0, 0);
    while x < a.len() && y < b.len() {
        match a[x].cmp(&b[y]) {
            std::cmp::Ordering::Less => x += 1,
            std::cmp::Ordering::Greater => y += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

/// Fills `out[k]` with the entry (see [`PairTable::entries`]) of routes `X` (robot i, delay `d_i`)
/// and `Y` (robot j, delay `d_j`) for every delay difference `d_i - d_j = k - max_delay`, given each
/// route in order and as its sorted `(vertex, index)` pairs; returns whether the routes share a
/// vertex (if not, `out` is left as it was). The starts must differ and the goals must differ.
///
/// With `u` the step counted from `d_i` and `δ = d_j - d_i`, robot i is at index `x` for `u` in
/// `[x, x]`, or `(-∞, 0]` for `x = 0`, or `[Lx, ∞)` for the last index, and robot j at index `y` for
/// `u - δ` in the same kind of interval; each `(x, y)` with `X[x] = Y[y]` adds the overlap of the
/// two intervals to the vertex conflicts at `δ`. A swap (`X[x-1] = Y[y]`, `X[x] = Y[y-1]`) happens
/// at `δ = x - y`, at step `max(x, y)` from the earlier delay.
pub fn pair_profile(
    (x_route, x): (&[VertexId], &[(VertexId, u32)]),
    (y_route, y): (&[VertexId], &[(VertexId, u32)]),
    max_delay: u32,
    out: &mut [u64],
) -> bool {
    const FAR: i64 = 1 << 40;
    let (lx, ly) = (x.len() as i64 - 1, y.len() as i64 - 1);
    let d = i64::from(max_delay);
    let span = |k: i64, last: i64| {
        (
            if k == 0 { -FAR } else { k },
            if k == last { FAR } else { k },
        )
    };
    let mut met = false;
    let (mut a, mut b) = (0, 0);
    while a < x.len() && b < y.len() {
        let v = x[a].0;
        match v.cmp(&y[b].0) {
            std::cmp::Ordering::Less => a += 1,
            std::cmp::Ordering::Greater => b += 1,
            std::cmp::Ordering::Equal => {
                if !met {
                    met = true;
                    out.fill(0);
                }
                let b_end = b + y[b..].iter().take_while(|e| e.0 == v).count();
                while a < x.len() && x[a].0 == v {
                    let xi = i64::from(x[a].1);
                    let (x_lo, x_hi) = span(xi, lx);
                    for &(_, yk) in &y[b..b_end] {
                        let yi = i64::from(yk);
                        let (y_lo, y_hi) = span(yi, ly);
                        // δ where the intervals overlap: y_lo + δ <= x_hi and x_lo <= y_hi + δ.
                        let from = (x_lo - y_hi).max(-d);
                        let to = (x_hi - y_lo).min(d);
                        for delta in from..=to {
                            let overlap = x_hi.min(y_hi + delta) - x_lo.max(y_lo + delta) + 1;
                            debug_assert!((1..FAR / 2).contains(&overlap), "equal starts or goals");
                            out[(d - delta) as usize] += (overlap as u64) << 32;
                        }
                        // A swap: i moves Y[y] -> Y[y - 1] while j moves Y[y - 1] -> Y[y].
                        let next = xi + 1;
                        if next <= lx
                            && yi >= 1
                            && x_route[next as usize] == y_route[yi as usize - 1]
                            && x_route[next as usize] != v
                        {
                            let delta = next - yi;
                            if (-d..=d).contains(&delta) {
                                let e = &mut out[(d - delta) as usize];
                                let when = next.max(yi) as u64;
                                let swaps = (*e >> 16) & 0xffff;
                                let first = *e & 0xffff;
                                let first = if swaps == 0 { when } else { first.min(when) };
                                *e = (*e & !0xffff_ffff) | (swaps + 1) << 16 | first;
                            }
                        }
                    }
                    a += 1;
                }
                b = b_end;
            }
        }
    }
    met
}

/// Vertex conflicts and swaps of two robots, one on route `a` after `da` waits, the other on
/// route `b` after `db` waits, each standing on its route's last vertex once there (`stay`
/// semantics), found by walking the steps: the number of steps they share a vertex, the number of
/// steps at which they have just traded vertices, and the first such step (0 when none). The
/// reference for [`pair_profile`].
#[cfg(test)]
pub fn pair_conflicts(a: &[VertexId], da: usize, b: &[VertexId], db: usize) -> (u32, u32, u32) {
    let horizon = (da + a.len()).max(db + b.len()) - 1;
    let (mut vertex, mut swaps, mut first) = (0u32, 0u32, 0u32);
    let (mut pa, mut pb) = (a[0], b[0]);
    vertex += u32::from(pa == pb);
    for t in 1..=horizon {
        let (qa, qb) = (at(a, da, t), at(b, db, t));
        vertex += u32::from(qa == qb);
        if qa != pa && qa == pb && qb == pa {
            if swaps == 0 {
                first = t as u32;
            }
            swaps += 1;
        }
        (pa, pb) = (qa, qb);
    }
    (vertex, swaps, first)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random route from `start` to `goal` through vertices `0..5` and the starts and goals of
    /// both robots (8 to 11), with repeats and waits (`len` = 1 gives a route that stays on its
    /// start, which is then its goal).
    fn route(rng: &mut ChaCha8Rng, start: VertexId, goal: VertexId, len: usize) -> Vec<VertexId> {
        if len == 1 {
            return vec![start];
        }
        let mut r = vec![start];
        r.extend((2..len).map(|_| [0, 1, 2, 3, 4, 8, 9, 10, 11][rng.random_range(0..9)]));
        r.push(goal);
        r
    }

    fn sorted(r: &[VertexId]) -> Vec<(VertexId, u32)> {
        let mut c: Vec<(VertexId, u32)> = r.iter().zip(0..).map(|(&v, k)| (v, k)).collect();
        c.sort_unstable();
        c
    }

    #[test]
    fn profile_matches_the_walk_for_every_delay_difference() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let max_delay = 6u32;
        let span = 2 * max_delay as usize + 1;
        let (mut met, mut swapped) = (0, 0);
        for _ in 0..3000 {
            // Distinct starts 8 and 9, distinct goals 10 and 11 (or the start, for a route of one
            // vertex); inner vertices at random, the other robot's start and goal among them.
            let (lx, ly) = (rng.random_range(1..8), rng.random_range(1..8));
            let x = route(&mut rng, 8, if lx == 1 { 8 } else { 10 }, lx);
            let y = route(&mut rng, 9, if ly == 1 { 9 } else { 11 }, ly);
            let mut out = vec![u64::MAX; span];
            let meet = pair_profile((&x, &sorted(&x)), (&y, &sorted(&y)), max_delay, &mut out);
            assert_eq!(meet, x.iter().any(|v| y.contains(v)), "{x:?} {y:?}");
            for (k, &entry) in out.iter().enumerate() {
                let (di, dj) = (
                    k.saturating_sub(max_delay as usize),
                    (max_delay as usize).saturating_sub(k),
                );
                let (v, s, first) = pair_conflicts(&x, di, &y, dj);
                let want = u64::from(v) << 32 | u64::from(s) << 16 | u64::from(first);
                let got = if meet { entry } else { 0 };
                assert_eq!(got, want, "{x:?} after {di}, {y:?} after {dj}");
                swapped += usize::from(s > 0);
            }
            met += usize::from(meet);
        }
        assert!(
            met > 800 && swapped > 100,
            "{met} meeting, {swapped} with swaps"
        );
    }

    #[test]
    fn tables_are_refused_where_the_pair_sum_is_not_exact() {
        let two = |a: Vec<VertexId>, b: Vec<VertexId>| vec![vec![a], vec![b]];
        assert!(PairTable::new(&two(vec![0, 1, 2], vec![3, 1, 4]), 5).is_some());
        assert!(
            PairTable::new(&two(vec![0, 1, 2], vec![0, 1, 4]), 5).is_none(),
            "same start"
        );
        assert!(
            PairTable::new(&two(vec![0, 1, 2], vec![3, 1, 2]), 5).is_none(),
            "same goal"
        );
        assert!(
            PairTable::new(&two(vec![0, 1, 2], vec![]), 5).is_none(),
            "empty route"
        );
        assert!(
            PairTable::new(&two(vec![0, 1, 2], vec![3, 1, 4]), 2048).is_none(),
            "delay differences past 12 bits"
        );
        let mixed = vec![vec![vec![0, 1, 2], vec![5, 1, 2]], vec![vec![3, 1, 4]]];
        assert!(PairTable::new(&mixed, 5).is_none(), "one robot, two starts");
        assert!(
            PairTable::new(&[vec![vec![0, 1, 2]]], 5).is_none(),
            "one robot"
        );
        let long = two((0..40_000).collect(), vec![50_000, 1]);
        assert!(PairTable::new(&long, 5).is_none(), "counts above 2^15");
    }
}
