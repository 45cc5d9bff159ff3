//! One case builder per command: what a case runs, with which options and inputs.

use super::*;

/// One invocation of the binary: its arguments, standard input and files, made in a directory of
/// its own (every path in `args` is relative to it).
#[derive(Debug, Clone)]
pub(super) struct Case {
    /// How the report names it.
    pub(super) label: String,
    /// The campaign seed and index it was made from (`None` for a pinned reproducer).
    pub(super) replay: Option<(u64, usize)>,
    pub(super) target: Target,
    /// The arguments, the command's name first.
    pub(super) args: Vec<String>,
    pub(super) stdin: Vec<u8>,
    /// Files written in the case's directory before the child starts.
    pub(super) files: Vec<(String, Vec<u8>)>,
    /// Files or directories of JSON lines the command writes besides standard output.
    pub(super) json_outputs: Vec<String>,
    /// What was fuzzed, in words, for reading a failure.
    pub(super) notes: Vec<String>,
}

impl Case {
    pub(super) fn new(label: String, target: Target) -> Self {
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

    pub(super) fn arg(&mut self, arg: impl Into<String>) {
        self.args.push(arg.into());
    }

    /// `--name value` or `--name=value`; a value that starts with `-` mostly takes the second form,
    /// so that it reaches the option's parser instead of reading as another option.
    pub(super) fn opt(&mut self, rng: &mut ChaCha8Rng, name: &str, value: impl Into<String>) {
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

    pub(super) fn file(&mut self, name: &str, bytes: Vec<u8>) {
        self.files.push((name.to_owned(), bytes));
    }

    pub(super) fn note(&mut self, note: impl Into<String>) {
        self.notes.push(note.into());
    }

    /// The directory name of the case.
    pub(super) fn slug(&self) -> String {
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
pub(super) fn generate(corpus: &Corpus, seed: u64, index: usize) -> Case {
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
        Target::Replay => replay_case(rng, corpus, &mut case),
        Target::Suite => suite_case(rng, corpus, &mut case),
        Target::Sample => sample_case(rng, corpus, &mut case),
        Target::Dataset => dataset_case(rng, corpus, &mut case),
    }
    case
}

pub(super) fn validate_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
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

pub(super) fn simulate_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
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
    if chance(rng, 0.25) {
        executor_options(rng, corpus, case, wild);
    }
    stray_argument(rng, case, wild);
}

/// An integer option: its name, how often a case gives it, its lowest and highest valid values,
/// and the range its typical values come from.
pub(super) type IntOption = (&'static str, f64, i128, i128, (i64, i64));
/// A floating-point option, as [`IntOption`].
pub(super) type FloatOption = (&'static str, f64, f64, f64, (f64, f64));

/// Budgets that end a run within two seconds.
pub(super) const SHORT_BUDGETS: [&str; 6] = ["0s", "1ms", "100ms", "500ms", "1s", "2s"];
/// Budgets a run with at most three tests may have: any valid one, and invalid ones.
pub(super) const OTHER_BUDGETS: [&str; 16] = [
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

pub(super) fn run_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
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
    if chance(rng, 0.15) {
        executor_options(rng, corpus, case, wild);
    }
    stray_argument(rng, case, wild);
}

/// `--executor` with an executor that answers garbage: `cat` of mutated lines (records of every
/// kind, huge numbers, binary, ...), so every answer tries the protocol's reader.
fn executor_options(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case, wild: bool) {
    let answers = if chance(rng, 0.7) {
        executor_answers(rng, &mut case.notes)
    } else {
        input_lines(rng, corpus, &mut case.notes)
    };
    case.file("answers.txt", answers);
    let executor = if wild && chance(rng, 0.3) {
        *pick(
            rng,
            &[
                "cmd:",
                "cat answers.txt",
                "cmd:no-such-program-here",
                "cmd:exit 3",
            ],
        )
    } else {
        "cmd:cat answers.txt"
    };
    case.opt(rng, "--executor", executor);
    // Short waits: an executor that says nothing is a timeout, not a hang of the harness.
    let timeout = if wild {
        *pick(rng, &["1s", "0s", "-1s", "10ms", "forever"])
    } else {
        "1s"
    };
    case.opt(rng, "--executor-timeout", timeout);
    if chance(rng, 0.5) {
        let errors = int_arg(rng, wild, 1, 1000, (1, 5));
        case.opt(rng, "--max-failed-drives", errors);
    }
}

/// What a hostile executor writes: a reply to `hello` (mostly a good one, so that its answers are
/// read), then answers to roads 1, 2, ... with every field the protocol has, mutated: garbage,
/// non-finite and huge numbers, ids out of range, oversized lines.
fn executor_answers(rng: &mut ChaCha8Rng, notes: &mut Vec<String>) -> Vec<u8> {
    let mut steps = Vec::new();
    let mut reply = serde_json::json!({
        "type": "hello", "protocol": "wogan-executor", "version": 3,
        "roads_at_once": 1,
        "executor": {"name": "fuzz", "version": "1", "settings": {"k": 1}},
    });
    if chance(rng, 0.2) {
        steps.push(format!("reply: {}", mutate_value(rng, &mut reply)));
    }
    let mut text = encode(rng, &reply, 0.0, &mut steps);
    text.push(b'\n');
    for id in 1..=rng.random_range(1..=6u64) {
        let mut answer = serde_json::json!({
            "id": id,
            "max_bolp": rng.random_range(0.0..=1.0f64),
            "outcome": *pick(rng, &["PASS", "FAIL", "ERROR"]),
            "sim_time_s": rng.random_range(0.0..100.0f64),
            "oob_side": *pick(rng, &["left", "right"]),
            "oob_point": [rng.random_range(0.0..200.0f64), rng.random_range(0.0..200.0f64)],
            "min_lane_distance_m": rng.random_range(-3.0..2.0f64),
            "error": "a reason",
        });
        if chance(rng, 0.6) {
            steps.push(format!("answer {id}: {}", mutate_value(rng, &mut answer)));
        }
        let mut line = encode(rng, &answer, 0.0, &mut steps);
        if chance(rng, 0.15) {
            steps.push(format!("answer {id}: {}", mutate_text(rng, &mut line)));
        }
        if chance(rng, 0.03) {
            // Past wogan's line bound (16 MiB): refused by length, never read whole.
            steps.push(format!("answer {id}: a 17 MiB line"));
            line = vec![b' '; 17 << 20];
        }
        text.extend_from_slice(&line);
        text.push(b'\n');
    }
    notes.push(format!("executor's answers: {}", steps.join("; ")));
    text
}

pub(super) fn report_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
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
    if chance(rng, 0.3) {
        // The page: every string of the files goes into it.
        case.arg("--html");
    }
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

pub(super) fn export_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.3);
    if chance(rng, 0.3) {
        let format = name_arg(rng, wild, &["sbst"]);
        case.opt(rng, "--format", format);
    }
    // Half the cases export a run of this version as it wrote it, so that they reach the export's
    // work (replaying every test); the rest mutate one, or an older layout's.
    let run = if chance(rng, 0.5) {
        case.note("run.jsonl: a run of this wogan, unchanged".to_owned());
        records_bytes(pick::<Vec<Value>>(rng, &corpus.own_runs))
    } else {
        let base = if chance(rng, 0.5) {
            pick(rng, &corpus.own_runs)
        } else {
            pick(rng, &corpus.runs)
        };
        records_file(rng, corpus, base, "run.jsonl", &mut case.notes)
    };
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

pub(super) fn camera_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
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

pub(super) fn dataset_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.4);
    // Few frames: every valid count is work, so the wild ones are the invalid counts only.
    let frames = if wild && chance(rng, 0.3) {
        pick(rng, &["0", "-1", "10000001", "1e9", "x", ""]).to_string()
    } else {
        rng.random_range(1..=20u32).to_string()
    };
    case.opt(rng, "--frames", frames);
    let out = if wild && chance(rng, 0.2) {
        *pick(rng, &["roads.jsonl", "/dev/null", "", "."])
    } else {
        "data"
    };
    case.opt(rng, "--out", out);
    if chance(rng, 0.5) {
        // The roads to drive, from a file of lines `validate` reads (fuzzed), else random ones.
        let roads = input_lines(rng, corpus, &mut case.notes);
        case.file("roads.jsonl", roads);
        case.opt(rng, "--roads", "roads.jsonl");
    }
    if chance(rng, 0.3) {
        let contract = name_arg(rng, wild, &["udacity", "sbst2022"]);
        case.opt(rng, "--contract", contract);
    }
    if chance(rng, 0.3) {
        let hz = float_arg(rng, wild, 0.1, 60.0, (5.0, 30.0));
        case.opt(rng, "--record-hz", hz);
    }
    if chance(rng, 0.3) {
        let curvature = float_arg(rng, wild, 0.0, 0.3, (0.005, 0.07));
        case.opt(rng, "--max-curvature", curvature);
    }
    if chance(rng, 0.3) {
        let failed = int_arg(rng, wild, 1, 1000, (1, 5));
        case.opt(rng, "--max-failed-drives", failed);
    }
    if chance(rng, 0.3) {
        let seed = int_arg(rng, wild, 0, u64::MAX as i128, (0, 1000));
        case.opt(rng, "--seed", seed);
    }
    driver_options(rng, corpus, case, wild);
    stray_argument(rng, case, wild);
}

/// Where a road-reading command reads its lines: standard input, `-`, a file, or (wild) a path
/// that is missing, a directory or empty.
pub(super) fn input_source(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case, wild: bool) {
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
pub(super) fn driver_options(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    case: &mut Case,
    wild: bool,
) -> DriverKind {
    if chance(rng, 0.1) {
        // A controller process that answers garbage: `cat` of mutated lines, one per step.
        let replies = input_lines(rng, corpus, &mut case.notes);
        case.file("controller.txt", replies);
        let oracle = if wild && chance(rng, 0.3) {
            *pick(
                rng,
                &[
                    "cmd:",
                    "cmd:exit 1",
                    "cmd:no-such-program-here",
                    "cmd:sleep 0",
                ],
            )
        } else {
            "cmd:cat controller.txt"
        };
        case.opt(rng, "--oracle", oracle);
        // Its settings are checked like any driver's (the built-in ones' fuzz the rest).
        return DriverKind::BeamNgAiProxy;
    }
    if chance(rng, 0.08) {
        // A camera network: a fixture, broken or not, and the settings under which the dave2-proxy
        // fixture drives (the competition's crop does not fit its 66 rows, which is refused).
        let path = match onnx_model_file(rng, &mut case.notes) {
            Some(bytes) => {
                case.file("model.onnx", bytes);
                "onnx:model.onnx"
            }
            None => *pick(rng, &["onnx:missing.onnx", "onnx:.", "onnx:"]),
        };
        case.opt(rng, "--oracle", path);
        if chance(rng, 0.7) {
            let config = *pick(
                rng,
                &[
                    r#"{"driver": {"crop_top_rows": 0, "crop_bottom_rows": 0}}"#,
                    r#"{"driver": {"crop_top_rows": 2, "crop_bottom_rows": 0, "throttle": "network"}}"#,
                    r#"{"driver": {"crop_top_rows": 0, "crop_bottom_rows": 0, "layout": "nchw", "pixel_scaling": "unit"}}"#,
                    r#"{"driver": {"crop_top_rows": 70, "model": "x.onnx"}}"#,
                ],
            );
            case.file("onnx.json", config.as_bytes().to_vec());
            case.opt(rng, "--config", "onnx.json");
        }
        return DriverKind::BeamNgAiProxy;
    }
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
pub(super) fn stray_argument(rng: &mut ChaCha8Rng, case: &mut Case, wild: bool) {
    if wild && chance(rng, 0.04) {
        // Not `--help`: help on stdout is right, and would read as a line that is not JSON.
        let stray = *pick(rng, &["--frobnicate", "stray", "--", "-x"]);
        case.arg(stray);
        case.note(format!("stray argument {stray:?}"));
    }
}

/// Records as the JSON lines of a file.
pub(super) fn records_bytes(records: &[Value]) -> Vec<u8> {
    records
        .iter()
        .flat_map(|r| (r.to_string() + "\n").into_bytes())
        .collect()
}

/// A file of saved roads for `replay` or `suite`: a run of this version as it is, a mutated run
/// (of this version or an older layout), a suite, or mutated input lines.
fn saved_roads_file(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case, name: &str) -> Vec<u8> {
    match rng.random_range(0..6) {
        0 | 1 => {
            case.note(format!("{name}: a run of this wogan, unchanged"));
            records_bytes(pick::<Vec<Value>>(rng, &corpus.own_runs))
        }
        2 => {
            let base = if chance(rng, 0.5) {
                pick(rng, &corpus.own_runs)
            } else {
                pick(rng, &corpus.runs)
            };
            records_file(rng, corpus, base, name, &mut case.notes)
        }
        3 => {
            case.note(format!("{name}: a suite"));
            corpus.suite.clone()
        }
        4 => {
            let mut suite: Vec<Value> = corpus
                .suite
                .split(|b| *b == b'\n')
                .filter_map(|line| serde_json::from_slice(line).ok())
                .collect();
            records_file(
                rng,
                corpus,
                &std::mem::take(&mut suite),
                name,
                &mut case.notes,
            )
        }
        _ => input_lines(rng, corpus, &mut case.notes),
    }
}

pub(super) fn replay_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.4);
    let files = if chance(rng, 0.8) {
        1
    } else {
        rng.random_range(2..=3)
    };
    for i in 0..files {
        let name = format!("roads.{i}.jsonl");
        let bytes = saved_roads_file(rng, corpus, case, &name);
        case.file(&name, bytes);
        case.arg(&name);
    }
    if wild && chance(rng, 0.3) {
        let path = *pick(rng, &["missing.jsonl", ".", "/dev/null", "-"]);
        case.arg(path);
        case.note(format!("FILE {path:?}"));
    }
    driver_options(rng, corpus, case, wild);
    if chance(rng, 0.3) {
        let jobs = int_arg(rng, wild, 1, 256, (1, 4));
        case.opt(rng, "--jobs", jobs);
    }
    if chance(rng, 0.4) {
        let fail_on = name_arg(rng, wild, &["any", "changed"]);
        case.opt(rng, "--fail-on", fail_on);
    }
    if chance(rng, 0.4) {
        let junit = if wild {
            *pick(rng, &["out.xml", "roads.0.jsonl", "/dev/null", "."])
        } else {
            "out.xml"
        };
        case.opt(rng, "--junit", junit);
    }
    if chance(rng, 0.25) {
        executor_options(rng, corpus, case, wild);
    }
    stray_argument(rng, case, wild);
}

pub(super) fn suite_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.4);
    // The suite written to: absent, a suite, a mutated one, or another file.
    match rng.random_range(0..4) {
        0 => case.note("suite.jsonl: absent".to_owned()),
        1 => case.file("suite.jsonl", corpus.suite.clone()),
        _ => {
            let bytes = saved_roads_file(rng, corpus, case, "suite.jsonl");
            case.file("suite.jsonl", bytes);
        }
    }
    if chance(rng, 0.3) {
        case.arg("list");
        case.arg(if wild {
            *pick(rng, &["suite.jsonl", "missing.jsonl", "."])
        } else {
            "suite.jsonl"
        });
        return;
    }
    case.arg("add");
    let runs = if chance(rng, 0.7) {
        1
    } else {
        rng.random_range(2..=3)
    };
    for i in 0..runs {
        let name = format!("run.{i}.jsonl");
        let bytes = saved_roads_file(rng, corpus, case, &name);
        case.file(&name, bytes);
        case.arg(&name);
    }
    let to = if wild && chance(rng, 0.2) {
        *pick(rng, &["run.0.jsonl", ".", "/dev/null"])
    } else {
        "suite.jsonl"
    };
    case.opt(rng, "--to", to);
    if chance(rng, 0.5) {
        let max = int_arg(rng, wild, 1, 1_000_000, (1, 20));
        case.opt(rng, "--max", max);
    }
    stray_argument(rng, case, wild);
}

pub(super) fn sample_case(rng: &mut ChaCha8Rng, corpus: &Corpus, case: &mut Case) {
    let wild = chance(rng, 0.4);
    // Half the cases sample from a generator file as this wogan wrote it, so that they reach the
    // sampling; the rest give it a damaged one.
    let generator = if chance(rng, 0.5) {
        case.note("gen.json: as saved".to_owned());
        corpus.generator.clone()
    } else {
        let mut value: Value =
            serde_json::from_slice(&corpus.generator).expect("the corpus generator is JSON");
        match rng.random_range(0..3) {
            0 => {
                let how = mutate_value(rng, &mut value);
                case.note(format!("gen.json: {how}"));
                serde_json::to_vec(&value).expect("JSON")
            }
            1 => {
                let cut = rng.random_range(0..corpus.generator.len());
                case.note(format!("gen.json: cut at byte {cut}"));
                corpus.generator[..cut].to_vec()
            }
            _ => input_lines(rng, corpus, &mut case.notes),
        }
    };
    case.file("gen.json", generator);
    let path = if wild && chance(rng, 0.2) {
        *pick(rng, &["missing.json", ".", "/dev/null"])
    } else {
        "gen.json"
    };
    case.opt(rng, "--generator", path);
    if chance(rng, 0.6) {
        let n = int_arg(rng, wild, 1, 100_000, (1, 20));
        case.opt(rng, "-n", n);
    } else {
        // The default of 50 is more than a sample case needs.
        case.opt(rng, "-n", "5");
    }
    if chance(rng, 0.5) {
        let seed = int_arg(rng, wild, 0, i128::from(u64::MAX), (0, 1000));
        case.opt(rng, "--seed", seed);
    }
    stray_argument(rng, case, wild);
}
