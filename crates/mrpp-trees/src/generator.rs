//! Random tree workspaces and robots: the paper's MST generator (Algorithm 2) and its robot
//! placement (§7.1).
//!
//! Algorithm 2 `MSTGenerator(root, seed, b)` draws `n ← random(0, b)`, and for each of the `n`
//! children creates a node, recurses on it with `seed − 1`, then links it to `root`. The paper
//! leaves open, and we choose:
//! - **The end of the recursion.** The pseudocode never tests `seed`, so as printed it only ends by
//!   luck. We stop at `seed = 0`: a node reached with seed 0 gets no children, so a tree made with
//!   seed `d` has depth at most `d` ("seed" is the depth budget, 4–10 in the paper's experiments).
//! - **`random(0, b)`.** Read as Java's `nextInt(b)` (the authors' code base is Java), i.e. `n`
//!   uniform in `0..b` (0 to b − 1 children), so a non-root node has degree at most `b` — the
//!   "maximum branching factor". [`ChildCount::Inclusive`] draws from `0..=b` instead. With the
//!   default, trees are small (mean 1.5 children per node for b = 4; over depth budgets 4–10,
//!   95 nodes on average, at most about 1000), closer to the paper's PSW average of 18.6 steps
//!   per problem; the inclusive reading gives 838.7 nodes on average (test
//!   `node_counts_of_the_two_readings`) and up to about 8600.
//! - **Ids and adjacency order.** Nodes are numbered in creation order (pre-order, root = 0) and
//!   edges are listed in the order `addNeighbor` runs (after the child's own subtree), so every
//!   node's neighbour list is its children in creation order followed by its parent, as in the
//!   pseudocode. The adjacency order fixes PSW's DFS priorities.
//! - **Degenerate trees.** The root may draw 0 children (a single node) or the tree may have too few
//!   leaves for a problem (|R| = #leaves − 1 would be 0). [`generate_problem`] draws trees from
//!   the same random stream until one has at least [`ProblemSpec::min_leaves`] leaves (default 2)
//!   and at least 3 nodes; the paper does not say how it handled such draws.
//!
//! Robots (§7.1: "each having a unique, random starting node and destination node"): starts are
//! distinct uniform nodes, goals are distinct uniform nodes, and a robot's goal differs from its
//! own start (the authors' generator also draws the destination until it differs from the source;
//! a robot born on its goal would be solved at t = 0). The count is a number or a multiple of the
//! leaf count (floor, §7.4), capped at |N| − 2 "because at least two nodes must be free to enable
//! a swap", and at least 1.
//!
//! Everything is drawn from one `ChaCha8Rng` seeded with the problem seed: first the tree, then
//! the robots, so a (depth, seed) pair gives the same tree whatever the robot count.
//!
//! **The authors' distribution** ([`generate_authors_problem`]). The authors' public code (Java,
//! `RobotsAndGraph.createRandomGraph` and `RobotsAndGraphList`) draws problems otherwise than
//! the paper's text, and its problems have the sizes the paper reports (about 15 nodes and 4
//! robots). mrpp offers it as a second distribution, written from that code's behaviour:
//! - a *node budget* `n` per problem, uniform in 4–10 (`baseSeed` 4 + `nextInt(7)`);
//! - the tree grows from node 0: a node with budget `n` draws `k` uniform in 1–3 (if `k > n`,
//!   `k` uniform in 1–`n` instead) and gets `k` children, each grown with budget `n − k` (a
//!   child with budget 0 is not made) — [`authors_tree`]; numbering and adjacency order as for
//!   Algorithm 2 above (the authors' code rebuilds its adjacency through a spanning-tree pass,
//!   whose order is not reproduced);
//! - robots: with `L` leaves (non-root nodes of degree 1, as the code counts them), `|R|`
//!   uniform in 2–`L − 1` when `L > 2`, else `L − 1`; a problem with fewer than 2 robots is
//!   drawn again (the code keeps only problems with more than one robot); starts and goals as
//!   above. The code draws from an unseeded `java.util.Random`; mrpp draws from the problem seed.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::instance::TreeInstance;
use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;

/// How `random(0, b)` of Algorithm 2 is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ChildCount {
    /// `0..b` (Java's `nextInt(b)`): at most b − 1 children, degree at most b. Default.
    #[default]
    Exclusive,
    /// `0..=b`: at most b children.
    Inclusive,
}

/// Trees larger than this are refused (the inclusive reading grows like 2^depth).
pub const MAX_TREE_NODES: usize = 1 << 22;

/// Algorithm 2: a random tree grown from node 0 with depth budget `depth` ("seed") and maximum
/// branching factor `branching` (b). Returns the node count and the edges in `addNeighbor` order.
/// Iterative, with the recursion's exact order of random draws.
pub fn mst_generator(
    depth: u32,
    branching: u32,
    children: ChildCount,
    rng: &mut ChaCha8Rng,
) -> Result<(usize, Vec<(VertexId, VertexId)>)> {
    let draw = |rng: &mut ChaCha8Rng, seed: u32| -> u32 {
        if seed == 0 {
            return 0;
        }
        match children {
            ChildCount::Exclusive if branching == 0 => 0,
            ChildCount::Exclusive => rng.random_range(0..branching),
            ChildCount::Inclusive => rng.random_range(0..=branching),
        }
    };
    struct Frame {
        node: VertexId,
        seed: u32,
        left: u32,
    }
    let mut nodes = 1usize;
    let mut edges = Vec::new();
    let mut stack = vec![Frame {
        node: 0,
        seed: depth,
        left: draw(rng, depth),
    }];
    while let Some(top) = stack.last_mut() {
        if top.left > 0 {
            top.left -= 1;
            let child_seed = top.seed - 1;
            if nodes >= MAX_TREE_NODES {
                return Err(Error::Param(format!(
                    "the tree grows past {MAX_TREE_NODES} nodes; lower the depth or the branching"
                )));
            }
            let child = nodes as VertexId;
            nodes += 1;
            let left = draw(rng, child_seed);
            stack.push(Frame {
                node: child,
                seed: child_seed,
                left,
            });
        } else {
            let done = stack.pop().expect("non-empty");
            if let Some(parent) = stack.last() {
                edges.push((parent.node, done.node));
            }
        }
    }
    Ok((nodes, edges))
}

/// How many robots a problem gets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RobotCount {
    Exactly(usize),
    /// ⌊f · #leaves⌋ (the paper's leaf multipliers 0.25, 0.5, 1.0, 1.5).
    PerLeaf(f64),
    /// #leaves − 1: the most robots for which PSW is complete (§7.2, §7.3).
    LeavesMinusOne,
}

impl RobotCount {
    /// The count for a tree with `leaves` leaves and `nodes` nodes: at most `nodes − 2`, at least 1.
    pub fn resolve(&self, leaves: usize, nodes: usize) -> usize {
        let want = match *self {
            RobotCount::Exactly(k) => k,
            RobotCount::PerLeaf(f) => (f * leaves as f64).floor().max(0.0) as usize,
            RobotCount::LeavesMinusOne => leaves.saturating_sub(1),
        };
        want.min(nodes.saturating_sub(2)).max(1)
    }
}

/// Everything that defines a random tree problem except its seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProblemSpec {
    /// Algorithm 2's seed: the depth budget (paper: 4–10).
    pub depth: u32,
    /// Maximum branching factor b (paper: 4).
    pub branching: u32,
    pub children: ChildCount,
    pub robots: RobotCount,
    /// Trees with fewer leaves are redrawn (at least 2 so that #leaves − 1 ≥ 1).
    pub min_leaves: usize,
}

impl ProblemSpec {
    /// The paper's settings (b = 4) for a depth budget and a robot count.
    pub fn paper(depth: u32, robots: RobotCount) -> Self {
        ProblemSpec {
            depth,
            branching: 4,
            children: ChildCount::Exclusive,
            robots,
            min_leaves: 2,
        }
    }
}

/// Redraws allowed before [`generate_problem`] gives up on a spec (e.g. too many leaves asked of
/// a shallow tree).
const MAX_REDRAWS: usize = 10_000;

/// A random tree (Algorithm 2) with its robots, fully determined by `spec` and `seed`.
pub fn generate_problem(spec: &ProblemSpec, seed: u64) -> Result<TreeInstance> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for _ in 0..MAX_REDRAWS {
        let (n, edges) = mst_generator(spec.depth, spec.branching, spec.children, &mut rng)?;
        let graph = mrpp_core::mapf::graph::Graph::from_edges(n, &edges);
        let leaves = crate::instance::count_leaves(&graph);
        if n < 3 || leaves < spec.min_leaves {
            continue;
        }
        let count = spec.robots.resolve(leaves, n);
        let instance = place_robots(n, count, &mut rng);
        return TreeInstance::new(n, edges, instance).map_err(Error::Param);
    }
    Err(Error::Param(format!(
        "no tree of depth {} and branching {} with at least {} leaves in {MAX_REDRAWS} draws",
        spec.depth, spec.branching, spec.min_leaves
    )))
}

/// A tree of the authors' code for node budget `budget` (module doc, "The authors'
/// distribution"): the node count and the edges, children in creation order, each edge listed
/// after its child's subtree. At most `3^budget` nodes; budgets above 12 are refused.
///
/// # Errors
/// A budget of 0 or above 12.
pub fn authors_tree(
    budget: u32,
    rng: &mut ChaCha8Rng,
) -> Result<(usize, Vec<(VertexId, VertexId)>)> {
    if !(1..=12).contains(&budget) {
        return Err(Error::Param(format!(
            "node budget {budget}: expected 1 to 12"
        )));
    }
    fn grow(
        budget: u32,
        rng: &mut ChaCha8Rng,
        n: &mut usize,
        edges: &mut Vec<(VertexId, VertexId)>,
    ) -> VertexId {
        let me = *n as VertexId;
        *n += 1;
        let mut k = rng.random_range(1..=3u32);
        if k > budget {
            k = rng.random_range(1..=budget);
        }
        for _ in 0..k {
            if budget > k {
                let child = grow(budget - k, rng, n, edges);
                edges.push((me, child));
            }
        }
        me
    }
    let (mut n, mut edges) = (0usize, Vec::new());
    grow(budget, rng, &mut n, &mut edges);
    Ok((n, edges))
}

/// A problem of the authors' distribution (module doc): the node budget uniform in `budgets`,
/// [`authors_tree`], and `robots` robots — [`RobotCount::LeavesMinusOne`] reads as the authors'
/// count, uniform in 2–#leaves − 1, and then problems with fewer than 2 robots are redrawn; other
/// counts as [`RobotCount::resolve`] gives them (trees with fewer than 2 leaves or 3 nodes are
/// redrawn). Returns the budget drawn and the problem, fully determined by `seed`.
///
/// # Errors
/// A budget range outside 1–12, or no fitting tree in 10,000 draws.
pub fn generate_authors_problem(
    budgets: std::ops::RangeInclusive<u32>,
    robots: RobotCount,
    seed: u64,
) -> Result<(u32, TreeInstance)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for _ in 0..MAX_REDRAWS {
        let budget = rng.random_range(budgets.clone());
        let (n, edges) = authors_tree(budget, &mut rng)?;
        let graph = mrpp_core::mapf::graph::Graph::from_edges(n, &edges);
        let leaves = crate::instance::count_leaves(&graph);
        if n < 3 || leaves < 2 {
            continue;
        }
        let count = match robots {
            RobotCount::LeavesMinusOne if leaves > 2 => rng.random_range(2..=leaves - 1),
            RobotCount::LeavesMinusOne => leaves - 1,
            other => other.resolve(leaves, n),
        };
        if robots == RobotCount::LeavesMinusOne && count < 2 {
            continue;
        }
        let instance = place_robots(n, count, &mut rng);
        return Ok((
            budget,
            TreeInstance::new(n, edges, instance).map_err(Error::Param)?,
        ));
    }
    Err(Error::Param(format!(
        "no tree of node budget {}-{} with a problem in {MAX_REDRAWS} draws",
        budgets.start(),
        budgets.end()
    )))
}

/// `count` robots on `n` nodes: distinct uniform starts, distinct uniform goals, each goal
/// different from its robot's start. Needs `1 <= count <= n − 2` (so a goal is always left).
pub fn place_robots(n: usize, count: usize, rng: &mut ChaCha8Rng) -> Instance {
    assert!(count >= 1 && count + 2 <= n, "{count} robots on {n} nodes");
    let mut pool: Vec<VertexId> = (0..n as VertexId).collect();
    let mut starts = Vec::with_capacity(count);
    for i in 0..count {
        // Partial Fisher–Yates: pool[i..] holds the unused nodes.
        let j = rng.random_range(i as u32..n as u32) as usize;
        pool.swap(i, j);
        starts.push(pool[i]);
    }
    let mut free: Vec<VertexId> = (0..n as VertexId).collect();
    let mut goals = Vec::with_capacity(count);
    for &s in &starts {
        loop {
            let j = rng.random_range(0..free.len() as u32) as usize;
            if free[j] != s {
                goals.push(free.swap_remove(j));
                break;
            }
        }
    }
    Instance::new(starts, goals).expect("distinct by construction")
}

/// The tree of Algorithm 2 for a depth budget, a branching factor and a seed (the first tree
/// [`generate_problem`] draws for that seed).
pub fn generate_tree(
    depth: u32,
    branching: u32,
    children: ChildCount,
    seed: u64,
) -> Result<(usize, Vec<(VertexId, VertexId)>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    mst_generator(depth, branching, children, &mut rng)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rooted::RootedTree;

    /// The two readings of Algorithm 2's `random(0, b)` on the problems of PSW's
    /// `paper_sizes` release check (b = 4, depth budgets 4 + seed mod 7, |R| = #leaves − 1,
    /// seeds 0–199): the mean node count of each, printed for docs/reproduction/gp-trees.md
    /// ("Deviations"; `-- --nocapture` shows it). The inclusive reading (up to b children)
    /// grows far larger trees.
    #[test]
    fn node_counts_of_the_two_readings() {
        let mean = |children| {
            let total: usize = (0..200u64)
                .map(|seed| {
                    let spec = ProblemSpec {
                        children,
                        ..ProblemSpec::paper(4 + (seed % 7) as u32, RobotCount::LeavesMinusOne)
                    };
                    generate_problem(&spec, seed).unwrap().num_nodes()
                })
                .sum();
            total as f64 / 200.0
        };
        let (exclusive, inclusive) = (mean(ChildCount::Exclusive), mean(ChildCount::Inclusive));
        println!(
            "random(0, b) read as 0..b-1 (exclusive): mean nodes {exclusive:.1} over 200 problems"
        );
        println!(
            "random(0, b) read as 0..b (inclusive): mean nodes {inclusive:.1} over 200 problems"
        );
        assert!(inclusive > 4.0 * exclusive, "{inclusive} vs {exclusive}");
    }

    #[test]
    fn same_seed_same_tree_and_depth_bound() {
        for seed in 0..50 {
            for depth in [0, 1, 4, 7] {
                let a = generate_tree(depth, 4, ChildCount::Exclusive, seed).unwrap();
                let b = generate_tree(depth, 4, ChildCount::Exclusive, seed).unwrap();
                assert_eq!(a, b);
                let g = mrpp_core::mapf::graph::Graph::from_edges(a.0, &a.1);
                let t = RootedTree::new(&g, 0).unwrap();
                for v in 0..a.0 as VertexId {
                    assert!(t.depth(v) <= depth);
                    // At most b - 1 children, so degree at most b.
                    assert!(t.children(v).len() <= 3);
                }
                // Pre-order ids: every child has a larger id than its parent.
                assert!(a.1.iter().all(|&(p, c)| p < c));
            }
        }
        assert_eq!(generate_tree(0, 4, ChildCount::Exclusive, 3).unwrap().0, 1);
    }

    #[test]
    fn pinned_stream() {
        // A change here silently changes every generated problem (and every experiment).
        let (n, edges) = generate_tree(6, 4, ChildCount::Exclusive, 1).unwrap();
        assert_eq!(n, 23);
        assert_eq!(edges[..4], [(2, 3), (2, 4), (6, 7), (5, 6)]);
        let p = generate_problem(&ProblemSpec::paper(6, RobotCount::LeavesMinusOne), 1).unwrap();
        assert_eq!(p.edges(), &edges[..]);
        assert_eq!(p.instance.starts, [20, 4, 16, 3, 13, 21, 15, 0, 9, 22]);
        assert_eq!(p.instance.goals, [6, 9, 21, 20, 5, 0, 16, 11, 13, 10]);
    }

    #[test]
    fn adjacency_lists_children_then_parent() {
        // Find a seed whose root has a child with children, and check the order.
        let (n, edges) = (0..100)
            .map(|s| generate_tree(4, 4, ChildCount::Exclusive, s).unwrap())
            .find(|(n, _)| *n > 6)
            .unwrap();
        let g = mrpp_core::mapf::graph::Graph::from_edges(n, &edges);
        let t = RootedTree::new(&g, 0).unwrap();
        for v in 1..n as VertexId {
            let nb = g.neighbors(v);
            assert_eq!(*nb.last().unwrap(), t.parent(v).unwrap());
            assert!(nb[..nb.len() - 1].windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn problems_follow_the_spec() {
        for seed in 0..100 {
            let spec = ProblemSpec::paper(5, RobotCount::LeavesMinusOne);
            let p = generate_problem(&spec, seed).unwrap();
            assert_eq!(p, generate_problem(&spec, seed).unwrap());
            let leaves = p.num_leaves();
            assert!(leaves >= 2 && p.num_nodes() >= 3);
            assert_eq!(p.num_robots(), (leaves - 1).min(p.num_nodes() - 2).max(1));
            for i in 0..p.num_robots() {
                assert_ne!(p.instance.starts[i], p.instance.goals[i]);
            }
            // Same tree whatever the robot count.
            let q =
                generate_problem(&ProblemSpec::paper(5, RobotCount::PerLeaf(1.5)), seed).unwrap();
            assert_eq!(q.edges(), p.edges());
            assert!(q.num_robots() <= q.num_nodes() - 2);
        }
        assert_eq!(RobotCount::PerLeaf(0.25).resolve(3, 10), 1);
        assert_eq!(RobotCount::PerLeaf(1.5).resolve(10, 12), 10);
        assert_eq!(RobotCount::Exactly(0).resolve(10, 12), 1);
        let impossible = ProblemSpec {
            min_leaves: 50,
            ..ProblemSpec::paper(1, RobotCount::LeavesMinusOne)
        };
        assert!(generate_problem(&impossible, 0).is_err());
    }
}

#[cfg(test)]
mod authors_tests {
    use super::*;

    /// The authors' distribution gives the paper's problem sizes (its text reports 14.9 nodes and
    /// 3.9 robots a problem on average); every problem has at least 2 robots.
    #[test]
    fn the_authors_distribution_has_the_papers_problem_sizes() {
        let (mut nodes, mut robots, mut leaves) = (0usize, 0usize, 0usize);
        let runs = 2000;
        for seed in 0..runs {
            let (budget, t) =
                generate_authors_problem(4..=10, RobotCount::LeavesMinusOne, seed).unwrap();
            assert!((4..=10).contains(&budget));
            assert!(t.num_robots() >= 2 && t.num_robots() < t.num_leaves());
            nodes += t.num_nodes();
            robots += t.num_robots();
            leaves += t.num_leaves();
        }
        let mean = |x: usize| x as f64 / runs as f64;
        eprintln!(
            "authors' distribution: {:.1} nodes, {:.1} leaves, {:.2} robots per problem",
            mean(nodes),
            mean(leaves),
            mean(robots)
        );
        assert!((12.0..=18.0).contains(&mean(nodes)), "{}", mean(nodes));
        assert!((3.0..=5.0).contains(&mean(robots)), "{}", mean(robots));
        // Deterministic for a seed; a budget out of range is refused.
        let a = generate_authors_problem(4..=10, RobotCount::LeavesMinusOne, 7).unwrap();
        let b = generate_authors_problem(4..=10, RobotCount::LeavesMinusOne, 7).unwrap();
        assert_eq!(a.1.num_nodes(), b.1.num_nodes());
        assert_eq!(a.1.instance.starts, b.1.instance.starts);
        assert!(generate_authors_problem(0..=3, RobotCount::LeavesMinusOne, 0).is_err());
    }
}
