//! A grid plan executed tick by tick under delays (issue 29, items 1–3).
//!
//! **Ticks.** Every move takes `ticks_per_move` ticks of progress (the League's `agentCounter`);
//! waits of the plan are not actions (a robot simply has no move to make). Each tick, first the
//! delays are drawn ([`DelayGenerator`]); then every robot in the middle of a move and not held
//! progresses by one tick; then every idle robot with a move left, not held and not busy this
//! tick, starts its next move if its executor lets it (and makes that tick's progress): a robot
//! progresses at most once a tick. A move finished this tick counts for
//! the executor's checks from the next robot start on; a move started and finished within the same
//! tick (one tick per move) counts from the next tick.
//!
//! **Executors.** `adg`: a robot starts a move once every move it depends on in the action
//! dependency graph ([`Adg`]) is finished (Hönig et al., RA-L 2019); `naive`: a robot starts its
//! `k`-th move at the plan's time of that move (`step x ticks_per_move`) or, when it is late, at
//! once; it may collide; `tpg`: the League of Robot Runners start kit's default executor (v3.1.0,
//! `default_planner/default_executor.cpp`; mrpp's lifelong copy is
//! `mrpp_lifelong::executor`), a temporal plan graph after Ma, Kumar & Koenig, AAAI 2017: per
//! cell, the queue of robots the plan brings there, in the plan's order (the robot starting there
//! first); a robot starts a move when it heads the queue of the cell it enters, and leaves a
//! cell's queue when its move out of that cell is finished. On one-shot plans staged whole this
//! keeps the same order of passage as the ADG, but it has no joint execution of rings: a ring
//! of the plan (each robot entering the cell the next leaves) waits forever, and the execution
//! ends in [`Ending::Deadlock`], as the kit's executor would stop those robots for good.
//!
//! **Rotations.** A plan may move robots in a ring at one step, each into the cell the next
//! leaves (grid plans allow it; LaCAM's do it). Their moves depend on each other, so the ADG alone
//! would wait forever; where the paper is silent mrpp executes such a ring *jointly*: its moves
//! start together once every member is ready, not held and its other dependencies are finished,
//! and progress together, all pausing while any member is held. The ring keeps its shape, so
//! footprints of side at most 0.5 never overlap; larger squares overlap at the ring's corners
//! (the plan's geometry, not lateness), and those collisions are reported like any other.
//!
//! **Positions and footprints.** At the end of a tick a moving robot stands at `from + (to -
//! from) x progress / ticks_per_move`; its footprint is the axis-aligned square of side
//! `agent_size` around that point (the League's `agentSize`). Two footprints collide when they
//! overlap with positive area (squares that only touch do not).

use std::collections::VecDeque;

use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::plan::Plan;
use mrpp_mapf::GridMap;
use serde::Serialize;

use crate::adg::Adg;
use crate::check::OverlapGrid;
use crate::delays::{DelayConfig, DelayGenerator};
use crate::replan::Replanning;

/// Who decides when a robot starts its next move (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExecutorKind {
    /// The action dependency graph (rings executed jointly).
    Adg,
    /// The plan's timing.
    Naive,
    /// The League's default executor: per-cell queues in the plan's order.
    Tpg,
}

impl ExecutorKind {
    pub fn name(self) -> &'static str {
        match self {
            ExecutorKind::Adg => "adg",
            ExecutorKind::Naive => "naive",
            ExecutorKind::Tpg => "tpg",
        }
    }

    /// `adg`, `naive` or `tpg`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "adg" => Some(ExecutorKind::Adg),
            "naive" => Some(ExecutorKind::Naive),
            "tpg" => Some(ExecutorKind::Tpg),
            _ => None,
        }
    }
}

/// How to execute.
#[derive(Debug, Clone)]
pub struct ExecConfig {
    pub executor: ExecutorKind,
    /// Ticks of progress per move (`agentCounter`), at least 1.
    pub ticks_per_move: u32,
    pub delays: DelayConfig,
    /// The delays' seed.
    pub seed: u64,
    /// Side of a robot's square footprint in cells (`agentSize`), in (0, 1].
    pub agent_size: f64,
    /// The execution stops here if robots are still moving (a safety net).
    pub max_ticks: u64,
}

/// How an execution ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ending {
    /// Every robot made all its moves.
    Finished,
    /// No robot could progress and none was held (the ADG of a valid plan never does this;
    /// `tpg` does at a ring of the plan, module doc).
    Deadlock { tick: u64 },
    /// `max_ticks` passed.
    TickLimit,
}

/// Two footprints overlapping at the end of a tick.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Collision {
    pub tick: u64,
    pub robots: [usize; 2],
    pub at: [[f64; 2]; 2],
}

/// What was executed.
#[derive(Debug, Clone, Serialize)]
pub struct Execution {
    /// Per robot, per move of the plan (waits dropped): `[first tick, tick after the last]`.
    pub moves: Vec<Vec<[u64; 2]>>,
    /// Per robot, its delays `[first tick, tick after the last]`.
    pub delays: Vec<Vec<[u64; 2]>>,
    /// Ticks executed.
    pub ticks: u64,
    pub ending: Ending,
    /// Every collision of the execution (end-of-tick footprints), in tick order.
    pub collisions: Vec<Collision>,
    /// Rings executed jointly (`adg`; module doc): `(robot, move)` pairs.
    pub rotations: Vec<Vec<(usize, usize)>>,
    /// Ticks at which a re-plan took over (re-planning on drift).
    pub replans: Vec<u64>,
    pub metrics: ExecMetrics,
}

/// What an execution measures (ticks).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ExecMetrics {
    /// The tick after every robot's last move.
    pub makespan: u64,
    /// Sum over robots of the tick after its last move.
    pub sum_of_costs: u64,
    /// The same for the plan executed without delays on its own timing.
    pub planned_makespan: u64,
    pub planned_sum_of_costs: u64,
    /// Executed / planned (1 when the plan has no move).
    pub makespan_ratio: f64,
    pub sum_of_costs_ratio: f64,
    /// Ticks robots were held by a delay before their last move was done.
    pub ticks_lost_to_delays: u64,
    /// Ticks robots stood ready (not held, a move left) waiting for a dependency (`adg`) or for
    /// the plan's time (`naive`) beyond the plan's own waits.
    pub waits_added: u64,
    pub collisions: usize,
    /// Plans that took over from the one before (re-planning on drift; 0 without it).
    pub replans: usize,
    /// Re-planning attempts whose planner found no plan (the execution went on with its plan).
    pub failed_replans: usize,
}

/// Cell centres of the map's vertices.
fn centre(map: &GridMap, v: VertexId) -> [f64; 2] {
    let (x, y) = map.cell(v);
    [f64::from(x) + 0.5, f64::from(y) + 0.5]
}

/// Per cell, the robots `plan` brings there in its order of passage, each robot's start first
/// (the `tpg` executor's queues; module doc).
fn cell_queues(plan: &Plan, cells: usize) -> Vec<VecDeque<u32>> {
    let mut stays: Vec<(VertexId, usize, u32)> = Vec::new();
    for (i, path) in plan.paths.iter().enumerate() {
        if let Some(&start) = path.first() {
            stays.push((start, 0, i as u32));
        }
        for (t, w) in path.windows(2).enumerate() {
            if w[0] != w[1] {
                stays.push((w[1], t + 1, i as u32));
            }
        }
    }
    stays.sort_unstable();
    let mut queues = vec![VecDeque::new(); cells];
    for (v, _, i) in stays {
        queues[v as usize].push_back(i);
    }
    queues
}

/// Executes `plan` on `map` (module doc).
pub fn execute(map: &GridMap, plan: &Plan, cfg: &ExecConfig) -> Execution {
    execute_replanning(map, plan, cfg, None).0
}

/// The ring of each `(robot, move)` of `rotations`, `usize::MAX` for none.
fn rings_of(adg: &Adg, rotations: &[Vec<(usize, usize)>]) -> Vec<Vec<usize>> {
    let mut ring_of: Vec<Vec<usize>> = adg
        .moves
        .iter()
        .map(|m| vec![usize::MAX; m.len()])
        .collect();
    for (g, members) in rotations.iter().enumerate() {
        for &(i, k) in members {
            ring_of[i][k] = g;
        }
    }
    ring_of
}

/// Executes `plan` on `map` (module doc), re-planning when the execution drifts from its plan
/// if `replanning` says how ([`crate::replan`]). Returns the execution and the plan its record
/// follows: `plan` itself without re-planning, else `plan`'s executed prefix, then each later
/// plan's executed prefix, then the last plan whole (the record's moves are that plan's moves,
/// waits dropped; [`crate::check::check`] replays the record against it).
pub fn execute_replanning(
    map: &GridMap,
    plan: &Plan,
    cfg: &ExecConfig,
    mut replanning: Option<Replanning<'_>>,
) -> (Execution, Plan) {
    let n = plan.paths.len();
    let mut cur = plan.clone();
    let mut executed = plan.clone();
    // `executed`'s path index at which `cur` starts.
    let mut offset = 0usize;
    let mut adg = Adg::new(&cur);
    let joint = |adg: &Adg| {
        if cfg.executor == ExecutorKind::Adg {
            adg.rotation_cycles()
        } else {
            Vec::new()
        }
    };
    let mut rotations = joint(&adg);
    let mut ring_of = rings_of(&adg, &rotations);
    let cells = map.graph().num_vertices();
    let tpg = cfg.executor == ExecutorKind::Tpg;
    let queues_of = |plan: &Plan| {
        if tpg {
            cell_queues(plan, cells)
        } else {
            Vec::new()
        }
    };
    let mut queues = queues_of(&cur);
    // Robots whose one-tick move finished this tick: they leave their cell's queue at its end.
    let mut leaving: Vec<(VertexId, u32)> = Vec::new();
    let ring = |ring_of: &[Vec<usize>], i: usize, k: usize| {
        ring_of[i].get(k).copied().filter(|&g| g != usize::MAX)
    };
    // Rings of finished segments, as `(robot, move of the whole record)`.
    let mut all_rings: Vec<Vec<(usize, usize)>> = Vec::new();
    // Moves recorded before the current plan took over.
    let mut base = vec![0usize; n];
    // The tick at which the current plan took over (its step 0).
    let mut t0 = 0u64;
    let mut retry_at = 0u64;
    let (mut replans, mut failed_replans) = (Vec::new(), 0usize);
    let mut grid = OverlapGrid::new(map.width(), map.height());
    let (mut busy, mut finished) = (vec![false; n], vec![0usize; n]);
    let centres: Vec<[f64; 2]> = (0..map.graph().num_vertices() as VertexId)
        .map(|v| centre(map, v))
        .collect();
    let mut points = Vec::with_capacity(n);
    let c = u64::from(cfg.ticks_per_move.max(1));
    let mut delays = DelayGenerator::new(cfg.delays.clone(), n, cfg.seed);
    // Per robot: moves of the current plan done, the move in progress and its progress.
    let mut done = vec![0usize; n];
    let mut progress: Vec<Option<u64>> = vec![None; n];
    let mut record: Vec<Vec<[u64; 2]>> = adg
        .moves
        .iter()
        .map(|m| Vec::with_capacity(m.len()))
        .collect();
    let mut collisions = Vec::new();
    let (mut lost, mut waits) = (0u64, 0u64);
    let planned_finish: Vec<u64> = adg
        .moves
        .iter()
        .map(|m| m.last().map_or(0, |l| (u64::from(l.step) + 1) * c))
        .collect();
    let mut starts: Vec<VertexId> = cur
        .paths
        .iter()
        .map(|p| p.first().copied().unwrap_or(0))
        .collect();
    let mut tick = 0u64;
    let ending = loop {
        if (0..n).all(|i| done[i] == adg.moves[i].len()) {
            break Ending::Finished;
        }
        if tick >= cfg.max_ticks {
            break Ending::TickLimit;
        }
        // Drift: a robot that should have started its next move more than `drift` ticks ago.
        if let Some(r) = replanning.as_mut().filter(|_| tick >= retry_at) {
            let lags = (0..n).any(|i| {
                progress[i].is_none()
                    && done[i] < adg.moves[i].len()
                    && tick > t0 + u64::from(adg.moves[i][done[i]].step) * c + r.drift
            });
            if lags {
                // Where each robot will stand once its move in progress is done.
                let at: Vec<VertexId> = (0..n)
                    .map(|i| match (progress[i], done[i]) {
                        (Some(_), k) => adg.moves[i][k].to,
                        (None, 0) => starts[i],
                        (None, k) => adg.moves[i][k - 1].to,
                    })
                    .collect();
                match (r.planner)(&at).filter(|p| {
                    p.paths.len() == n
                        && p.paths.iter().zip(&at).all(|(p, &v)| p.first() == Some(&v))
                }) {
                    Some(mut next) => {
                        // Moves in progress become the new plan's first step (the others wait
                        // it out), so its ADG orders them before any move into their cells.
                        if progress.iter().any(Option::is_some) {
                            for (i, path) in next.paths.iter_mut().enumerate() {
                                let from = match progress[i] {
                                    Some(_) => adg.moves[i][done[i]].from,
                                    None => path[0],
                                };
                                path.insert(0, from);
                            }
                        }
                        all_rings.extend(
                            rotations
                                .iter()
                                .filter(|r| r.iter().all(|&(i, k)| k < done[i]))
                                .map(|r| r.iter().map(|&(i, k)| (i, base[i] + k)).collect()),
                        );
                        offset = crate::replan::cut(&mut executed, offset, &adg, &done);
                        crate::replan::append(&mut executed, &next);
                        for i in 0..n {
                            base[i] += done[i];
                            done[i] = 0;
                        }
                        cur = next;
                        adg = Adg::new(&cur);
                        rotations = joint(&adg);
                        ring_of = rings_of(&adg, &rotations);
                        queues = queues_of(&cur);
                        starts = cur.paths.iter().map(|p| p[0]).collect();
                        t0 = tick;
                        replans.push(tick);
                    }
                    None => {
                        failed_replans += 1;
                        retry_at = tick + r.drift.max(1);
                    }
                }
            }
        }
        delays.next_tick();
        let mut moved = false;
        let mut held_any = false;
        // A robot progresses once a tick: one that finishes a move now starts the next one later.
        busy.iter_mut().for_each(|b| *b = false);
        // Rings under way pause while any member is held.
        let paused: Vec<bool> = rotations
            .iter()
            .map(|members| {
                members
                    .iter()
                    .any(|&(j, m)| done[j] == m && progress[j].is_some() && delays.delayed(j))
            })
            .collect();
        // Moves in progress.
        for i in 0..n {
            let Some(p) = progress[i] else { continue };
            if delays.delayed(i) {
                held_any = true;
                lost += 1;
                continue;
            }
            if ring(&ring_of, i, done[i]).is_some_and(|g| paused[g]) {
                held_any = true;
                waits += 1;
                continue;
            }
            moved = true;
            busy[i] = true;
            if p + 1 == c {
                progress[i] = None;
                record[i].last_mut().expect("a move in progress")[1] = tick + 1;
                if tpg {
                    leave(&mut queues, adg.moves[i][done[i]].from, i as u32);
                }
                done[i] += 1;
            } else {
                progress[i] = Some(p + 1);
            }
        }
        // Starts, judged on the moves finished before them.
        finished.clone_from(&done);
        let ready = |j: usize, m: usize| {
            finished[j] == m && progress[j].is_none() && !busy[j] && !delays.delayed(j)
        };
        // Rings that start this tick: every member ready, every outside dependency finished.
        let starting: Vec<bool> = rotations
            .iter()
            .map(|members| {
                members.iter().all(|&(j, m)| {
                    ready(j, m)
                        && adg.deps[j][m]
                            .iter()
                            .all(|&d| members.contains(&d) || finished[d.0] > d.1)
                })
            })
            .collect();
        for i in 0..n {
            if busy[i] || progress[i].is_some() || done[i] == adg.moves[i].len() {
                continue;
            }
            if delays.delayed(i) {
                held_any = true;
                lost += 1;
                continue;
            }
            let k = done[i];
            let planned = t0 + u64::from(adg.moves[i][k].step) * c;
            let go = match (cfg.executor, ring(&ring_of, i, k)) {
                (ExecutorKind::Adg, Some(g)) => starting[g],
                (ExecutorKind::Adg, None) => adg.deps[i][k].iter().all(|&(j, m)| finished[j] > m),
                (ExecutorKind::Naive, _) => tick >= planned,
                (ExecutorKind::Tpg, _) => {
                    queues[adg.moves[i][k].to as usize].front() == Some(&(i as u32))
                }
            };
            if !go {
                // Beyond the plan's own waits: the plan would have this move under way by now.
                if tick >= planned {
                    waits += 1;
                }
                continue;
            }
            moved = true;
            record[i].push([tick, tick + 1]);
            if c == 1 {
                if tpg {
                    leaving.push((adg.moves[i][k].from, i as u32));
                }
                done[i] += 1;
            } else {
                progress[i] = Some(1);
            }
        }
        for (v, i) in leaving.drain(..) {
            leave(&mut queues, v, i);
        }
        tick += 1;
        positions(&centres, &adg, &starts, &done, &progress, c, &mut points);
        grid.overlaps(&points, cfg.agent_size, tick - 1, &mut collisions);
        if !moved && !held_any && cfg.executor != ExecutorKind::Naive {
            break Ending::Deadlock { tick: tick - 1 };
        }
    };
    // The current plan is the executed plan's end, its rings all in it (executed or not).
    all_rings.extend(
        rotations
            .iter()
            .map(|r| r.iter().map(|&(i, k)| (i, base[i] + k)).collect()),
    );
    let finish: Vec<u64> = record
        .iter()
        .map(|r| r.last().map_or(0, |m| m[1]))
        .collect();
    let makespan = finish.iter().copied().max().unwrap_or(0);
    let soc: u64 = finish.iter().sum();
    let planned_makespan = planned_finish.iter().copied().max().unwrap_or(0);
    let planned_soc: u64 = planned_finish.iter().sum();
    let ratio = |a: u64, b: u64| if b == 0 { 1.0 } else { a as f64 / b as f64 };
    let execution = Execution {
        metrics: ExecMetrics {
            makespan,
            sum_of_costs: soc,
            planned_makespan,
            planned_sum_of_costs: planned_soc,
            makespan_ratio: ratio(makespan, planned_makespan),
            sum_of_costs_ratio: ratio(soc, planned_soc),
            ticks_lost_to_delays: lost,
            waits_added: waits,
            collisions: collisions.len(),
            replans: replans.len(),
            failed_replans,
        },
        moves: record,
        delays: delays.intervals,
        ticks: tick,
        ending,
        collisions,
        rotations: all_rings,
        replans,
    };
    (execution, executed)
}

/// Robot `i` leaves the queue of cell `v` (it heads it: it stood there).
fn leave(queues: &mut [VecDeque<u32>], v: VertexId, i: u32) {
    let q = &mut queues[v as usize];
    debug_assert_eq!(q.front(), Some(&i), "a robot leaves a cell it heads");
    if q.front() == Some(&i) {
        q.pop_front();
    }
}

/// Every robot's point at the end of a tick, into `out` (`centres` of the map's vertices).
fn positions(
    centres: &[[f64; 2]],
    adg: &Adg,
    starts: &[VertexId],
    done: &[usize],
    progress: &[Option<u64>],
    c: u64,
    out: &mut Vec<[f64; 2]>,
) {
    out.clear();
    out.extend((0..done.len()).map(|i| {
        let ms = &adg.moves[i];
        match progress[i] {
            Some(p) => {
                let m = ms[done[i]];
                let (a, b) = (centres[m.from as usize], centres[m.to as usize]);
                let f = p as f64 / c as f64;
                [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f]
            }
            None if done[i] == 0 => centres[starts[i] as usize],
            None => centres[ms[done[i] - 1].to as usize],
        }
    }));
}
