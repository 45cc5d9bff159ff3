//! `dave2-proxy`: a driver that steers with DAVE-2 from the front camera and holds a set speed.
//!
//! At each control tick (10 Hz by default) it renders the camera ([`crate::vision::Camera`]) at the
//! car's pose, runs the network ([`crate::vision::Dave2Net`]) and steers its output (clamped to
//! `[-1, 1]`) times the car's maximum wheel angle; a proportional controller holds the speed at the
//! set speed (25 km/h by default, never above the simulation's speed limit).

use super::pedals::pedals;
use crate::road::Road;
use crate::setting_checks::{all_within, SettingsError};
use crate::sim::{Command, Driver, Observation, VehicleParams};
use crate::vision::{Camera, CameraParams, Dave2Net, Dave2Weights, Frame, RoadScene, WeightsError};
use serde::{Deserialize, Serialize};
use std::sync::{Arc, OnceLock};

/// The weights of `dave2-proxy` trained by `wogan train-driver` and built into the binary.
const EMBEDDED_WEIGHTS: &[u8] = include_bytes!("../../weights/dave2-proxy.bin");

/// The built-in `dave2-proxy` weights, decoded once.
pub fn embedded_weights() -> Arc<Dave2Weights> {
    static WEIGHTS: OnceLock<Arc<Dave2Weights>> = OnceLock::new();
    WEIGHTS
        .get_or_init(|| {
            // A test decodes the embedded blob, so this cannot fail in a released binary.
            Arc::new(
                Dave2Weights::from_bytes(EMBEDDED_WEIGHTS)
                    .expect("the embedded DAVE-2 weights decode"),
            )
        })
        .clone()
}

/// The driver's settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Dave2DriverParams {
    /// Control (camera and network) rate, hertz.
    pub control_hz: f64,
    /// Set speed, km/h (capped by the simulation's speed limit).
    pub speed_kmh: f64,
    /// Throttle per m/s of speed deficit.
    pub throttle_gain: f64,
    /// Brake per m/s of excess speed beyond the deadband.
    pub brake_gain: f64,
    /// Excess speed tolerated without braking, m/s.
    pub brake_deadband_mps: f64,
}

impl Default for Dave2DriverParams {
    fn default() -> Self {
        Self {
            control_hz: 10.0,
            speed_kmh: 25.0,
            throttle_gain: 0.5,
            brake_gain: 0.3,
            brake_deadband_mps: 0.5,
        }
    }
}

impl Dave2DriverParams {
    /// Names the first setting the driver cannot work with. The control rate is at most 100 Hz:
    /// each tick renders a frame and runs the network, the costly part of a drive.
    pub fn validate(&self) -> Result<(), SettingsError> {
        all_within(
            "driver.",
            &[
                ("control_hz", self.control_hz, 0.1, 100.0),
                ("speed_kmh", self.speed_kmh, 0.1, 300.0),
            ],
        )?;
        all_within(
            "driver.",
            &[
                ("throttle_gain", self.throttle_gain, 0.0, 100.0),
                ("brake_gain", self.brake_gain, 0.0, 100.0),
                ("brake_deadband_mps", self.brake_deadband_mps, 0.0, 100.0),
            ],
        )
    }
}

/// DAVE-2 driving from the camera.
#[derive(Debug, Clone)]
pub struct Dave2Driver {
    params: Dave2DriverParams,
    net: Dave2Net,
    camera: Camera,
    scene: Option<RoadScene>,
    frame: Frame,
    max_steering_rad: f64,
    target_mps: f64,
}

impl Dave2Driver {
    /// A driver with the network `weights`.
    pub fn new(weights: &Dave2Weights, params: Dave2DriverParams) -> Self {
        let camera = Camera::new(CameraParams::default());
        let p = camera.params();
        let frame = Frame::new(p.width, p.height, 1);
        Self {
            params,
            net: Dave2Net::new(weights),
            camera,
            scene: None,
            frame,
            max_steering_rad: VehicleParams::default().max_steering_rad,
            target_mps: params.speed_kmh / 3.6,
        }
    }

    /// A driver with weights from a blob ([`Dave2Weights::to_bytes`]).
    pub fn from_bytes(bytes: &[u8], params: Dave2DriverParams) -> Result<Self, WeightsError> {
        Ok(Self::new(&Dave2Weights::from_bytes(bytes)?, params))
    }

    /// The last frame the driver saw.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }
}

impl Driver for Dave2Driver {
    fn name(&self) -> &'static str {
        "dave2-proxy"
    }

    fn control_hz(&self) -> f64 {
        self.params.control_hz
    }

    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64) {
        self.scene = Some(RoadScene::new(road));
        self.max_steering_rad = vehicle.max_steering_rad;
        self.target_mps = (self.params.speed_kmh / 3.6).min(speed_limit_mps);
    }

    fn act(&mut self, observation: &Observation<'_>) -> Command {
        let car = observation.car;
        let scene = self
            .scene
            .get_or_insert_with(|| RoadScene::new(observation.road));
        self.camera
            .render_into(scene, car.position, car.heading_rad, &mut self.frame);
        // A non-finite output stays non-finite, so the episode ends in ERROR: the network is
        // broken, and steering straight instead would pass a broken driver off as a working one.
        let raw = f64::from(self.net.predict(&self.frame.data));
        let steer = if raw.is_finite() {
            raw.clamp(-1.0, 1.0)
        } else {
            f64::NAN
        };
        let p = &self.params;
        let (throttle, brake) = pedals(
            self.target_mps - car.speed_mps,
            p.throttle_gain,
            p.brake_gain,
            p.brake_deadband_mps,
        );
        Command {
            steering_rad: steer * self.max_steering_rad,
            throttle,
            brake,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::CompetitionSetup;
    use crate::sim::{simulate, Outcome, SimConfig, StopReason};

    #[test]
    fn the_embedded_weights_decode() {
        assert_eq!(
            Dave2Weights::from_bytes(EMBEDDED_WEIGHTS).map(|w| w.to_bytes().len()),
            Ok(EMBEDDED_WEIGHTS.len())
        );
    }

    #[test]
    fn a_network_that_answers_with_a_non_finite_number_ends_the_drive_in_error() {
        // The largest weights a blob may hold overflow f32 within the nine layers.
        let mut weights = Dave2Weights::from_seed(1);
        for layer in weights
            .convs
            .iter_mut()
            .map(|c| (&mut c.weight, &mut c.bias))
        {
            layer.0.fill(1e4);
            layer.1.fill(1e4);
        }
        for layer in weights
            .denses
            .iter_mut()
            .map(|d| (&mut d.weight, &mut d.bias))
        {
            layer.0.fill(1e4);
            layer.1.fill(1e4);
        }
        let weights = Dave2Weights::from_bytes(&weights.to_bytes()).expect("within the bounds");
        let road = Road::new(&[[100.0, 10.0], [100.0, 60.0], [100.0, 110.0]]).unwrap();
        let mut driver = Dave2Driver::new(&weights, Dave2DriverParams::default());
        let r = simulate(&road, &mut driver, &SimConfig::default(), false, None);
        assert_eq!(
            (r.outcome, r.reason),
            (Outcome::Error, Some(StopReason::NonFiniteCommand))
        );
    }

    #[test]
    fn is_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<Dave2Driver>();
    }

    #[test]
    fn drives_deterministically_and_holds_speed() {
        let pts: Vec<[f64; 2]> = (0..=6).map(|i| [100.0, 10.0 + 12.0 * i as f64]).collect();
        let road = Road::new(&pts).unwrap();
        let weights = Dave2Weights::from_seed(11);
        let config = SimConfig::default();
        let run = || {
            let mut d =
                Dave2Driver::from_bytes(&weights.to_bytes(), Dave2DriverParams::default()).unwrap();
            simulate(&road, &mut d, &config, true, None)
        };
        let (a, b) = (run(), run());
        let (ta, tb) = (a.trace.unwrap(), b.trace.unwrap());
        assert_eq!(
            serde_json::to_string(&ta).unwrap(),
            serde_json::to_string(&tb).unwrap()
        );
        let max_kmh = ta.iter().map(|s| s.speed_kmh).fold(0.0, f64::max);
        assert!(max_kmh > 10.0 && max_kmh < 28.0, "max speed {max_kmh} km/h");
    }

    /// The built-in student on the SBST 2022 entries' sharpest long roads (the first 30 of
    /// AmbieGen's in `tests/reference/peer_roads_dev.jsonl`), in its competition setup: the
    /// competition's DAVE-2 failed about 5% of such roads; `scripts/runs/driver_rates.sh dave2-proxy`
    /// measures all.
    #[test]
    fn the_built_in_student_keeps_its_lane_on_long_sharp_roads() {
        let config = CompetitionSetup::Dave2.sim_config();
        let failed = crate::driver::reference_roads("peer_roads_dev.jsonl")
            .into_iter()
            .filter(|(generator, _)| generator == "ambiegen")
            .take(30)
            .filter(|(_, points)| {
                let road = Road::new(points).unwrap();
                let mut driver =
                    Dave2Driver::new(&embedded_weights(), Dave2DriverParams::default());
                let r = simulate(&road, &mut driver, &config, false, None);
                assert_ne!(r.outcome, Outcome::Error);
                r.outcome == Outcome::Fail
            })
            .count();
        assert!(failed <= 3, "{failed} of 30 AmbieGen roads failed");
    }

    #[test]
    #[ignore = "timing; run with --ignored --nocapture"]
    fn time_per_road() {
        // About 75 m of gently curving road.
        let pts: Vec<[f64; 2]> = (0..=5)
            .map(|i| {
                let t = i as f64 * 15.0;
                [100.0 + 8.0 * (t / 25.0).sin(), 10.0 + t]
            })
            .collect();
        let road = Road::new(&pts).unwrap();
        let mut d = Dave2Driver::new(&Dave2Weights::from_seed(11), Dave2DriverParams::default());
        let started = std::time::Instant::now();
        let r = simulate(&road, &mut d, &SimConfig::default(), false, None);
        eprintln!(
            "dave2-proxy: {:.1} m road, {:?} after {:.1} simulated s, {:.0} ms wall ({} control steps)",
            road.length_m(),
            r.outcome,
            r.sim_time_s,
            started.elapsed().as_secs_f64() * 1e3,
            (r.sim_time_s * d.control_hz()).round()
        );
    }
}
