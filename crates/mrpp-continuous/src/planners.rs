//! The continuous planners, each registered in [`crate::PLANNERS`]: the HBMO paper's per-step
//! navigation ([`crate::navigate`]) with its three heading optimisers from `mrpp-evo` — `hbmo`
//! (the paper's method, Table 1 parameters as defaults), `de` (DE/rand/1/bin) and `pso`
//! (inertia-weight PSO), the paper's comparison methods. Every planner takes the navigation
//! parameters (`mode`, `guide`, `obstacle_term`, `f_dp`, `f_st`, `deadlock_steps`, `snap`) and its
//! optimiser's.

use mrpp_core::registry::Params;
use mrpp_core::{Ctx, Param, Planner, PlannerEntry, Unsolved};
use mrpp_evo::de::De;
use mrpp_evo::hbmo::FitnessScale;
use mrpp_evo::hbmo::Hbmo;
use mrpp_evo::pso::Pso;
use mrpp_evo::space::Minimizer;

use crate::navigate::{Guide, HeadingSearch, Mode, Navigation};
use crate::objective::{Objective, ObstacleTerm};
use crate::orca::{Orca, OrcaRun};
use crate::problem::{NavProblem, Trajectories};

/// The loop's parameters (every planner, ORCA included), then the planner's own.
macro_rules! loop_params {
    ($($own:expr),* $(,)?) => {
        &[
            Param { name: "guide", default: "waypoints", doc: "waypoints (aim at the farthest visible point of the ideal path; beyond the paper) or goal (the paper)" },
            Param { name: "deadlock_steps", default: "50", doc: "steps without progress reported as a deadlock" },
            Param { name: "snap", default: "true", doc: "aim exactly at the goal when within one step of it" },
            $($own),*
        ]
    };
}

/// The heading optimisers' parameters: the loop's, the mode and the objective's, then their own.
macro_rules! nav_params {
    ($($own:expr),* $(,)?) => {
        loop_params![
            Param { name: "mode", default: "joint", doc: "joint (one optimisation of all headings, the paper's text) or per-robot (the pseudo-code's loop)" },
            Param { name: "obstacle_term", default: "near", doc: "near (f_st/d within a diameter of obstacles) or inverse (f_st/d everywhere, the paper literally)" },
            Param { name: "f_dp", default: "100", doc: "weight of overlapping robots in the objective (paper 100)" },
            Param { name: "f_st", default: "5000", doc: "weight of closeness to obstacles in the objective (paper 5000)" },
            Param { name: "straight_init", default: "true", doc: "give the optimiser \"every robot heads straight to its target\" as an initial point (beyond the paper: false)" },
            Param { name: "preset", default: "none", doc: "none, or paper: the paper-literal choices (guide=goal, obstacle_term=inverse, straight_init=false; hbmo also brood_drones=true, mating=absolute); explicit -p values override it" },
            $($own),*
        ]
    };
}

/// What `preset=paper` sets for every heading planner (`hbmo`, `de`, `pso`): the distance term
/// measured to the goal (eq. 5–7), `f_st / d` everywhere (eq. 7), and no straight-to-target
/// initial point (§4: "Initialize all the bees").
pub const PAPER_NAV: &[(&str, &str)] = &[
    ("guide", "goal"),
    ("obstacle_term", "inverse"),
    ("straight_init", "false"),
];

/// What `preset=paper` sets for `hbmo` beyond [`PAPER_NAV`]: failed broods become drones (§3,
/// last sentence) and the mating probability uses the absolute fitness difference (eq. 8).
pub const PAPER_HBMO: &[(&str, &str)] = &[("brood_drones", "true"), ("mating", "absolute")];

/// `p` with the preset it names applied: for `preset=paper`, every key of `paper` the user did
/// not set explicitly takes the paper's value; `preset=none` leaves `p` as it is.
fn with_preset(
    planner: &str,
    declared: &[Param],
    p: &Params,
    paper: &[&[(&str, &str)]],
) -> mrpp_core::error::Result<Params> {
    if p.choice("preset", &["none", "paper"])? == 0 {
        return Ok(p.clone());
    }
    let mut given: Vec<(String, String)> = paper
        .iter()
        .flat_map(|set| set.iter())
        .filter(|(k, _)| !p.is_given(k))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    given.extend(
        p.iter()
            .filter(|(k, _)| p.is_given(k))
            .map(|(k, v)| (k.to_string(), v.to_string())),
    );
    Params::resolve(planner, declared, &given)
}

/// The per-step planner around one optimiser.
pub struct StepPlanner {
    name: &'static str,
    nav: Navigation,
    optimizer: Box<dyn Minimizer>,
}

impl Planner<NavProblem> for StepPlanner {
    fn name(&self) -> &str {
        self.name
    }
    fn plan(&self, p: &NavProblem, ctx: &Ctx) -> Result<Trajectories, Unsolved> {
        self.nav
            .run(p, &mut HeadingSearch(self.optimizer.as_ref()), ctx)
    }
}

/// ORCA inside the same loop ([`crate::orca`]).
pub struct OrcaPlanner {
    nav: Navigation,
    orca: Orca,
}

impl Planner<NavProblem> for OrcaPlanner {
    fn name(&self) -> &str {
        "orca"
    }
    fn plan(&self, p: &NavProblem, ctx: &Ctx) -> Result<Trajectories, Unsolved> {
        self.nav.run(p, &mut OrcaRun::new(self.orca, p), ctx)
    }
}

/// The loop settings from ORCA's parameters (no objective, no heading mode).
fn loop_navigation(p: &Params) -> mrpp_core::error::Result<Navigation> {
    Ok(Navigation {
        guide: [Guide::Waypoints, Guide::Goal][p.choice("guide", &["waypoints", "goal"])?],
        deadlock_steps: p.get_in("deadlock_steps", 1..=1_000_000)?,
        snap: p.get("snap")?,
        ..Navigation::default()
    })
}

/// The navigation settings from a planner's parameters (the loop's, then mode and objective).
fn navigation(p: &Params) -> mrpp_core::error::Result<Navigation> {
    let mode = [Mode::Joint, Mode::PerRobot][p.choice("mode", &["joint", "per-robot"])?];
    let obstacle = [ObstacleTerm::Near, ObstacleTerm::Inverse]
        [p.choice("obstacle_term", &["near", "inverse"])?];
    Ok(Navigation {
        mode,
        objective: Objective {
            f_dp: p.get_in("f_dp", 0.0..=1e12)?,
            f_st: p.get_in("f_st", 0.0..=1e12)?,
            obstacle,
        },
        straight_init: p.get("straight_init")?,
        ..loop_navigation(p)?
    })
}

fn planner(
    name: &'static str,
    p: &Params,
    optimizer: Box<dyn Minimizer>,
) -> mrpp_core::error::Result<Box<dyn Planner<NavProblem>>> {
    Ok(Box::new(StepPlanner {
        name,
        nav: navigation(p)?,
        optimizer,
    }))
}

/// The `hbmo` planner's parameters: the navigation's, then Table 1's and the reconstruction's.
const HBMO_PARAMS: &[Param] = nav_params![
    Param {
        name: "population",
        default: "10",
        doc: "bees in the initial population (paper 10)"
    },
    Param {
        name: "drones",
        default: "9",
        doc: "drones per mating flight, D (paper 9)"
    },
    Param {
        name: "broods",
        default: "9",
        doc: "broods per flight, B (paper 9)"
    },
    Param {
        name: "workers",
        default: "5",
        doc: "worker heuristics, W (paper 5)"
    },
    Param {
        name: "spermatheca",
        default: "9",
        doc: "spermatheca capacity, C (paper 9)"
    },
    Param {
        name: "speed_max",
        default: "1",
        doc: "queen's speed at the start of a flight, S_max (paper 1)"
    },
    Param {
        name: "speed_min",
        default: "0.2",
        doc: "queen's speed that ends a flight, S_min (paper 0.2)"
    },
    Param {
        name: "energy_max",
        default: "1",
        doc: "queen's energy at the start of a flight, E_max (paper 1)"
    },
    Param {
        name: "alpha",
        default: "0.93",
        doc: "speed reduction per transition (paper 0.93)"
    },
    Param {
        name: "gamma",
        default: "0.93",
        doc: "energy reduction per transition (paper 0.93)"
    },
    Param {
        name: "flights",
        default: "18",
        doc: "mating flights per step (the paper's Maxiter, not given; 18 gives DE's and PSO's 820 evaluations)"
    },
    Param {
        name: "local_steps",
        default: "3",
        doc: "trial moves of a worker on one brood"
    },
    Param {
        name: "brood_drones",
        default: "true",
        doc: "broods that fail to replace the queen become drones of the next flight (the paper, §3)"
    },
    Param {
        name: "mating",
        default: "relative",
        doc: "relative (|f_queen − f_drone| / |f_queen|) or absolute (|f_queen − f_drone|, eq. 8 as written) fitness difference in exp(−D/S)"
    },
];

/// `hbmo` in the registry.
pub const HBMO_ENTRY: PlannerEntry<NavProblem> = PlannerEntry {
    name: "hbmo",
    about: "honey bee mating optimisation of every robot's heading, step by step (Sahoo et al., the HBMO navigation paper)",
    params: HBMO_PARAMS,
    build: |p| {
        let p = &with_preset("hbmo", HBMO_PARAMS, p, &[PAPER_NAV, PAPER_HBMO])?;
        let h = Hbmo {
            population: p.get_in("population", 1..=100_000)?,
            drones: p.get_in("drones", 1..=100_000)?,
            broods: p.get_in("broods", 1..=100_000)?,
            workers: p.get_in("workers", 1..=100)?,
            spermatheca: p.get_in("spermatheca", 1..=100_000)?,
            speed_max: p.get_in("speed_max", 1e-9..=1e9)?,
            speed_min: p.get_in("speed_min", 0.0..=1e9)?,
            energy_max: p.get_in("energy_max", 1e-9..=1e9)?,
            alpha: p.get_in("alpha", 1e-9..=0.999_999)?,
            gamma: p.get_in("gamma", 1e-9..=0.999_999)?,
            flights: p.get_in("flights", 1..=1_000_000)?,
            local_steps: p.get_in("local_steps", 0..=1_000_000)?,
            brood_drones: p.get("brood_drones")?,
            fitness_scale: [FitnessScale::Relative, FitnessScale::Absolute]
                [p.choice("mating", &["relative", "absolute"])?],
        };
        if h.speed_min >= h.speed_max {
            return Err(mrpp_core::error::Error::Param(format!(
                "hbmo: speed_min ({}) must be below speed_max ({}), or no mating flight happens",
                h.speed_min, h.speed_max
            )));
        }
        planner("hbmo", p, Box::new(h))
    },
};

/// The `de` planner's parameters: the navigation's, then the optimiser's.
const DE_PARAMS: &[Param] = nav_params![
    Param {
        name: "population",
        default: "20",
        doc: "population NP"
    },
    Param {
        name: "generations",
        default: "40",
        doc: "generations per step"
    },
    Param {
        name: "f",
        default: "0.6",
        doc: "differential weight F"
    },
    Param {
        name: "cr",
        default: "0.9",
        doc: "crossover rate CR"
    },
];

/// `de` in the registry.
pub const DE_ENTRY: PlannerEntry<NavProblem> = PlannerEntry {
    name: "de",
    about: "differential evolution (DE/rand/1/bin) of every robot's heading, step by step (the HBMO paper's comparison)",
    params: DE_PARAMS,
    build: |p| {
        let p = &with_preset("de", DE_PARAMS, p, &[PAPER_NAV])?;
        let d = De {
            population: p.get_in("population", 4..=100_000)?,
            generations: p.get_in("generations", 0..=1_000_000)?,
            f: p.get_in("f", 0.0..=2.0)?,
            cr: p.get_in("cr", 0.0..=1.0)?,
        };
        planner("de", p, Box::new(d))
    },
};

/// The `pso` planner's parameters: the navigation's, then the optimiser's.
const PSO_PARAMS: &[Param] = nav_params![
    Param {
        name: "particles",
        default: "20",
        doc: "swarm size"
    },
    Param {
        name: "iterations",
        default: "40",
        doc: "iterations per step"
    },
    Param {
        name: "w_start",
        default: "0.9",
        doc: "inertia weight at the first iteration"
    },
    Param {
        name: "w_end",
        default: "0.4",
        doc: "inertia weight at the last iteration"
    },
    Param {
        name: "c1",
        default: "2",
        doc: "cognitive coefficient"
    },
    Param {
        name: "c2",
        default: "2",
        doc: "social coefficient"
    },
];

/// `pso` in the registry.
pub const PSO_ENTRY: PlannerEntry<NavProblem> = PlannerEntry {
    name: "pso",
    about: "particle swarm optimisation (inertia weight) of every robot's heading, step by step (the HBMO paper's comparison)",
    params: PSO_PARAMS,
    build: |p| {
        let p = &with_preset("pso", PSO_PARAMS, p, &[PAPER_NAV])?;
        let s = Pso {
            particles: p.get_in("particles", 1..=100_000)?,
            iterations: p.get_in("iterations", 0..=1_000_000)?,
            w_start: p.get_in("w_start", 0.0..=10.0)?,
            w_end: p.get_in("w_end", 0.0..=10.0)?,
            c1: p.get_in("c1", 0.0..=10.0)?,
            c2: p.get_in("c2", 0.0..=10.0)?,
            ..Pso::default()
        };
        planner("pso", p, Box::new(s))
    },
};

/// `orca` in the registry.
pub const ORCA_ENTRY: PlannerEntry<NavProblem> = PlannerEntry {
    name: "orca",
    about: "ORCA reciprocal velocity obstacles through dodgy_2d, the RVO2 port (van den Berg et al., ISRR 2009): today's practical baseline",
    params: loop_params![
        Param {
            name: "time_horizon",
            default: "10",
            doc: "steps ahead that collisions between robots are avoided"
        },
        Param {
            name: "obstacle_time_horizon",
            default: "5",
            doc: "steps ahead that collisions with obstacles are avoided"
        },
        Param {
            name: "neighbours",
            default: "10",
            doc: "most neighbours each robot considers"
        },
        Param {
            name: "neighbour_distance",
            default: "10",
            doc: "neighbours within this many step lengths"
        },
        Param {
            name: "margin",
            default: "0.1",
            doc: "ORCA plans with radii this share larger (keeps its f32 velocities clear of the exact check)",
        },
    ],
    build: |p| {
        let orca = Orca {
            time_horizon: p.get_in("time_horizon", 1e-3..=1e6)?,
            obstacle_time_horizon: p.get_in("obstacle_time_horizon", 1e-3..=1e6)?,
            neighbours: p.get_in("neighbours", 0..=100_000)?,
            neighbour_distance: p.get_in("neighbour_distance", 0.0..=1e9)?,
            margin: p.get_in("margin", 0.0..=10.0)?,
        };
        Ok(Box::new(OrcaPlanner {
            nav: loop_navigation(p)?,
            orca,
        }))
    },
};

#[cfg(test)]
mod tests {
    use super::*;

    fn resolved(declared: &[Param], given: &[(&str, &str)], paper: &[&[(&str, &str)]]) -> Params {
        let given: Vec<(String, String)> = given
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        let p = Params::resolve("t", declared, &given).unwrap();
        with_preset("t", declared, &p, paper).unwrap()
    }

    #[test]
    fn preset_paper_sets_the_literal_choices_and_explicit_values_win() {
        let none = resolved(HBMO_PARAMS, &[], &[PAPER_NAV, PAPER_HBMO]);
        let defaults = [
            ("guide", "waypoints"),
            ("obstacle_term", "near"),
            ("straight_init", "true"),
            ("brood_drones", "true"),
            ("mating", "relative"),
        ];
        for (k, v) in defaults {
            assert_eq!(none.raw(k), v, "{k}");
        }
        let paper = resolved(
            HBMO_PARAMS,
            &[("preset", "paper")],
            &[PAPER_NAV, PAPER_HBMO],
        );
        for (k, v) in PAPER_NAV.iter().chain(PAPER_HBMO) {
            assert_eq!(paper.raw(k), *v, "{k}");
        }
        // An explicit value overrides the preset, before or after it on the command line.
        for given in [
            [("obstacle_term", "near"), ("preset", "paper")],
            [("preset", "paper"), ("obstacle_term", "near")],
        ] {
            let p = resolved(HBMO_PARAMS, &given, &[PAPER_NAV, PAPER_HBMO]);
            assert_eq!(p.raw("obstacle_term"), "near");
            assert_eq!(p.raw("mating"), "absolute");
            assert_eq!(p.raw("guide"), "goal");
        }
        // DE and PSO take the navigation part only.
        let de = resolved(DE_PARAMS, &[("preset", "paper")], &[PAPER_NAV]);
        assert_eq!(de.raw("straight_init"), "false");
        assert_eq!(de.raw("f"), "0.6");
    }

    #[test]
    fn hbmo_options_parse_and_bad_values_are_refused() {
        let build = |given: &[(&str, &str)]| {
            let given: Vec<(String, String)> = given
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            HBMO_ENTRY.instantiate(&given).map(|_| ())
        };
        assert!(build(&[("preset", "paper")]).is_ok());
        assert!(build(&[("brood_drones", "false"), ("mating", "absolute")]).is_ok());
        assert!(build(&[("straight_init", "false")]).is_ok());
        let e = build(&[("mating", "abs")]).unwrap_err().to_string();
        assert!(e.contains("relative, absolute"), "{e}");
        let e = build(&[("preset", "literal")]).unwrap_err().to_string();
        assert!(e.contains("none, paper"), "{e}");
        assert!(build(&[("brood_drones", "maybe")]).is_err());
    }
}
