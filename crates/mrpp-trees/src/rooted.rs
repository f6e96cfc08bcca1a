//! A tree rooted at a vertex: parents, depths, DFS entry/exit times and the DFS post-order that
//! gives PSW its vertex priorities.
//!
//! Paths on a tree are unique, so every "shortest path" question (next hop, distance, is a vertex
//! on a path) is answered from parent pointers and the DFS interval of each vertex: `a` is an
//! ancestor of `b` iff `tin[a] <= tin[b] <= tout[a]`. Children are visited in the graph's adjacency
//! order, so the post-order (and every tie broken by it) follows the instance's edge order.

use mrpp_core::mapf::graph::{Graph, VertexId};

const NONE: VertexId = VertexId::MAX;

/// A tree graph with a chosen root (node 0 for every tree instance of this module).
#[derive(Debug, Clone)]
pub struct RootedTree {
    root: VertexId,
    parent: Vec<VertexId>,
    depth: Vec<u32>,
    degree: Vec<u32>,
    tin: Vec<u32>,
    tout: Vec<u32>,
    post: Vec<u32>,
    /// Vertices by DFS entry time: a subtree is a contiguous slice.
    preorder: Vec<VertexId>,
    /// Children of each vertex in DFS order (hence sorted by `tin`).
    children: Vec<Vec<VertexId>>,
}

impl RootedTree {
    /// Roots `graph` at `root`; fails when the graph is not a tree (a cycle, or not connected).
    pub fn new(graph: &Graph, root: VertexId) -> Result<Self, String> {
        let n = graph.num_vertices();
        if (root as usize) >= n {
            return Err(format!("root {root} is not a vertex (the graph has {n})"));
        }
        if graph.num_edges() + 1 != n {
            return Err(format!(
                "{n} vertices need {} edges to form a tree, found {}",
                n - 1,
                graph.num_edges()
            ));
        }
        let mut parent = vec![NONE; n];
        let mut depth = vec![0u32; n];
        let mut tin = vec![u32::MAX; n];
        let mut tout = vec![0u32; n];
        let mut post = vec![0u32; n];
        let mut children = vec![Vec::new(); n];
        let mut preorder = Vec::with_capacity(n);
        preorder.push(root);
        let degree = (0..n as VertexId).map(|v| graph.degree(v) as u32).collect();
        // Iterative DFS: (vertex, index of the next neighbour to look at).
        let mut stack: Vec<(VertexId, usize)> = vec![(root, 0)];
        let (mut clock, mut post_clock) = (0u32, 0u32);
        tin[root as usize] = clock;
        clock += 1;
        while let Some(&mut (v, ref mut next)) = stack.last_mut() {
            let nbrs = graph.neighbors(v);
            if *next < nbrs.len() {
                let w = nbrs[*next];
                *next += 1;
                if w == parent[v as usize] {
                    continue;
                }
                if tin[w as usize] != u32::MAX {
                    return Err(format!("the graph has a cycle through vertex {w}"));
                }
                parent[w as usize] = v;
                depth[w as usize] = depth[v as usize] + 1;
                tin[w as usize] = clock;
                clock += 1;
                preorder.push(w);
                children[v as usize].push(w);
                stack.push((w, 0));
            } else {
                tout[v as usize] = clock - 1;
                post[v as usize] = post_clock;
                post_clock += 1;
                stack.pop();
            }
        }
        if (clock as usize) != n {
            return Err(format!(
                "the graph is not connected ({} of {n} vertices reachable from {root})",
                clock
            ));
        }
        Ok(RootedTree {
            root,
            parent,
            depth,
            degree,
            tin,
            tout,
            post,
            preorder,
            children,
        })
    }

    pub fn root(&self) -> VertexId {
        self.root
    }

    pub fn num_vertices(&self) -> usize {
        self.parent.len()
    }

    pub fn parent(&self, v: VertexId) -> Option<VertexId> {
        let p = self.parent[v as usize];
        (p != NONE).then_some(p)
    }

    pub fn children(&self, v: VertexId) -> &[VertexId] {
        &self.children[v as usize]
    }

    pub fn depth(&self, v: VertexId) -> u32 {
        self.depth[v as usize]
    }

    pub fn degree(&self, v: VertexId) -> usize {
        self.degree[v as usize] as usize
    }

    /// DFS post-order index (children in adjacency order); PSW's vertex priority, smaller = higher.
    pub fn post_order(&self, v: VertexId) -> u32 {
        self.post[v as usize]
    }

    /// A leaf: a non-root vertex of degree 1.
    pub fn is_leaf(&self, v: VertexId) -> bool {
        v != self.root && self.degree[v as usize] == 1
    }

    /// A branch: a vertex of degree at least 3 (for the root: at least 3 children).
    pub fn is_branch(&self, v: VertexId) -> bool {
        self.degree[v as usize] >= 3
    }

    pub fn leaves(&self) -> Vec<VertexId> {
        (0..self.num_vertices() as VertexId)
            .filter(|&v| self.is_leaf(v))
            .collect()
    }

    pub fn branches(&self) -> Vec<VertexId> {
        (0..self.num_vertices() as VertexId)
            .filter(|&v| self.is_branch(v))
            .collect()
    }

    /// The vertices of the subtree below `v` (`v` first), in DFS order.
    pub fn subtree(&self, v: VertexId) -> &[VertexId] {
        &self.preorder[self.tin[v as usize] as usize..=self.tout[v as usize] as usize]
    }

    /// `a` is `b` or an ancestor of `b`.
    #[inline]
    pub fn is_ancestor(&self, a: VertexId, b: VertexId) -> bool {
        let (a, b) = (a as usize, b as usize);
        self.tin[a] <= self.tin[b] && self.tin[b] <= self.tout[a]
    }

    /// The first vertex after `u` on the path from `u` to `v` (`u` itself when `u == v`).
    pub fn next_hop(&self, u: VertexId, v: VertexId) -> VertexId {
        if u == v {
            return u;
        }
        if !self.is_ancestor(u, v) {
            return self.parent[u as usize];
        }
        let kids = &self.children[u as usize];
        let t = self.tin[v as usize];
        // The last child entered at or before `v`'s entry holds `v` in its subtree.
        let i = kids.partition_point(|&c| self.tin[c as usize] <= t);
        kids[i - 1]
    }

    pub fn lca(&self, mut u: VertexId, mut v: VertexId) -> VertexId {
        while !self.is_ancestor(u, v) {
            u = self.parent[u as usize];
        }
        while !self.is_ancestor(v, u) {
            v = self.parent[v as usize];
        }
        u
    }

    /// Number of edges on the path from `u` to `v`.
    pub fn distance(&self, u: VertexId, v: VertexId) -> u32 {
        let l = self.lca(u, v);
        self.depth[u as usize] + self.depth[v as usize] - 2 * self.depth[l as usize]
    }

    /// Whether `x` lies on the path from `u` to `v` (ends included).
    ///
    /// O(log degree), without walking to the LCA (the GP simulator asks this for every robot in
    /// every network test): `x` is on the path iff it is an ancestor of exactly one end, or an
    /// ancestor of both whose subtrees toward `u` and `v` differ (then `x` is their LCA).
    pub fn on_path(&self, x: VertexId, u: VertexId, v: VertexId) -> bool {
        match (self.is_ancestor(x, u), self.is_ancestor(x, v)) {
            (true, true) => x == u || x == v || self.next_hop(x, u) != self.next_hop(x, v),
            (true, false) | (false, true) => true,
            (false, false) => false,
        }
    }

    /// The vertices from `u` to `v`, both included.
    pub fn path(&self, u: VertexId, v: VertexId) -> Vec<VertexId> {
        let l = self.lca(u, v);
        let mut up = Vec::new();
        let mut x = u;
        while x != l {
            up.push(x);
            x = self.parent[x as usize];
        }
        up.push(l);
        let mut down = Vec::new();
        let mut y = v;
        while y != l {
            down.push(y);
            y = self.parent[y as usize];
        }
        up.extend(down.into_iter().rev());
        up
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 0 - 1 - 2, 2 - 3, 2 - 4, 0 - 5
    fn sample() -> RootedTree {
        let g = Graph::from_edges(6, &[(0, 1), (1, 2), (2, 3), (2, 4), (0, 5)]);
        RootedTree::new(&g, 0).unwrap()
    }

    #[test]
    fn structure_and_paths() {
        let t = sample();
        assert_eq!(t.leaves(), vec![3, 4, 5]);
        assert_eq!(t.branches(), vec![2]);
        // Post-order: 3, 4, 2, 1, 5, 0.
        let order: Vec<u32> = (0..6).map(|v| t.post_order(v)).collect();
        assert_eq!(order, vec![5, 3, 2, 0, 1, 4]);
        assert_eq!(t.path(3, 5), vec![3, 2, 1, 0, 5]);
        assert_eq!(t.path(4, 3), vec![4, 2, 3]);
        assert_eq!(t.distance(4, 5), 4);
        assert_eq!(t.next_hop(0, 4), 1);
        assert_eq!(t.next_hop(2, 4), 4);
        assert_eq!(t.next_hop(3, 4), 2);
        assert!(t.on_path(1, 3, 5));
        assert!(!t.on_path(4, 3, 5));
        // on_path agrees with the explicit path for every triple.
        for u in 0..6 {
            for v in 0..6 {
                let p = t.path(u, v);
                for x in 0..6 {
                    assert_eq!(t.on_path(x, u, v), p.contains(&x), "{x} on {u}-{v}");
                }
            }
        }
        assert_eq!(t.subtree(1), &[1, 2, 3, 4]);
        assert_eq!(t.subtree(0).len(), 6);
    }

    #[test]
    fn non_trees_are_refused() {
        let cycle = Graph::from_edges(3, &[(0, 1), (1, 2), (2, 0)]);
        assert!(RootedTree::new(&cycle, 0).is_err());
        let split = Graph::from_edges(4, &[(0, 1), (2, 3), (2, 3)]);
        assert!(RootedTree::new(&split, 0).is_err());
    }
}
