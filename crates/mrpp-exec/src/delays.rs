//! Seeded robot delays, the League of Robot Runners' delay models (start kit v3.1.0,
//! `src/DelayGenerator.cpp`; its `delayConfig` fields and names).
//!
//! Every tick, first each delayed robot's remaining delay goes down by one; then, among the robots
//! not delayed, some are chosen to start a delay: `bernoulli` — each with probability `pDelay`;
//! `poisson` — a count drawn from a Poisson distribution of rate teamSize x `pDelay` (at most the
//! robots available), chosen uniformly. Each chosen robot is delayed for a duration in
//! [`minDelay`, `maxDelay`] ticks: `uniform` — uniformly; `gaussian` — a normal of mean
//! `minDelay + span x gaussMeanRatio` and deviation `span x gaussStdRatio` (span = max - min),
//! rounded and clamped. A delay drawn at tick `t` of duration `d` holds the robot for ticks `t .. t + d - 1`:
//! it makes no progress then, not even in the middle of a move.
//!
//! The random stream is mrpp's (ChaCha8 from the seed), not the kit's `mt19937`, so the same seed
//! gives the same delays in mrpp but not the kit's.

use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};

/// Which robots start a delay on a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventModel {
    /// Each available robot with probability `p_delay`.
    Bernoulli,
    /// A Poisson count of rate teamSize x `p_delay`, chosen uniformly among the available.
    Poisson,
}

/// How long a delay lasts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DurationModel {
    Uniform,
    /// Mean `min + span x mean_ratio`, deviation `span x std_ratio`.
    Gaussian {
        mean_ratio: f64,
        std_ratio: f64,
    },
}

/// The League's `delayConfig` (module doc); `p_delay = 0` is no delay at all.
#[derive(Debug, Clone, PartialEq)]
pub struct DelayConfig {
    pub event_model: EventModel,
    pub p_delay: f64,
    /// Ticks, at least 1.
    pub min_delay: u32,
    pub max_delay: u32,
    pub duration_model: DurationModel,
}

impl DelayConfig {
    /// No delays.
    pub fn none() -> Self {
        DelayConfig {
            event_model: EventModel::Bernoulli,
            p_delay: 0.0,
            min_delay: 1,
            max_delay: 1,
            duration_model: DurationModel::Uniform,
        }
    }

    /// Reads a spec: `none`, or `bernoulli:` / `poisson:` followed by comma-separated `p=`, `min=`,
    /// `max=` (required) and `duration=uniform|gaussian`, `mean=`, `std=` (the gaussian's ratios,
    /// default 0.5 and 0.22), e.g. `bernoulli:p=0.01,min=1,max=4`.
    ///
    /// # Errors
    /// A message naming the item that is wrong: an unknown model or key, a missing or malformed
    /// number, `p` outside [0, 1], `min` of 0, `min` above `max`, ratios out of range.
    pub fn parse(spec: &str) -> Result<Self, String> {
        let spec = spec.trim();
        if spec == "none" {
            return Ok(Self::none());
        }
        let (model, rest) = spec.split_once(':').ok_or_else(|| {
            format!(
                "delays `{spec}`: expected `none` or `bernoulli:p=..,min=..,max=..` (or poisson:)"
            )
        })?;
        let event_model = match model {
            "bernoulli" => EventModel::Bernoulli,
            "poisson" => EventModel::Poisson,
            _ => {
                return Err(format!(
                    "delays `{spec}`: unknown model `{model}` (bernoulli or poisson)"
                ));
            }
        };
        let (mut p, mut min, mut max) = (None, None, None);
        let (mut duration, mut mean, mut std) = ("uniform", 0.5, 0.22);
        for item in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (k, v) = item
                .split_once('=')
                .ok_or_else(|| format!("delays `{spec}`: `{item}` is not key=value"))?;
            let num = |v: &str| {
                v.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("delays `{spec}`: {k}={v} is not a number"))
            };
            let whole = |v: &str| {
                v.parse::<u32>()
                    .map_err(|_| format!("delays `{spec}`: {k}={v} is not a whole number of ticks"))
            };
            match k {
                "p" => p = Some(num(v)?),
                "min" => min = Some(whole(v)?),
                "max" => max = Some(whole(v)?),
                "duration" => duration = v,
                "mean" => mean = num(v)?,
                "std" => std = num(v)?,
                _ => {
                    return Err(format!(
                        "delays `{spec}`: unknown key `{k}` (p, min, max, duration, mean, std)"
                    ));
                }
            }
        }
        fn need<T>(x: Option<T>, spec: &str, k: &str) -> Result<T, String> {
            x.ok_or_else(|| format!("delays `{spec}`: {k}= is missing"))
        }
        let duration_model = match duration {
            "uniform" => DurationModel::Uniform,
            "gaussian" => DurationModel::Gaussian {
                mean_ratio: mean,
                std_ratio: std,
            },
            _ => {
                return Err(format!(
                    "delays `{spec}`: duration={duration} (uniform or gaussian)"
                ));
            }
        };
        let cfg = DelayConfig {
            event_model,
            p_delay: need(p, spec, "p")?,
            min_delay: need(min, spec, "min")?,
            max_delay: need(max, spec, "max")?,
            duration_model,
        };
        cfg.check().map_err(|e| format!("delays `{spec}`: {e}"))?;
        Ok(cfg)
    }

    /// The kit's checks (`DelayGenerator::validate_config`).
    ///
    /// # Errors
    /// The first rule broken.
    pub fn check(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.p_delay) {
            return Err(format!("p={} is outside [0, 1]", self.p_delay));
        }
        if self.min_delay == 0 {
            return Err("min must be at least 1 tick".into());
        }
        if self.max_delay < self.min_delay {
            return Err(format!(
                "min={} is above max={}",
                self.min_delay, self.max_delay
            ));
        }
        if let DurationModel::Gaussian {
            mean_ratio,
            std_ratio,
        } = self.duration_model
            && (!(0.0..=1.0).contains(&mean_ratio) || std_ratio < 0.0 || !std_ratio.is_finite())
        {
            return Err(format!(
                "the gaussian's mean={mean_ratio} must be in [0, 1] and std={std_ratio} at least 0"
            ));
        }
        Ok(())
    }

    /// The spec [`DelayConfig::parse`] reads back.
    pub fn spec(&self) -> String {
        if self.p_delay == 0.0 {
            return "none".into();
        }
        let model = match self.event_model {
            EventModel::Bernoulli => "bernoulli",
            EventModel::Poisson => "poisson",
        };
        let duration = match self.duration_model {
            DurationModel::Uniform => String::new(),
            DurationModel::Gaussian {
                mean_ratio,
                std_ratio,
            } => format!(",duration=gaussian,mean={mean_ratio},std={std_ratio}"),
        };
        format!(
            "{model}:p={},min={},max={}{duration}",
            self.p_delay, self.min_delay, self.max_delay
        )
    }
}

/// Delays drawn tick by tick (module doc).
#[derive(Debug, Clone)]
pub struct DelayGenerator {
    cfg: DelayConfig,
    remaining: Vec<u32>,
    /// Each robot's delays as `[first tick, first tick after]`.
    pub intervals: Vec<Vec<[u64; 2]>>,
    rng: ChaCha8Rng,
    tick: u64,
}

impl DelayGenerator {
    /// No robot delayed yet; `robots` robots; every draw from `seed`.
    pub fn new(cfg: DelayConfig, robots: usize, seed: u64) -> Self {
        DelayGenerator {
            cfg,
            remaining: vec![0; robots],
            intervals: vec![Vec::new(); robots],
            rng: ChaCha8Rng::seed_from_u64(seed),
            tick: 0,
        }
    }

    /// Draws the delays of the next tick; afterwards [`Self::delayed`] says who is held during it.
    pub fn next_tick(&mut self) {
        for r in &mut self.remaining {
            *r = r.saturating_sub(1);
        }
        if self.cfg.p_delay > 0.0 {
            match self.cfg.event_model {
                EventModel::Bernoulli => {
                    // Robots in index order, one draw each, then the chosen ones' durations
                    // (no list of the available built; it allocates only when someone is chosen).
                    let mut chosen = Vec::new();
                    for i in 0..self.remaining.len() {
                        if self.remaining[i] == 0 && self.rng.random_bool(self.cfg.p_delay) {
                            chosen.push(i);
                        }
                    }
                    for i in chosen {
                        self.start(i);
                    }
                }
                EventModel::Poisson => {
                    let available: Vec<usize> = (0..self.remaining.len())
                        .filter(|&i| self.remaining[i] == 0)
                        .collect();
                    let rate = self.remaining.len() as f64 * self.cfg.p_delay;
                    let count = Poisson::new(rate).map_or(0.0, |d| d.sample(&mut self.rng));
                    let mut pool = available;
                    pool.shuffle(&mut self.rng);
                    pool.truncate((count as usize).min(pool.len()));
                    for i in pool {
                        self.start(i);
                    }
                }
            }
        }
        self.tick += 1;
    }

    /// Robot `i` starts a delay at the current tick.
    fn start(&mut self, i: usize) {
        let d = self.duration();
        self.remaining[i] = d;
        self.intervals[i].push([self.tick, self.tick + u64::from(d)]);
    }

    /// Whether robot `i` is held during the tick just drawn.
    pub fn delayed(&self, i: usize) -> bool {
        self.remaining[i] > 0
    }

    fn duration(&mut self) -> u32 {
        let (lo, hi) = (self.cfg.min_delay, self.cfg.max_delay);
        if lo == hi {
            return lo;
        }
        match self.cfg.duration_model {
            DurationModel::Uniform => self.rng.random_range(lo..=hi),
            DurationModel::Gaussian {
                mean_ratio,
                std_ratio,
            } => {
                let span = f64::from(hi - lo);
                let mean = f64::from(lo) + span * mean_ratio;
                let x =
                    Normal::new(mean, span * std_ratio).map_or(mean, |n| n.sample(&mut self.rng));
                (x.round().clamp(f64::from(lo), f64::from(hi))) as u32
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_read_back_and_bad_ones_name_the_item() {
        for spec in [
            "none",
            "bernoulli:p=0.01,min=1,max=4",
            "poisson:p=0.002,min=5,max=12,duration=gaussian,mean=0.5,std=0.22",
        ] {
            assert_eq!(DelayConfig::parse(spec).unwrap().spec(), spec);
        }
        for (bad, says) in [
            ("bernoulli:p=0.1,min=5,max=4", "min=5 is above max=4"),
            ("bernoulli:p=1.5,min=1,max=4", "outside [0, 1]"),
            ("bernoulli:p=0.1,min=0,max=4", "at least 1 tick"),
            ("bernoulli:p=0.1,max=4", "min= is missing"),
            ("uniform:p=0.1", "unknown model"),
            ("bernoulli:p=0.1,min=1,max=2,speed=3", "unknown key `speed`"),
            ("bernoulli:p=x,min=1,max=2", "p=x is not a number"),
            (
                "bernoulli:p=0.1,min=-1,max=2",
                "min=-1 is not a whole number",
            ),
        ] {
            let e = DelayConfig::parse(bad).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn delays_are_seeded_last_their_duration_and_follow_the_rate() {
        let cfg = DelayConfig::parse("bernoulli:p=0.05,min=2,max=5").unwrap();
        let run = |seed| {
            let mut g = DelayGenerator::new(cfg.clone(), 20, seed);
            let mut held = 0usize;
            for _ in 0..2000 {
                g.next_tick();
                held += (0..20).filter(|&i| g.delayed(i)).count();
            }
            (g.intervals, held)
        };
        let (a, held) = run(1);
        assert_eq!(a, run(1).0);
        assert_ne!(a, run(2).0);
        // Every interval lasts min..=max ticks, and intervals of a robot never overlap.
        let mut total = 0u64;
        for iv in &a {
            for w in iv.windows(2) {
                assert!(w[1][0] >= w[0][1]);
            }
            for &[s, e] in iv {
                assert!((2..=5).contains(&(e - s)));
                total += e - s;
            }
        }
        // Held ticks are the intervals' ticks (the last ones may run past the end).
        assert!(held as u64 <= total && total - held as u64 <= 20 * 5);
        // About p of the free robot-ticks start a delay (mean length 3.5).
        let starts: usize = a.iter().map(Vec::len).sum();
        let free = 20.0 * 2000.0 - held as f64;
        let rate = starts as f64 / free;
        assert!((0.035..0.065).contains(&rate), "rate {rate}");
        // Poisson: teamSize x p events a tick on average.
        let cfg = DelayConfig::parse("poisson:p=0.01,min=1,max=1").unwrap();
        let mut g = DelayGenerator::new(cfg, 100, 3);
        for _ in 0..3000 {
            g.next_tick();
        }
        let events: usize = g.intervals.iter().map(Vec::len).sum();
        let per_tick = events as f64 / 3000.0;
        assert!((0.8..1.2).contains(&per_tick), "{per_tick}");
    }
}
