//! `wogan simulate`: drive the chosen driver along every road of the input.

use super::road_stream::{answer_each_road, Answer};
use super::Status;
use crate::files::json_lines::{open_input, JsonLinesWriter};
use crate::files::records::{HelloRecord, InvalidOutcome, Record, ResultRecord, TraceRecord};
use crate::files::sbst_format::execution_data;
use crate::interrupt::stop_flag;
use crate::options::driver_options::DriverOptions;
use crate::sut::executor_protocol;
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
    /// JSON file overriding the simulation's and the driver's defaults: `{"sim": {...},
    /// "driver": {...}}`, as `wogan run --config` reads them (a `search` section is refused).
    /// Options given on the command line win over the file.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Roads simulated at once (output keeps the input order).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256), allow_negative_numbers = true)]
    pub jobs: u32,
    /// Write DIR/trace.N.jsonl for input line N: the road, then one sample per lane-monitor step.
    #[arg(long, value_name = "DIR")]
    pub trace: Option<PathBuf>,
    /// Put the drive's records in each answer as the SBST pipeline stores them
    /// (`execution_data`: arrays of its 17 `SimulationDataRecord` fields), so that a pipeline
    /// executor needs nothing else.
    #[arg(long)]
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
        .resolve_for_driving(args.config.as_deref(), "simulate")?;
    let max_steering_deg = config.vehicle.max_steering_rad.to_degrees();
    let sampled = args.trace.is_some() || args.execution_data;
    // Serving as an executor (`wogan run --executor cmd:"wogan simulate"`), it says what it is.
    let hello_reply = Record::Hello(HelloRecord {
        protocol: executor_protocol::PROTOCOL.to_owned(),
        version: executor_protocol::VERSION,
        executor: serde_json::json!({
            "name": "wogan simulate",
            "version": env!("CARGO_PKG_VERSION"),
            "settings": {
                "oracle": args.driver.kind().name(),
                "speed_limit_kmh": config.speed_limit_kmh,
                "oob_tolerance": config.oob_tolerance,
            },
        }),
    });
    answer_each_road(
        input,
        &mut out,
        args.driver.map_size,
        args.jobs as usize,
        &stop,
        Some(hello_reply),
        |source, road| {
            let line = source.line;
            let verdict = validator.validate(road.points().unwrap_or_default());
            match (verdict.reason, verdict.road) {
                (None, Some(road)) => {
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
                (reason, _) => {
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
    )
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
