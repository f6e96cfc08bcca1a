//! Tree instances and their JSON file format.
//!
//! ```json
//! {"nodes": 5, "edges": [[0, 1], [1, 2]], "robots": [{"start": 3, "goal": 1}]}
//! ```
//!
//! Node ids are `0..nodes`; node 0 is the root (PSW's priorities and the leaf count depend on it).
//! Other keys are allowed and ignored. The edge order is kept: it fixes every adjacency list, hence
//! PSW's DFS priorities, so a file read back gives the same planner behaviour as the instance it
//! was written from. A file is refused, with its name and (where the fault sits on one edge or one
//! robot) the line, when it is not JSON of that shape, when the edges do not form a tree on the
//! nodes (an id out of range, a self-loop, a duplicate edge, a cycle, a disconnected graph), or
//! when the robots are not one-per-start and one-per-goal on the tree (at least one robot).

use std::path::Path;

use rustc_hash::{FxHashMap, FxHashSet};
use serde::Deserialize;

use crate::rooted::RootedTree;
use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::instance::Instance;

/// A tree workspace with its robots: the graph (built from `edges` in order) and the instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TreeInstance {
    pub graph: Graph,
    pub instance: Instance,
    edges: Vec<(VertexId, VertexId)>,
}

/// A fault found while checking nodes, edges and robots: the index of the edge or robot it sits
/// on (for the line number) and a message.
struct Fault {
    edge: Option<usize>,
    robot: Option<usize>,
    msg: String,
}

impl Fault {
    fn edge(i: usize, msg: String) -> Self {
        Fault {
            edge: Some(i),
            robot: None,
            msg,
        }
    }
    fn robot(i: usize, msg: String) -> Self {
        Fault {
            edge: None,
            robot: Some(i),
            msg,
        }
    }
    fn whole(msg: String) -> Self {
        Fault {
            edge: None,
            robot: None,
            msg,
        }
    }
}

/// Largest node count accepted (ids must fit a `VertexId` and the arrays must fit in memory).
const MAX_NODES: u64 = 1 << 28;

/// Checks that `edges` form a tree on `n` nodes: ids in range, no self-loop, no duplicate, no
/// cycle, and exactly `n - 1` edges (so, connected).
fn check_tree(n: u64, edges: &[(u64, u64)]) -> std::result::Result<(), Fault> {
    if n == 0 {
        return Err(Fault::whole("a tree needs at least one node".into()));
    }
    if n > MAX_NODES {
        return Err(Fault::whole(format!(
            "{n} nodes is more than this program accepts ({MAX_NODES})"
        )));
    }
    let mut seen: FxHashSet<(u64, u64)> = FxHashSet::default();
    for (i, &(u, v)) in edges.iter().enumerate() {
        for x in [u, v] {
            if x >= n {
                return Err(Fault::edge(
                    i,
                    format!(
                        "edge [{u}, {v}]: node {x} does not exist (nodes are 0..{})",
                        n - 1
                    ),
                ));
            }
        }
        if u == v {
            return Err(Fault::edge(i, format!("edge [{u}, {v}] is a self-loop")));
        }
        if !seen.insert((u.min(v), u.max(v))) {
            return Err(Fault::edge(i, format!("edge [{u}, {v}] appears twice")));
        }
    }
    let m = edges.len() as u64;
    if m + 1 < n {
        return Err(Fault::whole(format!(
            "the graph is disconnected: {n} nodes need {} edges, found {m} (node {} is not \
             connected to node 0)",
            n - 1,
            unreached_node(n, edges)
        )));
    }
    let mut uf = UnionFind::new(n as usize);
    for (i, &(u, v)) in edges.iter().enumerate() {
        if !uf.union(u as usize, v as usize) {
            return Err(Fault::edge(
                i,
                format!("edge [{u}, {v}] closes a cycle ({u} and {v} are already connected)"),
            ));
        }
    }
    Ok(())
}

/// A node that node 0 cannot reach, for a forest with fewer than `n - 1` edges (memory in the
/// number of edges, not of nodes: the node count comes from the file).
fn unreached_node(n: u64, edges: &[(u64, u64)]) -> u64 {
    let mut ids: Vec<u64> = edges.iter().flat_map(|&(u, v)| [u, v]).collect();
    ids.push(0);
    ids.sort_unstable();
    ids.dedup();
    let index = |x: u64| ids.binary_search(&x).expect("listed");
    let mut uf = UnionFind::new(ids.len());
    for &(u, v) in edges {
        uf.union(index(u), index(v));
    }
    let root0 = uf.find(index(0));
    if let Some(&x) = ids.iter().find(|&&x| uf.find(index(x)) != root0) {
        return x;
    }
    // Every node on an edge is connected to 0, so some node is on no edge: the first gap.
    (1..n)
        .find(|x| ids.binary_search(x).is_err())
        .unwrap_or(n - 1)
}

/// Checks the robots: at least one, every start and goal a node, no shared start, no shared goal.
fn check_robots(n: u64, robots: &[(u64, u64)]) -> std::result::Result<(), Fault> {
    if robots.is_empty() {
        return Err(Fault::whole("there are no robots".into()));
    }
    let mut starts: FxHashMap<u64, usize> = FxHashMap::default();
    let mut goals: FxHashMap<u64, usize> = FxHashMap::default();
    for (i, &(s, g)) in robots.iter().enumerate() {
        for (what, x) in [("start", s), ("goal", g)] {
            if x >= n {
                return Err(Fault::robot(
                    i,
                    format!(
                        "robot {i}: {what} {x} is not a node of the tree (nodes are 0..{})",
                        n - 1
                    ),
                ));
            }
        }
        if let Some(j) = starts.insert(s, i) {
            return Err(Fault::robot(
                i,
                format!("robot {i} starts on node {s}, the start of robot {j}"),
            ));
        }
        if let Some(j) = goals.insert(g, i) {
            return Err(Fault::robot(
                i,
                format!("robot {i} has goal {g}, the goal of robot {j}"),
            ));
        }
    }
    Ok(())
}

struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
        }
    }
    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }
    /// Joins the sets of `a` and `b`; false when they were already one set.
    fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.parent[ra.max(rb)] = ra.min(rb);
        true
    }
}

#[derive(Deserialize)]
struct RawInstance {
    nodes: u64,
    edges: Vec<[u64; 2]>,
    robots: Vec<RawRobot>,
}

#[derive(Deserialize)]
struct RawRobot {
    start: u64,
    goal: u64,
}

impl TreeInstance {
    /// A tree on `nodes` nodes from `edges` (kept in this order) with the robots of `instance`.
    pub fn new(
        nodes: usize,
        edges: Vec<(VertexId, VertexId)>,
        instance: Instance,
    ) -> std::result::Result<Self, String> {
        let wide: Vec<(u64, u64)> = edges
            .iter()
            .map(|&(u, v)| (u64::from(u), u64::from(v)))
            .collect();
        check_tree(nodes as u64, &wide).map_err(|f| f.msg)?;
        let robots: Vec<(u64, u64)> = instance
            .starts
            .iter()
            .zip(&instance.goals)
            .map(|(&s, &g)| (u64::from(s), u64::from(g)))
            .collect();
        check_robots(nodes as u64, &robots).map_err(|f| f.msg)?;
        Ok(TreeInstance {
            graph: Graph::from_edges(nodes, &edges),
            instance,
            edges,
        })
    }

    /// The edges in the order the graph was built from.
    pub fn edges(&self) -> &[(VertexId, VertexId)] {
        &self.edges
    }

    pub fn num_nodes(&self) -> usize {
        self.graph.num_vertices()
    }

    pub fn num_robots(&self) -> usize {
        self.instance.num_agents()
    }

    /// The tree rooted at node 0.
    pub fn rooted(&self) -> RootedTree {
        RootedTree::new(&self.graph, 0).expect("a TreeInstance always holds a tree")
    }

    /// Number of leaves (non-root nodes of degree 1).
    pub fn num_leaves(&self) -> usize {
        count_leaves(&self.graph)
    }

    /// The JSON text of this instance: one edge and one robot per line, so that a checker's
    /// line numbers point at them.
    pub fn to_json(&self) -> String {
        let mut s = format!("{{\n  \"nodes\": {},\n  \"edges\": [", self.num_nodes());
        for (i, (u, v)) in self.edges.iter().enumerate() {
            let sep = if i == 0 { "" } else { "," };
            s.push_str(&format!("{sep}\n    [{u}, {v}]"));
        }
        s.push_str(if self.edges.is_empty() {
            "],\n"
        } else {
            "\n  ],\n"
        });
        s.push_str("  \"robots\": [");
        for (i, (st, g)) in self
            .instance
            .starts
            .iter()
            .zip(&self.instance.goals)
            .enumerate()
        {
            let sep = if i == 0 { "" } else { "," };
            s.push_str(&format!("{sep}\n    {{\"start\": {st}, \"goal\": {g}}}"));
        }
        s.push_str("\n  ]\n}\n");
        s
    }

    /// Reads a tree instance file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = read_file(path)?;
        Self::parse(&text, path)
    }

    /// Parses tree instance JSON; `path` only names the source in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let raw: RawInstance = serde_json::from_str(text).map_err(|e| {
            Error::parse(
                path,
                e.line().max(1),
                format!("not a tree instance: {}", without_position(&e)),
            )
        })?;
        let edges: Vec<(u64, u64)> = raw.edges.iter().map(|e| (e[0], e[1])).collect();
        let robots: Vec<(u64, u64)> = raw.robots.iter().map(|r| (r.start, r.goal)).collect();
        let located = |f: Fault| {
            let line = match (f.edge, f.robot) {
                (Some(i), _) => element_line(text, "edges", i),
                (_, Some(i)) => element_line(text, "robots", i),
                _ => None,
            };
            match line {
                Some(line) => Error::parse(path, line, f.msg),
                None => Error::invalid(path, f.msg),
            }
        };
        check_tree(raw.nodes, &edges).map_err(located)?;
        check_robots(raw.nodes, &robots).map_err(located)?;
        let n = raw.nodes as usize;
        let edges: Vec<(VertexId, VertexId)> = edges
            .iter()
            .map(|&(u, v)| (u as VertexId, v as VertexId))
            .collect();
        let instance = Instance::new(
            robots.iter().map(|&(s, _)| s as VertexId).collect(),
            robots.iter().map(|&(_, g)| g as VertexId).collect(),
        )
        .map_err(|msg| Error::invalid(path, msg))?;
        Ok(TreeInstance {
            graph: Graph::from_edges(n, &edges),
            instance,
            edges,
        })
    }
}

/// Number of leaves (non-root vertices of degree 1, root = vertex 0) of a graph.
pub fn count_leaves(graph: &Graph) -> usize {
    (1..graph.num_vertices() as VertexId)
        .filter(|&v| graph.degree(v) == 1)
        .count()
}

/// serde_json's message without its trailing " at line L column C" (the line goes in front).
fn without_position(e: &serde_json::Error) -> String {
    let msg = e.to_string();
    let tail = format!(" at line {} column {}", e.line(), e.column());
    match msg.strip_suffix(&tail) {
        Some(m) if e.line() > 0 => format!("{m} (column {})", e.column()),
        _ => msg,
    }
}

/// The line of element `index` of the array under the top-level key `key`, in JSON text that
/// serde_json has already accepted (so the scan needs no error handling beyond giving up).
fn element_line(text: &str, key: &str, index: usize) -> Option<usize> {
    let b = text.as_bytes();
    let mut i = 0;
    let mut depth = 0usize;
    // Key of the value being read at depth 1, and whether we are inside that key's array.
    let mut last_key: Option<(usize, usize)> = None;
    let mut in_target = false;
    let mut count = 0usize;
    let mut expect_element = false;
    while i < b.len() {
        let c = b[i];
        if c == b'"' {
            let start = i + 1;
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            if in_target && depth == 2 && expect_element {
                if count == index {
                    return Some(line_of(text, start - 1));
                }
                count += 1;
                expect_element = false;
            }
            if depth == 1 {
                last_key = Some((start, i.min(b.len())));
            }
            i += 1;
            continue;
        }
        match c {
            b'{' | b'[' => {
                if in_target && depth == 2 && expect_element {
                    if count == index {
                        return Some(line_of(text, i));
                    }
                    count += 1;
                    expect_element = false;
                }
                depth += 1;
                if depth == 2
                    && c == b'['
                    && let Some((s, e)) = last_key
                    && &text[s..e] == key
                {
                    in_target = true;
                    expect_element = true;
                }
            }
            b'}' | b']' => {
                if depth == 2 && in_target {
                    return None;
                }
                depth = depth.saturating_sub(1);
            }
            b',' => {
                if in_target && depth == 2 {
                    expect_element = true;
                }
            }
            c if c.is_ascii_whitespace() || c == b':' => {}
            _ => {
                // A number, `true`, `false` or `null` as an element.
                if in_target && depth == 2 && expect_element {
                    if count == index {
                        return Some(line_of(text, i));
                    }
                    count += 1;
                    expect_element = false;
                }
            }
        }
        i += 1;
    }
    None
}

fn line_of(text: &str, byte: usize) -> usize {
    text.as_bytes()[..byte]
        .iter()
        .filter(|&&c| c == b'\n')
        .count()
        + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<TreeInstance> {
        TreeInstance::parse(text, Path::new("t.json"))
    }

    fn err(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    const GOOD: &str = r#"{
  "nodes": 4,
  "edges": [
    [0, 1],
    [1, 2],
    [1, 3]
  ],
  "robots": [
    {"start": 2, "goal": 3},
    {"start": 3, "goal": 0}
  ],
  "comment": "extra keys are ignored"
}"#;

    #[test]
    fn parses_and_round_trips() {
        let t = parse(GOOD).unwrap();
        assert_eq!(t.num_nodes(), 4);
        assert_eq!(t.edges(), &[(0, 1), (1, 2), (1, 3)]);
        assert_eq!(t.instance.starts, vec![2, 3]);
        assert_eq!(t.instance.goals, vec![3, 0]);
        assert_eq!(t.num_leaves(), 2);
        let back = parse(&t.to_json()).unwrap();
        assert_eq!(back, t);
        assert_eq!(back.to_json(), t.to_json());
    }

    #[test]
    fn element_lines_are_found() {
        assert_eq!(element_line(GOOD, "edges", 0), Some(4));
        assert_eq!(element_line(GOOD, "edges", 2), Some(6));
        assert_eq!(element_line(GOOD, "robots", 1), Some(10));
        assert_eq!(element_line(GOOD, "robots", 2), None);
        let packed =
            "{\"robots\":[{\"start\":1,\"goal\":2},\n{\"start\":1,\"goal\":3}],\"x\":[[1]]}";
        assert_eq!(element_line(packed, "robots", 1), Some(2));
    }

    #[test]
    fn every_bad_instance_is_an_error() {
        let with = |edges: &str, robots: &str| {
            format!("{{\"nodes\": 4,\n\"edges\": [\n{edges}\n],\n\"robots\": [\n{robots}\n]}}")
        };
        let ok_edges = "[0, 1],\n[1, 2],\n[1, 3]";
        let ok_robots = "{\"start\": 2, \"goal\": 3}";
        let cases: Vec<(String, &str, &str)> = vec![
            ("{\"nodes\": 4, \"edges\": [".into(), "t.json:1:", "EOF"),
            ("[1, 2]".into(), "t.json:1:", "not a tree instance"),
            (
                "{\"nodes\": 4, \"edges\": [], \"robots\": [{\"start\": -1, \"goal\": 0}]}".into(),
                "t.json:1:",
                "invalid value",
            ),
            (
                "{\"nodes\": 4, \"edges\": [[0, 1]]}".into(),
                "t.json:1:",
                "missing field `robots`",
            ),
            (
                with("[0, 1],\n[1, 7],\n[1, 3]", ok_robots),
                "t.json:4:",
                "node 7 does not exist",
            ),
            (
                with("[0, 1],\n[2, 2],\n[1, 3]", ok_robots),
                "t.json:4:",
                "self-loop",
            ),
            (
                with("[0, 1],\n[1, 0],\n[1, 3]", ok_robots),
                "t.json:4:",
                "appears twice",
            ),
            (
                with("[0, 1],\n[1, 2],\n[2, 0],\n[1, 3]", ok_robots),
                "t.json:5:",
                "closes a cycle",
            ),
            (
                with("[0, 1],\n[2, 3]", ok_robots),
                "t.json:",
                "disconnected",
            ),
            (
                with(
                    ok_edges,
                    "{\"start\": 2, \"goal\": 3},\n{\"start\": 2, \"goal\": 0}",
                ),
                "t.json:9:",
                "the start of robot 0",
            ),
            (
                with(
                    ok_edges,
                    "{\"start\": 2, \"goal\": 3},\n{\"start\": 0, \"goal\": 3}",
                ),
                "t.json:9:",
                "the goal of robot 0",
            ),
            (
                with(ok_edges, "{\"start\": 2, \"goal\": 4}"),
                "t.json:8:",
                "goal 4 is not a node",
            ),
            (
                with(ok_edges, "{\"start\": 9, \"goal\": 1}"),
                "t.json:8:",
                "start 9 is not a node",
            ),
            (with(ok_edges, ""), "t.json:", "no robots"),
            (
                "{\"nodes\": 0, \"edges\": [], \"robots\": []}".into(),
                "t.json:",
                "at least one node",
            ),
            (
                "{\"nodes\": 100000000, \"edges\": [[0, 1]], \"robots\": []}".into(),
                "t.json:",
                "node 2 is not connected",
            ),
            (
                "{\"nodes\": 3, \"edges\": [[0, 1, 2]], \"robots\": []}".into(),
                "t.json:1:",
                "not a tree instance",
            ),
            (
                "{\"nodes\": 3, \"edges\": [[1, 2], [0, 0]], \"robots\": []}".into(),
                "t.json:1:",
                "self-loop",
            ),
        ];
        for (text, prefix, needle) in cases {
            let e = err(&text);
            assert!(
                e.starts_with(prefix) && e.contains(needle),
                "{e}\n--- for ---\n{text}"
            );
        }
    }

    #[test]
    fn constructor_checks_too() {
        let inst = Instance::new(vec![2], vec![3]).unwrap();
        assert!(TreeInstance::new(4, vec![(0, 1), (1, 2), (1, 3)], inst.clone()).is_ok());
        assert!(TreeInstance::new(4, vec![(0, 1), (1, 2), (2, 0)], inst.clone()).is_err());
        assert!(TreeInstance::new(3, vec![(0, 1), (1, 2)], inst).is_err());
    }
}
