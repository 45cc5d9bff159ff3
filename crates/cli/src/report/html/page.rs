//! Writes `report.html`: one self-contained page (styles, script, pictures and data inline; it
//! loads nothing) whose static parts read without scripts: the runs, the failing roads' table,
//! and report.md's figures and pictures; the script sorts and filters the table and draws a
//! road's detail when its row is chosen.
//!
//! Everything on it that comes from a file (labels, file names, errors, report.md's text) is text:
//! escaped in elements and attributes, shown as text where report.md would have raw HTML, a link
//! elsewhere than the web, the page or beside it, or a picture the report did not draw, and
//! escaped in the roads' JSON so that no string can end or stall a script element.

use super::failing_roads::{failing_roads, FailingRoad};
use super::redrive::{redrive_worst, NotDrivenAgain};
use crate::files::run_file::RunFile;
use crate::report::markdown::GroupSection;
use anyhow::{Context, Result};
use base64::Engine;
use pulldown_cmark::{Event, LinkType, Options, Parser, Tag, TagEnd};
use std::collections::HashSet;
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
/// not be driven again.
pub fn write_html_report(
    out: &Path,
    markdown: &str,
    sections: &[GroupSection],
    groups: &[&[RunFile]],
    options: HtmlReport,
    stop: &AtomicBool,
) -> Result<(PathBuf, NotDrivenAgain)> {
    let mut roads = failing_roads(groups);
    let not_traced = redrive_worst(&mut roads, groups, options.traces, stop);
    let figures = markdown_html(markdown, out, &own_pictures(sections))?;
    let page = page(sections, &roads, &figures, &not_traced.reasons);
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

/// report.md as HTML, its first heading left out (the page has its own). Everything in it is text:
/// raw HTML shows as its text, a link stays a link only to the web, the page or a file beside it
/// ([`safe_link`]), and a picture is inlined as a data URL only when it is one of `pictures`, the
/// files this report drew into `out`; any other picture report.md names (whatever a run's header
/// put there) shows as its alt text.
fn markdown_html(markdown: &str, out: &Path, pictures: &HashSet<&str>) -> Result<String> {
    let body = markdown
        .strip_prefix("# wogan report\n")
        .unwrap_or(markdown);
    let mut events = Vec::new();
    // The picture being read (its file and alt text) and how deep in pictures the parser is (an
    // alt text may hold pictures of its own, which are only text).
    let mut image: Option<(String, String)> = None;
    let mut image_depth = 0usize;
    // Whether each link open at this point was kept.
    let mut links: Vec<bool> = Vec::new();
    for event in Parser::new_ext(body, Options::ENABLE_TABLES) {
        if image_depth > 0 {
            match event {
                Event::Start(Tag::Image { .. }) => image_depth += 1,
                Event::End(TagEnd::Image) => image_depth -= 1,
                Event::Text(text)
                | Event::Code(text)
                | Event::InlineHtml(text)
                | Event::Html(text) => {
                    if let Some((_, alt)) = &mut image {
                        alt.push_str(&text);
                    }
                }
                _ => {}
            }
            if image_depth == 0 {
                let (file, alt) = image.take().unwrap_or_default();
                events.push(match picture(out, &file, &alt, pictures)? {
                    Some(img) => Event::Html(img.into()),
                    None => Event::Text(alt.into()),
                });
            }
            continue;
        }
        match event {
            Event::Start(Tag::Image { dest_url, .. }) => {
                image = Some((dest_url.to_string(), String::new()));
                image_depth = 1;
            }
            Event::Start(Tag::Link {
                link_type,
                ref dest_url,
                ..
            }) => {
                let kept = link_type != LinkType::Email && safe_link(dest_url);
                links.push(kept);
                if kept {
                    events.push(event);
                }
            }
            Event::End(TagEnd::Link) => {
                if links.pop().unwrap_or(false) {
                    events.push(event);
                }
            }
            Event::Html(html) | Event::InlineHtml(html) => events.push(Event::Text(html)),
            Event::Start(Tag::HtmlBlock) => events.push(Event::Start(Tag::Paragraph)),
            Event::End(TagEnd::HtmlBlock) => events.push(Event::End(TagEnd::Paragraph)),
            event => events.push(event),
        }
    }
    let mut html = String::new();
    pulldown_cmark::html::push_html(&mut html, events.into_iter());
    Ok(html)
}

/// Whether a link may stay a link on the page: to a place on it (`#…`), a file beside it (a
/// relative path) or the web (`http:`, `https:`). Any other scheme (`javascript:`, `data:`,
/// `vbscript:`, `file:`, …) could run a script or reach outside, so its link shows as its text.
/// The URL is read as a browser reads it: tabs and line breaks anywhere dropped, leading spaces and
/// control characters too (entities and escapes the Markdown parser has decoded already); a colon
/// before any `/`, `?` or `#` ends a scheme.
fn safe_link(url: &str) -> bool {
    let url: String = url
        .chars()
        .filter(|c| !matches!(c, '\t' | '\n' | '\r'))
        .collect();
    let url = url.trim_start_matches(|c: char| c <= ' ');
    match url.find([':', '/', '?', '#']) {
        Some(end) if url[end..].starts_with(':') => {
            let scheme = &url[..end];
            scheme.eq_ignore_ascii_case("http") || scheme.eq_ignore_ascii_case("https")
        }
        _ => true,
    }
}

/// An `<img>` of `file` as a data URL when it is one of `pictures` (the report's own, beside
/// report.md in `out`), else `None`.
fn picture(out: &Path, file: &str, alt: &str, pictures: &HashSet<&str>) -> Result<Option<String>> {
    if !pictures.contains(file) {
        return Ok(None);
    }
    let mime = if file.ends_with(".svg") {
        "image/svg+xml"
    } else if file.ends_with(".png") {
        "image/png"
    } else {
        return Ok(None);
    };
    let path = out.join(file);
    let bytes = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let data = base64::engine::general_purpose::STANDARD.encode(bytes);
    Ok(Some(format!(
        "<img class=\"picture\" alt=\"{}\" src=\"data:{mime};base64,{data}\">",
        escaped(alt)
    )))
}

/// The names of the pictures this report drew into its folder, which alone the page inlines.
fn own_pictures(sections: &[GroupSection]) -> HashSet<&str> {
    sections
        .iter()
        .flat_map(|s| {
            let p = &s.pictures;
            [&p.roads, &p.bolp].into_iter().chain(&p.fitness)
        })
        .map(String::as_str)
        .collect()
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
/// the browser does not run ([`script_json`]: no string in it can end the element or change how
/// the browser reads the rest of the page).
fn road_data(html: &mut String, sections: &[GroupSection], roads: &[FailingRoad]) {
    let groups: Vec<&str> = sections.iter().map(|s| s.label.as_str()).collect();
    let roads: Vec<serde_json::Value> = roads.iter().map(FailingRoad::to_json).collect();
    let json = script_json(&serde_json::json!({ "groups": groups, "roads": roads }).to_string());
    let _ = writeln!(
        html,
        "<script type=\"application/json\" id=\"road-data\">{json}</script>"
    );
}

/// JSON text made safe inside a `<script>` element: `<`, `>` and `&` as `\u003c`, `\u003e` and
/// `\u0026` (so that neither `</script>` nor `<!--<script>`, which puts the browser's tokenizer in
/// a state where the page's own script would be swallowed, can appear), and the line separators
/// U+2028 and U+2029 escaped too. Those characters occur in JSON only inside strings, where the
/// escapes mean the same characters.
fn script_json(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    for c in json.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::group::GroupFigures;
    use crate::report::pictures::Pictures;

    /// A scratch folder holding `p.svg`, the one picture the report drew, and `q.svg`, which it
    /// did not.
    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("wogan-html-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("p.svg"), "<svg/>").unwrap();
        std::fs::write(dir.join("q.svg"), "<svg/>").unwrap();
        dir
    }

    /// report.md's `markdown` as the page shows it, `p.svg` the report's one picture.
    fn shown(markdown: &str, dir: &Path) -> String {
        markdown_html(markdown, dir, &HashSet::from(["p.svg"])).unwrap()
    }

    #[test]
    fn text_is_escaped_for_elements_and_attributes() {
        assert_eq!(escaped("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
    }

    #[test]
    fn only_the_reports_own_pictures_are_inlined_and_any_other_is_its_alt_text() {
        let dir = folder("pictures");
        let html = shown(
            "# wogan report\n\n| a |\n|---|\n| 1 |\n\n![the map](p.svg)\n",
            &dir,
        );
        assert!(!html.contains("<h1>"), "{html}");
        assert!(html.contains("<table>"), "{html}");
        assert!(
            html.contains("alt=\"the map\" src=\"data:image/svg+xml;base64,PHN2Zy8+\""),
            "{html}"
        );
        for (markdown, text) in [
            ("![x](nothere.svg)\n", "<p>x</p>\n"),
            ("![i](javascript:alert(1))\n", "<p>i</p>\n"),
            ("![up](../p.svg)\n", "<p>up</p>\n"),
            (
                "![beside, not drawn](q.svg)\n",
                "<p>beside, not drawn</p>\n",
            ),
            ("![a *b* `c`](/etc/passwd)\n", "<p>a b c</p>\n"),
            ("![a ![b](p.svg) c](x.svg)\n", "<p>a b c</p>\n"),
            ("![<img src=x>](x.svg)\n", "<p>&lt;img src=x&gt;</p>\n"),
        ] {
            assert_eq!(shown(markdown, &dir), text, "{markdown}");
        }
        // A picture the report drew must be there to be inlined.
        std::fs::remove_file(dir.join("p.svg")).unwrap();
        assert!(markdown_html("![m](p.svg)\n", &dir, &HashSet::from(["p.svg"])).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn raw_html_shows_as_its_text() {
        let dir = folder("raw-html");
        for (markdown, text) in [
            (
                "a <img src=x onerror=\"document.title=1\"> b\n",
                "<p>a &lt;img src=x onerror=\"document.title=1\"&gt; b</p>\n",
            ),
            (
                "<script>alert(1)</script>\n",
                "<p>&lt;script&gt;alert(1)&lt;/script&gt;\n</p>\n",
            ),
            (
                "<!--<script>-->\n",
                "<p>&lt;!--&lt;script&gt;--&gt;\n</p>\n",
            ),
            (
                "- `<b>` <b>bold</b>\n",
                "<ul>\n<li><code>&lt;b&gt;</code> &lt;b&gt;bold&lt;/b&gt;</li>\n</ul>\n",
            ),
        ] {
            assert_eq!(shown(markdown, &dir), text, "{markdown}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn links_stay_links_only_to_the_web_the_page_and_files_beside_it() {
        for url in [
            "roads.g1.svg",
            "#failing",
            "http://example.org/a",
            "HTTPS://example.org",
            "a/b:c",
            "?q=a:b",
            "//example.org/x",
            "",
        ] {
            assert!(safe_link(url), "{url:?}");
        }
        for url in [
            "javascript:alert(1)",
            "JaVaScRiPt:alert(1)",
            " javascript:alert(1)",
            "\u{1}javascript:alert(1)",
            "java\tscript:alert(1)",
            "java\nscript:alert(1)",
            "data:text/html,<script>alert(1)</script>",
            "vbscript:msgbox",
            "file:///etc/passwd",
            "mailto:a@b.c",
            "http\u{a0}:x",
        ] {
            assert!(!safe_link(url), "{url:?}");
        }
        let dir = folder("links");
        for (markdown, text) in [
            ("[x](javascript:alert(1))\n", "<p>x</p>\n"),
            ("[x](&#106;avascript:alert(1))\n", "<p>x</p>\n"),
            ("[x](<java\\script:alert(1)>)\n", "<p>x</p>\n"),
            ("<javascript:alert(1)>\n", "<p>javascript:alert(1)</p>\n"),
            ("<a@b.c>\n", "<p>a@b.c</p>\n"),
            ("[r]: javascript:alert(1)\n\n[x][r]\n", "<p>x</p>\n"),
            (
                "[map](roads.g1.svg) [top](#runs) [web](https://example.org)\n",
                "<p><a href=\"roads.g1.svg\">map</a> <a href=\"#runs\">top</a> \
                 <a href=\"https://example.org\">web</a></p>\n",
            ),
        ] {
            assert_eq!(shown(markdown, &dir), text, "{markdown}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn road_data_cannot_end_its_script_element_nor_stall_the_page_script() {
        let label = "`<!--<script>` </script> & \u{2028}\u{2029} '\"";
        let section = GroupSection {
            label: label.to_owned(),
            files: vec![],
            figures: GroupFigures::of(&[]),
            pictures: Pictures {
                roads: "roads.g1.svg".into(),
                bolp: "bolp.g1.svg".into(),
                fitness: vec![],
            },
            error_tests: vec![],
            error_total: 0,
        };
        let mut html = String::new();
        road_data(&mut html, &[section], &[]);
        let start = "<script type=\"application/json\" id=\"road-data\">";
        let json = html
            .strip_prefix(start)
            .and_then(|h| h.strip_suffix("</script>\n"))
            .expect("one element");
        assert!(
            !json.contains(['<', '>', '&', '\u{2028}', '\u{2029}']),
            "{json}"
        );
        let value: serde_json::Value = serde_json::from_str(json).unwrap();
        assert_eq!(value["groups"][0], label);
        assert_eq!(value["roads"], serde_json::json!([]));
    }
}
