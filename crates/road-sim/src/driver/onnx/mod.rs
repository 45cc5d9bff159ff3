//! `--oracle onnx:FILE`: a camera network in ONNX drives wogan's car, run inside the binary by
//! tract, under the contract of the competition's DAVE-2 executor (its crop, resize, colour space
//! and throttle rule by default; each a setting).

mod driver;
mod model;
mod preprocessing;
mod throttle;

pub use driver::{OnnxConfig, OnnxDriver, OnnxParams, PRESET};
pub use model::{
    InputShape, Layout, ModelState, OnnxError, OnnxModel, MAX_MODEL_BYTES, MAX_SIDE, MIN_SIDE,
};
pub use preprocessing::{rgb_to_yuv, ColourSpace, PixelScaling, Preprocessor};
pub use throttle::{CompetitionThrottle, ThrottleRule};
