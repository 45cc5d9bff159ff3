//! A result folder of the competition's pipeline read back as one run, so that `wogan report`
//! tables a peer generator (run in the pipeline with `wogan simulate` as its executor) beside
//! `wogan run`, and a `wogan export` beside the run it came from.
//!
//! The folder's `test.NNNN.json` files, in number order (the order the pipeline generated the
//! tests in), make the run. A test the pipeline found invalid (`is_valid` false: stored, never
//! executed) is no test of the run; it counts as the pipeline counts it, generated but not valid
//! ([`RunFile::pipeline_invalid`]). Every valid test is an executed test: its outcome is the
//! pipeline's `test_outcome`, its largest BOLP the largest `oob_percentage` of its
//! `execution_data`, and where the car left its lane the `pos` of the first record with `is_oob`
//! (the sample at which wogan's simulator stops a drive that fails out of its lane), so that the
//! distinct failures of a peer and of wogan are counted alike.
//!
//! The configuration comes from the `summary.json` the peers' harness
//! (`scripts/peers/run_peer.py`) writes beside the tests: `generator` names the algorithm,
//! `oracle` the driver, `oob_tolerance` and `speed_limit` the conditions, `interrupted` the signal
//! that cut the run short (a run so ended is reported as interrupted, as a `wogan run` would be),
//! `crashed` the exception that ended the generator (reported as a run that failed part-way, with
//! the exception: a crashed run is never a whole one).
//! Without it (a bare pipeline folder, an export) the algorithm is the folder's name and the rest
//! read `?`: nothing is guessed.

use crate::files::header_settings::HeaderSettings;
use crate::files::records::{RoadExecution, SummaryRecord, TestRecord};
use crate::files::road_input::road_reader;
use crate::files::run_file::{RunFile, RunHeader};
use crate::files::sbst_format::{test_file_number, test_files, FIELDS};
use anyhow::{Context, Result};
use road_sim::oob::geometry::distance_to_line;
use road_sim::oob::sbst_side;
use road_sim::road::input::RoadInput;
use road_sim::road::ROAD_WIDTH_M;
use road_sim::{DriverKind, LaneExit, LaneSide, Outcome, Road, SimResult, StopReason};
use serde_json::{json, Value};
use std::path::Path;
use wogan_core::Phase;

/// The file our harness writes beside the tests: what the run was.
pub const HARNESS_SUMMARY: &str = "summary.json";
/// What an algorithm read from a result folder is called before its name (`sbst:FreneticV`).
pub const ALGORITHM_PREFIX: &str = "sbst:";
/// The pipeline's `description` of an out-of-bound failure begins so (it counts OBEs by it).
const OBE_DESCRIPTION: &str = "Car drove out of the lane ";
/// Side of the map, metres, the pipeline's default (no file of a result folder says).
const MAP_SIZE_M: f64 = 200.0;

/// Whether `dir` is a result folder: it holds `test.NNNN.json` files directly.
pub fn is_result_folder(dir: &Path) -> bool {
    test_files(dir).is_ok_and(|files| !files.is_empty())
}

/// Reads the result folder `dir` as one run; `Err` only when it cannot be listed. A test file
/// that cannot be read is a problem of the run (naming the file and the field), and the rest
/// are read.
pub fn read_result_folder(dir: &Path) -> Result<RunFile> {
    let files = test_files(dir).with_context(|| format!("cannot list {}", dir.display()))?;
    let mut problems = Vec::new();
    let (header, ending) = folder_header(dir, &mut problems);
    let mut tests: Vec<TestRecord> = Vec::new();
    let mut pipeline_invalid = 0;
    for file in &files {
        match read_test_file(file) {
            Ok(None) => pipeline_invalid += 1,
            Ok(Some(test)) => tests.push(test),
            Err(problem) => problems.push(format!("{}: {problem}", file.display())),
        }
    }
    let summary = SummaryRecord {
        executed: tests.len(),
        failed: tests.iter().filter(|t| t.failed()).count(),
        // What a generator rejected before proposing is not in the folder.
        invalid_candidates: 0,
        wall_s: ending.wall_s,
        generation_s: f64::NAN,
        training_s: 0.0,
        simulation_s: tests
            .iter()
            .map(|t| t.execution.result.sim_time_s)
            .filter(|s| s.is_finite())
            .sum(),
        sbst_generation_s: None,
        execution_time_s: None,
        beyond_budget: None,
        diversity: None,
        diversity_pairs: String::new(),
        interrupted: ending.interrupted,
        error: ending
            .crashed
            .map(|exception| format!("the generator crashed: {exception}")),
        executor: None,
    };
    Ok(RunFile {
        path: dir.to_path_buf(),
        header: Some(header),
        tests,
        beyond_budget: Vec::new(),
        train_ms: 0.0,
        pipeline_invalid,
        summary: Some(summary),
        problems,
    })
}

/// How the harness says a run went, beside its header.
struct HarnessEnding {
    /// The run's wall time, seconds (NaN when the harness does not say).
    wall_s: f64,
    /// Whether a signal cut the run short (the summary names it).
    interrupted: bool,
    /// The last line of the exception that ended the generator, if one did.
    crashed: Option<String>,
}

/// The run's header from the harness's `summary.json`, or from the folder's name alone; and how
/// the run went, as far as the harness says.
fn folder_header(dir: &Path, problems: &mut Vec<String>) -> (RunHeader, HarnessEnding) {
    let path = dir.join(HARNESS_SUMMARY);
    let summary = match std::fs::read_to_string(&path) {
        Ok(text) => match serde_json::from_str::<Value>(&text) {
            Ok(value) if value.is_object() => value,
            Ok(_) => {
                problems.push(format!("{}: not a JSON object", path.display()));
                Value::Null
            }
            Err(e) => {
                problems.push(format!("{}: not JSON: {e}", path.display()));
                Value::Null
            }
        },
        // No summary: a bare pipeline folder or an export, whose settings no file says.
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Value::Null,
        Err(e) => {
            problems.push(format!("{}: cannot read: {e}", path.display()));
            Value::Null
        }
    };
    let generator = summary
        .get("generator")
        .and_then(Value::as_str)
        .and_then(|g| g.rsplit('.').next())
        .filter(|name| !name.is_empty());
    let folder = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    let folder = folder.file_name().map(|n| n.to_string_lossy().into_owned());
    let name = generator
        .map(str::to_owned)
        .or(folder)
        .unwrap_or_else(|| "?".to_owned());
    let oracle = summary.get("oracle");
    let oob = summary.get("oob_tolerance");
    let speed = summary.get("speed_limit");
    let header = RunHeader {
        algorithm: format!("{ALGORITHM_PREFIX}{name}"),
        simulator: oracle.and_then(Value::as_str).unwrap_or("?").to_owned(),
        // The pipeline's generators maximise no fitness of ours.
        fitness: None,
        seed: summary.get("seed").and_then(Value::as_u64),
        oob_tolerance: oob.and_then(Value::as_f64),
        speed_limit_kmh: speed.and_then(Value::as_f64),
        settings: HeaderSettings::default(),
        map_size_m: MAP_SIZE_M,
        // Only the key's name is reported; a report never drives a test again.
        driver: oracle.and_then(|o| serde_json::from_value::<DriverKind>(o.clone()).ok()),
        config: json!({"sim": {"oob_tolerance": oob, "speed_limit_kmh": speed}}),
        version: "-".to_owned(),
    };
    let ending = HarnessEnding {
        wall_s: summary
            .get("wall_s")
            .and_then(Value::as_f64)
            .unwrap_or(f64::NAN),
        interrupted: summary.get("interrupted").is_some_and(|s| !s.is_null()),
        crashed: summary
            .get("crashed")
            .filter(|c| !c.is_null())
            .map(|c| c.as_str().map_or_else(|| c.to_string(), str::to_owned)),
    };
    (header, ending)
}

/// One test file: `None` for a test the pipeline found invalid, else the executed test.
fn read_test_file(path: &Path) -> Result<Option<TestRecord>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
    let value: Value = serde_json::from_str(&text).map_err(|e| format!("not JSON: {e}"))?;
    if !value.is_object() {
        return Err("not a test object (a JSON object)".to_owned());
    }
    let is_valid = value
        .get("is_valid")
        .ok_or("is_valid: missing (not the competition's test object?)")?
        .as_bool()
        .ok_or("is_valid: expected true or false")?;
    if !is_valid {
        return Ok(None);
    }
    if value.get("road_points").is_none() {
        return Err("road_points: missing".to_owned());
    }
    let road_points = match road_reader(MAP_SIZE_M)
        .read_value(&value)
        .map_err(|e| e.to_string())?
    {
        RoadInput::Points(points) => points,
        _ => return Err("road_points: holds no road".to_owned()),
    };
    let outcome = match value.get("test_outcome").and_then(Value::as_str) {
        Some("PASS") => Outcome::Pass,
        Some("FAIL") => Outcome::Fail,
        Some("ERROR") => Outcome::Error,
        Some(other) => {
            return Err(format!(
                "test_outcome: {other:?} is not PASS, FAIL or ERROR"
            ))
        }
        None => return Err("test_outcome: missing or not text on a valid test".to_owned()),
    };
    let description = value.get("description").and_then(Value::as_str);
    let records = value
        .get("execution_data")
        .ok_or("execution_data: missing on a valid test")?
        .as_array()
        .ok_or("execution_data: expected a list of records")?;
    let drive = Drive::of(records)?;
    let oob = drive
        .exit
        .map(|(t_s, [x, y])| lane_exit(&road_points, t_s, x, y));
    let feature = |name: &str| {
        value
            .pointer(&format!("/features/{name}"))
            .and_then(Value::as_f64)
            .unwrap_or(f64::NAN)
    };
    let reason = (outcome == Outcome::Fail
        && description.is_some_and(|d| d.starts_with(OBE_DESCRIPTION)))
    .then_some(StopReason::OutOfLane);
    let id = path
        .file_name()
        .and_then(|n| n.to_str())
        .and_then(test_file_number)
        .unwrap_or_default() as usize;
    let result = SimResult {
        outcome,
        reason,
        max_bolp: drive.max_bolp,
        // Not in the pipeline's records in a form of ours.
        min_lane_distance_m: f64::NAN,
        fitness_distance: f64::NAN,
        sim_time_s: drive.last_timer,
        execution_ms: f64::NAN,
        max_curv: feature("MAX_CURV"),
        dir_cov: feature("DIR_COV"),
        std_sa: feature("STD_SA"),
        mean_lp: feature("MEAN_LP"),
        max_lp: feature("MAX_LP"),
        oob,
        error: None,
        trace: None,
    };
    Ok(Some(TestRecord {
        id,
        phase: Phase::Random,
        fitness: f64::NAN,
        predicted_fitness: None,
        invalid_candidates: 0,
        ranked_candidates: None,
        generation_ms: f64::NAN,
        sbst_generation_ms: None,
        beyond_budget: false,
        execution: RoadExecution {
            curvature: Vec::new(),
            road_points,
            interpolated: Vec::new(),
            result,
        },
    }))
}

/// What a report takes from a test's `execution_data`.
#[derive(Debug, PartialEq)]
struct Drive {
    /// Largest `oob_percentage` (NaN without records).
    max_bolp: f64,
    /// The last record's `timer`, the drive's simulated time (NaN without records).
    last_timer: f64,
    /// `timer` and `pos` (x, y) of the first record with `is_oob`.
    exit: Option<(f64, [f64; 2])>,
}

impl Drive {
    /// Reads the records, each the pipeline's array of fields in its order (as
    /// `SimulationDataRecord` is written; the 2021 layout is the same without the last field) or
    /// an object of them by name.
    fn of(records: &[Value]) -> Result<Self, String> {
        let mut drive = Drive {
            max_bolp: f64::NAN,
            last_timer: f64::NAN,
            exit: None,
        };
        for (i, record) in records.iter().enumerate() {
            let field = |name: &str| -> Result<&Value, String> {
                let found = match record {
                    Value::Array(values) => FIELDS
                        .iter()
                        .position(|f| *f == name)
                        .and_then(|at| values.get(at)),
                    Value::Object(fields) => fields.get(name),
                    _ => return Err(format!("execution_data[{i}]: not a record")),
                };
                found.ok_or_else(|| format!("execution_data[{i}]: {name}: missing"))
            };
            let number = |name: &str| -> Result<f64, String> {
                field(name)?
                    .as_f64()
                    .ok_or_else(|| format!("execution_data[{i}]: {name}: expected a number"))
            };
            let timer = number("timer")?;
            let bolp = match field("oob_percentage") {
                Ok(_) => number("oob_percentage")?,
                // The pipeline's records before February 2021 (the 2021 competition's, 16
                // fields) end before `oob_percentage`: the largest share out of the lane the
                // monitor kept stands in (our harness keeps the running maximum there).
                Err(_) if field("max_oob_percentage").is_ok() => number("max_oob_percentage")?,
                Err(missing) => return Err(missing),
            };
            let is_oob = field("is_oob")?
                .as_bool()
                .ok_or_else(|| format!("execution_data[{i}]: is_oob: expected true or false"))?;
            drive.max_bolp = drive.max_bolp.max(bolp);
            drive.last_timer = timer;
            if is_oob && drive.exit.is_none() {
                let pos = field("pos")?.as_array().and_then(|p| {
                    let x = p.first()?.as_f64()?;
                    let y = p.get(1)?.as_f64()?;
                    Some([x, y])
                });
                let pos =
                    pos.ok_or_else(|| format!("execution_data[{i}]: pos: expected [x, y, z]"))?;
                drive.exit = Some((timer, pos));
            }
        }
        Ok(drive)
    }
}

/// Where the car left its lane, as wogan's simulator records it: the edge nearer the car centre
/// (the centre line, the lane's left edge, or the road's right edge).
fn lane_exit(road_points: &[[f64; 2]], t_s: f64, x: f64, y: f64) -> LaneExit {
    let side = match Road::new(road_points) {
        Ok(road) => {
            let left = distance_to_line([x, y], &road.interpolated);
            let right = distance_to_line([x, y], &road.offset_line(-ROAD_WIDTH_M / 2.0));
            if left < right {
                LaneSide::Left
            } else {
                LaneSide::Right
            }
        }
        // A road that cannot be built is counted nowhere (see `distinct_failures`).
        Err(_) => LaneSide::Right,
    };
    LaneExit {
        t_s,
        x,
        y,
        side,
        sbst_side: sbst_side(road_points, [x, y]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record in the pipeline's 17-field layout.
    fn record(timer: f64, x: f64, bolp: f64, is_oob: bool) -> Value {
        json!([
            timer,
            [x, 30.0, -28.0],
            [0, 1, 0],
            [0, 8, 0],
            0,
            0,
            0,
            0,
            0,
            0,
            8,
            29,
            is_oob,
            u32::from(is_oob),
            0,
            1.5,
            bolp
        ])
    }

    /// A valid, executed test of a straight road up the map.
    fn test(outcome: &str, description: &str, records: Vec<Value>) -> Value {
        json!({"id": 1, "is_valid": true, "validation_message": "",
            "road_points": [[100.0, 10.0], [100.0, 60.0], [100.0, 110.0]],
            "interpolated_points": [], "test_outcome": outcome, "description": description,
            "execution_data": records, "features": {"MAX_CURV": 0.0, "DIR_COV": 0.5}})
    }

    fn scratch(name: &str, files: &[(&str, String)]) -> std::path::PathBuf {
        let dir = std::env::temp_dir()
            .join(format!("wogan-result-run-{}-{name}", std::process::id()))
            .join(name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for (file, text) in files {
            std::fs::write(dir.join(file), text).unwrap();
        }
        dir
    }

    #[test]
    fn a_drive_is_its_largest_bolp_and_its_first_record_out_of_the_lane() {
        let records = [
            record(0.0, 100.0, 0.0, false),
            record(1.0, 101.0, 0.9, true),
            json!({"timer": 2.0, "pos": [102.0, 31.0, 0.0], "is_oob": true, "oob_percentage": 0.95}),
        ];
        let drive = Drive::of(&records).unwrap();
        assert_eq!(drive.max_bolp, 0.95);
        assert_eq!(drive.last_timer, 2.0);
        assert_eq!(drive.exit, Some((1.0, [101.0, 30.0])));
        // The 2021 layout: the same fields without the last, oob_percentage.
        let mut old = record(1.0, 101.0, 0.9, true);
        old[14] = json!(0.92);
        old.as_array_mut().unwrap().pop();
        let drive = Drive::of(&[old]).unwrap();
        assert_eq!(
            (drive.max_bolp, drive.exit),
            (0.92, Some((1.0, [101.0, 30.0])))
        );
        let empty = Drive::of(&[]).unwrap();
        assert!(empty.max_bolp.is_nan() && empty.exit.is_none());
        let short = Drive::of(&[json!([0.5])]).unwrap_err();
        assert_eq!(short, "execution_data[0]: oob_percentage: missing");
        let bad = Drive::of(&[record(0.0, 100.0, 0.5, false), json!({"timer": "x"})]);
        assert_eq!(
            bad.unwrap_err(),
            "execution_data[1]: timer: expected a number"
        );
    }

    #[test]
    fn a_harness_folder_is_one_run_of_its_valid_tests() {
        let invalid = json!({"id": 2, "is_valid": false, "validation_message": "Not in the map",
            "road_points": [[0.0, 0.0]], "interpolated_points": []});
        let out = [record(0.0, 100.0, 0.1, false), record(3.0, 98.5, 0.9, true)];
        let summary = json!({"generator": "frenetic.generators.FreneticV",
            "oracle": "dave2-proxy", "oob_tolerance": 0.1, "speed_limit": 25, "seed": 4,
            "interrupted": null});
        let dir = scratch(
            "harness",
            &[
                (
                    "test.0001.json",
                    test("PASS", "Successful test", vec![]).to_string(),
                ),
                ("test.0002.json", invalid.to_string()),
                ("test.0003.json", invalid.to_string()),
                (
                    "test.0004.json",
                    test("FAIL", "Car drove out of the lane (x)", out.to_vec()).to_string(),
                ),
                (
                    "test.0005.json",
                    "{\"is_valid\": true, \"road_po".to_owned(),
                ),
                (
                    "test.0006.json",
                    json!({"is_valid": true, "road_points": [[1, 2], [3, 4]]}).to_string(),
                ),
                ("test.0007.json", invalid.to_string()),
                ("summary.json", summary.to_string()),
            ],
        );
        let run = read_result_folder(&dir).unwrap();
        let header = run.header.as_ref().unwrap();
        assert_eq!(
            (header.algorithm.as_str(), header.simulator.as_str()),
            ("sbst:FreneticV", "dave2-proxy")
        );
        assert_eq!(header.fitness, None);
        assert_eq!(
            (header.oob_tolerance, header.speed_limit_kmh),
            (Some(0.1), Some(25.0))
        );
        assert_eq!(run.header.as_ref().unwrap().seed, Some(4));
        let ids: Vec<usize> = run.tests.iter().map(|t| t.id).collect();
        assert_eq!(ids, [1, 4]);
        let summary = run.summary.as_ref().unwrap();
        assert_eq!((summary.executed, summary.failed), (2, 1));
        assert!(!summary.interrupted);
        // The pipeline's totals: three invalid tests generated, two valid.
        assert_eq!(run.pipeline_invalid, 3);
        let stats = crate::sbst::metrics::GenerationStats::of(&run);
        assert_eq!((stats.generated, stats.valid, stats.invalid), (5, 2, 3));
        let failed = &run.tests[1].execution.result;
        assert_eq!(failed.reason, Some(StopReason::OutOfLane));
        assert_eq!(failed.max_bolp, 0.9);
        assert_eq!(failed.max_curv, 0.0);
        assert!(failed.std_sa.is_nan());
        let exit = failed.oob.unwrap();
        assert_eq!(
            (exit.t_s, exit.x, exit.y, exit.side),
            (3.0, 98.5, 30.0, LaneSide::Left)
        );
        assert_eq!(run.problems.len(), 2, "{:?}", run.problems);
        assert!(
            run.problems[0].contains("test.0005.json: not JSON"),
            "{:?}",
            run.problems
        );
        assert!(
            run.problems[1]
                .ends_with("test.0006.json: test_outcome: missing or not text on a valid test"),
            "{:?}",
            run.problems
        );
        std::fs::remove_dir_all(dir.parent().unwrap()).unwrap();
    }

    #[test]
    fn without_the_harness_summary_the_folder_names_the_run_and_nothing_is_guessed() {
        let dir = scratch(
            "adafrenetic.2",
            &[(
                "test.0001.json",
                test("PASS", "Successful test", vec![]).to_string(),
            )],
        );
        let run = read_result_folder(&dir).unwrap();
        assert!(run.problems.is_empty(), "{:?}", run.problems);
        let header = run.header.unwrap();
        assert_eq!(
            (header.algorithm.as_str(), header.simulator.as_str()),
            ("sbst:adafrenetic.2", "?")
        );
        assert_eq!((header.oob_tolerance, header.speed_limit_kmh), (None, None));
        assert_eq!(header.seed, None);
        assert!(!run.summary.unwrap().interrupted);
        assert!(is_result_folder(&dir));
        assert!(!is_result_folder(dir.parent().unwrap()));
        // The harness's summary of a run a signal cut short names the signal.
        let cut_short = json!({"generator": "src.generators.AdaFrenetic", "seed": 2,
            "wall_s": 12.5, "interrupted": "SIGTERM"});
        std::fs::write(dir.join("summary.json"), cut_short.to_string()).unwrap();
        let run = read_result_folder(&dir).unwrap();
        let summary = run.summary.unwrap();
        assert!(summary.interrupted);
        assert_eq!(summary.wall_s, 12.5);
        assert_eq!(summary.error, None);
        // A run its generator's exception ended failed part-way, with the exception's line.
        let crashed = json!({"generator": "src.generators.Frenetic", "seed": 2,
            "crashed": "pandas.errors.InvalidIndexError: scalar", "interrupted": null});
        std::fs::write(dir.join("summary.json"), crashed.to_string()).unwrap();
        let summary = read_result_folder(&dir).unwrap().summary.unwrap();
        assert!(!summary.interrupted);
        assert_eq!(
            summary.error.as_deref(),
            Some("the generator crashed: pandas.errors.InvalidIndexError: scalar")
        );
        std::fs::write(dir.join("summary.json"), "[1]").unwrap();
        let run = read_result_folder(&dir).unwrap();
        assert!(
            run.problems[0].ends_with("summary.json: not a JSON object"),
            "{:?}",
            run.problems
        );
        std::fs::remove_dir_all(dir.parent().unwrap()).unwrap();
    }
}
