//! End-to-end tests of `wogan export`: the competition's layout written from runs made here
//! (each test driven again, its records checked against what the pipeline reads), the SBST budget's
//! boundary, runs that do not replay, and the directory it writes to: new or empty, an earlier
//! export replaced only with `--force`, nothing else ever removed, and never its own input.

use crate::common::{entry_names, scratch_dir, wogan, wogan_ok};
use crate::report::{fixture, path_str, read};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// A WOGAN run of 30 tests made by this build (seed 3), made once per test binary.
fn fresh_run() -> &'static Path {
    static RUN: OnceLock<PathBuf> = OnceLock::new();
    RUN.get_or_init(|| {
        let path = scratch_dir("export-run").join("run.jsonl");
        wogan_ok(
            &[
                "run",
                "--quiet",
                "--max-tests",
                "30",
                "--seed",
                "3",
                "--out",
                path_str(&path),
            ],
            "",
        );
        path
    })
}

/// The JSON lines of a file.
fn json_lines(path: &Path) -> Vec<Value> {
    read(path)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect()
}

/// The test records of a run file.
fn tests_of(path: &Path) -> Vec<Value> {
    json_lines(path)
        .into_iter()
        .filter(|r| r["type"] == "test")
        .collect()
}
/// Runs `wogan export RUN DIR` (with `--force` when `force`) and returns its exit status and
/// standard error.
fn export(run: &Path, dir: &str, force: bool) -> (Option<i32>, String) {
    let mut args = vec!["export", path_str(run), dir];
    if force {
        args.push("--force");
    }
    let output = wogan(&args, "");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn export_writes_the_competition_layout_and_round_trips_through_validate() {
    let out = scratch_dir("export");
    let run = fresh_run();
    wogan_ok(
        &["export", "--format", "sbst", path_str(run), path_str(&out)],
        "",
    );
    let records = tests_of(run);
    assert_eq!(records.len(), 30);
    let outcome = |o: &str| {
        records
            .iter()
            .filter(|t| t["outcome"] == o)
            .count()
            .to_string()
    };
    let csv = read(&out.join("generation_stats.csv"));
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(
        rows[0],
        "test_generated,test_valid,test_invalid,test_passed,test_failed,test_in_error,\
         real_time_generation,real_time_execution,simulated_time_execution"
    );
    let row: Vec<&str> = rows[1].split(',').collect();
    // Every test handed to the executor was valid: wogan validates before it proposes.
    assert_eq!(row[..3], ["30", "30", "0"]);
    assert_eq!(
        row[3..6],
        [outcome("PASS"), outcome("FAIL"), outcome("ERROR")]
    );
    assert!(
        row[6..]
            .iter()
            .all(|v| v.parse::<f64>().is_ok_and(|s| s > 0.0)),
        "{row:?}"
    );
    let simulated: f64 = records
        .iter()
        .map(|t| t["sim_time_s"].as_f64().unwrap())
        .sum();
    assert!((row[8].parse::<f64>().unwrap() - simulated).abs() < 1e-9);

    let mut objects = Vec::new();
    for record in &records {
        let id = record["id"].as_u64().unwrap();
        let text = read(&out.join(format!("test.{id:04}.json")));
        let object: Value = serde_json::from_str(&text).expect("a test object");
        assert_eq!(object["id"], id);
        for key in ["road_points", "interpolated_points", "validation_message"] {
            assert!(object.get(key).is_some(), "{key} missing");
        }
        assert_eq!(object["test_outcome"], record["outcome"]);
        for key in ["MAX_CURV", "DIR_COV", "STD_SA", "MEAN_LP", "MAX_LP"] {
            assert_eq!(object["features"][key], record[key], "{key}");
        }
        check_execution_data(&object, record);
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
    // The pipeline's OOB summary: one OOB per out-of-lane failure (the seed's roads are all
    // placed on the analysis's resampling).
    let oobs = records
        .iter()
        .filter(|t| t["reason"] == "out_of_lane")
        .count();
    let oob_stats = read(&out.join("oob_stats.csv"));
    let summary: Vec<&str> = oob_stats
        .lines()
        .nth(1)
        .expect("a row")
        .split(',')
        .collect();
    assert_eq!(summary[0], oobs.to_string(), "{oob_stats}");
}

/// The test object's records are the drive the run recorded, in the pipeline's layout: its last
/// `timer` is the drive's simulated time, `is_oob` holds only at the end of an out-of-lane
/// failure, and the pipeline's features recomputed from them are the record's.
fn check_execution_data(object: &Value, record: &Value) {
    let data = object["execution_data"].as_array().expect("execution_data");
    assert!(!data.is_empty());
    assert!(data
        .iter()
        .all(|r| r.as_array().is_some_and(|f| f.len() == 17)));
    let last = data.last().unwrap();
    assert_eq!(last[0], record["sim_time_s"]);
    let oob: Vec<bool> = data.iter().map(|r| r[12].as_bool().unwrap()).collect();
    let out_of_lane = record["reason"] == "out_of_lane";
    assert_eq!(oob.iter().filter(|&&o| o).count(), usize::from(out_of_lane));
    assert_eq!(*oob.last().unwrap(), out_of_lane);
    let description = object["description"].as_str().unwrap();
    assert_eq!(
        description.starts_with("Car drove out of the lane "),
        out_of_lane
    );
    if out_of_lane {
        // Where the record says the car left its lane.
        assert_eq!(last[1][0], record["oob"]["x"]);
        assert_eq!(last[1][1], record["oob"]["y"]);
    }
    // STD_SA (population SD of `steering`) and MEAN_LP (mean `oob_distance`), as the pipeline's
    // test_analysis computes them from the records.
    let column = |i: usize| -> Vec<f64> { data.iter().map(|r| r[i].as_f64().unwrap()).collect() };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let steering = column(4);
    let m = mean(&steering);
    let sd =
        (steering.iter().map(|s| (s - m) * (s - m)).sum::<f64>() / steering.len() as f64).sqrt();
    let close = |a: f64, b: &Value| (a - b.as_f64().unwrap()).abs() < 1e-9;
    assert!(close(sd, &record["STD_SA"]), "{sd} vs {}", record["STD_SA"]);
    assert!(close(mean(&column(15)), &record["MEAN_LP"]));
}

#[test]
fn export_keeps_the_pipelines_accounting_at_the_budgets_boundary() {
    let out = scratch_dir("export-budget");
    let run = out.join("run.jsonl");
    wogan_ok(
        &[
            "run",
            "--quiet",
            "--seed",
            "5",
            "--generation-budget",
            "1h",
            "--execution-budget",
            "300",
            "--out",
            path_str(&run),
        ],
        "",
    );
    let dir = out.join("sbst");
    wogan_ok(&["export", path_str(&run), path_str(&dir)], "");
    let records = tests_of(&run);
    let (last, kept) = records.split_last().unwrap();
    assert_eq!(last["beyond_budget"], true);
    // The test beyond the budget is not kept: no file, no outcome, no simulated time; it counts
    // as generated and valid.
    assert!(!dir
        .join(format!("test.{:04}.json", last["id"].as_u64().unwrap()))
        .exists());
    let files = entry_names(&dir)
        .iter()
        .filter(|n| n.starts_with("test."))
        .count();
    assert_eq!(files, kept.len());
    let csv = read(&dir.join("generation_stats.csv"));
    let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let handed = records.len().to_string();
    assert_eq!(row[..3], [handed.as_str(), handed.as_str(), "0"]);
    let decided: usize = row[3..6].iter().map(|v| v.parse::<usize>().unwrap()).sum();
    assert_eq!(decided, kept.len());
    let simulated: f64 = kept.iter().map(|t| t["sim_time_s"].as_f64().unwrap()).sum();
    assert!((row[8].parse::<f64>().unwrap() - simulated).abs() < 1e-9 && simulated < 300.0);
    let charged: f64 = records
        .iter()
        .map(|t| t["sbst_generation_ms"].as_f64().unwrap())
        .sum();
    assert!((row[6].parse::<f64>().unwrap() - charged / 1000.0).abs() < 1e-9);
}

#[test]
fn export_of_a_truncated_run_counts_its_test_records() {
    let out = scratch_dir("export-truncated");
    let text = read(fresh_run());
    let mut lines: Vec<&str> = text
        .lines()
        .filter(|l| !l.contains(r#""type":"summary""#))
        .collect();
    lines.push(r#"{"type":"test","id":"x"}"#);
    let bad_line = lines.len();
    let run = out.join("cut.jsonl");
    std::fs::write(&run, lines.join("\n")).expect("write");
    let dir = out.join("sbst");
    let output = wogan(
        &["export", "--format", "sbst", path_str(&run), path_str(&dir)],
        "",
    );
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains(&format!("cut.jsonl:{bad_line}: bad test record")),
        "{stderr}"
    );
    let csv = read(&dir.join("generation_stats.csv"));
    let row: Vec<&str> = csv.lines().nth(1).expect("a row").split(',').collect();
    assert_eq!(row[..3], ["30", "30", "0"]);
    assert!(dir.join("test.0030.json").exists());
}

#[test]
fn a_run_that_does_not_replay_is_not_exported() {
    let out = scratch_dir("export-replay");
    // A test whose record was altered after the run: driving it again gives another drive.
    let text = read(fresh_run());
    let altered = text.replacen(r#""sim_time_s":"#, r#""sim_time_s":1e-3,"was":"#, 1);
    assert_ne!(altered, text);
    let run = out.join("altered.jsonl");
    std::fs::write(&run, altered).expect("write");
    let dir = out.join("sbst");
    let (status, stderr) = export(&run, path_str(&dir), false);
    assert_eq!(status, Some(2), "{stderr}");
    assert!(stderr.contains("test 1 does not replay"), "{stderr}");
    assert_eq!(
        entry_names(&dir),
        Vec::<String>::new(),
        "a half export was left"
    );
    // A run of an older version (its driver's tuning in `sim.beamng_ai`, read as the driver's
    // section): its settings are read, but its drives are not this version's.
    let (status, stderr) = export(
        Path::new(&fixture("wogan.seed3.jsonl")),
        path_str(&dir),
        false,
    );
    assert_eq!(status, Some(2), "{stderr}");
    assert!(
        stderr.contains("test 1 does not replay") && stderr.contains("another wogan version"),
        "{stderr}"
    );
    assert_eq!(entry_names(&dir), Vec::<String>::new());
}

#[test]
fn export_refuses_a_directory_that_holds_other_files() {
    let out = scratch_dir("export-busy");
    let dir = out.join("sbst");
    std::fs::create_dir(&dir).expect("a directory");
    std::fs::write(dir.join("notes.txt"), "mine").expect("write");
    let run = fresh_run();
    for force in [false, true] {
        let (status, stderr) = export(run, path_str(&dir), force);
        assert_eq!(status, Some(2), "--force {force}: {stderr}");
        assert!(
            stderr.contains(path_str(&dir)) && stderr.contains("notes.txt"),
            "--force {force}: {stderr}"
        );
    }
    // Nothing was written, nothing removed.
    assert_eq!(entry_names(&dir), ["notes.txt"]);
    assert_eq!(read(&dir.join("notes.txt")), "mine");
}

#[test]
fn export_replaces_an_earlier_export_only_with_force() {
    let out = scratch_dir("export-force");
    let dir = out.join("sbst");
    wogan_ok(&["export", path_str(fresh_run()), path_str(&dir)], "");
    // 30 tests, generation_stats.csv and oob_stats.csv.
    assert_eq!(entry_names(&dir).len(), 32);
    // The header and the first 10 tests of the same run.
    let text = read(fresh_run());
    let short: Vec<&str> = text
        .lines()
        .filter(|l| l.contains(r#""type":"header""#) || l.contains(r#""type":"test""#))
        .take(1 + 10)
        .collect();
    let run = out.join("short.jsonl");
    std::fs::write(&run, short.join("\n")).expect("write");
    assert!(
        short[10].contains(r#""type":"test","id":10,"#),
        "{}",
        short[10]
    );

    let (status, stderr) = export(&run, path_str(&dir), false);
    assert_eq!(status, Some(2), "{stderr}");
    assert!(
        stderr.contains(path_str(&dir)) && stderr.contains("--force"),
        "{stderr}"
    );
    assert_eq!(
        entry_names(&dir).len(),
        32,
        "an export without --force removed files"
    );

    // With --force the earlier export's tests 11 to 30 do not linger beside the new one's.
    let (status, stderr) = export(&run, path_str(&dir), true);
    assert_eq!(status, Some(0), "{stderr}");
    let mut expected: Vec<String> = (1..=10).map(|id| format!("test.{id:04}.json")).collect();
    expected.insert(0, "generation_stats.csv".to_owned());
    expected.insert(1, "oob_stats.csv".to_owned());
    assert_eq!(entry_names(&dir), expected);
    let csv = read(&dir.join("generation_stats.csv"));
    let row: Vec<&str> = csv.lines().nth(1).expect("a row").split(',').collect();
    assert_eq!(row[1], "10", "{csv}");

    // Anything else in the directory stops --force before it removes anything.
    std::fs::write(dir.join("notes.txt"), "mine").expect("write");
    let (status, stderr) = export(fresh_run(), path_str(&dir), true);
    assert_eq!(status, Some(2), "{stderr}");
    assert!(
        stderr.contains(path_str(&dir)) && stderr.contains("notes.txt"),
        "{stderr}"
    );
    expected.push("notes.txt".to_owned());
    expected.sort();
    assert_eq!(entry_names(&dir), expected);
}

#[test]
fn export_refuses_to_write_over_its_input() {
    let dir = scratch_dir("export-input");
    let original = read(fresh_run());
    // The directory as typed with a trailing slash, so that the error shows it apart from the
    // run file's path.
    let dir_given = format!("{}/", path_str(&dir));
    for name in ["test.0001.json", "generation_stats.csv", "run.jsonl"] {
        let run = dir.join(name);
        std::fs::write(&run, &original).expect("write");
        for force in [false, true] {
            let (status, stderr) = export(&run, &dir_given, force);
            assert_eq!(status, Some(2), "{name}, --force {force}: {stderr}");
            assert!(
                stderr.contains(path_str(&run)) && stderr.contains(&dir_given),
                "{name}, --force {force}: {stderr}"
            );
            assert_eq!(read(&run), original, "{name} was written over");
            assert_eq!(entry_names(&dir), [name], "--force {force}");
        }
        std::fs::remove_file(&run).expect("remove");
    }
}
