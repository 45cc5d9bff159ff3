//! End-to-end tests of how `wogan` meets bad input and interruption: every case here broke the
//! tool once (a panic, an abort, a hang, lost answers, a misleading result or message).
//!
//! Streaming and signals are tested by protocol (read answer k before writing road k + 1; send
//! SIGTERM after k answers), never by time; a watchdog only keeps a broken build from hanging the
//! suite.

use crate::common::{records, scratch_dir, spawn, watchdog, wogan};
use serde_json::Value;
use std::io::{BufRead, BufReader, Write};
use std::process::Command;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The first `count` roads of the reference set, one JSON line each.
fn reference_roads(count: usize) -> Vec<String> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/roads.jsonl"
    );
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().take(count).map(str::to_owned).collect()
}

/// Exit status and standard error of `wogan ARGS` on `stdin`.
fn status_and_stderr(args: &[&str], stdin: &str) -> (Option<i32>, String, usize) {
    let output = wogan(args, stdin);
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
        output.stdout.len(),
    )
}

/// Asserts that `wogan ARGS` is refused as bad usage (exit 2), before any output, with a message
/// that contains `named`.
fn refused(args: &[&str], named: &str) {
    let (code, stderr, stdout_bytes) = status_and_stderr(args, "");
    assert_eq!(code, Some(2), "{args:?}: {stderr}");
    assert!(stderr.contains(named), "{args:?}: {stderr}");
    assert_eq!(stdout_bytes, 0, "{args:?} wrote output");
}

#[test]
fn simulate_answers_each_road_before_the_next_is_written() {
    let mut child = spawn(&["simulate"]);
    let done = watchdog(&child, Duration::from_secs(120));
    let mut stdin = child.stdin.take().unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    for (i, road) in reference_roads(3).iter().enumerate() {
        writeln!(stdin, "{road}").unwrap();
        stdin.flush().unwrap();
        // Road i's answer arrives while stdin stays open and road i + 1 is not yet written.
        let mut answer = String::new();
        stdout.read_line(&mut answer).unwrap();
        let answer: Value = serde_json::from_str(&answer).expect("a JSON answer");
        assert_eq!(answer["type"], "result");
        assert_eq!(answer["line"], i + 1);
    }
    drop(stdin);
    let status = child.wait().unwrap();
    done.store(true, Ordering::SeqCst);
    assert_eq!(status.code(), Some(0));
}

#[test]
fn sigterm_keeps_every_answer_given_and_exits_130() {
    let roads = reference_roads(300).join("\n") + "\n";
    let mut child = spawn(&["simulate", "--oracle", "dave2-proxy"]);
    let done = watchdog(&child, Duration::from_secs(300));
    let mut stdin = child.stdin.take().unwrap();
    // Write from another thread: the child may stop reading once it is told to stop.
    std::thread::spawn(move || {
        let _ = stdin.write_all(roads.as_bytes());
    });
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let k = 3;
    let mut lines = Vec::new();
    for _ in 0..k {
        let mut line = String::new();
        stdout.read_line(&mut line).unwrap();
        lines.push(line);
    }
    Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stdout, &mut rest).unwrap();
    lines.extend(rest.lines().map(|l| format!("{l}\n")));
    let status = child.wait().unwrap();
    done.store(true, Ordering::SeqCst);
    assert_eq!(status.code(), Some(130));
    assert!(
        lines.len() >= k && lines.len() < 300,
        "{} answers",
        lines.len()
    );
    for (i, line) in lines.iter().enumerate() {
        let answer: Value = serde_json::from_str(line).expect("only complete JSON answers");
        assert_eq!(answer["line"], i + 1);
        assert_ne!(
            answer["reason"], "interrupted",
            "a cut-short drive was reported"
        );
    }
}

#[test]
fn sizes_that_would_run_unbounded_are_refused_before_any_work() {
    // Panicked (capacity overflow) and took 18 s and 4 GB for one road at 1e9.
    refused(&["validate", "--map-size", "1e308"], "--map-size");
    refused(&["validate", "--map-size", "1e9"], "at most 2000");
    refused(
        &["run", "--map-size", "1e308", "--step-length", "1e300"],
        "--map-size",
    );
    refused(&["run", "--step-length", "1e300"], "--step-length");
    let dir = scratch_dir("unbounded");
    for (name, json, named) in [
        // Never ended and ignored signals.
        (
            "rate.json",
            r#"{"sim": {"physics_hz": 1e9}}"#,
            "physics_hz must be from 10 to 1000",
        ),
        // Aborted allocating memory.
        (
            "wide.json",
            r#"{"search": {"wogan": {"generator": {"hidden": 100000000}}}}"#,
            "wogan.generator.hidden must be from 1 to 512",
        ),
        // Trained to null losses and carried on.
        (
            "lr.json",
            r#"{"search": {"wogan": {"wgan": {"lr": 1e30}}}}"#,
            "wogan.wgan.lr must be above 0 and at most 1",
        ),
        (
            "timeout.json",
            r#"{"sim": {"timeout_speed_mps": 0}}"#,
            "timeout_speed_mps must be from 0.1 to 100",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, json).unwrap();
        refused(&["run", "--config", path.to_str().unwrap()], named);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_road_too_long_to_interpolate_gets_a_verdict_and_later_lines_are_answered() {
    let zigzag: Vec<[f64; 2]> = (0..30)
        .map(|i| [10.0 + 1900.0 * f64::from(i % 2), 10.0 + 60.0 * f64::from(i)])
        .collect();
    let input = format!(
        "{}\n[[1e300, 1e300], [1e300, 1.0000000000001e300]]\n{}\n",
        serde_json::to_string(&zigzag).unwrap(),
        reference_roads(1)[0]
    );
    let output = wogan(&["validate", "--map-size", "2000"], &input);
    let verdicts = records(&output);
    assert_eq!(verdicts.len(), 3);
    assert_eq!(verdicts[0]["reason"], "too_long");
    assert_eq!(verdicts[1]["reason"], "outside_map");
    assert_eq!(verdicts[2]["line"], 3);
}

#[test]
fn broken_weights_are_refused_on_load() {
    let dir = scratch_dir("weights");
    let good = dir.join("good.bin");
    // Weights written by the tool, then every value made +Inf.
    let output = wogan(
        &[
            "train-driver",
            "--out",
            good.to_str().unwrap(),
            "--roads",
            "1",
            "--epochs",
            "1",
        ],
        "",
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mut bytes = std::fs::read(&good).unwrap();
    for value in bytes[12..].chunks_exact_mut(4) {
        value.copy_from_slice(&f32::INFINITY.to_le_bytes());
    }
    let infinite = dir.join("inf.bin");
    std::fs::write(&infinite, &bytes).unwrap();
    let road = reference_roads(1)[0].clone();
    let (code, stderr, stdout_bytes) = status_and_stderr(
        &[
            "simulate",
            "--oracle",
            "dave2-proxy",
            "--driver-weights",
            infinite.to_str().unwrap(),
        ],
        &road,
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("weight 0 is inf"), "{stderr}");
    assert_eq!(stdout_bytes, 0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn no_output_replaces_an_input() {
    let dir = scratch_dir("clobber");
    let config = dir.join("c.json");
    let text = r#"{"sim": {"speed_limit_kmh": 50}}"#;
    std::fs::write(&config, text).unwrap();
    let path = config.to_str().unwrap();
    refused(
        &["run", "--config", path, "--out", path, "--max-tests", "2"],
        "is an input of the run",
    );
    assert_eq!(std::fs::read_to_string(&config).unwrap(), text);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_reader_that_goes_away_ends_the_run_quietly() {
    let mut child = spawn(&["run", "--max-tests", "40", "--quiet"]);
    let done = watchdog(&child, Duration::from_secs(300));
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut header = String::new();
    stdout.read_line(&mut header).unwrap();
    assert!(header.contains("\"header\""));
    // `| head -1`: the reader closes the pipe after one line.
    drop(stdout);
    let output = child.wait_with_output().unwrap();
    done.store(true, Ordering::SeqCst);
    assert_eq!(output.status.code(), Some(0));
    assert!(
        output.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn clear_messages_for_values_out_of_range() {
    // Each used to get clap's "unexpected argument" or a message that did not fit.
    refused(&["run", "--seed", "-1"], "--seed");
    refused(&["run", "--budget", "-5s"], "--budget");
    refused(
        &["run", "--init-fraction", "-0.1"],
        "strictly between 0 and 1",
    );
    refused(&["run", "--speed-limit", "0"], "above 0 and at most 300");
    refused(&["run", "--max-tests", "-3"], "--max-tests");
    for at in ["NaN", "-5"] {
        refused(&["camera", "--at", at, "--out", "/tmp/never"], "from 0 to");
    }
    let road = reference_roads(1)[0].clone();
    let dir = scratch_dir("camera-at");
    let output = wogan(
        &["camera", "--at", "1000", "--out", dir.to_str().unwrap()],
        &road,
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("the road is only"));
    std::fs::remove_dir_all(&dir).ok();
    // A directory as input names the path.
    let (code, stderr, _) = status_and_stderr(&["simulate", "/tmp"], "");
    assert_eq!(code, Some(2));
    assert!(stderr.contains("/tmp: it is a directory"), "{stderr}");
    // A config value of the wrong type is named by its field, not only its section.
    let dir = scratch_dir("config-path");
    let path = dir.join("bad.json");
    std::fs::write(&path, r#"{"search": {"wogan": {"target_decay": "slow"}}}"#).unwrap();
    refused(
        &["run", "--config", path.to_str().unwrap()],
        "search.wogan.target_decay: invalid type",
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn every_road_gets_an_answer_whatever_its_record_type_and_layout() {
    let road = reference_roads(1)[0].clone();
    let mut as_header: Value = serde_json::from_str(&road).unwrap();
    as_header["type"] = "header".into();
    // A competition test pretty-printed over several lines is one road.
    let pretty =
        serde_json::to_string_pretty(&serde_json::from_str::<Value>(&road).unwrap()).unwrap();
    let input = format!("{as_header}\n{{\"type\": \"summary\"}}\n{pretty}\n");
    let output = wogan(&["validate"], &input);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let verdicts = records(&output);
    assert_eq!(verdicts.len(), 2, "{verdicts:?}");
    assert_eq!(
        (verdicts[0]["line"].clone(), verdicts[0]["valid"].clone()),
        (1.into(), true.into())
    );
    assert_eq!(
        (verdicts[1]["line"].clone(), verdicts[1]["valid"].clone()),
        (3.into(), true.into())
    );
}
