//! A seeded fuzz harness for the `wogan` binary (issue "Trustworthy under bad input and
//! interruption"): it feeds mutated input lines, input files and option values to `validate`,
//! `simulate`, `run`, `report`, `export` and `camera`, and counts per command the inputs tried,
//! panics (exit 101 or "panicked" on stderr), aborts (killed by a signal, or exit 134), hangs (still
//! running when the watchdog kills it) and lines that are not JSON records in the JSON lines that
//! `validate`, `simulate` and `run` write.
//!
//! Inputs are real roads (`tests/reference/roads.jsonl`), real runs (`tests/fixtures`) and records
//! of every other kind, mutated: truncated, characters flipped, numbers made huge, tiny, negative,
//! non-finite or out of every integer type, points collapsed or near-duplicated, arrays emptied or
//! made very long, other `type`s, deep nesting, pretty-printed over many lines, empty lines, binary
//! bytes, lines of megabytes. Options get values inside, at and beyond their ranges, non-finite
//! values, overflowing integers and garbage; `run --config` files and `--driver-weights` files are
//! mutated the same way. About half the cases keep every option valid, so that their inputs reach
//! past the option parser.
//!
//! Every random choice of a case comes from ChaCha seeded by the campaign seed and the case's
//! index, so a case replays from those two numbers alone (`FUZZ_SEED=S FUZZ_ONLY=I
//! scripts/fuzz_campaign.sh`). A failure is reported with that replay, the shell command that
//! reproduces it in its kept directory (inputs, outputs, stderr), what was fuzzed, its input and
//! the tail of its standard error; failures are grouped into classes by their message and the first
//! frame of this workspace in the backtrace.
//!
//! One harness, two uses:
//! - `fuzz_sample` runs in `cargo test`: a small fixed-seed sample (`run` always bounded by
//!   `--max-tests` <= 3 and/or `--budget` <= 2s) plus the reproducers of failures already known,
//!   and asserts that none panics, aborts, hangs or writes a line that is not JSON.
//! - `fuzz_campaign` (ignored; `scripts/fuzz_campaign.sh`) runs as many cases as `FUZZ_CASES` from
//!   `FUZZ_SEED` and prints the table per command and every failure class. Its environment:
//!   `FUZZ_SEED` (1), `FUZZ_CASES` (600, spread evenly over the commands), `FUZZ_ONLY` (one case
//!   index), `FUZZ_COMMANDS` (e.g. `validate,run`), `FUZZ_JOBS` (children at once: the number of
//!   cores), `FUZZ_WATCHDOG_S` (30), `FUZZ_MEM_MB` (4096), `FUZZ_MINUTES` (no limit: start no new
//!   case after that many minutes), `FUZZ_KEEP` (set: keep every case's directory, not only the
//!   failing ones').
//!
//! Children run under `ulimit -v` so that a request for a huge allocation fails (and aborts) in the
//! child instead of taking the machine's memory from the tests and builds running beside it.

use crate::common::scratch_dir;
use rand::seq::{IndexedRandom, SliceRandom};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use road_sim::driver::{BeamNgAiParams, Dave2DriverParams};
use road_sim::vision::Dave2Weights;
use road_sim::DriverKind;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::fmt::{self, Write as _};
use std::fs::File;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use wogan_core::RunConfig;

/// The seed of the sample that `cargo test` runs.
const SAMPLE_SEED: u64 = 20_261_122;
/// Cases of that sample, spread evenly over the commands: enough to touch every option and input
/// form, few enough to take well under a minute on two cores.
const SAMPLE_CASES: usize = 360;
/// The largest `--map-size` the option parsers take today (metres); the fuzzing goes beyond it.
const MAX_MAP_SIZE_M: f64 = 2000.0;
/// The largest `camera --at` the option parser takes today (metres).
const MAX_ROAD_LENGTH_M: f64 = 20_000.0;
/// Examples shown per failure class.
const EXAMPLES_PER_CLASS: usize = 3;
/// Bytes of an input or output shown in a report.
const PREVIEW_BYTES: usize = 400;
/// The crates of this workspace, whose frames name where a failure happened.
const OUR_CRATES: [&str; 4] = ["wogan", "road_sim", "wogan_core", "driver_training"];

// ------------------------------------------------------------------------------------------------
// Settings
// ------------------------------------------------------------------------------------------------

/// How a campaign runs.
#[derive(Debug, Clone)]
struct Settings {
    /// Seed of every case.
    seed: u64,
    /// Case indices tried: `0..cases` (those of the chosen commands).
    cases: usize,
    /// Only this case index.
    only: Option<usize>,
    /// The commands fuzzed.
    targets: Vec<Target>,
    /// Children run at once.
    jobs: usize,
    /// A child still running after this long is killed and counted as a hang.
    watchdog: Duration,
    /// Address-space limit of each child, MiB.
    memory_mb: u64,
    /// No new case starts after this long.
    deadline: Option<Duration>,
    /// Name of the scratch directory (kept cases live there).
    dir_name: &'static str,
    /// Keep the directory of every case, not only of failing ones (to see what cases do).
    keep_all: bool,
}

impl Settings {
    /// The sample run by `cargo test`: fixed, so that it is the same on every machine.
    fn sample() -> Self {
        Self {
            seed: SAMPLE_SEED,
            cases: SAMPLE_CASES,
            only: None,
            targets: Target::ALL.to_vec(),
            jobs: 2,
            watchdog: Duration::from_secs(60),
            memory_mb: 4096,
            deadline: None,
            dir_name: "fuzz-sample",
            keep_all: false,
        }
    }

    /// A campaign as the `FUZZ_*` environment variables say.
    fn from_env() -> Self {
        let cores = std::thread::available_parallelism().map_or(2, usize::from);
        let targets = match std::env::var("FUZZ_COMMANDS") {
            Ok(names) => names
                .split(',')
                .map(|name| {
                    Target::ALL
                        .into_iter()
                        .find(|t| t.name() == name.trim())
                        .unwrap_or_else(|| panic!("FUZZ_COMMANDS: unknown command {name:?}"))
                })
                .collect(),
            Err(_) => Target::ALL.to_vec(),
        };
        Self {
            seed: env_or("FUZZ_SEED", 1),
            cases: env_or("FUZZ_CASES", 600),
            only: std::env::var("FUZZ_ONLY")
                .ok()
                .map(|_| env_or("FUZZ_ONLY", 0)),
            targets,
            jobs: env_or("FUZZ_JOBS", cores).max(1),
            watchdog: Duration::from_secs(env_or("FUZZ_WATCHDOG_S", 30)),
            memory_mb: env_or("FUZZ_MEM_MB", 4096),
            deadline: std::env::var("FUZZ_MINUTES")
                .ok()
                .map(|_| Duration::from_secs_f64(env_or::<f64>("FUZZ_MINUTES", 0.0) * 60.0)),
            dir_name: "fuzz-campaign",
            keep_all: std::env::var_os("FUZZ_KEEP").is_some(),
        }
    }
}

/// The value of environment variable `name`, or `default` when it is not set.
fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    match std::env::var(name) {
        Ok(text) => text
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("{name}={text:?} is not a valid value")),
        Err(_) => default,
    }
}

/// A fuzzed command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Target {
    Validate,
    Simulate,
    Run,
    Report,
    Export,
    Camera,
}

impl Target {
    const ALL: [Target; 6] = [
        Target::Validate,
        Target::Simulate,
        Target::Run,
        Target::Report,
        Target::Export,
        Target::Camera,
    ];

    fn name(self) -> &'static str {
        match self {
            Target::Validate => "validate",
            Target::Simulate => "simulate",
            Target::Run => "run",
            Target::Report => "report",
            Target::Export => "export",
            Target::Camera => "camera",
        }
    }

    /// Whether the command's standard output is JSON lines, one record per line.
    fn writes_json_lines(self) -> bool {
        matches!(self, Target::Validate | Target::Simulate | Target::Run)
    }

    /// The command case `index` of every campaign fuzzes, whichever commands are chosen, so that
    /// an index names the same case in every campaign of its seed.
    fn of_case(index: usize) -> Target {
        Target::ALL[index % Target::ALL.len()]
    }
}

// ------------------------------------------------------------------------------------------------
// Corpus: what cases are made of
// ------------------------------------------------------------------------------------------------

/// Real roads, real runs and records of every kind, read once per campaign. Only files of the
/// repository and values computed from the code go in, so that a seed makes the same cases on
/// every machine.
struct Corpus {
    /// Each line of `tests/reference/roads.jsonl`.
    roads: Vec<Value>,
    /// Each run of `tests/fixtures`, as its records.
    runs: Vec<Vec<Value>>,
    /// One record of every kind `wogan` writes or reads.
    records: Vec<Value>,
    /// A `simulate --trace` file: the road, then samples.
    trace: Vec<Value>,
    /// Every field a `run --config` file may set, at its default, per driver.
    config_defaults: Vec<(DriverKind, Value)>,
    /// Weights `--driver-weights` accepts.
    weights: Vec<u8>,
}

impl Corpus {
    fn load() -> Self {
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
            records,
            trace,
            config_defaults,
            weights: Dave2Weights::from_seed(1).to_bytes(),
        }
    }

    fn config_defaults(&self, kind: DriverKind) -> &Value {
        &self
            .config_defaults
            .iter()
            .find(|(k, _)| *k == kind)
            .expect("defaults for every driver")
            .1
    }
}

fn read_json_lines(path: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    text.lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| serde_json::from_str(line).expect("corpus lines are JSON"))
        .collect()
}

/// Every section of a `run --config` file with all its fields: the search's, the driver's
/// simulation preset and the driver's tuning, as the run lays the file over them.
fn config_defaults(kind: DriverKind) -> Value {
    let driver = if kind == DriverKind::Dave2Proxy {
        json!(Dave2DriverParams::default())
    } else {
        json!(BeamNgAiParams::default())
    };
    json!({
        "search": RunConfig::default(),
        "sim": kind.preset().sim_config(),
        "driver": driver,
    })
}

/// A trace of a drive along `road` in the layout of `simulate --trace`: the road with a centre
/// line of straight pieces about a metre long, and a sample every other point. Made here rather
/// than by the binary so that it is the same on every run (samples hold no timing, but it keeps
/// the corpus free of the code under test).
fn synthetic_trace(road: &Value) -> Vec<Value> {
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
fn records_of_every_kind(runs: &[Vec<Value>], trace: &[Value]) -> Vec<Value> {
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

// ------------------------------------------------------------------------------------------------
// Cases
// ------------------------------------------------------------------------------------------------

/// One invocation of the binary: its arguments, standard input and files, made in a directory of
/// its own (every path in `args` is relative to it).
#[derive(Debug, Clone)]
struct Case {
    /// How the report names it.
    label: String,
    /// The campaign seed and index it was made from (`None` for a pinned reproducer).
    replay: Option<(u64, usize)>,
    target: Target,
    /// The arguments, the command's name first.
    args: Vec<String>,
    stdin: Vec<u8>,
    /// Files written in the case's directory before the child starts.
    files: Vec<(String, Vec<u8>)>,
    /// Files or directories of JSON lines the command writes besides standard output.
    json_outputs: Vec<String>,
    /// What was fuzzed, in words, for reading a failure.
    notes: Vec<String>,
}

impl Case {
    fn new(label: String, target: Target) -> Self {
        Self {
            label,
            replay: None,
            target,
            args: vec![target.name().to_owned()],
            stdin: Vec::new(),
            files: Vec::new(),
            json_outputs: Vec::new(),
            notes: Vec::new(),
        }
    }

    fn arg(&mut self, arg: impl Into<String>) {
        self.args.push(arg.into());
    }

    /// `--name value` or `--name=value`; a value that starts with `-` mostly takes the second form,
    /// so that it reaches the option's parser instead of reading as another option.
    fn opt(&mut self, rng: &mut ChaCha8Rng, name: &str, value: impl Into<String>) {
        let value = value.into();
        // Only values the harness picked are worth a note: they are what a failure depends on.
        self.notes.push(format!("{name} {value:?}"));
        let joined = if value.starts_with('-') {
            chance(rng, 0.8)
        } else {
            chance(rng, 0.2)
        };
        if joined {
            self.args.push(format!("{name}={value}"));
        } else {
            self.args.push(name.to_owned());
            self.args.push(value);
        }
    }

    fn file(&mut self, name: &str, bytes: Vec<u8>) {
        self.files.push((name.to_owned(), bytes));
    }

    fn note(&mut self, note: impl Into<String>) {
        self.notes.push(note.into());
    }

    /// The directory name of the case.
    fn slug(&self) -> String {
        match self.replay {
            Some((_, index)) => format!("case-{index:05}-{}", self.target.name()),
            None => format!(
                "pinned-{}",
                self.label
                    .chars()
                    .filter(char::is_ascii_alphanumeric)
                    .take(40)
                    .collect::<String>()
            ),
        }
    }
}

/// Case `index` of the campaign of `seed`.
fn generate(corpus: &Corpus, seed: u64, index: usize) -> Case {
    // The seed and the index make the key: a case never depends on the cases before it.
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    key[8..16].copy_from_slice(&(index as u64).to_le_bytes());
    let rng = &mut ChaCha8Rng::from_seed(key);
    let target = Target::of_case(index);
    let mut case = Case::new(format!("seed {seed} case {index}"), target);
    case.replay = Some((seed, index));
    match target {
        Target::Validate => validate_case(rng, corpus, &mut case),
        Target::Simulate => simulate_case(rng, corpus, &mut case),
        Target::Run => run_case(rng, corpus, &mut case),
        Target::Report => report_case(rng, corpus, &mut case),
        Target::Export => export_case(rng, corpus, &mut case),
        Target::Camera => camera_case(rng, corpus, &mut case),
    }
    case
}

fn validate_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.5);
    input_source(rng, corpus, case, wild);
    if chance(rng, 0.5) {
        let size = float_arg(rng, wild, 0.0, MAX_MAP_SIZE_M, (50.0, 1000.0));
        case.opt(rng, "--map-size", size);
    }
    if chance(rng, 0.4) {
        case.arg("--details");
    }
    stray_argument(rng, case, wild);
}

fn simulate_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.5);
    input_source(rng, corpus, case, wild);
    driver_options(rng, corpus, case, wild);
    if chance(rng, 0.3) {
        let jobs = int_arg(rng, wild, 1, 256, (1, 4));
        case.opt(rng, "--jobs", jobs);
    }
    if chance(rng, 0.3) {
        case.opt(rng, "--trace", "trace");
        case.json_outputs.push("trace".into());
    }
    stray_argument(rng, case, wild);
}

/// An integer option: its name, how often a case gives it, its lowest and highest valid values,
/// and the range its typical values come from.
type IntOption = (&'static str, f64, i128, i128, (i64, i64));
/// A floating-point option, as [`IntOption`].
type FloatOption = (&'static str, f64, f64, f64, (f64, f64));

/// Budgets that end a run within two seconds.
const SHORT_BUDGETS: [&str; 6] = ["0s", "1ms", "100ms", "500ms", "1s", "2s"];
/// Budgets a run with at most three tests may have: any valid one, and invalid ones.
const OTHER_BUDGETS: [&str; 16] = [
    "10m",
    "3h",
    "1y",
    "",
    "0",
    "-1s",
    "1e308s",
    "18446744073709551616s",
    "nan",
    "inf",
    "2 s",
    "s",
    "10000000000000000000s",
    "1ns",
    "5000000000000000000000000h",
    "1s 1ns",
];

fn run_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    // A config file is fuzzed mostly with valid options, so that the parser lets it through.
    let with_config = chance(rng, 0.4);
    let wild = chance(rng, if with_config { 0.2 } else { 0.5 });
    if chance(rng, 0.5) {
        case.arg("--quiet");
    }
    // Every run is bounded by at most 3 tests or at most 2 s (or both); the other bound is fuzzed.
    match rng.random_range(0..3) {
        0 => {
            let count = rng.random_range(1..=3u32).to_string();
            case.opt(rng, "--max-tests", count);
            if chance(rng, 0.5) {
                let budget = if wild {
                    pick(rng, &OTHER_BUDGETS)
                } else {
                    pick(rng, &OTHER_BUDGETS[..3])
                };
                case.opt(rng, "--budget", *budget);
            }
        }
        1 => {
            let budget = *pick(rng, &SHORT_BUDGETS);
            case.opt(rng, "--budget", budget);
            if chance(rng, 0.5) {
                let count = int_arg(rng, wild, 1, i128::from(u64::MAX), (1, 3));
                case.opt(rng, "--max-tests", count);
            }
        }
        _ => {
            let count = rng.random_range(1..=3u32).to_string();
            case.opt(rng, "--max-tests", count);
            let budget = *pick(rng, &SHORT_BUDGETS);
            case.opt(rng, "--budget", budget);
        }
    }
    let oracle = driver_options(rng, corpus, case, wild);
    if chance(rng, 0.3) {
        let algorithm = name_arg(rng, wild, &["wogan", "random"]);
        case.opt(rng, "--algorithm", algorithm);
    }
    if chance(rng, 0.3) {
        let fitness = name_arg(rng, wild, &["bolp", "bolp-scaled", "distance"]);
        case.opt(rng, "--fitness", fitness);
    }
    let integers: [IntOption; 3] = [
        ("--seed", 0.4, 0, i128::from(u64::MAX), (0, 1_000_000)),
        ("--jobs", 0.25, 1, 256, (1, 4)),
        ("--curvature-points", 0.3, 2, 499, (2, 12)),
    ];
    for (name, p, lo, hi, typical) in integers {
        if chance(rng, p) {
            let value = int_arg(rng, wild, lo, hi, typical);
            case.opt(rng, name, value);
        }
    }
    let floats: [FloatOption; 4] = [
        ("--step-length", 0.3, 0.0, 1000.0, (5.0, 30.0)),
        ("--init-fraction", 0.25, 0.0, 1.0, (0.05, 0.95)),
        ("--mutation-share", 0.2, 0.0, 1.0, (0.0, 1.0)),
        ("--target-decay", 0.2, 0.0, 1.0, (0.5, 0.99)),
    ];
    for (name, p, lo, hi, typical) in floats {
        if chance(rng, p) {
            let value = float_arg(rng, wild, lo, hi, typical);
            case.opt(rng, name, value);
        }
    }
    if chance(rng, 0.2) {
        if wild && chance(rng, 0.3) {
            let out = *pick(rng, &[".", "nodir/out.jsonl", ""]);
            case.opt(rng, "--out", out);
        } else {
            case.opt(rng, "--out", "out.jsonl");
            case.json_outputs.push("out.jsonl".into());
        }
    }
    if with_config {
        let config = config_file(rng, corpus, oracle, &mut case.notes);
        case.file("config.json", config);
        case.opt(rng, "--config", "config.json");
    }
    stray_argument(rng, case, wild);
}

fn report_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.3);
    let trace = chance(rng, 0.25);
    if trace {
        let file = records_file(rng, corpus, &corpus.trace, "trace.jsonl", &mut case.notes);
        case.file("trace.jsonl", file);
        case.opt(rng, "--trace", "trace.jsonl");
    }
    if !trace || (wild && chance(rng, 0.2)) {
        for i in 0..*pick(rng, &[1, 1, 2, 3]) {
            let name = format!("run{i}.jsonl");
            let base = pick(rng, &corpus.runs);
            let file = records_file(rng, corpus, base, &name, &mut case.notes);
            case.file(&name, file);
            case.arg(name);
        }
        if wild && chance(rng, 0.2) {
            case.arg("missing.jsonl");
        }
    }
    let out = if wild && chance(rng, 0.2) {
        *pick(rng, &["run0.jsonl", "/dev/null", ""])
    } else {
        "report"
    };
    case.opt(rng, "--out", out);
    // `--vs` takes every argument after it, so it comes last.
    if !trace && chance(rng, 0.35) {
        case.arg("--vs");
        for i in 0..*pick(rng, &[1, 2]) {
            let name = format!("vs{i}.jsonl");
            let base = pick(rng, &corpus.runs);
            let file = records_file(rng, corpus, base, &name, &mut case.notes);
            case.file(&name, file);
            case.arg(name);
        }
    }
}

fn export_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.3);
    if chance(rng, 0.3) {
        let format = name_arg(rng, wild, &["sbst"]);
        case.opt(rng, "--format", format);
    }
    let base = pick(rng, &corpus.runs);
    let run = records_file(rng, corpus, base, "run.jsonl", &mut case.notes);
    case.file("run.jsonl", run);
    case.arg("run.jsonl");
    let dir = if wild && chance(rng, 0.3) {
        *pick(rng, &["run.jsonl", "/dev/null", ""])
    } else {
        "out"
    };
    case.arg(dir);
    case.note(format!("DIR {dir:?}"));
    if chance(rng, 0.3) {
        case.arg("--force");
    }
}

fn camera_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.5);
    // The camera looks at the first road only, and only at a valid one: half the cases give it a
    // reference road as it is, so that the options are what is fuzzed.
    if chance(rng, 0.5) {
        let (road, form) = road_value(rng, corpus);
        case.stdin = serde_json::to_vec(&road).expect("a Value encodes");
        case.note(format!("stdin: {form}, unchanged"));
    } else {
        input_source(rng, corpus, case, wild);
    }
    if chance(rng, 0.7) {
        let count = rng.random_range(1..=3);
        let at: Vec<String> = (0..count)
            .map(|_| float_arg(rng, wild, 0.0, MAX_ROAD_LENGTH_M, (0.0, 60.0)))
            .collect();
        case.opt(rng, "--at", at.join(","));
    }
    case.opt(rng, "--out", "frames");
    if chance(rng, 0.3) {
        case.arg("--gray");
    }
    if chance(rng, 0.35) {
        let size = float_arg(rng, wild, 0.0, MAX_MAP_SIZE_M, (50.0, 1000.0));
        case.opt(rng, "--map-size", size);
    }
    stray_argument(rng, case, wild);
}

/// Where a road-reading command reads its lines: standard input, `-`, a file, or (wild) a path
/// that is missing, a directory or empty.
fn input_source(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case, wild: bool) {
    let input = input_lines(rng, corpus, &mut case.notes);
    match rng.random_range(0..10) {
        0..=5 => case.stdin = input,
        6 => {
            case.arg("-");
            case.stdin = input;
        }
        7 | 8 => {
            case.file("in.jsonl", input);
            case.arg("in.jsonl");
        }
        _ if wild => {
            let path = *pick(rng, &["missing.jsonl", ".", "/dev/null"]);
            case.arg(path);
            case.note(format!("FILE {path:?}"));
            case.stdin = input;
        }
        _ => case.stdin = input,
    }
}

/// The options of `DriverOptions` (shared by `simulate` and `run`); returns the driver chosen.
fn driver_options(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    case: &mut Case,
    wild: bool,
) -> DriverKind {
    let oracle = if chance(rng, 0.6) {
        DriverKind::BeamNgAiProxy
    } else {
        DriverKind::Dave2Proxy
    };
    if oracle == DriverKind::Dave2Proxy || chance(rng, 0.3) {
        let name = if wild && chance(rng, 0.15) {
            pick(rng, &WRONG_NAMES).to_string()
        } else {
            oracle.name().to_owned()
        };
        case.opt(rng, "--oracle", name);
    }
    if chance(rng, 0.25) && (oracle == DriverKind::Dave2Proxy || wild) {
        let weights = weights_file(rng, corpus, &mut case.notes);
        let path = match weights {
            Some(bytes) => {
                case.file("weights.bin", bytes);
                "weights.bin"
            }
            None => *pick(rng, &["missing.bin", "."]),
        };
        case.opt(rng, "--driver-weights", path);
    }
    let floats: [FloatOption; 3] = [
        ("--speed-limit", 0.35, 0.0, 300.0, (5.0, 120.0)),
        ("--oob-tolerance", 0.35, 0.0, 1.0, (0.0, 1.0)),
        ("--map-size", 0.35, 0.0, MAX_MAP_SIZE_M, (50.0, 1000.0)),
    ];
    for (name, p, lo, hi, typical) in floats {
        if chance(rng, p) {
            let value = float_arg(rng, wild, lo, hi, typical);
            case.opt(rng, name, value);
        }
    }
    oracle
}

/// Now and then (wild cases only) an argument no command takes.
fn stray_argument(rng: &mut ChaCha8Rng, case: &mut Case, wild: bool) {
    if wild && chance(rng, 0.04) {
        // Not `--help`: help on stdout is right, and would read as a line that is not JSON.
        let stray = *pick(rng, &["--frobnicate", "stray", "--", "-x"]);
        case.arg(stray);
        case.note(format!("stray argument {stray:?}"));
    }
}

// ------------------------------------------------------------------------------------------------
// Option values
// ------------------------------------------------------------------------------------------------

/// One of `items`.
fn pick<'a, T>(rng: &mut ChaCha8Rng, items: &'a [T]) -> &'a T {
    items.choose(rng).expect("a choice from a non-empty list")
}

/// True with probability `p`.
fn chance(rng: &mut ChaCha8Rng, p: f64) -> bool {
    rng.random_bool(p)
}

/// Numbers no option takes, or takes only at its edge: signs, non-finite values, overflow,
/// underflow and integers beyond every integer type.
const WILD_NUMBERS: [&str; 20] = [
    "0",
    "-0",
    "-1",
    "NaN",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "infinity",
    "1e308",
    "-1e308",
    "1e309",
    "1.7976931348623157e308",
    "5e-324",
    "1e-300",
    "1e-400",
    "18446744073709551615",
    "18446744073709551616",
    "-9223372036854775809",
    "340282366920938463463374607431768211456",
];
/// Text that is no number, or only nearly one.
const GARBAGE: [&str; 12] = [
    "", " ", "abc", "1,5", "0x10", " 1", "1_000", "1e", "--1", "\u{bd}", "1.2.3", "+-1",
];
/// Integers beyond the ranges of `u32`, `u64` and `i64`, and numbers that are not integers.
const WILD_INTEGERS: [&str; 11] = [
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "-9223372036854775809",
    "99999999999999999999999999",
    "1e3",
    "1.5",
    "+3",
    "007",
    "-0",
];
/// Names no option takes.
const WRONG_NAMES: [&str; 8] = [
    "",
    "DAVE2-PROXY",
    "beamng",
    "Bolp",
    "wogan ",
    "random,wogan",
    "sbst2",
    "-",
];

/// A floating-point option's value: within `typical`; or (wild) also at and just beyond the
/// valid range `lo..=hi`, non-finite, huge, tiny or garbage. Even a wild case keeps most values
/// valid, so that a few edge values together get past the parser.
fn float_arg(rng: &mut ChaCha8Rng, wild: bool, lo: f64, hi: f64, typical: (f64, f64)) -> String {
    let inside = |rng: &mut ChaCha8Rng| rng.random_range(typical.0..=typical.1).to_string();
    if !wild {
        return inside(rng);
    }
    match rng.random_range(0..8) {
        0..=2 => inside(rng),
        3 | 4 => {
            let edges = [
                lo,
                lo.next_down(),
                lo.next_up(),
                -lo - 1.0,
                hi,
                hi.next_up(),
                hi.next_down(),
                hi * 2.0,
                hi * 1e6,
            ];
            format!("{:?}", pick(rng, &edges))
        }
        5 | 6 => pick(rng, &WILD_NUMBERS).to_string(),
        _ => pick(rng, &GARBAGE).to_string(),
    }
}

/// An integer option's value: within `typical`; or (wild) also at and beyond `lo..=hi`, beyond
/// every integer type, not an integer, or garbage.
fn int_arg(rng: &mut ChaCha8Rng, wild: bool, lo: i128, hi: i128, typical: (i64, i64)) -> String {
    let inside = |rng: &mut ChaCha8Rng| rng.random_range(typical.0..=typical.1).to_string();
    if !wild {
        return inside(rng);
    }
    match rng.random_range(0..8) {
        0..=2 => inside(rng),
        3 | 4 => pick(rng, &[lo - 1, lo, hi, hi + 1, 0, -1]).to_string(),
        5 | 6 => pick(rng, &WILD_INTEGERS).to_string(),
        _ => pick(rng, &GARBAGE).to_string(),
    }
}

/// One of `valid`, or (wild, now and then) a name no option takes.
fn name_arg(rng: &mut ChaCha8Rng, wild: bool, valid: &[&str]) -> String {
    if wild && chance(rng, 0.3) {
        pick(rng, &WRONG_NAMES).to_string()
    } else {
        pick(rng, valid).to_string()
    }
}

// ------------------------------------------------------------------------------------------------
// Input lines
// ------------------------------------------------------------------------------------------------

/// One to six input lines, some blank, some ending in CRLF, the last sometimes without a newline.
/// Lines that hold nothing.
const BLANK_LINES: [&[u8]; 3] = [b"", b"   ", b"\t"];

fn input_lines(rng: &mut ChaCha8Rng, corpus: &Corpus, notes: &mut Vec<String>) -> Vec<u8> {
    let count = *pick(rng, &[1, 1, 2, 3, 4, 6]);
    let eol: &[u8] = if chance(rng, 0.1) { b"\r\n" } else { b"\n" };
    let mut out = Vec::new();
    for i in 0..count {
        if chance(rng, 0.1) {
            let blank = *pick(rng, &BLANK_LINES);
            out.extend_from_slice(blank);
            out.extend_from_slice(eol);
            notes.push(format!("blank line before input {}", i + 1));
        }
        let line = input_line(rng, corpus, &format!("input {}", i + 1), notes);
        out.extend_from_slice(&line);
        if i + 1 < count || chance(rng, 0.85) {
            out.extend_from_slice(eol);
        }
    }
    out
}

/// A road in one of the forms `validate` reads, or a record of another kind, mutated.
fn input_line(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    label: &str,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let (mut value, base) = if chance(rng, 0.6) {
        road_value(rng, corpus)
    } else {
        let record = pick(rng, &corpus.records).clone();
        let kind = format!("{} record", record["type"].as_str().unwrap_or("?"));
        (record, kind)
    };
    let mut steps = vec![base];
    let mutations = if chance(rng, 0.25) {
        0
    } else {
        rng.random_range(1..=3)
    };
    let text_mutations = (0..mutations).filter(|_| chance(rng, 0.4)).count();
    for _ in text_mutations..mutations {
        steps.push(mutate_value(rng, &mut value));
    }
    let mut text = encode(rng, &value, 0.1, &mut steps);
    for _ in 0..text_mutations {
        steps.push(mutate_text(rng, &mut text));
    }
    notes.push(format!("{label}: {}", steps.join("; ")));
    text
}

/// `value` as JSON text: compact, or pretty-printed over many lines with probability `pretty`.
fn encode(rng: &mut ChaCha8Rng, value: &Value, pretty: f64, steps: &mut Vec<String>) -> Vec<u8> {
    if chance(rng, pretty) {
        steps.push("pretty-printed".into());
        serde_json::to_vec_pretty(value).expect("a Value encodes")
    } else {
        serde_json::to_vec(value).expect("a Value encodes")
    }
}

/// A reference road in one of the forms `validate` reads.
fn road_value(rng: &mut ChaCha8Rng, corpus: &Corpus) -> (Value, String) {
    let road = pick(rng, &corpus.roads);
    let points = road["road_points"].clone();
    let (value, form) = match rng.random_range(0..6) {
        0 => (road.clone(), "reference road"),
        1 => (points, "bare points"),
        2 => (json!({"curvature": road["curvature"]}), "curvature road"),
        3 => (
            json!({"curvature": road["curvature"], "step": 15.0}),
            "curvature road with step",
        ),
        4 => {
            let with_z: Vec<Value> = points
                .as_array()
                .into_iter()
                .flatten()
                .map(|p| json!([p[0], p[1], -28.0, 8.0]))
                .collect();
            (
                json!({"road_points": with_z, "interpolated_points": []}),
                "competition test",
            )
        }
        _ => {
            let run = pick(rng, &corpus.runs);
            let tests: Vec<&Value> = run.iter().filter(|r| r["type"] == "test").collect();
            let test = tests.choose(rng).map_or(Value::Null, |t| (*t).clone());
            (test, "run test record")
        }
    };
    (value, form.to_owned())
}

/// JSON numbers at the edges of `f64`, `u64` and `i64`.
fn extreme_number(rng: &mut ChaCha8Rng) -> Value {
    match rng.random_range(0..3) {
        0 => Value::from(*pick(
            rng,
            &[
                0.0,
                -0.0,
                -1.0,
                1e308,
                -1e308,
                f64::MAX,
                f64::MIN,
                f64::MIN_POSITIVE,
                5e-324,
                1e300,
                -1e300,
                1e-300,
                1e15,
                1e9,
                3.5e38,
                1.000_000_000_000_1e300,
                0.5,
            ],
        )),
        1 => Value::from(*pick(
            rng,
            &[
                u64::MAX,
                4_294_967_295,
                4_294_967_296,
                9_007_199_254_740_993,
                0,
                1,
            ],
        )),
        _ => Value::from(*pick(rng, &[i64::MIN, -1, -4_294_967_296, i64::MAX])),
    }
}

/// Mutates `value` once, in one of the ways that change its meaning but keep it JSON; says how.
fn mutate_value(rng: &mut ChaCha8Rng, value: &mut Value) -> String {
    match rng.random_range(0..10) {
        0 | 1 => {
            let new = extreme_number(rng);
            match pick_pointer(rng, value, Value::is_number) {
                Some(at) => {
                    set_pointer(value, &at, new.clone());
                    format!("{at} = {new}")
                }
                None => "no number to change".into(),
            }
        }
        2 => {
            let factor = *pick(rng, &[1e300, 1e10, -1.0, 1e-300, 0.0, 1e308, 1e15]);
            scale_numbers(value, factor);
            format!("every number times {factor:e}")
        }
        3 => {
            let Some(at) = pick_pointer(rng, value, is_point_list) else {
                return "no points to collapse".into();
            };
            let points = value
                .pointer_mut(&at)
                .and_then(Value::as_array_mut)
                .expect("a point list just found");
            match rng.random_range(0..3) {
                0 => {
                    let first = points[0].clone();
                    points.iter_mut().for_each(|p| *p = first.clone());
                    format!("{at}: every point the same")
                }
                1 => {
                    // Points a few ulps apart, as large as coordinates get: the spline and the
                    // distances between points divide by almost nothing.
                    let c = *pick(rng, &[1e300, -1e300, 1e15, 100.0]);
                    for (i, p) in points.iter_mut().enumerate() {
                        *p = json!([c, c * (1.0 + i as f64 * 1e-13)]);
                    }
                    format!("{at}: near-duplicate points at {c:e}")
                }
                _ => {
                    let i = rng.random_range(0..points.len());
                    let copy = points[i].clone();
                    points.insert(i, copy);
                    format!("{at}: point {i} repeated")
                }
            }
        }
        4 => {
            let Some(at) = pick_pointer(rng, value, Value::is_array) else {
                return "no array to resize".into();
            };
            let len = *pick(rng, &[0usize, 1, 2, 3, 50, 499, 500, 1000, 20_000]);
            let items = value
                .pointer_mut(&at)
                .and_then(Value::as_array_mut)
                .expect("an array just found");
            if items.is_empty() {
                items.push(json!(0.0));
            }
            let cycle: Vec<Value> = items.iter().cycle().take(len).cloned().collect();
            *items = cycle;
            format!("{at}: {len} items")
        }
        5 => {
            let kind = pick(
                rng,
                &[
                    json!("header"),
                    json!("test"),
                    json!("train"),
                    json!("summary"),
                    json!("error"),
                    json!("result"),
                    json!("verdict"),
                    json!("driver"),
                    json!("road"),
                    json!("sample"),
                    json!("future"),
                    json!(""),
                    json!("TEST"),
                    json!(7),
                    Value::Null,
                    json!(["test"]),
                ],
            )
            .clone();
            match value.as_object_mut() {
                Some(object) => {
                    object.insert("type".into(), kind.clone());
                    format!("type = {kind}")
                }
                None => "no object to retype".into(),
            }
        }
        6 => {
            let Some(at) =
                pick_pointer(rng, value, |v| v.as_object().is_some_and(|o| !o.is_empty()))
            else {
                return "no key to drop".into();
            };
            let object = value
                .pointer_mut(&at)
                .and_then(Value::as_object_mut)
                .expect("an object just found");
            let keys: Vec<String> = object.keys().cloned().collect();
            let key = pick(rng, &keys);
            object.remove(key);
            format!("{at}/{key} dropped")
        }
        7 => {
            let new = pick(
                rng,
                &[
                    json!("x"),
                    json!(true),
                    Value::Null,
                    json!([]),
                    json!({}),
                    json!([[]]),
                    json!(1),
                    json!("1.5"),
                    json!([1.0, 2.0]),
                ],
            )
            .clone();
            let at = pick_pointer(rng, value, |_| true).unwrap_or_default();
            set_pointer(value, &at, new.clone());
            format!("{at:?} replaced by {new}")
        }
        8 => {
            let (key, new) = match rng.random_range(0..4) {
                0 => ("step", extreme_number(rng)),
                1 => ("road_points", json!([[0.0, 0.0]])),
                2 => ("curvature", json!([])),
                _ => ("zz", json!({"a": [1, {"b": null}]})),
            };
            match value.as_object_mut() {
                Some(object) => {
                    object.insert(key.into(), new.clone());
                    format!("{key} = {new}")
                }
                None => "no object to extend".into(),
            }
        }
        _ => {
            let Some(at) = pick_pointer(rng, value, is_point) else {
                return "no point to reshape".into();
            };
            let point = value.pointer(&at).cloned().unwrap_or_default();
            let new = match rng.random_range(0..5) {
                0 => json!([point[0]]),
                1 => json!([point[0], point[1], 0.0, 8.0, 1.0]),
                2 => json!(["1", "2"]),
                3 => json!([null, null]),
                _ => json!([point[0], point[1], [1]]),
            };
            set_pointer(value, &at, new.clone());
            format!("{at} = {new}")
        }
    }
}

/// A point: an array of at least two numbers.
fn is_point(value: &Value) -> bool {
    value
        .as_array()
        .is_some_and(|a| a.len() >= 2 && a.iter().all(Value::is_number))
}

/// A list of at least two points.
fn is_point_list(value: &Value) -> bool {
    value
        .as_array()
        .is_some_and(|a| a.len() >= 2 && a.iter().all(is_point))
}

/// Multiplies every number in `value` by `factor` (a product that overflows becomes `null`).
fn scale_numbers(value: &mut Value, factor: f64) {
    if let Some(x) = value.as_f64() {
        *value = Value::from(x * factor);
        return;
    }
    match value {
        Value::Array(items) => items.iter_mut().for_each(|v| scale_numbers(v, factor)),
        Value::Object(fields) => fields.values_mut().for_each(|v| scale_numbers(v, factor)),
        _ => {}
    }
}

/// The JSON pointer of a random node of `value` that `keep` accepts.
fn pick_pointer(rng: &mut ChaCha8Rng, value: &Value, keep: fn(&Value) -> bool) -> Option<String> {
    fn walk(value: &Value, at: &mut String, keep: fn(&Value) -> bool, found: &mut Vec<String>) {
        if keep(value) {
            found.push(at.clone());
        }
        let len = at.len();
        match value {
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    write!(at, "/{i}").expect("a String takes text");
                    walk(item, at, keep, found);
                    at.truncate(len);
                }
            }
            Value::Object(fields) => {
                for (key, item) in fields {
                    at.push('/');
                    at.push_str(&key.replace('~', "~0").replace('/', "~1"));
                    walk(item, at, keep, found);
                    at.truncate(len);
                }
            }
            _ => {}
        }
    }
    let mut found = Vec::new();
    walk(value, &mut String::new(), keep, &mut found);
    found.choose(rng).cloned()
}

/// Sets the node at `pointer` to `new`, making objects on the way where there are none (keys are
/// this harness's own, never escaped).
fn set_pointer(root: &mut Value, pointer: &str, new: Value) {
    let mut node = root;
    for key in pointer.split('/').skip(1) {
        node = match node {
            Value::Array(items) => {
                let i = key.parse::<usize>().unwrap_or(0).min(items.len());
                if i == items.len() {
                    items.push(Value::Null);
                }
                &mut items[i]
            }
            other => {
                if !other.is_object() {
                    *other = json!({});
                }
                other
                    .as_object_mut()
                    .expect("an object just made")
                    .entry(key.to_owned())
                    .or_insert(Value::Null)
            }
        };
    }
    *node = new;
}

/// Numbers as JSON does not write them.
const NON_JSON_NUMBERS: [&str; 16] = [
    "NaN",
    "-NaN",
    "Infinity",
    "-Infinity",
    "inf",
    "1e999",
    "-1e999",
    "1e-999",
    "0x10",
    "01",
    "1.",
    ".5",
    "+1",
    "1e",
    "--1",
    "1e+",
];

/// Mutates JSON text once, in one of the ways that may leave it not JSON; says how.
fn mutate_text(rng: &mut ChaCha8Rng, text: &mut Vec<u8>) -> String {
    match rng.random_range(0..8) {
        0 => {
            let at = rng.random_range(0..=text.len());
            text.truncate(at);
            format!("truncated to {at} bytes")
        }
        1 => {
            let count = rng.random_range(1..=4);
            for _ in 0..count {
                if text.is_empty() {
                    break;
                }
                let i = rng.random_range(0..text.len());
                text[i] = *pick(rng, b"[]{},:\"-+.eE0123456789 \\nul");
            }
            format!("{count} bytes flipped")
        }
        2 => {
            let starts: Vec<usize> = (0..text.len())
                .filter(|&i| text[i].is_ascii_digit() && (i == 0 || !is_number_byte(text[i - 1])))
                .collect();
            let Some(&start) = starts.choose(rng) else {
                return "no number to spoil".into();
            };
            let end = (start..text.len())
                .find(|&i| !is_number_byte(text[i]))
                .unwrap_or(text.len());
            let long = "9".repeat(400);
            let new = if chance(rng, 0.1) {
                long.as_str()
            } else {
                *pick(rng, &NON_JSON_NUMBERS)
            };
            text.splice(start..end, new.bytes());
            format!("a number spelt {}", preview(new.as_bytes(), 20))
        }
        3 => {
            let at = rng.random_range(0..=text.len());
            let count = rng.random_range(1..=16);
            let bytes: Vec<u8> = (0..count).map(|_| rng.random::<u8>()).collect();
            text.splice(at..at, bytes);
            format!("{count} binary bytes at {at}")
        }
        4 => {
            let len = *pick(rng, &[10_000usize, 100_000, 1_000_000, 4_000_000]);
            match rng.random_range(0..3) {
                0 => {
                    let at = text.iter().position(|&b| b == b'{').map_or(0, |i| i + 1);
                    let pad = format!("\"pad\":\"{}\",", "x".repeat(len));
                    text.splice(at..at, pad.bytes());
                    format!("a {len}-byte string field")
                }
                1 => {
                    text.extend(std::iter::repeat_n(b' ', len));
                    format!("{len} trailing spaces")
                }
                _ => {
                    let at = text
                        .iter()
                        .position(u8::is_ascii_digit)
                        .unwrap_or(text.len());
                    let digits = format!("1{}", "0".repeat(len));
                    text.splice(at..at, digits.bytes());
                    format!("a {len}-digit number")
                }
            }
        }
        5 => {
            let depth = *pick(rng, &[2usize, 64, 127, 128, 129, 1000, 100_000]);
            let (open, close): (&[u8], &[u8]) = if chance(rng, 0.5) {
                (b"[", b"]")
            } else {
                (b"{\"a\":", b"}")
            };
            let mut nested = open.repeat(depth);
            nested.append(text);
            nested.extend(close.repeat(depth));
            *text = nested;
            format!("nested {depth} deep")
        }
        6 => {
            let whole = *pick(
                rng,
                &[
                    "",
                    " ",
                    "null",
                    "[]",
                    "{}",
                    "[[]]",
                    "\"\"",
                    "0",
                    "-1",
                    "[1,2]",
                    "{\"type\":\"test\"}",
                    "{\"type\":null}",
                    "[[0,0]]",
                    "\u{feff}{}",
                    "{\"road_points\":null}",
                    "{\"curvature\":[]}",
                ],
            );
            *text = whole.as_bytes().to_vec();
            format!("replaced by {whole:?}")
        }
        _ => {
            let copy = text.clone();
            text.push(b' ');
            text.extend(copy);
            "written twice on the line".into()
        }
    }
}

fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-')
}

// ------------------------------------------------------------------------------------------------
// Files: runs, traces, config, weights
// ------------------------------------------------------------------------------------------------

/// Fields of every test record (of a run) or sample (of a trace) that a report plots or sums.
const COLUMNS: [&str; 22] = [
    "fitness",
    "max_bolp",
    "min_lane_distance_m",
    "fitness_distance",
    "sim_time_s",
    "execution_ms",
    "generation_ms",
    "MAX_CURV",
    "DIR_COV",
    "STD_SA",
    "MEAN_LP",
    "MAX_LP",
    "predicted_fitness",
    "invalid_candidates",
    "ranked_candidates",
    "id",
    "t",
    "x",
    "y",
    "speed_kmh",
    "bolp",
    "steering_deg",
];
/// Places in a run's header that the report and export read.
const HEADER_FIELDS: [&str; 11] = [
    "/config/road/map_size_m",
    "/config/sim/oob_tolerance",
    "/config/sim/speed_limit_kmh",
    "/config/search/wogan/target_decay",
    "/config/max_tests",
    "/seed",
    "/algorithm",
    "/oracle",
    "/fitness",
    "/config",
    "/version",
];

/// A file of JSON lines made from `base` (a run or a trace), mutated: records changed, one field
/// of every record made extreme, the header's settings changed, records dropped, repeated,
/// shuffled or of other kinds inserted, lines spoiled as text, the file cut short.
fn records_file(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    base: &[Value],
    name: &str,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let mut records = base.to_vec();
    let mut steps = Vec::new();
    let mut spoiled_lines = 0;
    let ops = if chance(rng, 0.2) {
        0
    } else {
        rng.random_range(1..=3)
    };
    for _ in 0..ops {
        if records.is_empty() {
            break;
        }
        match rng.random_range(0..9) {
            0 | 1 => {
                let i = rng.random_range(0..records.len());
                let how = mutate_value(rng, &mut records[i]);
                steps.push(format!("record {}: {how}", i + 1));
            }
            2 => {
                let field = *pick(rng, &COLUMNS);
                let new = if chance(rng, 0.2) {
                    Value::Null
                } else {
                    extreme_number(rng)
                };
                for record in records.iter_mut().filter(|r| r.get(field).is_some()) {
                    record[field] = new.clone();
                }
                steps.push(format!("every {field} = {new}"));
            }
            3 => {
                let at = *pick(rng, &HEADER_FIELDS);
                let new = if chance(rng, 0.6) {
                    extreme_number(rng)
                } else {
                    pick(rng, &[json!("bogus"), Value::Null, json!([]), json!({})]).clone()
                };
                if let Some(header) = records.iter_mut().find(|r| r["type"] == "header") {
                    set_pointer(header, at, new.clone());
                    steps.push(format!("header {at} = {new}"));
                }
            }
            4 => {
                let kind = *pick(rng, &["header", "summary", "road", "test"]);
                records.retain(|r| r["type"] != kind);
                steps.push(format!("{kind} records dropped"));
            }
            5 => {
                let i = rng.random_range(0..records.len());
                let times = *pick(rng, &[2usize, 10, 50]);
                let copy = records[i].clone();
                records.splice(i..i, std::iter::repeat_n(copy, times - 1));
                steps.push(format!("record {} repeated {times} times", i + 1));
            }
            6 => {
                records.shuffle(rng);
                steps.push("records shuffled".into());
            }
            7 => {
                let record = pick(rng, &corpus.records).clone();
                let at = rng.random_range(0..=records.len());
                steps.push(format!(
                    "a {} record inserted at {}",
                    record["type"].as_str().unwrap_or("?"),
                    at + 1
                ));
                records.insert(at, record);
            }
            _ => spoiled_lines += 1,
        }
    }
    let mut lines: Vec<Vec<u8>> = records
        .iter()
        .map(|r| serde_json::to_vec(r).expect("a Value encodes"))
        .collect();
    for _ in 0..spoiled_lines {
        if lines.is_empty() {
            break;
        }
        let i = rng.random_range(0..lines.len());
        let how = mutate_text(rng, &mut lines[i]);
        steps.push(format!("line {}: {how}", i + 1));
    }
    if !lines.is_empty() && chance(rng, 0.05) {
        // Lines and records still correspond: spoiling a line changed its text only.
        let i = rng.random_range(0..lines.len());
        lines[i] = serde_json::to_vec_pretty(&records[i]).expect("a Value encodes");
        steps.push(format!("line {} pretty-printed", i + 1));
    }
    let mut file = lines.join(&b'\n');
    file.push(b'\n');
    if chance(rng, 0.1) {
        let at = rng.random_range(0..=file.len());
        file.truncate(at);
        steps.push(format!("file cut at byte {at}"));
    }
    if steps.is_empty() {
        steps.push("unchanged".into());
    }
    notes.push(format!("{name}: {}", steps.join("; ")));
    file
}

/// A `run --config` file: 1 to 3 settings (any field of any section) set to extreme values or
/// values of the wrong type, sometimes with unknown fields, the old layout that kept the driver
/// under `sim`, sections of the wrong type, or spoiled as text.
fn config_file(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    oracle: DriverKind,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let defaults = corpus.config_defaults(oracle);
    let mut config = if chance(rng, 0.15) {
        defaults.clone()
    } else {
        json!({})
    };
    let mut steps = Vec::new();
    for _ in 0..rng.random_range(1..=3) {
        let at = pick_pointer(rng, defaults, |v| !v.is_object()).expect("a leaf setting");
        let new = extreme_setting(rng, defaults.pointer(&at));
        set_pointer(&mut config, &at, new.clone());
        steps.push(format!("{at} = {new}"));
    }
    if chance(rng, 0.15) {
        match rng.random_range(0..3) {
            0 => {
                let at = *pick(
                    rng,
                    &[
                        "/bogus",
                        "/sim/bogus",
                        "/search/wogan/bogus",
                        "/driver/bogus",
                    ],
                );
                set_pointer(&mut config, at, json!(1));
                steps.push(format!("unknown {at}"));
            }
            1 => {
                // The layout before config.driver: the driver's section under `sim`.
                let old = if oracle == DriverKind::Dave2Proxy {
                    "/sim/dave2"
                } else {
                    "/sim/beamng_ai"
                };
                let driver = config.get("driver").cloned().unwrap_or_else(|| json!({}));
                if chance(rng, 0.5) {
                    if let Some(fields) = config.as_object_mut() {
                        fields.remove("driver");
                    }
                }
                set_pointer(&mut config, old, driver);
                steps.push(format!("the driver section at {old}"));
            }
            _ => {
                let section = *pick(rng, &["/sim", "/search", "/driver", "/search/wogan"]);
                let new = pick(rng, &[Value::Null, json!([]), json!("x"), json!(1)]).clone();
                set_pointer(&mut config, section, new.clone());
                steps.push(format!("{section} = {new}"));
            }
        }
    }
    let mut text = encode(rng, &config, 0.3, &mut steps);
    if chance(rng, 0.15) {
        steps.push(mutate_text(rng, &mut text));
    }
    notes.push(format!("config.json: {}", steps.join("; ")));
    text
}

/// A value for a setting whose default is `default`: integers at and beyond every integer type,
/// floats that are zero, negative, tiny, huge or beyond `f32`, other names, or the wrong type.
fn extreme_setting(rng: &mut ChaCha8Rng, default: Option<&Value>) -> Value {
    if chance(rng, 0.1) {
        return pick(
            rng,
            &[json!("1"), Value::Null, json!([]), json!({}), json!(true)],
        )
        .clone();
    }
    match default {
        Some(v) if v.is_u64() || v.is_i64() => pick(
            rng,
            &[
                json!(0),
                json!(1),
                json!(2),
                json!(1000),
                json!(65_536),
                json!(4_294_967_295_u64),
                json!(4_294_967_296_u64),
                json!(u64::MAX),
                json!(-1),
                json!(1.5),
                json!(1e20),
            ],
        )
        .clone(),
        Some(Value::Number(_)) => Value::from(*pick(
            rng,
            &[
                0.0,
                -0.0,
                -1.0,
                1e-300,
                5e-324,
                1e-9,
                0.999_999_999,
                1.000_000_1,
                100.0,
                1e9,
                1e15,
                3.5e38,
                1e308,
                -1e308,
            ],
        )),
        Some(Value::String(_)) => pick(
            rng,
            &[json!("random"), json!("wogan"), json!("bogus"), json!("")],
        )
        .clone(),
        Some(Value::Bool(b)) => json!(!b),
        _ => extreme_number(rng),
    }
}

/// A `--driver-weights` file: valid, with weights non-finite or huge, cut short, with a spoilt
/// header, empty, random bytes, or too long; `None` for a path that is no file.
fn weights_file(rng: &mut ChaCha8Rng, corpus: &Corpus, notes: &mut Vec<String>) -> Option<Vec<u8>> {
    let mut bytes = corpus.weights.clone();
    let how = match rng.random_range(0..9) {
        0 => "valid".to_owned(),
        1 | 2 => {
            let value = *pick(
                rng,
                &[
                    f32::NAN,
                    f32::INFINITY,
                    f32::NEG_INFINITY,
                    f32::MAX,
                    -f32::MAX,
                    1e30,
                    0.0,
                    1e-45,
                ],
            );
            let all = chance(rng, 0.3);
            // After the blob's 12-byte header (magic, version, count), one f32 per weight.
            let count = (bytes.len() - 12) / 4;
            let chosen: Vec<usize> = if all {
                (0..count).collect()
            } else {
                (0..rng.random_range(1..=100))
                    .map(|_| rng.random_range(0..count))
                    .collect()
            };
            for i in chosen {
                bytes[12 + 4 * i..16 + 4 * i].copy_from_slice(&value.to_le_bytes());
            }
            format!("{} weights = {value:e}", if all { "all" } else { "some" })
        }
        3 => {
            let at = rng.random_range(0..bytes.len());
            bytes.truncate(at);
            format!("cut at byte {at}")
        }
        4 => {
            let i = rng.random_range(0..12);
            bytes[i] ^= 0xff;
            format!("header byte {i} flipped")
        }
        5 => {
            bytes.clear();
            "empty".to_owned()
        }
        6 => {
            let len = rng.random_range(0..4096);
            bytes = (0..len).map(|_| rng.random::<u8>()).collect();
            format!("{len} random bytes")
        }
        7 => {
            bytes.extend_from_slice(&[0; 16]);
            "16 bytes too long".to_owned()
        }
        _ => {
            notes.push("weights: not a file".into());
            return None;
        }
    };
    notes.push(format!("weights.bin: {how}"));
    Some(bytes)
}

// ------------------------------------------------------------------------------------------------
// Cases known to fail, pinned so that the sample keeps checking them once they are fixed
// ------------------------------------------------------------------------------------------------

fn pinned_cases() -> Vec<Case> {
    let mut near_duplicates = Case::new(
        "pinned: validate --map-size 1e308, two points near 1e300 (panicked: capacity overflow)"
            .into(),
        Target::Validate,
    );
    near_duplicates
        .args
        .extend(["--map-size".into(), "1e308".into()]);
    near_duplicates.stdin = b"[[1e300,1e300],[1e300,1.0000000000001e300]]\n".to_vec();

    let config_case = |label: &str, config: &str| {
        let mut case = Case::new(label.into(), Target::Run);
        for arg in [
            "--config",
            "config.json",
            "--max-tests",
            "3",
            "--budget",
            "2s",
            "--quiet",
        ] {
            case.arg(arg);
        }
        case.file("config.json", config.as_bytes().to_vec());
        case.note(format!("config.json: {config}"));
        case
    };
    vec![
        near_duplicates,
        config_case(
            "pinned: run --config with sim.physics_hz 1e9 (hung)",
            r#"{"sim":{"physics_hz":1e9}}"#,
        ),
        config_case(
            "pinned: run --config with a generator of 4294967295 units (aborted)",
            r#"{"search":{"wogan":{"generator":{"hidden":4294967295}}}}"#,
        ),
    ]
}

// ------------------------------------------------------------------------------------------------
// Running and judging
// ------------------------------------------------------------------------------------------------

/// How a child ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum End {
    Exited(i32),
    Signalled(i32),
    /// Still running when the watchdog killed it.
    Hung,
}

/// The kinds of failure counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    Panic,
    Abort,
    Hang,
    NonJson,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Panic => "panic",
            Kind::Abort => "abort",
            Kind::Hang => "hang",
            Kind::NonJson => "non-JSON output",
        }
    }
}

/// Everything the report says about a failing case; a case that passes leaves only its counts.
#[derive(Debug, Clone)]
struct Failure {
    /// The kind and class of each failure of the case.
    found: Vec<(Kind, String)>,
    label: String,
    replay: Option<(u64, usize)>,
    target: Target,
    /// The shell command that runs the case again in its kept directory.
    command: String,
    notes: Vec<String>,
    /// Standard input and the input files, shortened.
    inputs: Vec<String>,
    stderr_tail: String,
    /// Output lines that are not JSON records, shortened.
    bad_lines: Vec<String>,
}

/// What one case did.
struct Ran {
    order: usize,
    target: Target,
    end: End,
    bad_line_count: usize,
    failure: Option<Failure>,
}

const STDIN: &str = "stdin";
const STDOUT: &str = "stdout";
const STDERR: &str = "stderr";

/// The shell script that limits the child's address space, then becomes the binary (`$0`).
fn limit_script(settings: &Settings) -> String {
    format!(
        "ulimit -v {}; exec \"$0\" \"$@\"",
        settings.memory_mb * 1024
    )
}

/// Runs `case` in `dir`, judges it, and removes `dir` unless the case failed.
fn run_one(case: &Case, order: usize, dir: &Path, settings: &Settings) -> Ran {
    let binary = env!("CARGO_BIN_EXE_wogan");
    std::fs::create_dir_all(dir).expect("a case directory");
    for (name, bytes) in &case.files {
        std::fs::write(dir.join(name), bytes).expect("a case's input file is written");
    }
    std::fs::write(dir.join(STDIN), &case.stdin).expect("a case's standard input is written");
    let file = |name: &str| File::create(dir.join(name)).expect("an output file");
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(limit_script(settings))
        .arg(binary)
        .args(&case.args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .stdin(File::open(dir.join(STDIN)).expect("standard input reads"))
        .stdout(file(STDOUT))
        .stderr(file(STDERR))
        .spawn()
        .expect("sh starts");
    let started = Instant::now();
    let mut pause = Duration::from_millis(1);
    let end = loop {
        if let Some(status) = child.try_wait().expect("the child can be waited for") {
            break match (status.code(), status.signal()) {
                (Some(code), _) => End::Exited(code),
                (None, Some(signal)) => End::Signalled(signal),
                (None, None) => End::Exited(-1),
            };
        }
        // The watchdog detects hangs: its limit is far above any case's normal time, so it says
        // nothing about speed.
        if started.elapsed() >= settings.watchdog {
            let _ = child.kill();
            let _ = child.wait();
            break End::Hung;
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(50));
    };
    let stdout = std::fs::read(dir.join(STDOUT)).unwrap_or_default();
    let stderr =
        String::from_utf8_lossy(&std::fs::read(dir.join(STDERR)).unwrap_or_default()).into_owned();
    let mut bad_lines = Vec::new();
    if case.target.writes_json_lines() {
        bad_lines.extend(non_json_lines("stdout", &stdout, end == End::Hung));
        for output in &case.json_outputs {
            for path in json_files(&dir.join(output)) {
                let bytes = std::fs::read(&path).unwrap_or_default();
                let name = path
                    .strip_prefix(dir)
                    .unwrap_or(&path)
                    .display()
                    .to_string();
                bad_lines.extend(non_json_lines(&name, &bytes, end == End::Hung));
            }
        }
    }
    let found = judge(case.target, end, &stderr, bad_lines.len());
    let failure = (!found.is_empty()).then(|| Failure {
        found,
        label: case.label.clone(),
        replay: case.replay,
        target: case.target,
        command: command_line(case, dir, binary, settings),
        notes: case.notes.clone(),
        inputs: inputs_shown(case),
        stderr_tail: tail(&stderr, 14),
        bad_lines: bad_lines.iter().take(2).cloned().collect(),
    });
    if failure.is_none() && !settings.keep_all {
        let _ = std::fs::remove_dir_all(dir);
    }
    Ran {
        order,
        target: case.target,
        end,
        bad_line_count: bad_lines.len(),
        failure,
    }
}

/// `path` if it is a file, or the files in it if it is a directory (a trace directory).
fn json_files(path: &Path) -> Vec<PathBuf> {
    if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        files.sort();
        files
    } else if path.is_file() {
        vec![path.to_path_buf()]
    } else {
        Vec::new()
    }
}

/// The lines of `bytes` that are not a JSON object with a string `"type"`, named by `source` and
/// line number. A last line cut short because the watchdog killed the writer is left out.
fn non_json_lines(source: &str, bytes: &[u8], killed: bool) -> Vec<String> {
    let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
    let last = lines.pop().unwrap_or_default();
    if !last.is_empty() && !killed {
        lines.push(last);
    }
    lines
        .iter()
        .enumerate()
        .filter(|(_, line)| !is_record(line))
        .map(|(i, line)| format!("{source}:{}: {}", i + 1, preview(line, 200)))
        .collect()
}

fn is_record(line: &[u8]) -> bool {
    serde_json::from_slice::<Value>(line)
        .ok()
        .is_some_and(|v| v.get("type").is_some_and(Value::is_string))
}

/// The failures a case showed: each with a class that groups failures of one cause.
fn judge(target: Target, end: End, stderr: &str, bad_lines: usize) -> Vec<(Kind, String)> {
    let name = target.name();
    let mut found = Vec::new();
    let panicked = end == End::Exited(101) || stderr.contains("panicked");
    if panicked {
        found.push((Kind::Panic, format!("{name}: {}", signature(stderr))));
    }
    match end {
        End::Signalled(signal) => found.push((
            Kind::Abort,
            format!("{name}: {}: {}", signal_name(signal), signature(stderr)),
        )),
        End::Exited(134) => found.push((
            Kind::Abort,
            format!("{name}: exit 134: {}", signature(stderr)),
        )),
        End::Hung => found.push((Kind::Hang, format!("{name}: still running at the watchdog"))),
        End::Exited(_) => {}
    }
    if bad_lines > 0 {
        found.push((
            Kind::NonJson,
            format!("{name}: an output line is not a JSON record"),
        ));
    }
    found
}

/// A failure's message (digits replaced by `N`, so that one cause makes one class) and the first
/// frame of this workspace in its backtrace.
fn signature(stderr: &str) -> String {
    let lines: Vec<&str> = stderr.lines().collect();
    let message = match lines.iter().position(|l| l.contains("panicked at")) {
        Some(i) => {
            let location = lines[i].split("panicked at ").nth(1).unwrap_or("");
            let message = lines.get(i + 1).copied().unwrap_or("").trim();
            // A location in the standard library (capacity overflow, slicing) says less than the
            // frame below; one in this workspace says where.
            if location.starts_with("/rustc/") || location.contains("/.cargo/") {
                message.to_owned()
            } else {
                format!("{message} at {}", location.trim_end_matches(':'))
            }
        }
        None => lines
            .iter()
            .rev()
            .find(|l| is_message(l))
            .map_or_else(|| "(nothing on stderr)".to_owned(), |l| l.trim().to_owned()),
    };
    let mut message: String = message
        .chars()
        .map(|c| if c.is_ascii_digit() { 'N' } else { c })
        .collect();
    // Runs of digits become one N.
    while message.contains("NN") {
        message = message.replace("NN", "N");
    }
    let message: String = message.chars().take(160).collect();
    let frame = lines.iter().filter_map(|l| frame_symbol(l)).find(|symbol| {
        let symbol = symbol.trim_start_matches('<');
        OUR_CRATES
            .iter()
            .any(|c| symbol.starts_with(&format!("{c}::")))
    });
    match frame {
        Some(frame) => format!("{message} (in {frame})"),
        None => message,
    }
}

/// The symbol of a backtrace frame line (`  12: road_sim::road::spline::interpolate`).
fn frame_symbol(line: &str) -> Option<&str> {
    let (number, symbol) = line.trim_start().split_once(": ")?;
    (!number.is_empty() && number.chars().all(|c| c.is_ascii_digit())).then_some(symbol.trim())
}

/// A line of stderr that says something (not backtrace or its notes).
fn is_message(line: &str) -> bool {
    let line = line.trim();
    !line.is_empty()
        && line != "stack backtrace:"
        && !line.starts_with("note:")
        && !line.starts_with("at ")
        && frame_symbol(line).is_none()
}

fn signal_name(signal: i32) -> String {
    match signal {
        4 => "SIGILL".into(),
        6 => "SIGABRT".into(),
        7 => "SIGBUS".into(),
        8 => "SIGFPE".into(),
        9 => "SIGKILL".into(),
        11 => "SIGSEGV".into(),
        15 => "SIGTERM".into(),
        other => format!("signal {other}"),
    }
}

/// The command that runs the case again, from any shell.
fn command_line(case: &Case, dir: &Path, binary: &str, settings: &Settings) -> String {
    let args: Vec<String> = case.args.iter().map(|a| shell_quote(a)).collect();
    format!(
        "cd {} && (ulimit -v {}; exec {} {}) < {STDIN}",
        shell_quote(&dir.display().to_string()),
        settings.memory_mb * 1024,
        shell_quote(binary),
        args.join(" ")
    )
}

fn shell_quote(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_./=,:+-%@".contains(c));
    if plain {
        text.to_owned()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// The case's standard input and input files, shortened.
fn inputs_shown(case: &Case) -> Vec<String> {
    let mut shown = Vec::new();
    if !case.stdin.is_empty() {
        shown.push(format!("stdin: {}", preview(&case.stdin, PREVIEW_BYTES)));
    }
    for (name, bytes) in &case.files {
        shown.push(format!("{name}: {}", preview(bytes, PREVIEW_BYTES)));
    }
    shown
}

/// Up to `max` bytes of `bytes` as one line of text: control characters escaped, the length said
/// when cut.
fn preview(bytes: &[u8], max: usize) -> String {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(max)]);
    let mut shown = String::new();
    for c in text.chars() {
        match c {
            '\n' => shown.push_str("\\n"),
            '\r' => shown.push_str("\\r"),
            '\t' => shown.push_str("\\t"),
            c if c.is_control() => write!(shown, "\\u{{{:x}}}", u32::from(c)).expect("text"),
            c => shown.push(c),
        }
    }
    if bytes.len() > max {
        write!(shown, "... ({} bytes in all)", bytes.len()).expect("text");
    }
    shown
}

/// The last `count` lines of `text`, each shortened.
fn tail(text: &str, count: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(count)..]
        .iter()
        .map(|l| preview(l.as_bytes(), 240))
        .collect::<Vec<_>>()
        .join("\n")
}

// ------------------------------------------------------------------------------------------------
// The campaign and its report
// ------------------------------------------------------------------------------------------------

/// A case to run: pinned, or made from the campaign's seed and this index.
enum Job {
    Pinned(Box<Case>),
    Generated(usize),
}

/// Counts of one command.
#[derive(Debug, Default, Clone)]
struct Tally {
    tried: usize,
    panics: usize,
    aborts: usize,
    hangs: usize,
    non_json_lines: usize,
    exit_0: usize,
    exit_1: usize,
    exit_2: usize,
    other: usize,
}

/// The outcome of a campaign.
struct Report {
    settings: Settings,
    pinned: usize,
    planned: usize,
    elapsed: Duration,
    root: PathBuf,
    tallies: BTreeMap<Target, Tally>,
    failures: Vec<Failure>,
}

impl Report {
    /// Failing cases.
    fn failing(&self) -> usize {
        self.failures.len()
    }
}

/// Runs the pinned cases and the campaign's cases, `settings.jobs` at a time.
fn fuzz(settings: &Settings, pinned: Vec<Case>) -> Report {
    let corpus = Corpus::load();
    let root = scratch_dir(settings.dir_name);
    let indices: Vec<usize> = match settings.only {
        Some(index) => vec![index],
        None => (0..settings.cases)
            .filter(|&i| settings.targets.contains(&Target::of_case(i)))
            .collect(),
    };
    let pinned_count = pinned.len();
    let jobs: Vec<Job> = pinned
        .into_iter()
        .map(|case| Job::Pinned(Box::new(case)))
        .chain(indices.into_iter().map(Job::Generated))
        .collect();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Ran>> = Mutex::new(Vec::new());
    let started = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..settings.jobs {
            scope.spawn(|| loop {
                let order = next.fetch_add(1, Ordering::SeqCst);
                let Some(job) = jobs.get(order) else { break };
                if settings.deadline.is_some_and(|d| started.elapsed() >= d) {
                    break;
                }
                let case = match job {
                    Job::Pinned(case) => (**case).clone(),
                    Job::Generated(index) => generate(&corpus, settings.seed, *index),
                };
                let ran = run_one(&case, order, &root.join(case.slug()), settings);
                results.lock().expect("no worker panicked").push(ran);
            });
        }
    });
    // Only the directories of failing cases are left; an empty root goes too.
    let _ = std::fs::remove_dir(&root);
    let mut results = results.into_inner().expect("no worker panicked");
    results.sort_by_key(|r| r.order);
    let mut tallies: BTreeMap<Target, Tally> = BTreeMap::new();
    let mut failures = Vec::new();
    for ran in results {
        let tally = tallies.entry(ran.target).or_default();
        tally.tried += 1;
        match ran.end {
            End::Exited(0) => tally.exit_0 += 1,
            End::Exited(1) => tally.exit_1 += 1,
            End::Exited(2) => tally.exit_2 += 1,
            _ => tally.other += 1,
        }
        tally.non_json_lines += ran.bad_line_count;
        if let Some(failure) = ran.failure {
            let has = |kind: Kind| failure.found.iter().any(|(k, _)| *k == kind);
            tally.panics += usize::from(has(Kind::Panic));
            tally.aborts += usize::from(has(Kind::Abort));
            tally.hangs += usize::from(has(Kind::Hang));
            failures.push(failure);
        }
    }
    Report {
        settings: settings.clone(),
        pinned: pinned_count,
        planned: jobs.len(),
        elapsed: started.elapsed(),
        root,
        tallies,
        failures,
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.settings;
        let tried: usize = self.tallies.values().map(|t| t.tried).sum();
        writeln!(
            f,
            "wogan fuzz: seed {}, {tried} of {} inputs ({} pinned) in {:.1} s; {} at once, \
             watchdog {} s, memory limit {} MiB",
            s.seed,
            self.planned,
            self.pinned,
            self.elapsed.as_secs_f64(),
            s.jobs,
            s.watchdog.as_secs(),
            s.memory_mb
        )?;
        if tried < self.planned {
            writeln!(f, "(stopped at FUZZ_MINUTES before every input was tried)")?;
        }
        writeln!(
            f,
            "{:<9} {:>7} {:>7} {:>7} {:>6} {:>15} | {:>7} {:>7} {:>7} {:>6}",
            "command",
            "inputs",
            "panics",
            "aborts",
            "hangs",
            "non-JSON lines",
            "exit 0",
            "exit 1",
            "exit 2",
            "other"
        )?;
        let mut total = Tally::default();
        for (target, t) in &self.tallies {
            writeln!(f, "{}", tally_row(target.name(), t))?;
            total.tried += t.tried;
            total.panics += t.panics;
            total.aborts += t.aborts;
            total.hangs += t.hangs;
            total.non_json_lines += t.non_json_lines;
            total.exit_0 += t.exit_0;
            total.exit_1 += t.exit_1;
            total.exit_2 += t.exit_2;
            total.other += t.other;
        }
        writeln!(f, "{}", tally_row("total", &total))?;
        if self.failures.is_empty() {
            return writeln!(f, "no failures");
        }
        let mut classes: BTreeMap<(Kind, &str), Vec<&Failure>> = BTreeMap::new();
        for failure in &self.failures {
            for (kind, class) in &failure.found {
                classes
                    .entry((*kind, class.as_str()))
                    .or_default()
                    .push(failure);
            }
        }
        writeln!(
            f,
            "\n{} failing inputs in {} classes (their directories are kept under {}):",
            self.failures.len(),
            classes.len(),
            self.root.display()
        )?;
        for ((kind, class), failures) in &classes {
            writeln!(f, "\n[{}] {class}: {} inputs", kind.name(), failures.len())?;
            for failure in failures.iter().take(EXAMPLES_PER_CLASS) {
                write_failure(f, failure)?;
            }
        }
        Ok(())
    }
}

fn tally_row(name: &str, t: &Tally) -> String {
    format!(
        "{name:<9} {:>7} {:>7} {:>7} {:>6} {:>15} | {:>7} {:>7} {:>7} {:>6}",
        t.tried,
        t.panics,
        t.aborts,
        t.hangs,
        t.non_json_lines,
        t.exit_0,
        t.exit_1,
        t.exit_2,
        t.other
    )
}

fn write_failure(f: &mut fmt::Formatter<'_>, failure: &Failure) -> fmt::Result {
    writeln!(f, "  - {} ({})", failure.label, failure.target.name())?;
    if let Some((seed, index)) = failure.replay {
        writeln!(
            f,
            "    replay:  FUZZ_SEED={seed} FUZZ_ONLY={index} scripts/fuzz_campaign.sh"
        )?;
    }
    writeln!(f, "    command: {}", failure.command)?;
    for note in &failure.notes {
        writeln!(
            f,
            "    fuzzed:  {}",
            preview(note.as_bytes(), PREVIEW_BYTES)
        )?;
    }
    for input in &failure.inputs {
        writeln!(f, "    input:   {input}")?;
    }
    for line in &failure.bad_lines {
        writeln!(f, "    output:  {line}")?;
    }
    for line in failure.stderr_tail.lines() {
        writeln!(f, "    stderr | {line}")?;
    }
    Ok(())
}

// ------------------------------------------------------------------------------------------------
// Tests
// ------------------------------------------------------------------------------------------------

/// The sample: none of its inputs may panic, abort, hang or make a command write a line that is
/// not JSON. The message lists every failure with what reproduces it.
#[test]
fn fuzz_sample() {
    let report = fuzz(&Settings::sample(), pinned_cases());
    assert_eq!(report.failing(), 0, "{report}");
}

/// The development-time campaign (`scripts/fuzz_campaign.sh`), set by the `FUZZ_*` variables.
#[test]
#[ignore = "minutes of fuzzing: run by scripts/fuzz_campaign.sh"]
fn fuzz_campaign() {
    let report = fuzz(&Settings::from_env(), Vec::new());
    println!("{report}");
    assert_eq!(report.failing(), 0, "failing inputs: see the classes above");
}

/// A case is a function of its seed and index alone, so that a failure replays.
#[test]
fn fuzz_cases_replay_from_their_seed() {
    let corpus = Corpus::load();
    for index in 0..12 {
        let (a, b) = (generate(&corpus, 5, index), generate(&corpus, 5, index));
        assert_eq!((&a.args, &a.stdin, &a.files), (&b.args, &b.stdin, &b.files));
    }
    let (a, b) = (generate(&corpus, 5, 0), generate(&corpus, 6, 0));
    assert_ne!((&a.args, &a.stdin, &a.files), (&b.args, &b.stdin, &b.files));
}
