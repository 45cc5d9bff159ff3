//! A camera network's contract: the camera its frames come from, how a frame becomes the model's
//! input, and what its answer means. A network trained elsewhere drives only under the contract
//! it was trained with; each contract is taken from the code of the system that defines it, and
//! every part of it stays a setting (`{"driver": {"contract": "udacity", "crop_top_rows": 50}}`).
//!
//! - [`Contract::Sbst2022`] (the default): the SBST 2022 competition's DAVE-2 executor
//!   (se2p/tool-competition-av, `self_driving/image_processing.py` and
//!   `nvidia_prediction.py`): crop 80 rows off the top and 1 off the bottom, resize back to the
//!   model's size, RGB to YUV, raw bytes; throttle `1 − s² − (v / limit)²` with the run's speed
//!   limit, 10 km/h once above it. The camera renders at the model's size (the competition's
//!   320 x 160 for its 160 x 320 model) from wogan's mounting ([`CameraParams::default`]), and the
//!   steering is wogan's (positive left, times the car's limit): the figures of networks trained
//!   in wogan's world are those they always had. The competition's BeamNG camera
//!   (`self_driving/beamng_car_cameras.py`: 120° field of view, 1.7 m ahead, 1.0 m high, level)
//!   is not wogan's, which shows a flat world without BeamNG's scenery.
//! - [`Contract::Udacity`]: the Udacity self-driving-car course's behavioural cloning (its
//!   simulator's centre camera and the course's `drive.py` / `utils.py`): a 320 x 160 camera,
//!   crop 60 rows off the top and 25 off the bottom, resize to the model's 200 x 66, RGB to YUV,
//!   raw bytes (the model normalises inside); steering in `[−1, 1]` positive right, ±25°;
//!   throttle `1 − s² − (v / limit)²` with the course's limits, 25 mph and 10 mph once above it
//!   (its simulator reports mph; the rule's ratio is the same in km/h).

use crate::vision::CameraParams;
use serde::{Deserialize, Serialize};

/// A named contract: the defaults a config file's `driver` section starts from
/// ([`super::OnnxParams::of`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Contract {
    /// The SBST 2022 competition's DAVE-2 executor, with wogan's camera and steering.
    #[default]
    Sbst2022,
    /// The Udacity self-driving-car course's behavioural cloning.
    Udacity,
}

impl Contract {
    /// Every contract, for messages.
    pub const ALL: [Contract; 2] = [Contract::Sbst2022, Contract::Udacity];

    /// The contract's name as a config file gives it.
    pub fn name(self) -> &'static str {
        match self {
            Contract::Sbst2022 => "sbst2022",
            Contract::Udacity => "udacity",
        }
    }
}

/// Which way a positive steering answer turns the car.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SteeringSide {
    /// Positive turns left (wogan's convention).
    #[default]
    Left,
    /// Positive turns right (the Udacity simulator's).
    Right,
}

/// The camera a contract's frames come from: its render size (`None`: the model's input size)
/// and mounting.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSetting {
    /// Rendered width, pixels (`None`: the model's input width).
    pub width: Option<usize>,
    /// Rendered height, pixels (`None`: the model's input height).
    pub height: Option<usize>,
    /// Horizontal field of view, degrees.
    pub hfov_deg: f64,
    /// Pitch below the horizontal, degrees.
    pub pitch_down_deg: f64,
    /// Height above the ground, metres.
    pub height_m: f64,
    /// Forward distance from the car's centre, metres.
    pub forward_m: f64,
}

impl Default for CameraSetting {
    fn default() -> Self {
        let wogan = CameraParams::default();
        Self {
            width: None,
            height: None,
            hfov_deg: wogan.hfov_deg,
            pitch_down_deg: wogan.pitch_down_deg,
            height_m: wogan.height_m,
            forward_m: wogan.forward_m,
        }
    }
}

impl CameraSetting {
    /// The Udacity simulator's camera in autonomous mode (udacity/self-driving-car-sim: the
    /// "Front Facing Camera" of `Assets/1_SelfDrivingCar/Prefabs/Car.prefab`, rendering to the
    /// 320 x 160 "Autonomous Camera Texture" that `drive.py` receives, placed by both autonomous
    /// scenes, `LakeTrackAutonomous.unity` and `JungleTrackAutonomous.unity`, where the training
    /// scenes' centre camera is): Unity's 60° vertical field of view, so about 98° across;
    /// pitched 9.5° down (its yaw of 0.7° and roll of 1.2° are left out); 1.2 m above and 1 m
    /// ahead of the car's origin, which sits about 0.06 m above the ground (the wheels' hubs,
    /// radii and suspension at rest) and 0.165 m ahead of the midpoint of the axles (wogan's car
    /// centre).
    pub fn udacity() -> Self {
        let (width, height) = (320, 160);
        let vfov_deg: f64 = 60.0;
        let aspect = width as f64 / height as f64;
        Self {
            width: Some(width),
            height: Some(height),
            hfov_deg: 2.0
                * ((vfov_deg.to_radians() / 2.0).tan() * aspect)
                    .atan()
                    .to_degrees(),
            pitch_down_deg: 9.5,
            height_m: 1.26,
            forward_m: 1.165,
        }
    }

    /// The camera for a model taking `width` x `height` frames.
    pub fn camera(&self, width: usize, height: usize) -> CameraParams {
        CameraParams {
            width: self.width.unwrap_or(width),
            height: self.height.unwrap_or(height),
            hfov_deg: self.hfov_deg,
            pitch_down_deg: self.pitch_down_deg,
            height_m: self.height_m,
            forward_m: self.forward_m,
            ..CameraParams::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_udacity_camera_is_the_simulators() {
        let c = CameraSetting::udacity().camera(200, 66);
        assert_eq!(
            (c.width, c.height),
            (320, 160),
            "the course's frames, not the model's size"
        );
        assert!((c.hfov_deg - 98.21).abs() < 0.01, "{}", c.hfov_deg);
        let wogan = CameraSetting::default().camera(320, 160);
        assert_eq!(
            wogan,
            CameraParams {
                width: 320,
                height: 160,
                ..CameraParams::default()
            }
        );
        for contract in Contract::ALL {
            let text = serde_json::to_string(&contract).unwrap();
            assert_eq!(text, format!("\"{}\"", contract.name()));
        }
    }
}
