//! What `dave2-proxy` sees and how it thinks: the front camera rendering the flat world at
//! DAVE-2's input size, the frame, and DAVE-2's weights with a fast inference for driving.

mod camera;
mod dave2_net;
mod dave2_weights;
mod frame;

pub use camera::{
    Camera, CameraParams, RoadScene, Surface, EDGE_LINE_INSET_M, FRAME_HEIGHT, FRAME_WIDTH, GRAY,
    LINE_WIDTH_M, RGB,
};
pub use dave2_net::Dave2Net;
pub use dave2_weights::{
    ConvWeights, Dave2Weights, DenseWeights, WeightsError, CONVS, DENSES, FRAME_PIXELS,
};
pub use frame::{write_png, Frame};
