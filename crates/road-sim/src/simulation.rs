//! One drive: a car in a fresh rapier world, a driver, and the oracle sampling it until the car
//! reaches the end of the road, leaves its lane, stops, runs out of time, or the physics breaks.

use crate::beamng_ai::BeamNgAiParams;
use crate::dave2_driver::Dave2DriverParams;
use crate::driver::{Driver, DriverKind, DriverSetup, Observation};
use crate::features::RoadFeatures;
use crate::oracle::LaneMonitor;
use crate::outcome::{
    fitness_from_distance, reason, Outcome, Sample, SimResult, CENTRED_DISTANCE_M,
};
use crate::road::{Road, LANE_WIDTH_M};
use crate::settings_check::{all_non_negative, all_positive};
use crate::vehicle::{Command, Vehicle, VehicleParams};
use crate::Point;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Centre-line segments (about 1 m each) before the road's end within which the car must
/// project for the end to count as reached.
const END_SEGMENTS: usize = 25;

/// How a drive is simulated and judged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// The driver's speed limit, km/h.
    pub speed_limit_kmh: f64,
    /// The drive fails when BOLP exceeds this.
    pub oob_tolerance: f64,
    /// Physics steps per simulated second.
    pub physics_hz: f64,
    /// Oracle samples per simulated second (rounded to a whole number of physics steps).
    pub sample_hz: f64,
    /// Distance along the road from its first point to the car's start, metres.
    pub start_offset_m: f64,
    /// The drive passes when the car centre is this close to the road's last point, metres.
    pub end_distance_m: f64,
    /// Time limit: this many seconds ...
    pub timeout_base_s: f64,
    /// ... plus the road's length driven at this speed, metres per second.
    pub timeout_speed_mps: f64,
    /// The drive fails `not_moving` when the car moves less than `not_moving_distance_m` ...
    pub not_moving_distance_m: f64,
    /// ... within this many simulated seconds.
    pub not_moving_window_s: f64,
    /// The car.
    pub vehicle: VehicleParams,
    /// Tuning of the `beamng-ai-proxy` driver (used by [`simulate_kind`]).
    pub beamng_ai: BeamNgAiParams,
    /// Settings of the `dave2-proxy` driver.
    pub dave2: Dave2DriverParams,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            speed_limit_kmh: 70.0,
            oob_tolerance: 0.85,
            physics_hz: 60.0,
            sample_hz: 60.0,
            start_offset_m: 2.5,
            end_distance_m: 8.0,
            timeout_base_s: 20.0,
            timeout_speed_mps: 2.0,
            not_moving_distance_m: 1.0,
            not_moving_window_s: 10.0,
            vehicle: VehicleParams::default(),
            beamng_ai: BeamNgAiParams::default(),
            dave2: Dave2DriverParams::default(),
        }
    }
}

impl SimConfig {
    /// Names the first setting no simulation can run with (from a hand-written config file).
    pub fn validate(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.oob_tolerance) {
            return Err("oob_tolerance must be in [0, 1]".to_string());
        }
        all_positive(
            "",
            &[
                ("speed_limit_kmh", self.speed_limit_kmh),
                ("physics_hz", self.physics_hz),
                ("sample_hz", self.sample_hz),
                ("timeout_base_s", self.timeout_base_s),
                ("not_moving_window_s", self.not_moving_window_s),
            ],
        )?;
        all_non_negative(
            "",
            &[
                ("start_offset_m", self.start_offset_m),
                ("end_distance_m", self.end_distance_m),
                ("timeout_speed_mps", self.timeout_speed_mps),
                ("not_moving_distance_m", self.not_moving_distance_m),
            ],
        )?;
        self.vehicle.validate()?;
        self.beamng_ai.validate()?;
        self.dave2.validate()
    }

    /// The time limit for `road`: `timeout_base_s + length / timeout_speed_mps`, seconds.
    pub fn timeout_s(&self, road: &Road) -> f64 {
        self.timeout_base_s + road.length_m() / self.timeout_speed_mps
    }
}

/// The car's start: on the right lane's centre `offset_m` along the centre line from its first
/// point, heading along the road. Returns the position and heading.
pub fn start_pose(road: &Road, offset_m: f64) -> (Point, f64) {
    let c = &road.interpolated;
    let mut remaining = offset_m.max(0.0);
    for i in 0..c.len() - 1 {
        let (a, b) = (c[i], c[i + 1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let length = dx.hypot(dy);
        if remaining <= length || i + 2 == c.len() {
            let t = remaining / length;
            let n = road.left_normals[i];
            let half_lane = LANE_WIDTH_M / 2.0;
            let p = [
                a[0] + t * dx - half_lane * n[0],
                a[1] + t * dy - half_lane * n[1],
            ];
            return (p, dy.atan2(dx));
        }
        remaining -= length;
    }
    unreachable!("a road has at least two interpolated points")
}

/// Simulates the driver of kind `kind` (tuned by `config`, with built-in weights) on `road`.
pub fn simulate_kind(road: &Road, kind: DriverKind, config: &SimConfig, trace: bool) -> SimResult {
    simulate_setup(road, &DriverSetup::new(kind), config, trace)
}

/// Simulates a driver built from `setup` (tuned by `config`) on `road`.
pub fn simulate_setup(
    road: &Road,
    setup: &DriverSetup,
    config: &SimConfig,
    trace: bool,
) -> SimResult {
    simulate(road, setup.build(config).as_mut(), config, trace)
}

/// Drives `driver` on `road`; returns the verdict, the oracle's figures and, if `trace`, the
/// samples.
pub fn simulate(
    road: &Road,
    driver: &mut dyn Driver,
    config: &SimConfig,
    trace: bool,
) -> SimResult {
    let started = Instant::now();
    let features = RoadFeatures::of(&road.interpolated);
    let v = config.vehicle;
    let (start, heading) = start_pose(road, config.start_offset_m);
    let mut vehicle = Vehicle::new(v, start, heading, config.physics_hz);
    let speed_limit_mps = config.speed_limit_kmh / 3.6;
    driver.reset(road, &v, speed_limit_mps);
    let mut monitor = LaneMonitor::new(road);

    let dt = 1.0 / config.physics_hz;
    let control_stride = ((config.physics_hz / driver.control_hz()).round() as u64).max(1);
    let sample_stride = ((config.physics_hz / config.sample_hz).round() as u64).max(1);
    let timeout_s = config.timeout_s(road);
    let end = *road.interpolated.last().expect("a road has points");

    let mut samples = Vec::new();
    let mut command = Command::default();
    let (mut max_bolp, mut min_distance) = (0.0_f64, f64::INFINITY);
    let (mut sum_lp, mut max_lp) = (0.0, f64::NEG_INFINITY);
    let (mut sum_sa, mut sum_sa_sq, mut count) = (0.0, 0.0, 0_u64);
    let (mut anchor, mut anchor_t) = (start, 0.0);
    let mut step = 0_u64;
    let (outcome, why) = loop {
        if step.is_multiple_of(control_stride) {
            let observation = Observation {
                time_s: step as f64 * dt,
                car: vehicle.state(),
                road,
            };
            command = driver.act(&observation);
            if !(command.steering_rad.is_finite()
                && command.throttle.is_finite()
                && command.brake.is_finite())
            {
                break (Outcome::Error, Some(reason::NON_FINITE_COMMAND));
            }
        }
        vehicle.step(&command);
        step += 1;
        if !vehicle.is_finite() {
            break (Outcome::Error, Some(reason::NON_FINITE));
        }
        if !step.is_multiple_of(sample_stride) {
            continue;
        }
        let t = step as f64 * dt;
        let car = vehicle.state();
        let m = monitor.measure(car.position, car.heading_rad, v.length_m, v.width_m);
        let steering_deg = car.steering_rad.to_degrees();
        max_bolp = max_bolp.max(m.bolp);
        min_distance = min_distance.min(m.dist_left_m.min(m.dist_right_m));
        sum_lp += m.oob_distance_m;
        max_lp = max_lp.max(m.oob_distance_m);
        sum_sa += steering_deg;
        sum_sa_sq += steering_deg * steering_deg;
        count += 1;
        if trace {
            samples.push(Sample {
                t,
                x: car.position[0],
                y: car.position[1],
                heading: car.heading_rad,
                speed_kmh: car.speed_mps * 3.6,
                steering_deg,
                bolp: m.bolp,
                dist_left_m: m.dist_left_m,
                dist_right_m: m.dist_right_m,
            });
        }
        if m.bolp > config.oob_tolerance {
            break (Outcome::Fail, Some(reason::OUT_OF_LANE));
        }
        // The end counts only once the car has got near it along the road (a road may pass close
        // to its own end earlier).
        let near_end_along = m.segment + END_SEGMENTS >= road.interpolated.len();
        if near_end_along
            && (car.position[0] - end[0]).hypot(car.position[1] - end[1]) <= config.end_distance_m
        {
            break (Outcome::Pass, None);
        }
        let moved = (car.position[0] - anchor[0]).hypot(car.position[1] - anchor[1]);
        if moved >= config.not_moving_distance_m {
            (anchor, anchor_t) = (car.position, t);
        } else if t - anchor_t >= config.not_moving_window_s {
            break (Outcome::Fail, Some(reason::NOT_MOVING));
        }
        if t >= timeout_s {
            break (Outcome::Fail, Some(reason::TIMEOUT));
        }
    };
    let n = count.max(1) as f64;
    let mean_sa = sum_sa / n;
    let min_lane_distance_m = if count == 0 {
        CENTRED_DISTANCE_M
    } else {
        min_distance
    };
    SimResult {
        outcome,
        reason: why.map(str::to_owned),
        max_bolp,
        min_lane_distance_m,
        fitness_distance: fitness_from_distance(min_lane_distance_m),
        sim_time_s: step as f64 * dt,
        execution_ms: started.elapsed().as_secs_f64() * 1e3,
        max_curv: features.max_curvature,
        dir_cov: features.direction_coverage,
        std_sa: (sum_sa_sq / n - mean_sa * mean_sa).max(0.0).sqrt(),
        mean_lp: if count == 0 {
            LANE_WIDTH_M / 2.0
        } else {
            sum_lp / n
        },
        max_lp: if count == 0 {
            LANE_WIDTH_M / 2.0
        } else {
            max_lp
        },
        trace: trace.then_some(samples),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validator::Validator;

    fn drive(points: &[Point], config: &SimConfig) -> SimResult {
        let road = Road::new(points).unwrap();
        simulate_kind(&road, DriverKind::BeamNgAiProxy, config, true)
    }

    /// A straight start of `lead_m`, then an arc of `radius_m` turning left by `angle_rad`,
    /// starting at (`x0`, `y0`) heading north; arc points about every 2 m.
    fn arc_road(x0: f64, y0: f64, lead_m: f64, radius_m: f64, angle_rad: f64) -> Vec<Point> {
        let mut points = vec![[x0, y0], [x0, y0 + lead_m / 2.0], [x0, y0 + lead_m]];
        let steps = ((radius_m * angle_rad / 2.0).ceil() as usize).max(3);
        let centre = [x0 - radius_m, y0 + lead_m];
        for k in 1..=steps {
            let a = angle_rad * k as f64 / steps as f64;
            points.push([
                centre[0] + radius_m * a.cos(),
                centre[1] + radius_m * a.sin(),
            ]);
        }
        points
    }

    #[test]
    fn start_pose_is_on_the_right_lane_centre() {
        let road = Road::new(&[[100.0, 10.0], [100.0, 60.0], [100.0, 110.0]]).unwrap();
        let (p, heading) = start_pose(&road, 2.5);
        assert!(
            (p[0] - 102.0).abs() < 1e-9 && (p[1] - 12.5).abs() < 1e-9,
            "{p:?}"
        );
        assert!((heading - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
    }

    #[test]
    fn reaches_the_speed_limit_on_a_straight_road_without_overshooting() {
        let config = SimConfig::default();
        let r = drive(&[[0.0, 0.0], [0.0, 100.0], [0.0, 200.0]], &config);
        assert_eq!(r.outcome, Outcome::Pass, "{:?}", r.reason);
        let trace = r.trace.unwrap();
        let top = trace.iter().map(|s| s.speed_kmh).fold(0.0, f64::max);
        assert!(top > 0.97 * config.speed_limit_kmh, "top speed {top}");
        assert!(top < 1.1 * config.speed_limit_kmh, "top speed {top}");
        let worst = trace
            .iter()
            .max_by(|a, b| a.bolp.total_cmp(&b.bolp))
            .unwrap();
        assert!(r.max_bolp < 1e-9, "{worst:?}");
    }

    #[test]
    fn settles_on_the_lane_centre_of_a_straight_road() {
        let r = drive(
            &[[0.0, 0.0], [0.0, 100.0], [0.0, 200.0]],
            &SimConfig::default(),
        );
        for s in r.trace.unwrap().iter().filter(|s| s.t >= 3.0) {
            let offset = s.dist_left_m - 2.0;
            assert!(offset.abs() < 0.3, "offset {offset} at {}", s.t);
        }
    }

    #[test]
    fn completes_a_gentle_curve() {
        let points = arc_road(100.0, 10.0, 30.0, 60.0, std::f64::consts::FRAC_PI_2);
        let r = drive(&points, &SimConfig::default());
        assert_eq!(r.outcome, Outcome::Pass, "{:?}", r.reason);
        assert!(r.max_bolp < 0.2, "max bolp {}", r.max_bolp);
        assert!(
            r.min_lane_distance_m > 0.5 && r.fitness_distance < 0.5,
            "{r:?}"
        );
        assert!(r.std_sa > 0.5 && r.mean_lp > 1.0 && r.max_lp <= 2.0);
    }

    #[test]
    fn cuts_corners_towards_the_inside_of_a_bend() {
        let left = arc_road(100.0, 10.0, 30.0, 25.0, 1.6);
        let right: Vec<Point> = left.iter().map(|p| [200.0 - p[0], p[1]]).collect();
        let min = |r: &SimResult, f: fn(&Sample) -> f64| {
            r.trace
                .as_ref()
                .unwrap()
                .iter()
                .map(f)
                .fold(f64::INFINITY, f64::min)
        };
        let l = drive(&left, &SimConfig::default());
        let r = drive(&right, &SimConfig::default());
        let (l_in, l_out) = (min(&l, |s| s.dist_left_m), min(&l, |s| s.dist_right_m));
        let (r_in, r_out) = (min(&r, |s| s.dist_right_m), min(&r, |s| s.dist_left_m));
        eprintln!("left bend: inside {l_in:.2} outside {l_out:.2}; right bend: inside {r_in:.2} outside {r_out:.2}");
        assert!(
            l_in < 1.5 && l_in < l_out,
            "left bend: inside {l_in} outside {l_out}"
        );
        assert!(
            r_in < 1.5 && r_in < r_out,
            "right bend: inside {r_in} outside {r_out}"
        );
    }

    #[test]
    fn same_road_same_result() {
        let points = arc_road(100.0, 10.0, 20.0, 25.0, 2.0);
        let config = SimConfig::default();
        let mut a = drive(&points, &config);
        let mut b = drive(&points, &config);
        a.execution_ms = 0.0;
        b.execution_ms = 0.0;
        assert_eq!(a, b);
        assert_eq!(
            serde_json::to_string(&a).unwrap(),
            serde_json::to_string(&b).unwrap()
        );
    }

    #[test]
    fn roads_at_the_validity_limits_run_without_error() {
        let validator = Validator::default();
        // Nearly the sharpest turn allowed: a half circle whose interpolated centre line has a
        // smallest 5-point radius of 14.8 m (the limit is 47 ft = 14.3 m).
        let sharp = arc_road(100.0, 10.0, 20.0, 15.5, std::f64::consts::PI);
        // 500 points.
        let many: Vec<Point> = (0..500)
            .map(|i| {
                let x = 20.0 + 0.3 * i as f64;
                [x, 100.0 + 8.0 * (x / 15.0).sin()]
            })
            .collect();
        // Close to the map's border.
        let border = vec![[4.2, 10.0], [4.2, 100.0], [4.2, 190.0]];
        for points in [sharp, many, border] {
            assert!(
                validator.validate(&points).is_valid(),
                "{:?}",
                validator.validate(&points).reason
            );
            let r = drive(&points, &SimConfig::default());
            assert_ne!(r.outcome, Outcome::Error, "{r:?}");
            assert!(r.max_bolp.is_finite() && r.sim_time_s > 1.0);
        }
    }

    /// A driver that ignores the road: `act` decides each command from the observation alone.
    struct Scripted {
        control_hz: f64,
        act: fn(&Observation<'_>) -> Command,
    }

    impl Driver for Scripted {
        fn name(&self) -> &'static str {
            "scripted"
        }
        fn control_hz(&self) -> f64 {
            self.control_hz
        }
        fn reset(&mut self, _: &Road, _: &VehicleParams, _: f64) {}
        fn act(&mut self, observation: &Observation<'_>) -> Command {
            (self.act)(observation)
        }
    }

    #[test]
    fn a_car_that_will_not_drive_fails_not_moving() {
        let mut parked = Scripted {
            control_hz: 10.0,
            act: |_| Command {
                brake: 1.0,
                ..Command::default()
            },
        };
        let road = Road::new(&[[0.0, 0.0], [0.0, 100.0]]).unwrap();
        let r = simulate(&road, &mut parked, &SimConfig::default(), false);
        assert_eq!(
            (r.outcome, r.reason.as_deref()),
            (Outcome::Fail, Some(reason::NOT_MOVING))
        );
        assert!((r.sim_time_s - 10.0).abs() < 0.1);
        assert!(r.trace.is_none());
    }

    #[test]
    fn a_non_finite_command_is_an_error() {
        let mut broken = Scripted {
            control_hz: 20.0,
            act: |o| Command {
                steering_rad: if o.time_s > 1.0 { f64::NAN } else { 0.0 },
                throttle: 0.5,
                brake: 0.0,
            },
        };
        let road = Road::new(&[[0.0, 0.0], [0.0, 100.0], [0.0, 200.0]]).unwrap();
        let r = simulate(&road, &mut broken, &SimConfig::default(), false);
        assert_eq!(
            (r.outcome, r.reason.as_deref()),
            (Outcome::Error, Some(reason::NON_FINITE_COMMAND))
        );
        assert!(r.sim_time_s > 1.0 && r.sim_time_s < 1.1, "{r:?}");
        assert!(r.std_sa.is_finite() && r.max_bolp.is_finite());
    }

    #[test]
    fn steering_off_the_road_fails_out_of_lane() {
        let mut swerve = Scripted {
            control_hz: 20.0,
            act: |_| Command {
                steering_rad: -0.3,
                throttle: 0.5,
                brake: 0.0,
            },
        };
        let road = Road::new(&[[0.0, 0.0], [0.0, 100.0], [0.0, 200.0]]).unwrap();
        let r = simulate(&road, &mut swerve, &SimConfig::default(), false);
        assert_eq!(
            (r.outcome, r.reason.as_deref()),
            (Outcome::Fail, Some(reason::OUT_OF_LANE))
        );
        assert!(r.max_bolp > 0.85 && r.min_lane_distance_m < 0.0 && r.fitness_distance > 0.5);
    }
}
