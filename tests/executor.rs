//! End-to-end tests of `wogan run --executor`: the protocol from both ends (`wogan simulate` as the
//! executor gives the run of wogan's own simulator), and an executor that crashes, hangs, writes
//! garbage, answers out of range or for another road, or floods (tests/python/faulty_executor.py; skipped, saying so,
//! where python3 is missing), and that a file never starts an executor.

use crate::common::{records, scratch_dir, signal_and_wait, spawn, test_records, watchdog, wogan};
use serde_json::Value;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn arg(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// `cmd:` and the faulty executor in `mode` at road `id`, or `None` without python3.
fn faulty(mode: &str, id: usize) -> Option<String> {
    let python = Command::new("python3").arg("--version").output();
    if !python.is_ok_and(|o| o.status.success()) {
        eprintln!("python3 is not installed: the faulty-executor test is skipped");
        return None;
    }
    let script = format!(
        "{}/../../tests/python/faulty_executor.py",
        env!("CARGO_MANIFEST_DIR")
    );
    Some(format!("cmd:python3 {script} {mode} {id}"))
}

/// The run file's summary.
fn summary_of(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).expect("a run file");
    serde_json::from_str(text.lines().last().expect("a last line")).expect("JSON")
}

#[test]
fn wogan_simulate_as_the_executor_drives_as_wogan_does() {
    // On BOLP, and on the lane distance, which `simulate`'s answers carry.
    for fitness in ["bolp", "distance"] {
        let dir = scratch_dir(&format!("executor-simulate-{fitness}"));
        let (own, outside) = (dir.join("own.jsonl"), dir.join("outside.jsonl"));
        let base = [
            "run",
            "--max-tests",
            "30",
            "--seed",
            "1",
            "--quiet",
            "--fitness",
            fitness,
        ];
        let executor = format!("cmd:{} simulate", env!("CARGO_BIN_EXE_wogan"));
        let ran = wogan(&[&base[..], &["--out", arg(&own)]].concat(), "");
        assert_eq!(ran.status.code(), Some(0));
        let ran = wogan(
            &[
                &base[..],
                &["--out", arg(&outside), "--executor", &executor],
            ]
            .concat(),
            "",
        );
        assert_eq!(
            ran.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&ran.stderr)
        );
        let key = |t: &Value| {
            (
                t["id"].clone(),
                t["outcome"].clone(),
                t["max_bolp"].clone(),
                t["fitness"].clone(),
                t["sim_time_s"].clone(),
                t["min_lane_distance_m"].clone(),
            )
        };
        let (a, b) = (test_records(&own), test_records(&outside));
        assert_eq!(a.len(), 30);
        assert_eq!(
            a.iter().map(key).collect::<Vec<_>>(),
            b.iter().map(key).collect::<Vec<_>>(),
            "{fitness}"
        );
        let header: Value = serde_json::from_str(
            std::fs::read_to_string(&outside)
                .unwrap()
                .lines()
                .next()
                .unwrap(),
        )
        .unwrap();
        // The header names the executor, with what it said of itself, and no driver of wogan's.
        assert_eq!(header["oracle"], "executor");
        assert_eq!(
            header["config"]["executor"]["command"],
            executor.trim_start_matches("cmd:")
        );
        assert!(
            header["config"]["executor"]["roads_at_once"].is_u64(),
            "{header}"
        );
        assert!(header["config"].get("driver").is_none(), "{header}");
    }
}

#[test]
fn a_lane_distance_search_refuses_answers_without_the_distance() {
    // The faulty executor answers normally (its fault is at a road never reached), without
    // `min_lane_distance_m`: every road fails, and the run stops after 5 in a row.
    let Some(executor) = faulty("error", 99) else {
        return;
    };
    let dir = scratch_dir("executor-no-distance");
    let out = dir.join("run.jsonl");
    let ran = wogan(
        &[
            "run",
            "--max-tests",
            "12",
            "--seed",
            "3",
            "--quiet",
            "--fitness",
            "distance",
            "--executor",
            &executor,
            "--out",
            arg(&out),
        ],
        "",
    );
    assert_eq!(
        ran.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let tests = test_records(&out);
    assert_eq!(tests.len(), 5);
    for test in &tests {
        assert_eq!(test["outcome"], "ERROR");
        let error = test["error"].as_str().unwrap_or_default();
        assert!(error.contains("min_lane_distance_m: missing"), "{error}");
    }
}

#[test]
fn a_faulty_executor_fails_one_road_and_is_restarted_for_the_next() {
    for (mode, says) in [
        ("crash", "it ended with exit status 3 before answering; its stderr ended with:\nfaulty executor: crashing at road 4"),
        ("status", "it ended with exit status 7 before answering"),
        ("segv", "it was killed by signal 11 (SIGSEGV) before answering"),
        // Its own end is seen though the process it started holds its output (not the timeout).
        ("orphan", "it ended with exit status 0 before answering"),
        // Escape sequences on its stderr are quoted, never sent to a terminal.
        ("ansi", "its stderr ended with:\n\\x1b]0;TITLE\\x07\\x1b[2Jcleared"),
        // A deadline a loaded machine's python3 meets at its start (its reply to hello is waited
        // for as long).
        ("hang", "no answer within 3.000 s"),
        ("garbage", "the answer is not JSON"),
        ("range", "max_bolp: 7 is outside [0, 1]"),
        ("wrong-id", "id: 104 is not the road asked (4)"),
        // A second line is found at the next road: left over when that road is sent, or read
        // after it and naming road 4.
        ("flood", "more than one line for one request"),
        ("late-second", "more than one line for one request (a second answer to road 4)"),
        // An executor's own ERROR keeps its reason (and the executor, which answered).
        ("error", "the executor: the simulator refused road 4"),
    ] {
        let Some(executor) = faulty(mode, 4) else { return };
        let dir = scratch_dir(&format!("executor-{mode}"));
        let out = dir.join("run.jsonl");
        let ran = wogan(
            &["run", "--max-tests", "12", "--seed", "3", "--quiet", "--executor", &executor, "--executor-timeout", "3s", "--out", arg(&out)],
            "",
        );
        assert_eq!(ran.status.code(), Some(0), "{mode}: {}", String::from_utf8_lossy(&ran.stderr));
        let tests = test_records(&out);
        assert_eq!(tests.len(), 12, "{mode}: the run goes on");
        let bad = if matches!(mode, "flood" | "late-second") { 5 } else { 4 };
        for test in &tests {
            if test["id"] == bad {
                assert_eq!(test["outcome"], "ERROR", "{mode}: {test}");
                let error = test["error"].as_str().unwrap_or_default();
                assert!(error.starts_with(&format!("road {bad}: ")), "{mode}: {error}");
                assert!(error.contains(says), "{mode}: {error}");
            } else {
                assert_eq!(test["outcome"], "PASS", "{mode}: {test}");
            }
        }
        if mode == "ansi" {
            // The report lists the ERROR test with its message, as text (issue 72).
            let report = dir.join("report");
            let made = wogan(&["report", arg(&out), "--out", arg(&report), "--html"], "");
            assert_eq!(made.status.code(), Some(0), "{}", String::from_utf8_lossy(&made.stderr));
            let markdown = std::fs::read_to_string(report.join("report.md")).expect("report.md");
            assert!(markdown.contains("1 test(s) ended in ERROR"), "{markdown}");
            assert!(markdown.contains(&format!(" test {bad}: error: road {bad}: ")), "{markdown}");
            let page = std::fs::read_to_string(report.join("report.html")).expect("report.html");
            assert!(page.contains("ended in ERROR") && !page.contains('\u{1b}'), "{page}");
        }
    }
}

#[test]
fn an_executor_must_answer_hello_before_its_first_road() {
    for (mode, says) in [
        // An answer written before anything was read is not taken for road 1's (hostile input,
        // defect 19).
        ("early", "its first line is not its reply to hello"),
        // A version 2 executor, which does not answer hello.
        ("no-hello", "no reply to hello: no answer within 1.000 s"),
    ] {
        let Some(executor) = faulty(mode, 0) else {
            return;
        };
        let dir = scratch_dir(&format!("executor-{mode}"));
        let out = dir.join("run.jsonl");
        let ran = wogan(
            &[
                "run",
                "--max-tests",
                "12",
                "--seed",
                "3",
                "--quiet",
                "--executor",
                &executor,
                "--executor-timeout",
                "1s",
                "--max-failed-drives",
                "2",
                "--out",
                arg(&out),
            ],
            "",
        );
        assert_eq!(
            ran.status.code(),
            Some(1),
            "{mode}: {}",
            String::from_utf8_lossy(&ran.stderr)
        );
        // The first executor answers hello before the run begins: one that does not ends the run
        // before any test, with the reason in the summary (and a header naming the command).
        assert!(test_records(&out).is_empty(), "{mode}");
        let text = std::fs::read_to_string(&out).expect("the run file");
        let records: Vec<Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(records.len(), 2, "{mode}: {text}");
        assert_eq!(
            records[0]["config"]["executor"]["command"],
            executor.trim_start_matches("cmd:")
        );
        let error = records[1]["error"].as_str().unwrap_or_default();
        assert!(
            error.starts_with("the executor: ") && error.contains(says),
            "{mode}: {error}"
        );
    }
}

#[test]
fn an_executors_stderr_neither_kills_it_nor_fills_wogans_memory() {
    // A first stderr line that is not UTF-8 closed wogan's reader, and the executor died of its
    // next write (defect 4); stderr without newlines grew wogan by the line (defect 5).
    for (mode, tests) in [("bad-stderr", 12), ("stderr-flood", 30)] {
        let Some(executor) = faulty(mode, 0) else {
            return;
        };
        let dir = scratch_dir(&format!("executor-{mode}"));
        let out = dir.join("run.jsonl");
        let count = tests.to_string();
        let ran = run_through(&executor, &count, "3", arg(&out));
        assert_eq!(
            ran.status.code(),
            Some(0),
            "{mode}: {}",
            String::from_utf8_lossy(&ran.stderr)
        );
        let records = test_records(&out);
        assert_eq!(records.len(), tests, "{mode}");
        assert!(records.iter().all(|t| t["outcome"] == "PASS"), "{mode}");
    }
}

#[test]
fn the_summary_says_what_the_executor_said_of_itself() {
    let Some(executor) = faulty("fail", 2) else {
        return;
    };
    let dir = scratch_dir("executor-described");
    let out = dir.join("run.jsonl");
    let ran = run_through(&executor, "3", "3", arg(&out));
    assert_eq!(
        ran.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let summary = summary_of(&out);
    assert_eq!(
        summary["executor"],
        serde_json::json!({"name": "faulty", "version": "1", "settings": {"mode": "fail"}, "roads_at_once": 1})
    );
}

#[test]
fn an_executor_timeout_out_of_range_is_refused() {
    // 2^64 s overflowed a deadline (a panic); 0 failed every road (defect 15).
    for timeout in ["0", "18446744073709551615s", "213503982334601d"] {
        let ran = wogan(
            &[
                "run",
                "--max-tests",
                "3",
                "--executor",
                "cmd:true",
                "--executor-timeout",
                timeout,
            ],
            "",
        );
        assert_eq!(ran.status.code(), Some(2), "{timeout}");
        let stderr = String::from_utf8_lossy(&ran.stderr);
        assert!(
            stderr.contains("--executor-timeout") && stderr.contains("100ms to 24h"),
            "{timeout}: {stderr}"
        );
    }
}

#[test]
fn an_executor_that_always_fails_stops_the_run_with_what_was_done_written() {
    let Some(executor) = faulty("always-crash", 0) else {
        return;
    };
    let dir = scratch_dir("executor-always");
    let out = dir.join("run.jsonl");
    let ran = wogan(
        &[
            "run",
            "--max-tests",
            "50",
            "--seed",
            "3",
            "--quiet",
            "--executor",
            &executor,
            "--max-failed-drives",
            "3",
            "--out",
            arg(&out),
        ],
        "",
    );
    assert_eq!(ran.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&ran.stderr);
    assert!(
        stderr.contains("the executor failed 3 roads in a row"),
        "{stderr}"
    );
    let tests = test_records(&out);
    assert_eq!(tests.len(), 3);
    assert!(tests.iter().all(|t| t["outcome"] == "ERROR"));
    let summary = summary_of(&out);
    assert_eq!(summary["type"], "summary");
    assert!(summary["error"]
        .as_str()
        .unwrap_or_default()
        .contains("3 roads in a row"));
}

#[test]
fn sigterm_ends_a_run_whose_executor_hangs_and_leaves_no_process() {
    let Some(executor) = faulty("hang", 2) else {
        return;
    };
    let dir = scratch_dir("executor-sigterm");
    let out = dir.join("run.jsonl");
    let marker = arg(&dir).to_owned();
    // The marker names this test's executors among the machine's processes.
    let executor = format!("{executor} {marker}");
    let mut child = spawn(&[
        "run",
        "--max-tests",
        "10",
        "--seed",
        "3",
        "--executor",
        &executor,
        "--out",
        arg(&out),
    ]);
    let done = watchdog(&child, Duration::from_secs(120));
    // The first test is written when its road is answered; the second road hangs.
    let mut waited = 0;
    while test_records(&out).is_empty() {
        std::thread::sleep(Duration::from_millis(50));
        waited += 1;
        assert!(waited < 1200, "no first test");
    }
    let (status, stderr) = signal_and_wait(&mut child, "-TERM", &done);
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert_eq!(summary_of(&out)["interrupted"], true);
    let left = Command::new("pgrep").args(["-f", &marker]).output();
    if let Ok(left) = left {
        assert!(
            left.stdout.is_empty(),
            "executors left running: {}",
            String::from_utf8_lossy(&left.stdout)
        );
    }
}

#[test]
fn no_file_starts_an_executor() {
    let dir = scratch_dir("executor-trust");
    let out = dir.join("run.jsonl");
    let executor = format!("cmd:{} simulate", env!("CARGO_BIN_EXE_wogan"));
    let ran = run_through(&executor, "5", "1", arg(&out));
    assert_eq!(ran.status.code(), Some(0));
    // A header naming a command that would leave a trace if it ran.
    let canary = dir.join("canary");
    let text = std::fs::read_to_string(&out).unwrap();
    let planted = text.replacen(
        &format!("\"command\":\"{} simulate\"", env!("CARGO_BIN_EXE_wogan")),
        &format!("\"command\":\"touch {}\"", arg(&canary)),
        1,
    );
    assert_ne!(planted, text);
    let planted_run = dir.join("planted.jsonl");
    std::fs::write(&planted_run, &planted).unwrap();
    let export = wogan(&["export", arg(&planted_run), arg(&dir.join("export"))], "");
    assert_eq!(export.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&export.stderr);
    assert!(
        stderr.contains("touch") && stderr.contains("--executor"),
        "{stderr}"
    );
    for args in [
        vec!["replay", arg(&planted_run)],
        vec!["report", arg(&planted_run), "--out", arg(&dir)],
        vec![
            "suite",
            "add",
            arg(&planted_run),
            "--to",
            arg(&dir.join("suite.jsonl")),
        ],
    ] {
        let _ = wogan(&args, "");
    }
    assert!(!canary.exists(), "a file started a process");
}

#[test]
fn the_sbst_pipeline_generator_drives_wogans_search_through_the_pipelines_executor() {
    // examples/sbst2022 against the pipeline's interface (a stand-in) and wogan simulate as the
    // pipeline's executor.
    crate::common::python_check("check_sbst_generator.py");
}

#[test]
fn a_run_an_executor_drove_reads_back_in_a_report() {
    // An executor says on which side the car left, and where when it can (`oob_point`). Without
    // the place the record's exit has `null`s, and the report still reads the test, counts its
    // failure, and has no distinct failures to count; with it the exit is placed and counted.
    for (mode, placed) in [("fail", false), ("fail-placed", true)] {
        let Some(executor) = faulty(mode, 3) else {
            return;
        };
        let dir = scratch_dir(&format!("executor-report-{mode}"));
        let out = dir.join("run.jsonl");
        let ran = run_through(&executor, "6", "3", arg(&out));
        assert_eq!(
            ran.status.code(),
            Some(0),
            "{mode}: {}",
            String::from_utf8_lossy(&ran.stderr)
        );
        let failed: Vec<Value> = test_records(&out)
            .into_iter()
            .filter(|t| t["outcome"] == "FAIL")
            .collect();
        assert_eq!(failed.len(), 1, "{mode}");
        let exit = &failed[0]["oob"];
        assert_eq!(exit["side"], "left", "{mode}");
        if placed {
            // The third road point, on the centre line: the competition's analysis calls it LEFT.
            let third = &failed[0]["road_points"][2];
            assert_eq!(
                (&exit["x"], &exit["y"]),
                (&third[0], &third[1]),
                "{mode}: {exit}"
            );
            assert_eq!(
                (&exit["t_s"], &exit["sbst_side"]),
                (&Value::from(1.5), &Value::from("LEFT"))
            );
        } else {
            assert!(
                exit["x"].is_null() && exit["sbst_side"].is_null(),
                "{mode}: {exit}"
            );
        }
        let table = wogan(&["report", arg(&out), "--table"], "");
        let stderr = String::from_utf8_lossy(&table.stderr);
        assert_eq!(
            table.status.code(),
            Some(0),
            "{mode}: every record reads back: {stderr}"
        );
        let stdout = String::from_utf8_lossy(&table.stdout);
        let row = stdout
            .lines()
            .find(|l| l.starts_with("| wogan"))
            .unwrap_or_default();
        // Grouped and labelled by the executor, as it named itself, with its own settings.
        assert!(
            row.contains(&format!("/ faulty (mode {mode}) /")),
            "the driver is the executor's: {row}"
        );
        let distinct = if placed { "1 (1)" } else { "–" };
        assert!(
            row.contains(&format!("| 1 | 1 (1) | {distinct} |")),
            "{mode}: one run, one failing road, distinct {distinct}: {stdout}"
        );
    }
}

/// `cmd:` and the concurrent executor (tests/python/concurrent_executor.py) in `mode`, taking
/// `at_once` roads, misbehaving at road `id`.
fn concurrent(mode: &str, at_once: usize, id: usize) -> String {
    format!(
        "cmd:python3 {}/../../tests/python/concurrent_executor.py {mode} {at_once} {id}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// `wogan run --max-tests TESTS --seed SEED --quiet --executor EXECUTOR --out OUT`.
fn run_through(executor: &str, tests: &str, seed: &str, out: &str) -> std::process::Output {
    wogan(
        &[
            "run",
            "--max-tests",
            tests,
            "--seed",
            seed,
            "--quiet",
            "--executor",
            executor,
            "--out",
            out,
        ],
        "",
    )
}

/// A 40-test run with `--jobs 4` through `executor`: its test records and summary.
fn run_with(
    executor: &str,
    name: &str,
    extra: &[&str],
) -> (Vec<Value>, Value, std::process::Output) {
    let dir = scratch_dir(name);
    let out = dir.join("run.jsonl");
    let ran = wogan(
        &[
            &[
                "run",
                "--max-tests",
                "40",
                "--seed",
                "5",
                "--jobs",
                "4",
                "--quiet",
                "--executor",
                executor,
                "--out",
                arg(&out),
            ][..],
            extra,
        ]
        .concat(),
        "",
    );
    (test_records(&out), summary_of(&out), ran)
}

#[test]
fn an_executor_that_takes_several_roads_answers_in_any_order_with_the_same_records() {
    // Roads in flight, answered out of order, give the records of one road at a time.
    let (at_once, summary, ran) = run_with(&concurrent("ok", 4, 0), "executor-at-once", &[]);
    assert_eq!(
        ran.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let (one, _, ran) = run_with(&concurrent("ok", 1, 0), "executor-one-at-once", &[]);
    assert_eq!(
        ran.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    assert_eq!(at_once.len(), 40);
    let comparable = |tests: &[Value]| -> Vec<(Value, Value, Value, Value)> {
        tests
            .iter()
            .map(|t| {
                (
                    t["id"].clone(),
                    t["road_points"].clone(),
                    t["outcome"].clone(),
                    t["max_bolp"].clone(),
                )
            })
            .collect()
    };
    assert_eq!(comparable(&at_once), comparable(&one));
    assert!(
        at_once.iter().any(|t| t["outcome"] == "FAIL")
            && at_once.iter().any(|t| t["outcome"] == "PASS")
    );
    assert_eq!(summary["executor"]["roads_at_once"], 4);
}

#[test]
fn faults_of_an_executor_holding_several_roads_end_those_roads_and_the_run_goes_on() {
    for (mode, says) in [
        ("twice", "a second answer to road 9"),
        // Named as a road not sent, or (when it was the only road in flight) as its answer's id.
        ("unsent", "1009"),
        ("die", "it ended with exit status 3 before answering; its stderr ended with:\nconcurrent executor: dying at road 9"),
    ] {
        let (tests, summary, ran) = run_with(&concurrent(mode, 4, 9), &format!("executor-at-once-{mode}"), &["--max-failed-drives", "20"]);
        assert_eq!(ran.status.code(), Some(0), "{mode}: {}", String::from_utf8_lossy(&ran.stderr));
        // Every test once, in order: none lost, none twice.
        let ids: Vec<u64> = tests.iter().map(|t| t["id"].as_u64().unwrap()).collect();
        assert_eq!(ids, (1..=40).collect::<Vec<_>>(), "{mode}");
        let failed: Vec<&Value> = tests.iter().filter(|t| t["outcome"] == "ERROR").collect();
        assert!(!failed.is_empty() && failed.len() <= 4, "{mode}: {} roads failed", failed.len());
        for test in &failed {
            let error = test["error"].as_str().unwrap_or_default();
            assert!(error.contains(says), "{mode}: {error}");
        }
        // A new executor took the roads after the fault.
        assert!(tests[20..].iter().all(|t| t["outcome"] != "ERROR"), "{mode}");
        assert_eq!(summary["executor"]["roads_at_once"], 4);
    }
}

#[test]
fn a_suite_from_an_executor_run_replays_through_the_executor_and_simulate_drives_through_it() {
    // `wogan simulate` as the executor drives as wogan does, so its verdicts are known.
    let dir = scratch_dir("executor-replay");
    let (run, suite) = (dir.join("run.jsonl"), dir.join("suite.jsonl"));
    // Judged strictly (BOLP above 0.2 fails), so that a short search fails some roads.
    let executor = format!(
        "cmd:{} simulate --oob-tolerance 0.2",
        env!("CARGO_BIN_EXE_wogan")
    );
    let strict = ["--oob-tolerance", "0.2"];
    let ran = wogan(
        &[
            &["run", "--max-tests", "30", "--seed", "1", "--quiet"][..],
            &["--executor", &executor, "--out", arg(&run)],
            &strict,
        ]
        .concat(),
        "",
    );
    assert_eq!(
        ran.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let added = wogan(&["suite", "add", "--to", arg(&suite), arg(&run)], "");
    assert_eq!(
        added.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&added.stderr)
    );
    let kept = std::fs::read_to_string(&suite).expect("the suite");
    let roads = kept.lines().count() - 1;
    assert!(roads > 0, "the run found failing roads: {kept}");
    // The suite records where its roads came from: the executor, as it named itself.
    assert!(kept.contains("\"driver\":\"wogan simulate"), "{kept}");

    // Replayed through the same executor, every road drives as recorded: nothing changed.
    let junit = dir.join("replay.xml");
    let replayed = wogan(
        &[
            "replay",
            arg(&suite),
            "--executor",
            &executor,
            "--jobs",
            "2",
            "--fail-on",
            "changed",
            "--junit",
            arg(&junit),
            "--oob-tolerance",
            "0.2",
        ],
        "",
    );
    assert_eq!(
        replayed.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&replayed.stderr)
    );
    let answers = records(&replayed);
    assert_eq!(answers.len(), roads);
    for answer in &answers {
        assert_eq!(answer["outcome"], answer["recorded_outcome"], "{answer}");
        assert_eq!(answer["max_bolp"], answer["recorded_max_bolp"], "{answer}");
    }
    let report = std::fs::read_to_string(&junit).expect("the JUnit report");
    assert!(
        report.contains("name=\"driver\" value=\"wogan simulate\""),
        "{report}"
    );
    assert_eq!(report.matches("<failure").count(), roads, "{report}");

    // Through an executor that crashes at the second road: that road ends in ERROR with the
    // reason, a new executor drives the rest (which it passes: changed), exit 1 (failing now).
    let Some(crashing) = faulty("crash", 2) else {
        return;
    };
    let replayed = wogan(
        &[
            "replay",
            arg(&suite),
            "--executor",
            &crashing,
            "--oob-tolerance",
            "0.2",
        ],
        "",
    );
    assert_eq!(
        replayed.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&replayed.stderr)
    );
    let answers = records(&replayed);
    assert_eq!(answers.len(), roads);
    for (i, answer) in answers.iter().enumerate() {
        if i == 1 {
            assert_eq!(answer["outcome"], "ERROR", "{answer}");
            let reason = answer["reason"].as_str().unwrap_or_default();
            assert!(
                reason.contains("road 2: the executor: it ended with exit status 3"),
                "{reason}"
            );
        } else {
            assert_eq!(answer["outcome"], "PASS", "{answer}");
            assert_eq!(answer["changed"], true, "{answer}");
        }
    }

    // `simulate --executor` answers each road as `simulate` does itself.
    let roads_text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/reference/roads.jsonl"),
    )
    .expect("reference roads");
    let input: String = roads_text
        .lines()
        .take(8)
        .map(|l| format!("{l}\n"))
        .collect();
    let own = wogan(&["simulate"], &input);
    let through = wogan(
        &["simulate", "--jobs", "2", "--executor", &executor],
        &input,
    );
    assert_eq!(
        through.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&through.stderr)
    );
    let key = |output: &std::process::Output| -> Vec<(Value, Value, Value)> {
        records(output)
            .into_iter()
            .map(|r| {
                (
                    r["line"].clone(),
                    r["outcome"].clone(),
                    r["max_bolp"].clone(),
                )
            })
            .collect()
    };
    assert_eq!(key(&own).len(), 8);
    assert_eq!(key(&own), key(&through));
    // What needs wogan's own simulator's samples is refused with an executor.
    let refused = wogan(
        &["simulate", "--execution-data", "--executor", &executor],
        &input,
    );
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--execution-data"));
}
