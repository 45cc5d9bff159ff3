//! `wogan run`: search for roads that push the driver out of its lane, streaming one JSON line per
//! executed test, per training round, and a final summary.

use super::Status;
use crate::interrupt::stop_flag;
use crate::json_lines::JsonLinesWriter;
use crate::plan::{RunArgs, RunPlan};
use crate::records::{Record, SummaryRecord, TestRecord, TrainRecord};
use crate::road_sut::RoadSut;
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use road_sim::road::heading_profile::heading_profile;
use road_sim::Validator;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use wogan_core::diversity::median_pairwise_distance;
use wogan_core::{Budget, Event, Summary};

/// Runs `wogan run`.
pub fn run(args: &RunArgs) -> Result<Status> {
    let plan = RunPlan::resolve(args)?;
    let stop = stop_flag()?;
    execute(&plan, &stop)
}

/// Searches as `plan` says until its budget is spent or `stop` is set, writing every record.
fn execute(plan: &RunPlan, stop: &AtomicBool) -> Result<Status> {
    let mut out = JsonLinesWriter::create(plan.out.as_ref())?;
    out.write_header(plan.header())?;
    let settings = &plan.settings;
    let sut = RoadSut {
        roads: settings.road,
        curvature_points: settings.curvature_points as usize,
        validator: Validator::new(settings.road.map_size_m),
        driver: settings.driver.clone(),
        sim: settings.sim,
        fitness: plan.fitness,
        stop,
    };
    let progress = Progress::new(&plan.budget, plan.quiet);
    let mut failing_profiles: Vec<Vec<f64>> = Vec::new();
    let mut write_error: Option<anyhow::Error> = None;
    let outcome = wogan_core::run(
        &sut,
        &settings.search,
        plan.budget,
        plan.seed,
        stop,
        &mut |event| {
            let record = match event {
                Event::Test {
                    id,
                    phase,
                    fitness,
                    predicted_fitness,
                    invalid_candidates,
                    ranked_candidates,
                    generation_ms,
                    sbst_generation_ms,
                    beyond_budget,
                    output,
                    ..
                } => {
                    let test = TestRecord {
                        id,
                        phase,
                        fitness,
                        predicted_fitness,
                        invalid_candidates,
                        ranked_candidates: Some(ranked_candidates),
                        generation_ms,
                        sbst_generation_ms: Some(sbst_generation_ms),
                        beyond_budget,
                        execution: output,
                    };
                    if test.failed() && !beyond_budget {
                        failing_profiles.push(heading_profile(&test.execution.interpolated));
                    }
                    progress.test_done(failing_profiles.len());
                    Record::Test(test)
                }
                Event::Train {
                    analyzer_loss,
                    critic_loss,
                    gradient_penalty,
                    generator_loss,
                    wasserstein_estimate,
                    train_ms,
                    tests,
                } => Record::Train(TrainRecord {
                    analyzer_loss,
                    critic_loss,
                    gradient_penalty: Some(gradient_penalty),
                    generator_loss,
                    wasserstein_estimate,
                    train_ms,
                    tests,
                }),
            };
            if let Err(error) = out.write(&record) {
                // Output is gone (a closed pipe, a full disk): stop searching, keep the first error.
                stop.store(true, Ordering::SeqCst);
                write_error.get_or_insert(error);
            }
        },
    );
    progress.finish();
    if let Some(error) = write_error {
        return Err(error);
    }
    let diversity = median_pairwise_distance(&failing_profiles, plan.seed);
    let (summary, error) = match outcome {
        Ok(summary) => (summary, None),
        Err(error) => (Summary::default(), Some(error.to_string())),
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
    }))?;
    match (error, summary.stopped_by_signal) {
        (Some(error), _) => {
            eprintln!("wogan: the search failed: {error}");
            Ok(Status::Failed)
        }
        (None, true) => Ok(Status::Interrupted),
        (None, false) => Ok(Status::AllRead),
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
