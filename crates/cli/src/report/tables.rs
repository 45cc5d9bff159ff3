//! `wogan report --table`: the figures as Markdown tables on stdout, without pictures, for a page
//! made from many run files (`python3 scripts/results`). Without `--vs`, one row per configuration;
//! with `--vs`, the Mann–Whitney table of A against B over every measure, the competition's
//! included.

use super::group::GroupFigures;
use super::markdown::{comparison_table, literal, COMPETITION};
use super::runs_report::{end_note, group_runs, Keep};
use super::stats::{mean, median};
use anyhow::Result;
use std::fmt::Write;
use std::path::PathBuf;

/// The tables of the runs of `a_paths` (and of `b_paths`, compared) and how many inputs were bad
/// (problems, each said on stderr, and runs that did not end normally, named under the table).
pub fn runs_tables(a_paths: &[PathBuf], b_paths: &[PathBuf]) -> Result<(String, usize)> {
    let grouped = group_runs(a_paths, b_paths, Keep::Measures)?;
    // Runs that did not end normally count as they are; the table says which they are.
    let early: Vec<String> = grouped
        .groups
        .iter()
        .flat_map(|(_, runs)| runs)
        .filter_map(|r| {
            let path = literal(&r.path.display().to_string());
            Some(format!("- {path}: {}\n", literal(&end_note(r)?)))
        })
        .collect();
    let figures: Vec<(String, GroupFigures)> = grouped.figures();
    let mut text = match figures.as_slice() {
        [(a_label, a), (b_label, b)] if grouped.compare => {
            format!(
                "- {}\n- {}\n\n{}",
                literal(a_label),
                literal(b_label),
                comparison_table(a, b, &COMPETITION)
            )
        }
        _ => configurations_table(&figures),
    };
    if !early.is_empty() {
        text.push_str("\nRuns that did not end normally (counted as they are):\n\n");
        text.extend(early);
    }
    Ok((text, grouped.bad_inputs()))
}

/// `median (mean)` of `values`, `–` when there are none.
fn median_mean(values: &[f64]) -> String {
    match (median(values), mean(values)) {
        (Some(median), Some(mean)) => format!("{} ({})", figure(median, 1), figure(mean, 1)),
        _ => "–".to_owned(),
    }
}

/// `text`, with how many of `all` runs it is of when not all.
fn runs_of(text: String, some: usize, all: usize) -> String {
    if some > 0 && some < all {
        format!("{text} ({some} runs)")
    } else {
        text
    }
}

/// A figure as people write it: `digits` decimals at most, no trailing zeros.
fn figure(value: f64, digits: usize) -> String {
    let text = format!("{value:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

/// One row per configuration: what a search found in its runs.
fn configurations_table(groups: &[(String, GroupFigures)]) -> String {
    let mut text = String::from(
        "| configuration | runs | failing roads | distinct failures | diversity | first failing \
         test | closest approach | invalid candidates per run | µs per candidate |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for (label, f) in groups {
        let runs = &f.runs;
        let failures: Vec<f64> = runs.iter().map(|m| m.failures as f64).collect();
        let diversity: Vec<f64> = runs.iter().filter_map(|m| m.diversity).collect();
        let distinct: Vec<f64> = runs
            .iter()
            .filter_map(|m| m.distinct_failures.map(|n| n as f64))
            .collect();
        let firsts: Vec<f64> = runs.iter().map(|m| m.first_failure_or_past_end()).collect();
        let closest: Vec<f64> = runs.iter().filter_map(|m| m.closest_approach).collect();
        let invalid: Vec<f64> = runs.iter().map(|m| m.invalid_candidates as f64).collect();
        // Pooled over runs: a run that chose few tests weighs little.
        let candidates: usize = runs.iter().map(|m| m.chosen_candidates).sum();
        let generation_ms: f64 = runs.iter().map(|m| m.chosen_generation_ms).sum();
        let per_candidate = if candidates > 0 {
            figure(1e3 * generation_ms / candidates as f64, 0)
        } else {
            "–".to_owned()
        };
        let diversity_text = match median(&diversity) {
            Some(d) if diversity.len() < runs.len() => {
                format!("{} ({} runs)", figure(d, 2), diversity.len())
            }
            Some(d) => figure(d, 2),
            None => "–".to_owned(),
        };
        let _ = writeln!(
            text,
            "| {} | {} | {} | {} | {diversity_text} | {} | {} | {} | {per_candidate} |",
            literal(label),
            runs.len(),
            median_mean(&failures),
            runs_of(median_mean(&distinct), distinct.len(), runs.len()),
            median_mean(&firsts),
            median(&closest).map_or_else(|| "–".to_owned(), |c| figure(c, 3)),
            median(&invalid).map_or_else(|| "–".to_owned(), |v| figure(v, 1)),
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_drop_trailing_zeros() {
        assert_eq!(figure(39.0, 1), "39");
        assert_eq!(figure(36.46, 1), "36.5");
        assert_eq!(figure(4.25, 2), "4.25");
        assert_eq!(figure(1234.4, 0), "1234");
        assert_eq!(median_mean(&[]), "–");
        assert_eq!(median_mean(&[1.0, 2.0, 6.0]), "2 (3)");
        assert_eq!(runs_of("2 (3)".to_owned(), 3, 3), "2 (3)");
        assert_eq!(runs_of("2 (3)".to_owned(), 3, 4), "2 (3) (3 runs)");
        assert_eq!(runs_of("–".to_owned(), 0, 4), "–");
    }
}
