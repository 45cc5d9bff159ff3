//! `wogan run`'s options, and the plan they resolve to: what was typed (options and `--config`
//! file) laid over the chosen driver's preset and the paper's defaults, resolved once into every
//! setting the run uses. The run reads nothing else, and the plan's settings are what its header
//! says.
//!
//! Precedence, lowest first: the paper's and the driver's defaults, the config file, the options.

use crate::config_file::{self, ConfigFile};
use crate::driver_options::DriverOptions;
use crate::records::{Header, VERSION};
use crate::value_parsers::{budget_duration, fitness_kind, fraction, share};
use anyhow::{bail, Context, Result};
use clap::Args;
use road_sim::{CurvatureRoad, DriverConfig, DriverKind, FitnessKind, SimConfig};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Duration;
use wogan_core::{Algorithm, Budget, RunConfig, SbstBudget, WoganConfig};

/// Options of `wogan run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The search algorithm.
    #[arg(long, value_enum, default_value_t = AlgorithmArg::Wogan)]
    pub algorithm: AlgorithmArg,
    #[command(flatten)]
    pub driver: DriverOptions,
    /// Wall-clock budget of the whole run, e.g. 30s, 10m, 3h.
    #[arg(long, value_parser = humantime::parse_duration, allow_hyphen_values = true)]
    pub budget: Option<Duration>,
    /// The SBST competition's generation budget: real time spent between tests (choosing,
    /// validating, training), seconds or e.g. 1h. Goes with --execution-budget.
    #[arg(long, value_parser = budget_duration, requires = "execution_budget", conflicts_with = "budget", allow_hyphen_values = true)]
    pub generation_budget: Option<Duration>,
    /// The SBST competition's execution budget: simulated driving time, seconds or e.g. 2h.
    /// Goes with --generation-budget.
    #[arg(long, value_parser = budget_duration, requires = "generation_budget", conflicts_with = "budget", allow_hyphen_values = true)]
    pub execution_budget: Option<Duration>,
    /// Most tests to execute [default: 300 when there is no other budget].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..), allow_negative_numbers = true)]
    pub max_tests: Option<u64>,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    pub seed: u64,
    /// Write the JSON lines to FILE instead of standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Tests simulated at once where they are independent (the random phase).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256), allow_negative_numbers = true)]
    pub jobs: u32,
    /// What the search maximises: bolp, bolp-scaled or distance [default: bolp, the paper's].
    #[arg(long, value_parser = fitness_kind)]
    pub fitness: Option<FitnessKind>,
    /// Curvature values per road (the road has one point more).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(2..=499), allow_negative_numbers = true)]
    pub curvature_points: u32,
    /// Distance between road points, metres.
    #[arg(long, default_value_t = 15.0, value_parser = crate::value_parsers::step_length_m, allow_negative_numbers = true)]
    pub step_length: f64,
    /// Share of the budget spent on the initial random search [default: 0.2].
    #[arg(long, value_parser = fraction, allow_negative_numbers = true)]
    pub init_fraction: Option<f64>,
    /// Share of WOGAN's candidates that are mutants of the best tests so far, ranked by the
    /// analyzer with the generator's (not in the paper; 0 is the paper's WOGAN) [default: 0].
    #[arg(long, value_parser = share, allow_negative_numbers = true)]
    pub mutation_share: Option<f64>,
    /// Factor applied to WOGAN's acceptance target per valid candidate: closer to 1 ranks more
    /// candidates per test [default: the paper's 0.95 with the BOLP fitnesses; with `--fitness
    /// distance` the decay matched to BOLP's at the tolerance, 0.9816 at DAVE-2's 0.10].
    #[arg(long, value_parser = fraction, allow_negative_numbers = true)]
    pub target_decay: Option<f64>,
    /// JSON file overriding the defaults: `{"search": {...}, "sim": {...}, "driver": {...}}`
    /// (the header's `config.search`, `config.sim` and `config.driver` show every field). Options
    /// given on the command line win over the file.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `--algorithm` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AlgorithmArg {
    /// WOGAN: random initial phase, then WGAN proposals ranked by the analyzer.
    Wogan,
    /// Random search with the paper's sampler for the whole budget.
    Random,
}

/// The slowest acceptance decay a matched default may have: about 5x the paper's candidates per
/// test, so that a fitness failing near its top (the distance at tolerances near 0.95) does not
/// make WOGAN rank thousands of candidates for each test.
const MAX_MATCHED_DECAY: f64 = 0.99;

/// Everything a run does, resolved.
#[derive(Debug, Clone)]
pub struct RunPlan {
    /// Seed of every random choice.
    pub seed: u64,
    /// The search algorithm.
    pub algorithm: Algorithm,
    /// What the search maximises.
    pub fitness: FitnessKind,
    /// Every other setting; written in the header.
    pub settings: RunSettings,
    /// When the run stops.
    pub budget: Budget,
    /// Where the JSON lines go (standard output when `None`).
    pub out: Option<PathBuf>,
    /// No progress bar.
    pub quiet: bool,
}

/// The settings that determine a run's results, as its header's `config` shows them.
#[derive(Debug, Clone, Serialize)]
pub struct RunSettings {
    /// Most tests to execute.
    pub max_tests: Option<u64>,
    /// Wall-clock budget, seconds.
    pub budget_s: Option<f64>,
    /// The SBST competition's generation budget (real time), seconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub generation_budget_s: Option<f64>,
    /// The SBST competition's execution budget (simulated time), seconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub execution_budget_s: Option<f64>,
    /// Tests simulated at once where they are independent.
    pub jobs: u32,
    /// Curvature values per road.
    pub curvature_points: u32,
    /// How curvature values become road points.
    pub road: CurvatureRoad,
    /// How drives are simulated and judged.
    pub sim: SimConfig,
    /// The driver under test and its tuning (serialised as the tuning of that driver).
    pub driver: DriverConfig,
    /// The search's settings.
    pub search: RunConfig,
}

impl RunPlan {
    /// Resolves `args` (and the config file it names) into a plan, or names what is wrong.
    pub fn resolve(args: &RunArgs) -> Result<Self> {
        if let Some(out) = &args.out {
            let inputs = [&args.config, &args.driver.driver_weights];
            if let Some(input) = inputs.into_iter().flatten().find(|i| same_file(out, i)) {
                bail!(
                    "--out {} is an input of the run ({}); write the run elsewhere",
                    out.display(),
                    input.display()
                );
            }
        }
        let kind = args.driver.kind;
        let preset = kind.preset();
        let file = ConfigFile::read_for(args.config.as_deref(), kind)?;
        let (sim, driver) = args.driver.resolve(&file)?;
        let fitness = args.fitness.unwrap_or(preset.fitness);
        let mut search_defaults = RunConfig::default();
        search_defaults.wogan.target_decay = default_target_decay(fitness, &sim);
        let mut search = RunConfig {
            algorithm: match args.algorithm {
                AlgorithmArg::Wogan => Algorithm::Wogan,
                AlgorithmArg::Random => Algorithm::Random,
            },
            jobs: args.jobs as usize,
            ..config_file::lay_over(file.search.as_ref(), search_defaults, "search")?
        };
        if let Some(init_fraction) = args.init_fraction {
            search.wogan.init_fraction = init_fraction;
        }
        if search.algorithm != Algorithm::Wogan {
            // How WOGAN chooses its proposals means nothing to random search: say so rather than
            // ignore it.
            let wogan_only = [
                ("--mutation-share", args.mutation_share.is_some()),
                ("--target-decay", args.target_decay.is_some()),
            ];
            if let Some((flag, _)) = wogan_only.iter().find(|(_, given)| *given) {
                bail!("{flag} applies to --algorithm wogan only");
            }
        }
        if let Some(share) = args.mutation_share {
            search.wogan.mutation.share = share;
        }
        if let Some(decay) = args.target_decay {
            search.wogan.target_decay = decay;
        }
        search.validate().context("invalid search settings")?;
        let sbst = match (args.generation_budget, args.execution_budget) {
            (Some(generation), Some(execution)) => Some(SbstBudget {
                generation,
                execution_s: execution.as_secs_f64(),
            }),
            _ => None,
        };
        let budget = Budget {
            max_tests: args.max_tests.map(|n| n as usize),
            wall: args.budget,
            sbst,
        }
        .effective();
        Ok(Self {
            seed: args.seed,
            algorithm: search.algorithm,
            fitness,
            settings: RunSettings {
                max_tests: budget.max_tests.map(|n| n as u64),
                budget_s: budget.wall.map(|d| d.as_secs_f64()),
                generation_budget_s: sbst.map(|b| b.generation.as_secs_f64()),
                execution_budget_s: sbst.map(|b| b.execution_s),
                jobs: args.jobs,
                curvature_points: args.curvature_points,
                road: CurvatureRoad {
                    map_size_m: args.driver.map_size,
                    step_m: args.step_length,
                },
                sim,
                driver,
                search,
            },
            budget,
            out: args.out.clone(),
            quiet: args.quiet,
        })
    }

    /// The driver under test.
    pub fn driver_kind(&self) -> DriverKind {
        self.settings.driver.kind()
    }

    /// The run's header record.
    pub fn header(&self) -> Header<&RunSettings> {
        Header {
            version: VERSION.to_string(),
            seed: Some(self.seed),
            algorithm: self.algorithm.name().to_owned(),
            driver: self.driver_kind(),
            fitness: self.fitness,
            config: &self.settings,
        }
    }
}

/// Whether `a` and `b` name the same existing file.
fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// WOGAN's acceptance decay unless `--target-decay` or the config file says otherwise: the
/// paper's 0.95 for the BOLP fitnesses; for the distance, the decay that reaches its failure level
/// after as many candidates as 0.95 takes to reach BOLP's at the same tolerance (0.9816 at
/// DAVE-2's 0.10, where the distance fails at 0.44 and BOLP at 0.10), so that the rule presses
/// on a failure the same whichever fitness found it.
pub fn default_target_decay(fitness: FitnessKind, sim: &SimConfig) -> f64 {
    let paper = WoganConfig::default();
    paper
        .matched_target_decay(
            FitnessKind::Bolp.failure_level(sim),
            fitness.failure_level(sim),
        )
        .map_or(paper.target_decay, |decay| decay.min(MAX_MATCHED_DECAY))
}
