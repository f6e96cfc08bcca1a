//! GP programs: decision trees whose internal nodes are the nine conditionals of the paper's
//! Table 1 (each with a then- and an else-branch) and whose leaves are the four actions of Table 2.
//!
//! A program is stored flat, in prefix order (a conditional, then its whole then-branch, then its
//! whole else-branch), so a subtree is a contiguous slice: crossover and mutation splice slices,
//! and running a program is a walk down one branch without recursion.
//!
//! **File format**: one S-expression, the paper's names in lower case, `;` starts a comment:
//!
//! ```text
//! ; Move toward the objective when the way is free, else step aside.
//! (if-neighbor-on-path-is-free
//!   move-toward-objective
//!   move-to-free-neighbor)
//! ```
//!
//! A conditional is written `(name then else)`, an action as its bare name. Names are matched
//! without regard to case (the paper writes them `If-Robot-At-Branch`). A malformed file is refused
//! with its line and column and what was expected there.

use std::fmt;
use std::path::Path;

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use mrpp_core::error::{Error, Result, read_file};

/// The function set F (Table 1). Each is a test on the robot that runs the program; some change
/// robot state as the table describes (see the module documentation of [`super`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Conditional {
    /// If-Two-Robots-On-Each-Others-Path: r_i is on the path of some r_j in c(r_i) and r_j is on
    /// r_i's path; both then set their paths to the nearest branch node to r_i.
    TwoRobotsOnEachOthersPath,
    /// If-Neighbor-Is-Surrounded: a robot adjacent to r_i has every adjacent node occupied.
    NeighborIsSurrounded,
    /// If-Robot-At-Branch: r_i stands on the branch node it set its path to.
    RobotAtBranch,
    /// If-Robot-At-Destination: r_i stands on its goal.
    RobotAtDestination,
    /// If-Robot-Moving-To-Branch: r_i has set its path to a branch node it has not reached yet.
    RobotMovingToBranch,
    /// If-Neighbor-On-Path-Is-Free: the next node on r_i's current path is free.
    NeighborOnPathIsFree,
    /// If-Robot-Is-Solved: r_i has visited its goal.
    RobotIsSolved,
    /// If-On-Path-Of-Robot-In-Network: r_i stands on the path of some r_j in c(r_i).
    OnPathOfRobotInNetwork,
    /// If-Robot-In-Network-Moving-To-Branch: some r_j in c(r_i) is travelling to a branch node.
    RobotInNetworkMovingToBranch,
}

/// The terminal set L (Table 2). Every action that moves checks for collisions first: a move into
/// an occupied node leaves the robot where it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Action {
    /// Move-Toward-Branch: one step toward the branch node the robot has set its path to (the
    /// nearest one, chosen now, when it has none).
    MoveTowardBranch,
    /// Move-To-Free-Neighbor: one step to a free adjacent node the robot has not visited.
    MoveToFreeNeighbor,
    /// Move-Toward-Objective: one step along the robot's current path.
    MoveTowardObjective,
    /// Stay: no move.
    Stay,
}

impl Conditional {
    pub const ALL: [Conditional; 9] = [
        Conditional::TwoRobotsOnEachOthersPath,
        Conditional::NeighborIsSurrounded,
        Conditional::RobotAtBranch,
        Conditional::RobotAtDestination,
        Conditional::RobotMovingToBranch,
        Conditional::NeighborOnPathIsFree,
        Conditional::RobotIsSolved,
        Conditional::OnPathOfRobotInNetwork,
        Conditional::RobotInNetworkMovingToBranch,
    ];

    /// The name used in program files.
    pub fn name(self) -> &'static str {
        match self {
            Conditional::TwoRobotsOnEachOthersPath => "if-two-robots-on-each-others-path",
            Conditional::NeighborIsSurrounded => "if-neighbor-is-surrounded",
            Conditional::RobotAtBranch => "if-robot-at-branch",
            Conditional::RobotAtDestination => "if-robot-at-destination",
            Conditional::RobotMovingToBranch => "if-robot-moving-to-branch",
            Conditional::NeighborOnPathIsFree => "if-neighbor-on-path-is-free",
            Conditional::RobotIsSolved => "if-robot-is-solved",
            Conditional::OnPathOfRobotInNetwork => "if-on-path-of-robot-in-network",
            Conditional::RobotInNetworkMovingToBranch => "if-robot-in-network-moving-to-branch",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(name))
    }
}

impl Action {
    pub const ALL: [Action; 4] = [
        Action::MoveTowardBranch,
        Action::MoveToFreeNeighbor,
        Action::MoveTowardObjective,
        Action::Stay,
    ];

    /// The name used in program files.
    pub fn name(self) -> &'static str {
        match self {
            Action::MoveTowardBranch => "move-toward-branch",
            Action::MoveToFreeNeighbor => "move-to-free-neighbor",
            Action::MoveTowardObjective => "move-toward-objective",
            Action::Stay => "stay",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|a| a.name().eq_ignore_ascii_case(name))
    }
}

/// One node of a program in prefix order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Gene {
    If(Conditional),
    Do(Action),
}

/// A decision tree over [`Conditional`]s and [`Action`]s, stored in prefix order.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Program {
    genes: Vec<Gene>,
    /// For a conditional at index `i`, the index where its else-branch starts (its then-branch
    /// starts at `i + 1`); unused for actions.
    else_at: Vec<u32>,
}

impl Program {
    /// A program from genes in prefix order; fails when the sequence is not exactly one tree.
    pub fn from_genes(genes: Vec<Gene>) -> std::result::Result<Self, String> {
        // `need` = subtrees still to read; the sequence is one tree iff it reaches 0 exactly at
        // the end.
        let mut need = 1usize;
        for (i, g) in genes.iter().enumerate() {
            if need == 0 {
                return Err(format!("genes after the end of the tree (at index {i})"));
            }
            need = match g {
                Gene::If(_) => need + 1,
                Gene::Do(_) => need - 1,
            };
        }
        if need != 0 {
            return Err(format!("the tree is missing {need} subtree(s)"));
        }
        let else_at = else_indices(&genes);
        Ok(Program { genes, else_at })
    }

    /// A single action.
    pub fn action(a: Action) -> Self {
        Program::from_genes(vec![Gene::Do(a)]).expect("one action is a tree")
    }

    /// `(c then otherwise)`.
    pub fn cond(c: Conditional, then: &Program, otherwise: &Program) -> Self {
        let mut genes = Vec::with_capacity(1 + then.len() + otherwise.len());
        genes.push(Gene::If(c));
        genes.extend_from_slice(&then.genes);
        genes.extend_from_slice(&otherwise.genes);
        Program::from_genes(genes).expect("built from two trees")
    }

    pub fn genes(&self) -> &[Gene] {
        &self.genes
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.genes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.genes.is_empty()
    }

    /// Depth in edges: a lone action has depth 0, `(c a b)` depth 1 (EpochX's convention, in which
    /// the paper's bounds "initial depth 2" and "depth between 1 and 50" are stated).
    pub fn depth(&self) -> usize {
        subtree_depth(&self.genes, 0).0
    }

    /// One past the last index of the subtree rooted at `i`.
    pub fn subtree_end(&self, i: usize) -> usize {
        subtree_end(&self.genes, i)
    }

    /// Depth of node `i` (the root is at depth 0).
    pub fn node_depth(&self, i: usize) -> usize {
        // Walk from the root, descending into whichever branch holds `i`.
        let mut k = 0;
        let mut d = 0;
        while k != i {
            debug_assert!(matches!(self.genes[k], Gene::If(_)));
            let e = self.else_at[k] as usize;
            k = if i < e { k + 1 } else { e };
            d += 1;
        }
        d
    }

    /// This program with the subtree at `i` replaced by `with` (a whole program's genes).
    pub fn replace_subtree(&self, i: usize, with: &[Gene]) -> Program {
        let end = self.subtree_end(i);
        let mut genes = Vec::with_capacity(self.len() - (end - i) + with.len());
        genes.extend_from_slice(&self.genes[..i]);
        genes.extend_from_slice(with);
        genes.extend_from_slice(&self.genes[end..]);
        Program::from_genes(genes).expect("a subtree replaced by a tree")
    }

    /// The program with its subtree `i..end` replaced by `donor`'s subtree `j..donor_end`; the
    /// caller vouches that both ranges are whole subtrees. The else-branch indices are the
    /// parents', moved: an else-branch starting after the replaced subtree moves by the size
    /// change (subtrees nest, so none starts inside it), the donor's by the new position.
    pub(crate) fn splice(
        &self,
        (i, end): (usize, usize),
        donor: &Program,
        (j, donor_end): (usize, usize),
    ) -> Program {
        let inserted = donor_end - j;
        let len = self.len() - (end - i) + inserted;
        let mut genes = Vec::with_capacity(len);
        genes.extend_from_slice(&self.genes[..i]);
        genes.extend_from_slice(&donor.genes[j..donor_end]);
        genes.extend_from_slice(&self.genes[end..]);
        // Actions keep 0; a conditional's else-branch is never at 0.
        let shift = |e: u32, from: u32, by: i64| {
            if e >= from && e != 0 {
                (i64::from(e) + by) as u32
            } else {
                e
            }
        };
        let delta = inserted as i64 - (end - i) as i64;
        let mut else_at = Vec::with_capacity(len);
        else_at.extend(
            self.else_at[..i]
                .iter()
                .map(|&e| shift(e, end as u32, delta)),
        );
        let moved = i as i64 - j as i64;
        else_at.extend(
            donor.else_at[j..donor_end]
                .iter()
                .map(|&e| shift(e, 1, moved)),
        );
        else_at.extend(self.else_at[end..].iter().map(|&e| shift(e, 1, delta)));
        let p = Program { genes, else_at };
        debug_assert_eq!(p.else_at, else_indices(&p.genes));
        p
    }

    /// The end and the depth of the subtree at `i` (one walk over it); `open` is scratch.
    pub(crate) fn subtree_extent(&self, i: usize, open: &mut Vec<u8>) -> (usize, usize) {
        let (depth, end) = subtree_depth_with(&self.genes, i, open);
        (end, depth)
    }

    /// The genes of the subtree rooted at `i`.
    pub fn subtree(&self, i: usize) -> &[Gene] {
        &self.genes[i..self.subtree_end(i)]
    }

    /// Runs the decision tree: `test` answers (and may act on) each conditional met on the way
    /// down; returns the action at the leaf reached.
    #[inline]
    pub fn decide(&self, test: impl FnMut(Conditional) -> bool) -> Action {
        self.decide_visiting(test, |_| {})
    }

    /// [`Program::decide`], telling `visit` the index of every node met, the leaf included.
    #[inline]
    pub fn decide_visiting(
        &self,
        mut test: impl FnMut(Conditional) -> bool,
        mut visit: impl FnMut(usize),
    ) -> Action {
        let mut k = 0;
        loop {
            visit(k);
            match self.genes[k] {
                Gene::If(c) => {
                    k = if test(c) {
                        k + 1
                    } else {
                        self.else_at[k] as usize
                    };
                }
                Gene::Do(a) => return a,
            }
        }
    }

    /// A random tree by Koza's *grow* method: below `max_depth` every node is drawn uniformly from
    /// the 13 primitives, at `max_depth` from the actions; the root is a conditional whenever
    /// `max_depth >= 1` (the paper's minimum depth 1).
    pub fn grow(rng: &mut ChaCha8Rng, max_depth: usize) -> Program {
        let mut genes = Vec::new();
        random_tree(rng, max_depth, false, true, &mut genes);
        Program::from_genes(genes).expect("generated trees are trees")
    }

    /// A random subtree by *grow* whose root may also be an action (mutation's new subtrees).
    pub fn grow_subtree(rng: &mut ChaCha8Rng, max_depth: usize) -> Program {
        let mut genes = Vec::new();
        random_tree(rng, max_depth, false, false, &mut genes);
        Program::from_genes(genes).expect("generated trees are trees")
    }

    /// A random tree by Koza's *full* method: every action sits at exactly `depth`.
    pub fn full(rng: &mut ChaCha8Rng, depth: usize) -> Program {
        let mut genes = Vec::new();
        random_tree(rng, depth, true, true, &mut genes);
        Program::from_genes(genes).expect("generated trees are trees")
    }

    /// The program as an S-expression, indented so that long programs stay readable.
    pub fn to_sexpr(&self) -> String {
        if self.depth() > 200 {
            // Indentation would only make such a program wider (and the writer recurses).
            return one_line(&self.genes);
        }
        let mut out = String::new();
        write_sexpr(&self.genes, 0, 0, &mut out);
        out
    }

    /// Parses the S-expression file format; `path` only names the source in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Program> {
        parse_sexpr(text)
            .map_err(|e| Error::parse(path, e.line, format!("column {}: {}", e.column, e.msg)))
    }

    /// Reads a program file.
    pub fn load(path: &Path) -> Result<Program> {
        let text = read_file(path)?;
        Program::parse(&text, path)
    }

    /// Writes the program file (a comment line, then the S-expression).
    pub fn save(&self, path: &Path) -> Result<()> {
        let text = format!(
            "; mrpp GP program (Trudeau & Clark decision tree): {} nodes, depth {}\n{}\n",
            self.len(),
            self.depth(),
            self.to_sexpr()
        );
        std::fs::write(path, text).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

impl fmt::Display for Program {
    /// One line: `(if-robot-is-solved stay move-toward-objective)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&one_line(&self.genes))
    }
}

impl std::str::FromStr for Program {
    type Err = SyntaxError;
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        parse_sexpr(s)
    }
}

/// For each conditional, where its else-branch starts; linear: a backward pass knows the end of
/// every later subtree (`genes` must be one tree).
fn else_indices(genes: &[Gene]) -> Vec<u32> {
    let n = genes.len();
    let mut else_at = vec![0u32; n];
    let mut end = vec![0u32; n];
    for i in (0..n).rev() {
        end[i] = match genes[i] {
            Gene::Do(_) => i as u32 + 1,
            Gene::If(_) => {
                let e = end[i + 1];
                else_at[i] = e;
                end[e as usize]
            }
        };
    }
    else_at
}

fn subtree_end(genes: &[Gene], i: usize) -> usize {
    let mut need = 1usize;
    let mut k = i;
    while need > 0 {
        need = match genes[k] {
            Gene::If(_) => need + 1,
            Gene::Do(_) => need - 1,
        };
        k += 1;
    }
    k
}

/// (depth, end) of the subtree at `i`, without recursion.
fn subtree_depth(genes: &[Gene], i: usize) -> (usize, usize) {
    subtree_depth_with(genes, i, &mut Vec::new())
}

/// [`subtree_depth`] with its stack (`open`, cleared first) supplied.
fn subtree_depth_with(genes: &[Gene], i: usize, open: &mut Vec<u8>) -> (usize, usize) {
    // Stack of remaining children per open conditional; its length is the current depth.
    open.clear();
    let mut depth = 0;
    let mut k = i;
    loop {
        depth = depth.max(open.len());
        match genes[k] {
            Gene::If(_) => open.push(2),
            Gene::Do(_) => loop {
                match open.last_mut() {
                    None => return (depth, k + 1),
                    Some(left) => {
                        *left -= 1;
                        if *left == 0 {
                            open.pop();
                        } else {
                            break;
                        }
                    }
                }
            },
        }
        k += 1;
    }
}

fn random_action(rng: &mut ChaCha8Rng) -> Action {
    Action::ALL[rng.random_range(0..Action::ALL.len())]
}

fn random_conditional(rng: &mut ChaCha8Rng) -> Conditional {
    Conditional::ALL[rng.random_range(0..Conditional::ALL.len())]
}

fn random_tree(rng: &mut ChaCha8Rng, depth: usize, full: bool, root: bool, out: &mut Vec<Gene>) {
    let n_f = Conditional::ALL.len();
    let n_t = Action::ALL.len();
    let function = depth > 0 && (full || root || rng.random_range(0..n_f + n_t) < n_f);
    if function {
        out.push(Gene::If(random_conditional(rng)));
        random_tree(rng, depth - 1, full, false, out);
        random_tree(rng, depth - 1, full, false, out);
    } else {
        out.push(Gene::Do(random_action(rng)));
    }
}

fn gene_name(g: Gene) -> &'static str {
    match g {
        Gene::If(c) => c.name(),
        Gene::Do(a) => a.name(),
    }
}

fn one_line(genes: &[Gene]) -> String {
    let mut s = String::new();
    // Count of branches still to close per open conditional.
    let mut open: Vec<u8> = Vec::new();
    for (k, &g) in genes.iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        match g {
            Gene::If(c) => {
                s.push('(');
                s.push_str(c.name());
                open.push(2);
            }
            Gene::Do(a) => {
                s.push_str(a.name());
                while let Some(left) = open.last_mut() {
                    *left -= 1;
                    if *left == 0 {
                        open.pop();
                        s.push(')');
                    } else {
                        break;
                    }
                }
            }
        }
    }
    s
}

/// Lines longer than this are broken: the conditional's name on its line, its branches indented.
const LINE_WIDTH: usize = 96;

fn write_sexpr(genes: &[Gene], i: usize, indent: usize, out: &mut String) -> usize {
    let end = subtree_end(genes, i);
    let flat = one_line(&genes[i..end]);
    if indent + flat.len() <= LINE_WIDTH || matches!(genes[i], Gene::Do(_)) {
        out.push_str(&flat);
        return end;
    }
    out.push('(');
    out.push_str(gene_name(genes[i]));
    let mut k = i + 1;
    for _ in 0..2 {
        out.push('\n');
        out.push_str(&" ".repeat(indent + 2));
        k = write_sexpr(genes, k, indent + 2, out);
    }
    out.push(')');
    end
}

/// Where and why a program text is malformed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyntaxError {
    /// 1-based.
    pub line: usize,
    /// 1-based, in characters.
    pub column: usize,
    pub msg: String,
}

impl fmt::Display for SyntaxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.line, self.column, self.msg
        )
    }
}

impl std::error::Error for SyntaxError {}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tok<'a> {
    Open,
    Close,
    Atom(&'a str),
}

/// Tokens with their (line, column).
fn tokenize(text: &str) -> Vec<(Tok<'_>, usize, usize)> {
    let mut toks = Vec::new();
    for (li, line) in text.lines().enumerate() {
        let line = line.split(';').next().unwrap_or("");
        let mut chars = line.char_indices().peekable();
        let mut col = 0usize;
        while let Some((bi, ch)) = chars.next() {
            col += 1;
            match ch {
                '(' => toks.push((Tok::Open, li + 1, col)),
                ')' => toks.push((Tok::Close, li + 1, col)),
                c if c.is_whitespace() => {}
                _ => {
                    let start_col = col;
                    let mut end = bi + ch.len_utf8();
                    while let Some(&(bj, c2)) = chars.peek() {
                        if c2 == '(' || c2 == ')' || c2.is_whitespace() {
                            break;
                        }
                        end = bj + c2.len_utf8();
                        col += 1;
                        chars.next();
                    }
                    toks.push((Tok::Atom(&line[bi..end]), li + 1, start_col));
                }
            }
        }
    }
    toks
}

/// Parses one S-expression program (iteratively, so any nesting depth is safe).
pub fn parse_sexpr(text: &str) -> std::result::Result<Program, SyntaxError> {
    let toks = tokenize(text);
    let err = |line: usize, column: usize, msg: String| SyntaxError { line, column, msg };
    let last = text.lines().count().max(1);
    let mut genes = Vec::new();
    // Open conditionals: (name, line, column, branches read so far).
    let mut open: Vec<(Conditional, usize, usize, u8)> = Vec::new();
    let mut done = false;
    let mut i = 0;
    while i < toks.len() {
        let (tok, line, col) = toks[i];
        if done {
            return Err(err(
                line,
                col,
                "text after the end of the program (a file holds one program)".into(),
            ));
        }
        match tok {
            Tok::Open => {
                let Some(&(next, l2, c2)) = toks.get(i + 1) else {
                    return Err(err(line, col, "'(' at the end of the text".into()));
                };
                let Tok::Atom(name) = next else {
                    return Err(err(
                        l2,
                        c2,
                        "expected a conditional name after '(' (e.g. if-robot-at-branch)".into(),
                    ));
                };
                match (Conditional::from_name(name), Action::from_name(name)) {
                    (Some(c), _) => {
                        genes.push(Gene::If(c));
                        open.push((c, l2, c2, 0));
                    }
                    (None, Some(a)) => {
                        return Err(err(
                            l2,
                            c2,
                            format!("'{}' is an action: write it without parentheses", a.name()),
                        ));
                    }
                    (None, None) => {
                        return Err(err(l2, c2, format!("unknown conditional '{name}'")));
                    }
                }
                i += 2;
                continue;
            }
            Tok::Close => {
                let Some(&(c, _, _, n)) = open.last() else {
                    return Err(err(line, col, "unbalanced ')'".into()));
                };
                if n != 2 {
                    return Err(err(
                        line,
                        col,
                        format!(
                            "'{}' needs a then-branch and an else-branch, found {n} branch(es)",
                            c.name()
                        ),
                    ));
                }
                open.pop();
            }
            Tok::Atom(name) => match (Action::from_name(name), Conditional::from_name(name)) {
                (Some(a), _) => genes.push(Gene::Do(a)),
                (None, Some(c)) => {
                    return Err(err(
                        line,
                        col,
                        format!(
                            "'{}' is a conditional: write '({} <then> <else>)'",
                            c.name(),
                            c.name()
                        ),
                    ));
                }
                (None, None) => {
                    return Err(err(
                        line,
                        col,
                        format!(
                            "unknown action '{name}' (actions: move-toward-branch, \
                             move-to-free-neighbor, move-toward-objective, stay)"
                        ),
                    ));
                }
            },
        }
        // A whole subtree was just completed (an action or a closed conditional).
        match open.last_mut() {
            None => done = true,
            Some((c, _, _, n)) => {
                if *n == 2 {
                    return Err(err(
                        line,
                        col,
                        format!("'{}' takes exactly two branches, found a third", c.name()),
                    ));
                }
                *n += 1;
            }
        }
        i += 1;
    }
    if let Some(&(c, l, col, _)) = open.last() {
        return Err(err(
            l,
            col,
            format!("'{}' is not closed (missing ')')", c.name()),
        ));
    }
    if genes.is_empty() {
        return Err(err(last, 1, "empty program".into()));
    }
    Ok(Program::from_genes(genes).expect("the parser only accepts trees"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn round_trip_and_display() {
        let p: Program = "(if-neighbor-on-path-is-free move-toward-objective \
                          (IF-Two-Robots-On-Each-Others-Path move-toward-branch stay))"
            .parse()
            .unwrap();
        assert_eq!(p.len(), 5);
        assert_eq!(p.depth(), 2);
        assert_eq!(
            p.to_string(),
            "(if-neighbor-on-path-is-free move-toward-objective \
             (if-two-robots-on-each-others-path move-toward-branch stay))"
        );
        assert_eq!(p.to_sexpr().parse::<Program>().unwrap(), p);
        assert_eq!(p.node_depth(0), 0);
        assert_eq!(p.node_depth(2), 1);
        assert_eq!(p.node_depth(4), 2);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for d in 0..8 {
            let q = Program::grow(&mut rng, d);
            assert!(q.depth() <= d);
            assert_eq!(q.to_sexpr().parse::<Program>().unwrap(), q);
            let f = Program::full(&mut rng, d);
            assert_eq!(f.depth(), d);
            assert_eq!(f.len(), (1 << (d + 1)) - 1);
            assert_eq!(f.to_sexpr().parse::<Program>().unwrap(), f);
        }
    }

    #[test]
    fn malformed_texts_are_refused_with_a_position() {
        let cases = [
            ("", "empty program"),
            ("; only a comment\n", "empty program"),
            ("(if-robot-at-branch stay)", "found 1 branch"),
            ("(if-robot-at-branch stay stay stay)", "found a third"),
            ("(if-robot-at-branch stay stay", "not closed"),
            ("stay)", "after the end"),
            ("stay stay", "after the end"),
            (")", "unbalanced"),
            ("(stay)", "is an action"),
            ("if-robot-at-branch", "is a conditional"),
            ("(if-robot-at-nowhere stay stay)", "unknown conditional"),
            (
                "(if-robot-at-branch\n  stay\n  jump)",
                "unknown action 'jump'",
            ),
            ("((stay))", "expected a conditional name"),
            ("(", "at the end"),
        ];
        for (text, want) in cases {
            let e = text.parse::<Program>().unwrap_err();
            assert!(e.msg.contains(want), "{text:?}: {e}");
        }
        let e = "(if-robot-at-branch\n  stay\n  jump)"
            .parse::<Program>()
            .unwrap_err();
        assert_eq!((e.line, e.column), (3, 3));
        let e = Program::parse("(stay", Path::new("p.gp")).unwrap_err();
        assert!(e.to_string().starts_with("p.gp:1: column 2:"), "{e}");
    }

    #[test]
    fn splicing_keeps_trees() {
        let p: Program = "(if-robot-is-solved stay (if-robot-at-branch stay move-toward-branch))"
            .parse()
            .unwrap();
        assert_eq!(p.subtree_end(2), 5);
        let q = p.replace_subtree(2, &[Gene::Do(Action::MoveTowardObjective)]);
        assert_eq!(
            q.to_string(),
            "(if-robot-is-solved stay move-toward-objective)"
        );
        let r = p.replace_subtree(1, p.subtree(2));
        assert_eq!(r.depth(), 2);
        assert_eq!(r.len(), 7);
        assert!(Program::from_genes(vec![Gene::If(Conditional::RobotIsSolved)]).is_err());
        assert!(Program::from_genes(vec![Gene::Do(Action::Stay), Gene::Do(Action::Stay)]).is_err());
    }
}
