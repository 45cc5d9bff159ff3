//! Reading the JSON lines of one `wogan run` (through [`crate::files::records`]): its header, test
//! records and (when the run finished) its summary. Bad lines are collected with their file and
//! line number, never fatal: lines that are not records, and records no run holds (values out of
//! their ranges, a test id twice, a second header or one after the tests), which are not read.

use crate::files::header_settings::HeaderSettings;
use crate::files::json_lines::{numbered_lines, open_input};
pub use crate::files::records::TestRecord;
use crate::files::records::{Header, Record, SummaryRecord};
use crate::options::config_file::SettingsSource;
use crate::options::driver_options::{checked_settings, DriverInputs};
use anyhow::{bail, Result};
use road_sim::setting_checks::shown;
use road_sim::sim::MAX_SIM_TIME_S;
use road_sim::validator::MAX_MAP_SIZE_M;
use road_sim::{DriverConfig, DriverKind, FitnessKind, Outcome, SimConfig};
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The header's fields the report uses.
#[derive(Debug, Clone)]
pub struct RunHeader {
    /// The search algorithm (`wogan`, `random`), or the name a reference or a peer's folder
    /// gives (`stgem-wogan`, `sbst:FreneticV`).
    pub algorithm: String,
    /// What drove the roads: the driver's name, `executor`, or the pipeline's oracle.
    pub simulator: String,
    /// What the search maximised; `None` for a peer's generator, which maximises none of ours.
    pub fitness: Option<FitnessKind>,
    /// The run's seed.
    pub seed: Option<u64>,
    /// BOLP failure threshold.
    pub oob_tolerance: Option<f64>,
    /// The speed limit, km/h.
    pub speed_limit_kmh: Option<f64>,
    /// The settings the search ran with, read typed.
    pub settings: HeaderSettings,
    /// Side of the map, metres.
    pub map_size_m: f64,
    /// The driver under test in wogan's simulator; `None` when an executor drove the roads (or a
    /// peer's folder names an oracle wogan does not know).
    pub driver: Option<DriverKind>,
    /// Every setting as the header gives it (for replaying a test).
    pub config: Value,
    /// The `wogan` version that wrote the run.
    pub version: String,
}

/// One run read from its file.
#[derive(Debug, Clone)]
pub struct RunFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// The header, when the file had one.
    pub header: Option<RunHeader>,
    /// The executed tests the run kept, in file order.
    pub tests: Vec<TestRecord>,
    /// A test executed with an SBST budget spent, which the competition does not keep (it
    /// counts only as generated).
    pub beyond_budget: Vec<TestRecord>,
    /// Training time from the `train` records, milliseconds.
    pub train_ms: f64,
    /// Tests the competition's pipeline found invalid and never executed (a result folder's),
    /// which it counts as generated; 0 for `wogan run`, which validates before it proposes.
    pub pipeline_invalid: usize,
    /// The summary; `None` for a truncated run.
    pub summary: Option<SummaryRecord>,
    /// `file:line: problem` for each line that could not be read.
    pub problems: Vec<String>,
}

impl RunFile {
    /// Number of failing tests.
    pub fn failures(&self) -> usize {
        self.tests.iter().filter(|t| t.failed()).count()
    }

    /// Drops the roads (curvature and points) of the tests that did not fail, and of those
    /// beyond an SBST budget, which no figure or picture of a report uses: only failing roads are
    /// drawn, measured for diversity and analysed for OOBs. A report of thousands of runs then
    /// holds a few hundred bytes per passing test instead of its road.
    pub fn drop_unused_roads(&mut self) {
        let passing = self.tests.iter_mut().filter(|t| !t.failed());
        for test in passing.chain(&mut self.beyond_budget) {
            test.execution.curvature = Vec::new();
            test.execution.road_points = Vec::new();
            test.execution.interpolated = Vec::new();
        }
        // What a run grew to while it was read is spare room now.
        self.tests.shrink_to_fit();
        self.beyond_budget.shrink_to_fit();
    }
}

/// Reads a run; `Err` only when the file cannot be opened. A line that cannot be read, or that
/// says what no run can hold (a value out of its range, a second test of one id, a second header
/// or one after the tests), is a problem naming it (`path:line`) and is not read.
pub fn read_run(path: &Path) -> Result<RunFile> {
    let input = open_input(Some(path))?;
    let mut run = RunFile {
        path: path.to_path_buf(),
        header: None,
        tests: Vec::new(),
        beyond_budget: Vec::new(),
        train_ms: 0.0,
        pipeline_invalid: 0,
        summary: None,
        problems: Vec::new(),
    };
    let mut read = ReadSoFar::default();
    for line in numbered_lines(input) {
        let line = match line {
            Ok(line) => line,
            Err(e) => {
                run.problems
                    .push(format!("{}: cannot read: {e}", path.display()));
                break;
            }
        };
        let at = format!("{}:{}", path.display(), line.number);
        match line
            .text
            .and_then(|text| read_record(&mut run, &mut read, line.number, &text))
        {
            Ok(()) => {}
            Err(problem) => run.problems.push(format!("{at}: {problem}")),
        }
        // A report stopped by Ctrl-C reads no further (nothing is reported then).
        if crate::interrupt::stopped() {
            break;
        }
    }
    if run.header.is_none() && !read.header_refused {
        run.problems
            .push(format!("{}: no header record", path.display()));
    }
    Ok(run)
}

/// What the lines read so far hold that a later line is checked against.
#[derive(Debug, Default)]
struct ReadSoFar {
    /// The line of the header read.
    header_line: Option<usize>,
    /// Whether a header line was refused (then the run has none, which that problem says).
    header_refused: bool,
    /// The line of a record that comes after the header (test, train, summary), if any.
    first_record_line: Option<usize>,
    /// The line of each test id read.
    test_lines: HashMap<usize, usize>,
}

/// Adds line `number`'s record to `run`, or says why it is not read.
fn read_record(
    run: &mut RunFile,
    read: &mut ReadSoFar,
    number: usize,
    text: &str,
) -> Result<(), String> {
    let value: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let kind = value
        .get("type")
        .and_then(Value::as_str)
        .ok_or("no \"type\" field")?
        .to_owned();
    let record: Record =
        serde_json::from_value(value).map_err(|e| format!("bad {kind} record: {e}"))?;
    match record {
        Record::Header(header) => {
            let checked = match (read.header_line, read.first_record_line) {
                (Some(first), _) => Err(format!(
                    "a second header (the run's is line {first}): not read"
                )),
                (None, Some(record)) => Err(format!(
                    "a header after the run's records (line {record}): a run's header is its \
                     first record; not read"
                )),
                (None, None) => header_problem(&header),
            };
            if let Err(problem) = checked {
                read.header_refused |= read.header_line.is_none();
                return Err(problem);
            }
            read.header_line = Some(number);
            run.header = Some(RunHeader::of(&header));
        }
        Record::Test(test) => {
            test_problem(&test)?;
            if let Some(first) = read.test_lines.get(&test.id) {
                return Err(format!(
                    "test {} again (first on line {first}): not read",
                    test.id
                ));
            }
            read.test_lines.insert(test.id, number);
            read.first_record_line.get_or_insert(number);
            if test.beyond_budget {
                run.beyond_budget.push(test);
            } else {
                run.tests.push(test);
            }
        }
        Record::Train(train) => {
            read.first_record_line.get_or_insert(number);
            run.train_ms += train.train_ms;
        }
        Record::Summary(summary) => {
            read.first_record_line.get_or_insert(number);
            run.summary = Some(summary);
        }
        // Records of kinds the report does not use are skipped.
        _ => {}
    }
    Ok(())
}

/// What is wrong with a header's settings that the report reads, if anything: `config` must be
/// an object, and the map size, failure threshold and speed limit, when given as numbers, within
/// the ranges `wogan run` accepts. (Fields of another type read as absent: older layouts.)
fn header_problem(header: &Header) -> Result<(), String> {
    let config = &header.config;
    if !config.is_object() {
        return Err(format!(
            "bad header record: config: {}, not an object",
            json_type(config)
        ));
    }
    let checks = [
        ("road", "map_size_m", f64::MIN_POSITIVE, MAX_MAP_SIZE_M),
        ("sim", "oob_tolerance", 0.0, 1.0),
        ("sim", "speed_limit_kmh", 0.1, 300.0),
    ];
    for (section, field, min, max) in checks {
        let Some(value) = config.get(section).and_then(|s| s.get(field)) else {
            continue;
        };
        if let Some(v) = value.as_f64() {
            if !(min..=max).contains(&v) {
                let range = if min == f64::MIN_POSITIVE {
                    format!("above 0 and at most {max}")
                } else {
                    format!("from {min} to {max}")
                };
                return Err(format!(
                    "bad header record: config.{section}.{field} must be {range} (got {})",
                    shown(v)
                ));
            }
        }
    }
    Ok(())
}

/// What is wrong with a test record's values, if anything: a max BOLP in `[0, 1]` (`null` only
/// for a drive that ended in ERROR) and a simulated time from 0 to the simulator's bound.
fn test_problem(test: &TestRecord) -> Result<(), String> {
    let result = &test.execution.result;
    let bolp = result.max_bolp;
    if bolp.is_nan() {
        if result.outcome != Outcome::Error {
            return Err(format!(
                "bad test record: max_bolp is null in a {} drive (only an ERROR may lack it)",
                result.outcome.name()
            ));
        }
    } else if !(0.0..=1.0).contains(&bolp) {
        return Err(format!(
            "bad test record: max_bolp must be from 0 to 1 (got {})",
            shown(bolp)
        ));
    }
    let time = result.sim_time_s;
    if !time.is_nan() && !(0.0..=MAX_SIM_TIME_S).contains(&time) {
        return Err(format!(
            "bad test record: sim_time_s must be from 0 to {MAX_SIM_TIME_S} (got {})",
            shown(time)
        ));
    }
    Ok(())
}

/// The JSON type of `value`, as a message names it.
fn json_type(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

impl RunHeader {
    /// Why this run's roads cannot be driven again when it is an executor's run: its drives were
    /// the executor's, which wogan never starts from a file.
    pub fn executor_run(&self) -> Option<String> {
        let executor = self.settings.executor.as_ref()?;
        let command = executor
            .command
            .as_deref()
            .unwrap_or("its command is not recorded");
        Some(format!(
            "its roads were driven by an external executor ({command}), which wogan never starts \
             from a file; wogan's own simulator would not give that executor's drives"
        ))
    }

    /// The simulation settings and the driver to drive this run's tests again: its header's
    /// `config.sim` and `config.driver` read as every source of settings is read
    /// ([`checked_settings`]: laid over the driver's defaults, every range checked); `weights`
    /// are the DAVE-2 weights the run used when not the built-in ones. Refused, saying why, for
    /// an executor's run (its drives were the executor's, which wogan never starts from a file),
    /// a driver wogan does not start or load from a file, and a setting out of its range.
    pub fn drive_settings(&self, weights: Option<&Path>) -> Result<(SimConfig, DriverConfig)> {
        if let Some(why) = self.executor_run() {
            bail!("{why}");
        }
        let Some(kind) = self.driver else {
            bail!("the run's header names no driver of wogan's");
        };
        if !self.config.is_object() {
            bail!("the run's header, config: not an object");
        }
        // Runs of wogan before `driver` was a section of its own kept the driver's tuning in
        // `sim.beamng_ai` or `sim.dave2`: read as the driver's section, as a config file's is.
        let mut sim = self.config.get("sim").cloned();
        let mut driver = self.config.get("driver").cloned();
        if let Some(serde_json::Value::Object(fields)) = &mut sim {
            for (old, old_kind) in [
                ("beamng_ai", DriverKind::BeamNgAiProxy),
                ("dave2", DriverKind::Dave2Proxy),
            ] {
                if let Some(section) = fields.remove(old) {
                    if old_kind == kind && driver.is_none() {
                        driver = Some(section);
                    }
                }
            }
        }
        checked_settings(
            SettingsSource::RunHeader,
            kind,
            sim.as_ref(),
            driver.as_ref(),
            DriverInputs {
                weights,
                ..DriverInputs::default()
            },
            |sim| sim,
        )
    }

    /// The fields of a run's header record.
    pub fn of(header: &Header) -> Self {
        let settings = HeaderSettings::of(&header.config);
        RunHeader {
            algorithm: header.algorithm.clone(),
            // An executor's run drove no driver of wogan's: the simulator is the executor's.
            simulator: match &settings.executor {
                Some(executor) => executor.label(),
                None => header.driver.name().to_owned(),
            },
            fitness: Some(header.fitness),
            seed: header.seed,
            oob_tolerance: settings.sim.oob_tolerance,
            speed_limit_kmh: settings.sim.speed_limit_kmh,
            map_size_m: settings.road.map_size_m.unwrap_or(200.0),
            driver: match settings.executor {
                Some(_) => None,
                None => header.driver.driver(),
            },
            config: header.config.clone(),
            version: header.version.clone(),
            settings,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use road_sim::Outcome;

    fn read_text(name: &str, text: &str) -> RunFile {
        let path =
            std::env::temp_dir().join(format!("wogan-run-file-{}-{name}", std::process::id()));
        std::fs::write(&path, text).expect("scratch file");
        let run = read_run(&path).expect("readable");
        let _ = std::fs::remove_file(&path);
        run
    }

    #[test]
    fn error_tests_with_null_measures_are_read() {
        let run = read_text(
            "nulls",
            concat!(
                r#"{"type":"header","version":"0.1.0","seed":7,"algorithm":"random","oracle":"beamng-ai-proxy","fitness":"bolp","config":{"sim":{"oob_tolerance":0.5,"speed_limit_kmh":70.0}}}"#,
                "\n",
                r#"{"type":"test","id":1,"phase":"random","fitness":null,"predicted_fitness":null,"invalid_candidates":0,"generation_ms":0.5,"curvature":[0.0],"road_points":[[1.0,2.0]],"outcome":"ERROR","reason":"non_finite_physics_state","max_bolp":null,"min_lane_distance_m":2.0,"fitness_distance":0.0,"sim_time_s":1.0,"execution_ms":1.0,"MAX_CURV":null,"DIR_COV":0.0,"STD_SA":0.0,"MEAN_LP":2.0,"MAX_LP":2.0}"#,
                "\n\n",
                r#"{"type":"train","analyzer_loss":1.0,"critic_loss":1.0,"generator_loss":1.0,"wasserstein_estimate":0.0,"train_ms":2.5,"tests":8}"#,
                "\n"
            ),
        );
        assert!(run.problems.is_empty(), "{:?}", run.problems);
        let header = run.header.expect("a header");
        assert_eq!(header.oob_tolerance, Some(0.5));
        assert_eq!(header.speed_limit_kmh, Some(70.0));
        assert_eq!(header.simulator, "beamng-ai-proxy");
        assert_eq!(header.seed, Some(7));
        assert_eq!(run.tests.len(), 1);
        assert!(!run.tests[0].failed());
        assert!(run.tests[0].fitness.is_nan());
        assert_eq!(run.train_ms, 2.5);
        assert!(run.summary.is_none());
    }

    #[test]
    fn only_failing_roads_are_kept_for_a_report() {
        let mut run = RunFile {
            path: "run.jsonl".into(),
            header: None,
            tests: [Outcome::Pass, Outcome::Fail, Outcome::Error]
                .iter()
                .enumerate()
                .map(|(i, &outcome)| TestRecord::example(i + 1, outcome, 0))
                .collect(),
            beyond_budget: vec![TestRecord::example(4, Outcome::Fail, 0)],
            train_ms: 0.0,
            pipeline_invalid: 0,
            summary: None,
            problems: Vec::new(),
        };
        run.drop_unused_roads();
        let kept: Vec<usize> = run
            .tests
            .iter()
            .chain(&run.beyond_budget)
            .map(|t| t.execution.road_points.len() + t.execution.curvature.len())
            .collect();
        assert_eq!(kept, [0, 3, 0, 0]);
        assert_eq!(run.failures(), 1);
        assert_eq!(run.tests[0].execution.result.max_bolp, 0.5);
    }

    #[test]
    fn bad_lines_and_a_missing_header_are_problems_not_panics() {
        let run = read_text("bad", "[1, 2]\n{\"type\":\"test\",\"id\":-1}\nnot json\n");
        assert_eq!(run.problems.len(), 4, "{:?}", run.problems);
        assert!(run.problems[0].contains("-bad:1: no \"type\" field"));
        assert!(run.problems[1].contains(":2: bad test record"));
        assert!(run.problems[2].contains(":3: not JSON"));
        assert!(run.problems[3].ends_with("no header record"));
    }
}
