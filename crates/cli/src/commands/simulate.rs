//! `wogan simulate`: drive the chosen driver along every road of the input, in wogan's simulator
//! or through an executor (`--executor`: a user's own simulator).

use super::road_stream::{answer_each_road, Answer};
use super::Status;
use crate::files::json_lines::{open_input, JsonLinesWriter};
use crate::files::records::{HelloRecord, InvalidOutcome, Record, ResultRecord, TraceRecord};
use crate::files::sbst_format::execution_data;
use crate::interrupt::stop_flag;
use crate::options::driver_options::{DriverOptions, DrivingConfig, RoadJobs};
use crate::options::executor_options::ExecutorOptions;
use crate::sut::executor_protocol;
use crate::sut::failure_streak::FailureStreak;
use anyhow::{Context, Result};
use clap::Args;
use road_sim::{simulate, Reason, Road, Sample, StopReason, Validator};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Options of `wogan simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// JSON lines of roads (the forms `wogan validate` reads). Standard input when absent or `-`.
    pub file: Option<PathBuf>,
    #[command(flatten)]
    pub driver: DriverOptions,
    #[command(flatten)]
    pub executor: ExecutorOptions,
    #[command(flatten)]
    pub driving: DrivingConfig,
    #[command(flatten)]
    pub jobs: RoadJobs,
    /// Write DIR/trace.N.jsonl for input line N: the road, then one sample per lane-monitor step
    /// (wogan's simulator only).
    #[arg(long, value_name = "DIR", conflicts_with = "executor")]
    pub trace: Option<PathBuf>,
    /// Put the drive's records in each answer as the SBST pipeline stores them
    /// (`execution_data`: arrays of its 17 `SimulationDataRecord` fields), so that a pipeline
    /// executor needs nothing else (wogan's simulator only).
    #[arg(long, conflicts_with = "executor")]
    pub execution_data: bool,
}

/// Runs `wogan simulate`.
pub fn run(args: &SimulateArgs) -> Result<Status> {
    let stop = stop_flag()?;
    let input = open_input(args.file.as_deref())?;
    if let Some(dir) = &args.trace {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create trace directory {}", dir.display()))?;
    }
    let mut out = JsonLinesWriter::create(None)?;
    let validator = Validator::new(args.driver.map_size);
    let (config, driver) = args
        .driver
        .resolve_for_driving(args.driving.config.as_deref(), "simulate")?;
    let max_steering_deg = config.vehicle.max_steering_rad.to_degrees();
    let sampled = args.trace.is_some() || args.execution_data;
    let streak = FailureStreak::new(args.executor.max_failed_drives as usize);
    let executor = match args
        .executor
        .start(args.driver.map_size, &config, &streak, &stop)
    {
        Ok(executor) => executor,
        Err(reason) => {
            eprintln!("wogan simulate: {reason}");
            return Ok(Status::Failed);
        }
    };
    // Serving as an executor (`wogan run --executor cmd:"wogan simulate"`), it says what it is.
    let oracle = match &args.executor.executor {
        Some(command) => format!("executor {command}"),
        None => args.driver.kind().name().to_owned(),
    };
    let hello_reply = Record::Hello(HelloRecord {
        protocol: executor_protocol::PROTOCOL.to_owned(),
        version: executor_protocol::VERSION,
        executor: serde_json::json!({
            "name": "wogan simulate",
            "version": env!("CARGO_PKG_VERSION"),
            "settings": {
                "oracle": oracle,
                "speed_limit_kmh": config.speed_limit_kmh,
                "oob_tolerance": config.oob_tolerance,
            },
        }),
    });
    let status = answer_each_road(
        input,
        &mut out,
        args.driver.map_size,
        args.jobs.jobs as usize,
        &stop,
        Some(hello_reply),
        |source, road| {
            let line = source.line;
            let verdict = validator.validate(road.points().unwrap_or_default());
            match (verdict.reason, verdict.road, &executor) {
                (None, Some(road), Some(executor)) => {
                    // The protocol's road id is the input line: unique among the roads in flight.
                    match executor.drive(line as u64, &road.road_points, &road) {
                        Some(result) => {
                            Answer::Record(Box::new(Record::Result(ResultRecord::Driven {
                                line,
                                id: source.id.clone(),
                                result,
                                execution_data: None,
                            })))
                        }
                        None => Answer::Dropped,
                    }
                }
                (None, Some(road), None) => {
                    let mut result = simulate(
                        &road,
                        driver.build().as_mut(),
                        &config,
                        sampled,
                        Some(&stop),
                    );
                    if result.reason == Some(StopReason::Interrupted) {
                        return Answer::Dropped;
                    }
                    let samples = result.trace.take().unwrap_or_default();
                    if let Some(dir) = &args.trace {
                        if let Err(error) = write_trace(dir, line, &road, &samples) {
                            eprintln!("wogan: line {line}: {error:#}");
                        }
                    }
                    let execution_data = args
                        .execution_data
                        .then(|| execution_data(&samples, config.oob_tolerance, max_steering_deg));
                    Answer::Record(Box::new(Record::Result(ResultRecord::Driven {
                        line,
                        id: source.id.clone(),
                        result,
                        execution_data,
                    })))
                }
                (reason, _, _) => {
                    let reason = reason.unwrap_or(Reason::Malformed);
                    Answer::Record(Box::new(Record::Result(ResultRecord::Invalid {
                        line,
                        id: source.id.clone(),
                        outcome: InvalidOutcome::Invalid,
                        reason,
                        message: reason.message().to_owned(),
                    })))
                }
            }
        },
    )?;
    // The executors end (and are reaped) before the command does.
    drop(executor);
    Ok(match streak.gave_up() {
        Some(reason) => {
            eprintln!("wogan simulate: stopped: {reason}");
            Status::Failed
        }
        None => status,
    })
}

/// Writes `DIR/trace.LINE.jsonl`.
fn write_trace(dir: &Path, line: usize, road: &Road, samples: &[Sample]) -> Result<()> {
    let path = dir.join(format!("trace.{line}.jsonl"));
    let file = std::fs::File::create(&path)
        .with_context(|| format!("cannot create {}", path.display()))?;
    let mut writer = std::io::BufWriter::new(file);
    let mut write = |record: &TraceRecord| -> Result<()> {
        serde_json::to_writer(&mut writer, record)?;
        writer.write_all(b"\n")?;
        Ok(())
    };
    write(&TraceRecord::Road {
        road_points: road.road_points.clone(),
        interpolated_points: road.interpolated.clone(),
    })?;
    for sample in samples {
        write(&TraceRecord::Sample(*sample))?;
    }
    writer
        .flush()
        .with_context(|| format!("cannot write {}", path.display()))
}
