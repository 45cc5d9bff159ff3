//! One drive: a car in a fresh rapier world, a driver, and the lane monitor sampling it until the
//! car reaches the end of the road, leaves its lane, stops, runs out of time, or the physics
//! breaks. The episode defines what it drives with ([`Driver`]); the drivers we ship live in
//! [`crate::driver`].

use super::config::{SimConfig, MAX_SIM_TIME_S};
use super::fitness::{fitness_from_distance, CENTRED_DISTANCE_M};
use super::lane_monitor::LaneMonitor;
use super::outcome::{LaneExit, LaneSide, Outcome, Sample, SimResult, StopReason};
use super::vehicle::{CarState, Command, Vehicle, VehicleParams};
use crate::oob::sbst_side;
use crate::road::{Point, Road, RoadFeatures, LANE_WIDTH_M};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// What a driver is told at each of its control ticks.
#[derive(Debug, Clone, Copy)]
pub struct Observation<'a> {
    /// Simulated time since the start, seconds.
    pub time_s: f64,
    /// The car's pose, speed and steering.
    pub car: CarState,
    /// The road being driven.
    pub road: &'a Road,
}

/// A lane-keeping driver.
pub trait Driver {
    /// The driver's name, as the CLI's `--oracle` spells it.
    fn name(&self) -> &'static str;
    /// How often the driver acts, hertz (the simulation holds the last command in between).
    fn control_hz(&self) -> f64;
    /// Prepares for a drive on `road` with a car of `vehicle`'s build and a speed limit.
    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64);
    /// The command for the next control period. A driver that cannot give one (a controller
    /// process that failed) returns a non-finite command and says why in [`Driver::failure`].
    fn act(&mut self, observation: &Observation<'_>) -> Command;
    /// Why the driver failed, when it did; the drive then ends as `ERROR` with this reason.
    fn failure(&self) -> Option<String> {
        None
    }
}

/// Centre-line segments (about 1 m each) before the road's end within which the car must
/// project for the end to count as reached.
pub const END_SEGMENTS: usize = 25;

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

/// Drives `driver` on `road`; returns the verdict, the lane monitor's figures and, if `trace`, the
/// samples. When `stop` is given and set, the drive ends between two physics steps in ERROR
/// (`interrupted`).
pub fn simulate(
    road: &Road,
    driver: &mut dyn Driver,
    config: &SimConfig,
    trace: bool,
    stop: Option<&AtomicBool>,
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
    let mut lane_exit = None;
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
                let why = match driver.failure() {
                    Some(_) => StopReason::DriverFailed,
                    None => StopReason::NonFiniteCommand,
                };
                break (Outcome::Error, Some(why));
            }
        }
        if stop.is_some_and(|stop| stop.load(Ordering::Relaxed)) {
            break (Outcome::Error, Some(StopReason::Interrupted));
        }
        vehicle.step(&command);
        step += 1;
        if !vehicle.is_finite() {
            break (Outcome::Error, Some(StopReason::NonFinitePhysicsState));
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
                oob_distance_m: m.oob_distance_m,
                throttle: command.throttle.clamp(0.0, 1.0),
                brake: command.brake.clamp(0.0, 1.0),
            });
        }
        if m.bolp > config.oob_tolerance {
            let side = if m.dist_left_m < m.dist_right_m {
                LaneSide::Left
            } else {
                LaneSide::Right
            };
            lane_exit = Some(LaneExit {
                t_s: t,
                x: car.position[0],
                y: car.position[1],
                side,
                sbst_side: sbst_side(&road.road_points, car.position),
            });
            break (Outcome::Fail, Some(StopReason::OutOfLane));
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
            break (Outcome::Fail, Some(StopReason::NotMoving));
        }
        if t >= timeout_s {
            break (Outcome::Fail, Some(StopReason::Timeout));
        }
        if t >= MAX_SIM_TIME_S {
            break (Outcome::Error, Some(StopReason::SimTimeLimit));
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
        reason: why,
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
        oob: lane_exit,
        error: driver.failure(),
        trace: trace.then_some(samples),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let r = simulate(&road, &mut parked, &SimConfig::default(), false, None);
        assert_eq!(
            (r.outcome, r.reason),
            (Outcome::Fail, Some(StopReason::NotMoving))
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
        let r = simulate(&road, &mut broken, &SimConfig::default(), false, None);
        assert_eq!(
            (r.outcome, r.reason),
            (Outcome::Error, Some(StopReason::NonFiniteCommand))
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
        let r = simulate(&road, &mut swerve, &SimConfig::default(), false, None);
        assert_eq!(
            (r.outcome, r.reason),
            (Outcome::Fail, Some(StopReason::OutOfLane))
        );
        assert!(r.max_bolp > 0.85 && r.min_lane_distance_m < 0.0 && r.fitness_distance > 0.5);
    }

    #[test]
    fn a_stop_ends_the_drive_between_physics_steps() {
        let mut cruise = Scripted {
            control_hz: 20.0,
            act: |_| Command {
                steering_rad: 0.0,
                throttle: 0.3,
                brake: 0.0,
            },
        };
        let road = Road::new(&[[0.0, 0.0], [0.0, 100.0], [0.0, 200.0]]).unwrap();
        let stop = AtomicBool::new(true);
        let r = simulate(
            &road,
            &mut cruise,
            &SimConfig::default(),
            false,
            Some(&stop),
        );
        assert_eq!(
            (r.outcome, r.reason, r.sim_time_s),
            (Outcome::Error, Some(StopReason::Interrupted), 0.0)
        );
    }

    #[test]
    fn a_drive_never_outlasts_the_simulated_time_limit() {
        let mut parked = Scripted {
            control_hz: 1.0,
            act: |_| Command {
                brake: 1.0,
                ..Command::default()
            },
        };
        // A time limit beyond the cap and no not-moving rule, at the lowest physics rate.
        let config = SimConfig {
            physics_hz: 10.0,
            sample_hz: 1.0,
            timeout_base_s: MAX_SIM_TIME_S,
            not_moving_distance_m: 0.0,
            ..SimConfig::default()
        };
        config.validate().unwrap();
        let road = Road::new(&[[0.0, 0.0], [0.0, 100.0], [0.0, 200.0]]).unwrap();
        let r = simulate(&road, &mut parked, &config, false, None);
        assert_eq!(r.reason, Some(StopReason::SimTimeLimit), "{r:?}");
        assert_eq!(r.outcome, Outcome::Error);
        assert!(
            (r.sim_time_s - MAX_SIM_TIME_S).abs() < 1e-6,
            "{}",
            r.sim_time_s
        );
    }
}
