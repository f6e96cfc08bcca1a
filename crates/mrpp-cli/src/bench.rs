//! `mrpp bench run`: a sweep of grid maps x scenarios x agent counts x planners x runs, from a
//! TOML config or flags; `mrpp bench merge`: joins the parts of any sweep run with `--shard`.

use std::path::PathBuf;

use mrpp_bench::Shard;
use mrpp_bench::sweep::{GridSweep, InstanceSpec, PeerSpec, PlannerSpec, SweepConfig};

use crate::output::Fail;
use crate::sweeps::{Mode, drive_on};

#[derive(clap::Subcommand)]
pub(crate) enum Bench {
    /// Run a sweep (or one shard of it): records.csv (one validated run per line), summary.md,
    /// manifest.json.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp bench run --config bench/configs/example.toml -o out/bench\n  mrpp bench run -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen -N 10,20,40 --planners hstar,whca,lacam --runs 3 -t 10 -o out/sweep"
    )]
    Run(Box<RunArgs>),
    /// Join the parts of a sharded sweep (`part-i-of-N.jsonl` in the given folders) into the
    /// files of the whole sweep; the sweep is rebuilt from the command its parts recorded.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp bench merge -o out/bench out/part-1 out/part-2"
    )]
    Merge {
        /// Where to write the merged files.
        #[arg(short = 'o', long)]
        out: PathBuf,
        /// Folders holding the parts.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
    },
}

#[derive(clap::Args)]
pub(crate) struct RunArgs {
    /// The sweep as TOML (see `mrpp-bench`'s `sweep` module doc and bench/configs/).
    #[arg(long, conflicts_with_all = ["map", "scen", "planners"])]
    config: Option<PathBuf>,
    /// Without --config: the map ...
    #[arg(short = 'm', long, requires = "scen")]
    map: Option<PathBuf>,
    /// ... its scenario ...
    #[arg(short = 'i', long, requires = "map")]
    scen: Option<PathBuf>,
    /// ... agent counts (comma-separated; default all) ...
    #[arg(short = 'N', long, value_delimiter = ',')]
    agents: Vec<usize>,
    /// ... and planners (comma-separated registry names, default parameters).
    #[arg(long, value_delimiter = ',')]
    planners: Vec<String>,
    /// Runs per cell (flags only; a config sets `runs`).
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long, conflicts_with = "config")]
    runs: Option<usize>,
    /// Seconds per run (flags only; a config sets `time_limit`).
    #[arg(
        short = 't',
        long,
        conflicts_with = "config",
        allow_negative_numbers = true
    )]
    time_limit: Option<f64>,
    /// Seed (overrides the config's).
    #[arg(short = 's', long, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: Option<u64>,
    /// Run only shard i of N (`i/N`).
    #[arg(long)]
    shard: Option<Shard>,
    /// An external solver writing LaCAM text results, `name=command template` with
    /// {map} {scen} {agents} {seed} {time_limit} {out}; repeatable; added to a config's peers.
    #[arg(long = "peer", value_name = "NAME=COMMAND")]
    peers: Vec<PeerSpec>,
    /// Jobs run at once (default: one per core). Use 1 to time solvers side by side without
    /// them competing for cores.
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long)]
    jobs: Option<usize>,
    /// Count the jobs (all, and --shard's) from the config alone and say which map and scenario
    /// files are missing; reads no map or scenario and runs nothing.
    #[arg(long)]
    dry_run: bool,
    /// Output folder. A folder holding an interrupted run of the same sweep resumes it.
    #[arg(short = 'o', long, default_value = "out/bench")]
    out: PathBuf,
}

impl RunArgs {
    fn config(&self) -> Result<SweepConfig, Fail> {
        let mut cfg = match &self.config {
            Some(path) => SweepConfig::load(path)?,
            None => {
                let (Some(map), Some(scen)) = (&self.map, &self.scen) else {
                    return Err(Fail(
                        "give --config C.toml, or --map, --scen and --planners".into(),
                    ));
                };
                SweepConfig {
                    name: "bench".into(),
                    seed: 0,
                    runs: self.runs.unwrap_or(1),
                    time_limit: self.time_limit.unwrap_or(10.0),
                    peer_timeout: None,
                    instances: vec![InstanceSpec {
                        map: map.clone(),
                        scen: scen.clone(),
                        agents: self.agents.clone(),
                        scens: None,
                    }],
                    planners: self
                        .planners
                        .iter()
                        .map(|n| PlannerSpec {
                            name: n.clone(),
                            params: Default::default(),
                        })
                        .collect(),
                    peers: Vec::new(),
                }
            }
        };
        cfg.peers.extend(self.peers.iter().cloned());
        if let Some(s) = self.seed {
            cfg.seed = s;
        }
        Ok(cfg)
    }
}

/// Runs a sweep (or, with `merge`, joins its parts: the sweep is rebuilt from the configuration
/// the parts recorded, not from the files named on their command line).
pub(crate) fn run(args: RunArgs, merge: Option<Mode>) -> Result<u8, Fail> {
    let cfg = match &merge {
        Some(Mode::Merge { manifest, .. }) => SweepConfig::from_recorded(&manifest.config)?,
        _ => args.config()?,
    };
    // The config and every map and scenario it names are inputs: the output folder may not
    // hold any of them (checked when the folder is, before any job runs).
    crate::output::declare_inputs(
        args.config.iter().map(PathBuf::as_path).chain(
            cfg.instances
                .iter()
                .flat_map(|i| [i.map.as_path(), i.scen.as_path()]),
        ),
    );
    if args.dry_run && merge.is_none() {
        return dry_run(&cfg, args.shard.unwrap_or(Shard::ALL));
    }
    let seed = cfg.seed;
    let sweep = GridSweep::new(cfg)?;
    let mode = merge.unwrap_or(Mode::run(args.shard, args.out));
    drive_on(&sweep, &mode, seed, "runs", args.jobs)
}

/// `bench run --dry-run`: the number of jobs, the shard's, and the missing files.
fn dry_run(cfg: &SweepConfig, shard: Shard) -> Result<u8, Fail> {
    let Some(jobs) = cfg.job_count() else {
        return Err(Fail(
            "--dry-run counts jobs without reading scenarios, so every instance needs its agent \
             counts (`agents = [...]` or \"50..=1000 step 50\")"
                .into(),
        ));
    };
    let owned = (0..jobs).filter(|&j| shard.owns(j)).count();
    let mut files: Vec<&std::path::Path> = cfg
        .instances
        .iter()
        .flat_map(|i| [i.map.as_path(), i.scen.as_path()])
        .collect();
    files.sort();
    files.dedup();
    let missing: Vec<_> = files.iter().filter(|f| !f.is_file()).collect();
    crate::output::out!(
        "{jobs} jobs ({} instance specs, {} solvers, {} runs); shard {shard}: {owned} jobs",
        cfg.instances.len(),
        cfg.planners.len() + cfg.peers.len(),
        cfg.runs
    );
    if let Some(first) = missing.first() {
        crate::output::out!(
            "{} of the {} map and scenario files are missing, e.g. {} (mrpp data get movingai \
             fetches the MovingAI benchmark)",
            missing.len(),
            files.len(),
            first.display()
        );
    } else {
        crate::output::out!("all {} map and scenario files are present", files.len());
    }
    Ok(0)
}
