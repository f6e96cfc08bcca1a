//! The League of Robot Runners' 2026 tick model: robots whose actions take several ticks, square
//! footprints, and the per-tick resolution that makes a robot wait instead of colliding (start
//! kit v3.1.0: `inc/Counter.h`; `src/ActionModel.cpp` `result_state`, `get_real_locations`,
//! `moving_boxes_collide`, `step`; `docs/lorr-semantics.md` §2 "K3 changes").
//!
//! - **Counters.** Every `F`, `R`, `C` (and, under `MAPF`, every move) takes `agent_counter`
//!   ticks: each tick it is commanded, a counter goes up; when it reaches `agent_counter` the cell
//!   or orientation changes and the counter resets. During a move the robot's cell stays the
//!   origin. Once started, a `W` pauses the action (the robot may stand between two cells) and any
//!   other command continues it, whatever was asked.
//! - **Footprints.** A robot is an axis-aligned square of side `agent_size` (in (0, 1]) whose
//!   top-left corner is at `(column, row)` of its cell, shifted by `counter / agent_counter` cells
//!   along the heading of a move in progress; turning does not move it.
//! - **Resolution** ([`Resolver`]). Each tick every robot asks for one action. Its requested
//!   motion (one tick of it) and its wait motion are linear sweeps of its square. Robots are
//!   decided in index order: a robot takes its requested motion unless that leaves the map or
//!   enters an obstacle, or sweeps through an already decided robot's motion, or needs an
//!   undecided robot to move out of the way — then that robot is decided first (recursively),
//!   and if it stays, or if it is already waiting on this one (a dependency cycle), the robot
//!   waits. Following at the same speed is allowed; swaps and rotating cycles are not; of two
//!   robots entering one cell the lower index goes first. Each robot made to wait records why.
//!
//! mrpp is stricter than the kit in one place: a move whose target cell is off the map or an
//! obstacle is refused from its first tick (the kit lets a small square start such a move and
//! stops it when the square would touch the obstacle). The recursion is an explicit stack, so
//! chains of thousands of robots do not grow the thread's stack.

use mrpp_core::mapf::graph::VertexId;
use mrpp_mapf::GridMap;

use crate::model::{Action, Orientation, State, apply, neighbour};

/// A robot between ticks: its cell and orientation (the origin during a move), the ticks done of
/// the action in progress, and that action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TickState {
    /// Cell and orientation; the cell changes only when a move completes.
    pub state: State,
    /// Ticks done of [`Self::current`], `0..agent_counter`.
    pub counter: u32,
    /// The action in progress (`None` when idle).
    pub current: Option<Action>,
}

impl TickState {
    /// Idle at `state`.
    pub fn idle(state: State) -> Self {
        TickState {
            state,
            counter: 0,
            current: None,
        }
    }

    /// The direction a move in progress heads (`None` when idle or turning).
    pub fn heading(&self) -> Option<Orientation> {
        match self.current {
            Some(Action::Forward) => Some(self.state.orientation),
            Some(Action::Move(d)) => Some(d),
            _ => None,
        }
    }
}

/// Whether `a` changes nothing (wait, or no action).
pub fn is_wait(a: Action) -> bool {
    matches!(a, Action::Wait | Action::NoAction)
}

/// The state after one tick in which robot `s` is commanded `a` (module doc, "Counters"), or
/// `None` when `a` would move it off the map or into an obstacle. `agent_counter >= 1`.
pub fn after_tick(map: &GridMap, s: TickState, a: Action, agent_counter: u32) -> Option<TickState> {
    let executed = match s.current {
        Some(current) if s.counter > 0 => {
            if is_wait(a) {
                return Some(s);
            }
            current
        }
        _ => a,
    };
    if is_wait(executed) {
        return Some(TickState::idle(s.state));
    }
    let done = apply(map, s.state, executed)?;
    let counter = s.counter + 1;
    Some(if counter >= agent_counter {
        TickState::idle(done)
    } else {
        TickState {
            state: s.state,
            counter,
            current: Some(executed),
        }
    })
}

/// The top-left corner `(x, y)` of robot `s`'s square, in cells (module doc, "Footprints").
pub fn corner(map: &GridMap, s: &TickState, agent_counter: u32) -> (f64, f64) {
    let (x, y) = map.cell(s.state.vertex);
    let (mut x, mut y) = (f64::from(x), f64::from(y));
    if let Some(d) = s.heading()
        && s.counter > 0
    {
        let f = f64::from(s.counter) / f64::from(agent_counter);
        match d {
            0 => x += f,
            1 => y += f,
            2 => x -= f,
            _ => y -= f,
        }
    }
    (x, y)
}

/// A square's sweep over one tick: its corner moves linearly from `(x0, y0)` to `(x1, y1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sweep {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Sweep {
    /// From `from` to `to`, both corners.
    pub fn between(from: (f64, f64), to: (f64, f64)) -> Self {
        Sweep {
            x0: from.0,
            y0: from.1,
            x1: to.0,
            y1: to.1,
        }
    }
}

const EPS: f64 = 1e-6;

/// The part of `[0, 1]` in which `d0 + dv t` lies strictly inside `(lower, upper)` (by more than
/// `EPS`), if any.
fn inside(d0: f64, dv: f64, lower: f64, upper: f64) -> Option<(f64, f64)> {
    if dv.abs() < EPS {
        return (d0 > lower + EPS && d0 < upper - EPS).then_some((0.0, 1.0));
    }
    let (mut t0, mut t1) = ((lower - d0) / dv, (upper - d0) / dv);
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let slack = EPS / dv.abs();
    let (t0, t1) = ((t0 + slack).max(0.0), (t1 - slack).min(1.0));
    (t0 <= t1).then_some((t0, t1))
}

/// Whether two squares of side `size` overlap with positive area at some instant of their
/// sweeps (touching does not count).
pub fn sweeps_collide(a: &Sweep, b: &Sweep, size: f64) -> bool {
    let (d0x, d0y) = (a.x0 - b.x0, a.y0 - b.y0);
    let dvx = (a.x1 - a.x0) - (b.x1 - b.x0);
    let dvy = (a.y1 - a.y0) - (b.y1 - b.y0);
    let Some((tx0, tx1)) = inside(d0x, dvx, -size, size) else {
        return false;
    };
    let Some((ty0, ty1)) = inside(d0y, dvy, -size, size) else {
        return false;
    };
    tx0.max(ty0) <= tx1.min(ty1)
}

/// Robots binned by the cells their squares cover, rebuilt each tick (a counting sort over the
/// map's cells).
#[derive(Debug, Clone, Default)]
pub struct Bins {
    width: i64,
    height: i64,
    start: Vec<u32>,
    items: Vec<u32>,
    keys: Vec<(u32, u32)>,
}

impl Bins {
    /// Bins for `map`.
    pub fn new(map: &GridMap) -> Self {
        let cells = (map.width() as usize) * (map.height() as usize);
        Bins {
            width: i64::from(map.width()),
            height: i64::from(map.height()),
            start: vec![0; cells + 1],
            items: Vec::new(),
            keys: Vec::new(),
        }
    }

    /// Cells `(column, row)` a rectangle `[x0, x1] x [y0, y1]` touches, clamped to the map.
    fn cells(&self, x0: f64, y0: f64, x1: f64, y1: f64) -> impl Iterator<Item = u32> + use<> {
        cell_range(self.width, self.height, x0, y0, x1, y1)
    }

    /// Bins every robot's square of side `size` at `corners`.
    pub fn fill(&mut self, corners: &[(f64, f64)], size: f64) {
        self.keys.clear();
        for (i, &(x, y)) in corners.iter().enumerate() {
            for c in cell_range(self.width, self.height, x, y, x + size, y + size) {
                self.keys.push((c, i as u32));
            }
        }
        self.start.iter_mut().for_each(|s| *s = 0);
        for &(c, _) in &self.keys {
            self.start[c as usize + 1] += 1;
        }
        for k in 1..self.start.len() {
            self.start[k] += self.start[k - 1];
        }
        self.items.clear();
        self.items.resize(self.keys.len(), 0);
        for &(c, i) in &self.keys {
            // `start[c]` counts up while filling and is restored below.
            self.items[self.start[c as usize] as usize] = i;
            self.start[c as usize] += 1;
        }
        for &(c, _) in self.keys.iter().rev() {
            self.start[c as usize] -= 1;
        }
    }

    /// Robots binned within `margin` cells of the sweep's rectangle, each once, into `out`
    /// (`seen` is scratch of one entry per robot, all `false` on entry and on return).
    pub fn near(&self, s: &Sweep, size: f64, margin: f64, seen: &mut [bool], out: &mut Vec<usize>) {
        out.clear();
        let (x0, x1) = (s.x0.min(s.x1) - margin, s.x0.max(s.x1) + size + margin);
        let (y0, y1) = (s.y0.min(s.y1) - margin, s.y0.max(s.y1) + size + margin);
        for c in self.cells(x0, y0, x1, y1) {
            let (a, b) = (self.start[c as usize], self.start[c as usize + 1]);
            for &j in &self.items[a as usize..b as usize] {
                if !seen[j as usize] {
                    seen[j as usize] = true;
                    out.push(j as usize);
                }
            }
        }
        for &j in out.iter() {
            seen[j] = false;
        }
    }
}

/// Cells of a `width x height` map a rectangle touches (row-major indices), clamped to the map.
fn cell_range(
    width: i64,
    height: i64,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
) -> impl Iterator<Item = u32> {
    let c0 = (x0.floor() as i64).max(0);
    let r0 = (y0.floor() as i64).max(0);
    let c1 = ((x1.ceil() as i64) - 1).min(width - 1);
    let r1 = ((y1.ceil() as i64) - 1).min(height - 1);
    (r0..=r1).flat_map(move |r| (c0..=c1).map(move |c| (r * width + c) as u32))
}

/// Why a robot that asked to act was made to wait.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Held {
    /// The robot.
    pub agent: usize,
    /// The other robot involved, if any.
    pub other: Option<usize>,
    /// The kit's message: `Agent waits instead of F: <reason>`.
    pub message: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Status {
    Unseen,
    Visiting,
    Done,
}

/// One robot being decided: which motion it tries, the robots near it, how far it got, and the
/// robot it waits to see decided.
struct Frame {
    agent: usize,
    requested: bool,
    near: Vec<usize>,
    k: usize,
    pending: Option<usize>,
}

/// The per-tick resolution of the module doc, with scratch kept between ticks.
#[derive(Debug, Clone, Default)]
pub struct Resolver {
    bins: Bins,
    seen: Vec<bool>,
}

impl Resolver {
    /// A resolver for `map`.
    pub fn new(map: &GridMap) -> Self {
        Resolver {
            bins: Bins::new(map),
            seen: Vec::new(),
        }
    }

    /// The actions executed this tick: `requested[i]` where it is safe, else `W`, and why each
    /// robot that asked for something else was held (in robot order). `prev` are the robots'
    /// states before the tick.
    pub fn resolve(
        &mut self,
        map: &GridMap,
        prev: &[TickState],
        requested: &[Action],
        agent_counter: u32,
        agent_size: f64,
    ) -> (Vec<Action>, Vec<Held>) {
        let n = prev.len();
        let corners: Vec<(f64, f64)> = prev.iter().map(|s| corner(map, s, agent_counter)).collect();
        let wanted: Vec<Option<Sweep>> = prev
            .iter()
            .zip(requested)
            .zip(&corners)
            .map(|((s, &a), &c)| {
                after_tick(map, *s, a, agent_counter)
                    .map(|next| Sweep::between(c, corner(map, &next, agent_counter)))
            })
            .collect();
        let still: Vec<Sweep> = corners.iter().map(|&c| Sweep::between(c, c)).collect();
        self.bins.fill(&corners, agent_size);
        self.seen.clear();
        self.seen.resize(n, false);
        let mut status = vec![Status::Unseen; n];
        let mut decided: Vec<Option<Sweep>> = vec![None; n];
        let mut moved = vec![false; n];
        let mut reasons: Vec<Option<(Option<usize>, String)>> = vec![None; n];
        let margin = 1.0 + agent_size;
        let mut stack: Vec<Frame> = Vec::new();
        for root in 0..n {
            if status[root] != Status::Unseen {
                continue;
            }
            status[root] = Status::Visiting;
            stack.push(self.frame(root, true, &wanted, &still, agent_size, margin));
            while let Some(f) = stack.last_mut() {
                let i = f.agent;
                let motion = if f.requested {
                    wanted[i]
                } else {
                    Some(still[i])
                };
                // The outcome of this step for the frame: None = go on, Some(true) = commit,
                // Some(false) = this motion fails.
                let mut outcome = None;
                let mut push = None;
                match motion {
                    None => {
                        note(
                            &mut reasons,
                            i,
                            None,
                            "requested motion is invalid (boundary or hard obstacle)".into(),
                        );
                        outcome = Some(false);
                    }
                    Some(m) => {
                        if let Some(j) = f.pending.take() {
                            let dj = decided[j].unwrap_or(still[j]);
                            if sweeps_collide(&m, &dj, agent_size) {
                                let tail = if moved[j] { "" } else { " (agent waited)" };
                                note(
                                    &mut reasons,
                                    i,
                                    Some(j),
                                    format!("requested motion blocked by agent {j}{tail}"),
                                );
                                outcome = Some(false);
                            } else {
                                f.k += 1;
                            }
                        } else if f.k == f.near.len() {
                            outcome = Some(true);
                        } else {
                            let j = f.near[f.k];
                            if j == i {
                                f.k += 1;
                            } else if let Some(dj) = decided[j] {
                                if sweeps_collide(&m, &dj, agent_size) {
                                    if f.requested {
                                        note(
                                            &mut reasons,
                                            i,
                                            Some(j),
                                            format!(
                                                "requested motion conflicts with resolved agent {j}"
                                            ),
                                        );
                                    }
                                    outcome = Some(false);
                                } else {
                                    f.k += 1;
                                }
                            } else if !(f.requested && sweeps_collide(&m, &still[j], agent_size)) {
                                f.k += 1;
                            } else if status[j] == Status::Visiting {
                                note(
                                    &mut reasons,
                                    i,
                                    Some(j),
                                    format!("dependency cycle through agent {j}"),
                                );
                                outcome = Some(false);
                            } else {
                                f.pending = Some(j);
                                status[j] = Status::Visiting;
                                push = Some(j);
                            }
                        }
                    }
                }
                if let Some(j) = push {
                    let frame = self.frame(j, true, &wanted, &still, agent_size, margin);
                    stack.push(frame);
                    continue;
                }
                match outcome {
                    None => {}
                    Some(true) => {
                        decided[i] = motion;
                        moved[i] = f.requested;
                        status[i] = Status::Done;
                        stack.pop();
                    }
                    Some(false) if f.requested => {
                        let frame = self.frame(i, false, &wanted, &still, agent_size, margin);
                        *stack.last_mut().expect("the frame is on the stack") = frame;
                    }
                    Some(false) => {
                        // Waiting is always kept (the kit's fallback); the validator would
                        // catch an overlap it caused.
                        decided[i] = Some(still[i]);
                        status[i] = Status::Done;
                        stack.pop();
                    }
                }
            }
        }
        let mut held = Vec::new();
        let actions = (0..n)
            .map(|i| {
                if moved[i] {
                    requested[i]
                } else {
                    if !is_wait(requested[i]) {
                        let (other, why) = reasons[i].take().unwrap_or((
                            None,
                            "requested motion rejected by dependency resolution".into(),
                        ));
                        held.push(Held {
                            agent: i,
                            other,
                            message: format!(
                                "Agent waits instead of {}: {why}",
                                requested[i].letter()
                            ),
                        });
                    }
                    Action::Wait
                }
            })
            .collect();
        (actions, held)
    }

    fn frame(
        &mut self,
        agent: usize,
        requested: bool,
        wanted: &[Option<Sweep>],
        still: &[Sweep],
        size: f64,
        margin: f64,
    ) -> Frame {
        let mut near = Vec::new();
        let m = if requested {
            wanted[agent]
        } else {
            Some(still[agent])
        };
        if let Some(m) = m {
            self.bins.near(&m, size, margin, &mut self.seen, &mut near);
        }
        Frame {
            agent,
            requested,
            near,
            k: 0,
            pending: None,
        }
    }
}

/// Keeps the first reason given for robot `i`.
fn note(
    reasons: &mut [Option<(Option<usize>, String)>],
    i: usize,
    other: Option<usize>,
    why: String,
) {
    if reasons[i].is_none() {
        reasons[i] = Some((other, why));
    }
}

/// The first pair of robots whose squares overlap at some instant of the tick from `prev` to
/// `next` (the validator's check; it shares only the geometry with [`Resolver`]).
pub fn first_overlap(
    map: &GridMap,
    prev: &[TickState],
    next: &[TickState],
    agent_counter: u32,
    agent_size: f64,
    bins: &mut Bins,
) -> Option<(usize, usize)> {
    let before: Vec<(f64, f64)> = prev.iter().map(|s| corner(map, s, agent_counter)).collect();
    let sweeps: Vec<Sweep> = next
        .iter()
        .zip(&before)
        .map(|(s, &b)| Sweep::between(b, corner(map, s, agent_counter)))
        .collect();
    bins.fill(&before, agent_size);
    let mut seen = vec![false; prev.len()];
    let mut near = Vec::new();
    for (i, s) in sweeps.iter().enumerate() {
        bins.near(s, agent_size, 1.0 + agent_size, &mut seen, &mut near);
        for &j in &near {
            if j > i && sweeps_collide(s, &sweeps[j], agent_size) {
                return Some((i, j));
            }
        }
    }
    None
}

/// The cell a robot's move in progress (or its next forward move) enters.
pub fn target(map: &GridMap, s: &TickState, a: Action) -> Option<VertexId> {
    match a {
        Action::Forward => neighbour(map, s.state.vertex, s.state.orientation),
        Action::Move(d) => neighbour(map, s.state.vertex, d),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::EAST;

    fn corridor(len: usize) -> GridMap {
        GridMap::from_free_rows(&[vec![true; len]])
    }

    fn at(map: &GridMap, x: i64, o: Orientation) -> TickState {
        TickState::idle(State {
            vertex: map.vertex_at(x, 0).unwrap(),
            orientation: o,
        })
    }

    #[test]
    fn a_move_takes_its_ticks_and_a_wait_pauses_it() {
        let m = corridor(3);
        let s = at(&m, 0, EAST);
        let s1 = after_tick(&m, s, Action::Forward, 3).unwrap();
        assert_eq!((s1.counter, s1.state.vertex), (1, s.state.vertex));
        assert_eq!(corner(&m, &s1, 3), (1.0 / 3.0, 0.0));
        let paused = after_tick(&m, s1, Action::Wait, 3).unwrap();
        assert_eq!(paused, s1);
        // Any other command continues the move in progress.
        let s2 = after_tick(&m, s1, Action::Clockwise, 3).unwrap();
        let s3 = after_tick(&m, s2, Action::Forward, 3).unwrap();
        assert_eq!(s3, at(&m, 1, EAST));
        assert_eq!(after_tick(&m, at(&m, 2, EAST), Action::Forward, 3), None);
    }

    #[test]
    fn followers_go_swaps_wait_and_the_lower_index_enters_first() {
        let m = corridor(4);
        let mut r = Resolver::new(&m);
        // 0 follows 1 east at the same speed: both go.
        let prev = [at(&m, 0, EAST), at(&m, 1, EAST)];
        let (a, held) = r.resolve(&m, &prev, &[Action::Forward, Action::Forward], 2, 1.0);
        assert_eq!(a, vec![Action::Forward, Action::Forward]);
        assert!(held.is_empty());
        // 1 stays: 0 may not enter its cell.
        let (a, held) = r.resolve(&m, &prev, &[Action::Forward, Action::Wait], 2, 1.0);
        assert_eq!(a, vec![Action::Wait, Action::Wait]);
        assert_eq!(held.len(), 1);
        assert!(
            held[0].message.starts_with("Agent waits instead of F"),
            "{}",
            held[0].message
        );
        // Head on: a swap, both wait.
        let prev = [at(&m, 1, EAST), at(&m, 2, 2)];
        let (a, held) = r.resolve(&m, &prev, &[Action::Forward, Action::Forward], 2, 1.0);
        assert_eq!(a, vec![Action::Wait, Action::Wait]);
        assert_eq!(held.len(), 2);
        // Two robots into one cell in one tick: the lower index goes.
        let prev = [at(&m, 0, EAST), at(&m, 2, 2)];
        let (a, _) = r.resolve(&m, &prev, &[Action::Forward, Action::Forward], 1, 1.0);
        assert_eq!(a, vec![Action::Forward, Action::Wait]);
        // In two ticks each, both start (their halves touch), then neither can go on.
        let (a, _) = r.resolve(&m, &prev, &[Action::Forward, Action::Forward], 2, 1.0);
        assert_eq!(a, vec![Action::Forward, Action::Forward]);
        let mid: Vec<TickState> = prev
            .iter()
            .map(|s| after_tick(&m, *s, Action::Forward, 2).unwrap())
            .collect();
        let (a, held) = r.resolve(&m, &mid, &[Action::Forward, Action::Forward], 2, 1.0);
        assert_eq!(a, vec![Action::Wait, Action::Wait]);
        assert!(held[1].message.contains("cycle"), "{}", held[1].message);
        // Small squares may share the corridor more closely, never overlap.
        let (a, _) = r.resolve(&m, &prev, &[Action::Forward, Action::Forward], 2, 0.4);
        let next: Vec<TickState> = prev
            .iter()
            .zip(&a)
            .map(|(s, &x)| after_tick(&m, *s, x, 2).unwrap())
            .collect();
        assert_eq!(
            first_overlap(&m, &prev, &next, 2, 0.4, &mut Bins::new(&m)),
            None
        );
    }

    #[test]
    fn a_long_chain_resolves_without_deep_recursion() {
        let n = 20_000;
        let m = corridor(n + 1);
        let prev: Vec<TickState> = (0..n).map(|x| at(&m, x as i64, EAST)).collect();
        let mut want = vec![Action::Forward; n];
        let mut r = Resolver::new(&m);
        let (a, _) = r.resolve(&m, &prev, &want, 1, 1.0);
        assert!(a.iter().all(|&x| x == Action::Forward));
        want[n - 1] = Action::Wait;
        let (a, held) = r.resolve(&m, &prev, &want, 1, 1.0);
        assert!(a.iter().all(|&x| x == Action::Wait));
        assert_eq!(held.len(), n - 1);
    }
}
