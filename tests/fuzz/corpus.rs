//! The corpus: real roads, real runs and records of every kind, which cases are made of.

use super::*;

/// Real roads, real runs and records of every kind, read once per campaign. Only files of the
/// repository and values computed from the code go in, so that a seed makes the same cases on
/// every machine.
pub(super) struct Corpus {
    /// Each line of `tests/reference/roads.jsonl`.
    pub(super) roads: Vec<Value>,
    /// Each run of `tests/fixtures`, as its records.
    pub(super) runs: Vec<Vec<Value>>,
    /// Short runs made by the binary under test when the corpus is loaded (6 tests, seed 1, each
    /// driver), exactly as it writes them: what `export` and `replay` accept, so that their cases
    /// reach the commands' work. (The fixtures are of an older layout, which export refuses.)
    pub(super) own_runs: Vec<Vec<Value>>,
    /// A suite of the failing roads of those runs and the fixtures (`wogan suite add`).
    pub(super) suite: Vec<u8>,
    /// A generator file saved by the binary under test (`run --save-generator`, 12 tests).
    pub(super) generator: Vec<u8>,
    /// One record of every kind `wogan` writes or reads.
    pub(super) records: Vec<Value>,
    /// A `simulate --trace` file: the road, then samples.
    pub(super) trace: Vec<Value>,
    /// Every field a `run --config` file may set, at its default, per driver.
    pub(super) config_defaults: Vec<(DriverKind, Value)>,
    /// Weights `--driver-weights` accepts.
    pub(super) weights: Vec<u8>,
}

/// The corpus files the binary under test makes, made once per test process (tests load the
/// corpus at once, and must not make them over each other).
struct OwnFiles {
    runs: Vec<Vec<Value>>,
    suite: Vec<u8>,
    generator: Vec<u8>,
}

fn own_files() -> &'static OwnFiles {
    static FILES: std::sync::OnceLock<OwnFiles> = std::sync::OnceLock::new();
    FILES.get_or_init(|| {
        let (suite, generator) = own_suite_and_generator();
        OwnFiles {
            runs: DriverKind::ALL.into_iter().map(own_run).collect(),
            suite,
            generator,
        }
    })
}

/// A 6-test run of `kind` by the binary under test, as its records.
fn own_run(kind: DriverKind) -> Vec<Value> {
    let dir = scratch_dir(&format!("fuzz-corpus-{}", kind.name()));
    let path = dir.join("run.jsonl");
    let output = Command::new(env!("CARGO_BIN_EXE_wogan"))
        .args([
            "run",
            "--oracle",
            kind.name(),
            "--max-tests",
            "6",
            "--seed",
            "1",
            "--quiet",
        ])
        .arg("--out")
        .arg(&path)
        .output()
        .expect("wogan runs");
    assert!(output.status.success(), "the corpus run of {kind} failed");
    read_json_lines(&path)
}

/// A suite and a generator file made by the binary under test.
fn own_suite_and_generator() -> (Vec<u8>, Vec<u8>) {
    let dir = scratch_dir("fuzz-corpus-generator");
    let wogan = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_wogan"))
            .args(args)
            .current_dir(&dir)
            .output()
            .expect("wogan runs");
        assert!(
            output.status.success(),
            "wogan {args:?} failed making the corpus"
        );
    };
    wogan(&[
        "run",
        "--max-tests",
        "30",
        "--seed",
        "2",
        "--quiet",
        "--out",
        "run.jsonl",
        "--save-generator",
        "gen.json",
    ]);
    wogan(&["suite", "add", "run.jsonl", "--to", "suite.jsonl"]);
    let read = |name: &str| std::fs::read(dir.join(name)).expect("a corpus file");
    (read("suite.jsonl"), read("gen.json"))
}

impl Corpus {
    pub(super) fn load() -> Self {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let roads = read_json_lines(&repo.join("tests/reference/roads.jsonl"));
        let mut fixtures: Vec<PathBuf> = std::fs::read_dir(repo.join("tests/fixtures"))
            .expect("tests/fixtures is readable")
            .map(|entry| entry.expect("a directory entry").path())
            .filter(|path| path.extension().is_some_and(|e| e == "jsonl"))
            .collect();
        // Directory order differs between machines; the seed must make the same cases.
        fixtures.sort();
        let runs: Vec<Vec<Value>> = fixtures.iter().map(|p| read_json_lines(p)).collect();
        let own = own_files();
        let (own_runs, suite, generator) =
            (own.runs.clone(), own.suite.clone(), own.generator.clone());
        assert!(!roads.is_empty() && !runs.is_empty(), "the corpus is empty");
        let trace = synthetic_trace(&roads[0]);
        let records = records_of_every_kind(&runs, &trace);
        let config_defaults = DriverKind::ALL
            .into_iter()
            .map(|kind| (kind, config_defaults(kind)))
            .collect();
        Self {
            roads,
            runs,
            own_runs,
            suite,
            generator,
            records,
            trace,
            config_defaults,
            weights: Dave2Weights::from_seed(1).to_bytes(),
        }
    }

    pub(super) fn config_defaults(&self, kind: DriverKind) -> &Value {
        &self
            .config_defaults
            .iter()
            .find(|(k, _)| *k == kind)
            .expect("defaults for every driver")
            .1
    }
}

pub(super) fn read_json_lines(path: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    text.lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| serde_json::from_str(line).expect("corpus lines are JSON"))
        .collect()
}

/// Every section of a `run --config` file with all its fields: the search's, the driver's
/// simulation preset and the driver's tuning, as the run lays the file over them.
pub(super) fn config_defaults(kind: DriverKind) -> Value {
    let driver = if kind == DriverKind::Dave2Proxy {
        json!(Dave2DriverParams::default())
    } else {
        json!(BeamNgAiParams::default())
    };
    json!({
        "search": RunConfig::default(),
        "sim": CompetitionSetup::of(kind).sim_config(),
        "driver": driver,
    })
}

/// A trace of a drive along `road` in the layout of `simulate --trace`: the road with a centre
/// line of straight pieces about a metre long, and a sample every other point. Made here rather
/// than by the binary so that it is the same on every run (samples hold no timing, but it keeps
/// the corpus free of the code under test).
pub(super) fn synthetic_trace(road: &Value) -> Vec<Value> {
    let points: Vec<[f64; 2]> =
        serde_json::from_value(road["road_points"].clone()).expect("a reference road");
    let mut centre = Vec::new();
    for pair in points.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let steps = (b[0] - a[0]).hypot(b[1] - a[1]).ceil().max(1.0) as usize;
        for s in 0..steps {
            let f = s as f64 / steps as f64;
            centre.push([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]);
        }
    }
    centre.extend(points.last().copied());
    let mut trace =
        vec![json!({"type": "road", "road_points": points, "interpolated_points": centre})];
    for (i, pair) in centre.windows(2).enumerate().step_by(2) {
        let heading = (pair[1][1] - pair[0][1]).atan2(pair[1][0] - pair[0][0]);
        trace.push(json!({
            "type": "sample", "t": i as f64 / 30.0, "x": pair[0][0] + 0.3, "y": pair[0][1],
            "heading": heading, "speed_kmh": 40.0, "steering_deg": 1.5, "bolp": 0.02,
            "dist_left_m": 1.7, "dist_right_m": 2.3,
        }));
    }
    trace
}

/// The first record of each kind in the fixture runs (header, test, train, summary), the trace's
/// road and a sample, and the kinds only `validate`, `simulate` and `train-driver` write.
pub(super) fn records_of_every_kind(runs: &[Vec<Value>], trace: &[Value]) -> Vec<Value> {
    let mut records: Vec<Value> = Vec::new();
    for record in runs.iter().flatten() {
        if !records.iter().any(|r| r["type"] == record["type"]) {
            records.push(record.clone());
        }
    }
    let test = records
        .iter()
        .find(|r| r["type"] == "test")
        .expect("a fixture test record")
        .clone();
    let mut result = test;
    if let Some(fields) = result.as_object_mut() {
        for key in [
            "id",
            "phase",
            "fitness",
            "predicted_fitness",
            "invalid_candidates",
            "ranked_candidates",
            "generation_ms",
            "curvature",
            "road_points",
        ] {
            fields.remove(key);
        }
        fields.insert("type".into(), json!("result"));
        fields.insert("line".into(), json!(1));
    }
    records.extend([
        result,
        json!({"type": "result", "line": 2, "outcome": "INVALID", "reason": "too_sharp",
               "message": "The road is too sharp"}),
        json!({"type": "error", "line": 4, "error": "not JSON"}),
        json!({"type": "verdict", "line": 1, "valid": false, "reason": "outside_map",
               "message": "Not entirely inside the map boundaries"}),
        json!({"type": "verdict", "line": 2, "valid": true, "reason": null, "message": "",
               "interpolated_points": [[100.0, 10.0], [100.0, 11.0]]}),
        json!({"type": "driver", "weights": "dave2.bin", "config": {"seed": 1, "epochs": 4},
               "train_loss": 0.01, "validation_loss": 0.02}),
        json!({"type": "future", "x": 1}),
    ]);
    records.extend(trace.iter().take(2).cloned());
    records
}
