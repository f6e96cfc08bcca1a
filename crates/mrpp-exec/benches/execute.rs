//! Issue 29's execution benchmark: `mrpp execute` on a 1,000-agent LaCAM plan builds the action
//! dependency graph and executes about 10,000 ticks under Bernoulli delays, one core.
//!
//! The plan (MovingAI `warehouse-20-40-10-2-2.map`, `random-1.scen`, first 1,000 agents, LaCAM,
//! seed 0) is made once, outside the timed loop; its makespan sets the ticks per move so that
//! the delay-free execution lasts at least 10,000 ticks. Timed: [`mrpp_exec::execute`] (the ADG
//! built from the plan, then every tick: delays drawn, robots started and advanced, footprints
//! checked). Before timing, one execution's ticks, collisions and ratios are printed on stderr.
//!
//! Run with `cargo bench -p mrpp-exec --bench execute`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};

use mrpp_core::{Ctx, Deadline, solve};
use mrpp_exec::{DelayConfig, ExecConfig, ExecutorKind, execute};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/movingai")
        .join(rel)
}

fn bench(c: &mut Criterion) {
    let (map, problem) = mrpp_grid::load_problem(
        &data("warehouse-20-40-10-2-2.map"),
        &data("warehouse-20-40-10-2-2-random-1.scen"),
        Some(1000),
    )
    .expect("the bundled warehouse map and scenario");
    let lacam = mrpp_grid::PLANNERS
        .iter()
        .find(|e| e.name == "lacam")
        .expect("lacam is registered")
        .instantiate(&[])
        .expect("default parameters");
    let ctx = Ctx {
        deadline: Deadline::after(Duration::from_secs(120)),
        ..Ctx::default()
    };
    let plan = solve(lacam.as_ref(), &problem, &ctx)
        .expect("LaCAM solves 1,000 agents on the warehouse")
        .plan;
    let makespan = plan.paths.iter().map(Vec::len).max().unwrap_or(1) as u32;
    let ticks_per_move = 10_000u32.div_ceil(makespan.max(1));
    for executor in [ExecutorKind::Adg, ExecutorKind::Naive] {
        let cfg = ExecConfig {
            executor,
            ticks_per_move,
            delays: DelayConfig::parse("bernoulli:p=0.001,min=1,max=10").expect("a valid spec"),
            seed: 0,
            agent_size: 0.5,
            max_ticks: 1_000_000,
        };
        let run = execute(&map, &plan, &cfg);
        eprintln!(
            "{}: 1,000 agents, plan makespan {makespan} steps x {ticks_per_move} ticks; executed {} ticks, {:?}, {} collisions, makespan ratio {:.3}",
            executor.name(),
            run.ticks,
            run.ending,
            run.metrics.collisions,
            run.metrics.makespan_ratio
        );
        let mut group = c.benchmark_group("execute");
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(20));
        group.bench_function(format!("{}-1000-agents-10k-ticks", executor.name()), |b| {
            b.iter(|| black_box(execute(&map, black_box(&plan), &cfg)));
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
