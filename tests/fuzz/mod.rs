//! A seeded fuzz harness for the `wogan` binary (issue "Trustworthy under bad input and
//! interruption"): it feeds mutated input lines, input files and option values to `validate`,
//! `simulate`, `run`, `report`, `export`, `camera`, `replay`, `suite` and `sample`, and counts per
//! command the inputs tried, panics (exit 101 or "panicked" on stderr), aborts (killed by a signal,
//! or exit 134), hangs (still running when the watchdog kills it), lines that are not JSON records
//! in the JSON lines that `validate`, `simulate`, `run`, `replay` and `sample` write, and the exit
//! statuses (so that a command refusing every input up front shows).
//!
//! One file per concern: [`corpus`] (what cases are made of, including runs, a suite and a
//! generator the binary under test makes once), [`cases`] (one case builder per command),
//! [`option_values`], [`input_lines`], [`files`] (mutated inputs), [`pinned`] (known failures kept
//! as cases), [`runner`] (a child under limits and a watchdog) and [`campaign`] (many cases and
//! their report).
//!
//! Inputs are real roads (`tests/reference/roads.jsonl`), real runs (`tests/fixtures`, and runs of
//! this version) and records of every other kind, mutated: truncated, characters flipped, numbers
//! made huge, tiny, negative,
//! non-finite or out of every integer type, points collapsed or near-duplicated, arrays emptied or
//! made very long, other `type`s, deep nesting, pretty-printed over many lines, empty lines, binary
//! bytes, lines of megabytes. Options get values inside, at and beyond their ranges, non-finite
//! values, overflowing integers and garbage; `run --config` files and `--driver-weights` files are
//! mutated the same way. About half the cases keep every option valid, so that their inputs reach
//! past the option parser.
//!
//! Every random choice of a case comes from ChaCha seeded by the campaign seed and the case's
//! index, so a case replays from those two numbers alone (`FUZZ_SEED=S FUZZ_ONLY=I
//! scripts/runs/fuzz_campaign.sh`). A failure is reported with that replay, the shell command that
//! reproduces it in its kept directory (inputs, outputs, stderr), what was fuzzed, its input and
//! the tail of its standard error; failures are grouped into classes by their message and the first
//! frame of this workspace in the backtrace.
//!
//! One harness, two uses:
//! - `fuzz_sample` runs in `cargo test`: a small fixed-seed sample (`run` always bounded by
//!   `--max-tests` <= 3 and/or `--budget` <= 2s) plus the reproducers of failures already known,
//!   and asserts that none panics, aborts, hangs or writes a line that is not JSON.
//! - `fuzz_campaign` (ignored; `scripts/runs/fuzz_campaign.sh`) runs as many cases as `FUZZ_CASES` from
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
use road_sim::{CompetitionSetup, DriverKind};
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

mod campaign;
mod cases;
mod corpus;
mod files;
mod input_lines;
mod option_values;
mod pinned;
mod runner;

use campaign::*;
use cases::*;
use corpus::*;
use files::*;
use input_lines::*;
use option_values::*;
use pinned::*;
use runner::*;

/// How a campaign runs.
#[derive(Debug, Clone)]
pub(super) struct Settings {
    /// Seed of every case.
    pub(super) seed: u64,
    /// Case indices tried: `0..cases` (those of the chosen commands).
    pub(super) cases: usize,
    /// Only this case index.
    pub(super) only: Option<usize>,
    /// The commands fuzzed.
    pub(super) targets: Vec<Target>,
    /// Children run at once.
    pub(super) jobs: usize,
    /// A child still running after this long is killed and counted as a hang.
    pub(super) watchdog: Duration,
    /// Address-space limit of each child, MiB.
    pub(super) memory_mb: u64,
    /// No new case starts after this long.
    pub(super) deadline: Option<Duration>,
    /// Name of the scratch directory (kept cases live there).
    pub(super) dir_name: &'static str,
    /// Keep the directory of every case, not only of failing ones (to see what cases do).
    pub(super) keep_all: bool,
}

impl Settings {
    /// The sample run by `cargo test`: fixed, so that it is the same on every machine.
    pub(super) fn sample() -> Self {
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
    pub(super) fn from_env() -> Self {
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
pub(super) fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
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
pub(super) enum Target {
    Validate,
    Simulate,
    Run,
    Report,
    Export,
    Camera,
    Replay,
    Suite,
    Sample,
    Dataset,
}

impl Target {
    const ALL: [Target; 10] = [
        Target::Validate,
        Target::Simulate,
        Target::Run,
        Target::Report,
        Target::Export,
        Target::Camera,
        Target::Replay,
        Target::Suite,
        Target::Sample,
        Target::Dataset,
    ];

    pub(super) fn name(self) -> &'static str {
        match self {
            Target::Validate => "validate",
            Target::Simulate => "simulate",
            Target::Run => "run",
            Target::Report => "report",
            Target::Export => "export",
            Target::Camera => "camera",
            Target::Replay => "replay",
            Target::Suite => "suite",
            Target::Sample => "sample",
            Target::Dataset => "dataset",
        }
    }

    /// Whether the command's standard output is JSON lines, one record per line.
    pub(super) fn writes_json_lines(self) -> bool {
        matches!(
            self,
            Target::Validate | Target::Simulate | Target::Run | Target::Replay | Target::Sample
        )
    }

    /// The command case `index` of every campaign fuzzes, whichever commands are chosen, so that
    /// an index names the same case in every campaign of its seed.
    pub(super) fn of_case(index: usize) -> Target {
        Target::ALL[index % Target::ALL.len()]
    }
}

/// The sample: none of its inputs may panic, abort, hang or make a command write a line that is
/// not JSON. The message lists every failure with what reproduces it.
#[test]
fn fuzz_sample() {
    let report = fuzz(&Settings::sample(), pinned_cases());
    assert_eq!(report.failing(), 0, "{report}");
    assert_dev_null_unharmed();
    // Inputs that reach the commands' work, not only their refusals (export once refused all).
    for target in [Target::Export, Target::Replay, Target::Sample] {
        let exported = report.tallies.get(&target).map_or(0, |t| t.exit_0);
        assert!(
            exported > 0,
            "no {} case got past its input checks:\n{report}",
            target.name()
        );
    }
}

/// The development-time campaign (`scripts/runs/fuzz_campaign.sh`), set by the `FUZZ_*` variables.
#[test]
#[ignore = "minutes of fuzzing: run by scripts/runs/fuzz_campaign.sh"]
fn fuzz_campaign() {
    let report = fuzz(&Settings::from_env(), Vec::new());
    println!("{report}");
    assert_eq!(report.failing(), 0, "failing inputs: see the classes above");
    assert_dev_null_unharmed();
}

/// Cases name `/dev/null` as an output: it must still be the device afterwards. (An output once
/// renamed a file over it, as root, and every later program on the machine that read /dev/null
/// read that file.)
fn assert_dev_null_unharmed() {
    use std::os::unix::fs::FileTypeExt;
    let null = std::fs::symlink_metadata("/dev/null").expect("/dev/null exists");
    assert!(
        null.file_type().is_char_device(),
        "a case replaced /dev/null with a regular file (restore it: rm /dev/null && mknod -m 666 /dev/null c 1 3)"
    );
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
