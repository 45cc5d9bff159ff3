//! The road problem with an external executor as the simulator: validity and roads are wogan's
//! (the competition's validator), driving is the executor's ([`ExecutorPool`]: executors started
//! as roads come, each answering `hello` before its first road and taking as many roads at once
//! as it announced). A road whose executor failed (ended, late, garbage, an answer out of range)
//! ends as `ERROR` with the reason and the tail of its stderr. After too many failed roads in a row
//! ([`FailureStreak`]) the run is stopped, with every finished test written.

use super::executor_pool::{ExecutorPool, ExecutorSettings, HelloSettings, NoAnswer};
use super::executor_protocol::{parse_answer, Answer, ExecutorDescription};
use crate::files::records::RoadExecution;
use crate::sut::failure_streak::FailureStreak;
use crate::sut::road_sut::RoadSut;
use road_sim::oob::sbst_side;
use road_sim::road::features::RoadFeatures;
use road_sim::sim::fitness_from_distance;
use road_sim::{FitnessKind, LaneExit, Outcome, Road, SimConfig, SimResult};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;
use wogan_core::{Execution, Sut};

/// Roads from test vectors, driven by an executor.
pub struct ExecutorSut<'a> {
    /// Validity and the vector-to-road mapping (its driver is not used).
    pub roads: RoadSut<'a>,
    /// How roads are judged (tolerance, speed limit) and told to the executor.
    pub sim: SimConfig,
    /// What the search maximises (the lane distance only from executors that answer with it).
    pub fitness: FitnessKind,
    /// Set by Ctrl-C, and by the executor giving up.
    pub stop: &'a AtomicBool,
    /// Failed roads in a row.
    pub streak: &'a FailureStreak,
    executors: ExecutorPool,
    roads_sent: AtomicUsize,
}

impl<'a> ExecutorSut<'a> {
    /// A SUT that starts executors as roads come.
    pub fn new(
        roads: RoadSut<'a>,
        sim: SimConfig,
        fitness: FitnessKind,
        settings: ExecutorSettings,
        streak: &'a FailureStreak,
        stop: &'a AtomicBool,
    ) -> Self {
        let hello = HelloSettings {
            map_size_m: roads.roads.map_size_m,
            oob_tolerance: sim.oob_tolerance,
            speed_limit_kmh: sim.speed_limit_kmh,
        };
        Self {
            roads,
            sim,
            fitness,
            stop,
            streak,
            executors: ExecutorPool::new(settings, hello),
            roads_sent: AtomicUsize::new(0),
        }
    }

    /// What the executor said of itself in its reply to `hello`, and how many roads it took at
    /// once, once one has answered.
    pub fn description(&self) -> Option<(ExecutorDescription, usize)> {
        self.executors.description()
    }

    /// Drives `road_points` with an executor: its checked answer, or why there is none (`None`:
    /// the run is being stopped).
    fn ask(&self, id: usize, road_points: &[road_sim::Point]) -> Result<Answer, Option<String>> {
        let needs_lane_distance = self.fitness == FitnessKind::Distance;
        let tolerance = self.sim.oob_tolerance;
        let read = |line: &str| parse_answer(line, id as u64, None, tolerance, needs_lane_distance);
        match self
            .executors
            .drive(id as u64, road_points, self.stop, read)
        {
            Ok(answer) => Ok(answer),
            Err(NoAnswer::Stopped) => Err(None),
            Err(NoAnswer::Failed(reason)) => Err(Some(reason)),
        }
    }
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

impl Sut for ExecutorSut<'_> {
    type Output = RoadExecution;

    fn dim(&self) -> usize {
        self.roads.dim()
    }

    fn is_valid(&self, test: &[f32]) -> bool {
        self.roads.is_valid(test)
    }

    fn execute(&self, test: &[f32]) -> Option<Execution<RoadExecution>> {
        let curvature = self.roads.curvature(test);
        let road_points = self.roads.roads.points(&curvature);
        // The search executes valid tests only, whose points always interpolate.
        let road = Road::new(&road_points).ok()?;
        let id = self.roads_sent.fetch_add(1, Ordering::SeqCst) + 1;
        let t0 = Instant::now();
        let asked = self.ask(id, &road_points);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        let result = match asked {
            Ok(answer) => {
                self.streak.passed();
                let mut result = result_of(
                    answer.outcome,
                    answer.max_bolp,
                    answer.sim_time_s,
                    &road,
                    ms,
                );
                if let Some(distance) = answer.min_lane_distance_m {
                    result.min_lane_distance_m = distance;
                    result.fitness_distance = fitness_from_distance(distance);
                }
                // Where the car left is the executor's to know: the side, and the place when it
                // says (the exit ends the drive, so its time is the drive's).
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
                        sbst_side: place.and_then(|p| sbst_side(&road_points, p)),
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
            Err(None) => return None,
            Err(Some(reason)) => {
                self.streak.failed("the executor", &reason, self.stop);
                let mut result = result_of(Outcome::Error, f64::NAN, 0.0, &road, ms);
                result.error = Some(reason);
                result
            }
        };
        Some(Execution {
            fitness: self.fitness.of(&result, &self.sim),
            execution_time_s: result.sim_time_s,
            output: RoadExecution {
                curvature,
                road_points,
                interpolated: road.interpolated,
                result,
            },
        })
    }
}
