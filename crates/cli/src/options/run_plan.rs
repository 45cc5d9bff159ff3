//! `wogan run`'s options, and the plan they resolve to: what was typed (options and `--config`
//! file) laid over the chosen driver's competition setup and the paper's defaults, resolved once
//! into every setting the run uses. The run reads nothing else, and the plan's settings are what
//! its header says.
//!
//! Precedence, lowest first: the paper's and the driver's defaults, the config file, the options.

use crate::files::generator_file::{self, GeneratorPayload};
use crate::files::output_file::same_file;
use crate::files::records::{Header, Oracle, VERSION};
use crate::options::config_file::{self, ConfigFile};
use crate::options::driver_options::{DriverOptions, DEFAULT_MAP_SIZE_M};
use crate::options::executor_options::ExecutorOptions;
use crate::options::search_preset::SearchPreset;
use crate::options::value_parsers::{
    budget_duration, fitness_kind, fraction, road_placement, road_shape, share,
};
use crate::sut::executor_protocol::ExecutorDescription;
use crate::sut::ExecutorSettings;
use anyhow::{bail, Context, Result};
use clap::Args;
use road_sim::road::curvature::DEFAULT_STEP_M;
use road_sim::road::RoadShape;
use road_sim::{
    CompetitionSetup, CurvatureRoad, DriverConfig, DriverKind, FitnessKind, RoadPlacement,
    SimConfig,
};
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
    /// Tests simulated at once: random tests N at a time, and WOGAN's in rounds of up to N
    /// chosen tests (1 is the paper's WOGAN; the same seed and N give the same run).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256), allow_negative_numbers = true)]
    pub jobs: u32,
    /// With --jobs above 1, how WOGAN's acceptance target carries over between the tests of a
    /// round: restart (from 1, as a test alone) or continue (from where the last choice left it)
    /// [default: restart].
    #[arg(long, value_parser = crate::options::value_parsers::round_acceptance)]
    pub round_acceptance: Option<wogan_core::RoundAcceptance>,
    /// What the search maximises: bolp, bolp-scaled or distance (the lane distance; an executor
    /// must then answer with `min_lane_distance_m`) [default: bolp, the paper's].
    #[arg(long, value_parser = fitness_kind)]
    pub fitness: Option<FitnessKind>,
    /// Curvature values per road (the road has one point more) [default: 5, the paper's, or the
    /// preset's].
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=499), allow_negative_numbers = true)]
    pub curvature_points: Option<u32>,
    /// A named set of search settings laid over the paper's WOGAN (the config file and the other
    /// options still win): `sbst`, failures many, distinct and varied as whole roads under the
    /// SBST competition's rules; `sbst-no-niches`, the same without niches, the most failures,
    /// all alike as whole roads (docs/reference.md).
    #[arg(long, value_enum)]
    pub preset: Option<SearchPreset>,
    /// Where roads lie on the map: `bottom-centre` (starting there heading north, the paper's) or
    /// `fitted` (a road that leaves the map from there is turned and moved until it fits, as the
    /// Frenetic generators place theirs) [default: bottom-centre, or the preset's].
    #[arg(long, value_parser = road_placement)]
    pub road_placement: Option<RoadPlacement>,
    /// How the niches and the shape novelty rule compare roads: `headings` (the heading profile,
    /// unwrapped) or `directions` (the WOGAN authors' diversity description: directions from
    /// north, not unwrapped) [default: headings, or the preset's].
    #[arg(long, value_parser = road_shape)]
    pub road_shape: Option<RoadShape>,
    /// Test only roads that turn at least this far from their first heading somewhere, radians,
    /// 0 to 6.283 (a narrower search, not a rule of the competition) [default: 0, any road, or
    /// the preset's].
    #[arg(long, value_name = "RAD", value_parser = crate::options::value_parsers::turn_rad)]
    pub min_road_turn: Option<f64>,
    /// Distance between road points, metres [default: 15, the paper's, or the preset's].
    #[arg(long, value_parser = crate::options::value_parsers::step_length_m, allow_negative_numbers = true)]
    pub step_length: Option<f64>,
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
    /// What makes the exit status 1: never (whatever the run found), or a failing road.
    #[arg(long, value_enum, default_value_t = FailOn::Never)]
    pub fail_on: FailOn,
    /// Also write a JUnit XML report to FILE: one test case per executed test, a failure for each
    /// failing road (written when the run ends, also after Ctrl-C).
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// When the run ends, save its trained generator and analyzer to FILE, for `wogan sample`
    /// (WOGAN only; versioned, with a checksum).
    #[arg(long, value_name = "FILE")]
    pub save_generator: Option<PathBuf>,
    /// Choose every test with the generator and analyzer saved in FILE (`--save-generator`), as
    /// the trained WOGAN chooses: no random phase, no training. Its roads' settings and WOGAN's
    /// settings are the file's.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["save_generator", "mutation_share", "target_decay", "init_fraction", "round_acceptance", "preset", "road_placement", "road_shape", "min_road_turn"])]
    pub generator: Option<PathBuf>,
    #[command(flatten)]
    pub executor: ExecutorOptions,
}

/// Curvature values per road unless `--curvature-points` says otherwise (the paper's).
const DEFAULT_CURVATURE_POINTS: u32 = 5;

/// `--fail-on` values of `wogan run`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FailOn {
    /// Exit 0 whatever the run found (the search's own use).
    Never,
    /// Exit 1 when the run found a failing road (a CI smoke run).
    Failure,
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
    /// What makes the exit status 1.
    pub fail_on: FailOn,
    /// Where the JUnit report goes, if anywhere.
    pub junit: Option<PathBuf>,
    /// Where the trained generator goes, if anywhere.
    pub save_generator: Option<PathBuf>,
    /// The saved generator every test is chosen with (`--generator`), if any.
    pub generator: Option<GeneratorPayload>,
    /// The driver wogan's simulator drives the roads with, unless an executor does.
    pub driver: DriverConfig,
    /// The external program that drives the roads (`--executor`), if any.
    pub executor: Option<ExecutorSettings>,
    /// Drives a controller or executor may fail in a row before the run stops.
    pub max_failed_drives: usize,
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
    /// The named set of search settings the run started from, when one was given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<SearchPreset>,
    /// Curvature values per road.
    pub curvature_points: u32,
    /// How curvature values become road points.
    pub road: CurvatureRoad,
    /// How the niches and the shape novelty rule compare roads.
    pub road_shape: RoadShape,
    /// Least turn of a tested road from its first heading, radians (0: any road).
    pub min_road_turn_rad: f64,
    /// How drives are simulated and judged.
    pub sim: SimConfig,
    /// The driver under test and its tuning (serialised as the tuning of that driver); none when
    /// an executor drives.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub driver: Option<DriverConfig>,
    /// The search's settings.
    pub search: RunConfig,
    /// The saved generator the tests are chosen with, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub generator: Option<GeneratorSource>,
    /// The external program that drove the roads, when one did (`--executor`; recorded, never
    /// started from a file).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub executor: Option<ExecutorRecord>,
}

/// The executor that drove a run's roads, as its header records it: its command (recorded, never
/// started from a file) and what it said of itself in its reply to `hello` (every field
/// optional, absent when no executor answered before the run began).
#[derive(Debug, Clone, Serialize)]
pub struct ExecutorRecord {
    /// The command, as typed after `cmd:`.
    pub command: String,
    /// Its name, version and own settings.
    #[serde(flatten)]
    pub description: ExecutorDescription,
    /// How many roads one executor took at once.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roads_at_once: Option<usize>,
}

impl ExecutorRecord {
    /// The record of the executor run with `command`, before it has said anything.
    pub fn command(command: String) -> Self {
        Self {
            command,
            description: ExecutorDescription::default(),
            roads_at_once: None,
        }
    }
}

/// Which saved generator a run chose its tests with, as its header records it.
#[derive(Debug, Clone, Serialize)]
pub struct GeneratorSource {
    /// The file, as given.
    pub file: String,
    /// The driver it was trained against.
    pub driver: String,
    /// The seed of the run that trained it.
    pub seed: u64,
    /// How many tests it learnt from.
    pub tests: usize,
}

impl RunPlan {
    /// Resolves `args` (and the config file it names) into a plan, or names what is wrong.
    pub fn resolve(args: &RunArgs) -> Result<Self> {
        check_outputs(args)?;
        let kind = args.driver.kind();
        let setup = CompetitionSetup::of(kind);
        let file = ConfigFile::read_for(args.config.as_deref(), kind)?;
        let (sim, driver) = args.driver.resolve(&file)?;
        let fitness = args.fitness.unwrap_or(setup.fitness());
        let mut search = search_settings(args, kind, &file, fitness, &sim)?;
        let sbst = match (args.generation_budget, args.execution_budget) {
            (Some(generation), Some(execution)) => Some(SbstBudget {
                generation,
                execution_s: execution.as_secs_f64(),
            }),
            _ => None,
        };
        let generator = match &args.generator {
            Some(path) => Some(generator_file::read(path)?),
            None => None,
        };
        let (curvature_points, road, road_shape, min_road_turn_rad) =
            road_settings(args, kind, generator.as_ref(), &mut search)?;
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
                preset: args.preset,
                curvature_points,
                road,
                road_shape,
                min_road_turn_rad,
                sim,
                driver: args.executor.executor.is_none().then(|| driver.clone()),
                search,
                executor: args.executor.executor.clone().map(ExecutorRecord::command),
                generator: args
                    .generator
                    .as_ref()
                    .zip(generator.as_ref())
                    .map(|(path, saved)| GeneratorSource {
                        file: path.display().to_string(),
                        driver: saved.driver.clone(),
                        seed: saved.seed,
                        tests: saved.tests,
                    }),
            },
            budget,
            out: args.out.clone(),
            quiet: args.quiet,
            fail_on: args.fail_on,
            junit: args.junit.clone(),
            save_generator: args.save_generator.clone(),
            generator,
            driver,
            executor: args.executor.settings(),
            max_failed_drives: args.executor.max_failed_drives as usize,
        })
    }

    /// The search's name as the header gives it: `wogan`, `random`, or `wogan-generator` for a
    /// run that chooses its tests with a saved generator.
    pub fn algorithm_name(&self) -> &'static str {
        if self.generator.is_some() {
            "wogan-generator"
        } else {
            self.algorithm.name()
        }
    }

    /// The driver under test (when an executor drives: the driver whose competition setup gave
    /// the conditions told to it).
    pub fn driver_kind(&self) -> DriverKind {
        self.driver.kind()
    }

    /// The run's header record. An executor's run names the executor, not a driver of wogan's
    /// that it did not use.
    pub fn header(&self) -> Header<&RunSettings> {
        Header {
            version: VERSION.to_string(),
            seed: Some(self.seed),
            algorithm: self.algorithm_name().to_owned(),
            driver: match self.executor {
                Some(_) => Oracle::Executor,
                None => Oracle::Driver(self.driver_kind()),
            },
            fitness: self.fitness,
            config: &self.settings,
        }
    }
}

/// Refuses an output that would overwrite an input of the run, or another output.
fn check_outputs(args: &RunArgs) -> Result<()> {
    let inputs = [&args.config, &args.driver.driver_weights, &args.generator];
    let outputs = [
        ("--out", &args.out),
        ("--junit", &args.junit),
        ("--save-generator", &args.save_generator),
    ];
    for (flag, output) in outputs {
        let Some(output) = output else { continue };
        if let Some(input) = inputs.into_iter().flatten().find(|i| same_file(output, i)) {
            bail!(
                "{flag} {} is an input of the run ({}); write it elsewhere",
                output.display(),
                input.display()
            );
        }
    }
    for (i, (flag, output)) in outputs.iter().enumerate() {
        for (other_flag, other) in &outputs[i + 1..] {
            if let (Some(a), Some(b)) = (output, other) {
                if a == b || same_file(a, b) {
                    bail!(
                        "{other_flag} {} is the {flag} file too; give each its own file",
                        b.display()
                    );
                }
            }
        }
    }
    Ok(())
}

/// WOGAN's or random search's settings: the paper's (the decay matched to the fitness), the
/// preset's, the config file's `search` section, then the options; checked.
fn search_settings(
    args: &RunArgs,
    kind: DriverKind,
    file: &ConfigFile,
    fitness: FitnessKind,
    sim: &SimConfig,
) -> Result<RunConfig> {
    let mut search_defaults = RunConfig::default();
    search_defaults.wogan.target_decay = default_target_decay(fitness, sim);
    if let Some(preset) = args.preset {
        preset.apply(&mut search_defaults, kind);
    }
    let mut search = RunConfig {
        algorithm: match args.algorithm {
            AlgorithmArg::Wogan => Algorithm::Wogan,
            AlgorithmArg::Random => Algorithm::Random,
        },
        jobs: args.jobs as usize,
        ..config_file::lay_over(file.search.as_ref(), search_defaults, "search")?
    };
    if search.wogan.niches.quota > 0 && search.wogan.niches.min_fitness == 0.0 {
        // Niches are filled by failures: unless told otherwise, the run's own.
        search.wogan.niches.min_fitness = fitness.failure_level(sim);
    }
    if search.wogan.remakes.enabled && search.wogan.remakes.min_fitness == 0.0 {
        // The failures remade are, unless told otherwise, the run's own.
        search.wogan.remakes.min_fitness = fitness.failure_level(sim);
    }
    if let Some(init_fraction) = args.init_fraction {
        search.wogan.init_fraction = init_fraction;
    }
    if search.algorithm != Algorithm::Wogan {
        // How WOGAN chooses its proposals means nothing to random search: say so rather than
        // ignore it.
        let wogan_only = [
            ("--mutation-share", args.mutation_share.is_some()),
            ("--target-decay", args.target_decay.is_some()),
            ("--round-acceptance", args.round_acceptance.is_some()),
            ("--preset", args.preset.is_some()),
            ("--save-generator", args.save_generator.is_some()),
            ("--generator", args.generator.is_some()),
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
    if let Some(rule) = args.round_acceptance {
        search.wogan.round_acceptance = rule;
    }
    search.validate().context("invalid search settings")?;
    Ok(search)
}

/// How test vectors become roads (curvature values, step, placement, shape, least turn): a
/// saved generator's (whose WOGAN settings then replace `search`'s), or the options' over the
/// preset's over the paper's.
fn road_settings(
    args: &RunArgs,
    kind: DriverKind,
    generator: Option<&GeneratorPayload>,
    search: &mut RunConfig,
) -> Result<(u32, CurvatureRoad, RoadShape, f64)> {
    Ok(match generator {
        Some(saved) => {
            let typed = (
                args.curvature_points.unwrap_or(DEFAULT_CURVATURE_POINTS),
                args.step_length.unwrap_or(DEFAULT_STEP_M),
                args.driver.map_size,
            );
            let file = (
                saved.curvature_points as u32,
                saved.road.step_m,
                saved.road.map_size_m,
            );
            let defaults = (DEFAULT_CURVATURE_POINTS, DEFAULT_STEP_M, DEFAULT_MAP_SIZE_M);
            if typed != file && typed != defaults {
                bail!(
                    "--generator makes roads of {} curvature points, {} m apart, on a {} m map; \
                     leave --curvature-points, --step-length and --map-size out, or give those",
                    file.0,
                    file.1,
                    file.2
                );
            }
            // WOGAN's settings are the ones the networks were trained with.
            search.wogan = saved.model.config.clone();
            (
                saved.curvature_points as u32,
                saved.road,
                saved.road_shape,
                saved.min_road_turn_rad,
            )
        }
        None => {
            let preset = args.preset.map(|p| p.roads(kind));
            (
                args.curvature_points
                    .or(preset.map(|r| r.curvature_points))
                    .unwrap_or(DEFAULT_CURVATURE_POINTS),
                CurvatureRoad {
                    map_size_m: args.driver.map_size,
                    step_m: args
                        .step_length
                        .or(preset.map(|r| r.step_m))
                        .unwrap_or(DEFAULT_STEP_M),
                    placement: args
                        .road_placement
                        .or(preset.map(|r| r.placement))
                        .unwrap_or_default(),
                },
                args.road_shape
                    .or(preset.map(|r| r.shape))
                    .unwrap_or_default(),
                args.min_road_turn
                    .or(preset.map(|r| r.min_turn_rad))
                    .unwrap_or(0.0),
            )
        }
    })
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
