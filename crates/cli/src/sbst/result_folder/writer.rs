//! The competition's result folder, written from a run: one `test.NNNN.json` per kept test with
//! its `execution_data`, `generation_stats.csv` and `oob_stats.csv` (the pipeline's `OOBAnalyzer`
//! summary). The execution records come from driving each test again with the run's settings,
//! checked to replay the recorded drive exactly.

use crate::files::records::TestRecord;
use crate::files::run_file::{RunFile, RunHeader};
use crate::files::sbst_format::{
    description, execution_data, test_file_number, CompetitionTest, Features,
};
use crate::sbst::metrics::{oob_summary, GenerationStats};
use anyhow::{bail, Context, Result};
use road_sim::{simulate, DriverConfig, Road, SimConfig, SimResult, Validator};
use std::path::{Path, PathBuf};

/// The file of generation totals.
const STATS_FILE: &str = "generation_stats.csv";
/// The file of the OOB analysis.
const OOB_STATS_FILE: &str = "oob_stats.csv";

/// Writes `run` (whose header is `header`) into `dir` as the pipeline's result folder: every
/// kept test driven again, `generation_stats.csv` and `oob_stats.csv`. `dir` must be new or empty,
/// or with `force` hold only an earlier export; `weights` are the DAVE-2 weights the run used
/// when not the built-in ones. Nothing is left of a half-written export.
pub fn write_result_folder(
    run: &RunFile,
    header: &RunHeader,
    dir: &Path,
    force: bool,
    weights: Option<&Path>,
) -> Result<()> {
    let replay = Replay::of(header, weights)?;
    prepare_dir(dir, force)?;
    let kept = &run.tests;
    let width = name_width(kept.iter().map(|t| t.id));
    let validator = Validator::new(header.map_size_m);
    let mut written = Vec::with_capacity(kept.len());
    for test in kept {
        match write_test(dir, width, test, &validator, &replay, header.seed) {
            Ok(path) => written.push(path),
            Err(error) => {
                // A half export would read as a whole one: take back what was written.
                for path in &written {
                    let _ = std::fs::remove_file(path);
                }
                return Err(error.context("nothing was exported"));
            }
        }
    }
    let csv_path = dir.join(STATS_FILE);
    std::fs::write(&csv_path, GenerationStats::of(run).csv())
        .with_context(|| format!("cannot write {}", csv_path.display()))?;
    write_oob_stats(dir, run)?;
    Ok(())
}

/// How many digits test file names give ids: as many as the largest id needs, and at least the
/// pipeline's 4, so that file names sort in id order, as the pipeline's analysis reads them.
fn name_width(ids: impl Iterator<Item = usize>) -> usize {
    ids.map(|id| id.to_string().len()).max().unwrap_or(0).max(4)
}

/// Writes `oob_stats.csv` as the pipeline's `create_summary` does; a run the pipeline's analysis
/// would stop on gets no file and a note on stderr, as the pipeline's would end there.
fn write_oob_stats(dir: &Path, run: &RunFile) -> Result<()> {
    let path = dir.join(OOB_STATS_FILE);
    match oob_summary(run) {
        Ok(summary) => std::fs::write(&path, road_sim::oob::summary_csv(&summary))
            .with_context(|| format!("cannot write {}", path.display())),
        Err(error) => {
            eprintln!("wogan export: no {OOB_STATS_FILE}: {error}");
            Ok(())
        }
    }
}

/// What drives a run's tests again: its simulation settings and driver.
struct Replay {
    sim: SimConfig,
    driver: DriverConfig,
}

impl Replay {
    /// The settings of the run `header` describes, checked as every source of settings is
    /// ([`RunHeader::drive_settings`]); `weights` are the DAVE-2 weights it used when not the
    /// built-in ones.
    fn of(header: &RunHeader, weights: Option<&Path>) -> Result<Self> {
        let (sim, driver) = header.drive_settings(weights)?;
        Ok(Self { sim, driver })
    }

    /// Drives `test` (its road built as `road`) again with samples, checking that the drive is
    /// the recorded one.
    fn drive(&self, test: &TestRecord, road: &Road) -> Result<SimResult> {
        let replayed = simulate(road, self.driver.build().as_mut(), &self.sim, true, None);
        // Everything but the wall time and the samples, as the record holds it.
        let comparable = |r: &SimResult| {
            let mut r = r.clone();
            r.execution_ms = 0.0;
            r.trace = None;
            serde_json::to_value(r).unwrap_or_default()
        };
        let (recorded, again) = (comparable(&test.execution.result), comparable(&replayed));
        if again != recorded {
            bail!(
                "test {} does not replay: recorded {recorded}, driven again {again} (was the run \
                 made by another wogan version, or with --driver-weights?)",
                test.id,
            );
        }
        Ok(replayed)
    }
}

/// Whether a file named `name` is one that export writes: `test.NNNN.json` (`NNNN` the test's
/// id, 4 digits or more), `generation_stats.csv` or `oob_stats.csv`.
fn is_export_file(name: &str) -> bool {
    name == STATS_FILE || name == OOB_STATS_FILE || test_file_number(name).is_some()
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
             export's test.NNNN.json, {STATS_FILE} and {OOB_STATS_FILE}, so nothing was removed",
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

/// Writes `DIR/test.NNNN.json` (the id padded to `width` digits) for one test; returns its path.
fn write_test(
    dir: &Path,
    width: usize,
    test: &TestRecord,
    validator: &Validator,
    replay: &Replay,
    seed: Option<u64>,
) -> Result<PathBuf> {
    let road_points = &test.execution.road_points;
    let result = &test.execution.result;
    // The validator's road serves the test object and the drive: built once.
    let verdict = validator.validate(road_points);
    let Some(road) = &verdict.road else {
        bail!("test {}: its road points make no road", test.id);
    };
    let drive = replay.drive(test, road)?;
    let samples = drive.trace.as_deref().unwrap_or_default();
    let max_steering_deg = replay.sim.vehicle.max_steering_rad.to_degrees();
    let phase = test.phase.name();
    let seed = seed.map_or_else(|| "unknown".to_owned(), |s| s.to_string());
    let name = format!("(wogan test {}, {phase} phase, seed {seed})", test.id);
    let known = crate::files::records::known;
    let object = CompetitionTest {
        id: test.id,
        road_points,
        interpolated_points: &road.interpolated,
        is_valid: verdict.is_valid(),
        validation_message: verdict.message(),
        test_outcome: result.outcome,
        description: description(result, &name),
        execution_data: execution_data(samples, replay.sim.oob_tolerance, max_steering_deg),
        features: Features {
            max_curv: known(result.max_curv),
            dir_cov: known(result.dir_cov),
            std_sa: known(result.std_sa),
            mean_lp: known(result.mean_lp),
            max_lp: known(result.max_lp),
        },
    };
    let path = dir.join(format!("test.{:0width$}.json", test.id));
    let text = serde_json::to_string(&object).context("cannot encode a test as JSON")?;
    std::fs::write(&path, text + "\n")
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_as_wide_as_the_largest_id_and_at_least_four_digits() {
        assert_eq!(name_width([1, 30].into_iter()), 4);
        assert_eq!(name_width(std::iter::empty()), 4);
        assert_eq!(name_width([9_999].into_iter()), 4);
        assert_eq!(name_width([3, 10_000].into_iter()), 5);
        assert_eq!(name_width([123_456].into_iter()), 6);
    }

    #[test]
    fn export_files_are_known_by_name() {
        for name in [
            "test.0001.json",
            "test.12345.json",
            "generation_stats.csv",
            "oob_stats.csv",
        ] {
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
