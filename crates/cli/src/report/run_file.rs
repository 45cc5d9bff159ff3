//! Reading the JSON lines of one `wogan run`: its header, test records and (when the run finished)
//! its summary. Bad lines are collected with their file and line number, never fatal.

use crate::json_lines::{numbered_lines, open_input};
use anyhow::Result;
use road_sim::Point;
use serde::Deserialize;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// What identifies a run's configuration for grouping repetitions.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RunKey {
    /// Search algorithm (`wogan`, `random`).
    pub algorithm: String,
    /// Driver under test.
    pub oracle: String,
    /// Fitness function (`bolp`, `distance`).
    pub fitness: String,
    /// BOLP above which a drive fails, as text to compare exactly.
    pub oob_tolerance: String,
    /// Speed limit in km/h, as text to compare exactly.
    pub speed_limit_kmh: String,
    /// How WOGAN chose its tests (`decay 0.9816`, `decay 0.95, mutants 0.25`); empty for random
    /// search and for headers without these settings.
    pub acceptance: String,
}

impl RunKey {
    /// A one-line description, e.g. `wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob
    /// 0.85 / 70 km/h`.
    pub fn label(&self) -> String {
        let acceptance = if self.acceptance.is_empty() {
            String::new()
        } else {
            format!(" / {}", self.acceptance)
        };
        format!(
            "{} / {} / fitness {}{acceptance} / oob {} / {} km/h",
            self.algorithm, self.oracle, self.fitness, self.oob_tolerance, self.speed_limit_kmh
        )
    }
}

/// The header record's fields the report uses.
#[derive(Debug, Clone)]
pub struct Header {
    /// The configuration the run is grouped by.
    pub key: RunKey,
    /// The run's seed.
    pub seed: Option<u64>,
    /// BOLP failure threshold.
    pub oob_tolerance: Option<f64>,
    /// Side of the map, metres.
    pub map_size_m: f64,
}

/// One executed test, as the report and export need it.
#[derive(Debug, Clone, Deserialize)]
pub struct TestRecord {
    /// The test's number in the run.
    pub id: u64,
    /// `random` or `wogan`.
    #[serde(default)]
    pub phase: Option<String>,
    /// Fitness in [0, 1], higher is closer to failure.
    #[serde(default)]
    pub fitness: Option<f64>,
    /// Invalid candidates rejected before this test.
    #[serde(default)]
    pub invalid_candidates: Option<u64>,
    /// Valid candidates the analyzer ranked to choose this test (0 when it did not choose it).
    #[serde(default)]
    pub ranked_candidates: Option<u64>,
    /// Time to generate the test, milliseconds.
    #[serde(default)]
    pub generation_ms: Option<f64>,
    /// The road's defining points.
    pub road_points: Vec<Point>,
    /// `PASS`, `FAIL` or `ERROR`.
    pub outcome: String,
    /// Largest body-out-of-lane share during the drive.
    #[serde(default)]
    pub max_bolp: Option<f64>,
    /// Simulated time of the drive, seconds.
    #[serde(default)]
    pub sim_time_s: Option<f64>,
    /// Wall time of the drive, milliseconds.
    #[serde(default)]
    pub execution_ms: Option<f64>,
    /// Competition feature MAX_CURV, 1/m.
    #[serde(rename = "MAX_CURV", default)]
    pub max_curv: Option<f64>,
    /// Competition feature DIR_COV (k/26).
    #[serde(rename = "DIR_COV", default)]
    pub dir_cov: Option<f64>,
    /// Competition feature STD_SA, degrees.
    #[serde(rename = "STD_SA", default)]
    pub std_sa: Option<f64>,
    /// Competition feature MEAN_LP, metres.
    #[serde(rename = "MEAN_LP", default)]
    pub mean_lp: Option<f64>,
    /// Competition feature MAX_LP, metres.
    #[serde(rename = "MAX_LP", default)]
    pub max_lp: Option<f64>,
}

impl TestRecord {
    /// Whether the car left its lane.
    pub fn failed(&self) -> bool {
        self.outcome == "FAIL"
    }
}

/// The summary record's fields the report and export use.
#[derive(Debug, Clone, Deserialize)]
pub struct Summary {
    /// Invalid candidates over the whole run.
    #[serde(default)]
    pub invalid_candidates: Option<u64>,
    /// Generation time, seconds.
    #[serde(default)]
    pub generation_s: Option<f64>,
    /// Training time, seconds.
    #[serde(default)]
    pub training_s: Option<f64>,
    /// Simulation wall time, seconds.
    #[serde(default)]
    pub simulation_s: Option<f64>,
    /// Whether Ctrl-C ended the run.
    #[serde(default)]
    pub interrupted: Option<bool>,
}

/// One run read from its file.
#[derive(Debug, Clone)]
pub struct RunFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// The header, when the file had one.
    pub header: Option<Header>,
    /// The executed tests, in file order.
    pub tests: Vec<TestRecord>,
    /// Training time from the `train` records, milliseconds.
    pub train_ms: f64,
    /// The summary; `None` for a truncated run.
    pub summary: Option<Summary>,
    /// `file:line: problem` for each line that could not be read.
    pub problems: Vec<String>,
}

impl RunFile {
    /// Number of failing tests.
    pub fn failures(&self) -> usize {
        self.tests.iter().filter(|t| t.failed()).count()
    }
}

/// Reads a run; `Err` only when the file cannot be opened.
pub fn read_run(path: &Path) -> Result<RunFile> {
    let input = open_input(Some(path))?;
    let mut run = RunFile {
        path: path.to_path_buf(),
        header: None,
        tests: Vec::new(),
        train_ms: 0.0,
        summary: None,
        problems: Vec::new(),
    };
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
        match line.text.and_then(|text| read_record(&mut run, &text)) {
            Ok(()) => {}
            Err(problem) => run.problems.push(format!("{at}: {problem}")),
        }
    }
    if run.header.is_none() {
        run.problems
            .push(format!("{}: no header record", path.display()));
    }
    Ok(run)
}

/// Adds one line's record to `run`.
fn read_record(run: &mut RunFile, text: &str) -> Result<(), String> {
    let value: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let kind = value
        .get("type")
        .and_then(Value::as_str)
        .ok_or("no \"type\" field")?;
    match kind {
        "header" => {
            run.header = Some(read_header(&value)?);
        }
        "test" => {
            let test: TestRecord =
                serde_json::from_value(value).map_err(|e| format!("bad test record: {e}"))?;
            run.tests.push(test);
        }
        "train" => {
            run.train_ms += value.get("train_ms").and_then(Value::as_f64).unwrap_or(0.0);
        }
        "summary" => {
            let summary: Summary =
                serde_json::from_value(value).map_err(|e| format!("bad summary record: {e}"))?;
            run.summary = Some(summary);
        }
        // Records of kinds the report does not use (e.g. "error") are skipped.
        _ => {}
    }
    Ok(())
}

/// WOGAN's settings for choosing tests, which change what a run finds as much as the fitness does:
/// the acceptance decay (to 4 decimals, so a matched default and the same value typed by hand
/// group together) and the mutation share when there are mutants.
fn acceptance(algorithm: &str, header: &Value) -> String {
    let setting = |name: &str| {
        header
            .pointer(&format!("/config/search/wogan/{name}"))
            .and_then(Value::as_f64)
    };
    let decay = match setting("target_decay") {
        Some(decay) if algorithm == "wogan" => decay,
        _ => return String::new(),
    };
    let decay = format!("{decay:.4}");
    let decay = decay.trim_end_matches('0').trim_end_matches('.');
    match setting("mutation/share") {
        Some(share) if share > 0.0 => format!("decay {decay}, mutants {share}"),
        _ => format!("decay {decay}"),
    }
}

/// Reads the header's grouping fields.
fn read_header(value: &Value) -> Result<Header, String> {
    let text = |v: Option<&Value>| match v {
        Some(Value::String(s)) => s.clone(),
        Some(Value::Null) | None => "?".to_owned(),
        Some(other) => other.to_string(),
    };
    let sim = value.pointer("/config/sim");
    let oob = sim.and_then(|s| s.get("oob_tolerance"));
    let speed = sim.and_then(|s| s.get("speed_limit_kmh"));
    let algorithm = value
        .get("algorithm")
        .and_then(Value::as_str)
        .ok_or("header without \"algorithm\"")?;
    Ok(Header {
        key: RunKey {
            algorithm: algorithm.to_owned(),
            oracle: text(value.get("oracle")),
            fitness: text(value.get("fitness")),
            oob_tolerance: text(oob),
            speed_limit_kmh: text(speed),
            acceptance: acceptance(algorithm, value),
        },
        seed: value.get("seed").and_then(Value::as_u64),
        oob_tolerance: oob.and_then(Value::as_f64),
        map_size_m: value
            .pointer("/config/road/map_size_m")
            .and_then(Value::as_f64)
            .unwrap_or(200.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
                r#"{"type":"header","seed":7,"algorithm":"random","oracle":"o","fitness":"bolp","config":{"sim":{"oob_tolerance":0.5,"speed_limit_kmh":70.0}}}"#,
                "\n",
                r#"{"type":"test","id":1,"fitness":null,"road_points":[[1.0,2.0]],"outcome":"ERROR","max_bolp":null,"MAX_CURV":null}"#,
                "\n\n",
                r#"{"type":"train","train_ms":2.5}"#,
                "\n"
            ),
        );
        assert!(run.problems.is_empty(), "{:?}", run.problems);
        let header = run.header.expect("a header");
        assert_eq!(header.key.oob_tolerance, "0.5");
        assert_eq!(header.key.speed_limit_kmh, "70.0");
        assert_eq!(header.seed, Some(7));
        assert_eq!(run.tests.len(), 1);
        assert!(!run.tests[0].failed());
        assert_eq!(run.train_ms, 2.5);
        assert!(run.summary.is_none());
    }

    #[test]
    fn wogan_runs_are_grouped_by_how_they_chose_tests() {
        let key_of = |algorithm: &str, wogan: &str| {
            let header: Value = serde_json::from_str(&format!(
                r#"{{"type":"header","algorithm":"{algorithm}","config":{{"search":{{"wogan":{wogan}}}}}}}"#
            ))
            .unwrap();
            read_header(&header).unwrap().key
        };
        let matched = key_of("wogan", r#"{"target_decay":0.9816321972824553}"#);
        assert_eq!(matched.acceptance, "decay 0.9816");
        assert!(matched.label().contains("fitness ? / decay 0.9816 / oob"));
        let paper = r#"{"target_decay":0.95,"mutation":{"share":0.0}}"#;
        assert_eq!(key_of("wogan", paper).acceptance, "decay 0.95");
        let mutants = r#"{"target_decay":0.95,"mutation":{"share":0.25}}"#;
        assert_eq!(
            key_of("wogan", mutants).acceptance,
            "decay 0.95, mutants 0.25"
        );
        // Random search ignores these settings, and older headers lack them.
        assert_eq!(key_of("random", mutants).acceptance, "");
        let old = key_of("wogan", "{}");
        assert_eq!(old.acceptance, "");
        assert!(old.label().contains("fitness ? / oob"));
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
