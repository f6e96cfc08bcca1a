//! k-robust plans from any grid plan, by re-timing along its action dependency graph.
//!
//! A plan is *k-robust* (D. Atzmon, R. Stern, A. Felner, G. Wagner, R. Barták, N.-F. Zhou,
//! "Robust multi-agent path finding and executing", JAIR 67, 2020) when no robot enters a cell
//! that another robot left fewer than `k` steps earlier: then any robot may be up to `k` steps
//! late without a collision. Atzmon et al. plan for it (k-robust CBS); mrpp makes any plan
//! k-robust afterwards, so that LaCAM's and PIBT's plans (thousands of robots) get it too: every
//! move keeps its place in the plan's order of passage at every cell (the ADG's type-2
//! dependencies, [`Adg`]) and starts at the earliest step that is not before the plan's own and
//! is at least `k` steps after the move that took the previous robot out of the cell it enters,
//! and after the robot's own previous move. Moves are taken in the plan's step order, so every
//! bound is known when it is needed.
//!
//! Where the paper is silent (it plans, it does not re-time): robots rotating together in a ring
//! at one step (each entering the cell the next leaves; [`Adg::rotation_cycles`]) cannot be
//! spread apart without re-planning, so a ring keeps moving jointly (its members start at the
//! latest of their bounds, the gaps inside the ring stay 0): those cells are not k-robust, and
//! [`min_gap`] leaves them out and counts them. `k = 0` returns the plan unchanged. The re-timed
//! plan is longer: what robustness costs in makespan and sum of costs is measured in
//! `mrpp experiment execution --robust`.

use mrpp_core::mapf::plan::Plan;

use crate::adg::Adg;

/// `plan` re-timed to be `k`-robust outside rings (module doc). `plan` must be valid.
pub fn k_robust(plan: &Plan, k: u32) -> Plan {
    if k == 0 {
        return plan.clone();
    }
    let adg = Adg::new(plan);
    let rings = adg.rotation_cycles();
    let mut ring_of: Vec<Vec<usize>> = adg
        .moves
        .iter()
        .map(|m| vec![usize::MAX; m.len()])
        .collect();
    for (g, members) in rings.iter().enumerate() {
        for &(i, m) in members {
            ring_of[i][m] = g;
        }
    }
    let in_ring = |i: usize, m: usize| Some(ring_of[i][m]).filter(|&g| g != usize::MAX);
    let mut start: Vec<Vec<Option<u32>>> = adg.moves.iter().map(|m| vec![None; m.len()]).collect();
    // Every move, in the plan's step order.
    let mut order: Vec<(u32, usize, usize)> = adg
        .moves
        .iter()
        .enumerate()
        .flat_map(|(i, ms)| ms.iter().enumerate().map(move |(m, mv)| (mv.step, i, m)))
        .collect();
    order.sort_unstable();
    // The earliest start of (i, m) once its bounds outside its ring are known, else `None`.
    let bound = |start: &[Vec<Option<u32>>], i: usize, m: usize| -> Option<u32> {
        let mut t = adg.moves[i][m].step;
        if m > 0 {
            t = t.max(start[i][m - 1]? + 1);
        }
        let ring = in_ring(i, m);
        for &(j, n) in &adg.deps[i][m] {
            if ring.is_some() && in_ring(j, n) == ring {
                continue;
            }
            t = t.max(start[j][n]? + k);
        }
        Some(t)
    };
    let mut at = 0;
    while at < order.len() {
        // The moves of one plan step; within a step a move may wait on a robot leaving the
        // cell it enters at the same step (following), so repeat until all are placed.
        let step = order[at].0;
        let end = order[at..]
            .iter()
            .position(|o| o.0 != step)
            .map_or(order.len(), |p| at + p);
        let mut pending: Vec<(usize, usize)> = order[at..end].iter().map(|o| (o.1, o.2)).collect();
        while !pending.is_empty() {
            let before = pending.len();
            let mut placed = Vec::new();
            for &(i, m) in &pending {
                if start[i][m].is_some() {
                    continue;
                }
                match in_ring(i, m) {
                    None => {
                        if let Some(t) = bound(&start, i, m) {
                            placed.push((i, m, t));
                            start[i][m] = Some(t);
                        }
                    }
                    Some(g) => {
                        let bounds: Option<Vec<u32>> =
                            rings[g].iter().map(|&(j, n)| bound(&start, j, n)).collect();
                        if let Some(b) = bounds {
                            let t = b.into_iter().max().unwrap_or(step);
                            for &(j, n) in &rings[g] {
                                start[j][n] = Some(t);
                                placed.push((j, n, t));
                            }
                        }
                    }
                }
            }
            pending.retain(|&(i, m)| start[i][m].is_none());
            if pending.len() == before {
                // Cannot happen for a valid plan (its own timing satisfies every bound); keep
                // the plan's step rather than loop.
                for &(i, m) in &pending {
                    start[i][m] = Some(adg.moves[i][m].step.max(bound_lenient(&start, &adg, i, m)));
                }
                pending.clear();
            }
        }
        at = end;
    }
    let paths = plan
        .paths
        .iter()
        .enumerate()
        .map(|(i, path)| {
            let Some(&first) = path.first() else {
                return Vec::new();
            };
            let mut out = vec![first];
            for (m, mv) in adg.moves[i].iter().enumerate() {
                let s = start[i][m].unwrap_or(mv.step) as usize;
                while out.len() <= s {
                    out.push(mv.from);
                }
                out.push(mv.to);
            }
            out
        })
        .collect();
    Plan { paths }
}

/// The bound of a move from what is known (used only if a plan is not valid).
fn bound_lenient(start: &[Vec<Option<u32>>], adg: &Adg, i: usize, m: usize) -> u32 {
    let own = if m > 0 {
        start[i][m - 1].map_or(0, |t| t + 1)
    } else {
        0
    };
    adg.deps[i][m]
        .iter()
        .filter_map(|&(j, n)| start[j][n])
        .fold(own, u32::max)
}

/// The smallest gap in `plan`, over every cell, between one robot's last step on it and the
/// next robot's first step on it, minus one (so a plan is k-robust iff the gap is at least `k`;
/// following gives 0), leaving out the entries of robots moving in a ring; and how many such
/// ring entries there are. `None` when no cell is visited by two robots. Computed from the
/// paths alone (not from the ADG), as a check of [`k_robust`].
pub fn min_gap(plan: &Plan) -> (Option<u32>, usize) {
    use std::collections::HashMap;
    // Per cell: (first step, last step, robot) of every stay.
    let mut stays: HashMap<u32, Vec<(usize, usize, usize)>> = HashMap::new();
    for (i, path) in plan.paths.iter().enumerate() {
        let mut t = 0;
        while t < path.len() {
            let v = path[t];
            let mut e = t;
            while e + 1 < path.len() && path[e + 1] == v {
                e += 1;
            }
            stays.entry(v).or_default().push((t, e, i));
            t = e + 1;
        }
    }
    // Ring entries: at step t robot i enters the cell robot j leaves, j enters the one the next
    // leaves, ..., back to i.
    let at = |i: usize, t: usize| plan.paths[i].get(t).or(plan.paths[i].last()).copied();
    let mut occupant: HashMap<(u32, usize), usize> = HashMap::new();
    for (i, path) in plan.paths.iter().enumerate() {
        for (t, &v) in path.iter().enumerate() {
            occupant.insert((v, t), i);
        }
    }
    let in_ring = |i: usize, t: usize| -> bool {
        // Robot i enters at step t (from t - 1): follow who left the cell entered.
        let mut who = i;
        for _ in 0..plan.paths.len() {
            let Some(to) = at(who, t) else { return false };
            let Some(&prev) = occupant.get(&(to, t - 1)) else {
                return false;
            };
            if prev == who || at(prev, t) == Some(to) {
                return false;
            }
            if prev == i {
                return true;
            }
            who = prev;
        }
        false
    };
    let (mut gap, mut rings) = (None::<u32>, 0);
    for list in stays.values_mut() {
        list.sort_unstable();
        for w in list.windows(2) {
            let ((_, last, a), (first, _, b)) = (w[0], w[1]);
            if a == b {
                continue;
            }
            if first > 0 && in_ring(b, first) {
                rings += 1;
                continue;
            }
            let g = first.saturating_sub(last + 1) as u32;
            gap = Some(gap.map_or(g, |x| x.min(g)));
        }
    }
    (gap, rings)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_follower_falls_back_k_steps() {
        // A corridor 0-1-2-3: robot 0 goes 1 -> 3, robot 1 follows from 0 to 2.
        let plan = Plan {
            paths: vec![vec![1, 2, 3], vec![0, 1, 2]],
        };
        assert_eq!(min_gap(&plan), (Some(0), 0));
        let two = k_robust(&plan, 2);
        assert_eq!(two.paths[0], plan.paths[0]);
        // Robot 1 enters 1 two steps after robot 0 left it, then 2 likewise.
        assert_eq!(two.paths[1], vec![0, 0, 0, 1, 2]);
        assert_eq!(min_gap(&two), (Some(2), 0));
        assert_eq!(k_robust(&plan, 0), plan);
    }

    #[test]
    fn a_ring_keeps_moving_jointly() {
        // Four robots rotate round the square 0-1-3-2 (cells of a 2 x 2 grid) in one step.
        let plan = Plan {
            paths: vec![vec![0, 1], vec![1, 3], vec![3, 2], vec![2, 0]],
        };
        let (_, rings) = min_gap(&plan);
        assert_eq!(rings, 4);
        assert_eq!(k_robust(&plan, 3), plan);
    }
}
