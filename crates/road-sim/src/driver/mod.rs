//! The drivers under test: `beamng-ai-proxy` (a geometric lane keeper) and `dave2-proxy` (DAVE-2
//! steering from the camera), each with its preset and tuning.
//!
//! The interface a driver fills, [`Driver`], belongs to the episode that calls it
//! ([`crate::sim`]); it is re-exported here so that a new driver finds everything in one place.

pub mod beamng_ai;
mod config;
pub mod dave2;

pub use crate::sim::{Driver, Observation};
pub use beamng_ai::{BeamNgAiParams, BeamNgAiProxy};
pub use config::{DriverConfig, DriverKind, DriverPreset, UnknownDriver};
pub use dave2::{Dave2Driver, Dave2DriverParams};

/// Throttle and brake, each in `[0, 1]`, of a proportional speed controller: throttle for a
/// speed deficit (`speed_error_mps > 0`), brake only for an excess beyond the deadband.
pub fn pedals(
    speed_error_mps: f64,
    throttle_gain: f64,
    brake_gain: f64,
    brake_deadband_mps: f64,
) -> (f64, f64) {
    if speed_error_mps >= 0.0 {
        ((throttle_gain * speed_error_mps).min(1.0), 0.0)
    } else if -speed_error_mps > brake_deadband_mps {
        (
            0.0,
            (brake_gain * (-speed_error_mps - brake_deadband_mps)).min(1.0),
        )
    } else {
        (0.0, 0.0)
    }
}

/// The roads of `tests/reference/FILE` (JSON lines with `road_points`) with each line's
/// `generator` (empty when it has none), for the drivers' calibration tests.
#[cfg(test)]
pub(crate) fn reference_roads(file: &str) -> Vec<(String, Vec<crate::road::Point>)> {
    #[derive(serde::Deserialize)]
    struct Line {
        #[serde(default)]
        generator: String,
        road_points: Vec<crate::road::Point>,
    }
    let path = format!(
        "{}/../../tests/reference/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).expect("a reference file");
    text.lines()
        .map(|line| {
            let line: Line = serde_json::from_str(line).expect("a road line");
            (line.generator, line.road_points)
        })
        .collect()
}
