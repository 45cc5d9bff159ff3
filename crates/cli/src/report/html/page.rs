//! Writes `report.html`: one self-contained page (styles, script, pictures and data inline; it
//! loads nothing) whose static parts read without scripts: the runs, the failing roads' table,
//! and report.md's figures and pictures; the script sorts and filters the table and draws a
//! road's detail when its row is chosen.

use super::failing_roads::{failing_roads, FailingRoad};
use super::redrive::redrive_worst;
use crate::files::run_file::RunFile;
use crate::report::markdown::GroupSection;
use anyhow::{Context, Result};
use base64::Engine;
use pulldown_cmark::{Event, Options, Parser, Tag, TagEnd};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// The page's style.
const STYLE: &str = include_str!("report.css");
/// The page's script: sorting, filtering and paging the rows, the detail view.
const SCRIPT: &str = include_str!("report.js");
/// The file name written beside report.md.
pub const FILE_NAME: &str = "report.html";
/// The page's size bound: this much for the page around the data, plus [`BYTES_PER_ROAD`] per
/// failing road and [`BYTES_PER_ROAD_METRE`] per metre of it, [`BYTES_PER_TRACE`] per re-driven
/// one, and report.md's pictures inlined (base64: 4/3 of their size). docs/reference.md states it
/// and tests/report.rs holds a page of 10,000 failing roads to it.
pub const FIXED_BYTES: usize = 64 * 1024;
/// See [`FIXED_BYTES`]: a failing road's row and what its geometry costs whatever its length.
pub const BYTES_PER_ROAD: usize = 1024;
/// See [`FIXED_BYTES`]: a point of the centre line every 2 m, at most 14 bytes.
pub const BYTES_PER_ROAD_METRE: usize = 8;
/// See [`FIXED_BYTES`]: a trace of at most `TRACE_SAMPLES` samples.
pub const BYTES_PER_TRACE: usize = 16 * 1024;

/// What `--html` asks of the page.
#[derive(Debug, Clone, Copy, Default)]
pub struct HtmlReport {
    /// Failing roads of highest BOLP to drive again and trace (`--traces N`).
    pub traces: usize,
}

/// Writes `out/report.html` from report.md's text `markdown` (its pictures read from `out`), the
/// groups' sections and their runs (`groups`, in the same order). Returns its path and what could
/// not be traced.
pub fn write_html_report(
    out: &Path,
    markdown: &str,
    sections: &[GroupSection],
    groups: &[&[RunFile]],
    options: HtmlReport,
    stop: &AtomicBool,
) -> Result<(PathBuf, Vec<String>)> {
    let mut roads = failing_roads(groups);
    let not_traced = redrive_worst(&mut roads, groups, options.traces, stop);
    let figures = markdown_html(markdown, out)?;
    let page = page(sections, &roads, &figures, &not_traced);
    let path = out.join(FILE_NAME);
    std::fs::write(&path, page).with_context(|| format!("cannot write {}", path.display()))?;
    Ok((path, not_traced))
}

/// `text` with `&`, `<`, `>` and quotes escaped, for element text and attribute values.
fn escaped(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// report.md as HTML, its first heading left out (the page has its own) and each picture it
/// names (an SVG file beside it) inlined as a data URL, so that the page needs no other file.
fn markdown_html(markdown: &str, out: &Path) -> Result<String> {
    let body = markdown
        .strip_prefix("# wogan report\n")
        .unwrap_or(markdown);
    let mut events = Vec::new();
    let mut image: Option<(String, String)> = None;
    for event in Parser::new_ext(body, Options::ENABLE_TABLES) {
        match event {
            Event::Start(Tag::Image { dest_url, .. }) => {
                image = Some((dest_url.to_string(), String::new()))
            }
            Event::End(TagEnd::Image) => {
                let (file, alt) = image.take().unwrap_or_default();
                events.push(Event::Html(picture(out, &file, &alt)?.into()));
            }
            Event::Text(text) if image.is_some() => {
                if let Some((_, alt)) = &mut image {
                    alt.push_str(&text);
                }
            }
            _ if image.is_some() => {}
            event => events.push(event),
        }
    }
    let mut html = String::new();
    pulldown_cmark::html::push_html(&mut html, events.into_iter());
    Ok(html)
}

/// An `<img>` of the picture `file` (a file name beside report.md) as a data URL.
fn picture(out: &Path, file: &str, alt: &str) -> Result<String> {
    if file.contains(['/', '\\']) || !file.ends_with(".svg") {
        anyhow::bail!("report.md names a picture outside its folder: {file}");
    }
    let path = out.join(file);
    let svg = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let data = base64::engine::general_purpose::STANDARD.encode(svg);
    Ok(format!(
        "<img class=\"picture\" alt=\"{}\" src=\"data:image/svg+xml;base64,{data}\">",
        escaped(alt)
    ))
}

/// A number with `decimals`, or a dash.
fn figure(value: Option<f64>, decimals: usize) -> String {
    match value {
        Some(v) if v.is_finite() => format!("{v:.decimals$}"),
        _ => "–".to_owned(),
    }
}

/// The whole page.
fn page(
    sections: &[GroupSection],
    roads: &[FailingRoad],
    figures: &str,
    not_traced: &[String],
) -> String {
    let runs: usize = sections.iter().map(|s| s.files.len()).sum();
    let traced = roads.iter().filter(|r| r.trace.is_some()).count();
    let metres: f64 = roads
        .iter()
        .map(|r| r.length_m)
        .filter(|m| m.is_finite())
        .sum();
    let mut html = String::with_capacity(
        FIXED_BYTES
            + roads.len() * BYTES_PER_ROAD
            + metres as usize * BYTES_PER_ROAD_METRE
            + traced * BYTES_PER_TRACE,
    );
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>wogan report: {runs} run(s), {} failing road(s)</title>\n<style>\n{STYLE}</style>\n\
         <script>document.documentElement.classList.add(\"js\");</script>\n</head>\n<body>\n\
         <header>\n<h1>wogan report</h1>\n<p>{runs} run(s) in {} group(s); <a href=\"#failing\">{} failing road(s)</a>; \
         <a href=\"#figures\">figures and pictures</a>.</p>\n</header>\n<main>\n",
        roads.len(),
        sections.len(),
        roads.len(),
    );
    runs_table(&mut html, sections);
    failing_table(&mut html, roads, traced, not_traced);
    let _ = write!(
        html,
        "<section id=\"figures\">\n<h2>Figures</h2>\n{figures}</section>\n</main>\n"
    );
    road_data(&mut html, sections, roads);
    let _ = write!(html, "<script>\n{SCRIPT}</script>\n</body>\n</html>\n");
    html
}

/// The runs: one row per run, by group.
fn runs_table(html: &mut String, sections: &[GroupSection]) {
    html.push_str(
        "<section id=\"runs\">\n<h2>Runs</h2>\n<table class=\"sortable\">\n<thead><tr>\
         <th>group</th><th>run file</th><th class=\"num\">tests</th><th class=\"num\">failures</th>\
         <th class=\"num\">distinct failures</th><th class=\"num\">diversity</th><th>ended</th></tr></thead>\n<tbody>\n",
    );
    for (index, section) in sections.iter().enumerate() {
        for ((file, ended), measures) in section.files.iter().zip(&section.figures.runs) {
            let _ = writeln!(
                html,
                "<tr><td title=\"{label}\">g{group}</td><td>{file}</td><td class=\"num\">{tests}</td>\
                 <td class=\"num\">{failures}</td><td class=\"num\">{distinct}</td><td class=\"num\">{diversity}</td>\
                 <td>{ended}</td></tr>",
                label = escaped(&section.label),
                group = index + 1,
                file = escaped(file),
                tests = measures.executed,
                failures = measures.failures,
                distinct = measures.distinct_failures.map_or_else(|| "–".to_owned(), |n| n.to_string()),
                diversity = figure(measures.diversity, 2),
                ended = escaped(ended.as_deref().unwrap_or("normally")),
            );
        }
    }
    html.push_str("</tbody>\n</table>\n<dl class=\"groups\">\n");
    for (index, section) in sections.iter().enumerate() {
        let _ = writeln!(
            html,
            "<dt>g{}</dt><dd>{}</dd>",
            index + 1,
            escaped(&section.label)
        );
    }
    html.push_str("</dl>\n</section>\n");
}

/// The failing roads' table, its filter and the detail view's place.
fn failing_table(html: &mut String, roads: &[FailingRoad], traced: usize, not_traced: &[String]) {
    let _ = write!(
        html,
        "<section id=\"failing\">\n<h2>Failing roads</h2>\n<p>{} failing road(s); {traced} re-driven with a trace \
         (<code>--traces N</code>). Choose a row to see the road.</p>\n",
        roads.len()
    );
    if !not_traced.is_empty() {
        html.push_str(
            "<details class=\"problems\"><summary>roads not driven again</summary><ul>\n",
        );
        for problem in not_traced {
            let _ = writeln!(html, "<li>{}</li>", escaped(problem));
        }
        html.push_str("</ul></details>\n");
    }
    html.push_str(
        "<form id=\"filter\" class=\"needs-script\" hidden>\n\
         <label>find <input type=\"search\" id=\"filter-text\" placeholder=\"run file, test, group\"></label>\n\
         <label>side <select id=\"filter-side\"><option value=\"\">either</option><option>left</option>\
         <option>right</option></select></label>\n\
         <label>max BOLP at least <input type=\"number\" id=\"filter-bolp\" min=\"0\" max=\"1\" step=\"0.05\" value=\"0\"></label>\n\
         <output id=\"filter-count\"></output>\n<button type=\"button\" id=\"filter-more\" hidden>show 500 more</button>\n</form>\n\
         <div class=\"failing-view\">\n<div class=\"table-box\">\n\
         <table id=\"failing-roads\" class=\"sortable\">\n<thead><tr><th>group</th><th>run file</th>\
         <th class=\"num\">test</th><th class=\"num\">max BOLP</th><th>side</th><th class=\"num\">length (m)</th>\
         <th>driven again</th></tr></thead>\n<tbody>\n",
    );
    for (index, road) in roads.iter().enumerate() {
        let _ = writeln!(
            html,
            "<tr id=\"road-{index}\" data-road=\"{index}\" tabindex=\"0\"><td>g{group}</td>\
             <td>{file}</td><td class=\"num\">{test}</td><td class=\"num\">{bolp}</td><td>{side}</td>\
             <td class=\"num\">{length}</td><td>{trace}</td></tr>",
            group = road.group + 1,
            file = escaped(&road.run_file),
            test = road.test,
            bolp = figure(Some(road.max_bolp), 3),
            side = road.side.unwrap_or("–"),
            length = figure(Some(road.length_m), 1),
            trace = road.trace.as_ref().map_or("", |t| t.outcome.as_str()),
        );
    }
    html.push_str(
        "</tbody>\n</table>\n</div>\n<aside id=\"detail\" aria-live=\"polite\">\n\
         <p class=\"needs-script\" hidden>Choose a row: its road, where the car left its lane and, when \
         re-driven, the car's path and its BOLP along the drive.</p>\n\
         <noscript><p>The detail view of a road needs scripts; the table above is complete without \
         them.</p></noscript>\n</aside>\n</div>\n</section>\n",
    );
}

/// The groups' labels and the roads' geometry for the detail view, as JSON in a script element
/// the browser does not run (`</` escaped so that no string closes it).
fn road_data(html: &mut String, sections: &[GroupSection], roads: &[FailingRoad]) {
    let groups: Vec<&str> = sections.iter().map(|s| s.label.as_str()).collect();
    let roads: Vec<serde_json::Value> = roads.iter().map(FailingRoad::to_json).collect();
    let json = serde_json::json!({ "groups": groups, "roads": roads })
        .to_string()
        .replace("</", "<\\/");
    let _ = writeln!(
        html,
        "<script type=\"application/json\" id=\"road-data\">{json}</script>"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_for_elements_and_attributes() {
        assert_eq!(escaped("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
    }

    #[test]
    fn pictures_are_inlined_and_one_outside_the_folder_is_refused() {
        let dir = std::env::temp_dir().join(format!("wogan-html-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("p.svg"), "<svg/>").unwrap();
        let html = markdown_html(
            "# wogan report\n\n| a |\n|---|\n| 1 |\n\n![the map](p.svg)\n",
            &dir,
        )
        .unwrap();
        assert!(!html.contains("<h1>"), "{html}");
        assert!(html.contains("<table>"), "{html}");
        assert!(
            html.contains("alt=\"the map\" src=\"data:image/svg+xml;base64,PHN2Zy8+\""),
            "{html}"
        );
        assert!(markdown_html("![x](../p.svg)\n", &dir).is_err());
        assert!(markdown_html("![x](missing.svg)\n", &dir).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn road_data_cannot_close_its_script_element() {
        let mut html = String::new();
        road_data(&mut html, &[], &[]);
        assert_eq!(
            html,
            "<script type=\"application/json\" id=\"road-data\">{\"groups\":[],\"roads\":[]}</script>\n"
        );
        let text = serde_json::Value::String("</script>".into())
            .to_string()
            .replace("</", "<\\/");
        assert_eq!(text, "\"<\\/script>\"");
    }
}
