//! One navigation step (targets, heading optimisation, repair) for 10 robots among 4 obstacles,
//! per optimiser at its default settings, joint and per-robot mode: the bar is 1 ms per
//! step. `cargo bench -p mrpp-continuous --bench step`.

use criterion::{Criterion, criterion_group, criterion_main};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use mrpp_continuous::generator::random_world;
use mrpp_continuous::navigate::{Mode, Navigation};
use mrpp_continuous::{NavProblem, PLANNERS};
use mrpp_evo::de::De;
use mrpp_evo::hbmo::Hbmo;
use mrpp_evo::pso::Pso;
use mrpp_evo::space::Minimizer;

fn step(c: &mut Criterion) {
    let p = NavProblem::new(random_world(10, 4, 1).expect("a world"));
    let w = p.world();
    let pos: Vec<[f64; 2]> = w.robots.iter().map(|r| r.start).collect();
    let moving: Vec<usize> = (0..w.robots.len()).collect();
    let optimizers: [(&str, Box<dyn Minimizer>); 3] = [
        ("hbmo", Box::new(Hbmo::default())),
        ("de", Box::new(De::default())),
        ("pso", Box::new(Pso::default())),
    ];
    assert_eq!(PLANNERS.len(), optimizers.len());
    for mode in [Mode::Joint, Mode::PerRobot] {
        let nav = Navigation {
            mode,
            ..Navigation::default()
        };
        let (targets, _) = nav.targets(&p, &pos);
        for (name, opt) in &optimizers {
            let mut rng = ChaCha8Rng::seed_from_u64(1);
            c.bench_function(&format!("step 10 robots {name} {mode:?}"), |b| {
                b.iter(|| nav.step(&p, &pos, &targets, &moving, opt.as_ref(), &mut rng))
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = step
}
criterion_main!(benches);
