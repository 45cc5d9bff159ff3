//! `wogan run`: search for roads that push the driver out of its lane, streaming one JSON line per
//! executed test, per training round, and a final summary.

use crate::config_file;
use crate::json_lines::JsonLinesWriter;
use crate::road_sut::{FitnessKind, RoadExecution, RoadSut};
use crate::sim_options::SimOptions;
use crate::Status;
use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use road_sim::heading_profile::heading_profile;
use road_sim::outcome::Outcome;
use road_sim::{CurvatureRoad, DriverKind, SimConfig, Validator};
use serde::Serialize;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use wogan_core::diversity::{median_pairwise_distance, Diversity};
use wogan_core::{Algorithm, Budget, Event, Phase, RunConfig, Summary, WoganConfig};

/// Options of `wogan run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The search algorithm.
    #[arg(long, value_enum, default_value_t = AlgorithmArg::Wogan)]
    pub algorithm: AlgorithmArg,
    #[command(flatten)]
    pub sim: SimOptions,
    /// Wall-clock budget of the whole run, e.g. 30s, 10m, 3h.
    #[arg(long, value_parser = humantime::parse_duration)]
    pub budget: Option<Duration>,
    /// Most tests to execute [default: 300 when there is no --budget].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub max_tests: Option<u64>,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Write the JSON lines to FILE instead of standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Tests simulated at once where they are independent (the random phase).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub jobs: u32,
    /// What the search maximises [default: bolp for beamng-ai-proxy, distance for dave2-proxy].
    #[arg(long, value_enum)]
    pub fitness: Option<FitnessKind>,
    /// Curvature values per road (the road has one point more).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(2..=499))]
    pub curvature_points: u32,
    /// Distance between road points, metres.
    #[arg(long, default_value_t = 15.0, value_parser = crate::validate::positive_metres)]
    pub step_length: f64,
    /// Share of the budget spent on the initial random search [default: 0.2].
    #[arg(long, value_parser = fraction)]
    pub init_fraction: Option<f64>,
    /// Share of WOGAN's candidates that are mutants of the best tests so far, ranked by the
    /// analyzer with the generator's (not in the paper; 0 is the paper's WOGAN) [default: 0].
    #[arg(long, value_parser = share)]
    pub mutation_share: Option<f64>,
    /// Factor applied to WOGAN's acceptance target per valid candidate: closer to 1 ranks more
    /// candidates per test [default: the paper's 0.95 with the BOLP fitnesses; with `--fitness
    /// distance` the decay matched to BOLP's at the tolerance, 0.9816 at DAVE-2's 0.10].
    #[arg(long, value_parser = fraction)]
    pub target_decay: Option<f64>,
    /// JSON file overriding the paper's defaults: `{"search": {...}, "sim": {...}}` (the
    /// header's `config.search` and `config.sim` show every field). Options given on the command
    /// line win over the file.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The settings a `--config` file may override: partial objects, laid over the defaults.
#[derive(Debug, Default, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
struct ConfigFile {
    search: Option<serde_json::Value>,
    sim: Option<serde_json::Value>,
}

/// `--algorithm` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AlgorithmArg {
    /// WOGAN: random initial phase, then WGAN proposals ranked by the analyzer.
    Wogan,
    /// Random search with the paper's sampler for the whole budget.
    Random,
}

fn fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v < 1.0 => Ok(v),
        _ => Err(format!(
            "expected a number strictly between 0 and 1, got {text:?}"
        )),
    }
}

fn share(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("expected a number from 0 to 1, got {text:?}")),
    }
}

/// The fitness a driver is searched with unless `--fitness` says otherwise.
fn default_fitness(driver: DriverKind) -> FitnessKind {
    match driver {
        DriverKind::BeamNgAiProxy => FitnessKind::Bolp,
        // DAVE-2's BOLP stays 0 on most roads, which leaves nothing to learn from.
        DriverKind::Dave2Proxy => FitnessKind::Distance,
    }
}

/// The slowest acceptance decay a matched default may have: about 5x the paper's candidates per
/// test, so that a fitness failing near its top (the distance at tolerances near 0.95) does not
/// make WOGAN rank thousands of candidates for each test.
const MAX_MATCHED_DECAY: f64 = 0.99;

/// WOGAN's acceptance decay unless `--target-decay` or the config file says otherwise: the
/// paper's 0.95 for the BOLP fitnesses; for the distance, the decay that reaches its failure level
/// after as many candidates as 0.95 takes to reach BOLP's at the same tolerance (0.9816 at
/// DAVE-2's 0.10, where the distance fails at 0.44 and BOLP at 0.10), so that the rule presses
/// on a failure the same whichever fitness found it.
fn default_target_decay(fitness: FitnessKind, sim: &SimConfig) -> f64 {
    let paper = WoganConfig::default();
    paper
        .matched_target_decay(
            FitnessKind::Bolp.failure_level(sim),
            fitness.failure_level(sim),
        )
        .map_or(paper.target_decay, |decay| decay.min(MAX_MATCHED_DECAY))
}

/// Everything that determines a run, written in the header.
#[derive(Debug, Serialize)]
struct RunSettings<'a> {
    max_tests: Option<u64>,
    budget_s: Option<f64>,
    jobs: u32,
    curvature_points: u32,
    road: CurvatureRoad,
    sim: &'a SimConfig,
    search: &'a RunConfig,
}

#[derive(Debug, Serialize)]
struct Header<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    version: &'static str,
    seed: u64,
    algorithm: Algorithm,
    oracle: DriverKind,
    fitness: FitnessKind,
    config: RunSettings<'a>,
}

#[derive(Debug, Serialize)]
struct TestRecord<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    id: usize,
    phase: Phase,
    fitness: f64,
    predicted_fitness: Option<f64>,
    invalid_candidates: usize,
    ranked_candidates: usize,
    generation_ms: f64,
    #[serde(flatten)]
    execution: &'a RoadExecution,
}

#[derive(Debug, Serialize)]
struct SummaryRecord {
    #[serde(rename = "type")]
    kind: &'static str,
    executed: usize,
    failed: usize,
    invalid_candidates: usize,
    wall_s: f64,
    generation_s: f64,
    training_s: f64,
    simulation_s: f64,
    diversity: Option<f64>,
    diversity_pairs: &'static str,
    interrupted: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

/// Runs `wogan run`.
pub fn run(args: &RunArgs) -> Result<Status> {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = Arc::clone(&stop);
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst))
            .context("cannot install the Ctrl-C handler")?;
    }
    let file = match &args.config {
        Some(path) => config_file::read::<ConfigFile>(path)?,
        None => ConfigFile::default(),
    };
    let sim = args.sim.apply_to(config_file::lay_over(
        file.sim.as_ref(),
        args.sim.driver_defaults(),
        "\"sim\"",
    )?);
    let fitness = args
        .fitness
        .unwrap_or_else(|| default_fitness(args.sim.oracle));
    let roads = CurvatureRoad {
        map_size_m: args.sim.map_size,
        step_m: args.step_length,
    };
    let mut search_defaults = RunConfig::default();
    search_defaults.wogan.target_decay = default_target_decay(fitness, &sim);
    let mut search = RunConfig {
        algorithm: match args.algorithm {
            AlgorithmArg::Wogan => Algorithm::Wogan,
            AlgorithmArg::Random => Algorithm::Random,
        },
        jobs: args.jobs as usize,
        ..config_file::lay_over(file.search.as_ref(), search_defaults, "\"search\"")?
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
            anyhow::bail!("{flag} applies to --algorithm wogan only");
        }
    }
    if let Some(share) = args.mutation_share {
        search.wogan.mutation.share = share;
    }
    if let Some(decay) = args.target_decay {
        search.wogan.target_decay = decay;
    }
    search.validate().context("invalid search settings")?;
    sim.validate()
        .map_err(|problem| anyhow::anyhow!("invalid simulation settings: {problem}"))?;
    let driver = args.sim.driver_setup()?;
    let budget = Budget {
        max_tests: args.max_tests.map(|n| n as usize),
        wall: args.budget,
    }
    .effective();
    let mut out = JsonLinesWriter::create(args.out.as_ref())?;
    out.write(&Header {
        kind: "header",
        version: env!("CARGO_PKG_VERSION"),
        seed: args.seed,
        algorithm: search.algorithm,
        oracle: args.sim.oracle,
        fitness,
        config: RunSettings {
            max_tests: budget.max_tests.map(|n| n as u64),
            budget_s: budget.wall.map(|d| d.as_secs_f64()),
            jobs: args.jobs,
            curvature_points: args.curvature_points,
            road: roads,
            sim: &sim,
            search: &search,
        },
    })?;
    let sut = RoadSut {
        roads,
        curvature_points: args.curvature_points as usize,
        validator: Validator::new(args.sim.map_size),
        driver,
        sim,
        fitness,
    };
    let progress = Progress::new(&budget, args.quiet);
    let mut failing_profiles: Vec<Vec<f64>> = Vec::new();
    let mut write_error: Option<anyhow::Error> = None;
    let outcome = wogan_core::run(&sut, &search, budget, args.seed, &stop, &mut |event| {
        let written = match &event {
            Event::Test {
                id,
                phase,
                fitness,
                predicted_fitness,
                invalid_candidates,
                ranked_candidates,
                generation_ms,
                output,
                ..
            } => {
                let failed = output.result.outcome == Outcome::Fail;
                if failed {
                    failing_profiles.push(heading_profile(&output.interpolated));
                }
                progress.test_done(failing_profiles.len());
                out.write(&TestRecord {
                    kind: "test",
                    id: *id,
                    phase: *phase,
                    fitness: *fitness,
                    predicted_fitness: *predicted_fitness,
                    invalid_candidates: *invalid_candidates,
                    ranked_candidates: *ranked_candidates,
                    generation_ms: *generation_ms,
                    execution: output,
                })
            }
            Event::Train { .. } => out.write(&event),
        };
        if let Err(error) = written {
            // Output is gone (a closed pipe, a full disk): stop searching, keep the first error.
            stop.store(true, Ordering::SeqCst);
            write_error.get_or_insert(error);
        }
    });
    progress.finish();
    if let Some(error) = write_error {
        return Err(error);
    }
    let diversity = median_pairwise_distance(&failing_profiles, args.seed);
    let (summary, error) = match outcome {
        Ok(summary) => (summary, None),
        Err(error) => (Summary::default(), Some(error.to_string())),
    };
    write_summary(
        &mut out,
        &summary,
        failing_profiles.len(),
        diversity,
        error.clone(),
    )?;
    match (error, summary.stopped_by_signal) {
        (Some(error), _) => {
            eprintln!("wogan: the search failed: {error}");
            Ok(Status::Failed)
        }
        (None, true) => Ok(Status::Interrupted),
        (None, false) => Ok(Status::AllRead),
    }
}

fn write_summary(
    out: &mut JsonLinesWriter,
    summary: &Summary,
    failed: usize,
    diversity: Diversity,
    error: Option<String>,
) -> Result<()> {
    out.write(&SummaryRecord {
        kind: "summary",
        executed: summary.executed,
        failed,
        invalid_candidates: summary.invalid_candidates,
        wall_s: summary.wall_s,
        generation_s: summary.generation_s,
        training_s: summary.training_s,
        simulation_s: summary.simulation_s,
        diversity: diversity.median_distance,
        diversity_pairs: diversity.pairs,
        interrupted: summary.stopped_by_signal,
        error,
    })
}

/// The progress bar on stderr, shown only on a terminal.
struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    fn new(budget: &Budget, quiet: bool) -> Self {
        if quiet || !std::io::stderr().is_terminal() {
            return Self { bar: None };
        }
        let bar = match (budget.max_tests, budget.wall) {
            (Some(tests), _) => {
                let bar = ProgressBar::new(tests as u64);
                bar.set_style(
                    ProgressStyle::with_template(
                        "{elapsed_precise} [{bar:30}] {pos}/{len} tests, {msg}, {eta} left",
                    )
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
                bar
            }
            (None, wall) => {
                let bar = ProgressBar::new_spinner();
                let limit = wall
                    .map(|w| humantime::format_duration(w).to_string())
                    .unwrap_or_default();
                bar.set_style(
                    ProgressStyle::with_template(&format!(
                        "{{elapsed_precise}} of {limit} {{pos}} tests, {{msg}}"
                    ))
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                );
                bar
            }
        };
        bar.set_message("0 failures");
        Self { bar: Some(bar) }
    }

    fn test_done(&self, failures: usize) {
        if let Some(bar) = &self.bar {
            bar.inc(1);
            bar.set_message(format!("{failures} failures"));
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }
}
