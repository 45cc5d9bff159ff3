//! End-to-end tests of `wogan report` and `wogan export` on small committed fixture runs
//! (tests/fixtures: two WOGAN runs, seeds 3 and 4, 5 and 1 failures; two random runs, seeds 4 and
//! 5, 2 failures each; 30 tests each, made with `wogan run --max-tests 30 --seed N`).

use crate::common::{scratch_dir, wogan, wogan_ok};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> String {
    format!("{}/../../tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn path_str(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

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

/// Reports the WOGAN fixture runs of seeds 3 and 4 into a fresh scratch directory `name`.
fn report_of_seeds_3_and_4(name: &str) -> PathBuf {
    let out = scratch_dir(name);
    wogan_ok(
        &[
            "report",
            &fixture("wogan.seed3.jsonl"),
            &fixture("wogan.seed4.jsonl"),
            "--out",
            path_str(&out),
        ],
        "",
    );
    out
}

#[test]
fn report_numbers_match_hand_computation() {
    let out = report_of_seeds_3_and_4("numbers");
    let report = read(&out.join("report.md"));
    assert_eq!(report.matches("## Group ").count(), 1, "{report}");
    assert!(
        report
            .contains("## Group 1: wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob 0.85 / 70.0 km/h"),
        "{report}"
    );
    assert!(
        report.contains("| tests executed | 30.000 | 0.000 | 2 |"),
        "{report}"
    );
    // Failures 5 and 1: mean 3, SD sqrt((4 + 4) / 1) = 2.828.
    assert!(
        report.contains("| failures | 3.000 | 2.828 | 2 |"),
        "{report}"
    );
    // 6 failures of 60 tests.
    assert!(
        report.contains("| failure rate (all tests pooled) | 0.100 |"),
        "{report}"
    );
    // Only seed 3 has two or more failures; its summary record says diversity 3.2861...
    assert!(report.contains("| 3.286 | – | 1 |"), "{report}");
    // Seed 3 fails first at test 23, then 4 of the 7 tests after it; seed 4 at test 5, then none
    // of 25: means 14 and 0.286, SDs sqrt(2 * 9^2) = 12.728 and sqrt(2 * 0.2857^2) = 0.404.
    assert!(
        report.contains(
            "| first failing test (a run without one: tests executed + 1) | 14.000 | 12.728 | 2 |"
        ),
        "{report}"
    );
    assert!(
        report.contains("| failure rate after the first failing test (runs with tests after one) | 0.286 | 0.404 | 2 |"),
        "{report}"
    );
    // DIR_COV of the six failing tests: 9, 8, 5, 6, 6 (seed 3) and 11 (seed 4) of 26.
    assert!(
        report.contains("DIR_COV values hit: 5/26, 6/26, 8/26, 9/26, 11/26."),
        "{report}"
    );
    // 5/26 = 0.192, median of 5, 6, 6, 8, 9, 11 is 7/26 = 0.269, 11/26 = 0.423.
    assert!(
        report.contains("| DIR_COV (buckets of 1/26) | 5 | 0.192 | 0.269 | 0.423 |"),
        "{report}"
    );
    for link in [
        "roads.g1.svg",
        "bolp.g1.svg",
        "fitness.g1.r1.svg",
        "fitness.g1.r2.svg",
    ] {
        assert!(report.contains(&format!("({link})")), "{link} not linked");
        assert!(out.join(link).exists(), "{link} not written");
    }
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
fn groups_by_configuration_and_compares_with_vs() {
    let out = scratch_dir("groups");
    let runs = [
        fixture("wogan.seed3.jsonl"),
        fixture("random.seed4.jsonl"),
        fixture("wogan.seed4.jsonl"),
    ];
    let mut args: Vec<&str> = vec!["report"];
    args.extend(runs.iter().map(String::as_str));
    args.extend(["--out", path_str(&out)]);
    wogan_ok(&args, "");
    let report = read(&out.join("report.md"));
    assert_eq!(report.matches("## Group ").count(), 2, "{report}");
    assert!(report.contains("## Group 1: random /"), "{report}");
    assert!(report.contains("## Group 2: wogan /"), "{report}");

    let out = scratch_dir("vs");
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
    let report = read(&out.join("report.md"));
    // Failures [5, 1] vs [2, 2]: midranks 4, 1 vs 2.5, 2.5; R1 = 5, U1 = 2; every split of the
    // ranks has P(R ≤ 5) = P(R ≥ 5) = 4/6, so p = 1.
    assert!(
        report.contains(
            "| failures per run | 3.000 (2.828) n=2 | 2.000 (0.000) n=2 | 2 | 1.0000 | exact |"
        ),
        "{report}"
    );
    assert!(report.contains("| diversity |"), "{report}");
    // First failing tests [23, 5] vs [5, 6]: midranks 4, 1.5 vs 1.5, 3; R1 = 5.5, U1 = 2.5.
    assert!(
        report.contains(
            "| first failing test (a run without one: tests executed + 1) | 14.000 (12.728) n=2 \
             | 5.500 (0.707) n=2 | 2.5 |"
        ),
        "{report}"
    );
    assert!(out.join("roads.g2.svg").exists());
}

#[test]
fn truncated_run_with_a_bad_line_is_reported_with_status_1() {
    let out = scratch_dir("truncated");
    let text = read(Path::new(&fixture("wogan.seed3.jsonl")));
    let mut lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.contains(r#""type":"summary""#))
        .collect();
    lines.insert(3, "{not json");
    let run = out.join("cut.jsonl");
    std::fs::write(&run, lines.join("\n")).expect("write");
    let output = wogan(&["report", path_str(&run), "--out", path_str(&out)], "");
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cut.jsonl:4: not JSON"), "{stderr}");
    let report = read(&out.join("report.md"));
    assert!(
        report.contains("(truncated: no summary record)"),
        "{report}"
    );
    assert!(report.contains("| failures | 5.000 | – | 1 |"), "{report}");
}

#[test]
fn bad_usage_gives_status_2() {
    let out = scratch_dir("usage");
    let output = wogan(&["report", "--out", path_str(&out)], "");
    assert_eq!(output.status.code(), Some(2));
    let output = wogan(
        &[
            "report",
            path_str(&out.join("missing.jsonl")),
            "--out",
            path_str(&out),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(2));
    let output = wogan(
        &[
            "export",
            "--format",
            "csv",
            &fixture("wogan.seed3.jsonl"),
            path_str(&out),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn export_writes_the_competition_layout_and_round_trips_through_validate() {
    let out = scratch_dir("export");
    wogan_ok(
        &[
            "export",
            "--format",
            "sbst",
            &fixture("wogan.seed3.jsonl"),
            path_str(&out),
        ],
        "",
    );
    let csv = read(&out.join("generation_stats.csv"));
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(
        rows[0],
        "test_generated,test_valid,test_invalid,test_passed,test_failed,test_in_error,\
         real_time_generation,real_time_execution,simulated_time_execution"
    );
    let row: Vec<&str> = rows[1].split(',').collect();
    // The summary: 30 executed, 8 invalid candidates; 25 PASS, 5 FAIL.
    assert_eq!(row[..6], ["38", "30", "8", "25", "5", "0"]);
    assert!(
        row[6..]
            .iter()
            .all(|v| v.parse::<f64>().is_ok_and(|s| s > 0.0)),
        "{row:?}"
    );

    let mut objects = Vec::new();
    for id in 1..=30 {
        let text = read(&out.join(format!("test.{id:04}.json")));
        let object: Value = serde_json::from_str(&text).expect("a test object");
        assert_eq!(object["id"], id);
        assert!(object.get("execution_data").is_none());
        for key in [
            "road_points",
            "interpolated_points",
            "validation_message",
            "description",
        ] {
            assert!(object.get(key).is_some(), "{key} missing");
        }
        assert!(["PASS", "FAIL", "ERROR"].contains(&object["test_outcome"].as_str().unwrap_or("")));
        for key in ["MAX_CURV", "DIR_COV", "STD_SA", "MEAN_LP", "MAX_LP"] {
            assert!(object["features"][key].is_number(), "{key} missing");
        }
        objects.push(object);
    }
    assert!(!out.join("test.0031.json").exists());
    let input: Vec<String> = objects.iter().map(Value::to_string).collect();
    let output = wogan_ok(&["validate"], &input.join("\n"));
    let verdicts: Vec<Value> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a verdict"))
        .collect();
    assert_eq!(verdicts.len(), objects.len());
    for (object, verdict) in objects.iter().zip(&verdicts) {
        assert_eq!(verdict["valid"], object["is_valid"], "{object}");
    }
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
}

#[test]
fn export_of_a_truncated_run_sums_the_test_records() {
    let out = scratch_dir("export-truncated");
    let text = read(Path::new(&fixture("wogan.seed3.jsonl")));
    let mut lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.contains(r#""type":"summary""#))
        .collect();
    lines.push(r#"{"type":"test","id":"x"}"#);
    let run = out.join("cut.jsonl");
    std::fs::write(&run, lines.join("\n")).expect("write");
    let dir = out.join("sbst");
    let output = wogan(
        &["export", "--format", "sbst", path_str(&run), path_str(&dir)],
        "",
    );
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cut.jsonl:40: bad test record"), "{stderr}");
    let csv = read(&dir.join("generation_stats.csv"));
    let row: Vec<&str> = csv.lines().nth(1).expect("a row").split(',').collect();
    // Without a summary, the invalid candidates are summed over the test records (8).
    assert_eq!(row[..6], ["38", "30", "8", "25", "5", "0"]);
    assert!(dir.join("test.0030.json").exists());
}
