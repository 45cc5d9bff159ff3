//! `wogan report --html`: the page holds the runs, the failing roads and the traces asked for,
//! within its size bound, and opens in a real browser where a click opens a road.

use super::*;
use crate::common::{scratch_dir, wogan, wogan_ok};
use serde_json::Value;
use std::path::Path;

/// The bound `wogan report --html` keeps its page within (docs/reference.md): 64 KiB around the
/// data, 1 KiB per failing road and 8 bytes per metre of it, 16 KiB per road driven again, and
/// report.md's pictures inlined (base64, 4/3 of their size). `metres`: the failing roads' length.
pub fn html_size_bound(dir: &Path, failing: usize, metres: u64, traced: usize) -> u64 {
    let pictures: u64 = std::fs::read_dir(dir)
        .expect("the report's folder")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "svg"))
        .map(|e| e.metadata().expect("metadata").len())
        .sum();
    64 * 1024
        + 1024 * failing as u64
        + 8 * metres
        + 16 * 1024 * traced as u64
        + pictures.div_ceil(3) * 4
}

#[test]
fn ten_thousand_failing_roads_make_a_page_within_its_size_bound() {
    let out = scratch_dir("crowded-html");
    let run = out.join("crowded.jsonl");
    write_synthetic_run(&run, 0.1, &crowded_tests());
    let dir = out.join("report");
    wogan_ok(
        &["report", path_str(&run), "--out", path_str(&dir), "--html"],
        "",
    );
    let page = read(&dir.join("report.html"));
    assert_eq!(page.matches("<tr id=\"road-").count(), 10_000);
    let size = page.len() as u64;
    // Every synthetic road is 75 m: a 15 m step per curvature value.
    let bound = html_size_bound(&dir, 10_000, 10_000 * 75, 0);
    assert!(
        size <= bound,
        "report.html is {size} bytes, over its bound {bound}"
    );
    // Self-contained: nothing is loaded from elsewhere.
    for reference in [
        "src=\"http",
        "href=\"http",
        "<link",
        "src=\"roads",
        "@import",
    ] {
        assert!(
            !page.contains(reference),
            "the page refers outside itself: {reference}"
        );
    }
}

#[test]
fn html_page_holds_the_runs_the_failing_roads_and_the_traces_asked_for() {
    let dir = scratch_dir("html-page");
    let (run_a, run_b) = (dir.join("wogan.jsonl"), dir.join("random.jsonl"));
    seeded_run(&run_a, &[]);
    seeded_run(&run_b, &["--algorithm", "random"]);
    let failures = |run: &Path| -> usize {
        let text = read(run);
        let summary: Value =
            serde_json::from_str(text.lines().last().expect("a summary")).expect("JSON");
        summary["failed"].as_u64().expect("failed") as usize
    };
    let failing = failures(&run_a) + failures(&run_b);
    assert!(failing >= 3, "{failing} failures: too few to test the page");
    let (run_a, run_b) = (path_str(&run_a).to_owned(), path_str(&run_b).to_owned());
    let out = dir.join("report");
    let output = wogan_ok(
        &[
            "report",
            &run_a,
            "--vs",
            &run_b,
            "--out",
            path_str(&out),
            "--html",
            "--traces",
            "2",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("report.html"), "{stderr}");
    let page = read(&out.join("report.html"));
    let markdown = read(&out.join("report.md"));
    // One row per failure; the two worst driven again with the recorded driver.
    assert_eq!(page.matches("<tr id=\"road-").count(), failing);
    let data_start =
        page.find("id=\"road-data\">").expect("the road data") + "id=\"road-data\">".len();
    let data_end = data_start + page[data_start..].find("</script>").expect("its end");
    let data: Value = serde_json::from_str(&page[data_start..data_end]).expect("JSON");
    assert_eq!(
        data["groups"].as_array().map(Vec::len),
        Some(2),
        "{}",
        data["groups"]
    );
    let roads = data["roads"].as_array().expect("the roads");
    assert_eq!(roads.len(), failing);
    assert!(roads
        .iter()
        .all(|r| r["line"].as_array().is_some_and(|l| l.len() > 10)));
    assert!(roads
        .iter()
        .all(|r| r["exit"].as_array().is_some_and(|e| e.len() == 2)));
    let traced: Vec<&Value> = roads.iter().filter(|r| r.get("trace").is_some()).collect();
    assert_eq!(traced.len(), 2, "{roads:?}");
    for road in &traced {
        let trace = &road["trace"];
        assert_eq!(trace["driver"], "beamng-ai-proxy");
        let samples = trace["t"].as_array().expect("times").len();
        assert!(samples > 10 && samples <= 400, "{samples} samples");
        assert_eq!(trace["xy"].as_array().expect("places").len(), samples);
        // Made by this binary and driven again with the settings its header records: as recorded.
        assert_eq!(trace["outcome"], "FAIL", "{trace}");
    }
    // The runs' table, the Mann–Whitney comparison and the pictures, inlined.
    assert!(page.contains("wogan.jsonl") && page.contains("random.jsonl"));
    assert!(markdown.contains("Comparison: A vs B"));
    assert!(
        page.contains("<h2>Comparison: A vs B</h2>") && page.contains("<th>p (two-sided)</th>")
    );
    let pictures = page.matches("src=\"data:image/svg+xml;base64,").count();
    assert_eq!(pictures, markdown.matches("![").count());
    assert!(pictures >= 4, "{pictures} pictures");
    // wogan's roads are about 76 m (five 15 m steps).
    assert!(page.len() as u64 <= html_size_bound(&out, failing, failing as u64 * 80, 2));

    // A run of an older layout (the driver's tuning in `sim.beamng_ai`) is read as a config file
    // of that layout is: its road is driven again with the tuning it recorded.
    let old = fixture("wogan.seed3.jsonl");
    let old_out = dir.join("old");
    let output = wogan_ok(
        &[
            "report",
            &old,
            "--out",
            path_str(&old_out),
            "--html",
            "--traces",
            "1",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("not driven again"), "{stderr}");
    let page = read(&old_out.join("report.html"));
    assert!(!page.contains("roads not driven again"));
    assert_eq!(page.matches("\"trace\":{").count(), 1);

    // --traces needs --html, and --html needs --out.
    let refused = wogan(
        &["report", &run_a, "--out", path_str(&out), "--traces", "2"],
        "",
    );
    assert_eq!(refused.status.code(), Some(2));
    let refused = wogan(&["report", &old, "--html", "--table"], "");
    assert_eq!(refused.status.code(), Some(2));
}

/// Whether the system's chromium can be run: absent, the browser test says so and checks nothing,
/// unless WOGAN_REQUIRE_CHROMIUM is set (CI sets it, after installing Debian's chromium), when it
/// fails.
pub fn chromium_present() -> bool {
    let present = std::process::Command::new("chromium")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !present {
        assert!(
            std::env::var_os("WOGAN_REQUIRE_CHROMIUM").is_none(),
            "WOGAN_REQUIRE_CHROMIUM is set and chromium cannot be run (apt-get install chromium)"
        );
        eprintln!("chromium is not installed: the browser check is skipped");
    }
    present
}

#[test]
fn html_report_opens_in_chromium_and_a_click_opens_a_road() {
    if !chromium_present() {
        return;
    }
    let dir = scratch_dir("html-browser");
    let run = dir.join("run.jsonl");
    seeded_run(&run, &[]);
    let out = dir.join("report");
    wogan_ok(
        &[
            "report",
            path_str(&run),
            "--out",
            path_str(&out),
            "--html",
            "--traces",
            "3",
        ],
        "",
    );
    // The screenshot is CI's artifact: target/ci-artifacts/report-html.png.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let screenshot = root.join("target/ci-artifacts/report-html.png");
    let check = std::process::Command::new("python3")
        .arg(root.join("scripts/ci/browser_check.py"))
        .args(["--page", path_str(&out.join("report.html"))])
        .args(["--run", path_str(&run)])
        .args(["--screenshot", path_str(&screenshot)])
        .arg("--expect-trace")
        .output()
        .expect("python3 runs scripts/ci/browser_check.py");
    let stdout = String::from_utf8_lossy(&check.stdout);
    let stderr = String::from_utf8_lossy(&check.stderr);
    assert!(check.status.success(), "browser check: {stdout}\n{stderr}");
    for line in [
        "failing-road rows, as the summary counts",
        "the max BOLP column sorts",
        "a click opens the detail of run.jsonl, test",
        "with the car's path driven again",
        "no console error, no exception, nothing fetched",
    ] {
        assert!(stdout.contains(line), "{line:?} not in {stdout}");
    }
    let png = std::fs::read(&screenshot).expect("the screenshot");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 10_000,
        "{} bytes",
        png.len()
    );
}
