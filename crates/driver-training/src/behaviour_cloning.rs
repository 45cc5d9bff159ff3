//! Training `dave2-proxy` by behaviour cloning from the `beamng-ai-proxy` teacher.
//!
//! The teacher drives random valid roads (the WOGAN paper's sampler) at the student's speed. The
//! car executes the teacher's steering *plus* a slowly changing random perturbation, so it drifts
//! off the lane centre, while each recorded label is the teacher's own, corrective, steering for
//! the pose the camera saw (DAgger-style): the student learns to recover, not only to follow.
//! DAVE-2 is then trained with Adam on the mean squared error of the normalised steering, on a
//! seeded shuffle, and judged on frames of roads it never saw.
//!
//! The defaults make the built-in student: 120 roads no sharper than 0.03/m, half of them 75 m
//! (WOGAN's) and half 180 m (the competition's lengths), 4 epochs, the calibrated proxy as the
//! teacher, and steering noise of up to 0.096 rad. The noise sets how far the student reaches
//! beyond the bends it was shown: with this much it keeps its lane on most roads and fails on some
//! of the sharpest bends to the right (its lane on the inside), as the competition's DAVE-2
//! failed a few percent of long roads. How each candidate drove is in
//! `docs/experiments/2026-11-23-drivers-on-long-roads.md`.
//!
//! The student is a steep, erratic function of its training: one road, epoch or seed more or
//! less swings its failure rate across whole bands. Earlier students (teachers, noise, road
//! sets, seeds) and what WOGAN made of them are in `docs/experiments/2026-11-22-dave2-students.md`.

use crate::dave2_model::Dave2Trainer;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use road_sim::driver::{BeamNgAiParams, BeamNgAiProxy, Driver, Observation};
use road_sim::setting_checks::{
    all_non_negative, all_positive, all_within, first_problem, positive, SettingsError,
};
use road_sim::sim::{simulate, Command, SimConfig, VehicleParams};
use road_sim::vision::{
    Camera, CameraParams, Dave2Net, Dave2Weights, Frame, RoadScene, FRAME_PIXELS,
};
use road_sim::{CurvatureRoad, Road, Validator};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The teacher that recorded the built-in student: `beamng-ai-proxy` as calibrated on
/// 2026-11-23 (look-ahead 5 m + 0.3 s, which keeps near the lane centre at the student's 25 km/h).
/// It is fixed here, apart from the proxy's defaults, so that `train-driver`'s defaults still
/// make that student when the proxy is recalibrated as a driver under test.
pub const BUILT_IN_STUDENT_TEACHER: BeamNgAiParams = BeamNgAiParams {
    aggression: 0.7,
    lateral_grip_base: 0.3,
    lateral_grip_per_aggression: 0.735,
    brake_base: 0.3,
    brake_per_aggression: 0.4,
    lookahead_base_m: 5.0,
    lookahead_time_s: 0.3,
    steering_gain: 1.0,
    plan_half_chord_m: 3.0,
    speed_preview_s: 1.0,
    throttle_gain: 0.5,
    brake_gain: 1.0,
    brake_deadband_mps: 0.5,
    lift_off_offset_m: Some(1.8),
    control_hz: 30.0,
};

/// How the student is trained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CloningConfig {
    /// Seed of every random choice (roads, noise, initial weights, shuffles).
    pub seed: u64,
    /// Random roads driven for training frames.
    pub training_roads: usize,
    /// Other random roads driven for validation frames.
    pub validation_roads: usize,
    /// Curvature values per road (the paper's 5: 75 m roads).
    pub curvature_points: usize,
    /// Share of the roads (training and validation alike) that are long instead.
    pub long_road_share: f64,
    /// Curvature values of a long road (12: 180 m, the length of the SBST competition's roads).
    pub long_road_curvature_points: usize,
    /// Largest curvature of the training roads, 1/m. Below the paper's 0.07, the student meets
    /// sharper turns in testing than it learned from, as DAVE-2 did in the competition.
    pub max_curvature_per_m: f64,
    /// Speed limit of the recorded drives, km/h (the student's speed).
    pub speed_kmh: f64,
    /// Frames recorded per simulated second (the student's control rate).
    pub record_hz: f64,
    /// Largest steering perturbation, radians of wheel angle.
    pub noise_max_rad: f64,
    /// Shortest and longest time one perturbation is held, seconds.
    pub noise_hold_s: (f64, f64),
    /// The teacher's settings ([`BUILT_IN_STUDENT_TEACHER`] by default).
    pub teacher: BeamNgAiParams,
    /// Passes over the training frames.
    pub epochs: usize,
    /// Frames per Adam step.
    pub batch_size: usize,
    /// Adam's learning rate.
    pub learning_rate: f64,
    /// Wall time the whole training may take, seconds: no epoch starts that would end past it
    /// (judged by the last epoch's length).
    pub time_limit_s: f64,
}

impl Default for CloningConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            training_roads: 120,
            validation_roads: 20,
            curvature_points: 5,
            long_road_share: 0.5,
            long_road_curvature_points: 12,
            max_curvature_per_m: 0.03,
            speed_kmh: 25.0,
            record_hz: 10.0,
            noise_max_rad: 0.096,
            noise_hold_s: (0.3, 1.2),
            teacher: BUILT_IN_STUDENT_TEACHER,
            epochs: 4,
            batch_size: 64,
            learning_rate: 3e-4,
            time_limit_s: 28.0 * 60.0,
        }
    }
}

impl CloningConfig {
    /// Names the first setting training cannot work with (from a hand-written config file).
    pub fn validate(&self) -> Result<(), SettingsError> {
        let (shortest, longest) = self.noise_hold_s;
        first_problem(&[
            (
                (1..=100_000).contains(&self.training_roads),
                "training_roads",
                "from 1 to 100000",
            ),
            (
                (1..=100_000).contains(&self.validation_roads),
                "validation_roads",
                "from 1 to 100000",
            ),
            // Beyond these, valid random roads become too rare to collect.
            (
                (2..=14).contains(&self.curvature_points),
                "curvature_points",
                "between 2 and 14",
            ),
            (
                (2..=14).contains(&self.long_road_curvature_points),
                "long_road_curvature_points",
                "between 2 and 14",
            ),
            (
                (0.0..=1.0).contains(&self.long_road_share),
                "long_road_share",
                "in [0, 1]",
            ),
            (
                positive(self.max_curvature_per_m) && self.max_curvature_per_m <= 0.07,
                "max_curvature_per_m",
                "in (0, 0.07]",
            ),
            (
                positive(shortest) && shortest <= longest && longest.is_finite(),
                "noise_hold_s",
                "two positive times, the shorter first",
            ),
            (
                (1..=1000).contains(&self.epochs),
                "epochs",
                "from 1 to 1000",
            ),
            (
                (1..=4096).contains(&self.batch_size),
                "batch_size",
                "from 1 to 4096",
            ),
        ])?;
        all_within(
            "",
            &[
                ("speed_kmh", self.speed_kmh, 0.1, 300.0),
                ("record_hz", self.record_hz, 0.1, 100.0),
                ("learning_rate", self.learning_rate, 1e-9, 1.0),
            ],
        )?;
        all_positive("", &[("time_limit_s", self.time_limit_s)])?;
        all_non_negative("", &[("noise_max_rad", self.noise_max_rad)])?;
        self.teacher.validate().map_err(|problem| {
            // The teacher's settings sit under `teacher` in a training config.
            let setting = problem.setting.replacen("driver.", "teacher.", 1);
            SettingsError { setting, ..problem }
        })
    }
}

/// Recorded camera frames (grayscale, concatenated) and the teacher's normalised steering.
#[derive(Debug, Clone, Default)]
pub struct DrivingData {
    /// `len() * FRAME_PIXELS` bytes.
    pub frames: Vec<u8>,
    /// Teacher steering over the car's maximum wheel angle, in `[-1, 1]`.
    pub targets: Vec<f32>,
}

impl DrivingData {
    /// Number of recorded frames.
    pub fn len(&self) -> usize {
        self.targets.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.targets.is_empty()
    }

    /// Frame `i`'s pixels.
    pub fn frame(&self, i: usize) -> &[u8] {
        &self.frames[i * FRAME_PIXELS..(i + 1) * FRAME_PIXELS]
    }
}

/// What a training run measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CloningReport {
    /// Frames trained on.
    pub training_frames: usize,
    /// Frames of unseen roads validated on.
    pub validation_frames: usize,
    /// Mean training loss of each epoch run.
    pub epoch_losses: Vec<f64>,
    /// Root mean squared steering error of the student on the validation frames, degrees of
    /// wheel angle.
    pub student_rmse_deg: f64,
    /// The same for the best constant steering (the training mean).
    pub constant_rmse_deg: f64,
    /// The same for the untrained network the training started from.
    pub untrained_rmse_deg: f64,
    /// Wall time of recording and training, seconds.
    pub seconds: f64,
}

/// Progress of a training run, for a progress display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CloningProgress {
    /// Roads recorded so far (of the total).
    Recorded {
        roads: usize,
        of: usize,
        frames: usize,
    },
    /// An epoch ended.
    Epoch {
        epoch: usize,
        of: usize,
        loss: f64,
        validation_rmse_deg: f64,
        seconds: f64,
    },
}

/// Random valid roads from the paper's sampler on the competition's 200 m map: the first
/// curvature value uniform in `[-max_curvature_per_m, max_curvature_per_m]`, each next one a
/// uniform step of at most 0.05/m from it, clipped to that range.
pub fn random_valid_roads(
    count: usize,
    curvature_points: usize,
    max_curvature_per_m: f64,
    rng: &mut ChaCha20Rng,
) -> Vec<Road> {
    let sampler = RandomRoads::new(curvature_points, max_curvature_per_m, 200.0);
    // On the 200 m map nearly every second draw is valid: the tries never run out.
    (0..count).filter_map(|_| sampler.draw(rng)).collect()
}

/// The paper's sampler of random roads on a map of a given size, with a bounded number of draws
/// per road: on a map too small for its roads it says so instead of drawing forever.
#[derive(Debug, Clone)]
pub struct RandomRoads {
    curvature_points: usize,
    max_curvature_per_m: f64,
    roads: CurvatureRoad,
    validator: Validator,
}

/// Draws per road before [`RandomRoads::draw`] gives up.
pub const MAX_DRAWS_PER_ROAD: usize = 100_000;

impl RandomRoads {
    /// Roads of `curvature_points` values of at most `max_curvature_per_m`, on a map of side
    /// `map_size_m`, starting as the search's roads do.
    pub fn new(curvature_points: usize, max_curvature_per_m: f64, map_size_m: f64) -> Self {
        Self {
            curvature_points,
            max_curvature_per_m,
            roads: CurvatureRoad {
                map_size_m,
                ..CurvatureRoad::default()
            },
            validator: Validator::new(map_size_m),
        }
    }

    /// A random valid road, or `None` after [`MAX_DRAWS_PER_ROAD`] invalid draws.
    pub fn draw(&self, rng: &mut ChaCha20Rng) -> Option<Road> {
        let step = 0.05;
        let bound = self.max_curvature_per_m;
        for _ in 0..MAX_DRAWS_PER_ROAD {
            let mut curvature = Vec::with_capacity(self.curvature_points);
            let mut value: f64 = rng.random_range(-bound..=bound);
            for _ in 0..self.curvature_points {
                curvature.push(value);
                value = (value + rng.random_range(-step..=step)).clamp(-bound, bound);
            }
            let verdict = self.validator.validate(&self.roads.points(&curvature));
            if let (None, Some(road)) = (verdict.reason, verdict.road) {
                return Some(road);
            }
        }
        None
    }
}

/// The teacher at the wheel, perturbed, with the camera recording its corrective steering.
struct NoisyTeacher<'a> {
    teacher: BeamNgAiProxy,
    camera: &'a Camera,
    scene: Option<RoadScene>,
    frame: Frame,
    rng: ChaCha20Rng,
    config: CloningConfig,
    max_steering_rad: f64,
    record_every: u64,
    tick: u64,
    noise_rad: f64,
    noise_until_s: f64,
    data: &'a mut DrivingData,
}

impl Driver for NoisyTeacher<'_> {
    fn name(&self) -> &'static str {
        "noisy-teacher"
    }

    fn control_hz(&self) -> f64 {
        self.teacher.control_hz()
    }

    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64) {
        self.teacher.reset(road, vehicle, speed_limit_mps);
        self.scene = Some(RoadScene::new(road));
        self.max_steering_rad = vehicle.max_steering_rad;
        self.tick = 0;
        self.noise_rad = 0.0;
        self.noise_until_s = 0.0;
    }

    fn act(&mut self, observation: &Observation<'_>) -> Command {
        let command = self.teacher.act(observation);
        if self.tick.is_multiple_of(self.record_every) {
            if let Some(scene) = &self.scene {
                let car = &observation.car;
                self.camera
                    .render_into(scene, car.position, car.heading_rad, &mut self.frame);
                self.data.frames.extend_from_slice(&self.frame.data);
                let label = (command.steering_rad / self.max_steering_rad).clamp(-1.0, 1.0);
                self.data.targets.push(label as f32);
            }
        }
        self.tick += 1;
        if observation.time_s >= self.noise_until_s {
            let (shortest, longest) = self.config.noise_hold_s;
            self.noise_until_s = observation.time_s + self.rng.random_range(shortest..=longest);
            let max = self.config.noise_max_rad;
            self.noise_rad = self.rng.random_range(-max..=max);
        }
        Command {
            steering_rad: command.steering_rad + self.noise_rad,
            ..command
        }
    }
}

/// Drives every road with the perturbed teacher and records what the camera saw.
pub fn record(
    roads: &[Road],
    config: &CloningConfig,
    rng: &mut ChaCha20Rng,
    on_road: &mut dyn FnMut(usize, usize),
) -> DrivingData {
    let camera = Camera::new(CameraParams::default());
    let sim = SimConfig {
        speed_limit_kmh: config.speed_kmh,
        // Recording goes on whatever the car does: the perturbed drives must not end early.
        oob_tolerance: 1.0,
        ..SimConfig::default()
    };
    let teacher_hz = config.teacher.control_hz;
    let mut data = DrivingData::default();
    for (i, road) in roads.iter().enumerate() {
        let mut driver = NoisyTeacher {
            teacher: BeamNgAiProxy::new(config.teacher),
            camera: &camera,
            scene: None,
            frame: Frame::new(0, 0, 1),
            rng: ChaCha20Rng::seed_from_u64(rng.random()),
            config: *config,
            max_steering_rad: VehicleParams::default().max_steering_rad,
            record_every: ((teacher_hz / config.record_hz).round() as u64).max(1),
            tick: 0,
            noise_rad: 0.0,
            noise_until_s: 0.0,
            data: &mut data,
        };
        simulate(road, &mut driver, &sim, false, None);
        on_road(i + 1, data.len());
    }
    data
}

/// Root mean squared error of `predict` on `data`, in degrees of wheel angle.
fn rmse_deg(
    data: &DrivingData,
    max_steering_rad: f64,
    mut predict: impl FnMut(usize) -> f32,
) -> f64 {
    if data.is_empty() {
        return f64::NAN;
    }
    let sum: f64 = (0..data.len())
        .map(|i| f64::from(predict(i) - data.targets[i]).powi(2))
        .sum();
    (sum / data.len() as f64).sqrt() * max_steering_rad.to_degrees()
}

/// Records data and trains DAVE-2 on it; returns the weights and what was measured.
pub fn train(
    config: &CloningConfig,
    on_progress: &mut dyn FnMut(CloningProgress),
) -> Result<(Dave2Weights, CloningReport), Diverged> {
    let started = Instant::now();
    let mut rng = ChaCha20Rng::seed_from_u64(config.seed);
    let all_roads = config.training_roads + config.validation_roads;
    let mut draw = |count: usize| {
        // Rounded, so that a share of 0.5 of an odd count still leaves both kinds of road.
        let long = (count as f64 * config.long_road_share).round() as usize;
        let mut roads = random_valid_roads(
            count - long,
            config.curvature_points,
            config.max_curvature_per_m,
            &mut rng,
        );
        roads.extend(random_valid_roads(
            long,
            config.long_road_curvature_points,
            config.max_curvature_per_m,
            &mut rng,
        ));
        roads
    };
    let training_roads = draw(config.training_roads);
    let validation_roads = draw(config.validation_roads);
    let mut report_road = |done: usize, frames: usize| {
        on_progress(CloningProgress::Recorded {
            roads: done,
            of: all_roads,
            frames,
        })
    };
    let training = record(&training_roads, config, &mut rng, &mut report_road);
    let validation = record(&validation_roads, config, &mut rng, &mut |done, frames| {
        report_road(config.training_roads + done, training.len() + frames)
    });

    let max_steering_rad = VehicleParams::default().max_steering_rad;
    let initial = Dave2Weights::from_seed(rng.random());
    let untrained_rmse_deg = {
        let mut net = Dave2Net::new(&initial);
        rmse_deg(&validation, max_steering_rad, |i| {
            net.predict(validation.frame(i))
        })
    };
    let mean_target =
        training.targets.iter().map(|&t| f64::from(t)).sum::<f64>() / training.len().max(1) as f64;
    let constant_rmse_deg = rmse_deg(&validation, max_steering_rad, |_| mean_target as f32);

    let mut trainer = Dave2Trainer::new(&initial, config.learning_rate);
    let mut order: Vec<usize> = (0..training.len()).collect();
    let mut epoch_losses = Vec::new();
    let mut student_rmse_deg = untrained_rmse_deg;
    let mut batch_frames = Vec::with_capacity(config.batch_size * FRAME_PIXELS);
    let mut batch_targets = Vec::with_capacity(config.batch_size);
    let mut last_epoch_s = 0.0;
    for epoch in 0..config.epochs {
        let epoch_started = Instant::now();
        if epoch > 0 && started.elapsed().as_secs_f64() + last_epoch_s > config.time_limit_s {
            break;
        }
        // Fisher–Yates with the run's RNG, so the shuffle follows the seed.
        for i in (1..order.len()).rev() {
            order.swap(i, rng.random_range(0..=i));
        }
        let (mut loss_sum, mut batches) = (0.0, 0usize);
        for batch in order.chunks(config.batch_size) {
            batch_frames.clear();
            batch_targets.clear();
            for &i in batch {
                batch_frames.extend_from_slice(training.frame(i));
                batch_targets.push(training.targets[i]);
            }
            loss_sum += trainer.step(&batch_frames, &batch_targets);
            batches += 1;
        }
        let loss = loss_sum / batches.max(1) as f64;
        if !loss.is_finite() {
            return Err(Diverged {
                epoch: epoch + 1,
                loss,
            });
        }
        epoch_losses.push(loss);
        let mut net = Dave2Net::new(&trainer.weights());
        student_rmse_deg = rmse_deg(&validation, max_steering_rad, |i| {
            net.predict(validation.frame(i))
        });
        let seconds = started.elapsed().as_secs_f64();
        on_progress(CloningProgress::Epoch {
            epoch: epoch + 1,
            of: config.epochs,
            loss,
            validation_rmse_deg: student_rmse_deg,
            seconds,
        });
        last_epoch_s = epoch_started.elapsed().as_secs_f64();
    }
    let report = CloningReport {
        training_frames: training.len(),
        validation_frames: validation.len(),
        epoch_losses,
        student_rmse_deg,
        constant_rmse_deg,
        untrained_rmse_deg,
        seconds: started.elapsed().as_secs_f64(),
    };
    Ok((trainer.weights(), report))
}

/// Training stopped because an epoch's loss was not finite: the weights are no longer numbers.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("training diverged in epoch {epoch} (mean loss {loss}); lower the learning rate")]
pub struct Diverged {
    /// The epoch, from 1.
    pub epoch: usize,
    /// Its mean loss.
    pub loss: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use road_sim::road::curvature::MAX_CURVATURE_PER_M;

    fn tiny() -> CloningConfig {
        CloningConfig {
            seed: 3,
            training_roads: 1,
            validation_roads: 1,
            record_hz: 5.0,
            epochs: 3,
            batch_size: 8,
            learning_rate: 1e-3,
            ..CloningConfig::default()
        }
    }

    #[test]
    fn recorded_labels_are_the_teachers_and_frames_match_them() {
        let mut rng = ChaCha20Rng::seed_from_u64(1);
        let roads = random_valid_roads(2, 5, MAX_CURVATURE_PER_M, &mut rng);
        let data = record(&roads, &tiny(), &mut rng, &mut |_, _| {});
        assert_eq!(data.frames.len(), data.len() * FRAME_PIXELS);
        // About 5 frames per simulated second over two 75 m roads at 25 km/h.
        assert!(data.len() > 80, "{} frames", data.len());
        assert!(data.targets.iter().all(|t| (-1.0..=1.0).contains(t)));
        // The perturbation makes the teacher correct both ways.
        assert!(data.targets.iter().any(|&t| t > 0.05) && data.targets.iter().any(|&t| t < -0.05));
    }

    #[test]
    fn a_few_steps_of_training_lower_the_loss_and_follow_the_seed() {
        let (weights, report) = train(&tiny(), &mut |_| {}).unwrap();
        let losses = &report.epoch_losses;
        assert_eq!(losses.len(), 3);
        assert!(losses[2] < losses[0], "loss did not fall: {losses:?}");
        let (again, _) = train(&tiny(), &mut |_| {}).unwrap();
        assert_eq!(weights.to_bytes(), again.to_bytes());
    }
}
