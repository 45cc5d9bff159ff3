//! `wogan`: finds roads on which a self-driving car's lane keeper leaves its lane.
//!
//! The binary only wires things together: roads, validity and simulation come from `road-sim`,
//! search algorithms from `wogan-core`. Results go to stdout as JSON lines, one object per line,
//! flushed as soon as known; progress and logs go to stderr.

mod json_lines;
mod validate;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Exit status when every input line was answered.
const EXIT_OK: u8 = 0;
/// Exit status when some input lines could not be read as roads (the others were answered).
const EXIT_BAD_LINES: u8 = 1;
/// Exit status for bad usage (options, unreadable input file).
const EXIT_USAGE: u8 = 2;

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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Validate(args) => validate::run(&args),
    };
    match outcome {
        Ok(Status::AllRead) => ExitCode::from(EXIT_OK),
        Ok(Status::SomeLinesBad) => ExitCode::from(EXIT_BAD_LINES),
        Err(error) => {
            eprintln!("wogan: {error:#}");
            ExitCode::from(EXIT_USAGE)
        }
    }
}

/// How a command ended when it did not fail outright.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Every input line was read and answered.
    AllRead,
    /// Some input lines were not roads; they were reported as `error` records.
    SomeLinesBad,
}
