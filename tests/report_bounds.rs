//! `wogan report` on runs no `wogan run` writes (issue 74, defects 2, 8, 9 and 22 of the
//! hostile-input report of 2026-11-29): a header's settings are checked as a `--config` file's
//! are and a run out of range is named and not driven again; an executor's run is never driven
//! again by wogan's own driver; records out of their ranges are named by line and not read;
//! options that cannot go together are refused; Ctrl-C ends the report with exit 130.

use crate::common::{scratch_dir, signal_and_wait, spawn, watchdog, wogan};
use crate::report::{fixture, path_str, read};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The records of the committed fixture run (seed 3 of WOGAN: 30 tests, 5 failing).
fn fixture_records() -> Vec<Value> {
    read(Path::new(&fixture("wogan.seed3.jsonl")))
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect()
}

/// Writes `records` as the run file `name` in `dir`.
fn write_run(dir: &Path, name: &str, records: &[Value]) -> PathBuf {
    let path = dir.join(name);
    let text: String = records.iter().map(|r| format!("{r}\n")).collect();
    std::fs::write(&path, text).expect("a scratch run");
    path
}

/// The fixture run with `change` made to its header.
fn with_header(change: impl FnOnce(&mut Value)) -> Vec<Value> {
    let mut records = fixture_records();
    change(&mut records[0]);
    records
}

/// `wogan report RUN --out DIR --html --traces 2`: its exit code and stderr, and the page.
fn traced_report(dir: &Path, run: &Path) -> (Option<i32>, String, String) {
    let out = dir.join(format!(
        "{}.report",
        run.file_name().unwrap().to_string_lossy()
    ));
    let output = wogan(
        &[
            "report",
            path_str(run),
            "--out",
            path_str(&out),
            "--html",
            "--traces",
            "2",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let page = std::fs::read_to_string(out.join("report.html")).unwrap_or_default();
    (output.status.code(), stderr, page)
}

#[test]
fn a_header_setting_out_of_range_is_named_and_its_roads_are_not_driven_again() {
    let dir = scratch_dir("report-header-ranges");
    // Each a setting the simulator cannot run with, and what the report says of it.
    let cases: [(&str, Value, &str); 3] = [
        (
            "hz0",
            json!(["sim", "physics_hz", 0.0]),
            "the run's header, config.sim.physics_hz must be",
        ),
        (
            "hz1e9",
            json!(["sim", "physics_hz", 1e9]),
            "config.sim.physics_hz must be",
        ),
        (
            "mass",
            json!(["vehicle", "mass_kg", 1e12]),
            "config.sim.vehicle.mass_kg must be from 10 to 100000 (got 1e12)",
        ),
    ];
    for (name, change, says) in cases {
        let records = with_header(|header| {
            let sim = &mut header["config"]["sim"];
            match change[0].as_str() {
                Some("sim") => sim[change[1].as_str().unwrap()] = change[2].clone(),
                _ => sim["vehicle"][change[1].as_str().unwrap()] = change[2].clone(),
            }
        });
        let run = write_run(&dir, &format!("{name}.jsonl"), &records);
        let (code, stderr, page) = traced_report(&dir, &run);
        assert_eq!(code, Some(1), "{name}: {stderr}");
        assert!(stderr.contains(says), "{name}: {stderr}");
        assert_eq!(
            stderr.matches("not driven again").count(),
            1,
            "{name}: said once for the run: {stderr}"
        );
        assert!(!page.is_empty(), "{name}: the page is still written");
        assert!(!page.contains("driven again: PASS"), "{name}");
    }
    // A driver's section that is not the driver's: named as the header's, not a config file's.
    let records = with_header(|header| header["config"]["driver"] = json!({"command": "x"}));
    let run = write_run(&dir, "driver.jsonl", &records);
    let (code, stderr, _) = traced_report(&dir, &run);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("the run's header, config.driver"),
        "{stderr}"
    );
    assert!(!stderr.contains("config file"), "{stderr}");
}

#[test]
fn an_executors_run_is_not_driven_again_by_wogans_driver() {
    let dir = scratch_dir("report-executor-run");
    // As `wogan run --executor` writes it: the oracle a default, the executor named in config.
    let records = with_header(|header| {
        header["config"]["executor"] = json!("cmd:python3 my_simulator.py");
    });
    let run = write_run(&dir, "executor.jsonl", &records);
    let (code, stderr, page) = traced_report(&dir, &run);
    // Said once for the run, and no bad input: the run is sound.
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(stderr.matches("not driven again").count(), 1, "{stderr}");
    assert!(
        stderr.contains("driven by an external executor (cmd:python3 my_simulator.py)"),
        "{stderr}"
    );
    assert!(!page.contains("driven again: PASS"), "{page}");
    // Nor exported: a result folder's traces would be wogan's driver's, not the executor's.
    let output = wogan(
        &["export", path_str(&run), path_str(&dir.join("exported"))],
        "",
    );
    assert_ne!(output.status.code(), Some(0));
    assert!(
        String::from_utf8_lossy(&output.stderr).contains("external executor"),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn records_no_run_holds_are_named_by_line_and_not_read() {
    let dir = scratch_dir("report-bad-records");
    let records = fixture_records();
    let header = records[0].clone();
    let failing: Vec<&Value> = records.iter().filter(|r| r["outcome"] == "FAIL").collect();
    let passing = records
        .iter()
        .find(|r| r["outcome"] == "PASS")
        .expect("a passing test");
    let mut lines = vec![header.clone()];
    // Lines 2-6: the run's failing tests, as recorded.
    lines.extend(failing.iter().map(|&r| r.clone()));
    // Line 7: a test of an id read already; line 8: max_bolp 1e308; line 9: -1; line 10: a PASS
    // without a max_bolp; line 11: a drive of 1e308 s; line 12: a second header.
    lines.push(failing[0].clone());
    for (bolp, id) in [(json!(1e308), 901), (json!(-1.0), 902), (Value::Null, 903)] {
        let mut test = passing.clone();
        test["id"] = json!(id);
        test["max_bolp"] = bolp;
        lines.push(test);
    }
    let mut long = passing.clone();
    long["id"] = json!(904);
    long["sim_time_s"] = json!(1e308);
    lines.push(long);
    lines.push(header.clone());
    let run = write_run(&dir, "bad.jsonl", &lines);
    let output = wogan(&["report", path_str(&run), "--table"], "");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let at = path_str(&run);
    for says in [
        format!("{at}:7: test {} again (first on line 2)", failing[0]["id"]),
        format!("{at}:8: bad test record: max_bolp must be from 0 to 1 (got 1e308)"),
        format!("{at}:9: bad test record: max_bolp must be from 0 to 1 (got -1)"),
        format!("{at}:10: bad test record: max_bolp is null in a PASS drive"),
        format!("{at}:11: bad test record: sim_time_s must be from 0 to"),
        format!("{at}:12: a second header (the run's is line 1)"),
    ] {
        assert!(stderr.contains(&says), "{says}\n{stderr}");
    }
    // What was read is the run's: its five failures once, no 309-digit cell.
    let table = String::from_utf8_lossy(&output.stdout);
    assert!(!table.contains("1000000000000000"), "{table}");

    // A header after the tests, a config that is no object, a map of no size.
    let mut late = failing.iter().map(|&r| r.clone()).collect::<Vec<_>>();
    late.push(header.clone());
    let bad_config = with_header(|h| h["config"] = json!("x"));
    let no_map = with_header(|h| h["config"]["road"]["map_size_m"] = json!(-5.0));
    for (name, lines, says) in [
        ("late", late, "6: a header after the run's records (line 1)"),
        (
            "config",
            bad_config,
            "1: bad header record: config: a string, not an object",
        ),
        (
            "map",
            no_map,
            "1: bad header record: config.road.map_size_m must be above 0",
        ),
    ] {
        let run = write_run(&dir, &format!("{name}.jsonl"), &lines);
        let output = wogan(&["report", path_str(&run), "--table"], "");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{name}: {stderr}");
        assert!(
            stderr.contains(&format!("{}:{says}", path_str(&run))),
            "{name}: {stderr}"
        );
    }
}

#[test]
fn options_that_cannot_go_together_and_an_out_that_is_a_file_are_refused() {
    let dir = scratch_dir("report-options");
    let run = fixture("wogan.seed3.jsonl");
    let output = wogan(&["report", &run, "--table", "--html", "--traces", "5"], "");
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--traces") && stderr.contains("--table"),
        "{stderr}"
    );

    let file = dir.join("afile");
    std::fs::write(&file, "mine").unwrap();
    let output = wogan(&["report", &run, "--out", path_str(&file)], "");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(output.status.code(), Some(0));
    assert!(stderr.contains("is a file, not a folder"), "{stderr}");
    assert_eq!(read(&file), "mine", "no output overwrites an input");
}

/// Whether process `pid` has a handler for SIGINT (the kernel's `SigCgt` mask in its status).
fn catches_sigint(pid: u32) -> bool {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| mask & (1 << (2 - 1)) != 0)
}

#[test]
fn ctrl_c_while_roads_are_driven_again_writes_the_page_without_them_and_exits_130() {
    let dir = scratch_dir("report-interrupted");
    // 400 failing tests (the fixture's five, again under new ids): minutes of drives again.
    let records = fixture_records();
    let failing: Vec<&Value> = records.iter().filter(|r| r["outcome"] == "FAIL").collect();
    let mut lines = vec![records[0].clone()];
    for id in 1..=400 {
        let mut test = failing[id % failing.len()].clone();
        test["id"] = json!(id);
        lines.push(test);
    }
    let run = write_run(&dir, "many.jsonl", &lines);
    let out = dir.join("out");
    let mut child = spawn(&[
        "report",
        path_str(&run),
        "--out",
        path_str(&out),
        "--html",
        "--traces",
        "400",
    ]);
    let done = watchdog(&child, Duration::from_secs(300));
    // The protocol: the signal goes once report.md is written, which is after the measures and
    // before the drives again (minutes of them).
    let mut polls = 0;
    while !out.join("report.md").exists() {
        std::thread::sleep(Duration::from_millis(10));
        polls += 1;
        assert!(polls < 12_000, "no report.md");
    }
    let (status, stderr) = signal_and_wait(&mut child, "-INT", &done);
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("wogan report: interrupted; the report was written without the drives"),
        "{stderr}"
    );
    assert!(stderr.contains("were not driven again: Ctrl-C"), "{stderr}");
    let page = read(&out.join("report.html"));
    assert!(
        !page.contains("the drive was interrupted"),
        "interrupted drives shown as results"
    );
}

#[test]
fn ctrl_c_while_a_report_measures_ends_it_with_exit_130_and_nothing_written() {
    let dir = scratch_dir("report-interrupted-early");
    let run = fixture("wogan.seed3.jsonl");
    let out = dir.join("out");
    let mut child = spawn(&["report", &run, "--out", path_str(&out)]);
    let done = watchdog(&child, Duration::from_secs(120));
    // The handler is installed before any run is read; the signal goes once it is there, and
    // wherever it lands, the report ends with 130 (if it ended first, it said so with 0).
    let mut polls = 0;
    while !catches_sigint(child.id()) {
        std::thread::sleep(Duration::from_millis(1));
        polls += 1;
        assert!(polls < 60_000, "no SIGINT handler");
    }
    let (status, stderr) = signal_and_wait(&mut child, "-INT", &done);
    match status.code() {
        Some(130) => assert!(stderr.contains("wogan report: interrupted; "), "{stderr}"),
        // The 30-test run was reported before the signal came.
        Some(0) => assert!(out.join("report.md").exists()),
        other => panic!("exit {other:?}: {stderr}"),
    }
}
