//! The driver of `--oracle onnx:FILE`: at each control tick (dave2-proxy's rate) it renders the
//! front camera (dave2-proxy's camera, at the model's size and channels), prepares the frame
//! ([`super::preprocessing`]), runs the network and steers its first answer (clamped to
//! `[-1, 1]`) times the car's maximum wheel angle, as dave2-proxy does; the throttle follows
//! [`ThrottleRule`].

use super::contract::{CameraSetting, Contract, SteeringSide};
use super::model::{Layout, ModelState, OnnxError, OnnxModel, MAX_SIDE, MIN_SIDE};
use super::preprocessing::{ColourSpace, PixelScaling, Preprocessor};
use super::throttle::{CompetitionThrottle, ThrottleRule};
use crate::driver::pedals::pedals;
use crate::road::Road;
use crate::setting_checks::{all_within, SettingsError};
use crate::sim::{Command, Driver, Observation, VehicleParams};
use crate::vision::{Camera, Frame, RoadScene};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

/// A camera network's settings (a config file's `driver` section); the model itself comes only
/// from the command line. The defaults are the competition's DAVE-2 executor's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OnnxParams {
    /// The contract these settings started from (recorded; the settings below are what drives).
    pub contract: Contract,
    /// Control (camera and network) rate, hertz: dave2-proxy's.
    pub control_hz: f64,
    /// The camera the frames come from.
    pub camera: CameraSetting,
    /// How the input shape is read.
    pub layout: Layout,
    /// Rows cropped off the top of the camera frame (the competition's 80 of 160: the sky).
    pub crop_top_rows: usize,
    /// Rows cropped off the bottom (the competition's 1).
    pub crop_bottom_rows: usize,
    /// What a 3-channel model's channels hold.
    pub colour_space: ColourSpace,
    /// How pixel bytes become input values.
    pub pixel_scaling: PixelScaling,
    /// Which way a positive steering answer turns.
    pub steering_positive: SteeringSide,
    /// The wheel angle of a steering answer of 1, degrees (`None`: the car's limit); the car
    /// clamps it to its limit.
    pub max_steering_deg: Option<f64>,
    /// How the speed is kept.
    pub throttle: ThrottleRule,
    /// The competition rule's speed limit, km/h (`None`: the run's `--speed-limit`).
    pub max_speed_kmh: Option<f64>,
    /// The competition rule's speed once the car went above the limit, km/h.
    pub slow_down_kmh: f64,
    /// The speed controller's set speed, km/h (capped by the speed limit).
    pub speed_kmh: f64,
    /// The speed controller's throttle per m/s of speed deficit.
    pub throttle_gain: f64,
    /// The speed controller's brake per m/s of excess speed beyond the deadband.
    pub brake_gain: f64,
    /// The speed controller's excess speed tolerated without braking, m/s.
    pub brake_deadband_mps: f64,
}

impl Default for OnnxParams {
    fn default() -> Self {
        Self::sbst2022()
    }
}

/// Kilometres per hour in a mile per hour (the Udacity simulator's speeds).
const KMH_PER_MPH: f64 = 1.609_344;

impl OnnxParams {
    /// A contract's settings ([`super::contract`] says whose they are).
    pub fn of(contract: Contract) -> Self {
        let sbst2022 = Self::sbst2022();
        match contract {
            Contract::Sbst2022 => sbst2022,
            Contract::Udacity => Self {
                contract,
                camera: CameraSetting::udacity(),
                crop_top_rows: 60,
                crop_bottom_rows: 25,
                colour_space: ColourSpace::Yuv,
                pixel_scaling: PixelScaling::Raw,
                steering_positive: SteeringSide::Right,
                max_steering_deg: Some(25.0),
                throttle: ThrottleRule::Competition,
                max_speed_kmh: Some(25.0 * KMH_PER_MPH),
                slow_down_kmh: 10.0 * KMH_PER_MPH,
                ..sbst2022
            },
        }
    }

    /// The `sbst2022` contract's settings (the default).
    fn sbst2022() -> Self {
        Self {
            contract: Contract::Sbst2022,
            control_hz: 10.0,
            camera: CameraSetting::default(),
            layout: Layout::Auto,
            crop_top_rows: 80,
            crop_bottom_rows: 1,
            colour_space: ColourSpace::Yuv,
            pixel_scaling: PixelScaling::Raw,
            steering_positive: SteeringSide::Left,
            max_steering_deg: None,
            throttle: ThrottleRule::Competition,
            max_speed_kmh: None,
            slow_down_kmh: 10.0,
            speed_kmh: 25.0,
            throttle_gain: 0.5,
            brake_gain: 0.3,
            brake_deadband_mps: 0.5,
        }
    }

    /// Names the first setting no model can be driven with (those that depend on the model are
    /// checked by [`OnnxConfig::load`]).
    pub fn validate(&self) -> Result<(), SettingsError> {
        let c = &self.camera;
        let side = |v: Option<usize>| v.map_or(MIN_SIDE as f64, |v| v as f64);
        all_within(
            "driver.",
            &[
                ("control_hz", self.control_hz, 0.1, 100.0),
                ("slow_down_kmh", self.slow_down_kmh, 0.1, 300.0),
                ("speed_kmh", self.speed_kmh, 0.1, 300.0),
                (
                    "max_speed_kmh",
                    self.max_speed_kmh.unwrap_or(1.0),
                    0.1,
                    300.0,
                ),
                (
                    "max_steering_deg",
                    self.max_steering_deg.unwrap_or(1.0),
                    0.1,
                    90.0,
                ),
                (
                    "camera.width",
                    side(c.width),
                    MIN_SIDE as f64,
                    MAX_SIDE as f64,
                ),
                (
                    "camera.height",
                    side(c.height),
                    MIN_SIDE as f64,
                    MAX_SIDE as f64,
                ),
                ("camera.hfov_deg", c.hfov_deg, 1.0, 170.0),
                ("camera.pitch_down_deg", c.pitch_down_deg, -45.0, 89.0),
                ("camera.height_m", c.height_m, 0.1, 10.0),
                ("camera.forward_m", c.forward_m, -5.0, 5.0),
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

/// A camera network to drive with: the model, loaded and checked once, and its settings.
#[derive(Debug, Clone)]
pub struct OnnxConfig {
    /// The settings.
    pub params: OnnxParams,
    model: Arc<OnnxModel>,
}

impl OnnxConfig {
    /// Loads the model at `path` and checks that `params` fit it (the crop leaves rows, a
    /// `network` throttle has a second output).
    pub fn load(path: &Path, params: OnnxParams) -> Result<Self, OnnxError> {
        let model = OnnxModel::load(path, params.layout)?;
        let setting = |problem: String| OnnxError::Setting {
            path: path.to_owned(),
            problem,
        };
        let input = model.input();
        let camera = params.camera.camera(input.width, input.height);
        if params.crop_top_rows + params.crop_bottom_rows >= camera.height {
            let whose = if params.camera.height.is_some() {
                "driver.camera.height"
            } else {
                "the model's"
            };
            return Err(setting(format!(
                "driver.crop_top_rows ({}) and driver.crop_bottom_rows ({}) leave no row of \
                 the camera's {}-row frame ({whose})",
                params.crop_top_rows, params.crop_bottom_rows, camera.height
            )));
        }
        if params.throttle == ThrottleRule::Network && model.outputs() != 2 {
            return Err(setting(
                "driver.throttle is \"network\" but the model answers one number (the steering), \
                 not two"
                    .into(),
            ));
        }
        Ok(Self {
            params,
            model: Arc::new(model),
        })
    }

    /// The model.
    pub fn model(&self) -> &OnnxModel {
        &self.model
    }

    /// A driver for one drive.
    pub fn build(&self) -> OnnxDriver {
        let input = self.model.input();
        let p = &self.params;
        let camera = p.camera.camera(input.width, input.height);
        let preprocessor = Preprocessor::new(
            input,
            [camera.width, camera.height],
            p.crop_top_rows,
            p.crop_bottom_rows,
            p.colour_space,
            p.pixel_scaling,
        );
        let (state, failure) = match (self.model.spawn(), preprocessor.is_some()) {
            (Ok(state), true) => (Some(state), None),
            (Err(e), _) => (None, Some(e.to_string())),
            // `load` checked the crop.
            (Ok(_), false) => (None, Some("the crop leaves no row".to_string())),
        };
        let frame = Frame::new(camera.width, camera.height, input.channels);
        let camera = Camera::new(camera);
        OnnxDriver {
            params: self.params,
            path: self.model.path().display().to_string(),
            channels: input.channels,
            state,
            preprocessor,
            camera,
            scene: None,
            frame,
            input: Vec::new(),
            max_steering_rad: VehicleParams::default().max_steering_rad,
            target_mps: p.speed_kmh / 3.6,
            competition: CompetitionThrottle::new(
                p.max_speed_kmh.unwrap_or(p.speed_kmh),
                p.slow_down_kmh,
            ),
            failure,
        }
    }
}

/// The driver of one drive.
#[derive(Debug)]
pub struct OnnxDriver {
    params: OnnxParams,
    path: String,
    channels: usize,
    state: Option<ModelState>,
    preprocessor: Option<Preprocessor>,
    camera: Camera,
    scene: Option<RoadScene>,
    frame: Frame,
    input: Vec<f32>,
    max_steering_rad: f64,
    target_mps: f64,
    competition: CompetitionThrottle,
    failure: Option<String>,
}

impl OnnxDriver {
    /// The last frame the camera rendered.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// Ends the drive: `why` is kept for [`Driver::failure`], the command is non-finite.
    fn fail(&mut self, why: String) -> Command {
        self.failure.get_or_insert(why);
        Command {
            steering_rad: f64::NAN,
            throttle: f64::NAN,
            brake: f64::NAN,
        }
    }
}

impl Driver for OnnxDriver {
    fn name(&self) -> &'static str {
        "onnx"
    }

    fn control_hz(&self) -> f64 {
        self.params.control_hz
    }

    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64) {
        self.scene = Some(RoadScene::new(road));
        let p = &self.params;
        self.max_steering_rad = p
            .max_steering_deg
            .map_or(vehicle.max_steering_rad, f64::to_radians);
        self.target_mps = (p.speed_kmh / 3.6).min(speed_limit_mps);
        let max_kmh = p.max_speed_kmh.unwrap_or(speed_limit_mps * 3.6);
        self.competition = CompetitionThrottle::new(max_kmh, p.slow_down_kmh);
    }

    fn act(&mut self, observation: &Observation<'_>) -> Command {
        let car = observation.car;
        let (Some(state), Some(preprocessor)) = (&mut self.state, &mut self.preprocessor) else {
            let why = self.failure.clone().unwrap_or_default();
            return self.fail(why);
        };
        let scene = self
            .scene
            .get_or_insert_with(|| RoadScene::new(observation.road));
        if self.channels == 1 {
            self.camera
                .render_into(scene, car.position, car.heading_rad, &mut self.frame);
        } else {
            self.camera
                .render_rgb_into(scene, car.position, car.heading_rad, &mut self.frame);
        }
        preprocessor.prepare(&self.frame, &mut self.input);
        let answer = match state.run(&self.input) {
            Ok(answer) => answer,
            Err(e) => {
                let why = format!("ONNX model {}: {e}", self.path);
                return self.fail(why);
            }
        };
        let uses_second = self.params.throttle == ThrottleRule::Network;
        let used = if uses_second {
            &answer[..]
        } else {
            &answer[..1]
        };
        if let Some(v) = used.iter().find(|v| !v.is_finite()) {
            let why = format!(
                "ONNX model {} answered {v} at {:.1} s into the drive",
                self.path, observation.time_s
            );
            return self.fail(why);
        }
        let raw = f64::from(answer[0]);
        let speed_error = self.target_mps - car.speed_mps;
        let p = &self.params;
        let (throttle, brake) = match p.throttle {
            ThrottleRule::Competition => {
                let t = self.competition.throttle(raw, car.speed_mps * 3.6);
                (t.clamp(0.0, 1.0), 0.0)
            }
            ThrottleRule::SpeedController => pedals(
                speed_error,
                p.throttle_gain,
                p.brake_gain,
                p.brake_deadband_mps,
            ),
            ThrottleRule::Network => {
                let t = f64::from(answer[1]);
                (t.clamp(0.0, 1.0), (-t).clamp(0.0, 1.0))
            }
        };
        let left = match p.steering_positive {
            SteeringSide::Left => raw,
            SteeringSide::Right => -raw,
        };
        Command {
            steering_rad: left.clamp(-1.0, 1.0) * self.max_steering_rad,
            throttle,
            brake,
        }
    }

    fn failure(&self) -> Option<String> {
        self.failure.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::dave2::{embedded_weights, Dave2Driver, Dave2DriverParams};
    use crate::driver::CompetitionSetup;
    use crate::sim::{simulate, Outcome, StopReason};
    use crate::vision::{CameraParams, Dave2Net};
    use std::path::PathBuf;

    fn fixture(name: &str) -> PathBuf {
        PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/fixtures/onnx"
        ))
        .join(name)
    }

    /// dave2-proxy's contract: no crop, its speed controller.
    fn as_dave2_proxy() -> OnnxParams {
        OnnxParams {
            crop_top_rows: 0,
            crop_bottom_rows: 0,
            throttle: ThrottleRule::SpeedController,
            ..OnnxParams::default()
        }
    }

    fn bend() -> Road {
        Road::new(&[[100.0, 10.0], [100.0, 40.0], [120.0, 70.0], [150.0, 80.0]]).unwrap()
    }

    #[test]
    fn tract_answers_as_the_fast_inference_on_camera_frames() {
        let config = OnnxConfig::load(&fixture("dave2-proxy.onnx"), as_dave2_proxy()).unwrap();
        let input = config.model().input();
        assert_eq!(input.to_string(), "NHWC [1, 66, 200, 1]");
        assert_eq!(config.model().outputs(), 1);
        let mut state = config.model().spawn().unwrap();
        let mut fast = Dave2Net::new(&embedded_weights());
        let road = bend();
        let scene = RoadScene::new(&road);
        let camera = Camera::default();
        let mut pre =
            Preprocessor::new(input, [200, 66], 0, 0, ColourSpace::Yuv, PixelScaling::Raw).unwrap();
        let mut values = Vec::new();
        let mut compared = 0;
        for i in 0..40 {
            let t = i as f64 / 40.0;
            let position = [100.5 + 30.0 * t * t + (i % 3) as f64 * 0.7, 12.0 + 60.0 * t];
            let heading = 1.57 - 1.2 * t + 0.1 * ((i % 5) as f64 - 2.0);
            let frame = camera.render(&scene, position, heading);
            pre.prepare(&frame, &mut values);
            let [got, _] = state.run(&values).unwrap();
            let want = fast.predict(&frame.data);
            assert!((got - want).abs() < 1e-4, "frame {i}: {got} vs {want}");
            compared += 1;
        }
        assert_eq!(compared, 40);
    }

    #[test]
    fn sbst2022_is_todays_default_and_udacity_the_courses() {
        assert_eq!(OnnxParams::of(Contract::Sbst2022), OnnxParams::default());
        let u = OnnxParams::of(Contract::Udacity);
        assert_eq!(u.contract, Contract::Udacity);
        assert_eq!((u.crop_top_rows, u.crop_bottom_rows), (60, 25));
        assert_eq!(u.camera.camera(200, 66).height, 160);
        assert!((u.max_speed_kmh.unwrap() - 40.2336).abs() < 1e-9);
    }

    #[test]
    fn the_fixture_drives_as_dave2_proxy() {
        let config = OnnxConfig::load(&fixture("dave2-proxy.onnx"), as_dave2_proxy()).unwrap();
        let sim = CompetitionSetup::Dave2.sim_config();
        for road in [
            bend(),
            Road::new(&[[100.0, 10.0], [90.0, 50.0], [110.0, 90.0], [100.0, 130.0]]).unwrap(),
        ] {
            let mut network = config.build();
            let a = simulate(&road, &mut network, &sim, false, None);
            let mut proxy = Dave2Driver::new(&embedded_weights(), Dave2DriverParams::default());
            let b = simulate(&road, &mut proxy, &sim, false, None);
            assert_eq!((a.outcome, a.reason), (b.outcome, b.reason));
            assert!((a.max_bolp - b.max_bolp).abs() < 1e-3, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn a_colour_network_sees_yuv_and_may_set_the_throttle() {
        let params = OnnxParams {
            crop_top_rows: 4,
            crop_bottom_rows: 0,
            throttle: ThrottleRule::Network,
            ..OnnxParams::default()
        };
        let config = OnnxConfig::load(&fixture("rgb_mean.onnx"), params).unwrap();
        let input = config.model().input();
        assert_eq!(input.to_string(), "NCHW [1, 3, 16, 32]");
        assert_eq!(config.model().outputs(), 2);
        // The model answers (mean U - 128) / 128 and 0.5.
        let camera = Camera::new(CameraParams {
            width: 32,
            height: 16,
            ..CameraParams::default()
        });
        let road = bend();
        let frame = camera.render_rgb(&RoadScene::new(&road), [102.0, 20.0], 1.5);
        let mut pre =
            Preprocessor::new(input, [32, 16], 4, 0, ColourSpace::Yuv, PixelScaling::Raw).unwrap();
        let mut values = Vec::new();
        pre.prepare(&frame, &mut values);
        let u = &values[16 * 32..2 * 16 * 32];
        let mean = u.iter().sum::<f32>() / u.len() as f32;
        assert!(u.iter().any(|&v| v != u[0]), "a uniform frame tests little");
        let [steering, throttle] = config.model().spawn().unwrap().run(&values).unwrap();
        assert!((steering - (mean - 128.0) / 128.0).abs() < 1e-5);
        assert_eq!(throttle, 0.5);
        let r = simulate(
            &road,
            &mut config.build(),
            &CompetitionSetup::Dave2.sim_config(),
            true,
            None,
        );
        assert_ne!(r.outcome, Outcome::Error);
        let trace = r.trace.unwrap();
        assert!(trace.iter().any(|s| s.speed_kmh > 5.0));
    }

    #[test]
    fn a_nan_answer_ends_the_drive_as_error_with_the_reason() {
        let path = fixture("nan_on_road.onnx");
        // A blank frame gives sqrt(-0): the model loads.
        let config = OnnxConfig::load(&path, as_dave2_proxy()).unwrap();
        let r = simulate(
            &bend(),
            &mut config.build(),
            &CompetitionSetup::Dave2.sim_config(),
            false,
            None,
        );
        assert_eq!(
            (r.outcome, r.reason),
            (Outcome::Error, Some(StopReason::DriverFailed))
        );
        let error = r.error.unwrap();
        assert!(
            error.contains("nan_on_road.onnx") && error.contains("answered NaN at 0.0 s"),
            "{error}"
        );
    }

    #[test]
    fn bad_models_are_refused_naming_the_file_and_the_problem() {
        let refused = |path: &Path, params: OnnxParams| {
            OnnxConfig::load(path, params).unwrap_err().to_string()
        };
        let dir = std::env::temp_dir().join(format!("road-sim-onnx-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let garbage = dir.join("garbage.onnx");
        std::fs::write(&garbage, b"\x08\x07not a protobuf at all \xff\xff\xff\xff").unwrap();
        let e = refused(&garbage, as_dave2_proxy());
        assert!(e.contains("garbage.onnx is not an ONNX model"), "{e}");
        let empty = dir.join("empty.onnx");
        std::fs::write(&empty, b"").unwrap();
        let e = refused(&empty, as_dave2_proxy());
        assert!(e.contains("empty.onnx"), "{e}");
        let e = refused(&dir.join("missing.onnx"), as_dave2_proxy());
        assert!(
            e.contains("cannot read ONNX model") && e.contains("missing.onnx"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();

        let e = refused(&fixture("rank2.onnx"), as_dave2_proxy());
        assert!(
            e.contains("rank2.onnx") && e.contains("[1, 200]") && e.contains("rank 4"),
            "{e}"
        );
        let e = refused(&fixture("three_outputs.onnx"), as_dave2_proxy());
        assert!(
            e.contains("three_outputs.onnx") && e.contains("3 numbers"),
            "{e}"
        );
        // The competition's crop does not fit a 66-row model.
        let e = refused(&fixture("dave2-proxy.onnx"), OnnxParams::default());
        assert!(
            e.contains("driver.crop_top_rows (80)") && e.contains("66-row"),
            "{e}"
        );
        let e = refused(
            &fixture("dave2-proxy.onnx"),
            OnnxParams {
                throttle: ThrottleRule::Network,
                ..as_dave2_proxy()
            },
        );
        assert!(
            e.contains("driver.throttle") && e.contains("one number"),
            "{e}"
        );
        let e = refused(
            &fixture("dave2-proxy.onnx"),
            OnnxParams {
                layout: Layout::Nchw,
                ..as_dave2_proxy()
            },
        );
        assert!(e.contains("66 channels"), "{e}");
    }

    #[test]
    fn is_send() {
        fn check<T: Send>() {}
        check::<OnnxDriver>();
        check::<OnnxConfig>();
    }
}
