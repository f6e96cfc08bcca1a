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
//! Run with `cargo bench -p mrpp --bench planners`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

use mrpp::grid_mapf::{PlannerSpec, build_planner};
use mrpp::solve::{Deadline, Planner, SolveOptions, solve};
use mrpp::{GridMap, Instance, ValidateOptions};

/// Generous per-call wall-clock limit.
const TIME_LIMIT: Duration = Duration::from_secs(60);
/// Samples per benchmark (criterion's minimum).
const SAMPLES: usize = 10;
/// Measurement time of a benchmark whose calls are fast.
const MEASUREMENT: Duration = Duration::from_secs(5);

/// One benchmark instance, loaded once.
struct Case {
    name: &'static str,
    map: GridMap,
    inst: Instance,
}

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data")
}

fn load_case(name: &'static str, map: &str, scen: &str, agents: Option<usize>) -> Case {
    let dir = data_dir();
    let map_path = dir.join(map);
    let scen_path = dir.join(scen);
    let map = GridMap::load(&map_path)
        .unwrap_or_else(|e| panic!("cannot load map {}: {e}", map_path.display()));
    let inst = Instance::load(&scen_path, &map, agents)
        .unwrap_or_else(|e| panic!("cannot load scenario {}: {e}", scen_path.display()));
    Case { name, map, inst }
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

fn planners() -> Vec<(&'static str, Box<dyn Planner>)> {
    let hstar = PlannerSpec {
        name: "hstar".into(),
        ..PlannerSpec::default()
    };
    let whca = PlannerSpec {
        name: "whca".into(),
        window: Some(8),
        ..PlannerSpec::default()
    };
    vec![
        ("hstar", build_planner(&hstar).expect("hstar spec is valid")),
        ("whca8", build_planner(&whca).expect("whca spec is valid")),
    ]
}

fn options() -> SolveOptions {
    SolveOptions {
        seed: 0,
        deadline: Deadline::after(TIME_LIMIT),
    }
}

/// Solves once (untimed), prints the outcome and its quality on stderr, and returns how long the
/// call took (used to size the measurement time).
fn report_quality(label: &str, planner: &dyn Planner, case: &Case) -> Duration {
    let graph = case.map.graph();
    let started = Instant::now();
    let outcome = solve(planner, graph, &case.inst, &options());
    let elapsed = started.elapsed();
    match outcome {
        Ok(plan) => match plan.validate(graph, &case.inst, ValidateOptions::default()) {
            Ok(m) => eprintln!(
                "quality {label}/{}: solved=true agents={} sum_of_costs={} makespan={} sum_of_moves={}",
                case.name,
                case.inst.num_agents(),
                m.sum_of_costs,
                m.makespan,
                m.sum_of_moves
            ),
            // `solve` only returns validated plans, so this is not expected; record, don't panic.
            Err(v) => eprintln!(
                "quality {label}/{}: solved=false (plan rejected: {})",
                case.name,
                v.describe(graph)
            ),
        },
        Err(why) => eprintln!(
            "quality {label}/{}: solved=false agents={} reason={why}",
            case.name,
            case.inst.num_agents()
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
            let graph = case.map.graph();
            group.bench_with_input(BenchmarkId::new(*label, case.name), case, |b, case| {
                b.iter(|| {
                    // A fresh deadline per call; building it costs next to nothing.
                    let opts = options();
                    black_box(solve(
                        planner.as_ref(),
                        black_box(graph),
                        black_box(&case.inst),
                        &opts,
                    ))
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_planners);
criterion_main!(benches);
