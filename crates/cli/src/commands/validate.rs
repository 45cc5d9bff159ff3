//! `wogan validate`: the competition's verdict for every road of the input.

use super::road_stream::{answer_each_road, Answer};
use super::Status;
use crate::files::json_lines::{open_input, JsonLinesWriter};
use crate::files::records::{Record, VerdictRecord};
use crate::interrupt::stop_flag;
use crate::options::value_parsers::map_size_m;
use anyhow::Result;
use clap::Args;
use road_sim::Validator;
use std::path::PathBuf;

/// Options of `wogan validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// JSON lines of roads: competition tests, `wogan run` test records, `{"curvature": [...]}`
    /// or `[[x, y], ...]`. Standard input when absent or `-`.
    pub file: Option<PathBuf>,
    /// Side of the square map, metres.
    #[arg(long, default_value_t = 200.0, value_parser = map_size_m, allow_negative_numbers = true)]
    pub map_size: f64,
    /// Add the interpolated centre line to each verdict.
    #[arg(long)]
    pub details: bool,
}

/// Runs `wogan validate`.
pub fn run(args: &ValidateArgs) -> Result<Status> {
    let stop = stop_flag()?;
    let input = open_input(args.file.as_deref())?;
    let mut out = JsonLinesWriter::create(None)?;
    let validator = Validator::new(args.map_size);
    answer_each_road(
        input,
        &mut out,
        args.map_size,
        1,
        &stop,
        None,
        |source, road| {
            let verdict = validator.validate(road.points().unwrap_or_default());
            Answer::Record(Box::new(Record::Verdict(VerdictRecord {
                line: source.line,
                id: source.id.clone(),
                valid: verdict.is_valid(),
                reason: verdict.reason,
                message: verdict.message().to_owned(),
                interpolated_points: if args.details {
                    verdict.road.map(|r| r.interpolated)
                } else {
                    None
                },
            })))
        },
    )
}
