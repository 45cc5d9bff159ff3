//! The drivers under test: `beamng-ai-proxy` (a geometric lane keeper), `dave2-proxy` (DAVE-2
//! steering from the camera), a camera network in ONNX (`--oracle onnx:FILE`) and a controller
//! process (`--oracle cmd:...`), each with its tuning; [`CompetitionSetup`] is the competition's
//! setting each is judged by.
//!
//! The interface a driver fills, [`Driver`], belongs to the episode that calls it
//! ([`crate::sim`]); it is re-exported here so that a new driver finds everything in one place.

pub mod beamng_ai;
mod competition_setup;
mod config;
pub mod controller;
pub mod dave2;
pub mod onnx;
mod pedals;

pub use crate::sim::{Driver, Observation};
pub use beamng_ai::{BeamNgAiParams, BeamNgAiProxy};
pub use competition_setup::CompetitionSetup;
pub use config::{DriverConfig, DriverKind, UnknownDriver};
pub use controller::{ControllerConfig, ControllerParams};
pub use dave2::{Dave2Driver, Dave2DriverParams};
pub use onnx::{Contract, OnnxConfig, OnnxError, OnnxParams, SteeringSide};
pub use pedals::pedals;

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
