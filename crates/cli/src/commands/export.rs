//! `wogan export --format sbst`: a run in the SBST competition's result layout, one
//! `test.NNNN.json` per executed test (without `execution_data`) and `generation_stats.csv`.
//!
//! The directory written to must be new or empty, so that an export is never mixed with files
//! of another (an earlier, longer export's `test.0031.json` would read as part of this one).
//! `--force` replaces an earlier export, and removes nothing else. The run file must not be in
//! that directory, where the export could write over it.

use crate::records::{known, TestRecord};
use crate::report::run_file::{read_run, RunFile};
use crate::Status;
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use road_sim::{Outcome, Point, Road, Validator};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The layouts `wogan export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// The SBST tool competition's results: test.NNNN.json and generation_stats.csv.
    Sbst,
}

/// Options of `wogan export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The layout to write.
    #[arg(long, value_enum, default_value_t = ExportFormat::Sbst)]
    pub format: ExportFormat,
    /// JSON lines of one `wogan run`.
    #[arg(value_name = "RUN")]
    pub run: PathBuf,
    /// Directory to write to: new (created) or empty.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Replace an earlier export in DIR: remove its test.NNNN.json and generation_stats.csv
    /// first (refused, removing nothing, when DIR holds anything else).
    #[arg(long)]
    pub force: bool,
}

/// The file of generation totals.
const STATS_FILE: &str = "generation_stats.csv";

/// The competition's features of a test.
#[derive(Debug, Serialize)]
struct Features {
    #[serde(rename = "MAX_CURV")]
    max_curv: Option<f64>,
    #[serde(rename = "DIR_COV")]
    dir_cov: Option<f64>,
    #[serde(rename = "STD_SA")]
    std_sa: Option<f64>,
    #[serde(rename = "MEAN_LP")]
    mean_lp: Option<f64>,
    #[serde(rename = "MAX_LP")]
    max_lp: Option<f64>,
}

/// A competition test object, without `execution_data`.
#[derive(Debug, Serialize)]
struct CompetitionTest<'a> {
    id: usize,
    road_points: &'a [Point],
    interpolated_points: Vec<Point>,
    is_valid: bool,
    validation_message: &'static str,
    test_outcome: Outcome,
    description: String,
    features: Features,
}

/// Totals of `generation_stats.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerationStats {
    /// Valid plus invalid tests generated.
    pub generated: u64,
    /// Tests executed (valid).
    pub valid: u64,
    /// Invalid candidates rejected.
    pub invalid: u64,
    /// Tests that passed.
    pub passed: u64,
    /// Tests that failed.
    pub failed: u64,
    /// Tests in error.
    pub in_error: u64,
    /// Generation wall time including training, seconds.
    pub generation_s: f64,
    /// Execution wall time, seconds.
    pub execution_s: f64,
    /// Simulated time, seconds.
    pub simulated_s: f64,
}

impl GenerationStats {
    /// Totals of `run`: from its summary where present, else summed from the test records.
    pub fn of(run: &RunFile) -> Self {
        let count = |outcome: Outcome| {
            run.tests
                .iter()
                .filter(|t| t.execution.result.outcome == outcome)
                .count() as u64
        };
        let summed =
            |f: fn(&TestRecord) -> f64| run.tests.iter().filter_map(|t| known(f(t))).sum::<f64>();
        let (invalid, generation_s, execution_s) = match &run.summary {
            Some(s) => (
                s.invalid_candidates as u64,
                s.generation_s + s.training_s,
                s.simulation_s,
            ),
            None => (
                run.tests.iter().map(|t| t.invalid_candidates as u64).sum(),
                (summed(|t| t.generation_ms) + run.train_ms) / 1000.0,
                summed(|t| t.execution.result.execution_ms) / 1000.0,
            ),
        };
        let valid = run.tests.len() as u64;
        Self {
            generated: valid + invalid,
            valid,
            invalid,
            passed: count(Outcome::Pass),
            failed: count(Outcome::Fail),
            in_error: count(Outcome::Error),
            generation_s,
            execution_s,
            simulated_s: summed(|t| t.execution.result.sim_time_s),
        }
    }

    /// The CSV text: the competition's header and one row of totals.
    pub fn csv(&self) -> String {
        format!(
            "test_generated,test_valid,test_invalid,test_passed,test_failed,test_in_error,\
             real_time_generation,real_time_execution,simulated_time_execution\n\
             {},{},{},{},{},{},{},{},{}\n",
            self.generated,
            self.valid,
            self.invalid,
            self.passed,
            self.failed,
            self.in_error,
            self.generation_s,
            self.execution_s,
            self.simulated_s
        )
    }
}

/// Runs `wogan export`.
pub fn run(args: &ExportArgs) -> Result<Status> {
    refuse_input_in_dir(&args.run, &args.dir)?;
    let run = read_run(&args.run)?;
    for problem in &run.problems {
        eprintln!("wogan export: {problem}");
    }
    prepare_dir(&args.dir, args.force)?;
    let validator = Validator::default();
    let seed = run.header.as_ref().and_then(|h| h.seed);
    for test in &run.tests {
        write_test(&args.dir, test, &validator, seed)?;
    }
    let csv_path = args.dir.join(STATS_FILE);
    std::fs::write(&csv_path, GenerationStats::of(&run).csv())
        .with_context(|| format!("cannot write {}", csv_path.display()))?;
    eprintln!(
        "wogan export: wrote {} tests to {}",
        run.tests.len(),
        args.dir.display()
    );
    Ok(if run.problems.is_empty() {
        Status::AllRead
    } else {
        Status::SomeLinesBad
    })
}

/// Whether a file named `name` is one that export writes: `test.NNNN.json` (`NNNN` the test's
/// id, 4 digits or more) or `generation_stats.csv`.
fn is_export_file(name: &str) -> bool {
    let id = name
        .strip_prefix("test.")
        .and_then(|rest| rest.strip_suffix(".json"));
    name == STATS_FILE
        || id.is_some_and(|id| !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()))
}

/// Refuses a run file in `dir` itself, where the export writes: it could be written over
/// (`wogan export dir/test.0001.json dir`), or read as part of the export.
fn refuse_input_in_dir(run: &Path, dir: &Path) -> Result<()> {
    // A file or directory that cannot be resolved (a missing one, standard input) is no clash;
    // reading the run reports a missing file.
    let (Ok(run_file), Ok(dir_resolved)) = (std::fs::canonicalize(run), std::fs::canonicalize(dir))
    else {
        return Ok(());
    };
    if run_file.parent() == Some(dir_resolved.as_path()) {
        bail!(
            "cannot export {} into {}: the run file is in that directory, where the export \
             writes its files (it could write over its input); export to another directory",
            run.display(),
            dir.display()
        );
    }
    Ok(())
}

/// Makes `dir` ready for the export: creates it when missing; an empty one is fine. One holding
/// files is refused, unless `force` and they are all an earlier export's (see
/// [`is_export_file`]), which are then removed. Nothing is removed when anything else is there.
fn prepare_dir(dir: &Path, force: bool) -> Result<()> {
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create {}", dir.display()));
        }
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", dir.display())),
        Ok(metadata) if !metadata.is_dir() => bail!("{} is not a directory", dir.display()),
        Ok(_) => {}
    }
    let mut own: Vec<String> = Vec::new();
    let mut others: Vec<String> = Vec::new();
    let entries =
        std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))?;
    for entry in entries {
        let entry = entry.with_context(|| format!("cannot list {}", dir.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        // A directory or link under an export's name is not one of its files.
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if is_file && is_export_file(&name) {
            own.push(name);
        } else {
            others.push(name);
        }
    }
    if own.is_empty() && others.is_empty() {
        return Ok(());
    }
    own.sort();
    others.sort();
    if !force {
        let all: Vec<String> = others.iter().chain(&own).cloned().collect();
        bail!(
            "{} already holds {}; export into a new or empty directory, or give --force to \
             replace an earlier export there",
            dir.display(),
            some_of(&all)
        );
    }
    if !others.is_empty() {
        bail!(
            "{} holds what export does not write ({}); --force replaces only an earlier \
             export's test.NNNN.json and {STATS_FILE}, so nothing was removed",
            dir.display(),
            some_of(&others)
        );
    }
    for name in &own {
        let path = dir.join(name);
        std::fs::remove_file(&path)
            .with_context(|| format!("cannot remove {} (--force)", path.display()))?;
    }
    eprintln!(
        "wogan export: removed the {} file(s) of an earlier export from {}",
        own.len(),
        dir.display()
    );
    Ok(())
}

/// How many files `names` are, naming the first few (`3 files: a, b, c`).
fn some_of(names: &[String]) -> String {
    const SHOWN: usize = 5;
    let shown = names[..names.len().min(SHOWN)].join(", ");
    let more = if names.len() > SHOWN { ", …" } else { "" };
    match names.len() {
        1 => format!("1 file: {shown}"),
        n => format!("{n} files: {shown}{more}"),
    }
}

/// Writes `DIR/test.NNNN.json` for one test.
fn write_test(
    dir: &Path,
    test: &TestRecord,
    validator: &Validator,
    seed: Option<u64>,
) -> Result<()> {
    let road_points = &test.execution.road_points;
    let result = &test.execution.result;
    let verdict = validator.validate(road_points);
    let interpolated_points = Road::new(road_points)
        .map(|r| r.interpolated)
        .unwrap_or_default();
    let phase = test.phase.name();
    let seed = seed.map_or_else(|| "unknown".to_owned(), |s| s.to_string());
    let object = CompetitionTest {
        id: test.id,
        road_points,
        interpolated_points,
        is_valid: verdict.is_valid(),
        validation_message: verdict.message(),
        test_outcome: result.outcome,
        description: format!("wogan test {} ({phase} phase, seed {seed})", test.id),
        features: Features {
            max_curv: known(result.max_curv),
            dir_cov: known(result.dir_cov),
            std_sa: known(result.std_sa),
            mean_lp: known(result.mean_lp),
            max_lp: known(result.max_lp),
        },
    };
    let path = dir.join(format!("test.{:04}.json", test.id));
    let text = serde_json::to_string(&object).context("cannot encode a test as JSON")?;
    std::fs::write(&path, text + "\n").with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn export_files_are_known_by_name() {
        for name in ["test.0001.json", "test.12345.json", "generation_stats.csv"] {
            assert!(is_export_file(name), "{name}");
        }
        for name in [
            "test..json",
            "test.1a.json",
            "test.0001.json.bak",
            "run.jsonl",
            "notes",
        ] {
            assert!(!is_export_file(name), "{name}");
        }
    }
}
