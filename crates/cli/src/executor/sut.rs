//! The road problem with an external executor as the simulator: validity and roads are wogan's
//! (the competition's validator), driving is the executor's. Executors are started as needed, one
//! per worker, and reused; one that fails a road (ended, late, garbage, an answer out of range) is
//! killed, the road ends as `ERROR` with the reason and the tail of its stderr, and the next road
//! starts a new one. After `max_consecutive_errors` failed roads in a row the executor gives up:
//! the run is stopped, with every finished test written.

use super::protocol::{parse_answer, Answer, Request, PROTOCOL, VERSION};
use crate::records::RoadExecution;
use crate::road_sut::RoadSut;
use road_sim::child_process::{ChildProcess, Fault};
use road_sim::road::features::RoadFeatures;
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
    /// Failed roads in a row after which the run stops.
    pub max_consecutive_errors: usize,
}

/// Roads from test vectors, driven by an executor.
pub struct ExecutorSut<'a> {
    /// Validity and the vector-to-road mapping (its driver is not used).
    pub roads: RoadSut<'a>,
    /// How roads are judged (tolerance, speed limit) and told to the executor.
    pub sim: SimConfig,
    /// What the search maximises (BOLP-based).
    pub fitness: FitnessKind,
    /// The executor's command and limits.
    pub settings: ExecutorSettings,
    /// Set by Ctrl-C, and by the executor giving up.
    pub stop: &'a AtomicBool,
    idle: Mutex<Vec<ChildProcess>>,
    consecutive_errors: AtomicUsize,
    roads_sent: AtomicUsize,
    gave_up: Mutex<Option<String>>,
}

impl<'a> ExecutorSut<'a> {
    /// A SUT that starts executors as roads come.
    pub fn new(
        roads: RoadSut<'a>,
        sim: SimConfig,
        fitness: FitnessKind,
        settings: ExecutorSettings,
        stop: &'a AtomicBool,
    ) -> Self {
        Self {
            roads,
            sim,
            fitness,
            settings,
            stop,
            idle: Mutex::new(Vec::new()),
            consecutive_errors: AtomicUsize::new(0),
            roads_sent: AtomicUsize::new(0),
            gave_up: Mutex::new(None),
        }
    }

    /// Why the executor gave up and stopped the run, if it did.
    pub fn gave_up(&self) -> Option<String> {
        self.gave_up
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
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
        let answered = process
            .answer(&request, self.settings.timeout, self.stop)
            .map(|line| parse_answer(&line, self.sim.oob_tolerance));
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
                    Ok(Err(problem)) => problem,
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

    /// Counts a failed road; gives up (and stops the run) after too many in a row.
    fn failed(&self, reason: &str) {
        let in_a_row = self.consecutive_errors.fetch_add(1, Ordering::SeqCst) + 1;
        if in_a_row >= self.settings.max_consecutive_errors {
            let mut gave_up = self.gave_up.lock().unwrap_or_else(|p| p.into_inner());
            gave_up.get_or_insert_with(|| {
                format!("the executor failed {in_a_row} roads in a row; the last: {reason}")
            });
            self.stop.store(true, Ordering::SeqCst);
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
        let (result, error) = match asked {
            Ok(answer) => {
                self.consecutive_errors.store(0, Ordering::SeqCst);
                let mut result = result_of(
                    answer.outcome,
                    answer.max_bolp,
                    answer.sim_time_s,
                    &road,
                    ms,
                );
                // The side without a place: where the car left is the executor's to know.
                result.oob = answer.oob_side.map(|side| LaneExit {
                    t_s: f64::NAN,
                    x: f64::NAN,
                    y: f64::NAN,
                    side,
                    sbst_side: None,
                });
                (result, None)
            }
            Err(None) => return None,
            Err(Some(reason)) => {
                self.failed(&reason);
                (
                    result_of(Outcome::Error, f64::NAN, 0.0, &road, ms),
                    Some(reason),
                )
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
                error,
            },
        })
    }
}
