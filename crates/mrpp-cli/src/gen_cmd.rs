//! `mrpp gen ...`: problem files from seeds — random grid maps and MovingAI scenarios, League
//! of Robot Runners problems, polygon
//! worlds (stand-ins for the GA paper's maps that are not public), formation files (random
//! Q_ini/Q_goal on a map) and continuous worlds.

use std::path::PathBuf;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use mrpp_formation::CostModel;
use mrpp_formation::polymap::PolygonMap;
use mrpp_formation::world::{Formation, FormationFile, random_pair};

use crate::output::{Fail, file_name, guard, say, write_atomic};

#[derive(clap::Subcommand)]
pub(crate) enum Gen {
    /// A random MovingAI scenario on a grid map: --agents distinct starts and distinct goals drawn
    /// uniformly (seeded) from the map's largest connected area, e.g. 10,000 agents on
    /// warehouse-20-40-10-2-2.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen scen -m data/movingai/random-32-32-20.map -N 100 -s 1 -o random-100.scen"
    )]
    Scen {
        #[arg(short = 'm', long)]
        map: PathBuf,
        #[arg(short = 'N', long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
        agents: usize,
        #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
    /// A random League of Robot Runners problem on a grid map: --robots distinct start cells and
    /// --tasks tasks of --errands errands each, drawn uniformly (seeded) from the map's largest
    /// connected area (an errand differs from the one before it). Writes OUT.json and, beside it as
    /// the start kit lays them out, maps/, agents/ and tasks/ (the 2024 layout).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen lorr -m data/movingai/warehouse-20-40-10-2-2.map --robots 10000 --tasks 100000 -s 0 -o warehouse-10k.json\n  mrpp gen lorr -m data/robot-runners/lorr2026-maze/maps/maze-32-32-2.map --robots 25 --tasks 200 --errands 3 -s 1 -o maze-25.json\n\nThen e.g. mrpp solve --lorr warehouse-10k.json -P lifelong-pibt --steps 300 -o run.json"
    )]
    Lorr {
        #[arg(short = 'm', long)]
        map: PathBuf,
        #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
        robots: usize,
        #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
        tasks: usize,
        /// Errands per task.
        #[arg(long, default_value_t = 2, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
        errands: usize,
        /// `numTasksReveal`: tasks open at a time per robot.
        #[arg(long, default_value_t = 1.5, allow_negative_numbers = true)]
        reveal: f64,
        #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
    /// A random MovingAI grid map: --width x --height cells, each an obstacle with probability
    /// --obstacles (seeded), e.g. a 500 x 500 map for 10,000 agents.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen map --width 64 --height 64 --obstacles 0.2 -s 0 -o random-64-64-20.map"
    )]
    Map {
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_whole, long)]
        width: usize,
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_whole, long)]
        height: usize,
        /// Fraction of cells that are obstacles (0 to 0.9).
        #[arg(allow_negative_numbers = true, long, default_value_t = 0.1)]
        obstacles: f64,
        #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
    /// A seeded polygon world in the CTU text format (gen-dense, gen-staggered-brick-wall,
    /// gen-var-density, gen-var-density3); the file records its kind and seed.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen polygon-map --kind gen-dense -s 0 -o dense.txt"
    )]
    PolygonMap {
        #[arg(long, value_parser = crate::output::Offer(|| mrpp_formation::generator::KINDS.to_vec()))]
        kind: String,
        #[arg(short = 's', long, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
    /// A formation file on a polygon map: R robots, random Q_ini and Q_goal in free space (at
    /// least half the map's diagonal apart), radius and cost model.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen formation -m data/polygon-maps/potholes.txt --robots 3 -s 0 -o formation.json"
    )]
    Formation {
        /// The polygon map (recorded relative to the output file's folder when possible).
        #[arg(short = 'm', long)]
        map: PathBuf,
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_whole, long)]
        robots: usize,
        #[arg(short = 's', long, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        #[arg(allow_negative_numbers = true, long, default_value_t = 0.3)]
        radius: f64,
        /// Cost model: lanes (with --kappa), waves or hard.
        #[arg(long, default_value = "lanes")]
        cost: String,
        #[arg(allow_negative_numbers = true, long, default_value_t = 0.5)]
        kappa: f64,
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
    /// A continuous world (JSON): `random` (the HBMO paper's setting: a 500 x 400 workspace,
    /// --obstacles polygons of different shapes, --robots discs of radius 6 and speed 16) or
    /// `circle` (RVO2's circle: --robots discs on a circle of radius --ring, each to its antipode).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen continuous --kind random --robots 10 --obstacles 5 -s 0 -o world.json\n  mrpp gen continuous --kind circle --robots 16 -o circle.json"
    )]
    Continuous {
        #[arg(long, default_value = "random", value_parser = crate::output::Offer(|| vec!["random", "circle"]))]
        kind: String,
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_whole, long)]
        robots: usize,
        /// Obstacles of a random world.
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_whole, long, default_value_t = 4)]
        obstacles: usize,
        #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        /// Circle: radius of the ring.
        #[arg(allow_negative_numbers = true, long, default_value_t = 200.0)]
        ring: f64,
        /// Circle: robot radius.
        #[arg(allow_negative_numbers = true, long, default_value_t = 6.0)]
        radius: f64,
        /// Circle: robot speed per step.
        #[arg(allow_negative_numbers = true, long, default_value_t = 8.0)]
        speed: f64,
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
}

pub(crate) fn run(cmd: Gen) -> Result<u8, Fail> {
    match cmd {
        Gen::Scen {
            map,
            agents,
            seed,
            out,
        } => {
            guard([map.as_path()], &[&out])?;
            let grid = mrpp_grid::GridMap::load(&map)?;
            let inst = mrpp_grid::scen::random_instance(&grid, agents, seed)
                .map_err(|e| Fail(format!("{}: {e}", map.display())))?;
            write_atomic(
                &out,
                mrpp_grid::scen::scen_text(&grid, &file_name(&map), &inst),
            )?;
            say!(
                "mrpp {} | gen scen | map {} | agents {agents} | seed {seed} | written to {}",
                env!("CARGO_PKG_VERSION"),
                file_name(&map),
                out.display()
            );
            Ok(0)
        }
        Gen::Lorr {
            map,
            robots,
            tasks,
            errands,
            reveal,
            seed,
            out,
        } => lorr(&map, robots, tasks, errands, reveal, seed, &out),
        Gen::Map {
            width,
            height,
            obstacles,
            seed,
            out,
        } => {
            guard([], &[&out])?;
            let text = mrpp_grid::scen::random_map_text(width, height, obstacles, seed)
                .map_err(|e| Fail(format!("gen map: {e}")))?;
            write_atomic(&out, text)?;
            say!(
                "mrpp {} | gen map | {width} x {height} | obstacles {obstacles} | seed {seed} | written to {}",
                env!("CARGO_PKG_VERSION"),
                out.display()
            );
            Ok(0)
        }
        Gen::Continuous {
            kind,
            robots,
            obstacles,
            seed,
            ring,
            radius,
            speed,
            out,
        } => continuous(&kind, robots, obstacles, seed, (ring, radius, speed), &out),
        Gen::PolygonMap { kind, seed, out } => {
            guard([], &[&out])?;
            let text = mrpp_formation::generator::generate(&kind, seed).map_err(Fail)?;
            write_atomic(&out, &text)?;
            say!(
                "mrpp {} | gen polygon-map | {kind} | seed {seed} | written to {}",
                env!("CARGO_PKG_VERSION"),
                out.display()
            );
            Ok(0)
        }
        Gen::Formation {
            map,
            robots,
            seed,
            radius,
            cost,
            kappa,
            out,
        } => {
            guard([map.as_path()], &[&out])?;
            let cost = match cost.as_str() {
                "lanes" => CostModel::Lanes { kappa },
                "waves" => CostModel::Waves,
                "hard" => CostModel::Hard,
                other => {
                    return Err(Fail(format!(
                        "--cost must be lanes, waves or hard, got `{other}`"
                    )));
                }
            };
            let polygons = PolygonMap::load(&map)?;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (start, goal) = random_pair(&polygons, radius, &mut rng)
                .ok_or_else(|| Fail(format!("{}: found no free start/goal pair", map.display())))?;
            let file = FormationFile {
                map: relative_map(&map, &out),
                robots,
                start,
                goal,
                radius,
                cost,
            };
            // Checked like any formation file before it is written (roadmap, links).
            let resolved = FormationFile {
                map: map.clone(),
                ..file.clone()
            };
            Formation::on(resolved, polygons, &out)?;
            let text = serde_json::to_string_pretty(&file).map_err(|e| Fail(e.to_string()))? + "\n";
            write_atomic(&out, &text)?;
            say!(
                "mrpp {} | gen formation | map {} | robots {robots} | seed {seed} | start {start:?} | goal {goal:?} | written to {}",
                env!("CARGO_PKG_VERSION"),
                file_name(&map),
                out.display()
            );
            Ok(0)
        }
    }
}

/// `mrpp gen lorr` (the subcommand's doc).
fn lorr(
    map: &std::path::Path,
    robots: usize,
    tasks: usize,
    errands: usize,
    reveal: f64,
    seed: u64,
    out: &std::path::Path,
) -> Result<u8, Fail> {
    use rand::RngExt;
    use rand::seq::IndexedRandom;
    if out.extension().and_then(|e| e.to_str()) != Some("json") {
        return Err(Fail(format!("{}: --out must end in .json", out.display())));
    }
    if !(reveal.is_finite() && reveal > 0.0 && reveal <= 1000.0) {
        return Err(Fail(format!(
            "--reveal must be more than 0 and at most 1000 tasks per robot, got {reveal}"
        )));
    }
    if !(1..=1_000_000).contains(&errands) || !(1..=10_000_000).contains(&tasks) {
        return Err(Fail(format!(
            "--tasks must be 1 to 10000000 and --errands 1 to 1000000, got {tasks} and {errands}"
        )));
    }
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = out.parent().unwrap_or(std::path::Path::new(""));
    let map_name = format!("{}.map", file_name(map).trim_end_matches(".map"));
    let rel = [
        format!("maps/{map_name}"),
        format!("agents/{stem}.agents"),
        format!("tasks/{stem}.tasks"),
    ];
    let files: Vec<PathBuf> = rel.iter().map(|r| dir.join(r)).collect();
    // The three files go in sub-folders made below; where a folder exists already, the file
    // in it is checked like --out (it may not be an input, e.g. the map itself).
    guard([map], &[out])?;
    for f in &files {
        if f.parent().is_some_and(std::path::Path::is_dir) {
            crate::output::check_output(f)?;
        }
    }
    let grid = mrpp_grid::GridMap::load(map)?;
    let area = mrpp_mapf::map::largest_component(&grid);
    if robots > area.len() || area.len() < 2 {
        return Err(Fail(format!(
            "{}: cannot place {robots} robots: the largest connected area has {} free cells",
            map.display(),
            area.len()
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let width = u64::from(grid.width());
    let location = |v: mrpp_core::VertexId| {
        let (x, y) = grid.cell(v);
        u64::from(y) * width + u64::from(x)
    };
    let starts: Vec<String> = area
        .sample(&mut rng, robots)
        .map(|&v| location(v).to_string())
        .collect();
    let mut task_lines = Vec::with_capacity(tasks);
    for _ in 0..tasks {
        let mut line: Vec<mrpp_core::VertexId> = Vec::with_capacity(errands);
        while line.len() < errands {
            let v = area[rng.random_range(0..area.len())];
            if line.last() != Some(&v) {
                line.push(v);
            }
        }
        task_lines.push(
            line.iter()
                .map(|&v| location(v).to_string())
                .collect::<Vec<_>>()
                .join(","),
        );
    }
    let header = "# version for LoRR 2024";
    let problem = serde_json::json!({
        "mapFile": rel[0],
        "agentFile": rel[1],
        "teamSize": robots,
        "taskFile": rel[2],
        "numTasksReveal": reveal,
        "version": "2024 LoRR",
    });
    for sub in ["maps", "agents", "tasks"] {
        std::fs::create_dir_all(dir.join(sub))
            .map_err(|e| Fail(format!("{}: {e}", dir.join(sub).display())))?;
    }
    write_atomic(&files[0], grid.movingai_text())?;
    write_atomic(
        &files[1],
        format!("{header}\n{robots}\n{}\n", starts.join("\n")),
    )?;
    write_atomic(
        &files[2],
        format!("{header}\n{tasks}\n{}\n", task_lines.join("\n")),
    )?;
    write_atomic(
        out,
        serde_json::to_string_pretty(&problem).expect("json") + "\n",
    )?;
    say!(
        "mrpp {} | gen lorr | map {} | {robots} robots | {tasks} tasks of {errands} errands | seed {seed} | written to {} (and {})",
        env!("CARGO_PKG_VERSION"),
        file_name(map),
        out.display(),
        rel.join(", ")
    );
    Ok(0)
}

/// The map's path as the formation file should record it: relative to the file's folder when
/// both are relative paths, else as given.
fn relative_map(map: &std::path::Path, out: &std::path::Path) -> PathBuf {
    let dir = out.parent().unwrap_or(std::path::Path::new(""));
    if map.is_absolute() || dir.is_absolute() {
        return std::fs::canonicalize(map).unwrap_or_else(|_| map.to_path_buf());
    }
    let ups = dir.components().count();
    let mut p = PathBuf::new();
    for _ in 0..ups {
        p.push("..");
    }
    p.join(map)
}

/// `mrpp gen continuous`.
fn continuous(
    kind: &str,
    robots: usize,
    obstacles: usize,
    seed: u64,
    (ring, radius, speed): (f64, f64, f64),
    out: &std::path::Path,
) -> Result<u8, Fail> {
    use mrpp_continuous::generator::{circle_world, random_world};
    guard([], &[out])?;
    if !(1..=1000).contains(&robots) {
        return Err(Fail(format!("--robots must be 1 to 1000, got {robots}")));
    }
    let (mut world, what) = match kind {
        "random" => {
            if robots > 64 || obstacles > 20 {
                return Err(Fail(format!(
                    "a random world takes at most 64 robots and 20 obstacles, got {robots} and {obstacles}"
                )));
            }
            let w = random_world(robots, obstacles, seed).ok_or_else(|| {
                Fail(format!("no placement of {robots} robots among {obstacles} obstacles found for seed {seed}"))
            })?;
            (
                w,
                format!("--kind random --robots {robots} --obstacles {obstacles} --seed {seed}"),
            )
        }
        "circle" => {
            let w = circle_world(robots, ring, radius, speed);
            w.check()
                .map_err(|e| Fail(format!("this circle is not a valid world: {e}")))?;
            (
                w,
                format!(
                    "--kind circle --robots {robots} --ring {ring} --radius {radius} --speed {speed}"
                ),
            )
        }
        other => {
            return Err(Fail(format!(
                "--kind must be random or circle, got `{other}`"
            )));
        }
    };
    world.source = Some(format!(
        "mrpp gen continuous {what} (mrpp {})",
        env!("CARGO_PKG_VERSION")
    ));
    let text = serde_json::to_string_pretty(&world).map_err(|e| Fail(e.to_string()))?;
    write_atomic(out, &(text + "\n"))?;
    say!(
        "mrpp {} | gen continuous | {what} | written to {}",
        env!("CARGO_PKG_VERSION"),
        out.display()
    );
    Ok(0)
}

/// `mrpp convert`: `map` (any grid format) as a MovingAI `.map` at `out_map`, and the agents of
/// `scen` (first `agents`) as a `.scen` at `out_scen` naming that map. Neither output may be an
/// input; both are written whole or not at all.
pub(crate) fn convert(
    map: &std::path::Path,
    scen: Option<&std::path::Path>,
    agents: Option<usize>,
    out_map: &std::path::Path,
    out_scen: Option<&std::path::Path>,
) -> Result<u8, Fail> {
    let outs: Vec<&std::path::Path> = std::iter::once(out_map).chain(out_scen).collect();
    guard(std::iter::once(map).chain(scen), &outs)?;
    if out_scen.is_some() != scen.is_some() {
        return Err(Fail(
            "convert: --out-scen and --scen go together (the agents to write and where)".into(),
        ));
    }
    let grid = mrpp_grid::GridMap::load(map)?;
    let scen_text = match (scen, out_scen) {
        (Some(scen), Some(_)) => {
            let inst = mrpp_grid::scen::load_agents(scen, &grid, agents)?;
            Some(mrpp_grid::scen::scen_text(
                &grid,
                &file_name(out_map),
                &inst,
            ))
        }
        _ => None,
    };
    write_atomic(out_map, grid.movingai_text())?;
    if let (Some(text), Some(out)) = (scen_text, out_scen) {
        write_atomic(out, text)?;
    }
    say!(
        "mrpp {} | convert | map {} {}x{} -> {}{}",
        env!("CARGO_PKG_VERSION"),
        file_name(map),
        grid.width(),
        grid.height(),
        out_map.display(),
        out_scen.map_or(String::new(), |o| format!(" | agents -> {}", o.display()))
    );
    Ok(0)
}

/// The plan formats `mrpp convert --to` writes.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanFormat {
    /// mrpp's plan envelope (JSON, `[x, y]` cells).
    Envelope,
    /// LaCAM/PIBT text (lacam3's keys).
    Lacam,
    /// The MAPF Tracker's result CSV (one row; `mrpp_grid::io::tracker`).
    Tracker,
    /// PlanViz's LoRR JSON (2024 layout, `MAPF` model; `mrpp_lifelong::lorr_output`).
    Planviz,
}

/// `mrpp convert --plan`: the grid plan `plan` (any format `mrpp validate` reads on grids,
/// detected from the content) for `map` and `scen` (first `agents`), validated, written to `out`
/// as `to`. `out` may not be an input; it is written whole (temp file and rename) or not at all.
pub(crate) fn convert_plan(
    map: &std::path::Path,
    scen: Option<&std::path::Path>,
    agents: Option<usize>,
    plan: &std::path::Path,
    to: PlanFormat,
    out: &std::path::Path,
) -> Result<u8, Fail> {
    use mrpp_core::Problem as _;
    let scen = scen.ok_or_else(|| Fail("convert --plan needs --scen".into()))?;
    guard([map, scen, plan], &[out])?;
    let inputs = crate::family::Inputs {
        map: Some(map.to_path_buf()),
        scen: Some(scen.to_path_buf()),
        agents,
        ..Default::default()
    };
    let read = crate::grid_family::read_plan(&inputs, plan)?;
    let grid = mrpp_grid::GridMap::load(map)?;
    let problem = read.problem;
    let mut paths = read.plan;
    paths.trim();
    let metrics = problem
        .validate(&paths)
        .map_err(|v| Fail(format!("{}: not a valid plan: {v}", plan.display())))?;
    let actual = serde_json::Value::Object(crate::output::metrics_object(&metrics));
    if let Some((k, claim, real)) = mrpp_core::envelope::disputed(&read.claims, &actual).first() {
        return Err(Fail(format!(
            "{}: plan claims {k} {claim} but its paths give {real}",
            plan.display()
        )));
    }
    let inst = problem.instance();
    let map_file = file_name(map);
    let text = match to {
        PlanFormat::Envelope => {
            let info = mrpp_core::mapf::plan_file::RunInfo {
                planner: "unknown".into(),
                ..Default::default()
            };
            let solved = Ok(mrpp_core::Solved {
                plan: paths,
                metrics,
                runtime: std::time::Duration::ZERO,
            });
            let mut env =
                mrpp_grid::io::plan_json::grid_envelope(&grid, &map_file, &problem, info, &solved);
            env.extra
                .insert("converted_from".into(), file_name(plan).into());
            env.to_json()
        }
        PlanFormat::Lacam => mrpp_grid::io::lacam::write_lacam(
            &grid,
            &map_file,
            "unknown",
            inst,
            Some((&paths, metrics)),
            0.0,
            0,
        ),
        PlanFormat::Tracker => {
            let row = mrpp_grid::io::tracker::TrackerRow::of_plan(
                &grid,
                &map_file,
                &file_name(scen),
                inst,
                &paths,
            )
            .map_err(|e| Fail(format!("{}: {e}", plan.display())))?;
            mrpp_grid::io::tracker::write_tracker(&[row])
        }
        PlanFormat::Planviz => {
            let json = mrpp_lifelong::lorr_output::one_shot_to_json(&grid, inst, &paths)
                .map_err(|e| Fail(format!("{}: {e}", plan.display())))?;
            serde_json::to_string(&json).map_err(|e| Fail(e.to_string()))? + "\n"
        }
    };
    write_atomic(out, text)?;
    say!(
        "mrpp {} | convert | plan {} ({}) | agents {} | sum_of_costs {} | makespan {} -> {} ({to:?})",
        env!("CARGO_PKG_VERSION"),
        file_name(plan),
        if read.about.is_empty() {
            "LaCAM text"
        } else {
            &read.about
        },
        inst.num_agents(),
        metrics.sum_of_costs,
        metrics.makespan,
        out.display()
    );
    Ok(0)
}
