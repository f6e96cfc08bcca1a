//! GP benchmarks on the bundled tree problem `data/trees/example.json` (37 nodes, 18 robots):
//!
//! - `gp/evaluate/bundled-program`: one fitness evaluation (equation (1), cap M) of the bundled
//!   11-node program `data/trees/example-program.gp`, which solves the problem in 70 steps — the
//!   unit of work of the evolution;
//! - `gp/evaluate/population`: the fitness of 200 random initial programs (depth ≤ 2), i.e. one
//!   generation of the default settings without the cache, in parallel;
//! - `gp/evolve/default`: a whole default evolution (|P| = 200, 2 × 25 generations).
//!
//! The paper-settings run (|P| = 2000, 5 × 400 generations) takes about 15 s and is measured with
//! `mrpp trees solve --paper-settings` instead (see docs/performance.md).
//!
//! Run with `cargo bench -p mrpp-trees --bench gp`.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use rayon::prelude::*;

use mrpp_core::contract::Deadline;
use mrpp_trees::TreeInstance;
use mrpp_trees::gp::evolve::initial_population;
use mrpp_trees::gp::{GpParams, Problem, Program, calculate_fitness, evolve};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/trees")
        .join(rel)
}

fn bench_gp(c: &mut Criterion) {
    let tree = TreeInstance::load(&data("example.json")).expect("bundled instance");
    let problem = Problem::from_tree_instance(&tree);
    let problems = std::slice::from_ref(&problem);
    let program = Program::load(&data("example-program.gp")).expect("bundled program");
    let paper = GpParams::paper();
    let params = GpParams::default();
    let mut group = c.benchmark_group("gp");
    group.sample_size(10);
    group.bench_function("evaluate/bundled-program", |b| {
        b.iter(|| {
            calculate_fitness(
                black_box(&program),
                problems,
                &paper,
                None,
                Deadline::none(),
            )
        })
    });
    let population = initial_population(&params, 7, 0);
    group.bench_function("evaluate/population", |b| {
        b.iter(|| {
            population
                .par_iter()
                .map(|p| {
                    calculate_fitness(p, problems, &params, None, Deadline::none())
                        .expect("no deadline")
                        .fitness
                })
                .sum::<u64>()
        })
    });
    group.bench_function("evolve/default", |b| {
        b.iter(|| evolve(problems, &params, 1, Deadline::none(), &mut |_| {}).map(|r| r.best_steps))
    });
    group.finish();
}

criterion_group!(benches, bench_gp);
criterion_main!(benches);
