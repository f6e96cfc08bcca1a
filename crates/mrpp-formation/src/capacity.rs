//! Whether the formation fits the corridors at all: a plan has a finite cost exactly when the
//! robots can be routed with every corridor within capacity, and that is a maximum-flow question.
//!
//! A corridor `e` carries at most `hold_e` robots, the largest count `r ≤ R` with a finite cost
//! `c_e(r)` (costs never fall, so the finite counts are `0..=hold_e`): under the `hard` model its
//! capacity ([`crate::cost::capacity`]), under `lanes` and `waves` all `R`. A valid plan with a
//! finite `c_max` puts `n_e ≤ hold_e` robots on every corridor, all one way, so it is an integer
//! flow of value `R` from `Q_ini` to `Q_goal` with capacities `hold_e`. Conversely, an integer
//! flow of value `R` whose arcs form no cycle splits into `R` simple paths that cross every
//! corridor one way, and their union has no cycle, so they wait for each other in no circle: a
//! valid plan with a finite cost ([`within_capacity`] builds it). Hence: **a plan with a finite
//! cost exists if and only if the maximum flow is at least `R`**, and when it is not, a minimum
//! cut names the corridors that hold the formation back ([`Bottleneck`]).
//!
//! Only the edge [`crate::roadmap::Roadmap::edge_between`] returns for a pair of vertices takes
//! flow (a plan's step between two vertices is judged on that edge), and loops take none.

use std::collections::VecDeque;

use crate::problem::FormationProblem;

/// Corridors that separate `Q_ini` from `Q_goal` and together hold fewer robots than the
/// formation has: no plan with a finite cost exists.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bottleneck {
    /// The corridors of a minimum cut, each as `(from, to, holds)`: `from` on `Q_ini`'s side,
    /// and the most robots that may cross it together at a finite cost. Empty when `Q_goal`
    /// cannot be reached at all.
    pub corridors: Vec<(u32, u32, usize)>,
    /// The most robots that can travel from `Q_ini` to `Q_goal` within capacity (the sum of
    /// `holds` over `corridors`).
    pub holds: usize,
    /// The formation's robots (more than `holds`).
    pub robots: usize,
}

impl std::fmt::Display for Bottleneck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.corridors.is_empty() {
            return write!(f, "Q_goal cannot be reached from Q_ini on the roadmap");
        }
        let list: Vec<String> = self
            .corridors
            .iter()
            .map(|&(a, b, h)| format!("{a}-{b} (holds {h})"))
            .collect();
        let (s, them) = if list.len() == 1 {
            ("", "which holds")
        } else {
            ("s", "which hold")
        };
        write!(
            f,
            "the formation is over capacity: every route from Q_ini to Q_goal crosses \
             corridor{s} {}, {them} {} robot{} in all, not the formation's {}, so every plan \
             has an infinite cost",
            list.join(", "),
            self.holds,
            if self.holds == 1 { "" } else { "s" },
            self.robots
        )
    }
}

/// The most robots that may cross edge `e` together at a finite cost (at most R).
fn hold(p: &FormationProblem, e: u32) -> usize {
    (1..=p.robots())
        .take_while(|&r| p.edge_cost(e, r).is_finite())
        .last()
        .unwrap_or(0)
}

/// A plan with a finite cost (every corridor within capacity; valid by the validator's rules),
/// or the [`Bottleneck`] that proves none exists. O(R · (V + E)) time (one breadth-first search
/// per robot).
///
/// # Errors
/// The bottleneck when the maximum flow from `Q_ini` to `Q_goal` is below the robot count.
pub fn within_capacity(p: &FormationProblem) -> Result<Vec<Vec<u32>>, Bottleneck> {
    let r = p.roadmap();
    let robots = p.robots();
    let (s, g) = (p.start(), p.goal());
    if s == g {
        return Ok(vec![vec![s]; robots]);
    }
    let ne = r.edges.len();
    // Edges that take flow: the one `edge_between` picks for its pair, no loops.
    let cap: Vec<i64> = (0..ne as u32)
        .map(|e| {
            let edge = &r.edges[e as usize];
            if edge.u != edge.v && r.edge_between(edge.u, edge.v) == Some(e) {
                hold(p, e) as i64
            } else {
                0
            }
        })
        .collect();
    // Signed flow per edge, positive from `u` to `v`.
    let mut x = vec![0i64; ne];
    let nv = r.num_vertices();
    let residual = |x: &[i64], e: u32, from: u32| -> i64 {
        let e = e as usize;
        if r.edges[e].u == from {
            cap[e] - x[e]
        } else {
            cap[e] + x[e]
        }
    };
    let mut via: Vec<Option<(u32, u32)>> = vec![None; nv];
    let mut reached = vec![false; nv];
    let mut flow = 0;
    while flow < robots {
        // Breadth-first search for an augmenting path (unit augmentations: R is at most 64).
        reached.iter_mut().for_each(|b| *b = false);
        reached[s as usize] = true;
        let mut queue = VecDeque::from([s]);
        while let Some(a) = queue.pop_front() {
            for &(b, e) in r.neighbors(a) {
                if !reached[b as usize] && residual(&x, e, a) > 0 {
                    reached[b as usize] = true;
                    via[b as usize] = Some((a, e));
                    queue.push_back(b);
                }
            }
        }
        if !reached[g as usize] {
            // A minimum cut: the saturated corridors leaving the vertices `s` still reaches.
            let mut corridors: Vec<(u32, u32, usize)> = Vec::new();
            for (e, edge) in r.edges.iter().enumerate() {
                if cap[e] == 0 {
                    continue;
                }
                let (iu, iv) = (reached[edge.u as usize], reached[edge.v as usize]);
                if iu != iv {
                    let (a, b) = if iu {
                        (edge.u, edge.v)
                    } else {
                        (edge.v, edge.u)
                    };
                    corridors.push((a, b, cap[e] as usize));
                }
            }
            corridors.sort_unstable();
            return Err(Bottleneck {
                holds: corridors.iter().map(|c| c.2).sum(),
                corridors,
                robots,
            });
        }
        let mut v = g;
        while v != s {
            let (a, e) = via[v as usize].expect("on the search tree");
            x[e as usize] += if r.edges[e as usize].u == a { 1 } else { -1 };
            v = a;
        }
        flow += 1;
    }
    Ok(decompose(p, &mut x, robots))
}

/// `robots` simple paths from `Q_ini` to `Q_goal` out of the flow `x` (of that value): the
/// flow's cycles are cancelled first (the value is unchanged), so the paths' union has no cycle
/// (no circular wait), and each path walks from `Q_ini` along arcs with flow, taking one unit.
fn decompose(p: &FormationProblem, x: &mut [i64], robots: usize) -> Vec<Vec<u32>> {
    let r = p.roadmap();
    let (s, g) = (p.start(), p.goal());
    while let Some(cycle) = find_cycle(p, x) {
        for (a, e) in cycle {
            take(p, x, a, e);
        }
    }
    let mut paths = Vec::with_capacity(robots);
    while paths.len() < robots {
        let mut path = vec![s];
        let mut a = s;
        while a != g {
            let (b, e) = out_arc(p, x, a)
                .expect("flow conservation: an arc with flow leaves every inner vertex");
            take(p, x, a, e);
            path.push(b);
            a = b;
        }
        debug_assert!(
            path.len() <= r.num_vertices(),
            "an acyclic flow gives simple paths"
        );
        paths.push(path);
    }
    paths
}

/// The first arc with flow out of `a`: `(next vertex, edge)`.
fn out_arc(p: &FormationProblem, x: &[i64], a: u32) -> Option<(u32, u32)> {
    out_arc_from(p, x, a, 0).map(|(b, e, _)| (b, e))
}

/// The first arc with flow out of `a` from its `k`-th neighbour on: `(next vertex, edge, index
/// of that neighbour)`.
fn out_arc_from(p: &FormationProblem, x: &[i64], a: u32, k: usize) -> Option<(u32, u32, usize)> {
    let r = p.roadmap();
    r.neighbors(a)
        .iter()
        .enumerate()
        .skip(k)
        .find(|&(_, &(_, e))| {
            let edge = &r.edges[e as usize];
            (edge.u == a && x[e as usize] > 0) || (edge.v == a && x[e as usize] < 0)
        })
        .map(|(i, &(b, e))| (b, e, i))
}

/// One unit less flow on the arc of edge `e` out of `a`.
fn take(p: &FormationProblem, x: &mut [i64], a: u32, e: u32) {
    x[e as usize] += if p.roadmap().edges[e as usize].u == a {
        -1
    } else {
        1
    };
}

/// A directed cycle of arcs with flow, as `(tail, edge)` arcs, by depth-first search.
fn find_cycle(p: &FormationProblem, x: &[i64]) -> Option<Vec<(u32, u32)>> {
    let nv = p.roadmap().num_vertices();
    // 0: unvisited, 1: on the stack, 2: done.
    let mut state = vec![0u8; nv];
    // The stack: (vertex, next neighbour index to try, edge it was entered by).
    let mut stack: Vec<(u32, usize, u32)> = Vec::new();
    for root in 0..nv as u32 {
        if state[root as usize] != 0 {
            continue;
        }
        state[root as usize] = 1;
        stack.push((root, 0, u32::MAX));
        while let Some(&(a, k, _)) = stack.last() {
            match out_arc_from(p, x, a, k) {
                None => {
                    state[a as usize] = 2;
                    stack.pop();
                }
                Some((b, e, i)) => {
                    stack.last_mut().expect("not empty").1 = i + 1;
                    match state[b as usize] {
                        0 => {
                            state[b as usize] = 1;
                            stack.push((b, 0, e));
                        }
                        1 => {
                            // b is on the stack: the arcs from b up to a, then a → b.
                            let from = stack.iter().position(|f| f.0 == b).expect("on the stack");
                            let mut cycle: Vec<(u32, u32)> =
                                stack[from..].windows(2).map(|w| (w[0].0, w[1].2)).collect();
                            cycle.push((a, e));
                            return Some(cycle);
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::CostModel;
    use crate::problem::tests::diamond;
    use crate::roadmap::Roadmap;
    use mrpp_core::Problem;
    use std::sync::Arc;

    #[test]
    fn the_diamond_fits_three_and_not_five_under_the_hard_model() {
        // Through A holds 1, through B holds 3: 4 robots at most.
        let p = diamond(CostModel::Hard);
        let paths = within_capacity(&p).unwrap();
        let m = p
            .validate(&crate::FormationPlan {
                paths: paths.clone(),
            })
            .unwrap();
        assert!(m.c_max.is_finite());
        let r = p.roadmap_arc().clone();
        let five = FormationProblem::new(r.clone(), 5, 0, 3, CostModel::Hard, 0.4).unwrap();
        let b = within_capacity(&five).unwrap_err();
        assert_eq!(b.holds, 4);
        assert_eq!(b.corridors, vec![(0, 1, 1), (0, 2, 3)]);
        let text = b.to_string();
        assert!(
            text.contains("corridors 0-1 (holds 1), 0-2 (holds 3)"),
            "{text}"
        );
        // Lanes: any number fits.
        let lanes = FormationProblem::new(r, 5, 0, 3, CostModel::default(), 0.4).unwrap();
        assert_eq!(within_capacity(&lanes).unwrap().len(), 5);
    }

    /// Random graphs and capacities: the flow's plan is always valid with a finite cost, and
    /// when there is a bottleneck, no multiset of simple paths (the exhaustive search) has a
    /// finite cost either.
    #[test]
    fn flow_agrees_with_the_exhaustive_search() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(27);
        let (mut fits, mut blocked) = (0, 0);
        for _ in 0..300 {
            let n = rng.random_range(3..8u32);
            let pts: Vec<[f64; 2]> = (0..n).map(|i| [f64::from(i), 0.0]).collect();
            let mut segs = Vec::new();
            for a in 0..n {
                for b in a + 1..n {
                    if rng.random::<f64>() < 0.45 {
                        // Clearance 0.5 holds 1 robot of radius 0.4, 1.5 holds 3.
                        segs.push((a, b, [0.5, 1.0, 1.5][rng.random_range(0..3)]));
                    }
                }
            }
            let robots = rng.random_range(1..5);
            let p = FormationProblem::new(
                Arc::new(Roadmap::from_segments(pts, &segs)),
                robots,
                0,
                n - 1,
                CostModel::Hard,
                0.4,
            )
            .unwrap();
            let (_, best) = crate::exact::brute_force(&p, 10_000).unwrap();
            match within_capacity(&p) {
                Ok(paths) => {
                    fits += 1;
                    let m = p.validate(&crate::FormationPlan { paths }).unwrap();
                    assert!(m.c_max.is_finite() && best.is_finite());
                }
                Err(b) => {
                    blocked += 1;
                    assert!(b.holds < robots);
                    assert!(best.is_infinite(), "{b} but a plan costs {best}");
                }
            }
        }
        assert!(fits > 50 && blocked > 50, "{fits} fit, {blocked} blocked");
    }
}
