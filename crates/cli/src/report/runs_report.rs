//! `wogan report RUN... [--vs RUN...]`: which runs make which group, the checks that a comparison
//! is like with like, and the report written from the groups.

use super::group::GroupFigures;
use super::markdown::{self, GroupSection};
use super::pictures::draw_group;
use crate::run_file::{read_run, RunFile, RunKey};
use anyhow::{bail, Context, Result};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Runs read and grouped: by configuration, or the two groups of a comparison.
pub(super) struct Grouped {
    /// Each group's label and runs (in input order), in the order the report shows them.
    pub groups: Vec<(String, Vec<RunFile>)>,
    /// Whether the groups are A and B of a comparison.
    pub compare: bool,
    /// What was wrong with the files (each said on stderr once).
    pub problems: Vec<String>,
}

/// Reads the runs of `a_paths` and groups them by configuration, or, when `b_paths` is not
/// empty, makes them group A and the runs of `b_paths` group B. Runs without a header are left
/// out (a problem says why); a comparison must be like with like.
pub(super) fn group_runs(a_paths: &[PathBuf], b_paths: &[PathBuf]) -> Result<Grouped> {
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
    let usable = |runs: Vec<RunFile>| -> Vec<RunFile> {
        runs.into_iter().filter(|r| r.header.is_some()).collect()
    };
    let (a, b) = (usable(a), usable(b));
    let mut groups: Vec<(String, Vec<RunFile>)> = Vec::new();
    if compare {
        like_with_like("A", &a)?;
        like_with_like("B", &b)?;
        note_different_conditions(&a, &b);
        groups.push((format!("A: {}", labels(&a)), a));
        groups.push((format!("B: {}", labels(&b)), b));
    } else {
        let mut by_key: BTreeMap<RunKey, Vec<RunFile>> = BTreeMap::new();
        for run in a {
            if let Some(header) = &run.header {
                by_key.entry(header.key.clone()).or_default().push(run);
            }
        }
        groups.extend(by_key.into_iter().map(|(key, runs)| (key.label(), runs)));
    }
    Ok(Grouped {
        groups,
        compare,
        problems,
    })
}

/// Writes `out/report.md` and its pictures for the runs of `a_paths`: grouped by configuration,
/// or, when `b_paths` is not empty, as two groups compared with Mann–Whitney U tests. Returns how
/// many problems the run files had (each said on stderr; their good lines are reported).
pub fn runs_report(a_paths: &[PathBuf], b_paths: &[PathBuf], out: &Path) -> Result<usize> {
    let grouped = group_runs(a_paths, b_paths)?;
    let mut sections = Vec::new();
    for (index, (label, runs)) in grouped.groups.into_iter().enumerate() {
        let slug = format!("g{}", index + 1);
        let runs: Vec<&RunFile> = runs.iter().collect();
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
    let text = markdown::report(&sections, grouped.compare, &grouped.problems);
    let path = out.join("report.md");
    std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    eprintln!("wogan report: wrote {}", path.display());
    Ok(grouped.problems.len())
}

/// How a run ended, when not normally.
pub(super) fn end_note(run: &RunFile) -> Option<&'static str> {
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
