//! `--oracle onnx:FILE`: a camera network in ONNX drives wogan's car, run inside the binary by
//! tract, under the contract of the competition's DAVE-2 executor (its crop, resize, colour space
//! and throttle rule by default; each a setting).

mod driver;
mod model;
mod preprocessing;
mod throttle;

pub use driver::{OnnxConfig, OnnxDriver, OnnxParams};
pub use model::{
    InputShape, Layout, ModelState, OnnxError, OnnxModel, MAX_MODEL_BYTES, MAX_SIDE, MIN_SIDE,
};
pub use preprocessing::{rgb_to_yuv, ColourSpace, PixelScaling, Preprocessor};
pub use throttle::{CompetitionThrottle, ThrottleRule};

use super::dave2;
use super::preset::DriverPreset;

/// How a camera network is judged unless told otherwise: the competition's DAVE-2 experiment
/// (dave2-proxy's preset).
pub const PRESET: DriverPreset = dave2::PRESET;
