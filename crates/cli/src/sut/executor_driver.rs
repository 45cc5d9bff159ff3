//! A road driven by an external executor: the road sent to one of the run's executors
//! ([`ExecutorPool`]), its answer checked and read as a [`SimResult`] with NaN for what an
//! executor does not report. What `wogan run`'s search, `replay` and `simulate` share when
//! `--executor` drives. A road whose executor failed (ended, late, garbage, an answer out of
//! range) ends as `ERROR` with the reason and the tail of its stderr; after too many failed roads
//! in a row ([`FailureStreak`]) the command is stopped.

use super::executor_pool::{ExecutorPool, ExecutorSettings, HelloSettings, NoAnswer};
use super::executor_protocol::{parse_answer, Answer, ExecutorDescription};
use crate::sut::failure_streak::FailureStreak;
use road_sim::oob::sbst_side;
use road_sim::road::features::RoadFeatures;
use road_sim::sim::fitness_from_distance;
use road_sim::{LaneExit, Outcome, Road, SimResult};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Drives roads with executors started from one command.
pub struct ExecutorDriver<'a> {
    /// Told to every executor in `hello`; the tolerance also judges answers without an outcome.
    pub hello: HelloSettings,
    /// An answer without `min_lane_distance_m` is no answer (the search climbs the distance).
    pub needs_lane_distance: bool,
    /// Set by Ctrl-C, and by the executor giving up.
    pub stop: &'a AtomicBool,
    /// Failed roads in a row.
    pub streak: &'a FailureStreak,
    executors: ExecutorPool,
}

impl<'a> ExecutorDriver<'a> {
    /// A driver that starts executors with `settings` as roads come.
    pub fn new(
        settings: ExecutorSettings,
        hello: HelloSettings,
        needs_lane_distance: bool,
        streak: &'a FailureStreak,
        stop: &'a AtomicBool,
    ) -> Self {
        Self {
            hello,
            needs_lane_distance,
            stop,
            streak,
            executors: ExecutorPool::new(settings, hello),
        }
    }

    /// Starts the first executor and waits for its reply to `hello`, so that what it says of
    /// itself is known before anything is written; or why it could not be started.
    pub fn start(&self) -> Result<(), String> {
        match self.executors.start_first(self.stop) {
            Ok(()) => Ok(()),
            Err(NoAnswer::Stopped) => Err("stopped before the executor answered hello".into()),
            Err(NoAnswer::Failed(reason)) => Err(reason),
        }
    }

    /// What the executor said of itself in its reply to `hello`, and how many roads it took at
    /// once, once one has answered.
    pub fn description(&self) -> Option<(ExecutorDescription, usize)> {
        self.executors.description()
    }

    /// Drives `road` (whose control points are `road_points`) as road `id`: the drive as the
    /// executor reported it, an `ERROR` with the reason when it failed, or `None` when the
    /// command is being stopped. `id` must be unique among the roads in flight.
    pub fn drive(
        &self,
        id: u64,
        road_points: &[road_sim::Point],
        road: &Road,
    ) -> Option<SimResult> {
        let t0 = Instant::now();
        let tolerance = self.hello.oob_tolerance;
        let needs_lane_distance = self.needs_lane_distance;
        let read = |line: &str| parse_answer(line, id, None, tolerance, needs_lane_distance);
        let asked = self.executors.drive(id, road_points, self.stop, read);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        match asked {
            Ok(answer) => {
                self.streak.passed();
                Some(answered(id, answer, road_points, road, ms))
            }
            Err(NoAnswer::Stopped) => None,
            Err(NoAnswer::Failed(reason)) => {
                self.streak.failed("the executor", &reason, self.stop);
                let mut result = result_of(Outcome::Error, f64::NAN, 0.0, road, ms);
                result.error = Some(reason);
                Some(result)
            }
        }
    }
}

/// The drive an executor's checked answer to road `id` reports.
fn answered(
    id: u64,
    answer: Answer,
    road_points: &[road_sim::Point],
    road: &Road,
    ms: f64,
) -> SimResult {
    let mut result = result_of(answer.outcome, answer.max_bolp, answer.sim_time_s, road, ms);
    if let Some(distance) = answer.min_lane_distance_m {
        result.min_lane_distance_m = distance;
        result.fitness_distance = fitness_from_distance(distance);
    }
    // Where the car left is the executor's to know: the side, and the place when it says (the
    // exit ends the drive, so its time is the drive's).
    result.oob = answer.oob_side.map(|side| {
        let place = answer.oob_point;
        let [x, y] = place.unwrap_or([f64::NAN, f64::NAN]);
        LaneExit {
            t_s: if place.is_some() {
                answer.sim_time_s
            } else {
                f64::NAN
            },
            x,
            y,
            side,
            sbst_side: place.and_then(|p| sbst_side(road_points, p)),
        }
    });
    // An executor's own ERROR keeps its reason, as wogan's own failed drives do.
    if answer.outcome == Outcome::Error {
        result.error = answer
            .error
            .map(|error| format!("road {id}: the executor: {error}"));
    }
    result
}

/// A drive as the executor reported it: its figures, and NaN for what it does not report.
fn result_of(outcome: Outcome, max_bolp: f64, sim_time_s: f64, road: &Road, ms: f64) -> SimResult {
    let features = RoadFeatures::of(&road.interpolated);
    SimResult {
        outcome,
        reason: None,
        max_bolp,
        min_lane_distance_m: f64::NAN,
        fitness_distance: f64::NAN,
        sim_time_s,
        execution_ms: ms,
        max_curv: features.max_curvature,
        dir_cov: features.direction_coverage,
        std_sa: f64::NAN,
        mean_lp: f64::NAN,
        max_lp: f64::NAN,
        oob: None,
        error: None,
        trace: None,
    }
}
