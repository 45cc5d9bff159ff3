//! The JSON-lines wire format: every record `wogan` writes, and reads back, as one serde type.
//!
//! Each line is one object tagged by `"type"`. `run` writes a header, then test and train records
//! as they happen, then a summary; `simulate` writes a result per road (and `--trace` files of road
//! and sample records); `validate` a verdict per road; both write an error record for a line that
//! holds no road; `train-driver` writes one driver record. `report` and `export` read run files
//! back through the same types, so a field is named, typed and documented once. The library's enums
//! travel as themselves (outcome, stop reason, validity reason, phase, algorithm, driver, fitness).
//!
//! Numbers round-trip exactly (serde_json's `float_roundtrip`). JSON has no NaN: serde_json writes
//! a non-finite number as `null`, which reads back as NaN. Fields added after a record was first
//! written are optional when read, so that older run files stay readable.

use crate::files::sbst_format::ExecutionRecord;
use driver_training::{CloningConfig, CloningReport};
use road_sim::road::Point;
use road_sim::{DriverKind, FitnessKind, LaneExit, Outcome, Reason, Sample, SimResult};
use serde::{Deserialize, Serialize};
#[cfg(doc)]
use wogan_core::Algorithm;
use wogan_core::{Event, Phase};

/// The version written in headers.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// One line of `wogan`'s output. `C` is the header's configuration: the resolved plan when
/// written, any JSON when read (older runs have older layouts).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Record<C = serde_json::Value> {
    /// What a run is: the first line of its file.
    Header(Header<C>),
    /// One executed test of a run.
    Test(TestRecord),
    /// One training round of WOGAN.
    Train(TrainRecord),
    /// The totals of a run: its last line.
    Summary(SummaryRecord),
    /// An input line that holds no road.
    Error(ErrorRecord),
    /// `simulate`'s answer for one road.
    Result(ResultRecord),
    /// `validate`'s answer for one road.
    Verdict(VerdictRecord),
    /// What `train-driver` trained and measured.
    Driver(DriverRecord),
    /// The first line of a regression suite file.
    Suite(SuiteHeader),
    /// One road of a regression suite.
    Road(SuiteRoad),
    /// `replay`'s answer for one saved road.
    Replay(ReplayRecord),
    /// A road `sample` drew from a saved generator.
    Sample(SampleRecord),
    /// `simulate`'s reply to the executor protocol's `hello`, when it serves as an executor.
    Hello(HelloRecord),
    /// A record of a kind this version does not know (skipped by readers).
    #[serde(other, skip_serializing)]
    Unknown,
}

impl Record {
    /// The record of one of the search's events: a test executed, or a training round.
    pub fn of_event(event: Event<RoadExecution>) -> Self {
        match event {
            Event::Test {
                id,
                phase,
                fitness,
                predicted_fitness,
                invalid_candidates,
                ranked_candidates,
                generation_ms,
                sbst_generation_ms,
                beyond_budget,
                output,
                ..
            } => Record::Test(TestRecord {
                id,
                phase,
                fitness,
                predicted_fitness,
                invalid_candidates,
                ranked_candidates: Some(ranked_candidates),
                generation_ms,
                sbst_generation_ms: Some(sbst_generation_ms),
                beyond_budget,
                execution: output,
            }),
            Event::Train {
                analyzer_loss,
                critic_loss,
                gradient_penalty,
                generator_loss,
                wasserstein_estimate,
                train_ms,
                tests,
            } => Record::Train(TrainRecord {
                analyzer_loss,
                critic_loss,
                gradient_penalty: Some(gradient_penalty),
                generator_loss,
                wasserstein_estimate,
                train_ms,
                tests,
            }),
        }
    }
}

/// An executor's reply to the executor protocol's `hello`
/// ([`crate::sut::executor_protocol`]): the protocol it speaks, and what it is.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct HelloRecord {
    /// The protocol's name.
    pub protocol: String,
    /// The protocol's version.
    pub version: u32,
    /// What the executor is: `name`, `version`, `settings`.
    pub executor: serde_json::Value,
}

/// What a run is: everything that determines its results.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Header<C = serde_json::Value> {
    /// The `wogan` version that wrote the run.
    pub version: String,
    /// Seed of every random choice.
    #[serde(default)]
    pub seed: Option<u64>,
    /// The search algorithm: `wogan` or `random` ([`Algorithm`]) when `wogan run` wrote the file;
    /// run files of reference implementations name their own (`stgem-wogan`), so it is read as a
    /// name.
    pub algorithm: String,
    /// What drove the roads: the driver under test (`--oracle`, the competition's word, names it
    /// on the wire), or `executor`.
    #[serde(rename = "oracle")]
    pub driver: Oracle,
    /// What the search maximised.
    pub fitness: FitnessKind,
    /// Every setting, resolved (see `options::run_plan::RunSettings`).
    pub config: C,
}

/// What drove a run's roads, as its header's `oracle` names it: one of wogan's drivers, or
/// `executor`, an external program (the header's `config.executor` says which).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Oracle {
    /// A driver in wogan's simulator.
    Driver(DriverKind),
    /// An executor (`--executor`).
    Executor,
}

impl Oracle {
    /// The driver in wogan's simulator, unless an executor drove.
    pub fn driver(self) -> Option<DriverKind> {
        match self {
            Oracle::Driver(kind) => Some(kind),
            Oracle::Executor => None,
        }
    }

    /// Its name on the wire.
    pub fn name(self) -> &'static str {
        match self {
            Oracle::Driver(kind) => kind.name(),
            Oracle::Executor => "executor",
        }
    }
}

impl Serialize for Oracle {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Oracle {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        if name == "executor" {
            return Ok(Oracle::Executor);
        }
        serde_json::from_value(serde_json::Value::String(name))
            .map(Oracle::Driver)
            .map_err(serde::de::Error::custom)
    }
}

/// One executed test.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TestRecord {
    /// 1-based position in the run.
    pub id: usize,
    /// Who proposed it.
    pub phase: Phase,
    /// Fitness in `[0, 1]`, higher is closer to failure.
    #[serde(deserialize_with = "road_sim::json_float::nan_for_null")]
    pub fitness: f64,
    /// The analyzer's prediction, when WOGAN chose the test.
    #[serde(default)]
    pub predicted_fitness: Option<f64>,
    /// Invalid candidates rejected since the previous executed test.
    pub invalid_candidates: usize,
    /// Valid candidates the analyzer ranked to choose it (absent in runs before it was written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ranked_candidates: Option<usize>,
    /// Time spent choosing the test, milliseconds (validity checks included, training
    /// excluded: the paper's efficiency).
    #[serde(deserialize_with = "road_sim::json_float::nan_for_null")]
    pub generation_ms: f64,
    /// The generation time the SBST competition charges for the test, milliseconds: real time
    /// from the end of the previous test's execution (or the start of the run) to the start of
    /// this one, training included (absent in runs before it was written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sbst_generation_ms: Option<f64>,
    /// Whether the test ended with an SBST budget spent: executed and reported, but not kept by
    /// the competition, and not counted in this run's results.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub beyond_budget: bool,
    /// The road and its drive.
    #[serde(flatten)]
    pub execution: RoadExecution,
}

impl TestRecord {
    /// Whether the car left its lane.
    pub fn failed(&self) -> bool {
        self.execution.result.outcome == Outcome::Fail
    }

    /// A random-phase test of a straight road with this outcome, for tests of readers.
    #[cfg(test)]
    pub fn example(id: usize, outcome: Outcome, ranked_candidates: usize) -> Self {
        let json = serde_json::json!({"id": id, "phase": "random", "fitness": 0.5,
            "invalid_candidates": 0, "ranked_candidates": ranked_candidates, "generation_ms": 1.0,
            "curvature": [0.0], "road_points": [[100.0, 10.0], [100.0, 40.0]],
            "outcome": outcome, "reason": null, "max_bolp": 0.5, "min_lane_distance_m": 1.0,
            "fitness_distance": 0.3, "sim_time_s": 3.0, "execution_ms": 1.0, "MAX_CURV": 0.0,
            "DIR_COV": 0.0, "STD_SA": 0.0, "MEAN_LP": 2.0, "MAX_LP": 2.0});
        serde_json::from_value(json).expect("an example test record")
    }
}

/// A road and what driving it produced.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RoadExecution {
    /// Curvature values, 1/m.
    pub curvature: Vec<f64>,
    /// The road points they make.
    pub road_points: Vec<Point>,
    /// The interpolated centre line (not written: the run uses it for the diversity measure).
    #[serde(skip)]
    pub interpolated: Vec<Point>,
    /// The simulator's report.
    #[serde(flatten)]
    pub result: SimResult,
}

/// One training round of WOGAN (the losses of its last steps). A reference implementation's run
/// file may give only the time: the losses then read as NaN.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TrainRecord {
    /// Analyzer loss.
    #[serde(
        default = "road_sim::json_float::nan",
        deserialize_with = "road_sim::json_float::nan_for_null"
    )]
    pub analyzer_loss: f64,
    /// Critic loss.
    #[serde(
        default = "road_sim::json_float::nan",
        deserialize_with = "road_sim::json_float::nan_for_null"
    )]
    pub critic_loss: f64,
    /// Gradient penalty of the last critic step, coefficient included (absent in older runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradient_penalty: Option<f64>,
    /// Generator loss.
    #[serde(
        default = "road_sim::json_float::nan",
        deserialize_with = "road_sim::json_float::nan_for_null"
    )]
    pub generator_loss: f64,
    /// The critic's Wasserstein estimate.
    #[serde(
        default = "road_sim::json_float::nan",
        deserialize_with = "road_sim::json_float::nan_for_null"
    )]
    pub wasserstein_estimate: f64,
    /// Duration of the round, milliseconds.
    pub train_ms: f64,
    /// Tests the round learnt from (absent in a reference implementation's file).
    #[serde(default)]
    pub tests: usize,
}

/// The totals of a run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SummaryRecord {
    /// Tests executed.
    pub executed: usize,
    /// Tests whose drive failed.
    pub failed: usize,
    /// Invalid candidates over the whole run.
    pub invalid_candidates: usize,
    /// Wall time of the run, seconds.
    pub wall_s: f64,
    /// Time spent generating tests, seconds.
    pub generation_s: f64,
    /// Time spent training, seconds.
    pub training_s: f64,
    /// Time spent simulating, seconds.
    pub simulation_s: f64,
    /// The SBST competition's generation time, seconds (the budget's use).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sbst_generation_s: Option<f64>,
    /// Simulated time of every executed test, seconds (the execution budget's use, the test
    /// beyond the budget included).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub execution_time_s: Option<f64>,
    /// Tests executed beyond an SBST budget and not kept (0 or 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beyond_budget: Option<usize>,
    /// The paper's diversity: median pairwise distance of the failing roads' diversity profiles.
    pub diversity: Option<f64>,
    /// Which pairs the diversity was measured on.
    pub diversity_pairs: String,
    /// Whether Ctrl-C or SIGTERM ended the run.
    pub interrupted: bool,
    /// Why the search failed part-way, if it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// What the executor said of itself in its reply to `hello` (`name`, `version`,
    /// `settings`), when an executor drove the roads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub executor: Option<serde_json::Value>,
}

/// An input line that holds no road.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ErrorRecord {
    /// The input line, from 1.
    pub line: usize,
    /// What is wrong with it.
    pub error: String,
}

/// The first line of a regression suite (`wogan suite`): what the file is and its layout's version.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SuiteHeader {
    /// Always [`SUITE_FORMAT`], so that another JSON-lines file is not taken for a suite.
    pub format: String,
    /// The layout's version, [`SUITE_VERSION`] when written by this `wogan`.
    pub version: u32,
}

/// What a suite's first line says it is.
pub const SUITE_FORMAT: &str = "wogan-suite";
/// The suite layout this `wogan` writes; it reads this version and older ones.
pub const SUITE_VERSION: u32 = 1;

/// One road of a regression suite, with where it came from and how it was judged then.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteRoad {
    /// A name unique in the suite, `RUN-STEM#ID` (the run file's stem and the test's id).
    pub name: String,
    /// The road's points, metres.
    pub road_points: Vec<Point>,
    /// How the drive that put it in the suite ended.
    pub recorded: RecordedDrive,
    /// Where it came from.
    pub origin: RoadOrigin,
}

/// How a saved road's drive ended when it was recorded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RecordedDrive {
    /// `PASS`, `FAIL` or `ERROR`.
    pub outcome: Outcome,
    /// Largest BOLP of that drive.
    #[serde(deserialize_with = "road_sim::json_float::nan_for_null")]
    pub max_bolp: f64,
}

/// The run a suite road was found in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoadOrigin {
    /// The run file, as it was given to `wogan suite add`.
    pub run: String,
    /// The test's id in that run.
    pub test: usize,
    /// The run's seed.
    pub seed: Option<u64>,
    /// The driver the road failed.
    pub driver: String,
    /// The failure threshold it failed at.
    pub oob_tolerance: Option<f64>,
    /// The `wogan` version that made the run.
    pub wogan: String,
}

/// `replay`'s answer for one saved road: how it drives now, beside how it drove when recorded.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ReplayRecord {
    /// The file the road came from.
    pub file: String,
    /// The line of that file it begins on, from 1.
    pub line: usize,
    /// The road's name: the suite's, or the test id of a run or export.
    pub name: String,
    /// The outcome now: `PASS`, `FAIL`, `ERROR`, or `INVALID` when the road no longer validates.
    pub outcome: String,
    /// What it was when recorded, when the file says.
    pub recorded_outcome: Option<String>,
    /// Whether the outcome differs from the recorded one (`false` when none is recorded).
    pub changed: bool,
    /// Largest BOLP now (NaN, written `null`, when not driven).
    pub max_bolp: f64,
    /// Largest BOLP when recorded.
    pub recorded_max_bolp: Option<f64>,
    /// Why the drive did not pass, or why the road is invalid.
    pub reason: Option<String>,
    /// Where the car first left its lane now.
    pub oob: Option<LaneExit>,
}

/// A road `sample` drew from a saved generator: WOGAN's choice, ranked by the analyzer.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SampleRecord {
    /// Its place among the roads drawn, by predicted fitness, from 1.
    pub rank: usize,
    /// The analyzer's prediction; `null` for a random valid road drawn after too many invalid
    /// candidates.
    pub predicted_fitness: Option<f64>,
    /// Curvature values, 1/m.
    pub curvature: Vec<f64>,
    /// The road points they make.
    pub road_points: Vec<Point>,
}

/// `simulate`'s answer for one road.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ResultRecord {
    /// The road was driven.
    Driven {
        /// The input line, from 1.
        line: usize,
        /// The input's `id`, echoed when it has one (an executor's answer names its road so).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        id: Option<serde_json::Value>,
        /// The drive.
        #[serde(flatten)]
        result: SimResult,
        /// The drive's records in the SBST pipeline's layout, when asked for.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        execution_data: Option<Vec<ExecutionRecord>>,
    },
    /// The road is invalid and was not driven.
    Invalid {
        /// The input line, from 1.
        line: usize,
        /// The input's `id`, echoed when it has one (an executor's answer names its road so).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        id: Option<serde_json::Value>,
        /// Always `INVALID`.
        outcome: InvalidOutcome,
        /// Why the road is invalid.
        reason: Reason,
        /// The competition's message.
        message: String,
    },
}

/// The outcome written for a road that was not driven because it is invalid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum InvalidOutcome {
    /// Not a valid road.
    Invalid,
}

/// `validate`'s answer for one road.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VerdictRecord {
    /// The input line, from 1.
    pub line: usize,
    /// The input's `id`, echoed when it has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<serde_json::Value>,
    /// Whether the road is valid.
    pub valid: bool,
    /// Why not.
    pub reason: Option<Reason>,
    /// The competition's message (empty for a valid road).
    pub message: String,
    /// The interpolated centre line, with `--details`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interpolated_points: Option<Vec<Point>>,
}

/// What `train-driver` trained and measured.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DriverRecord {
    /// Where the weights were written.
    pub weights: String,
    /// The training settings.
    pub config: CloningConfig,
    /// What the training measured.
    #[serde(flatten)]
    pub report: CloningReport,
}

/// One line of a `simulate --trace` file: the road first, then one sample per lane-monitor step.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum TraceRecord {
    /// The road driven.
    Road {
        /// Its defining points.
        road_points: Vec<Point>,
        /// Its interpolated centre line.
        interpolated_points: Vec<Point>,
    },
    /// One lane-monitor sample.
    Sample(Sample),
    /// A record of a kind this version does not know (skipped by readers).
    #[serde(other, skip_serializing)]
    Unknown,
}

/// `value` unless it is NaN (a number that was not finite when written, or missing).
pub fn known(value: f64) -> Option<f64> {
    (!value.is_nan()).then_some(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record written and read back is the same record, byte for byte.
    fn round_trips(line: &str) {
        let record: Record = serde_json::from_str(line).unwrap();
        assert_eq!(serde_json::to_string(&record).unwrap(), line);
    }

    #[test]
    fn every_kind_round_trips() {
        round_trips(
            r#"{"type":"header","version":"0.1.0","seed":7,"algorithm":"wogan","oracle":"dave2-proxy","fitness":"distance","config":{"jobs":1}}"#,
        );
        round_trips(
            r#"{"type":"test","id":3,"phase":"wogan","fitness":0.25,"predicted_fitness":0.5,"invalid_candidates":2,"ranked_candidates":9,"generation_ms":1.5,"sbst_generation_ms":20.5,"beyond_budget":true,"curvature":[0.01,-0.02],"road_points":[[100.0,10.0],[100.0,25.0],[101.0,40.0]],"outcome":"FAIL","reason":"out_of_lane","max_bolp":0.9,"min_lane_distance_m":-0.1,"fitness_distance":0.73,"sim_time_s":12.5,"execution_ms":4.0,"MAX_CURV":0.05,"DIR_COV":0.2,"STD_SA":3.0,"MEAN_LP":1.2,"MAX_LP":2.0,"oob":{"t_s":12.5,"x":104.5,"y":38.0,"side":"right","sbst_side":"RIGHT"}}"#,
        );
        round_trips(
            r#"{"type":"train","analyzer_loss":0.5,"critic_loss":8.2,"gradient_penalty":8.3,"generator_loss":0.1,"wasserstein_estimate":0.01,"train_ms":20.5,"tests":8}"#,
        );
        round_trips(
            r#"{"type":"summary","executed":40,"failed":13,"invalid_candidates":197,"wall_s":9.5,"generation_s":1.0,"training_s":0.5,"simulation_s":8.0,"sbst_generation_s":1.5,"execution_time_s":400.5,"beyond_budget":0,"diversity":9.25,"diversity_pairs":"all","interrupted":false}"#,
        );
        round_trips(r#"{"type":"error","line":4,"error":"not JSON"}"#);
        round_trips(
            r#"{"type":"result","line":1,"outcome":"PASS","reason":null,"max_bolp":0.1,"min_lane_distance_m":1.5,"fitness_distance":0.2,"sim_time_s":0.5,"execution_ms":1.0,"MAX_CURV":0.0,"DIR_COV":0.04,"STD_SA":0.0,"MEAN_LP":1.9,"MAX_LP":1.9,"oob":null,"execution_data":[[0.5,[102.0,11.0,-28.0],[0.0,1.0,0.0],[0.0,5.0,0.0],0.0,0.0,0.0,0.0,0.5,0.5,5.0,18,false,0,0.0,1.9,0.1]]}"#,
        );
        round_trips(
            r#"{"type":"result","line":2,"outcome":"INVALID","reason":"too_sharp","message":"The road is too sharp"}"#,
        );
        round_trips(
            r#"{"type":"verdict","line":1,"valid":false,"reason":"outside_map","message":"Not entirely inside the map boundaries"}"#,
        );
    }

    #[test]
    fn nulls_read_as_nan_and_older_records_read() {
        let old = r#"{"type":"test","id":1,"phase":"random","fitness":null,"predicted_fitness":null,"invalid_candidates":0,"generation_ms":0.5,"curvature":[0.0],"road_points":[[1.0,2.0]],"outcome":"ERROR","reason":"non_finite_physics_state","max_bolp":null,"min_lane_distance_m":2.0,"fitness_distance":0.0,"sim_time_s":1.0,"execution_ms":1.0,"MAX_CURV":0.0,"DIR_COV":0.0,"STD_SA":0.0,"MEAN_LP":2.0,"MAX_LP":2.0}"#;
        let Record::<serde_json::Value>::Test(test) = serde_json::from_str(old).unwrap() else {
            panic!("not a test record");
        };
        assert!(test.fitness.is_nan() && test.execution.result.max_bolp.is_nan());
        assert_eq!(test.ranked_candidates, None);
        // A reference implementation's run (stgem's WOGAN on our simulator) names its own
        // algorithm and reports only the training time.
        let header: Record = serde_json::from_str(
            r#"{"type":"header","version":"stgem-reference","seed":1,"algorithm":"stgem-wogan","oracle":"beamng-ai-proxy","fitness":"bolp","config":{}}"#,
        )
        .unwrap();
        assert!(matches!(header, Record::Header(h) if h.algorithm == "stgem-wogan"));
        let train: Record =
            serde_json::from_str(r#"{"type":"train","before_test":298,"train_ms":102.0}"#).unwrap();
        assert!(matches!(train, Record::Train(t) if t.critic_loss.is_nan() && t.train_ms == 102.0));
        let unknown: Record = serde_json::from_str(r#"{"type":"future","x":1}"#).unwrap();
        assert!(matches!(unknown, Record::Unknown));
    }
}
