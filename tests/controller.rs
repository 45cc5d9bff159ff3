//! End-to-end tests of a controller process as the driver (`--oracle cmd:...`): the examples drive
//! the reference roads, and a controller that crashes, hangs, writes garbage, a number out of range,
//! a reply to another step or two replies to one fails that drive as ERROR and is restarted for the
//! next (tests/python/faulty_controller.py; skipped, saying so, where python3 is missing); no file
//! starts a controller.

use crate::common::{records, scratch_dir, spawn, watchdog, wogan, write_file};
use serde_json::Value;
use std::io::Read;
use std::process::Command;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The repository's root.
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

fn python() -> bool {
    let ok = Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("python3 is not installed: the controller tests are skipped");
    }
    ok
}

/// The first `n` reference roads as input lines.
fn reference_roads(n: usize) -> String {
    let text = std::fs::read_to_string(format!("{REPO}/tests/reference/roads.jsonl")).unwrap();
    text.lines().take(n).map(|l| format!("{l}\n")).collect()
}

#[test]
fn the_example_controllers_drive_the_reference_roads() {
    if !python() {
        return;
    }
    let dir = scratch_dir("controller-examples");
    let roads = reference_roads(10);
    let pure_pursuit = format!("cmd:python3 {REPO}/examples/controllers/pure_pursuit.py");
    let first = wogan(&["simulate", "--oracle", &pure_pursuit], &roads);
    assert_eq!(
        first.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let answers = records(&first);
    assert_eq!(answers.len(), 10);
    assert!(
        answers.iter().all(|a| a["outcome"] == "PASS"),
        "{answers:?}"
    );
    // The same controller, the same drives.
    let again = wogan(
        &["simulate", "--oracle", &pure_pursuit, "--jobs", "2"],
        &roads,
    );
    let key = |a: &Value| {
        (
            a["outcome"].clone(),
            a["max_bolp"].clone(),
            a["sim_time_s"].clone(),
        )
    };
    assert_eq!(
        records(&again).iter().map(key).collect::<Vec<_>>(),
        answers.iter().map(key).collect::<Vec<_>>()
    );
    // The camera keeper sees the frame only when its config asks for it.
    let config = write_file(&dir, "camera.json", r#"{"driver": {"camera": true}}"#);
    let camera = format!("cmd:python3 {REPO}/examples/controllers/camera_keeper.py");
    let seen = wogan(
        &["simulate", "--oracle", &camera, "--config", &config],
        &roads,
    );
    assert_eq!(seen.status.code(), Some(0));
    let passed = records(&seen)
        .iter()
        .filter(|a| a["outcome"] == "PASS")
        .count();
    assert!(passed >= 8, "the camera keeper passes {passed} of 10");
}

#[test]
fn a_faulty_controller_fails_one_drive_and_is_restarted_for_the_next() {
    if !python() {
        return;
    }
    let dir = scratch_dir("controller-faults");
    let config = write_file(&dir, "fast.json", r#"{"driver": {"step_timeout_s": 0.5}}"#);
    let roads = reference_roads(3);
    // (mode, the drive that fails, what its error says)
    for (mode, bad, says) in [
        ("crash", 1, "it ended with exit status 3 before answering; its stderr ended with:\nfaulty controller: crashing at step 5 of drive 2"),
        ("hang", 1, "no answer within 0.500 s"),
        ("garbage", 1, "the reply is not JSON"),
        ("range", 1, "steering: 5 is outside [-1, 1]"),
        ("wrong-step", 1, "step: 105 is not the step asked (5)"),
        // A second line is found at the next step: left over when that step is sent, or read
        // after it and naming step 5.
        ("flood", 1, "more than one line for one request"),
        ("late-second", 1, "more than one line for one request (a second reply to step 5)"),
        // ... and a second reply to a drive's last step, at the first step of the next drive.
        ("end-second", 2, "more than one line for one request"),
    ] {
        let oracle = format!("cmd:python3 {REPO}/tests/python/faulty_controller.py {mode} 2 5");
        let output = wogan(&["simulate", "--oracle", &oracle, "--config", &config], &roads);
        assert_eq!(output.status.code(), Some(0), "{mode}");
        let answers = records(&output);
        assert_eq!(answers.len(), 3, "{mode}");
        for (i, answer) in answers.iter().enumerate() {
            if i != bad {
                // A new controller drives the road after a failed one.
                assert_ne!(answer["outcome"], "ERROR", "{mode}: {answer}");
                continue;
            }
            assert_eq!(answer["outcome"], "ERROR", "{mode}: {answer}");
            assert_eq!(answer["reason"], "driver_failed");
            let error = answer["error"].as_str().unwrap_or_default();
            assert!(error.starts_with("the controller: at t = "), "{mode}: {error}");
            assert!(error.contains(says), "{mode}: {error}");
        }
    }
}

#[test]
fn a_controller_whose_stderr_is_not_text_drives_on() {
    // Its first stderr line closed wogan's reader, and its next write killed it (defect 4).
    if !python() {
        return;
    }
    let roads = reference_roads(2);
    let oracle = format!("cmd:python3 {REPO}/tests/python/faulty_controller.py bad-stderr 0 0");
    let output = wogan(&["simulate", "--oracle", &oracle], &roads);
    assert_eq!(output.status.code(), Some(0));
    let answers = records(&output);
    assert_eq!(answers.len(), 2);
    for answer in &answers {
        assert_ne!(answer["outcome"], "ERROR", "{answer}");
    }
}

#[test]
fn a_controller_slow_to_start_has_its_own_deadline_for_the_first_reply() {
    if !python() {
        return;
    }
    let dir = scratch_dir("controller-slow-start");
    let roads = reference_roads(2);
    let oracle = format!("cmd:python3 {REPO}/tests/python/faulty_controller.py slow-start 0 0");
    // Its 1.5 s start-up is within `start_timeout_s` (30 s), not within a step's 0.5 s.
    let config = write_file(&dir, "steps.json", r#"{"driver": {"step_timeout_s": 0.5}}"#);
    let output = wogan(
        &["simulate", "--oracle", &oracle, "--config", &config],
        &roads,
    );
    assert_eq!(output.status.code(), Some(0));
    let answers = records(&output);
    assert_eq!(answers.len(), 2);
    for answer in &answers {
        assert_ne!(answer["outcome"], "ERROR", "{answer}");
    }
    // Past `start_timeout_s` the first drive fails, saying so.
    let config = write_file(
        &dir,
        "start.json",
        r#"{"driver": {"step_timeout_s": 0.5, "start_timeout_s": 0.5}}"#,
    );
    let output = wogan(
        &["simulate", "--oracle", &oracle, "--config", &config],
        &roads,
    );
    let answers = records(&output);
    assert_eq!(answers[0]["outcome"], "ERROR", "{}", answers[0]);
    let error = answers[0]["error"].as_str().unwrap_or_default();
    assert!(
        error.contains("at t = 0.00 s: no answer within 0.500 s"),
        "{error}"
    );
}

#[test]
fn a_controller_that_always_fails_stops_the_run_and_no_file_starts_one() {
    if !python() {
        return;
    }
    let dir = scratch_dir("controller-always");
    let out = dir.join("run.jsonl");
    let oracle = format!("cmd:python3 {REPO}/tests/python/faulty_controller.py always-crash 0 0");
    let output = wogan(
        &[
            "run",
            "--oracle",
            &oracle,
            "--max-tests",
            "40",
            "--seed",
            "2",
            "--quiet",
            "--max-failed-drives",
            "3",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("the controller failed 3 roads in a row"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines[0]["oracle"], "controller");
    assert!(lines[0]["config"]["driver"]["command"]
        .as_str()
        .unwrap()
        .contains("faulty_controller.py"));
    let tests: Vec<&Value> = lines.iter().filter(|r| r["type"] == "test").collect();
    assert_eq!(tests.len(), 3);
    assert!(tests.iter().all(|t| t["reason"] == "driver_failed"));
    assert_eq!(lines.last().unwrap()["type"], "summary");
    // The run's header names the command; exporting it starts nothing and says how to give it.
    let canary = dir.join("canary");
    let planted = text.replacen(
        lines[0]["config"]["driver"]["command"].as_str().unwrap(),
        &format!("touch {}", canary.display()),
        1,
    );
    let planted_run = write_file(&dir, "planted.jsonl", &planted);
    let export = wogan(
        &["export", &planted_run, dir.join("export").to_str().unwrap()],
        "",
    );
    assert_eq!(export.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&export.stderr);
    assert!(stderr.contains("--oracle cmd:"), "{stderr}");
    let _ = wogan(&["replay", &planted_run], "");
    let _ = wogan(
        &["report", &planted_run, "--out", dir.to_str().unwrap()],
        "",
    );
    assert!(!canary.exists(), "a file started a process");
}

#[test]
fn sigterm_ends_a_drive_whose_controller_hangs_at_once_and_leaves_no_process() {
    if !python() {
        return;
    }
    let dir = scratch_dir("controller-sigterm");
    // A deadline of ten minutes: only the stop may end the wait.
    let config = write_file(&dir, "slow.json", r#"{"driver": {"step_timeout_s": 600}}"#);
    let marker = dir.to_str().unwrap().to_owned();
    let oracle = format!("cmd:python3 {REPO}/tests/python/faulty_controller.py hang 2 5 {marker}");
    let roads = write_file(&dir, "roads.jsonl", &reference_roads(3));
    let mut child = spawn(&["simulate", "--oracle", &oracle, "--config", &config, &roads]);
    let done = watchdog(&child, Duration::from_secs(120));
    // The first road is answered; the second hangs at its fifth step.
    let mut stdout = child.stdout.take().unwrap();
    let mut first = [0u8; 1];
    stdout.read_exact(&mut first).unwrap();
    Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    let mut rest = String::new();
    stdout.read_to_string(&mut rest).unwrap();
    let status = child.wait().unwrap();
    done.store(true, Ordering::SeqCst);
    assert_eq!(status.code(), Some(130));
    assert_eq!(
        rest.lines().count(),
        1,
        "only the first road answered: {rest}"
    );
    if let Ok(left) = Command::new("pgrep").args(["-f", &marker]).output() {
        assert!(left.stdout.is_empty(), "controllers left running");
    }
}
