//! `wogan report RUN... [--vs RUN...]`: which runs make which group, the checks that a comparison
//! is like with like, and the report written from the groups.

use super::group::{GroupFigures, RunMeasures};
use super::html::{write_html_report, HtmlReport};
use super::inputs::{run_inputs, InputKind, RunInput};
use super::markdown::{self, ErrorTest, GroupSection, ERROR_TESTS_LISTED};
use super::pictures::draw_group;
use super::run_key::RunKey;
use crate::files::run_file::{read_run, RunFile};
use crate::sbst::read_result_folder;
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use road_sim::Outcome;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// The report was stopped by Ctrl-C or SIGTERM before it was written (nothing was).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("stopped by Ctrl-C or SIGTERM before the report was written")]
pub struct Interrupted;

/// `Err(Interrupted)` once Ctrl-C or SIGTERM came: checked between the report's long steps.
fn not_stopped() -> Result<()> {
    if crate::interrupt::stopped() {
        return Err(Interrupted.into());
    }
    Ok(())
}

/// What a report keeps of each run it reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Keep {
    /// Every test (the roads of failing ones only): what the pictures draw.
    Tests,
    /// The run's measures, taken as it is read, and its failing tests: all the tables need, so
    /// that the tables of thousands of runs hold little more than their failing tests.
    Measures,
}

/// A run as read, with its measures when they were taken then.
type ReadRun = (RunFile, Option<RunMeasures>);

/// Runs read and grouped: by configuration, or the two groups of a comparison.
pub(super) struct Grouped {
    /// Each group's label and runs (in input order), in the order the report shows them.
    pub groups: Vec<(String, Vec<RunFile>)>,
    /// Each group's runs' measures, when they were taken as the runs were read ([`Keep`]).
    measures: Vec<Option<Vec<RunMeasures>>>,
    /// Whether the groups are A and B of a comparison.
    pub compare: bool,
    /// What was wrong with the files (each said on stderr once).
    pub problems: Vec<String>,
}

impl Grouped {
    /// How many inputs were bad, which the exit status tells: problems with the files, and runs
    /// that did not end normally (cut short or interrupted), which count with what they have.
    pub fn bad_inputs(&self) -> usize {
        self.problems.len() + self.unfinished_runs()
    }

    /// Each group's label and figures.
    pub fn figures(&self) -> Vec<(String, GroupFigures)> {
        self.groups
            .iter()
            .zip(&self.measures)
            .map(|((label, runs), measures)| {
                let runs: Vec<&RunFile> = runs.iter().collect();
                let figures = match measures {
                    Some(measures) => GroupFigures::of_measured(&runs, measures.clone()),
                    None => GroupFigures::of(&runs),
                };
                (label.clone(), figures)
            })
            .collect()
    }

    /// The runs that did not end normally.
    fn unfinished_runs(&self) -> usize {
        self.groups
            .iter()
            .flat_map(|(_, runs)| runs)
            .filter(|r| end_note(r).is_some())
            .count()
    }
}

/// Reads the runs of `a_paths` (files and folders of them) and groups them by configuration, or,
/// when `b_paths` is not empty, makes them group A and the runs of `b_paths` group B. Runs without
/// a header are left out (a problem says why); a comparison must be like with like. `keep` says
/// what is kept of each run.
pub(super) fn group_runs(a_paths: &[PathBuf], b_paths: &[PathBuf], keep: Keep) -> Result<Grouped> {
    let (a_paths, b_paths) = (
        distinct(&run_inputs(a_paths)?),
        distinct(&run_inputs(b_paths)?),
    );
    refuse_files_on_both_sides(&a_paths, &b_paths)?;
    let compare = !b_paths.is_empty();
    let mut problems = Vec::new();
    let a = read_runs(&a_paths, keep, &mut problems)?;
    let b = read_runs(&b_paths, keep, &mut problems)?;
    not_stopped()?;
    for (run, measures) in a.iter().chain(&b) {
        if let Some(measures) = measures {
            note_samples(&run.path, measures);
        }
    }
    problems.extend(
        a.iter()
            .chain(&b)
            .flat_map(|(r, _)| r.problems.iter().cloned()),
    );
    for problem in &problems {
        eprintln!("wogan report: {problem}");
    }
    let usable = |runs: Vec<ReadRun>| -> (Vec<RunFile>, Vec<Option<RunMeasures>>) {
        runs.into_iter().filter(|(r, _)| r.header.is_some()).unzip()
    };
    let ((a, a_measures), (b, b_measures)) = (usable(a), usable(b));
    let mut groups: Vec<(String, Vec<RunFile>)> = Vec::new();
    let mut measures: Vec<Vec<Option<RunMeasures>>> = Vec::new();
    if compare {
        like_with_like("A", &a)?;
        like_with_like("B", &b)?;
        note_different_conditions(&a, &b);
        groups.push((format!("A: {}", labels(&a)), a));
        groups.push((format!("B: {}", labels(&b)), b));
        measures.extend([a_measures, b_measures]);
    } else {
        let mut by_key: BTreeMap<RunKey, Vec<ReadRun>> = BTreeMap::new();
        for (run, measured) in a.into_iter().zip(a_measures) {
            if let Some(header) = &run.header {
                by_key
                    .entry(RunKey::of(header))
                    .or_default()
                    .push((run, measured));
            }
        }
        for (key, runs) in by_key {
            let (runs, measured) = runs.into_iter().unzip();
            groups.push((key.label(), runs));
            measures.push(measured);
        }
    }
    let grouped = Grouped {
        groups,
        // Measures for a whole group, or none.
        measures: measures
            .into_iter()
            .map(|m| m.into_iter().collect())
            .collect(),
        compare,
        problems,
    };
    let unfinished = grouped.unfinished_runs();
    if unfinished > 0 {
        let runs: usize = grouped.groups.iter().map(|(_, runs)| runs.len()).sum();
        eprintln!(
            "wogan report: {unfinished} of {runs} runs did not end normally; they count with the \
             tests they have (named in the report)"
        );
    }
    Ok(grouped)
}

/// Writes `out/report.md` and its pictures for the runs of `a_paths`: grouped by configuration,
/// or, when `b_paths` is not empty, as two groups compared with Mann–Whitney U tests; with `html`,
/// `out/report.html` too. Returns how many inputs were bad (problems, each said on stderr, and
/// runs that did not end normally; what they hold is reported). Ctrl-C or SIGTERM (once
/// [`crate::interrupt::stop_flag`] is installed) ends it with [`Interrupted`] before report.md is
/// written; during `--traces` drives, the page is written with the drives that ended.
pub fn runs_report(
    a_paths: &[PathBuf],
    b_paths: &[PathBuf],
    out: &Path,
    html: Option<(HtmlReport, &AtomicBool)>,
) -> Result<usize> {
    let grouped = group_runs(a_paths, b_paths, Keep::Tests)?;
    let bad_inputs = grouped.bad_inputs();
    let mut sections = Vec::new();
    for (index, (label, runs)) in grouped.groups.iter().enumerate() {
        let slug = format!("g{}", index + 1);
        let runs: Vec<&RunFile> = runs.iter().collect();
        let figures = GroupFigures::of(&runs);
        not_stopped()?;
        for (run, measures) in runs.iter().zip(&figures.runs) {
            note_samples(&run.path, measures);
        }
        let pictures = draw_group(out, &slug, label, &runs)?;
        not_stopped()?;
        let files = runs
            .iter()
            .map(|r| (r.path.display().to_string(), end_note(r)))
            .collect();
        let errored: Vec<ErrorTest> = runs
            .iter()
            .flat_map(|run| {
                run.tests
                    .iter()
                    .filter(|t| t.execution.result.outcome == Outcome::Error)
                    .map(|t| ErrorTest {
                        file: run.path.display().to_string(),
                        test: t.id,
                        reason: t.execution.result.reason.map(|r| r.name().to_owned()),
                        message: t.execution.result.error.clone(),
                    })
            })
            .collect();
        sections.push(GroupSection {
            label: label.clone(),
            files,
            figures,
            pictures,
            error_total: errored.len(),
            error_tests: errored.into_iter().take(ERROR_TESTS_LISTED).collect(),
        });
    }
    let mut text = markdown::report(&sections, grouped.compare, &grouped.problems);
    text.push_str(&sampled_section(&sections));
    let path = out.join("report.md");
    std::fs::write(&path, &text).with_context(|| format!("cannot write {}", path.display()))?;
    eprintln!("wogan report: wrote {}", path.display());
    if let Some((options, stop)) = html {
        let groups: Vec<&[RunFile]> = grouped
            .groups
            .iter()
            .map(|(_, runs)| runs.as_slice())
            .collect();
        let (path, not_traced) = write_html_report(out, &text, &sections, &groups, options, stop)?;
        for reason in &not_traced.reasons {
            eprintln!("wogan report: {reason}");
        }
        eprintln!("wogan report: wrote {}", path.display());
        return Ok(bad_inputs + not_traced.bad_headers);
    }
    Ok(bad_inputs)
}

/// Says on stderr which of a run's measures were taken on a sample of its failures.
fn note_samples(path: &Path, measures: &RunMeasures) {
    let sampled = measures.sampled();
    if !sampled.is_empty() {
        eprintln!(
            "wogan report: {}: {} (a seeded sample: docs/reference.md, `wogan report`)",
            path.display(),
            sampled.join("; ")
        );
    }
}

/// A section of report.md naming the runs whose measures were taken on a sample of their
/// failures (by group and place in the group's list: no text from the files), or nothing.
fn sampled_section(sections: &[GroupSection]) -> String {
    let mut lines = String::new();
    for (group, section) in sections.iter().enumerate() {
        for (run, measures) in section.figures.runs.iter().enumerate() {
            let sampled = measures.sampled();
            if !sampled.is_empty() {
                lines.push_str(&format!(
                    "- group {}, run {}: {}\n",
                    group + 1,
                    run + 1,
                    sampled.join("; ")
                ));
            }
        }
    }
    if lines.is_empty() {
        return lines;
    }
    format!(
        "\n## Measures taken on a sample\n\nThese runs have more failures than the pairwise \
         measures compare in full; each was measured on a sample drawn with the run's seed \
         (docs/reference.md, `wogan report`):\n\n{lines}"
    )
}

/// How a run ended, when not normally.
pub(super) fn end_note(run: &RunFile) -> Option<String> {
    match &run.summary {
        None => Some("truncated: no summary record".to_owned()),
        // A run that gave up (a search's error, a peer generator's crash) is stopped like an
        // interrupted one; the error says why.
        Some(summary) => match &summary.error {
            Some(error) => Some(format!("failed part-way: {error}")),
            None if summary.interrupted => Some("interrupted".to_owned()),
            None => None,
        },
    }
}

/// A run file as given, and the file it is: its canonical path, or the path as given when that
/// cannot be resolved (a missing file, which reading reports; `-` for standard input).
struct GivenFile {
    /// The path as given.
    path: PathBuf,
    /// The canonical path.
    file: PathBuf,
    /// What it is read as.
    kind: InputKind,
    /// Whether it was found in a folder rather than named.
    found: bool,
}

/// `inputs` with each file once (by canonical path), where first given. Counting a run twice
/// would weigh it twice in the figures and in the tests between groups, so a repetition is left
/// out, and said so on stderr.
fn distinct(inputs: &[RunInput]) -> Vec<GivenFile> {
    let mut files: Vec<GivenFile> = Vec::new();
    let mut first_of: HashMap<PathBuf, usize> = HashMap::new();
    for input in inputs {
        let path = &input.path;
        let file = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        if let Some(&first) = first_of.get(&file) {
            eprintln!(
                "wogan report: {} is the same file as {}; it counts once",
                path.display(),
                files[first].path.display()
            );
            continue;
        }
        first_of.insert(file.clone(), files.len());
        files.push(GivenFile {
            path: path.clone(),
            file,
            kind: input.kind,
            found: input.found,
        });
    }
    files
}

/// Refuses a file given in both groups of a comparison: a run cannot be a sample of both.
fn refuse_files_on_both_sides(a: &[GivenFile], b: &[GivenFile]) -> Result<()> {
    let in_a: HashMap<&Path, &GivenFile> = a.iter().map(|f| (f.file.as_path(), f)).collect();
    for in_b in b {
        if let Some(in_a) = in_a.get(in_b.file.as_path()) {
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
        .filter_map(|r| {
            Some((
                r.path.as_path(),
                RunKey::of(r.header.as_ref()?).conditions(),
            ))
        })
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
            .find_map(|r| Some(RunKey::of(r.header.as_ref()?).conditions()))
    };
    if let (Some(a), Some(b)) = (condition(a), condition(b)) {
        if a != b {
            eprintln!("wogan report: note: group A is of {a}, group B of {b}");
        }
    }
}

/// Reads every file, a few at a time (one per thread: the open-file limit is never near), each
/// kept as `keep` says, without the roads no figure uses. A named file that cannot be opened is
/// bad usage; one found in a folder (renamed or removed since it was listed, unreadable) is a
/// problem in `problems`, and the rest are reported.
fn read_runs(files: &[GivenFile], keep: Keep, problems: &mut Vec<String>) -> Result<Vec<ReadRun>> {
    let read: Vec<Result<ReadRun>> = files
        .par_iter()
        .map(|f| {
            not_stopped()?;
            let mut run = match f.kind {
                InputKind::RunFile => read_run(&f.path)?,
                InputKind::ResultFolder => read_result_folder(&f.path)?,
            };
            let measures = (keep == Keep::Measures).then(|| {
                let measures = RunMeasures::of(&run);
                run.tests.retain(|t| t.failed());
                run.beyond_budget.clear();
                measures
            });
            run.drop_unused_roads();
            Ok((run, measures))
        })
        .collect();
    not_stopped()?;
    let mut runs = Vec::with_capacity(read.len());
    for (file, run) in files.iter().zip(read) {
        match run {
            Ok(run) => runs.push(run),
            Err(error) if file.found => problems.push(format!("{error:#}")),
            Err(error) => return Err(error),
        }
    }
    Ok(runs)
}

/// The distinct configurations of `runs`, joined.
fn labels(runs: &[RunFile]) -> String {
    let mut keys: Vec<String> = runs
        .iter()
        .filter_map(|r| r.header.as_ref())
        .map(|h| RunKey::of(h).label())
        .collect();
    keys.sort();
    keys.dedup();
    if keys.is_empty() {
        "no runs".to_owned()
    } else {
        keys.join("; ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixtures() -> Vec<PathBuf> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures");
        ["wogan.seed3", "wogan.seed4", "random.seed4", "random.seed5"]
            .iter()
            .map(|name| dir.join(format!("{name}.jsonl")))
            .collect()
    }

    #[test]
    fn measures_taken_as_runs_are_read_give_the_figures_of_every_test() {
        let runs = fixtures();
        let whole = group_runs(&runs, &[], Keep::Tests).unwrap();
        let measured = group_runs(&runs, &[], Keep::Measures).unwrap();
        let (whole, measured) = (whole.figures(), measured.figures());
        assert_eq!(whole.len(), 2);
        assert_eq!(format!("{whole:?}"), format!("{measured:?}"));
        // Compared as two groups, too.
        let compared = |keep| {
            let grouped = group_runs(&runs[..2], &runs[2..], keep).unwrap();
            format!("{:?}", grouped.figures())
        };
        assert_eq!(compared(Keep::Tests), compared(Keep::Measures));
    }

    #[test]
    fn only_failing_tests_are_kept_with_measures() {
        let grouped = group_runs(&fixtures()[..1], &[], Keep::Measures).unwrap();
        let run = &grouped.groups[0].1[0];
        assert_eq!(run.tests.len(), 5);
        assert!(run.tests.iter().all(|t| t.failed()));
        assert_eq!(grouped.figures()[0].1.runs[0].executed, 30);
        assert_eq!(grouped.bad_inputs(), 0);
    }
}
