//! What a simulation reports: the outcome, the oracle's figures and an optional trace.

use serde::{Deserialize, Serialize};

/// Verdict of one drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Outcome {
    /// The car reached the end of the road in its lane.
    Pass,
    /// The car left its lane, stopped, or ran out of time.
    Fail,
    /// The simulation itself broke down.
    Error,
}

/// Why a drive did not pass.
pub mod reason {
    /// BOLP exceeded the oob tolerance.
    pub const OUT_OF_LANE: &str = "out_of_lane";
    /// The car moved less than 1 m in 10 s of simulated time.
    pub const NOT_MOVING: &str = "not_moving";
    /// The drive took longer than the road's time limit.
    pub const TIMEOUT: &str = "timeout";
    /// The physics state became non-finite.
    pub const NON_FINITE: &str = "non_finite_physics_state";
    /// The driver asked for a non-finite steering, throttle or brake.
    pub const NON_FINITE_COMMAND: &str = "non_finite_command";
}

/// One oracle sample of the drive.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Sample {
    /// Simulated time, seconds.
    pub t: f64,
    /// Car centre, metres.
    pub x: f64,
    /// Car centre, metres.
    pub y: f64,
    /// Heading, radians counter-clockwise from east.
    pub heading: f64,
    /// Speed, km/h.
    pub speed_kmh: f64,
    /// Steering angle of the front wheels, degrees, positive left.
    pub steering_deg: f64,
    /// Share of the car's footprint outside the right lane.
    pub bolp: f64,
    /// Signed distance from the car centre to the lane's left edge (the road's centre line),
    /// metres, positive inside the lane.
    pub dist_left_m: f64,
    /// Signed distance from the car centre to the lane's right edge (the road's right edge),
    /// metres, positive inside the lane.
    pub dist_right_m: f64,
}

/// Result of one drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimResult {
    /// PASS, FAIL or ERROR.
    pub outcome: Outcome,
    /// Why the drive did not pass (`out_of_lane`, `not_moving`, `timeout`, or an error).
    pub reason: Option<String>,
    /// Largest BOLP over the samples, `[0, 1]`.
    pub max_bolp: f64,
    /// Smallest signed distance of the car centre to the lane's edges over the samples, metres
    /// (2 when always centred, negative when the centre left the lane).
    pub min_lane_distance_m: f64,
    /// Fitness from the lane distance, `[0, 1]`: `clamp((2 - min_lane_distance_m) / 2.85, 0, 1)`,
    /// 0 when the car stays centred, 1 when its centre got 0.85 m outside the lane.
    pub fitness_distance: f64,
    /// Simulated time, seconds.
    pub sim_time_s: f64,
    /// Wall time of the simulation, milliseconds.
    pub execution_ms: f64,
    /// The competition's MAX_CURV of the road, 1/m.
    #[serde(rename = "MAX_CURV")]
    pub max_curv: f64,
    /// The competition's DIR_COV of the road.
    #[serde(rename = "DIR_COV")]
    pub dir_cov: f64,
    /// Population standard deviation of the front wheels' steering angle, degrees.
    #[serde(rename = "STD_SA")]
    pub std_sa: f64,
    /// Mean over the samples of `2 - distance from the car centre to the right lane's centre`.
    #[serde(rename = "MEAN_LP")]
    pub mean_lp: f64,
    /// Largest such value.
    #[serde(rename = "MAX_LP")]
    pub max_lp: f64,
    /// The samples, when a trace was asked for.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub trace: Option<Vec<Sample>>,
}

/// Lane distance (metres, signed, positive inside) at which `fitness_distance` reaches 1.
pub const FITNESS_FAILURE_DISTANCE_M: f64 = -0.85;
/// Lane distance of a centred car.
pub const CENTRED_DISTANCE_M: f64 = 2.0;

/// The lane-distance fitness of a minimum lane distance: linear from 0 (centred, 2 m) to 1
/// (0.85 m outside the lane, where a 1.9 m wide car's BOLP reaches 0.95), clamped. The WOGAN
/// authors scaled their BeamNG distance the same way: to reach 1 where BOLP reaches 0.95.
pub fn fitness_from_distance(min_lane_distance_m: f64) -> f64 {
    if min_lane_distance_m.is_nan() {
        return 1.0;
    }
    ((CENTRED_DISTANCE_M - min_lane_distance_m) / (CENTRED_DISTANCE_M - FITNESS_FAILURE_DISTANCE_M))
        .clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcome_serialises_upper_case() {
        assert_eq!(serde_json::to_string(&Outcome::Pass).unwrap(), "\"PASS\"");
        assert_eq!(serde_json::to_string(&Outcome::Error).unwrap(), "\"ERROR\"");
    }

    #[test]
    fn fitness_scale() {
        assert_eq!(fitness_from_distance(2.0), 0.0);
        assert_eq!(fitness_from_distance(2.5), 0.0);
        assert!((fitness_from_distance(-0.85) - 1.0).abs() < 1e-12);
        assert!((fitness_from_distance(0.575) - 0.5).abs() < 1e-12);
        assert_eq!(fitness_from_distance(-5.0), 1.0);
    }
}
