//! The road problem with an external executor as the simulator: validity and roads are wogan's
//! (the competition's validator), driving is the executor's. Executors are started as needed, one
//! per worker, and reused; one that fails a road (ended, late, garbage, an answer out of range) is
//! killed, the road ends as `ERROR` with the reason and the tail of its stderr, and the next road
//! starts a new one. After too many failed roads in a row ([`FailureStreak`]) the run is stopped,
//! with every finished test written.

use super::executor_protocol::{parse_answer, Answer, Request, PROTOCOL, VERSION};
use crate::files::records::RoadExecution;
use crate::sut::failure_streak::FailureStreak;
use crate::sut::road_sut::RoadSut;
use child_process::{ChildProcess, Fault};
use road_sim::oob::sbst_side;
use road_sim::road::features::RoadFeatures;
use road_sim::sim::fitness_from_distance;
use road_sim::{FitnessKind, LaneExit, Outcome, Road, SimConfig, SimResult};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use wogan_core::{Execution, Sut};

/// How the executor is run.
#[derive(Debug, Clone, PartialEq)]
pub struct ExecutorSettings {
    /// The command, as typed after `cmd:` on the command line (never read from a file).
    pub command: String,
    /// Longest wait for one road's answer.
    pub timeout: Duration,
}

/// Roads from test vectors, driven by an executor.
pub struct ExecutorSut<'a> {
    /// Validity and the vector-to-road mapping (its driver is not used).
    pub roads: RoadSut<'a>,
    /// How roads are judged (tolerance, speed limit) and told to the executor.
    pub sim: SimConfig,
    /// What the search maximises (the lane distance only from executors that answer with it).
    pub fitness: FitnessKind,
    /// The executor's command and limits.
    pub settings: ExecutorSettings,
    /// Set by Ctrl-C, and by the executor giving up.
    pub stop: &'a AtomicBool,
    /// Failed roads in a row.
    pub streak: &'a FailureStreak,
    idle: Mutex<Vec<ChildProcess>>,
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
        Self {
            roads,
            sim,
            fitness,
            settings,
            stop,
            streak,
            idle: Mutex::new(Vec::new()),
            roads_sent: AtomicUsize::new(0),
        }
    }

    fn hello(&self) -> Request<'static> {
        Request::Hello {
            protocol: PROTOCOL,
            version: VERSION,
            units: "metres, seconds",
            map_size_m: self.roads.roads.map_size_m,
            oob_tolerance: self.sim.oob_tolerance,
            speed_limit_kmh: self.sim.speed_limit_kmh,
        }
    }

    /// Drives `road_points` with an idle executor or a new one: its checked answer, or why there
    /// is none (`None`: the run is being stopped). An executor that failed is killed, not reused.
    fn ask(&self, id: usize, road_points: &[road_sim::Point]) -> Result<Answer, Option<String>> {
        let idle = self.idle.lock().unwrap_or_else(|p| p.into_inner()).pop();
        let mut process = match idle {
            Some(process) => process,
            None => ChildProcess::start(&self.settings.command, &self.hello(), &Request::Bye)
                .map_err(|fault| Some(format!("road {id}: the executor: {fault}")))?,
        };
        let request = Request::Road { id, road_points };
        let answered = process.answer(
            &request,
            id as u64,
            self.settings.timeout,
            self.stop,
            |line, answered| {
                let needs_lane_distance = self.fitness == FitnessKind::Distance;
                parse_answer(
                    line,
                    id as u64,
                    answered,
                    self.sim.oob_tolerance,
                    needs_lane_distance,
                )
            },
        );
        match answered {
            Ok(Ok(answer)) => {
                self.idle
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push(process);
                Ok(answer)
            }
            Err(Fault::Stopped) => Err(None),
            failed => {
                let problem = match failed {
                    Ok(Err(problem)) => problem.to_string(),
                    Err(fault) => fault.to_string(),
                    Ok(Ok(_)) => String::new(),
                };
                let stderr = process.stderr_tail();
                let mut reason = format!("road {id}: the executor: {problem}");
                if !stderr.is_empty() {
                    reason.push_str(&format!("; its stderr ended with:\n{stderr}"));
                }
                Err(Some(reason))
            }
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
