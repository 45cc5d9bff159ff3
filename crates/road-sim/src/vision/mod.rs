//! What `dave2-proxy` sees and how it thinks: the road scene (the flat world's surfaces), the
//! front camera rendering it at DAVE-2's input size, the frame, and DAVE-2's weights with a fast
//! inference for driving.

mod camera;
mod dave2_net;
mod dave2_weights;
mod frame;
mod scene;

pub use camera::{Camera, CameraParams, FRAME_HEIGHT, FRAME_WIDTH};
pub use dave2_net::Dave2Net;
pub use dave2_weights::{
    ConvWeights, Dave2Weights, DenseWeights, WeightsError, CONVS, DENSES, FRAME_PIXELS,
};
pub use frame::{write_png, Frame};
pub use scene::{RoadScene, Surface, EDGE_LINE_INSET_M, GRAY, LINE_WIDTH_M, RGB};
