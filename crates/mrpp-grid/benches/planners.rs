//! Planner benchmarks: H* and WHCA* (window 8) on two instances.
//!
//! - `warehouse-30`: the H* paper's scenario 3 (`scenery_warehouse.txt`, robots `30warehouse`).
//! - `random-32-32-20-a100`: MovingAI `random-32-32-20.map`, `random-1.scen`, first 100 agents.
//!
//! Files are loaded once, outside the timed loop; only `solve(...)` (planning plus the validator
//! check it always runs) is timed. Before timing, each (planner, instance) pair is solved once and
//! its outcome (solved or not, sum of costs, makespan) is printed on stderr, so a report can give
//! quality next to time. An unsolved instance is recorded, never a panic: the benchmark still times
//! the call that returns "not solved".
//!
//! Run with `cargo bench -p mrpp-grid --bench planners`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

use mrpp_core::registry::find;
use mrpp_core::{Ctx, Deadline, MapfProblem, Planner, Problem, solve};
use mrpp_grid::PLANNERS;

/// Generous per-call wall-clock limit.
const TIME_LIMIT: Duration = Duration::from_secs(60);
/// Samples per benchmark (criterion's minimum).
const SAMPLES: usize = 10;
/// Measurement time of a benchmark whose calls are fast.
const MEASUREMENT: Duration = Duration::from_secs(5);

/// One benchmark instance, loaded once.
struct Case {
    name: &'static str,
    problem: MapfProblem,
}

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data")
}

fn load_case(name: &'static str, map: &str, scen: &str, agents: Option<usize>) -> Case {
    let dir = data_dir();
    let map_path = dir.join(map);
    let scen_path = dir.join(scen);
    let (_, problem) = mrpp_grid::load_problem(&map_path, &scen_path, agents)
        .unwrap_or_else(|e| panic!("cannot load {name}: {e}"));
    Case { name, problem }
}

fn cases() -> Vec<Case> {
    vec![
        load_case(
            "warehouse-30",
            "hstar-paper/scenario3/scenery_warehouse.txt",
            "hstar-paper/scenario3/30warehouse",
            None,
        ),
        load_case(
            "random-32-32-20-a100",
            "movingai/random-32-32-20.map",
            "movingai/random-32-32-20-random-1.scen",
            Some(100),
        ),
    ]
}

fn planners() -> Vec<(&'static str, Box<dyn Planner<MapfProblem>>)> {
    let build = |name: &str, params: &[(String, String)]| {
        find(PLANNERS, name)
            .and_then(|e| e.instantiate(params).ok())
            .unwrap_or_else(|| panic!("{name} is registered"))
    };
    vec![
        ("hstar", build("hstar", &[])),
        ("whca8", build("whca", &[("window".into(), "8".into())])),
    ]
}

fn options() -> Ctx {
    Ctx::new(0, Deadline::after(TIME_LIMIT))
}

/// Solves once (untimed), prints the outcome and its quality on stderr, and returns how long the
/// call took (used to size the measurement time).
fn report_quality(label: &str, planner: &dyn Planner<MapfProblem>, case: &Case) -> Duration {
    let started = Instant::now();
    let outcome = solve(planner, &case.problem, &options());
    let elapsed = started.elapsed();
    let agents = case.problem.num_agents();
    match outcome {
        Ok(solved) => {
            let m = solved.metrics;
            eprintln!(
                "quality {label}/{}: solved=true agents={agents} sum_of_costs={} makespan={} sum_of_moves={}",
                case.name, m.sum_of_costs, m.makespan, m.sum_of_moves
            )
        }
        Err(why) => eprintln!(
            "quality {label}/{}: solved=false agents={agents} reason={why}",
            case.name
        ),
    }
    elapsed
}

fn bench_planners(c: &mut Criterion) {
    let cases = cases();
    let planners = planners();
    let mut group = c.benchmark_group("planners");
    group
        .sample_size(SAMPLES)
        .warm_up_time(Duration::from_secs(1));
    for case in &cases {
        for (label, planner) in &planners {
            let once = report_quality(label, planner.as_ref(), case);
            // Enough time for SAMPLES slow calls, so criterion need not stretch (and warn).
            group.measurement_time(MEASUREMENT.max(once * (SAMPLES as u32 + 2)));
            group.bench_with_input(BenchmarkId::new(*label, case.name), case, |b, case| {
                b.iter(|| {
                    // A fresh deadline per call; building it costs next to nothing.
                    let opts = options();
                    black_box(solve(planner.as_ref(), black_box(&case.problem), &opts))
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_planners);
criterion_main!(benches);
