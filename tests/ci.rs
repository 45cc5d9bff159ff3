//! End-to-end tests of the CI commands: `run --fail-on/--junit`, `replay`, `suite` and the saved
//! generator (`run --save-generator`, `sample`, `run --generator`), their exit statuses, their
//! JUnit XML and their bad input.

use crate::common::{records, scratch_dir, spawn, watchdog, wogan, write_file};
use serde_json::Value;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::Command;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The path as an argument.
fn arg(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// A seeded 50-test beamng-ai-proxy run into `dir/name`; its test records.
fn smoke_run(dir: &Path, name: &str, extra: &[&str]) -> (std::process::Output, Vec<Value>) {
    let out = dir.join(name);
    let mut args = vec![
        "run",
        "--max-tests",
        "50",
        "--seed",
        "5",
        "--quiet",
        "--out",
        arg(&out),
    ];
    args.extend_from_slice(extra);
    let output = wogan(&args, "");
    let text = std::fs::read_to_string(&out).unwrap_or_default();
    let tests = text
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).expect("JSON"))
        .filter(|r| r["type"] == "test")
        .collect();
    (output, tests)
}

/// A suite's `tests`, `failures`, `errors` and `skipped`.
type Counts = (usize, usize, usize, usize);
/// Each test case's name with its failure or error message, if any.
type Cases = Vec<(String, Option<String>)>;

/// The JUnit report at `path`, parsed: the counts of its one suite and its cases.
fn junit(path: &Path) -> (Counts, Cases) {
    let text = std::fs::read_to_string(path).expect("a JUnit file");
    let document = roxmltree::Document::parse(&text).expect("the JUnit report is XML");
    let suite = document
        .descendants()
        .find(|n| n.has_tag_name("testsuite"))
        .expect("a testsuite");
    let count = |name: &str| {
        suite
            .attribute(name)
            .and_then(|v| v.parse().ok())
            .unwrap_or(99_999)
    };
    let cases = suite
        .children()
        .filter(|n| n.has_tag_name("testcase"))
        .map(|case| {
            let failure = case
                .children()
                .find(|n| n.has_tag_name("failure") || n.has_tag_name("error"))
                .and_then(|f| f.attribute("message").map(str::to_owned));
            (case.attribute("name").unwrap_or("").to_owned(), failure)
        })
        .collect();
    (
        (
            count("tests"),
            count("failures"),
            count("errors"),
            count("skipped"),
        ),
        cases,
    )
}

/// The file without its `time="..."` attributes: what two runs of one seed share.
fn without_times(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("a file");
    text.split("time=\"")
        .enumerate()
        .map(|(i, part)| {
            if i == 0 {
                part
            } else {
                part.split_once('"').map_or(part, |(_, rest)| rest)
            }
        })
        .collect()
}

#[test]
fn fail_on_failure_turns_a_failing_road_into_exit_1_with_a_junit_report() {
    let dir = scratch_dir("ci-smoke");
    let xml = dir.join("smoke.xml");
    let (output, tests) = smoke_run(
        &dir,
        "smoke.jsonl",
        &["--fail-on", "failure", "--junit", arg(&xml)],
    );
    let failing: Vec<&Value> = tests.iter().filter(|t| t["outcome"] == "FAIL").collect();
    assert!(
        !failing.is_empty(),
        "seed 5 finds a failing road in 50 tests"
    );
    assert_eq!(
        output.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let ((n, failures, errors, skipped), cases) = junit(&xml);
    assert_eq!((n, failures, errors, skipped), (50, failing.len(), 0, 0));
    let failed_case = cases
        .iter()
        .find(|(name, _)| {
            *name == format!("test {} (wogan)", failing[0]["id"])
                || name.starts_with(&format!("test {} ", failing[0]["id"]))
        })
        .expect("the failing test's case");
    let message = failed_case.1.as_deref().expect("a failure message");
    assert!(
        message.starts_with("FAIL, out_of_lane: max BOLP "),
        "{message}"
    );
    assert!(message.contains("left its lane over the"), "{message}");
    // The same seed again: the same verdict and the same report but for its timings.
    let xml_again = dir.join("again.xml");
    let (again, _) = smoke_run(
        &dir,
        "again.jsonl",
        &["--fail-on", "failure", "--junit", arg(&xml_again)],
    );
    assert_eq!(again.status.code(), Some(1));
    assert_eq!(
        without_times(&xml),
        without_times(&xml_again).replace("again.jsonl", "smoke.jsonl")
    );
    // `--fail-on never`, the default, keeps today's exit status.
    let (never, _) = smoke_run(&dir, "never.jsonl", &[]);
    assert_eq!(never.status.code(), Some(0));
    // No output over an input or over another output.
    let (same, _) = smoke_run(&dir, "x.jsonl", &["--junit", arg(&dir.join("x.jsonl"))]);
    assert_eq!(same.status.code(), Some(2));
}

#[test]
fn replay_drives_saved_roads_again_and_says_what_changed() {
    let dir = scratch_dir("ci-replay");
    let (_, tests) = smoke_run(&dir, "run.jsonl", &[]);
    let failing = tests.iter().filter(|t| t["outcome"] == "FAIL").count();
    let run = dir.join("run.jsonl");
    let xml = dir.join("replay.xml");
    let output = wogan(
        &["replay", arg(&run), "--jobs", "2", "--junit", arg(&xml)],
        "",
    );
    assert_eq!(output.status.code(), Some(1), "a road fails now");
    let answers = records(&output);
    assert_eq!(answers.len(), 50);
    for (answer, test) in answers.iter().zip(&tests) {
        assert_eq!(answer["type"], "replay");
        assert_eq!(answer["name"], format!("test {}", test["id"]));
        // The same driver and settings: every drive replays exactly.
        assert_eq!(answer["outcome"], test["outcome"]);
        assert_eq!(answer["recorded_outcome"], test["outcome"]);
        assert_eq!(answer["max_bolp"], test["max_bolp"]);
        assert_eq!(answer["changed"], false);
    }
    let ((n, failures, _, _), _) = junit(&xml);
    assert_eq!((n, failures), (50, failing));
    // Only a change fails the build with --fail-on changed.
    let output = wogan(&["replay", arg(&run), "--fail-on", "changed"], "");
    assert_eq!(output.status.code(), Some(0));
    // Bad input: named by file and line, the good roads still driven, exit 2.
    let text = std::fs::read_to_string(&run).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let truncated = &lines[3][..lines[3].len() / 2];
    lines[3] = truncated;
    let bad = write_file(
        &dir,
        "bad.jsonl",
        &(lines.join("\n") + "\n{\"type\":\"result\",\"line\":1}\n"),
    );
    let output = wogan(&["replay", &bad, arg(&dir.join("missing.jsonl"))], "");
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(records(&output).len(), 49);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("bad.jsonl:4: not JSON"), "{stderr}");
    assert!(
        stderr.contains("a `result` record holds no road"),
        "{stderr}"
    );
    assert!(stderr.contains("missing.jsonl"), "{stderr}");
    // A road that no longer validates (on a smaller map) is bad input too, and still answered.
    let output = wogan(&["replay", arg(&run), "--map-size", "100"], "");
    assert_eq!(output.status.code(), Some(2));
    assert!(records(&output).iter().any(|r| r["outcome"] == "INVALID"));
}

#[test]
fn a_suite_keeps_failing_roads_once_the_most_different_first_and_never_loses_any() {
    let dir = scratch_dir("ci-suite");
    let run = dir.join("run.jsonl");
    let output = wogan(
        &[
            "run",
            "--max-tests",
            "150",
            "--seed",
            "2",
            "--quiet",
            "--out",
            arg(&run),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(0));
    let failing = std::fs::read_to_string(&run)
        .unwrap()
        .lines()
        .filter(|l| l.contains("\"outcome\":\"FAIL\""))
        .count();
    assert!(failing >= 4, "seed 2 fails {failing} roads in 150 tests");
    let suite = dir.join("suite.jsonl");
    let add = |max: Option<&str>| {
        let mut args = vec!["suite", "add", arg(&run), "--to", arg(&suite)];
        if let Some(max) = max {
            args.extend(["--max", max]);
        }
        wogan(&args, "")
    };
    assert_eq!(add(Some("3")).status.code(), Some(0));
    let first = std::fs::read_to_string(&suite).unwrap();
    assert_eq!(first.lines().count(), 4, "a header and 3 roads");
    assert!(first.starts_with("{\"type\":\"suite\",\"format\":\"wogan-suite\",\"version\":1}\n"));
    // Adding again: nothing is lost, nothing twice; the cap counts what is kept.
    assert_eq!(add(None).status.code(), Some(0));
    let second = std::fs::read_to_string(&suite).unwrap();
    assert!(
        second.starts_with(&first),
        "the roads already kept stay first, unchanged"
    );
    assert_eq!(second.lines().count(), 1 + failing);
    assert_eq!(add(None).status.code(), Some(0));
    assert_eq!(std::fs::read_to_string(&suite).unwrap(), second);
    let listed = wogan(&["suite", "list", arg(&suite)], "");
    assert_eq!(listed.status.code(), Some(0));
    let listing = String::from_utf8_lossy(&listed.stdout);
    assert!(
        listing.starts_with(&format!("{failing} road(s) in ")),
        "{listing}"
    );
    assert!(listing.contains("FAIL max BOLP"), "{listing}");
    // The suite replays: every road fails as recorded.
    let replayed = wogan(&["replay", arg(&suite), "--fail-on", "changed"], "");
    assert_eq!(replayed.status.code(), Some(0));
    assert!(records(&replayed)
        .iter()
        .all(|r| r["outcome"] == "FAIL" && r["changed"] == false));
    // A file that is not a suite is refused as --to and left as it was.
    let foreign = write_file(
        &dir,
        "notes.jsonl",
        "{\"type\":\"header\",\"version\":\"0.1.0\"}\n",
    );
    let output = wogan(&["suite", "add", arg(&run), "--to", &foreign], "");
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("notes.jsonl:1: not a wogan suite"));
    assert_eq!(
        std::fs::read_to_string(&foreign).unwrap(),
        "{\"type\":\"header\",\"version\":\"0.1.0\"}\n"
    );
    // Nor may the suite be one of the runs read.
    let output = wogan(&["suite", "add", arg(&run), "--to", arg(&run)], "");
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn a_saved_generator_samples_the_roads_a_generator_run_drives() {
    let dir = scratch_dir("ci-generator");
    let generator = dir.join("gen.json");
    let output = wogan(
        &[
            "run",
            "--max-tests",
            "40",
            "--seed",
            "4",
            "--quiet",
            "--out",
            arg(&dir.join("train.jsonl")),
            "--save-generator",
            arg(&generator),
        ],
        "",
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let sample = |seed: &str| {
        wogan(
            &[
                "sample",
                "--generator",
                arg(&generator),
                "-n",
                "10",
                "--seed",
                seed,
            ],
            "",
        )
    };
    let sampled = sample("2");
    assert_eq!(sampled.status.code(), Some(0));
    assert_eq!(
        sampled.stdout,
        sample("2").stdout,
        "same file and seed, same roads"
    );
    assert_ne!(sampled.stdout, sample("3").stdout);
    let roads = records(&sampled);
    assert_eq!(roads.len(), 10);
    let predictions: Vec<f64> = roads
        .iter()
        .filter_map(|r| r["predicted_fitness"].as_f64())
        .collect();
    assert!(
        predictions.windows(2).all(|w| w[0] >= w[1]),
        "ranked best first: {predictions:?}"
    );
    // A run that chooses its tests with the generator drives exactly the sampled roads.
    let run = dir.join("generated.jsonl");
    let output = wogan(
        &[
            "run",
            "--generator",
            arg(&generator),
            "--max-tests",
            "10",
            "--seed",
            "2",
            "--quiet",
            "--out",
            arg(&run),
        ],
        "",
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = std::fs::read_to_string(&run).unwrap();
    let mut driven: Vec<String> = text
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|r| r["type"] == "test")
        .map(|r| r["road_points"].to_string())
        .collect();
    let mut drawn: Vec<String> = roads.iter().map(|r| r["road_points"].to_string()).collect();
    driven.sort();
    drawn.sort();
    assert_eq!(driven, drawn);
    assert!(text.starts_with("{\"type\":\"header\""));
    assert!(text.contains("\"algorithm\":\"wogan-generator\""));
    // Sampled roads are what replay and simulate read.
    let sampled_file = write_file(
        &dir,
        "sampled.jsonl",
        &String::from_utf8_lossy(&sampled.stdout),
    );
    let replayed = wogan(&["replay", &sampled_file], "");
    assert!(matches!(replayed.status.code(), Some(0 | 1)));
    assert_eq!(records(&replayed).len(), 10);
    // A damaged, truncated or foreign generator file is refused before anything is sampled.
    let text = std::fs::read_to_string(&generator).unwrap();
    let damaged = write_file(
        &dir,
        "damaged.json",
        &text.replacen("\"seed\":4", "\"seed\":5", 1),
    );
    let truncated = write_file(&dir, "truncated.json", &text[..text.len() / 2]);
    let foreign = write_file(&dir, "foreign.json", "{\"format\":\"onnx\",\"version\":1}");
    let newer = write_file(
        &dir,
        "newer.json",
        &text.replacen("\"version\":1", "\"version\":7", 1),
    );
    for (file, says) in [
        (&damaged, "checksum"),
        (&truncated, "not a whole generator file"),
        (&foreign, "is not a wogan generator"),
        (&newer, "version: generator layout 7"),
    ] {
        let output = wogan(&["sample", "--generator", file], "");
        assert_eq!(output.status.code(), Some(2), "{file}");
        assert!(output.stdout.is_empty());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains(says), "{file}: {stderr}");
    }
    // The default road shape and least turn are not written, so files from before the choice
    // keep their checksums; others are, and a run from the file compares and chooses roads by
    // them.
    assert!(!text.contains("road_shape") && !text.contains("min_road_turn_rad"));
    let directions = dir.join("directions.json");
    let save = [
        "run",
        "--max-tests",
        "12",
        "--road-shape",
        "directions",
        "--min-road-turn",
        "1.5",
        "--save-generator",
        arg(&directions),
    ];
    assert_eq!(wogan(&save, "").status.code(), Some(0));
    let text = std::fs::read_to_string(&directions).unwrap();
    assert!(text.contains("\"road_shape\":\"directions\""));
    assert!(text.contains("\"min_road_turn_rad\":1.5"));
    let generated = wogan(
        &["run", "--generator", arg(&directions), "--max-tests", "2"],
        "",
    );
    assert_eq!(generated.status.code(), Some(0));
    let config = &records(&generated)[0]["config"];
    assert_eq!(config["road_shape"], "directions");
    assert_eq!(config["min_road_turn_rad"], 1.5);
    // Random search trains no generator to save.
    let output = wogan(
        &[
            "run",
            "--algorithm",
            "random",
            "--max-tests",
            "3",
            "--save-generator",
            arg(&dir.join("r.json")),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(2));
}

/// Sends SIGTERM to `child`.
fn terminate(child: &std::process::Child) {
    Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill runs");
}

#[test]
fn sigterm_ends_replay_and_sample_with_what_they_did_written() {
    let dir = scratch_dir("ci-sigterm");
    let run = dir.join("run.jsonl");
    let generator = dir.join("gen.json");
    let output = wogan(
        &[
            "run",
            "--max-tests",
            "40",
            "--seed",
            "6",
            "--quiet",
            "--out",
            arg(&run),
            "--save-generator",
            arg(&generator),
        ],
        "",
    );
    assert_eq!(output.status.code(), Some(0));
    // Replay: the first answer read, then SIGTERM: exit 130 with every answer given kept.
    let roads = "tests/reference/roads.jsonl";
    let roads = format!("{}/../../{roads}", env!("CARGO_MANIFEST_DIR"));
    let mut child = spawn(&[
        "replay",
        &roads,
        "--oracle",
        "dave2-proxy",
        "--junit",
        arg(&dir.join("r.xml")),
    ]);
    let done = watchdog(&child, Duration::from_secs(300));
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut first = String::new();
    stdout.read_line(&mut first).unwrap();
    terminate(&child);
    let mut rest = String::new();
    stdout.read_to_string(&mut rest).unwrap();
    let status = child.wait().unwrap();
    done.store(true, Ordering::SeqCst);
    assert_eq!(status.code(), Some(130));
    let answered = 1 + rest.lines().count();
    assert!(answered < 300, "{answered} of 300 roads answered");
    let ((cases, _, _, _), _) = junit(&dir.join("r.xml"));
    assert_eq!(cases, answered, "the JUnit report holds what was driven");
    // Sample: once it says it is drawing, SIGTERM: the roads drawn so far, ranked, and exit 130.
    let mut child = spawn(&["sample", "--generator", arg(&generator), "-n", "100000"]);
    let done = watchdog(&child, Duration::from_secs(300));
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut said = String::new();
    stderr.read_line(&mut said).unwrap();
    assert!(
        said.starts_with("wogan sample: drawing 100000 road(s)"),
        "{said}"
    );
    terminate(&child);
    let mut drawn = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut drawn)
        .unwrap();
    let status = child.wait().unwrap();
    done.store(true, Ordering::SeqCst);
    assert_eq!(status.code(), Some(130));
    let ranks: Vec<u64> = drawn
        .lines()
        .map(|l| {
            serde_json::from_str::<Value>(l).expect("JSON")["rank"]
                .as_u64()
                .unwrap()
        })
        .collect();
    assert!(ranks.len() < 100_000);
    assert!(ranks.iter().enumerate().all(|(i, r)| *r == i as u64 + 1));
}
