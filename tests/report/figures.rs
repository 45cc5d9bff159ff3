//! `wogan report`'s figures: the measures against hand computation, grouping by configuration
//! and conditions, `--vs` and its tests, `--table`, distinct failures, a result folder read as
//! its run, and bad input.

use super::*;
use crate::common::{scratch_dir, wogan, wogan_ok};
use serde_json::json;
use std::path::Path;

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
    // Only seed 3 has two or more failures (5). The authors' measure over them (stgem's
    // `euclidean_diversity` on the pipeline's interpolation of their roads) is 3.2755; the
    // fixture's summary record, written before wogan computed it as they do, says 3.2861.
    assert!(report.contains("| 3.276 | – | 1 |"), "{report}");
    // No two of the five point more than half a turn apart anywhere, so taking each difference
    // as the angle between the directions changes nothing.
    assert!(
        report.contains("the angle between the directions) | 3.276 | – | 1 |"),
        "{report}"
    );
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
fn runs_of_other_drivers_tolerances_or_speed_limits_are_grouped_apart() {
    let out = scratch_dir("conditions");
    let seed4 = "wogan.seed4.jsonl";
    let runs = [
        PathBuf::from(fixture("wogan.seed3.jsonl")),
        variant(
            &out,
            seed4,
            "oob.jsonl",
            r#""oob_tolerance":0.85"#,
            r#""oob_tolerance":0.5"#,
        ),
        variant(
            &out,
            seed4,
            "speed.jsonl",
            r#""speed_limit_kmh":70.0"#,
            r#""speed_limit_kmh":50.0"#,
        ),
        variant(
            &out,
            seed4,
            "driver.jsonl",
            r#""oracle":"beamng-ai-proxy""#,
            r#""oracle":"dave2-proxy""#,
        ),
        // The same speed limit written as a whole number is the same condition.
        variant(
            &out,
            seed4,
            "whole.jsonl",
            r#""speed_limit_kmh":70.0"#,
            r#""speed_limit_kmh":70"#,
        ),
    ];
    let mut args = vec!["report"];
    args.extend(runs.iter().map(|p| path_str(p)));
    args.extend(["--out", path_str(&out)]);
    wogan_ok(&args, "");
    let report = read(&out.join("report.md"));
    assert!(report.contains("5 run(s) in 4 group(s)."), "{report}");
    for label in [
        "wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob 0.85 / 70.0 km/h",
        "wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob 0.5 / 70.0 km/h",
        "wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob 0.85 / 50.0 km/h",
        "wogan / dave2-proxy / fitness bolp / decay 0.95 / oob 0.85 / 70.0 km/h",
    ] {
        assert_eq!(
            report.matches(&format!(": {label}\n")).count(),
            1,
            "{label}: {report}"
        );
    }
    let group = report
        .split("## Group ")
        .find(|g| g.contains("oob 0.85 / 70.0 km/h") && g.contains("beamng"))
        .expect("the seed-3 group");
    assert!(
        group.contains("wogan.seed3.jsonl") && group.contains("whole.jsonl"),
        "{group}"
    );
}

#[test]
fn vs_refuses_a_group_that_mixes_conditions() {
    let out = scratch_dir("vs-mixed");
    let seed3 = fixture("wogan.seed3.jsonl");
    let random4 = fixture("random.seed4.jsonl");
    let random5 = fixture("random.seed5.jsonl");
    let cases = [
        (
            "oob",
            r#""oob_tolerance":0.85"#,
            r#""oob_tolerance":0.5"#,
            "oob 0.85",
            "oob 0.5",
        ),
        (
            "speed",
            r#""speed_limit_kmh":70.0"#,
            r#""speed_limit_kmh":50.0"#,
            "70.0 km/h",
            "50.0 km/h",
        ),
        (
            "driver",
            r#""oracle":"beamng-ai-proxy""#,
            r#""oracle":"dave2-proxy""#,
            "driver beamng-ai-proxy",
            "driver dave2-proxy",
        ),
    ];
    for (what, from, to, usual, odd_condition) in cases {
        let odd = variant(
            &out,
            "wogan.seed4.jsonl",
            &format!("{what}.jsonl"),
            from,
            to,
        );
        let report_dir = out.join(what);
        // The odd run in group A beside seed 3, then in group B beside the random seed 4.
        let in_a = [
            seed3.as_str(),
            path_str(&odd),
            "--vs",
            random4.as_str(),
            random5.as_str(),
        ];
        let in_b = [seed3.as_str(), "--vs", random4.as_str(), path_str(&odd)];
        for (group, runs, other) in [("A", &in_a[..], &seed3), ("B", &in_b[..], &random4)] {
            let mut args = vec!["report"];
            args.extend(runs);
            args.extend(["--out", path_str(&report_dir)]);
            let output = wogan(&args, "");
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert_eq!(output.status.code(), Some(2), "{what} in {group}: {stderr}");
            let mixes = format!("group {group} mixes");
            for needle in [
                mixes.as_str(),
                path_str(&odd),
                other.as_str(),
                usual,
                odd_condition,
            ] {
                assert!(
                    stderr.contains(needle),
                    "{what} in {group}: no {needle}: {stderr}"
                );
            }
            assert!(!report_dir.join("report.md").exists());
        }
    }
}

#[test]
fn a_file_given_twice_counts_once() {
    let out = scratch_dir("twice");
    let seed3 = fixture("wogan.seed3.jsonl");
    let seed4 = fixture("wogan.seed4.jsonl");
    let random4 = fixture("random.seed4.jsonl");
    // The same file under another spelling.
    let again = format!("{}/../fixtures/wogan.seed3.jsonl", fixture(""));
    let output = wogan_ok(
        &["report", &seed3, &again, &seed4, "--out", path_str(&out)],
        "",
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(&again) && stderr.contains("counts once"),
        "{stderr}"
    );
    let report = read(&out.join("report.md"));
    assert!(report.contains("2 run(s) in 1 group(s)."), "{report}");
    assert!(
        report.contains("| failures | 3.000 | 2.828 | 2 |"),
        "{report}"
    );

    let output = wogan_ok(
        &[
            "report",
            &seed3,
            &seed4,
            "--vs",
            &random4,
            &random4,
            "--out",
            path_str(&out),
        ],
        "",
    );
    assert!(String::from_utf8_lossy(&output.stderr).contains("counts once"));
    let report = read(&out.join("report.md"));
    assert!(
        report.contains("| failures per run | 3.000 (2.828) n=2 | 2.000 (–) n=1 |"),
        "{report}"
    );

    // A run cannot be on both sides of a comparison.
    let output = wogan(
        &[
            "report",
            &seed3,
            &seed4,
            "--vs",
            &random4,
            &again,
            "--out",
            path_str(&out),
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&again) && stderr.contains(&seed3) && stderr.contains("both sides"),
        "{stderr}"
    );
}

/// The data rows of the Markdown table(s) `wogan report --table` printed.
fn table_rows(output: &std::process::Output) -> Vec<Vec<String>> {
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter(|l| {
            l.starts_with("| ") && !l.starts_with("| measure") && !l.starts_with("| configuration")
        })
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_owned())
                .collect()
        })
        .collect()
}

#[test]
fn table_prints_one_row_per_configuration_and_writes_no_files() {
    let dir = scratch_dir("report-table");
    let runs = [
        fixture("wogan.seed3.jsonl"),
        fixture("wogan.seed4.jsonl"),
        fixture("random.seed4.jsonl"),
        fixture("random.seed5.jsonl"),
    ];
    let mut args: Vec<&str> = vec!["report", "--table"];
    args.extend(runs.iter().map(String::as_str));
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_wogan"))
        .args(&args)
        .current_dir(&dir)
        .output()
        .expect("wogan runs");
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let rows = table_rows(&output);
    assert_eq!(rows.len(), 2, "{rows:?}");
    // Grouped as without --table: random first (its key sorts first), then WOGAN.
    assert!(
        rows[0][0].starts_with("random / beamng-ai-proxy"),
        "{rows:?}"
    );
    assert!(
        rows[1][0].starts_with("wogan / beamng-ai-proxy"),
        "{rows:?}"
    );
    // Two runs each; WOGAN's 5 and 1 failures: median 3, mean 3. Random's 2 and 2.
    assert_eq!(rows[1][1], "2");
    assert_eq!(rows[1][2], "3 (3)");
    assert_eq!(rows[0][2], "2 (2)");
    // Random search chooses no test after a random phase: no cost per candidate.
    assert_eq!(rows[0][8], "–");
    assert_ne!(rows[1][8], "–");
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "--table writes no file"
    );
}

#[test]
fn table_with_vs_gives_every_measure_with_its_p_value() {
    let output = wogan_ok(
        &[
            "report",
            "--table",
            &fixture("wogan.seed3.jsonl"),
            &fixture("wogan.seed4.jsonl"),
            "--vs",
            &fixture("random.seed4.jsonl"),
            &fixture("random.seed5.jsonl"),
        ],
        "",
    );
    let rows = table_rows(&output);
    let failures = rows
        .iter()
        .find(|r| r[0] == "failures per run")
        .expect("a failures row");
    assert_eq!(failures[1], "3.000 (2.828) n=2");
    assert_eq!(failures[2], "2.000 (0.000) n=2");
    assert_eq!(failures[4], "1.0000");
    // The competition's measures are all there, not only those report.md compares.
    for measure in [
        "effectiveness (valid / generated)",
        "lane exits over the centre line (left)",
    ] {
        assert!(rows.iter().any(|r| r[0] == measure), "{measure}: {rows:?}");
    }
}

#[test]
fn table_and_out_are_one_or_the_other() {
    let dir = scratch_dir("report-table-out");
    let output = wogan(
        &[
            "report",
            "--table",
            &fixture("wogan.seed3.jsonl"),
            "--out",
            path_str(&dir),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(2));
    let output = wogan(&["report", &fixture("wogan.seed3.jsonl")], "");
    assert_eq!(output.status.code(), Some(2), "neither --out nor --table");
}

/// A test on the road of `curvature`: failing with the car leaving 2 m right of the road's
/// fourth point, or passing.
fn exit_test(curvature: &[f64], failed: bool) -> SyntheticTest {
    let points = road_points(curvature);
    let [x, y] = points[3];
    let [px, py] = points[2];
    let length = (x - px).hypot(y - py);
    // Right of the direction of travel from the third point to the fourth.
    let exit = [x + 2.0 * (y - py) / length, y - 2.0 * (x - px) / length];
    SyntheticTest {
        curvature: curvature.to_vec(),
        max_bolp: if failed { 0.5 } else { 0.05 },
        failed,
        exit: failed.then_some(exit),
    }
}

#[test]
fn distinct_failures_count_roads_apart_around_their_exits() {
    let out = scratch_dir("distinct");
    // A left bend failed twice at the same place (one failure), its mirror (another), a gentle
    // bend (a third) and a passing road (none).
    let left = [0.0, 0.06, 0.06, 0.0, 0.0];
    let right = left.map(|c: f64| -c);
    let gentle = [0.0, 0.01, 0.01, 0.0, 0.0];
    let three = out.join("three.jsonl");
    write_synthetic_run(
        &three,
        0.1,
        &[
            exit_test(&left, true),
            exit_test(&gentle, false),
            exit_test(&left, true),
            exit_test(&right, true),
            exit_test(&gentle, true),
        ],
    );
    let one = out.join("one.jsonl");
    write_synthetic_run(
        &one,
        0.1,
        &[exit_test(&right, true), exit_test(&right, true)],
    );
    wogan_ok(
        &[
            "report",
            path_str(&three),
            path_str(&one),
            "--out",
            path_str(&out),
        ],
        "",
    );
    let report = read(&out.join("report.md"));
    // Runs of 3 and 1 distinct failures: mean 2, SD sqrt(2).
    assert!(
        report.contains(
            "| distinct failures (failing roads ≥ δ apart around the lane exit; runs that record \
             where the car left its lane) | 2.000 | 1.414 | 2 |"
        ),
        "{report}"
    );
    // Beside the paper's diversity, in the table of configurations.
    let table = wogan_ok(&["report", path_str(&three), path_str(&one), "--table"], "");
    let table = String::from_utf8_lossy(&table.stdout);
    assert!(
        table.contains("| failing roads | distinct failures | diversity |"),
        "{table}"
    );
    assert!(table.contains("| 2 | 3 (3) | 2 (2) | "), "{table}");
    // A run written before records said where the car left: no count, and the table says of
    // how many runs the figure is.
    let table = wogan_ok(
        &[
            "report",
            path_str(&three),
            &fixture("wogan.seed3.jsonl"),
            "--table",
        ],
        "",
    );
    let table = String::from_utf8_lossy(&table.stdout);
    assert!(table.contains("| 1 | 4 (4) | 3 (3) | "), "{table}");
    assert!(table.contains("| 1 | 5 (5) | – | "), "{table}");
    // Compared: 3 against 1.
    let vs = wogan_ok(
        &[
            "report",
            path_str(&three),
            "--vs",
            path_str(&one),
            "--table",
        ],
        "",
    );
    let vs = String::from_utf8_lossy(&vs.stdout);
    assert!(
        vs.contains("| distinct failures per run | 3.000 (–) n=1 | 1.000 (–) n=1 |"),
        "{vs}"
    );
}

/// The cells of the `--vs` table's row for `measure`: A's and B's `mean (SD) n=N`.
fn vs_cells(output: &std::process::Output, measure: &str) -> (String, String) {
    let rows = table_rows(output);
    let row = rows
        .iter()
        .find(|r| r[0] == measure)
        .unwrap_or_else(|| panic!("no row {measure:?} in {rows:?}"));
    (row[1].clone(), row[2].clone())
}

/// A run of this build and its `wogan export`, and both read by `wogan report`: the result folder
/// reader and the run file reader give the same failures, distinct failures, diversity and lane
/// exits. (100 tests at seed 3: 8 failures of 3 distinct kinds with this build; 30 tests fail none.)
#[test]
fn a_result_folder_reads_as_the_run_it_was_exported_from() {
    let out = scratch_dir("report-result-folder");
    let run = out.join("run.jsonl");
    let args = ["run", "--quiet", "--max-tests", "100", "--seed", "3"];
    wogan_ok(&[&args[..], &["--out", path_str(&run)]].concat(), "");
    let export = out.join("export");
    wogan_ok(
        &[
            "export",
            "--format",
            "sbst",
            path_str(&run),
            path_str(&export),
        ],
        "",
    );
    let vs = wogan_ok(
        &[
            "report",
            path_str(&export),
            "--vs",
            path_str(&run),
            "--table",
        ],
        "",
    );
    let stdout = String::from_utf8_lossy(&vs.stdout);
    // No file says the export's driver or tolerance: they read `?`, the algorithm is the folder.
    assert!(
        stdout.contains("- A: sbst:export / ? / fitness - / oob ? / ? km/h"),
        "{stdout}"
    );
    let failures = vs_cells(&vs, "failures per run");
    assert_eq!(failures.0, failures.1);
    assert_ne!(failures.0, "0.000 (–) n=1", "the run must fail some tests");
    let distinct = vs_cells(&vs, "distinct failures per run");
    assert_eq!(distinct.0, distinct.1);
    assert_ne!(distinct.0, "0.000 (–) n=1");
    for measure in [
        "diversity",
        "angle diversity",
        "first failing test (a run without one: tests executed + 1)",
        "tests generated (handed to execution)",
        "lane exits over the centre line (left)",
        "lane exits over the road's edge (right)",
    ] {
        let (a, b) = vs_cells(&vs, measure);
        assert_eq!(a, b, "{measure}");
    }

    // The harness's layout: summary.json names the configuration, an invalid test counts as
    // generated, and tests.jsonl beside the tests is not read as a run.
    let peer = out.join("peers/beamng.fake.1");
    std::fs::create_dir_all(&peer).unwrap();
    for id in 1..=100 {
        let from = export.join(format!("test.{id:04}.json"));
        std::fs::copy(&from, peer.join(format!("test.{:04}.json", id + 1))).unwrap();
    }
    let invalid = json!({"id": 1, "is_valid": false, "validation_message": "Not in the map",
        "road_points": [[0.0, 0.0], [-10.0, 0.0]], "interpolated_points": []});
    std::fs::write(peer.join("test.0001.json"), invalid.to_string()).unwrap();
    let summary = json!({"type": "summary", "generator": "fake.generators.FakeGen",
        "oracle": "beamng-ai-proxy", "oob_tolerance": 0.85, "speed_limit": 70, "seed": 1});
    std::fs::write(peer.join("summary.json"), summary.to_string()).unwrap();
    std::fs::write(peer.join("tests.jsonl"), "{\"proposal\": 1}\n").unwrap();
    let peers = out.join("peers");
    let vs = wogan(
        &[
            "report",
            path_str(&peers),
            "--vs",
            path_str(&run),
            "--table",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&vs.stderr);
    assert_eq!(vs.status.code(), Some(0), "{stderr}");
    assert!(
        !stderr.contains("note: group A is of"),
        "same conditions: {stderr}"
    );
    let stdout = String::from_utf8_lossy(&vs.stdout);
    assert!(
        stdout.contains("- A: sbst:FakeGen / beamng-ai-proxy / fitness - / oob 0.85 / 70.0 km/h"),
        "{stdout}"
    );
    assert_eq!(vs_cells(&vs, "distinct failures per run"), distinct);
    // The invalid test was generated, as the pipeline counts it, and not rejected by wogan.
    let generated = vs_cells(&vs, "tests generated (handed to execution)");
    assert_eq!(generated.0, "101.000 (–) n=1");
    let effectiveness = vs_cells(&vs, "effectiveness (valid / generated)");
    assert_eq!(effectiveness.0, "0.990 (–) n=1");
    let invalid = vs_cells(&vs, "invalid candidates rejected before proposing");
    assert_eq!(invalid.0, "0.000 (–) n=1");

    // A run its generator's exception ended is named under the table with the exception, and
    // the exit status says an input did not end normally; its tests still count.
    let crashed = json!({"type": "summary", "generator": "fake.generators.FakeGen",
        "oracle": "beamng-ai-proxy", "oob_tolerance": 0.85, "speed_limit": 70, "seed": 1,
        "crashed": "pandas.errors.InvalidIndexError: You can only assign a scalar value"});
    std::fs::write(peer.join("summary.json"), crashed.to_string()).unwrap();
    let table = wogan(&["report", path_str(&peer), "--table"], "");
    assert_eq!(table.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&table.stdout);
    assert!(
        stdout.contains(&format!(
            "- {}: failed part-way: the generator crashed: pandas.errors.InvalidIndexError: You \
             can only assign a scalar value",
            peer.display()
        )),
        "{stdout}"
    );
    assert!(
        stdout.contains("| 1 | "),
        "the crashed run still counts: {stdout}"
    );
    std::fs::write(peer.join("summary.json"), summary.to_string()).unwrap();

    // A truncated file and a foreign one: each named with its field, the rest read, exit 1.
    let text = read(&peer.join("test.0004.json"));
    std::fs::write(peer.join("test.0004.json"), &text[..text.len() / 2]).unwrap();
    let foreign = json!({"is_valid": true, "road_points": [[10.0, 10.0], [10.0, 60.0]],
        "test_outcome": "FAIL", "execution_data": [[0.5]]});
    std::fs::write(peer.join("test.0005.json"), foreign.to_string()).unwrap();
    let bad = wogan(&["report", path_str(&peer), "--table"], "");
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("test.0004.json: not JSON"), "{stderr}");
    assert!(
        stderr.contains("test.0005.json: execution_data[0]: oob_percentage: missing"),
        "{stderr}"
    );
    let rows = table_rows(&bad);
    assert_eq!(rows.len(), 1, "{rows:?}");
    // The other tests are read with every failure: the broken files held tests 3 and 4 of the
    // run, before its first failing test.
    let (first, _) = vs_cells(
        &vs,
        "first failing test (a run without one: tests executed + 1)",
    );
    let first: f64 = first.split(' ').next().unwrap().parse().unwrap();
    assert!(first > 5.0, "first failing test {first}");
    let failed = failures.0.trim_end_matches(".000 (–) n=1");
    assert_eq!(rows[0][2], format!("{failed} ({failed})"), "{rows:?}");
}
