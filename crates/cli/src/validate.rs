//! `wogan validate`: the competition's verdict for every road of the input.

use crate::json_lines::{numbered_lines, open_input, ErrorRecord, JsonLinesWriter};
use crate::Status;
use anyhow::Result;
use clap::Args;
use road_sim::input::{parse_line, RoadInput};
use road_sim::{Point, Validator};
use serde::Serialize;
use std::path::PathBuf;

/// Options of `wogan validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// JSON lines of roads: competition tests, `wogan run` test records, `{"curvature": [...]}`
    /// or `[[x, y], ...]`. Standard input when absent or `-`.
    pub file: Option<PathBuf>,
    /// Side of the square map, metres.
    #[arg(long, default_value_t = 200.0, value_parser = positive_metres, allow_negative_numbers = true)]
    pub map_size: f64,
    /// Add the interpolated centre line to each verdict.
    #[arg(long)]
    pub details: bool,
}

/// Parses a strictly positive, finite length in metres.
pub fn positive_metres(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!(
            "expected a positive number of metres, got {text:?}"
        )),
    }
}

#[derive(Debug, Serialize)]
struct VerdictRecord<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    line: usize,
    valid: bool,
    reason: Option<&'static str>,
    message: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    interpolated_points: Option<&'a [Point]>,
}

/// Runs `wogan validate`.
pub fn run(args: &ValidateArgs) -> Result<Status> {
    let input = open_input(args.file.as_deref())?;
    let mut out = JsonLinesWriter::create(None)?;
    let validator = Validator::new(args.map_size);
    let mut status = Status::AllRead;
    for line in numbered_lines(input) {
        let line = line?;
        let parsed = line
            .text
            .and_then(|text| parse_line(&text, args.map_size).map_err(|e| e.to_string()));
        let road = match parsed {
            Ok(RoadInput::Skip) => continue,
            Ok(road) => road,
            Err(error) => {
                status = Status::SomeLinesBad;
                out.write(&ErrorRecord::new(line.number, &error))?;
                continue;
            }
        };
        let verdict = validator.validate(road.points().unwrap_or_default());
        out.write(&VerdictRecord {
            kind: "verdict",
            line: line.number,
            valid: verdict.is_valid(),
            reason: verdict.reason.map(|r| r.code()),
            message: verdict.message(),
            interpolated_points: if args.details {
                verdict.road.as_ref().map(|r| r.interpolated.as_slice())
            } else {
                None
            },
        })?;
    }
    Ok(status)
}
