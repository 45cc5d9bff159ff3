//! `wogan replay`: the regression suite's command. It drives saved roads again (from runs, suites,
//! road files and the competition's exports) against the driver given now, or through an
//! executor (`--executor`: a user's own simulator), and writes, per road,
//! its outcome now beside the one recorded, in input order as each is known; optionally a JUnit
//! report. The exit status is the CI verdict: 1 when a road fails now (`--fail-on any`) or when
//! an outcome changed (`--fail-on changed`), 2 when some input could not be used (the good roads
//! are still driven), 130 after Ctrl-C with what was driven written.

use super::Status;
use crate::files::json_lines::JsonLinesWriter;
use crate::files::junit::{self, JunitCase};
use crate::files::output_file::same_file;
use crate::files::records::{Record, ReplayRecord};
use crate::files::saved_roads::{read_saved_roads, SavedRoad};
use crate::interrupt::stop_flag;
use crate::jobs::{Jobs, Next};
use crate::options::driver_options::{DriverOptions, DrivingConfig, RoadJobs};
use crate::options::executor_options::ExecutorOptions;
use crate::sut::failure_streak::FailureStreak;
use crate::sut::ExecutorDriver;
use anyhow::{bail, Result};
use clap::Args;
use road_sim::{simulate, DriverConfig, SimConfig, SimResult, StopReason, Validator};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

/// Options of `wogan replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// Files of saved roads: `wogan run` files, suites (`wogan suite`), road files in the forms
    /// `validate` reads, the competition's test.NNNN.json, or a folder of those.
    #[arg(value_name = "FILE", required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub driver: DriverOptions,
    #[command(flatten)]
    pub executor: ExecutorOptions,
    #[command(flatten)]
    pub driving: DrivingConfig,
    #[command(flatten)]
    pub jobs: RoadJobs,
    /// Also write a JUnit XML report to FILE: one test case per road.
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// What makes the exit status 1: a road that fails now (any), or a road whose outcome now
    /// differs from the recorded one, fixed or newly failing (changed).
    #[arg(long, value_enum, default_value_t = ReplayFailOn::Any)]
    pub fail_on: ReplayFailOn,
}

/// `--fail-on` values of `wogan replay`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ReplayFailOn {
    /// Exit 1 when any road fails (or errs) now.
    Any,
    /// Exit 1 when any road's outcome differs from the one recorded.
    Changed,
}

/// How one saved road drives now.
struct Replayed {
    record: ReplayRecord,
    result: Option<SimResult>,
}

/// Runs `wogan replay`.
pub fn run(args: &ReplayArgs) -> Result<Status> {
    if let Some(junit) = &args.junit {
        if let Some(input) = args.files.iter().find(|f| same_file(junit, f)) {
            bail!(
                "--junit {} is an input of the replay ({}); write it elsewhere",
                junit.display(),
                input.display()
            );
        }
    }
    let stop = stop_flag()?;
    let (sim, driver) = args
        .driver
        .resolve_for_driving(args.driving.config.as_deref(), "replay")?;
    let streak = FailureStreak::new(args.executor.max_failed_drives as usize);
    let executor = match args
        .executor
        .start(args.driver.map_size, &sim, &streak, &stop)
    {
        Ok(executor) => executor,
        Err(reason) => {
            eprintln!("wogan replay: {reason}");
            return Ok(Status::Failed);
        }
    };
    let driving = match &executor {
        Some(executor) => Driving::Executor(executor),
        None => Driving::Simulator {
            driver: &driver,
            sim: &sim,
        },
    };
    if let DriverConfig::Onnx(network) = &driver {
        for warning in changed_models(&args.files, network.model().sha256()) {
            eprintln!("wogan replay: {warning}");
        }
    }
    let (roads, mut problems) = read_saved_roads(&args.files, args.driver.map_size);
    for problem in &problems {
        eprintln!("wogan replay: {problem}");
    }
    let validator = Validator::new(args.driver.map_size);
    let jobs = Jobs::new(args.jobs.jobs as usize)?;
    let mut out = JsonLinesWriter::create(None)?;
    let mut replayed: Vec<(&SavedRoad, Replayed)> = Vec::with_capacity(roads.len());
    // Items are indices into `roads`.
    let mut indices = 0..roads.len();
    let next = |asked: usize| -> Result<Next<usize>> {
        let batch: Vec<usize> = indices.by_ref().take(asked).collect();
        Ok(if batch.is_empty() {
            Next::End
        } else {
            Next::Items(batch)
        })
    };
    let drive = |&index: &usize| replay_one(index, &roads[index], &validator, &driving, &stop);
    let write = |&index: &usize, answer: Option<Replayed>| -> Result<()> {
        let road = &roads[index];
        // Cut short by Ctrl-C: not reported, as the drive did not end.
        let Some(answer) = answer else { return Ok(()) };
        out.write(&Record::Replay(answer.record.clone()))?;
        if answer.record.outcome == "INVALID" {
            let problem = format!(
                "{}:{}: {}: {}",
                road.file.display(),
                road.line,
                road.name,
                answer.record.reason.as_deref().unwrap_or("invalid")
            );
            eprintln!("wogan replay: {problem}");
            problems.push(problem);
        }
        replayed.push((road, answer));
        Ok(())
    };
    jobs.answer_in_order(&stop, next, drive, write)?;
    let gave_up = streak.gave_up();
    let interrupted = stop.load(Ordering::SeqCst) && gave_up.is_none();
    let described = executor.as_ref().and_then(ExecutorDriver::description);
    // The executors end (and are reaped) before the report is written.
    drop(executor);
    if let Some(path) = &args.junit {
        let driver = match (&args.executor.executor, described) {
            (Some(_), Some((description, _))) => {
                description.name.unwrap_or_else(|| "executor".to_owned())
            }
            (Some(_), None) => "executor".to_owned(),
            (None, _) => args.driver.kind().name().to_owned(),
        };
        write_junit(path, &driver, &replayed)?;
    }
    let failing = replayed
        .iter()
        .filter(|(_, r)| matches!(r.record.outcome.as_str(), "FAIL" | "ERROR"))
        .count();
    let changed = replayed.iter().filter(|(_, r)| r.record.changed).count();
    eprintln!(
        "wogan replay: {} road(s) driven, {failing} failing now, {changed} changed from the \
         recorded outcome{}",
        replayed.len(),
        if problems.is_empty() {
            String::new()
        } else {
            format!(", {} input problem(s)", problems.len())
        }
    );
    let verdict = match args.fail_on {
        ReplayFailOn::Any => failing > 0,
        ReplayFailOn::Changed => changed > 0,
    };
    if let Some(reason) = &gave_up {
        eprintln!("wogan replay: stopped: {reason}");
    }
    Ok(if interrupted {
        Status::Interrupted
    } else if gave_up.is_some() {
        Status::Failed
    } else if !problems.is_empty() {
        Status::BadInput
    } else if verdict {
        Status::FailuresFound
    } else {
        Status::AllRead
    })
}

/// What drives the roads now.
enum Driving<'a> {
    /// A driver in wogan's simulator.
    Simulator {
        driver: &'a DriverConfig,
        sim: &'a SimConfig,
    },
    /// An executor.
    Executor(&'a ExecutorDriver<'a>),
}

/// Drives saved road number `index` (from 0, in input order); `None` when Ctrl-C cut the drive
/// short (or the executor gave up before it).
fn replay_one(
    index: usize,
    road: &SavedRoad,
    validator: &Validator,
    driving: &Driving<'_>,
    stop: &AtomicBool,
) -> Option<Replayed> {
    let verdict = validator.validate(&road.road_points);
    let (outcome, max_bolp, reason, oob, result) = match (verdict.reason, &verdict.road) {
        (None, Some(valid)) => {
            let result = match driving {
                Driving::Simulator { driver, sim } => {
                    simulate(valid, driver.build().as_mut(), sim, false, Some(stop))
                }
                // The protocol's road id is the road's place in the input, from 1.
                Driving::Executor(executor) => {
                    executor.drive(index as u64 + 1, &road.road_points, valid)?
                }
            };
            if result.reason == Some(StopReason::Interrupted) {
                return None;
            }
            // An ERROR's reason is its error (an executor's, or a controller's).
            let reason = result
                .reason
                .map(|r| r.name().to_owned())
                .or_else(|| result.error.clone());
            (
                result.outcome.name().to_owned(),
                result.max_bolp,
                reason,
                result.oob,
                Some(result),
            )
        }
        (reason, _) => (
            "INVALID".to_owned(),
            f64::NAN,
            Some(format!(
                "no longer a valid road: {}",
                reason.map_or("malformed", |r| r.message())
            )),
            None,
            None,
        ),
    };
    let changed = road
        .recorded_outcome
        .as_ref()
        .is_some_and(|recorded| *recorded != outcome);
    Some(Replayed {
        record: ReplayRecord {
            file: road.file.display().to_string(),
            line: road.line,
            name: road.name.clone(),
            outcome,
            recorded_outcome: road.recorded_outcome.clone(),
            changed,
            max_bolp,
            recorded_max_bolp: road.recorded_max_bolp,
            reason,
            oob,
        },
        result,
    })
}

/// Writes the replay's JUnit report: one case per road, the recorded outcome in its message.
fn write_junit(
    path: &std::path::Path,
    driver: &str,
    replayed: &[(&SavedRoad, Replayed)],
) -> Result<()> {
    let cases: Vec<JunitCase> = replayed
        .iter()
        .map(|(road, answer)| JunitCase {
            name: road.name.clone(),
            source: road.file.display().to_string(),
            road_points: &road.road_points,
            result: answer.result.as_ref(),
            skip_reason: answer.result.is_none().then(|| {
                answer
                    .record
                    .reason
                    .clone()
                    .unwrap_or_else(|| "not driven".to_owned())
            }),
            note: road.recorded_outcome.as_ref().map(|recorded| {
                let bolp = road
                    .recorded_max_bolp
                    .map_or_else(String::new, |b| format!(", max BOLP {b:.3}"));
                let change = if answer.record.changed {
                    "changed; "
                } else {
                    ""
                };
                format!("{change}recorded {recorded}{bolp}")
            }),
        })
        .collect();
    let properties = [
        ("driver", driver.to_owned()),
        ("wogan", crate::files::records::VERSION.to_owned()),
    ];
    junit::write_report(path, "wogan replay", &properties, &cases)
}

/// For each run file among `files` whose header records a camera network of another checksum
/// than `sha256` (the model given now), a warning naming both: the roads are then not driven by
/// the network the run tested. Files that cannot be read are reported when their roads are read.
fn changed_models(files: &[std::path::PathBuf], sha256: &str) -> Vec<String> {
    use std::io::{BufRead, Read};
    let mut warnings = Vec::new();
    for file in files {
        let Ok(opened) = std::fs::File::open(file) else {
            continue;
        };
        let mut first = String::new();
        // A header is one line; a longer first line is no run file's header.
        let mut reader = std::io::BufReader::new(opened).take(1 << 20);
        if reader.read_line(&mut first).is_err() {
            continue;
        }
        let Ok(header) = serde_json::from_str::<serde_json::Value>(&first) else {
            continue;
        };
        if header.get("type").and_then(|t| t.as_str()) != Some("header") {
            continue;
        }
        let driver = &header["config"]["driver"];
        if let (Some(recorded), Some(model)) = (
            driver.get("model_sha256").and_then(|s| s.as_str()),
            driver.get("model").and_then(|s| s.as_str()),
        ) {
            if recorded != sha256 {
                warnings.push(format!(
                    "{}: the run's model ({model}) had SHA-256 {recorded}; the model given now \
                     has {sha256}: the roads are driven by another network than the run's",
                    file.display()
                ));
            }
        }
    }
    warnings
}
