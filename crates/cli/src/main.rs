//! `wogan`: finds roads on which a self-driving car's lane keeper leaves its lane.
//!
//! The binary only wires things together: roads, validity and simulation come from `road-sim`,
//! search algorithms from `wogan-core`, driver training from `driver-training`. Its rooms:
//! - [`commands`]: one module per subcommand, its options and what it does with them;
//! - [`options`]: what was typed becomes settings (`run` resolves everything once into a
//!   [`RunPlan`](options::run_plan::RunPlan));
//! - [`files`]: what wogan writes and reads; every record is a type of [`files::records`];
//! - [`sut`]: what the search drives (wogan's simulator, or an executor);
//! - [`report`] and [`sbst`]: reports on runs, and the SBST competition's files and measures.
//!
//! Results go to stdout as JSON lines, one object per line, flushed as soon as known; progress
//! and logs go to stderr.

mod commands;
mod files;
mod interrupt;
mod jobs;
mod options;
mod report;
mod sbst;
mod sut;

use commands::{
    camera, dataset, export, replay, report as report_command, run, sample, simulate, suite,
    train_driver, validate, Status,
};

use clap::{Parser, Subcommand};
use commands::EXIT_USAGE;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "wogan",
    version,
    about = "Online test generation for lane-keeping systems (WOGAN)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Check roads against the SBST competition's validity rules.
    Validate(validate::ValidateArgs),
    /// Drive a lane-keeping driver along roads and report how far it left its lane.
    Simulate(simulate::SimulateArgs),
    /// Search for roads on which the driver leaves its lane (WOGAN or random search).
    Run(Box<options::run_plan::RunArgs>),
    /// Train the dave2-proxy driver by behaviour cloning from beamng-ai-proxy.
    TrainDriver(train_driver::TrainDriverArgs),
    /// Write what the dave2-proxy camera sees along a road, as PNG.
    Camera(camera::CameraArgs),
    /// Record frames and steering labels from a driver, in the Udacity simulator's layout.
    Dataset(dataset::DatasetArgs),
    /// Write a Markdown report with SVG pictures of runs, or a picture of one simulation trace.
    Report(report_command::ReportArgs),
    /// Write a run in the SBST competition's result layout.
    Export(export::ExportArgs),
    /// Drive saved roads (runs, suites, road files, exports) again and say what changed.
    Replay(replay::ReplayArgs),
    /// Keep failing roads as a regression suite (`add`), or list one (`list`).
    Suite(suite::SuiteArgs),
    /// Draw likely-failing roads from a generator saved by `wogan run --save-generator`.
    Sample(sample::SampleArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Validate(args) => validate::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Run(args) => run::run(&args),
        Command::TrainDriver(args) => train_driver::run(&args),
        Command::Camera(args) => camera::run(&args),
        Command::Dataset(args) => dataset::run(&args),
        Command::Report(args) => report_command::run(&args),
        Command::Export(args) => export::run(&args),
        Command::Replay(args) => replay::run(&args),
        Command::Suite(args) => suite::run(&args),
        Command::Sample(args) => sample::run(&args),
    };
    match outcome {
        Ok(status) => ExitCode::from(status.exit_code()),
        // The reader went away (`wogan run | head -1`): what it wanted was written.
        Err(error) if is_broken_pipe(&error) => ExitCode::from(Status::AllRead.exit_code()),
        Err(error) => {
            eprintln!("wogan: {error:#}");
            ExitCode::from(EXIT_USAGE)
        }
    }
}

/// Whether `error` comes from writing to a pipe whose reader has closed it.
fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
