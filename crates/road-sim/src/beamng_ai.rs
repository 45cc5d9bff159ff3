//! `beamng-ai-proxy`: a lane keeper in the spirit of BeamNG.AI as the SBST competition used it
//! ("drive in lane", aggression 0.7, a speed limit).
//!
//! Steering is pure pursuit on the right lane's centre line: the front wheels are turned so that
//! the rear axle would follow a circle through a target point one look-ahead distance ahead on the
//! lane centre (look-ahead = base + time x speed). On a bend the circle through the target lies
//! inside the lane's centre, so the car cuts corners, more so at speed; the steering rate limit
//! and the speed planner's optimism (aggression) make it run wide out of sharp bends.
//!
//! Speed is planned once per road: the curvature of the lane centre (over a 3 m chord on each
//! side) gives a corner speed `sqrt(a_lat / |k|)` (capped by the speed limit), with
//! `a_lat = g * (lateral_grip_base + lateral_grip_per_aggression * aggression)`, and a backward
//! pass lets the car brake at `g * (brake_base + brake_per_aggression * aggression)` in time for
//! each corner. A proportional controller turns the speed error into throttle or brake.

use crate::driver::{pedals, Driver, Observation};
use crate::polyline;
use crate::road::Road;
use crate::settings_check::{all_non_negative, all_positive};
use crate::vehicle::{Command, VehicleParams};
use crate::Point;
use serde::{Deserialize, Serialize};

const G: f64 = 9.81;

/// Tuning of the `beamng-ai-proxy` driver.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BeamNgAiParams {
    /// BeamNG.AI's aggression, `[0, 1]`: scales the planned lateral and braking accelerations.
    pub aggression: f64,
    /// Planned lateral acceleration at aggression 0, in g.
    pub lateral_grip_base: f64,
    /// Extra planned lateral acceleration per unit of aggression, in g.
    pub lateral_grip_per_aggression: f64,
    /// Planned braking deceleration at aggression 0, in g.
    pub brake_base: f64,
    /// Extra planned braking deceleration per unit of aggression, in g.
    pub brake_per_aggression: f64,
    /// Look-ahead distance at standstill, metres.
    pub lookahead_base_m: f64,
    /// Look-ahead added per metre per second of speed, seconds.
    pub lookahead_time_s: f64,
    /// Multiplier of the pure-pursuit steering angle.
    pub steering_gain: f64,
    /// How far ahead of the car the speed plan is read, seconds of travel.
    pub speed_preview_s: f64,
    /// Throttle per metre per second of speed shortfall.
    pub throttle_gain: f64,
    /// Brake per metre per second of excess speed.
    pub brake_gain: f64,
    /// Excess speed tolerated before braking, metres per second.
    pub brake_deadband_mps: f64,
    /// Control rate, hertz.
    pub control_hz: f64,
}

impl Default for BeamNgAiParams {
    fn default() -> Self {
        Self {
            aggression: 0.7,
            lateral_grip_base: 0.3,
            lateral_grip_per_aggression: 1.0,
            brake_base: 0.3,
            brake_per_aggression: 0.4,
            lookahead_base_m: 6.25,
            lookahead_time_s: 0.8,
            steering_gain: 1.0,
            speed_preview_s: 0.3,
            throttle_gain: 0.5,
            brake_gain: 0.3,
            brake_deadband_mps: 0.5,
            control_hz: 30.0,
        }
    }
}

impl BeamNgAiParams {
    /// Names the first setting the driver cannot work with.
    pub fn validate(&self) -> Result<(), String> {
        let settings = [
            ("aggression", self.aggression),
            ("lateral_grip_base", self.lateral_grip_base),
            (
                "lateral_grip_per_aggression",
                self.lateral_grip_per_aggression,
            ),
            ("brake_base", self.brake_base),
            ("brake_per_aggression", self.brake_per_aggression),
            ("lookahead_base_m", self.lookahead_base_m),
            ("lookahead_time_s", self.lookahead_time_s),
            ("steering_gain", self.steering_gain),
            ("speed_preview_s", self.speed_preview_s),
            ("throttle_gain", self.throttle_gain),
            ("brake_gain", self.brake_gain),
            ("brake_deadband_mps", self.brake_deadband_mps),
        ];
        all_non_negative("beamng_ai.", &settings)?;
        all_positive("beamng_ai.", &[("control_hz", self.control_hz)])
    }
}

/// The `beamng-ai-proxy` driver.
#[derive(Debug, Clone, Default)]
pub struct BeamNgAiProxy {
    params: BeamNgAiParams,
    wheelbase_m: f64,
    cg_to_rear_m: f64,
    /// Right-lane centre line.
    lane: Vec<Point>,
    /// Arc length at each lane point, metres.
    arc_m: Vec<f64>,
    /// Planned speed at each lane point, metres per second.
    plan_mps: Vec<f64>,
    /// Segment of the lane the car was last projected on.
    segment: usize,
}

impl BeamNgAiProxy {
    /// A driver with these parameters (call [`Driver::reset`] before driving).
    pub fn new(params: BeamNgAiParams) -> Self {
        Self {
            params,
            ..Self::default()
        }
    }

    /// The driver's parameters.
    pub fn params(&self) -> &BeamNgAiParams {
        &self.params
    }

    /// The planned speed along the lane centre (one value per lane point), metres per second.
    pub fn speed_plan(&self) -> &[f64] {
        &self.plan_mps
    }

    /// Arc length of the car's projection on the lane centre (searched near the last one).
    fn locate(&mut self, position: Point) -> f64 {
        let window = (self.segment.saturating_sub(3), self.segment + 25);
        let projection = polyline::project(position, &self.lane, Some(window));
        self.segment = projection.segment;
        let i = projection.segment;
        self.arc_m[i] + projection.along * (self.arc_m[i + 1] - self.arc_m[i])
    }

    /// The point at arc length `s` on the lane centre (extrapolated past the ends), and the index
    /// of the lane point at or before it.
    fn point_at(&self, s: f64, from: usize) -> (Point, usize) {
        let last = self.lane.len() - 1;
        let mut i = from.min(last - 1);
        while i + 1 < last && self.arc_m[i + 1] < s {
            i += 1;
        }
        let (a, b) = (self.lane[i], self.lane[i + 1]);
        let t = (s - self.arc_m[i]) / (self.arc_m[i + 1] - self.arc_m[i]);
        ([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])], i)
    }
}

/// Signed curvature (1/m, positive left) of the circle through `a`, `b`, `c`.
fn signed_curvature(a: Point, b: Point, c: Point) -> f64 {
    let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let ab = (b[0] - a[0]).hypot(b[1] - a[1]);
    let bc = (c[0] - b[0]).hypot(c[1] - b[1]);
    let ca = (a[0] - c[0]).hypot(a[1] - c[1]);
    let denominator = ab * bc * ca;
    if denominator > 0.0 {
        2.0 * cross / denominator
    } else {
        0.0
    }
}

impl Driver for BeamNgAiProxy {
    fn name(&self) -> &'static str {
        "beamng-ai-proxy"
    }

    fn control_hz(&self) -> f64 {
        self.params.control_hz
    }

    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64) {
        let p = self.params;
        self.wheelbase_m = vehicle.wheelbase_m();
        self.cg_to_rear_m = vehicle.cg_to_rear_axle_m;
        self.lane = road.right_lane_centre();
        self.segment = 0;
        let n = self.lane.len();
        self.arc_m.clear();
        self.arc_m.push(0.0);
        for w in self.lane.windows(2) {
            let last = *self.arc_m.last().expect("not empty");
            self.arc_m
                .push(last + (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]));
        }
        let a_lat = G * (p.lateral_grip_base + p.lateral_grip_per_aggression * p.aggression);
        let a_brake = G * (p.brake_base + p.brake_per_aggression * p.aggression);
        const CHORD: usize = 3;
        self.plan_mps = (0..n)
            .map(|i| {
                let (a, c) = (i.saturating_sub(CHORD), (i + CHORD).min(n - 1));
                let k = if c > a + 1 {
                    signed_curvature(self.lane[a], self.lane[(a + c) / 2], self.lane[c]).abs()
                } else {
                    0.0
                };
                if k > 0.0 {
                    (a_lat / k).sqrt().min(speed_limit_mps)
                } else {
                    speed_limit_mps
                }
            })
            .collect();
        for i in (0..n.saturating_sub(1)).rev() {
            let reachable = (self.plan_mps[i + 1].powi(2)
                + 2.0 * a_brake * (self.arc_m[i + 1] - self.arc_m[i]))
                .sqrt();
            self.plan_mps[i] = self.plan_mps[i].min(reachable);
        }
    }

    fn act(&mut self, observation: &Observation<'_>) -> Command {
        let p = self.params;
        let car = observation.car;
        let speed = car.speed_mps;
        let s = self.locate(car.position);
        // Speed: read the plan a little ahead and follow it.
        let (_, plan_index) = self.point_at(s + speed * p.speed_preview_s, self.segment);
        let target_speed = self.plan_mps[plan_index + 1].min(self.plan_mps[plan_index]);
        let (throttle, brake) = pedals(
            target_speed - speed,
            p.throttle_gain,
            p.brake_gain,
            p.brake_deadband_mps,
        );
        // Steering: pure pursuit from the rear axle.
        let (sin_h, cos_h) = car.heading_rad.sin_cos();
        let rear = [
            car.position[0] - self.cg_to_rear_m * cos_h,
            car.position[1] - self.cg_to_rear_m * sin_h,
        ];
        let lookahead = p.lookahead_base_m + p.lookahead_time_s * speed;
        let (target, _) = self.point_at(s + lookahead, self.segment);
        let (dx, dy) = (target[0] - rear[0], target[1] - rear[1]);
        let forward = dx * cos_h + dy * sin_h;
        let left = -dx * sin_h + dy * cos_h;
        let alpha = left.atan2(forward);
        let distance = dx.hypot(dy).max(1.0);
        let steering = p.steering_gain * (2.0 * self.wheelbase_m * alpha.sin() / distance).atan();
        Command {
            steering_rad: steering,
            throttle,
            brake,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curvature_of_a_circle() {
        let r = 20.0_f64;
        let at = |a: f64| [r * a.cos(), r * a.sin()];
        assert!((signed_curvature(at(0.0), at(0.1), at(0.2)) - 1.0 / r).abs() < 1e-9);
        assert!((signed_curvature(at(0.2), at(0.1), at(0.0)) + 1.0 / r).abs() < 1e-9);
    }

    #[test]
    fn plans_slower_speed_for_a_sharp_bend_and_brakes_before_it() {
        let mut points = vec![[100.0, 10.0], [100.0, 40.0], [100.0, 60.0]];
        let (cx, cy, r) = (80.0, 60.0, 20.0);
        for k in 1..=6 {
            let a = k as f64 * std::f64::consts::PI / 12.0;
            points.push([cx + r * a.cos(), cy + r * a.sin()]);
        }
        let road = Road::new(&points).unwrap();
        let mut driver = BeamNgAiProxy::new(BeamNgAiParams::default());
        let limit = 70.0 / 3.6;
        driver.reset(&road, &VehicleParams::default(), limit);
        let plan = driver.speed_plan();
        assert!((plan[0] - limit).abs() < 1e-9);
        let min = plan.iter().cloned().fold(f64::INFINITY, f64::min);
        // Lane radius 22 m, planned at 1.0 g: about 14.7 m/s (a little less over the chord).
        assert!(min > 12.5 && min < 15.0, "min {min}");
        let first_slow = plan.iter().position(|&v| v < limit - 0.1).unwrap();
        assert!(first_slow > 5 && first_slow < 45, "{first_slow}");
    }
}
