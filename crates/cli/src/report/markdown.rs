//! The text of `report.md`: a table of figures per group, feature coverage, links to the
//! pictures, and (with `--vs`) the two groups side by side with Mann–Whitney p-values.
//!
//! Every string that comes from a file (a group's label from a header, a file or folder name, how
//! a run ended, a bad line's problem) enters the text through [`literal`], so that it reads as
//! itself in any Markdown viewer: no markup, link, picture or HTML of its own.

use super::group::{
    FeatureCoverage, GroupFigures, Measure, Spread, MAX_CURV_BIN_PER_M, MEAN_LP_BIN_M,
    STD_SA_BIN_DEG,
};
use super::pictures::Pictures;
use super::stats::{mann_whitney, PMethod};
use std::fmt::Write;

/// One group as the report shows it.
pub struct GroupSection {
    /// The group's configuration.
    pub label: String,
    /// Each run's file and how it ended when not normally.
    pub files: Vec<(String, Option<String>)>,
    /// The group's figures.
    pub figures: GroupFigures,
    /// The group's pictures.
    pub pictures: Pictures,
    /// Its tests that ended in ERROR, the first [`ERROR_TESTS_LISTED`] of them.
    pub error_tests: Vec<ErrorTest>,
    /// How many of its tests ended in ERROR in all.
    pub error_total: usize,
}

/// Most ERROR tests a group's section lists (the rest are counted).
pub const ERROR_TESTS_LISTED: usize = 20;

/// Longest error message a listed ERROR test shows, characters (an executor's stderr tail is
/// longer; the run file holds it whole).
const ERROR_MESSAGE_CHARS: usize = 400;

/// A test that ended in ERROR, as its group's section lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorTest {
    /// The run file.
    pub file: String,
    /// The test's id.
    pub test: usize,
    /// Why the drive did not pass (`error`, `timeout`, ...), when recorded.
    pub reason: Option<String>,
    /// What the driver, controller or executor said, when recorded.
    pub message: Option<String>,
}

/// `text`, a string from a file, as Markdown text that shows as itself: the characters that make
/// markup anywhere in a line are escaped with a backslash, `<`, `>` and `&` written as entities
/// (no HTML, autolink or entity of the file's own reaches a viewer), control characters and line
/// breaks made spaces (the text stays on its line), and a first character that would start a
/// block (a list item, a definition, a numbered item) escaped.
pub fn literal(text: &str) -> String {
    let chars: Vec<char> = text
        .chars()
        .map(|c| {
            if c.is_control() || matches!(c, '\u{2028}' | '\u{2029}') {
                ' '
            } else {
                c
            }
        })
        .collect();
    // `12.` or `12)` at the start would number a list.
    let digits = chars.iter().take_while(|c| c.is_ascii_digit()).count();
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for (index, &c) in chars.iter().enumerate() {
        // An underscore between letters or digits neither opens nor closes emphasis (CommonMark's
        // flanking rules), so `max_bolp` stays readable in the file.
        let inside_a_word = || {
            index > 0
                && chars[index - 1].is_alphanumeric()
                && chars.get(index + 1).is_some_and(|n| n.is_alphanumeric())
        };
        let entity = match c {
            '&' => "&amp;",
            '<' => "&lt;",
            '>' => "&gt;",
            _ => "",
        };
        if !entity.is_empty() {
            out.push_str(entity);
            continue;
        }
        let backslashed = match c {
            '\\' | '`' | '*' | '[' | ']' | '#' | '|' | '~' | '$' | '{' | '}' => true,
            '_' => !inside_a_word(),
            '-' | '+' | '=' | ':' => index == 0,
            '.' | ')' => digits > 0 && index == digits,
            _ => false,
        };
        if backslashed {
            out.push('\\');
        }
        out.push(c);
    }
    out
}

/// A number with 3 decimals, or a dash when undefined.
fn number(value: Option<f64>) -> String {
    value.map_or_else(|| "–".to_owned(), |v| format!("{v:.3}"))
}

/// A table row `| name | mean | SD | runs |`.
fn spread_row(name: &str, spread: &Spread) -> String {
    format!(
        "| {name} | {} | {} | {} |\n",
        number(spread.mean),
        number(spread.sd),
        spread.count
    )
}

/// A feature-coverage row.
fn coverage_row(name: &str, coverage: &FeatureCoverage) -> String {
    format!(
        "| {name} | {} | {} | {} | {} |\n",
        coverage.bins,
        number(coverage.min),
        number(coverage.median),
        number(coverage.max)
    )
}

/// The whole report.
pub fn report(sections: &[GroupSection], compare: bool, problems: &[String]) -> String {
    let mut text = String::from("# wogan report\n\n");
    let runs: usize = sections.iter().map(|s| s.files.len()).sum();
    let _ = writeln!(text, "{runs} run(s) in {} group(s).\n", sections.len());
    if !problems.is_empty() {
        let _ = writeln!(
            text,
            "**{} input line(s) could not be read** (the rest is reported):\n",
            problems.len()
        );
        for problem in problems {
            let _ = writeln!(text, "- {}", literal(problem));
        }
        text.push('\n');
    }
    if compare && sections.len() == 2 {
        text.push_str(&comparison(&sections[0], &sections[1]));
    }
    for (index, section) in sections.iter().enumerate() {
        text.push_str(&group(index + 1, section));
    }
    text
}

/// What a run's failures cost and what they are like: rows of each group's table and of the
/// comparison, beside the failures and their diversity.
const YIELD: [(&str, Measure); 2] = [
    ("failures per simulated hour", |m| {
        m.failures_per_simulated_hour
    }),
    (
        "failing road length (m; median of a run's failing roads)",
        |m| m.failing_road_length_m,
    ),
];

/// How a search met and exploited failures (and how near it came when it met none), per run: a
/// row of each group's table, and one of the comparison.
const EXPLOITATION: [(&str, Measure); 4] = [
    (
        "first failing test (a run without one: tests executed + 1)",
        |m| Some(m.first_failure_or_past_end()),
    ),
    (
        "failure rate after the first failing test (runs with tests after one)",
        |m| m.failure_rate_after_first,
    ),
    ("candidates ranked per test the analyzer chose", |m| {
        m.ranked_per_choice
    }),
    (
        "closest approach (largest fitness_distance of a run)",
        |m| m.closest_approach,
    ),
];

/// The SBST competition's measures per run, as its pipeline computes them: a table of each group,
/// and rows of the comparison.
pub const COMPETITION: [(&str, Measure); 12] = [
    ("tests generated (handed to execution)", |m| {
        Some(m.sbst.generated as f64)
    }),
    ("failures", |m| Some(m.failures as f64)),
    ("effectiveness (valid / generated)", |m| {
        m.sbst.effectiveness
    }),
    ("invalid candidates rejected before proposing", |m| {
        Some(m.sbst.invalid_candidates as f64)
    }),
    ("efficiency (generation time per test, ms)", |m| {
        m.sbst.efficiency_s.map(|s| s * 1e3)
    }),
    ("lane exits over the centre line (left)", |m| {
        Some(m.sbst.exits_left as f64)
    }),
    ("lane exits over the road's edge (right)", |m| {
        Some(m.sbst.exits_right as f64)
    }),
    ("OOBAnalyzer: LEFT OOBs", |m| {
        m.sbst.oob_figure(|s| s.left as f64)
    }),
    ("OOBAnalyzer: RIGHT OOBs", |m| {
        m.sbst.oob_figure(|s| s.right as f64)
    }),
    ("OOBAnalyzer: sparseness mean (runs it completes)", |m| {
        m.sbst.oob_figure(|s| s.sparseness_mean)
    }),
    ("OOBAnalyzer: sparseness SD (runs it completes)", |m| {
        m.sbst.oob_figure(|s| s.sparseness_sd)
    }),
    ("sparseness mean over the OOBs it places", |m| {
        m.sbst.oob_placed_figure(|s| s.sparseness_mean)
    }),
];

/// The rows of [`COMPETITION`] the comparison tests (failures are tested already).
const COMPETITION_COMPARED: [usize; 6] = [4, 5, 6, 7, 9, 11];

/// The name of the distinct-failures row of a group's table.
const DISTINCT_FAILURES: &str = "distinct failures (failing roads ≥ δ apart around the lane exit; \
     runs that record where the car left its lane)";

/// The group's ERROR tests with their reason and message, or nothing when there are none.
fn error_tests(section: &GroupSection) -> String {
    if section.error_total == 0 {
        return String::new();
    }
    let mut text = format!(
        "\n{} test(s) ended in ERROR (the driver under test or the simulator failed, not the road):\n\n",
        section.error_total
    );
    for test in &section.error_tests {
        let reason = test.reason.as_deref().unwrap_or("error");
        let message = test.message.as_deref().map_or_else(String::new, |m| {
            let cut: String = m.chars().take(ERROR_MESSAGE_CHARS).collect();
            let more = if cut.len() < m.len() { " …" } else { "" };
            format!(": {}{more}", literal(&cut))
        });
        let _ = writeln!(
            text,
            "- {} test {}: {}{message}",
            literal(&test.file),
            test.test,
            literal(reason)
        );
    }
    if section.error_total > section.error_tests.len() {
        let _ = writeln!(
            text,
            "- and {} more (the run files hold each)",
            section.error_total - section.error_tests.len()
        );
    }
    text
}

/// One group's section.
fn group(number_1: usize, section: &GroupSection) -> String {
    let f = &section.figures;
    let mut text = format!("## Group {number_1}: {}\n\n", literal(&section.label));
    for (file, note) in &section.files {
        let note = note
            .as_ref()
            .map_or_else(String::new, |n| format!(" ({})", literal(n)));
        let _ = writeln!(text, "- {}{note}", literal(file));
    }
    text.push_str(&error_tests(section));
    text.push_str("\n| measure | mean | SD | runs |\n|---|---|---|---|\n");
    text.push_str(&spread_row("tests executed", &f.executed));
    text.push_str(&spread_row("failures", &f.failures));
    let _ = writeln!(
        text,
        "| failure rate (all tests pooled) | {} | | |",
        number(f.failure_rate)
    );
    text.push_str(&spread_row(
        "generation time per test (ms)",
        &f.generation_ms,
    ));
    text.push_str(&spread_row("training time per run (s)", &f.training_s));
    text.push_str(&spread_row("simulated time per run (s)", &f.simulated_s));
    text.push_str(&spread_row(
        "diversity (the paper's: median pairwise distance of failing roads' directions; runs with ≥ 2 failures)",
        &f.diversity,
    ));
    text.push_str(&spread_row(
        "angle diversity (the same, each direction difference the angle between the directions)",
        &f.angle_diversity,
    ));
    text.push_str(&spread_row(DISTINCT_FAILURES, &f.distinct_failures));
    for (name, measure) in YIELD.into_iter().chain(EXPLOITATION) {
        text.push_str(&spread_row(name, &Spread::of(&f.values(measure))));
    }
    text.push_str(&competition(f));
    let failing: usize = f.runs.iter().map(|m| m.failures).sum();
    let _ = writeln!(
        text,
        "\nFeature coverage of the {failing} failing test(s):\n"
    );
    text.push_str("| feature | bins covered | min | median | max |\n|---|---|---|---|---|\n");
    text.push_str(&coverage_row("DIR_COV (buckets of 1/26)", &f.dir_cov));
    text.push_str(&coverage_row(
        &format!("MAX_CURV (1/m, bins of {MAX_CURV_BIN_PER_M})"),
        &f.max_curv,
    ));
    text.push_str(&coverage_row(
        &format!("STD_SA (deg, bins of {STD_SA_BIN_DEG})"),
        &f.std_sa,
    ));
    text.push_str(&coverage_row(
        &format!("MEAN_LP (m, bins of {MEAN_LP_BIN_M})"),
        &f.mean_lp,
    ));
    let buckets: Vec<String> = f
        .dir_cov_buckets
        .iter()
        .map(|k| format!("{k}/26"))
        .collect();
    if !buckets.is_empty() {
        let _ = writeln!(text, "\nDIR_COV values hit: {}.", buckets.join(", "));
    }
    let p = &section.pictures;
    let _ = writeln!(
        text,
        "\nPictures: [failing roads]({}) · [max BOLP histogram]({})",
        p.roads, p.bolp
    );
    let runs: Vec<String> = p
        .fitness
        .iter()
        .enumerate()
        .map(|(i, name)| format!("[run {}]({name})", i + 1))
        .collect();
    let _ = writeln!(text, "· fitness over the run: {}\n", runs.join(" "));
    let _ = writeln!(
        text,
        "![failing roads]({})\n\n![max BOLP]({})\n",
        p.roads, p.bolp
    );
    if let Some(first) = p.fitness.first() {
        let _ = writeln!(text, "![fitness over run 1]({first})\n");
    }
    text
}

/// A group's table of the competition's measures, with a note on runs its OOB analysis fails.
fn competition(f: &GroupFigures) -> String {
    let mut text = String::from(
        "\nThe SBST competition's measures, as its pipeline computes them (beside the paper's \
         diversity above):\n\n| measure | mean | SD | runs |\n|---|---|---|---|\n",
    );
    for (name, measure) in COMPETITION {
        text.push_str(&spread_row(name, &Spread::of(&f.values(measure))));
    }
    let failed: Vec<String> = f
        .runs
        .iter()
        .enumerate()
        .filter_map(|(i, m)| {
            m.sbst
                .oob
                .as_ref()
                .err()
                .map(|e| format!("run {}: {}", i + 1, literal(e)))
        })
        .collect();
    if !failed.is_empty() {
        let unplaced: usize = f.runs.iter().map(|m| m.sbst.oob_unplaced).sum();
        let _ = writeln!(
            text,
            "\nThe pipeline's OOB analysis fails on {} of {} run(s) ({unplaced} OOB(s) it cannot \
             place on its resampled road), as the pipeline itself would:\n",
            failed.len(),
            f.runs.len()
        );
        for line in failed {
            let _ = writeln!(text, "- {line}");
        }
    }
    text
}

/// The side-by-side table of two groups.
fn comparison(a: &GroupSection, b: &GroupSection) -> String {
    let mut text = String::from("## Comparison: A vs B\n\n");
    let _ = writeln!(text, "- {}\n- {}\n", literal(&a.label), literal(&b.label));
    let competition = COMPETITION_COMPARED.map(|i| COMPETITION[i]);
    text.push_str(&comparison_table(&a.figures, &b.figures, &competition));
    text.push('\n');
    text
}

/// The Mann–Whitney table of A against B: the outcomes, the exploitation measures and
/// `competition` (some or all of the competition's measures).
pub fn comparison_table(
    a: &GroupFigures,
    b: &GroupFigures,
    competition: &[(&str, Measure)],
) -> String {
    let mut text =
        String::from("| measure | A mean (SD) | B mean (SD) | U of A | p (two-sided) | method |\n");
    text.push_str("|---|---|---|---|---|---|\n");
    // The means shown are those of the samples the test compares.
    let outcomes: [(&str, Measure); 4] = [
        ("failures per run", |m| Some(m.failures as f64)),
        ("diversity", |m| m.diversity),
        ("angle diversity", |m| m.angle_diversity),
        ("distinct failures per run", |m| {
            m.distinct_failures.map(|n| n as f64)
        }),
    ];
    let measures = outcomes
        .into_iter()
        .chain(YIELD)
        .chain(EXPLOITATION)
        .chain(competition.iter().copied());
    for (name, measure) in measures {
        let (x, y) = (a.values(measure), b.values(measure));
        let both = |s: &Spread| format!("{} ({}) n={}", number(s.mean), number(s.sd), s.count);
        let (u, p, method) = match mann_whitney(&x, &y) {
            Some(r) => {
                let method = match r.method {
                    PMethod::Exact => "exact",
                    PMethod::Normal => "normal, tie-corrected",
                };
                (r.u1.to_string(), format!("{:.4}", r.p_value), method)
            }
            None => ("–".to_owned(), "–".to_owned(), "too few runs"),
        };
        let _ = writeln!(
            text,
            "| {name} | {} | {} | {u} | {p} | {method} |",
            both(&Spread::of(&x)),
            both(&Spread::of(&y))
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use pulldown_cmark::{html::push_html, Parser};

    /// Strings files have carried into reports: HTML, links, pictures, code spans, entities, and
    /// what would start a block or end a line.
    const HOSTILE: [&str; 17] = [
        "<img src=x onerror=\"document.title=1\">",
        "[x](javascript:alert(1))",
        "<javascript:alert(1)>",
        "`<!--<script>`",
        "![x](nothere.svg)",
        "![i](javascript:alert(1))",
        "a` <img src=x onerror=\"document.title=4\"> `b.jsonl",
        "&lt;b&gt; &#106;avascript",
        "*strong* _em_ __x__ ~~gone~~ $x$ {: .c} | a | b |",
        "[ref]: javascript:alert(1)",
        "- item",
        "+ item",
        "12. item",
        "3) item",
        "# heading #",
        "line\nbreak\r\n\n# heading\n<script>x</script>",
        "trailing \\",
    ];

    /// The HTML Markdown `text` renders to.
    fn rendered(text: &str) -> String {
        let mut html = String::new();
        push_html(&mut html, Parser::new(text));
        html
    }

    /// `text` as a renderer writes plain text.
    fn as_html_text(text: &str) -> String {
        text.chars()
            .map(|c| match c {
                '&' => "&amp;".to_owned(),
                '<' => "&lt;".to_owned(),
                '>' => "&gt;".to_owned(),
                c if c.is_control() => " ".to_owned(),
                c => c.to_string(),
            })
            .collect()
    }

    #[test]
    fn a_file_string_renders_as_itself_in_a_list_item_and_a_heading() {
        for hostile in HOSTILE {
            let text = as_html_text(hostile);
            assert_eq!(
                rendered(&format!("- {}\n", literal(hostile))),
                format!("<ul>\n<li>{}</li>\n</ul>\n", text.trim_end()),
                "{hostile:?} as {:?}",
                literal(hostile)
            );
            assert_eq!(
                rendered(&format!("## Group 1: {}\n", literal(hostile))),
                format!("<h2>Group 1: {}</h2>\n", text.trim_end()),
                "{hostile:?} as {:?}",
                literal(hostile)
            );
        }
    }

    #[test]
    fn a_backtick_cannot_end_a_code_span_nor_a_bracket_make_a_link() {
        assert_eq!(literal("a` <img> `b.jsonl"), "a\\` &lt;img&gt; \\`b.jsonl");
        assert_eq!(literal("[x](javascript:1)"), "\\[x\\](javascript:1)");
        assert_eq!(literal("&#106;"), "&amp;\\#106;");
        assert_eq!(literal("1\n2\r3\u{2028}4"), "1 2 3 4");
    }

    #[test]
    fn ordinary_labels_and_paths_stay_readable() {
        for plain in [
            "wogan / beamng-ai-proxy / fitness max_bolp / decay 0.95 / oob 0.85 / 70.0 km/h",
            "/tmp/runs/wogan.seed3.jsonl",
            "sbst:FakeGen",
            "failed part-way: the generator crashed: pandas.errors.InvalidIndexError (x)",
        ] {
            assert_eq!(literal(plain), plain);
        }
        assert_eq!(literal("-x_ _y 2021.jsonl"), "\\-x\\_ \\_y 2021.jsonl");
    }

    #[test]
    fn the_report_quotes_every_file_string_literally() {
        let hostile = "<img src=x onerror=\"document.title=1\">";
        let section = GroupSection {
            label: hostile.to_owned(),
            files: vec![(format!("`{hostile}`.jsonl"), Some(hostile.to_owned()))],
            figures: GroupFigures::of(&[]),
            pictures: Pictures {
                roads: "roads.g1.svg".into(),
                bolp: "bolp.g1.svg".into(),
                fitness: vec![],
            },
            error_tests: vec![ErrorTest {
                file: hostile.to_owned(),
                test: 7,
                reason: Some("error".to_owned()),
                message: Some(hostile.repeat(100)),
            }],
            error_total: 3,
        };
        let text = report(&[section], false, &[format!("x.jsonl:1: `{hostile}`")]);
        assert!(text.contains("3 test(s) ended in ERROR"), "{text}");
        assert!(
            text.contains(" test 7: error: ") && text.contains("- and 2 more"),
            "{text}"
        );
        assert!(!text.contains('<'), "{text}");
        assert!(!rendered(&text).contains("<img src=x"), "{text}");
    }
}
