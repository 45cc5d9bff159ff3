//! End-to-end test of the MetaDrive executor (examples/metadrive/): a simulator nobody here wrote,
//! driven through `wogan run --executor`. Protocol lines piped to the executor (a straight road
//! passes, a tight U-turn leaves the lane on a side); a 20-test search with `--jobs 2` whose every
//! test is answered; its failing roads kept as a suite and replayed through the executor (the CI
//! walk-through with a user's own simulator); Ctrl-C of a search; and after each, no executor left
//! running.
//!
//! MetaDrive is not a build dependency: `examples/metadrive/setup.sh` makes its venv. Without the
//! venv the test says so and checks nothing, unless WOGAN_REQUIRE_METADRIVE is set (CI sets it, after
//! running setup.sh), when it fails.

use crate::common::{
    scratch_dir, signal_and_wait, spawn, test_records, venv_python, watchdog, wogan,
};
use serde_json::Value;
use std::io::{BufReader, Read, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The checkout.
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
/// The executor script, as its README names it; also what finds its processes.
const EXECUTOR: &str = "examples/metadrive/executor.py";

/// The executor script's full path: how the test starts it, and so how it finds its processes.
fn executor_script() -> String {
    let script = Path::new(REPO).join(EXECUTOR);
    script.canonicalize().unwrap().display().to_string()
}

/// A wall-time limit of the test's own, given to every executor it starts, so that its processes
/// are told apart from any other of this checkout (a campaign running beside the tests).
const MARK: &str = "--road-wall-timeout 299.5";

/// The executor processes this test started still running.
fn executors_left() -> String {
    let found = Command::new("pgrep")
        .args(["-f", &format!("{} .*{MARK}", executor_script())])
        .output()
        .expect("pgrep");
    String::from_utf8_lossy(&found.stdout).into_owned()
}

#[test]
fn metadrive_drives_roads_searches_and_leaves_no_process() {
    let Some(python) = venv_python(
        "metadrive-venv",
        "examples/metadrive/setup.sh",
        "WOGAN_REQUIRE_METADRIVE",
    ) else {
        return;
    };
    let script = executor_script();
    let command = format!("cmd:{} {script} --policy idm {MARK}", python.display());

    // 1. The protocol from the executor's end: a straight road passes; a U-turn tighter than the
    // car can follow at 70 km/h leaves the lane, over the road's outer edge.
    let mut executor = Command::new(&python)
        .args([&script, "--policy", "idm", "--execution-data"])
        .args(MARK.split(' '))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lines = [
        r#"{"type":"hello","protocol":"wogan-executor","version":2,"units":"metres, seconds","map_size_m":200.0,"oob_tolerance":0.85,"speed_limit_kmh":70.0}"#,
        r#"{"type":"road","id":1,"road_points":[[100.0,10.0],[100.0,25.0],[100.0,40.0],[100.0,55.0],[100.0,70.0],[100.0,85.0]]}"#,
        r#"{"type":"road","id":2,"road_points":[[100.0,10.0],[100.0,25.0],[90.0,35.0],[75.0,35.0],[65.0,25.0],[65.0,10.0]]}"#,
        r#"{"type":"bye"}"#,
    ];
    let mut stdin = executor.stdin.take().unwrap();
    for line in lines {
        writeln!(stdin, "{line}").unwrap();
    }
    drop(stdin);
    let done = watchdog(&executor, Duration::from_secs(300));
    let mut stdout = String::new();
    BufReader::new(executor.stdout.take().unwrap())
        .read_to_string(&mut stdout)
        .unwrap();
    assert!(executor.wait().unwrap().success());
    done.store(true, Ordering::SeqCst);
    let answers: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("only protocol lines on stdout"))
        .collect();
    assert_eq!(answers.len(), 2, "{stdout}");
    assert_eq!(
        (&answers[0]["id"], &answers[0]["outcome"]),
        (&Value::from(1), &Value::from("PASS")),
        "{stdout}"
    );
    assert!(answers[0]["max_bolp"].as_f64().unwrap() < 0.85);
    assert_eq!(
        (
            &answers[1]["id"],
            &answers[1]["outcome"],
            &answers[1]["oob_side"]
        ),
        (&Value::from(2), &Value::from("FAIL"), &Value::from("right")),
        "{stdout}"
    );
    assert!(answers[1]["max_bolp"].as_f64().unwrap() > 0.85);
    // The lane distance: near the lane's half width on the straight road, the centre outside the
    // lane on the one it leaves (BOLP past 0.85 puts the centre past the edge).
    let distance = |i: usize| {
        answers[i]["min_lane_distance_m"]
            .as_f64()
            .expect("a lane distance")
    };
    assert!((1.0..=2.0).contains(&distance(0)), "{stdout}");
    assert!(distance(1) < 0.0, "{stdout}");
    // Where it left: the car centre, in the road's frame, right of the right lane's centre (over
    // 2 m from the road's points' polyline) and within a car's length of the road.
    let point: Vec<f64> = serde_json::from_value(answers[1]["oob_point"].clone()).expect("[x, y]");
    let u_turn = [
        [100.0, 10.0],
        [100.0, 25.0],
        [90.0, 35.0],
        [75.0, 35.0],
        [65.0, 25.0],
        [65.0, 10.0],
    ];
    let off_road_m = u_turn
        .windows(2)
        .map(|s| {
            let (d, p) = (
                [s[1][0] - s[0][0], s[1][1] - s[0][1]],
                [point[0] - s[0][0], point[1] - s[0][1]],
            );
            let t = ((p[0] * d[0] + p[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
            (p[0] - t * d[0]).hypot(p[1] - t * d[1])
        })
        .fold(f64::INFINITY, f64::min);
    assert!(
        (2.0..8.0).contains(&off_road_m),
        "exit at {point:?}, {off_road_m} m off the road: {stdout}"
    );
    // With --execution-data (scripts/peers' pipeline reads it): the SBST pipeline's 17-field
    // records, one per sample (50 Hz) to the end; out of bounds only at the last, where it left.
    let records = answers[1]["execution_data"]
        .as_array()
        .expect("execution_data");
    let sim_time_s = answers[1]["sim_time_s"].as_f64().unwrap();
    assert!(records
        .iter()
        .all(|r| r.as_array().is_some_and(|r| r.len() == 17)));
    assert_eq!(
        records.len(),
        (sim_time_s * 50.0).round() as usize,
        "one record per sample"
    );
    let last = &records[records.len() - 1];
    assert_eq!(last[0].as_f64(), Some(sim_time_s), "timer");
    assert_eq!(
        (&last[12], &last[13]),
        (&Value::from(true), &Value::from(1)),
        "is_oob, oob_counter: {last}"
    );
    assert!(records[..records.len() - 1].iter().all(|r| r[12] == false));
    for (axis, at) in point.iter().enumerate() {
        assert!(
            (last[1][axis].as_f64().unwrap() - at).abs() < 1e-3,
            "pos {last} at oob_point {point:?}"
        );
    }
    assert_eq!(executors_left(), "", "the piped executor ended");

    // 2. A search with two executors: every test answered by MetaDrive, none left running.
    let dir = scratch_dir("metadrive");
    let out = dir.join("run.jsonl");
    let ran = wogan(
        &[
            "run",
            "--max-tests",
            "20",
            "--seed",
            "1",
            "--jobs",
            "2",
            "--quiet",
            "--executor",
            &command,
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(
        ran.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let tests = test_records(&out);
    assert_eq!(tests.len(), 20);
    for test in &tests {
        assert!(
            test["outcome"] == "PASS" || test["outcome"] == "FAIL",
            "every test answered: {test}"
        );
        assert!(test["sim_time_s"].as_f64().unwrap() > 0.0, "{test}");
        if test["reason"] == "out_of_lane" {
            assert!(
                test["oob"]["x"].is_f64() && test["oob"]["y"].is_f64(),
                "{test}"
            );
        }
    }
    assert_eq!(executors_left(), "", "after a run");
    // The header names the executor, as it described itself, and no driver of wogan's.
    let text = std::fs::read_to_string(&out).unwrap();
    let header: Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    assert_eq!(header["oracle"], "executor", "{header}");
    assert_eq!(
        header["config"]["executor"]["settings"]["policy"], "idm",
        "{header}"
    );
    assert!(header["config"]["executor"]["name"].is_string(), "{header}");

    // 2b. The CI walk-through (README, examples/ci/) with a user's own simulator: the search's
    // failing roads kept as a suite, driven again through the executor on each commit, with a
    // JUnit report. (MetaDrive's drives need not repeat to the bit, so the verdict is `any`.)
    let suite = dir.join("suite.jsonl");
    let added = wogan(
        &[
            "suite",
            "add",
            out.to_str().unwrap(),
            "--to",
            suite.to_str().unwrap(),
            "--max",
            "4",
        ],
        "",
    );
    assert_eq!(
        added.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&added.stderr)
    );
    let roads = std::fs::read_to_string(&suite).unwrap().lines().count() - 1;
    assert!(roads > 0, "IDM at 70 km/h failed none of 20 roads");
    let junit = dir.join("replay.xml");
    let replayed = wogan(
        &[
            "replay",
            suite.to_str().unwrap(),
            "--executor",
            &command,
            "--jobs",
            "2",
            "--junit",
            junit.to_str().unwrap(),
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&replayed.stderr);
    assert!(matches!(replayed.status.code(), Some(0 | 1)), "{stderr}");
    let answers = crate::common::records(&replayed);
    assert_eq!(answers.len(), roads, "{stderr}");
    for answer in &answers {
        assert!(
            answer["outcome"] == "PASS" || answer["outcome"] == "FAIL",
            "driven: {answer}"
        );
        assert_eq!(answer["recorded_outcome"], "FAIL", "{answer}");
    }
    let report = std::fs::read_to_string(&junit).unwrap();
    assert_eq!(report.matches("<testcase").count(), roads, "{report}");
    assert_eq!(executors_left(), "", "after a replay");

    // 3. Ctrl-C in the middle of a search: exit 130, the summary says so, no executor left.
    let out = dir.join("interrupted.jsonl");
    let mut child = spawn(&[
        "run",
        "--max-tests",
        "500",
        "--seed",
        "2",
        "--jobs",
        "2",
        "--executor",
        &command,
        "--out",
        out.to_str().unwrap(),
    ]);
    let done = watchdog(&child, Duration::from_secs(300));
    let mut waited = 0;
    while test_records(&out).len() < 3 {
        std::thread::sleep(Duration::from_millis(50));
        waited += 1;
        assert!(waited < 4800, "no third test");
    }
    let (status, stderr) = signal_and_wait(&mut child, "-INT", &done);
    assert_eq!(status.code(), Some(130), "{stderr}");
    let last = std::fs::read_to_string(&out).unwrap();
    let summary: Value = serde_json::from_str(last.lines().last().unwrap()).unwrap();
    assert_eq!(summary["interrupted"], true);
    assert_eq!(executors_left(), "", "after Ctrl-C");
}
