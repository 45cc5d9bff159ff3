//! What a simulation reports: the outcome, the lane monitor's figures and an optional trace.

use crate::oob::SbstSide;
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

impl Outcome {
    /// The name as records spell it (`PASS`, `FAIL`, `ERROR`).
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Pass => "PASS",
            Outcome::Fail => "FAIL",
            Outcome::Error => "ERROR",
        }
    }
}

/// Why a drive stopped before reaching the end of the road.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// BOLP exceeded the oob tolerance.
    OutOfLane,
    /// The car moved less than 1 m in 10 s of simulated time.
    NotMoving,
    /// The drive took longer than the road's time limit.
    Timeout,
    /// The physics state became non-finite.
    NonFinitePhysicsState,
    /// The driver asked for a non-finite steering, throttle or brake.
    NonFiniteCommand,
    /// The drive reached [`super::config::MAX_SIM_TIME_S`] simulated seconds without ending.
    SimTimeLimit,
    /// The caller's stop flag cut the drive short.
    Interrupted,
    /// The driver failed (a controller process ended, answered late or wrongly; a camera network
    /// answered NaN or failed to run): the result's `error` says how.
    DriverFailed,
}

impl StopReason {
    /// The name as records spell it (`out_of_lane`, ...).
    pub fn name(self) -> &'static str {
        match self {
            StopReason::OutOfLane => "out_of_lane",
            StopReason::NotMoving => "not_moving",
            StopReason::Timeout => "timeout",
            StopReason::NonFinitePhysicsState => "non_finite_physics_state",
            StopReason::NonFiniteCommand => "non_finite_command",
            StopReason::SimTimeLimit => "sim_time_limit",
            StopReason::Interrupted => "interrupted",
            StopReason::DriverFailed => "driver_failed",
        }
    }
}

/// One lane-monitor sample of the drive.
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
    /// The competition's `oob_distance`: half the lane width minus the distance from the car
    /// centre to the lane's centre line, metres (the per-sample value of `MEAN_LP`; absent, so
    /// NaN, in traces written before it was).
    #[serde(
        default = "crate::json_float::nan",
        deserialize_with = "crate::json_float::nan_for_null"
    )]
    pub oob_distance_m: f64,
    /// The driver's throttle command in force, `[0, 1]`.
    #[serde(default)]
    pub throttle: f64,
    /// The driver's brake command in force, `[0, 1]`.
    #[serde(default)]
    pub brake: f64,
}

/// Which edge of its lane the car crossed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LaneSide {
    /// The lane's left edge, the road's centre line (towards oncoming traffic).
    Left,
    /// The lane's right edge, the road's edge.
    Right,
}

impl LaneSide {
    /// The name as records spell it (`left`, `right`).
    pub fn name(self) -> &'static str {
        match self {
            LaneSide::Left => "left",
            LaneSide::Right => "right",
        }
    }
}

/// Where the car first left its lane: the first sample whose BOLP exceeded the tolerance (the
/// competition's first `is_oob` record).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LaneExit {
    /// Simulated time, seconds (NaN, written `null`, when an executor reports only the side).
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub t_s: f64,
    /// Car centre, metres (NaN, written `null`, when an executor reports only the side).
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub x: f64,
    /// Car centre, metres (NaN, written `null`, when an executor reports only the side).
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub y: f64,
    /// The edge the car crossed: the one its centre is nearer to (or beyond).
    pub side: LaneSide,
    /// The competition's label of the same exit (`OOBAnalyzer`: LEFT when the car centre is
    /// within 2 m of its own resampling of the centre line, else RIGHT, so leaving past the far
    /// edge counts RIGHT); `None` when that analysis cannot resample the road (under 4 points).
    pub sbst_side: Option<SbstSide>,
}

impl LaneExit {
    /// Where the car left, `[x, y]` metres; `None` when the exit has no place (an executor's
    /// answer gives only the side).
    pub fn place(&self) -> Option<[f64; 2]> {
        (self.x.is_finite() && self.y.is_finite()).then_some([self.x, self.y])
    }
}

/// Result of one drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimResult {
    /// PASS, FAIL or ERROR.
    pub outcome: Outcome,
    /// Why the drive did not pass.
    pub reason: Option<StopReason>,
    /// Largest BOLP over the samples, `[0, 1]`.
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub max_bolp: f64,
    /// Smallest signed distance of the car centre to the lane's edges over the samples, metres
    /// (2 when always centred, negative when the centre left the lane).
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub min_lane_distance_m: f64,
    /// Fitness from the lane distance, `[0, 1]`: `clamp((2 - min_lane_distance_m) / 2.85, 0, 1)`,
    /// 0 when the car stays centred, 1 when its centre got 0.85 m outside the lane.
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub fitness_distance: f64,
    /// Simulated time, seconds.
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub sim_time_s: f64,
    /// Wall time of the simulation, milliseconds.
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub execution_ms: f64,
    /// The competition's MAX_CURV of the road, 1/m.
    #[serde(rename = "MAX_CURV")]
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub max_curv: f64,
    /// The competition's DIR_COV of the road.
    #[serde(rename = "DIR_COV")]
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub dir_cov: f64,
    /// Population standard deviation of the front wheels' steering angle, degrees.
    #[serde(rename = "STD_SA")]
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub std_sa: f64,
    /// Mean over the samples of `2 - distance from the car centre to the right lane's centre`.
    #[serde(rename = "MEAN_LP")]
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub mean_lp: f64,
    /// Largest such value.
    #[serde(rename = "MAX_LP")]
    #[serde(deserialize_with = "crate::json_float::nan_for_null")]
    pub max_lp: f64,
    /// Where the car first left its lane, when it did (absent in records written before it was).
    #[serde(default)]
    pub oob: Option<LaneExit>,
    /// Why the drive ended in `ERROR` when something outside wogan failed (a controller process,
    /// an executor): what happened and the last lines it wrote to stderr.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub error: Option<String>,
    /// The samples, when a trace was asked for.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub trace: Option<Vec<Sample>>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_as_records_spell_them() {
        let spelled = |v: serde_json::Value| v.as_str().unwrap_or_default().to_owned();
        for outcome in [Outcome::Pass, Outcome::Fail, Outcome::Error] {
            assert_eq!(
                spelled(serde_json::to_value(outcome).unwrap()),
                outcome.name()
            );
        }
        for reason in [
            StopReason::OutOfLane,
            StopReason::NotMoving,
            StopReason::Timeout,
            StopReason::NonFinitePhysicsState,
            StopReason::NonFiniteCommand,
            StopReason::SimTimeLimit,
            StopReason::Interrupted,
            StopReason::DriverFailed,
        ] {
            assert_eq!(
                spelled(serde_json::to_value(reason).unwrap()),
                reason.name()
            );
        }
        for side in [LaneSide::Left, LaneSide::Right] {
            assert_eq!(spelled(serde_json::to_value(side).unwrap()), side.name());
        }
    }

    #[test]
    fn outcome_serialises_upper_case() {
        assert_eq!(serde_json::to_string(&Outcome::Pass).unwrap(), "\"PASS\"");
        assert_eq!(serde_json::to_string(&Outcome::Error).unwrap(), "\"ERROR\"");
    }

    #[test]
    fn stop_reasons_serialise_as_before() {
        let names = [
            (StopReason::OutOfLane, "out_of_lane"),
            (StopReason::NotMoving, "not_moving"),
            (StopReason::Timeout, "timeout"),
            (
                StopReason::NonFinitePhysicsState,
                "non_finite_physics_state",
            ),
            (StopReason::NonFiniteCommand, "non_finite_command"),
            (StopReason::SimTimeLimit, "sim_time_limit"),
            (StopReason::Interrupted, "interrupted"),
        ];
        for (reason, name) in names {
            assert_eq!(
                serde_json::to_string(&reason).unwrap(),
                format!("\"{name}\"")
            );
        }
    }

    #[test]
    fn a_result_serialises_with_the_competition_names() {
        let result = SimResult {
            outcome: Outcome::Fail,
            reason: Some(StopReason::OutOfLane),
            max_bolp: 0.9,
            min_lane_distance_m: -0.2,
            fitness_distance: 0.8,
            sim_time_s: 12.0,
            execution_ms: 3.0,
            max_curv: 0.05,
            dir_cov: 0.3,
            std_sa: 4.0,
            mean_lp: 1.5,
            max_lp: 2.0,
            oob: None,
            error: None,
            trace: None,
        };
        let json = serde_json::to_value(&result).unwrap();
        let mut keys: Vec<&str> = json
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        keys.sort_unstable();
        let mut expected = [
            "outcome",
            "reason",
            "max_bolp",
            "min_lane_distance_m",
            "fitness_distance",
            "sim_time_s",
            "execution_ms",
            "MAX_CURV",
            "DIR_COV",
            "STD_SA",
            "MEAN_LP",
            "MAX_LP",
            "oob",
        ];
        expected.sort_unstable();
        assert_eq!(keys, expected);
        assert_eq!(json["reason"], "out_of_lane");
        let back: SimResult = serde_json::from_value(json).unwrap();
        assert_eq!(back, result);
    }

    #[test]
    fn an_exit_without_a_place_reads_back() {
        // What a run driven by an executor writes: the side, and no place (NaN as null).
        let text = r#"{"t_s":null,"x":null,"y":null,"side":"left","sbst_side":null}"#;
        let exit: LaneExit = serde_json::from_str(text).unwrap();
        assert_eq!(exit.side, LaneSide::Left);
        assert!(exit.t_s.is_nan() && exit.x.is_nan() && exit.y.is_nan());
        assert_eq!(exit.place(), None);
        let placed = LaneExit {
            x: 1.0,
            y: 2.0,
            ..exit
        };
        assert_eq!(placed.place(), Some([1.0, 2.0]));
    }
}
