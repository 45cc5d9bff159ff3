//! Reading the JSON lines of one `wogan run` (through [`crate::files::records`]): its header, test
//! records and (when the run finished) its summary. Bad lines are collected with their file and
//! line number, never fatal.

use crate::files::json_lines::{numbered_lines, open_input};
pub use crate::files::records::TestRecord;
use crate::files::records::{Header, Record, SummaryRecord};
use anyhow::Result;
use road_sim::DriverKind;
use serde_json::Value;
use std::path::{Path, PathBuf};
use wogan_core::MutationConfig;

/// What identifies a run's configuration for grouping repetitions.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RunKey {
    /// Search algorithm (`wogan`, `random`).
    pub algorithm: String,
    /// Driver under test.
    pub driver: String,
    /// Fitness function (`bolp`, `distance`).
    pub fitness: String,
    /// BOLP above which a drive fails, as text to compare exactly.
    pub oob_tolerance: String,
    /// Speed limit in km/h, as text to compare exactly.
    pub speed_limit_kmh: String,
    /// How WOGAN chose its tests (`decay 0.9816`, `decay 0.95, mutants 0.25`); empty for random
    /// search and for headers without these settings.
    pub acceptance: String,
    /// The roads' shape when it is not the paper's five curvature values 15 m apart
    /// (`8 x 15 m roads`), with a least turn when one was asked for; empty for the paper's and
    /// for runs that do not say.
    pub roads: String,
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
        let roads = if self.roads.is_empty() {
            String::new()
        } else {
            format!(" / {}", self.roads)
        };
        format!(
            "{} / {} / fitness {}{acceptance}{roads} / oob {} / {} km/h",
            self.algorithm, self.driver, self.fitness, self.oob_tolerance, self.speed_limit_kmh
        )
    }

    /// What a drive is judged under, which runs compared as one group must share: the driver,
    /// the failure threshold and the speed limit (`driver dave2-proxy, oob 0.1, 30.0 km/h`).
    pub fn conditions(&self) -> String {
        format!(
            "driver {}, oob {}, {} km/h",
            self.driver, self.oob_tolerance, self.speed_limit_kmh
        )
    }
}

/// The header's fields the report uses.
#[derive(Debug, Clone)]
pub struct RunHeader {
    /// The configuration the run is grouped by.
    pub key: RunKey,
    /// The run's seed.
    pub seed: Option<u64>,
    /// BOLP failure threshold.
    pub oob_tolerance: Option<f64>,
    /// Side of the map, metres.
    pub map_size_m: f64,
    /// The driver under test.
    pub driver: DriverKind,
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

/// Reads a run; `Err` only when the file cannot be opened.
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
        .ok_or("no \"type\" field")?
        .to_owned();
    let record: Record =
        serde_json::from_value(value).map_err(|e| format!("bad {kind} record: {e}"))?;
    match record {
        Record::Header(header) => run.header = Some(read_header(&header)),
        Record::Test(test) if test.beyond_budget => run.beyond_budget.push(test),
        Record::Test(test) => run.tests.push(test),
        Record::Train(train) => run.train_ms += train.train_ms,
        Record::Summary(summary) => run.summary = Some(summary),
        // Records of kinds the report does not use are skipped.
        _ => {}
    }
    Ok(())
}

/// `value` to at most 4 decimals, without trailing zeros: settings written from f32 and a
/// matched decay group with the same value typed by hand.
fn four_decimals(value: f64) -> String {
    let text = format!("{value:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// WOGAN's settings for choosing tests, which change what a run finds as much as the fitness does:
/// the acceptance decay (to 4 decimals, so a matched default and the same value typed by hand
/// group together), the mutation share when there are mutants (and their step when it is not the
/// default, and their shifts), and rounds of several tests.
fn acceptance(algorithm: &str, config: &Value) -> String {
    let setting = |name: &str| {
        config
            .pointer(&format!("/search/wogan/{name}"))
            .and_then(Value::as_f64)
    };
    let decay = match setting("target_decay") {
        Some(decay) if algorithm == "wogan" => decay,
        _ => return String::new(),
    };
    let decay = four_decimals(decay);
    let mut text = format!("decay {decay}");
    if let Some(share) = setting("mutation/share").filter(|&s| s > 0.0) {
        text.push_str(&format!(", mutants {share}"));
        // Older headers and the default step say nothing; another step finds other failures.
        let default_step = four_decimals(f64::from(MutationConfig::default().max_step));
        if let Some(step) = setting("mutation/max_step").map(four_decimals) {
            if step != default_step {
                text.push_str(&format!(" of steps up to {step}"));
            }
        }
        if let Some(places) = setting("mutation/shift_places").filter(|&p| p > 0.0) {
            text.push_str(&format!(" shifted up to {places} places"));
        }
    }
    for (rule, name) in [("novelty", "novelty"), ("shape_novelty", "shape novelty")] {
        if let Some(distance) = setting(&format!("{rule}/distance")).filter(|&d| d > 0.0) {
            // Written from f32: 4 decimals, as the decay.
            text.push_str(&format!(", {name} {}", four_decimals(distance)));
            if let Some(fitness) = setting(&format!("{rule}/min_fitness")).filter(|&f| f > 0.0) {
                text.push_str(&format!(" from fitness {fitness}"));
            }
            if let Some(allowed) =
                setting(&format!("{rule}/allowed_neighbours")).filter(|&n| n > 0.0)
            {
                text.push_str(&format!(" allowing {allowed}"));
            }
        }
    }
    if let Some(quota) = setting("niches/quota").filter(|&q| q > 0.0) {
        let short = |name: &str| four_decimals(setting(name).unwrap_or(0.0));
        text.push_str(&format!(
            ", niches of {quota} within {} seeded {} apart",
            short("niches/radius"),
            short("niches/distance")
        ));
        if let Some(patience) = setting("niches/patience").filter(|&p| p > 0.0) {
            text.push_str(&format!(" or after {patience} tests"));
        }
        let between = config.pointer("/search/wogan/niches/between");
        if between.and_then(Value::as_str) == Some("random") {
            text.push_str(", random between");
        }
        if let Some(stale) = setting("niches/stale").filter(|&s| s > 0.0) {
            text.push_str(&format!(", closed after {stale} repeats"));
        }
    }
    // Rounds of several tests change which tests are chosen (one job is the paper's loop).
    let jobs = config.pointer("/search/jobs").and_then(Value::as_u64);
    if let Some(jobs) = jobs.filter(|&j| j > 1) {
        text.push_str(&format!(", rounds of {jobs}"));
        let rule = config.pointer("/search/wogan/round_acceptance");
        if rule.and_then(Value::as_str) == Some("continue") {
            text.push_str(" continued");
        }
    }
    text
}

/// The roads' shape unless it is the paper's (five curvature values, 15 m apart) or unknown, their
/// placement unless it is the paper's (from the bottom centre), how the search compared them
/// unless by the heading profile, and their least turn unless any road was tested.
fn roads(config: &Value) -> String {
    let points = config.pointer("/curvature_points").and_then(Value::as_u64);
    let step_m = config.pointer("/road/step_m").and_then(Value::as_f64);
    let shape = match (points, step_m) {
        (Some(5), Some(15.0)) => String::new(),
        (Some(points), Some(step_m)) => format!("{points} x {step_m} m roads"),
        _ => String::new(),
    };
    let placed = match config.pointer("/road/placement").and_then(Value::as_str) {
        Some("fitted") if shape.is_empty() => "fitted roads".to_owned(),
        Some("fitted") => format!("{shape}, fitted"),
        _ => shape,
    };
    // Older headers and the default (the heading profile) say nothing.
    let compared = match config.pointer("/road_shape").and_then(Value::as_str) {
        Some("directions") if placed.is_empty() => "roads compared by directions".to_owned(),
        Some("directions") => format!("{placed}, compared by directions"),
        _ => placed,
    };
    // Older headers and the default (any road) say nothing.
    match config.pointer("/min_road_turn_rad").and_then(Value::as_f64) {
        Some(turn) if turn > 0.0 && compared.is_empty() => format!("roads turning {turn} rad"),
        Some(turn) if turn > 0.0 => format!("{compared}, turning {turn} rad"),
        _ => compared,
    }
}

/// A setting as a [`RunKey`] holds it: a number as the number it is (so that a limit written `70`
/// groups with `70.0`), `?` when unknown.
pub fn key_text(value: Option<&Value>) -> String {
    match value {
        Some(Value::String(s)) => s.clone(),
        Some(Value::Number(n)) => n
            .as_f64()
            .map_or_else(|| n.to_string(), |f| Value::from(f).to_string()),
        Some(Value::Null) | None => "?".to_owned(),
        Some(other) => other.to_string(),
    }
}

/// Reads the header's grouping fields. The configuration is read by path, so that runs written
/// by older versions (other layouts) still group.
fn read_header(header: &Header) -> RunHeader {
    let text = key_text;
    let sim = header.config.get("sim");
    let oob = sim.and_then(|s| s.get("oob_tolerance"));
    let speed = sim.and_then(|s| s.get("speed_limit_kmh"));
    let algorithm = header.algorithm.clone();
    RunHeader {
        key: RunKey {
            // An executor's run drove no driver of wogan's: the simulator is the executor's.
            driver: if header.config.get("executor").is_some_and(Value::is_string) {
                "executor".to_owned()
            } else {
                header.driver.name().to_owned()
            },
            fitness: header.fitness.name().to_owned(),
            oob_tolerance: text(oob),
            speed_limit_kmh: text(speed),
            acceptance: acceptance(&algorithm, &header.config),
            roads: roads(&header.config),
            algorithm,
        },
        seed: header.seed,
        oob_tolerance: oob.and_then(Value::as_f64),
        map_size_m: header
            .config
            .pointer("/road/map_size_m")
            .and_then(Value::as_f64)
            .unwrap_or(200.0),
        driver: header.driver,
        config: header.config.clone(),
        version: header.version.clone(),
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
        assert_eq!(header.key.oob_tolerance, "0.5");
        assert_eq!(header.key.speed_limit_kmh, "70.0");
        assert_eq!(
            header.key.conditions(),
            "driver beamng-ai-proxy, oob 0.5, 70.0 km/h"
        );
        assert_eq!(header.seed, Some(7));
        assert_eq!(run.tests.len(), 1);
        assert!(!run.tests[0].failed());
        assert!(run.tests[0].fitness.is_nan());
        assert_eq!(run.train_ms, 2.5);
        assert!(run.summary.is_none());
    }

    #[test]
    fn wogan_runs_are_grouped_by_how_they_chose_tests() {
        let key_of = |algorithm: &str, wogan: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"{algorithm}","oracle":"dave2-proxy","fitness":"distance","config":{{"search":{{"wogan":{wogan}}}}}}}"#
            ))
            .unwrap();
            read_header(&header).key
        };
        let matched = key_of("wogan", r#"{"target_decay":0.9816321972824553}"#);
        assert_eq!(matched.acceptance, "decay 0.9816");
        assert!(matched
            .label()
            .contains("fitness distance / decay 0.9816 / oob"));
        let paper = r#"{"target_decay":0.95,"mutation":{"share":0.0}}"#;
        assert_eq!(key_of("wogan", paper).acceptance, "decay 0.95");
        let mutants = r#"{"target_decay":0.95,"mutation":{"share":0.25}}"#;
        assert_eq!(
            key_of("wogan", mutants).acceptance,
            "decay 0.95, mutants 0.25"
        );
        let shifted = r#"{"target_decay":0.95,"mutation":{"share":0.5,"shift_places":3}}"#;
        assert_eq!(
            key_of("wogan", shifted).acceptance,
            "decay 0.95, mutants 0.5 shifted up to 3 places"
        );
        // The default step as a header writes it from f32 says nothing; another step is named.
        let default_step =
            r#"{"target_decay":0.95,"mutation":{"share":0.5,"max_step":0.15000000596046448}}"#;
        assert_eq!(
            key_of("wogan", default_step).acceptance,
            "decay 0.95, mutants 0.5"
        );
        let larger_steps =
            r#"{"target_decay":0.95,"mutation":{"share":0.5,"max_step":0.4000000059604645}}"#;
        assert_eq!(
            key_of("wogan", larger_steps).acceptance,
            "decay 0.95, mutants 0.5 of steps up to 0.4"
        );
        let no_mutants = r#"{"target_decay":0.95,"mutation":{"share":0,"shift_places":3}}"#;
        assert_eq!(key_of("wogan", no_mutants).acceptance, "decay 0.95");
        // Random search ignores these settings, and older headers lack them.
        assert_eq!(key_of("random", mutants).acceptance, "");
        let old = key_of("wogan", "{}");
        assert_eq!(old.acceptance, "");
        assert!(old.label().contains("fitness distance / oob"));
    }

    #[test]
    fn wogan_runs_in_rounds_group_apart_from_one_test_at_a_time() {
        let key_of = |search: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"wogan","oracle":"dave2-proxy","fitness":"bolp","config":{{"search":{search}}}}}"#
            ))
            .unwrap();
            read_header(&header).key.acceptance
        };
        let one = r#"{"jobs":1,"wogan":{"target_decay":0.95}}"#;
        assert_eq!(key_of(one), "decay 0.95");
        let two = r#"{"jobs":2,"wogan":{"target_decay":0.95,"round_acceptance":"continue"}}"#;
        assert_eq!(key_of(two), "decay 0.95, rounds of 2 continued");
        let four = r#"{"jobs":4,"wogan":{"target_decay":0.95,"round_acceptance":"restart"}}"#;
        assert_eq!(key_of(four), "decay 0.95, rounds of 4");
    }

    #[test]
    fn novelty_road_shape_and_least_turn_group_runs_apart() {
        let key_of = |config: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"wogan","oracle":"beamng-ai-proxy","fitness":"bolp","config":{config}}}"#
            ))
            .unwrap();
            read_header(&header).key
        };
        let paper = key_of(
            r#"{"curvature_points":5,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"novelty":{"distance":0.0}}}}"#,
        );
        assert_eq!(
            (paper.acceptance.as_str(), paper.roads.as_str()),
            ("decay 0.95", "")
        );
        let preset = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"novelty":{"distance":0.2,"min_fitness":0.85}}}}"#,
        );
        assert_eq!(
            preset.acceptance,
            "decay 0.95, novelty 0.2 from fitness 0.85"
        );
        assert_eq!(preset.roads, "8 x 15 m roads");
        assert!(preset
            .label()
            .ends_with("novelty 0.2 from fitness 0.85 / 8 x 15 m roads / oob ? / ? km/h"));
        assert_ne!(paper, preset);
        let shapes = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"novelty":{"distance":0.1},"shape_novelty":{"distance":0.5,"min_fitness":0.85}}}}"#,
        );
        assert_eq!(
            shapes.acceptance,
            "decay 0.95, novelty 0.1, shape novelty 0.5 from fitness 0.85"
        );
        let crowded = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"shape_novelty":{"distance":0.5,"min_fitness":0.85,"allowed_neighbours":4}}}}"#,
        );
        assert_eq!(
            crowded.acceptance,
            "decay 0.95, shape novelty 0.5 from fitness 0.85 allowing 4"
        );
        let niches = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"niches":{"quota":60,"distance":2.5,"radius":0.75,"min_fitness":0.85,"patience":40}}}}"#,
        );
        assert_eq!(
            niches.acceptance,
            "decay 0.95, niches of 60 within 0.75 seeded 2.5 apart or after 40 tests"
        );
        let stale = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"niches":{"quota":60,"distance":2.5,"radius":0.75,"min_fitness":0.85,"patience":0,"between":"random","stale":10,"repeat_distance":0.1}}}}"#,
        );
        assert_eq!(
            stale.acceptance,
            "decay 0.95, niches of 60 within 0.75 seeded 2.5 apart, random between, closed after 10 repeats"
        );
        let fitted = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(fitted.roads, "8 x 15 m roads, fitted");
        let directions = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"road_shape":"directions","search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(
            directions.roads,
            "8 x 15 m roads, fitted, compared by directions"
        );
        let headings = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"road_shape":"headings","search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(headings, fitted);
        let winding = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"road_shape":"headings","min_road_turn_rad":2.5,"search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(winding.roads, "8 x 15 m roads, fitted, turning 2.5 rad");
        let any_road = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"min_road_turn_rad":0.0,"search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(any_road, fitted);
        let paper_roads =
            key_of(r#"{"curvature_points":5,"road":{"step_m":15.0},"min_road_turn_rad":1.0}"#);
        assert_eq!(paper_roads.roads, "roads turning 1 rad");
    }

    #[test]
    fn numbers_group_as_the_numbers_they_are() {
        let key_of = |sim: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"random","oracle":"dave2-proxy","fitness":"distance","config":{{"sim":{sim}}}}}"#
            ))
            .unwrap();
            read_header(&header).key
        };
        let typed = key_of(r#"{"oob_tolerance":0.10,"speed_limit_kmh":30}"#);
        let written = key_of(r#"{"oob_tolerance":0.1,"speed_limit_kmh":30.0}"#);
        assert_eq!(typed, written);
        assert_eq!(typed.conditions(), "driver dave2-proxy, oob 0.1, 30.0 km/h");
        assert_eq!(
            key_of("{}").conditions(),
            "driver dave2-proxy, oob ?, ? km/h"
        );
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
