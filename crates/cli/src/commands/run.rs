//! `wogan run`: search for roads that push the driver out of its lane, streaming one JSON line per
//! executed test, per training round, and a final summary.

use super::Status;
use crate::files::generator_file::{self, GeneratorPayload};
use crate::files::json_lines::JsonLinesWriter;
use crate::files::junit::{self, JunitCase};
use crate::files::records::{Header, Record, RoadExecution, SummaryRecord, TestRecord};
use crate::interrupt::stop_flag;
use crate::options::run_plan::{FailOn, RunArgs, RunPlan};
use crate::sut::failure_streak::FailureStreak;
use crate::sut::road_sut::RoadSut;
use crate::sut::{ExecutorDriver, ExecutorSut, HelloSettings};
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use road_sim::road::diversity_profile::diversity_profile;
use road_sim::{FitnessKind, Validator};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use wogan_core::diversity::median_pairwise_distance;
use wogan_core::{Budget, Event, ModelSnapshot, Summary, Sut};

/// Runs `wogan run`.
pub fn run(args: &RunArgs) -> Result<Status> {
    let plan = RunPlan::resolve(args)?;
    let stop = stop_flag()?;
    execute(&plan, &stop)
}

/// Searches as `plan` says until its budget is spent or `stop` is set, writing every record.
fn execute(plan: &RunPlan, stop: &AtomicBool) -> Result<Status> {
    let mut out = JsonLinesWriter::create(plan.out.as_ref())?;
    let settings = &plan.settings;
    let streak = FailureStreak::new(plan.max_failed_drives);
    let executor = plan.executor.as_ref().map(|executor| {
        let hello = HelloSettings::of(settings.road.map_size_m, &settings.sim);
        let needs_lane_distance = plan.fitness == FitnessKind::Distance;
        ExecutorDriver::new(executor.clone(), hello, needs_lane_distance, &streak, stop)
    });
    // The first executor answers `hello` before the header is written, which records what it
    // said of itself; one that cannot even be started ends the run.
    let not_started = executor.as_ref().and_then(|e| e.start().err());
    let described = executor.as_ref().and_then(ExecutorDriver::description);
    let mut recorded = settings.clone();
    if let (Some(record), Some((description, roads_at_once))) =
        (recorded.executor.as_mut(), described.clone())
    {
        record.description = description;
        record.roads_at_once = Some(roads_at_once);
    }
    out.write_header(Header {
        config: &recorded,
        ..plan.header()
    })?;
    let sut = RoadSut {
        roads: settings.road,
        curvature_points: settings.curvature_points as usize,
        shape: settings.road_shape,
        min_turn_rad: settings.min_road_turn_rad,
        validator: Validator::new(settings.road.map_size_m),
        driver: plan.driver.clone(),
        sim: settings.sim,
        fitness: plan.fitness,
        stop,
        streak: Some(&streak),
    };
    let progress = Progress::new(&plan.budget, plan.quiet);
    let mut failing_profiles: Vec<Vec<f64>> = Vec::new();
    // What the JUnit report needs of each test, kept only when one is asked for.
    let mut driven: Vec<TestRecord> = Vec::new();
    let mut write_error: Option<anyhow::Error> = None;
    let mut on_event = |event| {
        let record = Record::of_event(event);
        if let Record::Test(test) = &record {
            if test.failed() && !test.beyond_budget {
                failing_profiles.push(diversity_profile(&test.execution.interpolated));
            }
            progress.test_done(failing_profiles.len());
            if plan.junit.is_some() {
                driven.push(test.clone());
            }
        }
        if let Err(error) = out.write(&record) {
            // Output is gone (a closed pipe, a full disk): stop searching, keep the first error.
            stop.store(true, Ordering::SeqCst);
            write_error.get_or_insert(error);
        }
    };
    let outcome = match (&executor, not_started) {
        (_, Some(reason)) => Err(reason),
        (Some(executor), None) => {
            let sut = ExecutorSut::new(sut.clone(), settings.sim, plan.fitness, executor);
            search(&sut, plan, stop, &mut on_event).map_err(|e| e.to_string())
        }
        (None, None) => search(&sut, plan, stop, &mut on_event).map_err(|e| e.to_string()),
    };
    let gave_up = streak.gave_up();
    // The summary repeats the header's description, for readers of the older summaries.
    let described = described.and_then(|(description, roads_at_once)| {
        let mut described = serde_json::to_value(description).ok()?;
        described["roads_at_once"] = roads_at_once.into();
        Some(described)
    });
    // The executors end (and are reaped) before the summary is written.
    drop(executor);
    progress.finish();
    if let Some(error) = write_error {
        return Err(error);
    }
    let diversity = median_pairwise_distance(&failing_profiles, plan.seed);
    let (summary, snapshot, error) = match outcome {
        Ok((summary, snapshot)) => (summary, snapshot, gave_up),
        Err(error) => (Summary::default(), None, Some(error)),
    };
    out.write(&Record::Summary(SummaryRecord {
        executed: summary.executed,
        failed: failing_profiles.len(),
        invalid_candidates: summary.invalid_candidates,
        wall_s: summary.wall_s,
        generation_s: summary.generation_s,
        training_s: summary.training_s,
        simulation_s: summary.simulation_s,
        sbst_generation_s: Some(summary.sbst_generation_s),
        execution_time_s: Some(summary.execution_time_s),
        beyond_budget: Some(summary.beyond_budget),
        diversity: diversity.median_distance,
        diversity_pairs: diversity.pairs.to_owned(),
        interrupted: summary.stopped_by_signal,
        error: error.clone(),
        executor: described,
    }))?;
    if let Some(path) = &plan.junit {
        write_junit(path, plan, &driven)?;
    }
    if let Some(path) = &plan.save_generator {
        let Some(model) = snapshot else {
            eprintln!(
                "wogan: --save-generator {}: no generator was trained (the run ended before its \
                 first training round)",
                path.display()
            );
            return Ok(Status::Failed);
        };
        generator_file::write(
            path,
            GeneratorPayload {
                wogan: generator_file::wogan_version(),
                driver: plan.driver_kind().name().to_owned(),
                oob_tolerance: settings.sim.oob_tolerance,
                seed: plan.seed,
                tests: summary.executed,
                curvature_points: settings.curvature_points as usize,
                road: settings.road,
                road_shape: settings.road_shape,
                min_road_turn_rad: settings.min_road_turn_rad,
                sampler: settings.search.sampler.clone(),
                model,
            },
        )?;
        eprintln!("wogan: saved the generator to {}", path.display());
    }
    let found_failure = !failing_profiles.is_empty();
    match (error, summary.stopped_by_signal) {
        (Some(error), _) => {
            eprintln!("wogan: the search failed: {error}");
            Ok(Status::Failed)
        }
        (None, true) => Ok(Status::Interrupted),
        (None, false) if plan.fail_on == FailOn::Failure && found_failure => {
            eprintln!(
                "wogan: the run found {} failing road(s) (--fail-on failure)",
                failing_profiles.len()
            );
            Ok(Status::FailuresFound)
        }
        (None, false) => Ok(Status::AllRead),
    }
}

/// Writes the run's JUnit report: one case per executed test (those beyond an SBST budget, which
/// the competition does not keep, are left out).
fn write_junit(path: &std::path::Path, plan: &RunPlan, tests: &[TestRecord]) -> Result<()> {
    let source = plan
        .out
        .as_ref()
        .map_or_else(|| "wogan run".to_owned(), |p| p.display().to_string());
    let cases: Vec<JunitCase> = tests
        .iter()
        .filter(|t| !t.beyond_budget)
        .map(|t| JunitCase {
            name: format!("test {} ({})", t.id, t.phase.name()),
            source: source.clone(),
            road_points: &t.execution.road_points,
            result: Some(&t.execution.result),
            skip_reason: None,
            note: None,
        })
        .collect();
    let properties = [
        ("seed", plan.seed.to_string()),
        ("driver", plan.driver_kind().name().to_owned()),
        ("algorithm", plan.algorithm_name().to_owned()),
        ("fitness", plan.fitness.name().to_owned()),
        ("wogan", crate::files::records::VERSION.to_owned()),
    ];
    junit::write_report(path, "wogan run", &properties, &cases)
}

/// Runs the plan's search on `sut`: from a saved generator, or WOGAN or random search.
fn search<S: Sut<Output = RoadExecution> + ?Sized>(
    sut: &S,
    plan: &RunPlan,
    stop: &AtomicBool,
    on_event: &mut dyn FnMut(Event<RoadExecution>),
) -> Result<(Summary, Option<ModelSnapshot>), wogan_core::Error> {
    let (config, budget, seed) = (&plan.settings.search, plan.budget, plan.seed);
    match &plan.generator {
        Some(saved) => {
            wogan_core::run_from_snapshot(sut, &saved.model, config, budget, seed, stop, on_event)
                .map(|summary| (summary, None))
        }
        None => wogan_core::run_with_snapshot(sut, config, budget, seed, stop, on_event),
    }
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
                let limit = match (budget.sbst, wall) {
                    (Some(b), _) => format!("{} s simulated", b.execution_s),
                    (None, Some(w)) => humantime::format_duration(w).to_string(),
                    (None, None) => String::new(),
                };
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
