//! `--oracle onnx:FILE`: a camera network in ONNX drives wogan's car, run inside the binary by
//! tract, under a named contract ([`Contract`]: the competition's DAVE-2 executor's by default,
//! or the Udacity course's): the camera, crop, resize, colour space, steering and throttle rule,
//! each a setting.

mod contract;
mod driver;
mod model;
mod preprocessing;
mod throttle;

pub use contract::{CameraSetting, Contract, SteeringSide};
pub use driver::{OnnxConfig, OnnxDriver, OnnxParams};
pub use model::{
    InputShape, Layout, ModelState, OnnxError, OnnxModel, MAX_MODEL_BYTES, MAX_SIDE, MIN_SIDE,
};
pub use preprocessing::{rgb_to_yuv, ColourSpace, PixelScaling, Preprocessor};
pub use throttle::{CompetitionThrottle, ThrottleRule};
