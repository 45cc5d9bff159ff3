//! Reports on runs: reading run files, the figures of a group of runs, the statistics that
//! compare two groups (Mann–Whitney U), the SVG pictures and the Markdown that holds them; and the
//! picture of one simulation trace.
//!
//! A group is a sample of one condition: without `--vs` runs are grouped by their configuration
//! ([`RunKey`]); with `--vs` each of the two groups given must be of one driver, failure
//! threshold and speed limit, and a file given twice counts once.

mod group;
mod markdown;
mod plots;
pub mod run_file;
pub mod sbst_metrics;
mod stats;
mod trace_plot;

use crate::records::known;
use crate::Status;
use anyhow::{bail, Context, Result};
use group::GroupFigures;
use markdown::{GroupSection, Pictures};
use plots::{bolp_histogram_svg, fitness_svg, roads_svg, MapRoad};
use run_file::{read_run, RunFile, RunKey};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use trace_plot::{read_trace, trace_svg};

/// Writes `out/report.md` and its pictures for the runs of `a_paths`: grouped by configuration,
/// or, when `b_paths` is not empty, as two groups compared with Mann–Whitney U tests.
pub fn runs_report(a_paths: &[PathBuf], b_paths: &[PathBuf], out: &Path) -> Result<Status> {
    let (a_paths, b_paths) = (distinct(a_paths), distinct(b_paths));
    refuse_files_on_both_sides(&a_paths, &b_paths)?;
    let compare = !b_paths.is_empty();
    let a = read_runs(&a_paths)?;
    let b = read_runs(&b_paths)?;
    let problems: Vec<String> = a
        .iter()
        .chain(&b)
        .flat_map(|r| r.problems.iter().cloned())
        .collect();
    for problem in &problems {
        eprintln!("wogan report: {problem}");
    }
    let usable = |runs: &[RunFile]| -> Vec<RunFile> {
        runs.iter()
            .filter(|r| r.header.is_some())
            .cloned()
            .collect()
    };
    let (a, b) = (usable(&a), usable(&b));
    if compare {
        like_with_like("A", &a)?;
        like_with_like("B", &b)?;
        note_different_conditions(&a, &b);
    }
    let mut groups: Vec<(String, Vec<&RunFile>)> = Vec::new();
    if !compare {
        let mut by_key: BTreeMap<RunKey, Vec<&RunFile>> = BTreeMap::new();
        for run in &a {
            if let Some(header) = &run.header {
                by_key.entry(header.key.clone()).or_default().push(run);
            }
        }
        groups.extend(by_key.into_iter().map(|(key, runs)| (key.label(), runs)));
    } else {
        groups.push((format!("A: {}", labels(&a)), a.iter().collect()));
        groups.push((format!("B: {}", labels(&b)), b.iter().collect()));
    }
    let mut sections = Vec::new();
    for (index, (label, runs)) in groups.into_iter().enumerate() {
        let slug = format!("g{}", index + 1);
        let figures = GroupFigures::of(&runs);
        let pictures = draw_group(out, &slug, &label, &runs)?;
        let files = runs
            .iter()
            .map(|r| (r.path.display().to_string(), end_note(r)))
            .collect();
        sections.push(GroupSection {
            label,
            files,
            figures,
            pictures,
        });
    }
    let text = markdown::report(&sections, compare, &problems);
    let path = out.join("report.md");
    std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    eprintln!("wogan report: wrote {}", path.display());
    Ok(if problems.is_empty() {
        Status::AllRead
    } else {
        Status::SomeLinesBad
    })
}

/// How a run ended, when not normally.
fn end_note(run: &RunFile) -> Option<&'static str> {
    match &run.summary {
        None => Some("truncated: no summary record"),
        Some(summary) if summary.interrupted => Some("interrupted"),
        Some(_) => None,
    }
}

/// A run file as given, and the file it is: its canonical path, or the path as given when that
/// cannot be resolved (a missing file, which reading reports; `-` for standard input).
struct GivenFile {
    /// The path as given.
    path: PathBuf,
    /// The canonical path.
    file: PathBuf,
}

/// `paths` with each file once (by canonical path), where first given. Counting a run twice
/// would weigh it twice in the figures and in the tests between groups, so a repetition is left
/// out, and said so on stderr.
fn distinct(paths: &[PathBuf]) -> Vec<GivenFile> {
    let mut files: Vec<GivenFile> = Vec::new();
    for path in paths {
        let file = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        if let Some(first) = files.iter().find(|f| f.file == file) {
            eprintln!(
                "wogan report: {} is the same file as {}; it counts once",
                path.display(),
                first.path.display()
            );
            continue;
        }
        files.push(GivenFile {
            path: path.clone(),
            file,
        });
    }
    files
}

/// Refuses a file given in both groups of a comparison: a run cannot be a sample of both.
fn refuse_files_on_both_sides(a: &[GivenFile], b: &[GivenFile]) -> Result<()> {
    for in_b in b {
        if let Some(in_a) = a.iter().find(|f| f.file == in_b.file) {
            bail!(
                "{} (group B, after --vs) is the same file as {} (group A): a run cannot be on \
                 both sides of a comparison",
                in_b.path.display(),
                in_a.path.display()
            );
        }
    }
    Ok(())
}

/// Refuses a group of a comparison whose runs mix drivers, failure thresholds or speed limits:
/// its figures would be no sample of one condition, and the comparison not like with like.
fn like_with_like(group: &str, runs: &[RunFile]) -> Result<()> {
    let conditions: Vec<(&Path, String)> = runs
        .iter()
        .filter_map(|r| Some((r.path.as_path(), r.header.as_ref()?.key.conditions())))
        .collect();
    let distinct: BTreeSet<&str> = conditions.iter().map(|(_, c)| c.as_str()).collect();
    if distinct.len() <= 1 {
        return Ok(());
    }
    let files: String = conditions
        .iter()
        .map(|(path, condition)| format!("\n  {}: {condition}", path.display()))
        .collect();
    bail!(
        "group {group} mixes drivers, oob tolerances or speed limits, so it is no sample of one \
         condition:{files}\ngive each group of a comparison runs of one driver, tolerance and \
         speed limit (without --vs, runs are grouped by configuration)"
    )
}

/// Says on stderr when the two groups of a comparison differ in driver, failure threshold or
/// speed limit, since then the comparison is between those too, not only between searches.
fn note_different_conditions(a: &[RunFile], b: &[RunFile]) {
    let condition = |runs: &[RunFile]| {
        runs.iter()
            .find_map(|r| Some(r.header.as_ref()?.key.conditions()))
    };
    if let (Some(a), Some(b)) = (condition(a), condition(b)) {
        if a != b {
            eprintln!("wogan report: note: group A is of {a}, group B of {b}");
        }
    }
}

/// Reads every file; a file that cannot be opened is bad usage.
fn read_runs(files: &[GivenFile]) -> Result<Vec<RunFile>> {
    files.iter().map(|f| read_run(&f.path)).collect()
}

/// The distinct configurations of `runs`, joined.
fn labels(runs: &[RunFile]) -> String {
    let mut keys: Vec<String> = runs
        .iter()
        .filter_map(|r| r.header.as_ref())
        .map(|h| h.key.label())
        .collect();
    keys.sort();
    keys.dedup();
    if keys.is_empty() {
        "no runs".to_owned()
    } else {
        keys.join("; ")
    }
}

/// Draws a group's pictures into `out`, named after `slug`.
fn draw_group(out: &Path, slug: &str, label: &str, runs: &[&RunFile]) -> Result<Pictures> {
    let map_size_m = runs
        .iter()
        .filter_map(|r| r.header.as_ref())
        .map(|h| h.map_size_m)
        .fold(0.0, f64::max);
    let map_size_m = if map_size_m > 0.0 { map_size_m } else { 200.0 };
    // Test ids repeat across runs, so with several runs the label names the run too.
    let several = runs.len() > 1;
    let failing: Vec<MapRoad> = runs
        .iter()
        .enumerate()
        .flat_map(|(i, r)| r.tests.iter().filter(|t| t.failed()).map(move |t| (i, t)))
        .map(|(i, t)| MapRoad {
            label: if several {
                format!("r{} #{}", i + 1, t.id)
            } else {
                format!("#{}", t.id)
            },
            road_points: &t.execution.road_points,
        })
        .collect();
    let roads = format!("roads.{slug}.svg");
    roads_svg(
        &out.join(&roads),
        &format!("failing roads ({label})"),
        &failing,
        map_size_m,
    )?;
    let bolps: Vec<f64> = runs
        .iter()
        .flat_map(|r| {
            r.tests
                .iter()
                .filter_map(|t| known(t.execution.result.max_bolp))
        })
        .collect();
    let tolerance = runs
        .iter()
        .filter_map(|r| r.header.as_ref())
        .find_map(|h| h.oob_tolerance);
    let bolp = format!("bolp.{slug}.svg");
    bolp_histogram_svg(
        &out.join(&bolp),
        &format!("max BOLP of every test ({label})"),
        &bolps,
        tolerance,
    )?;
    let mut fitness = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let name = format!("fitness.{slug}.r{}.svg", i + 1);
        let file = run
            .path
            .file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
        fitness_svg(
            &out.join(&name),
            &format!("fitness over the run: {file}"),
            &run.tests,
        )?;
        fitness.push(name);
    }
    Ok(Pictures {
        roads,
        bolp,
        fitness,
    })
}

/// Draws one `simulate --trace` file to `out/trace.svg`.
pub fn trace_picture(trace_path: &Path, out: &Path) -> Result<Status> {
    let trace = read_trace(trace_path)?;
    for problem in &trace.problems {
        eprintln!("wogan report: {problem}");
    }
    let name = trace_path
        .file_name()
        .map_or_else(|| "trace".to_owned(), |f| f.to_string_lossy().into_owned());
    let path = out.join("trace.svg");
    trace_svg(&path, &format!("simulation {name}"), &trace)?;
    eprintln!("wogan report: wrote {}", path.display());
    Ok(if trace.problems.is_empty() {
        Status::AllRead
    } else {
        Status::SomeLinesBad
    })
}
