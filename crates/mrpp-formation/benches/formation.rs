//! Formation benchmarks: the roadmap build of each bundled public map (radius 0.3), and the GA
//! (the paper's population 20, R = 3) on `data/formation/var_density2-3.json` with 0 and 20
//! generations — the difference / 20 is the time per generation (the bars: roadmap
//! <= 20 ms, generation <= 2 ms; the paper: about 0.2 s per generation in Python).
//!
//! Run with `cargo bench -p mrpp-formation --bench formation`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};

use mrpp_core::Ctx;
use mrpp_formation::ga::Ga;
use mrpp_formation::polymap::PolygonMap;
use mrpp_formation::roadmap::{RoadmapOptions, build_roadmap};
use mrpp_formation::world::Formation;

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data")
        .join(rel)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("formation");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_secs(1));
    for name in ["gaps", "potholes", "var_density2"] {
        let map = PolygonMap::load(&data(&format!("polygon-maps/{name}.txt"))).unwrap();
        let opts = RoadmapOptions {
            radius: 0.3,
            ..RoadmapOptions::default()
        };
        g.bench_function(format!("roadmap/{name}"), |b| {
            b.iter(|| black_box(build_roadmap(&map, &opts)))
        });
    }
    let f = Formation::load(&data("formation/var_density2-3.json")).unwrap();
    for generations in [0, 20] {
        let ga = Ga {
            generations,
            ..Ga::default()
        };
        g.bench_function(
            format!("ga/var_density2-3/generations-{generations}"),
            |b| b.iter(|| black_box(ga.run(&f.problem, &Ctx::default()))),
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
