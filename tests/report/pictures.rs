//! `wogan report`'s pictures: SVGs that parse, one road per failing test, every text inside its
//! picture, legends over no bar, labels that do not pile up, ten thousand roads drawn small.

use super::*;
use crate::common::{scratch_dir, wogan_ok};
use std::path::Path;

/// Counts the elements named `tag` of an SVG file, after checking that it parses as XML.
fn count_elements(path: &Path, tag: &str) -> usize {
    let text = read(path);
    let document =
        roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(document.root_element().tag_name().name(), "svg");
    document
        .descendants()
        .filter(|n| n.tag_name().name() == tag)
        .count()
}

/// The trimmed text of every `<text>` element of an SVG file.
fn texts(path: &Path) -> Vec<String> {
    let text = read(path);
    let document =
        roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    document
        .descendants()
        .filter(|n| n.tag_name().name() == "text")
        .map(|n| n.text().unwrap_or("").trim().to_owned())
        .collect()
}

/// Estimated advance of a character, in ems of its font size (sans-serif text averages about
/// 0.55; the estimate errs wide).
const CHAR_WIDTH_EM: f64 = 0.6;

/// A `<text>` element of an SVG with its estimated extent, pixels.
#[derive(Debug)]
struct TextBox {
    text: String,
    left: f64,
    top: f64,
    right: f64,
    bottom: f64,
}

impl TextBox {
    fn overlaps(&self, other: &TextBox) -> bool {
        self.left < other.right
            && other.left < self.right
            && self.top < other.bottom
            && other.top < self.bottom
    }
}

/// A number attribute of an SVG element.
fn number(node: roxmltree::Node, name: &str) -> f64 {
    let value = node
        .attribute(name)
        .unwrap_or_else(|| panic!("<{}> without {name}", node.tag_name().name()));
    value
        .parse()
        .unwrap_or_else(|e| panic!("{name}=\"{value}\": {e}"))
}

/// The view box of an SVG file (width, height) and the estimated box of each of its `<text>`
/// elements: as wide as its characters times [`CHAR_WIDTH_EM`] times its font size and one font
/// size high, placed by its anchor, its baseline shift (plotters writes one per vertical
/// position) and its rotation.
fn text_boxes(path: &Path) -> ((f64, f64), Vec<TextBox>) {
    let svg = read(path);
    let document =
        roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let root = document.root_element();
    let view = match root.attribute("viewBox") {
        Some(view) => {
            let n: Vec<f64> = view
                .split([' ', ','])
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().expect("a viewBox number"))
                .collect();
            assert_eq!(n[..2], [0.0, 0.0], "{}: viewBox {view}", path.display());
            (n[2], n[3])
        }
        None => (number(root, "width"), number(root, "height")),
    };
    let boxes = document
        .descendants()
        .filter(|n| n.tag_name().name() == "text")
        .map(|node| {
            let text = node.text().unwrap_or("").trim().to_owned();
            let (x, y, size) = (
                number(node, "x"),
                number(node, "y"),
                number(node, "font-size"),
            );
            let width = text.chars().count() as f64 * size * CHAR_WIDTH_EM;
            let (left, right) = match node.attribute("text-anchor").unwrap_or("start") {
                "start" => (0.0, width),
                "middle" => (-width / 2.0, width / 2.0),
                "end" => (-width, 0.0),
                other => panic!("text-anchor {other}"),
            };
            let (top, bottom) = match node.attribute("dy") {
                Some("0.76em") => (0.0, size),
                Some("0.5ex") => (-size / 2.0, size / 2.0),
                Some("-0.5ex") => (-size, 0.0),
                None => (-0.8 * size, 0.2 * size),
                Some(other) => panic!("dy {other}"),
            };
            // plotters rotates text about its anchor: `rotate(angle, x, y)`.
            let angle = node.attribute("transform").map_or(0.0, |t| {
                let inner = t
                    .strip_prefix("rotate(")
                    .and_then(|t| t.strip_suffix(')'))
                    .unwrap_or_else(|| panic!("transform {t}"));
                let n: Vec<f64> = inner
                    .split(',')
                    .map(|v| v.trim().parse().expect("a rotate number"))
                    .collect();
                assert_eq!(n[1..], [x, y], "rotation about another point: {t}");
                n[0]
            });
            let (sin, cos) = f64::to_radians(angle).sin_cos();
            let corners = [(left, top), (right, top), (left, bottom), (right, bottom)]
                .map(|(dx, dy)| (x + dx * cos - dy * sin, y + dx * sin + dy * cos));
            let xs = corners.map(|c| c.0);
            let ys = corners.map(|c| c.1);
            TextBox {
                text,
                left: xs.into_iter().fold(f64::MAX, f64::min),
                right: xs.into_iter().fold(f64::MIN, f64::max),
                top: ys.into_iter().fold(f64::MAX, f64::min),
                bottom: ys.into_iter().fold(f64::MIN, f64::max),
            }
        })
        .collect();
    (view, boxes)
}

/// Asserts that every text of an SVG file lies inside its view box (half a pixel of rounding
/// allowed).
fn assert_texts_inside(path: &Path) {
    let ((width, height), boxes) = text_boxes(path);
    assert!(!boxes.is_empty(), "{}: no text", path.display());
    for b in &boxes {
        assert!(
            b.left >= -0.5 && b.top >= -0.5 && b.right <= width + 0.5 && b.bottom <= height + 0.5,
            "{}: {:?} spans x {:.1}..{:.1}, y {:.1}..{:.1}, outside 0..{width} x 0..{height}",
            path.display(),
            b.text,
            b.left,
            b.right,
            b.top,
            b.bottom
        );
    }
}

/// Asserts [`assert_texts_inside`] of every SVG file in `dir`; returns how many there were.
fn assert_texts_inside_every_svg(dir: &Path) -> usize {
    let mut svgs = 0;
    for entry in std::fs::read_dir(dir).expect("a directory") {
        let path = entry.expect("an entry").path();
        if path.extension().is_some_and(|e| e == "svg") {
            assert_texts_inside(&path);
            svgs += 1;
        }
    }
    svgs
}

/// An SVG `<rect>`: left, top, right, bottom.
type Rect = [f64; 4];

/// The bars of a histogram SVG (blue filled rectangles) and its legend's border, if any.
fn bars_and_legend(path: &Path) -> (Vec<Rect>, Option<Rect>) {
    let svg = read(path);
    let document =
        roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let rect = |node: roxmltree::Node| {
        let (x, y) = (number(node, "x"), number(node, "y"));
        [x, y, x + number(node, "width"), y + number(node, "height")]
    };
    let rects: Vec<roxmltree::Node> = document
        .descendants()
        .filter(|n| n.tag_name().name() == "rect")
        .collect();
    let bars = rects
        .iter()
        .filter(|n| n.attribute("fill") == Some("#0000FF"))
        .map(|&n| rect(n))
        .collect();
    let borders: Vec<Rect> = rects
        .iter()
        .filter(|n| n.attribute("fill") == Some("none") && n.attribute("stroke") == Some("#000000"))
        .map(|&n| rect(n))
        .collect();
    assert!(borders.len() <= 1, "{}: {borders:?}", path.display());
    (bars, borders.first().copied())
}

#[test]
fn svgs_parse_and_draw_one_road_per_failing_test() {
    let out = report_of_seeds_3_and_4("svgs");
    // One road surface polygon per failing test (5 + 1), labelled by its test id.
    assert_eq!(count_elements(&out.join("roads.g1.svg"), "polygon"), 6);
    let labels = texts(&out.join("roads.g1.svg"));
    for id in ["r1 #23", "r1 #24", "r1 #28", "r1 #29", "r1 #30", "r2 #5"] {
        assert!(labels.iter().any(|l| l == id), "road {id} not labelled");
    }
    // Fitness of seed 3: 5 failures (plus the legend's marker) drawn as big red dots.
    let fitness = read(&out.join("fitness.g1.r1.svg"));
    assert!(count_elements(&out.join("fitness.g1.r1.svg"), "circle") >= 30);
    assert_eq!(fitness.matches(r#"r="6""#).count(), 6);
    assert!(count_elements(&out.join("bolp.g1.svg"), "rect") > 2);
    assert!(count_elements(&out.join("bolp.g1.svg"), "text") > 2);
}

#[test]
fn trace_picture_draws_path_bolp_and_speed() {
    let out = scratch_dir("trace");
    let text = read(Path::new(&fixture("wogan.seed4.jsonl")));
    let failing = text
        .lines()
        .find(|l| l.contains(r#""outcome":"FAIL""#))
        .expect("a failing test");
    let trace_dir = out.join("traces");
    wogan_ok(&["simulate", "--trace", path_str(&trace_dir)], failing);
    let trace = trace_dir.join("trace.1.jsonl");
    wogan_ok(
        &[
            "report",
            "--trace",
            path_str(&trace),
            "--out",
            path_str(&out),
        ],
        "",
    );
    let svg = out.join("trace.svg");
    assert_eq!(count_elements(&svg, "polygon"), 1);
    // The path is one segment per pair of samples, BOLP and speed one line each.
    let samples = read(&trace)
        .lines()
        .filter(|l| l.contains(r#""type":"sample""#))
        .count();
    assert!(count_elements(&svg, "polyline") >= samples - 1 + 2);
    let picture = read(&svg);
    assert!(picture.contains("BOLP over time") && picture.contains("speed over time"));
    assert_texts_inside(&svg);
}

#[test]
fn every_text_lies_inside_its_picture() {
    // The labels of --vs groups are the longest titles (`A: wogan / ... / decay 0.95 / ...`).
    let out = scratch_dir("inside");
    wogan_ok(
        &[
            "report",
            &fixture("wogan.seed3.jsonl"),
            &fixture("wogan.seed4.jsonl"),
            "--vs",
            &fixture("random.seed4.jsonl"),
            &fixture("random.seed5.jsonl"),
            "--out",
            path_str(&out),
        ],
        "",
    );
    assert_eq!(assert_texts_inside_every_svg(&out), 8);
    // A wrapped title keeps its words, on two lines.
    let titles = texts(&out.join("bolp.g1.svg"));
    assert!(
        titles
            .iter()
            .any(|t| t.starts_with("max BOLP of every test (A: wogan /"))
            && titles.iter().any(|t| t.ends_with("70.0 km/h)")),
        "{titles:?}"
    );
}

#[test]
fn the_bolp_legend_covers_no_bar() {
    // Seed 3 and 4's tallest bar is the first, under the legend in the upper left corner.
    let out = report_of_seeds_3_and_4("legend");
    let (bars, legend) = bars_and_legend(&out.join("bolp.g1.svg"));
    let legend = legend.expect("a legend");
    assert!(bars.len() > 2);
    for bar in &bars {
        let apart = bar[2] <= legend[0]
            || legend[2] <= bar[0]
            || bar[3] <= legend[1]
            || legend[3] <= bar[1];
        assert!(apart, "the legend {legend:?} covers the bar {bar:?}");
    }
}

#[test]
fn ten_thousand_failing_roads_make_small_readable_pictures() {
    let out = scratch_dir("crowded");
    let run = out.join("crowded.jsonl");
    write_synthetic_run(&run, 0.1, &crowded_tests());
    let report = |name: &str| {
        let dir = out.join(name);
        wogan_ok(&["report", path_str(&run), "--out", path_str(&dir)], "");
        dir
    };
    let first = report("first");
    let roads = first.join("roads.g1.svg");
    let size = std::fs::metadata(&roads).expect("roads.g1.svg").len();
    assert!(size < 2_000_000, "roads.g1.svg is {size} bytes");
    assert_eq!(count_elements(&roads, "polygon"), 500);
    let labels = texts(&roads);
    assert!(
        labels
            .iter()
            .any(|t| t.contains("500 of 10,000 roads drawn")),
        "{labels:?}"
    );
    assert!(
        !labels.iter().any(|t| t.starts_with('#')),
        "roads labelled on a crowded map: {labels:?}"
    );
    // The sample is seeded: the same run gives the same picture.
    let second = report("second");
    assert!(
        read(&roads) == read(&second.join("roads.g1.svg")),
        "two reports of one run drew different roads"
    );

    // At threshold 0.10 the histogram's axis ends at 0.2, in bins of 0.01: the failing tests'
    // 0.10 to 0.14 fill 4 bars, the passing ones' 0 to 0.10 another 10.
    let bolp = first.join("bolp.g1.svg");
    let (bars, legend) = bars_and_legend(&bolp);
    assert_eq!(bars.len(), 14, "{bars:?}");
    let ticks: Vec<f64> = texts(&bolp)
        .iter()
        .filter(|t| t.contains('.'))
        .filter_map(|t| t.parse().ok())
        .collect();
    let last = ticks.iter().copied().fold(0.0, f64::max);
    assert!(last > 0.15 && last <= 0.2 + 1e-9, "x axis labels {ticks:?}");
    let legend = legend.expect("a legend");
    assert!(
        bars.iter().all(|bar| bar[1] >= legend[3]),
        "the legend {legend:?} covers a bar"
    );
    assert_eq!(assert_texts_inside_every_svg(&first), 3);
}

#[test]
fn road_labels_do_not_pile_up() {
    // Twenty failing roads that all end in one place.
    let out = scratch_dir("labels");
    let run = out.join("one-end.jsonl");
    let tests: Vec<SyntheticTest> = (0..20)
        .map(|_| SyntheticTest {
            curvature: vec![0.03; 5],
            max_bolp: 0.12,
            failed: true,
            exit: None,
        })
        .collect();
    write_synthetic_run(&run, 0.1, &tests);
    wogan_ok(&["report", path_str(&run), "--out", path_str(&out)], "");
    let roads = out.join("roads.g1.svg");
    let (_, boxes) = text_boxes(&roads);
    let labels: Vec<&TextBox> = boxes.iter().filter(|b| b.text.starts_with('#')).collect();
    assert!(labels.len() >= 5, "{labels:?}");
    for (i, a) in labels.iter().enumerate() {
        for b in &labels[i + 1..] {
            assert!(!a.overlaps(b), "{a:?} overlaps {b:?}");
        }
    }
    assert_texts_inside(&roads);
}
