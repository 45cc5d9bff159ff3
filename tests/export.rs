//! End-to-end tests of `wogan export`: the competition's layout written from the committed
//! fixture runs (see tests/report.rs), and the directory it writes to: new or empty, an earlier
//! export replaced only with `--force`, nothing else ever removed, and never its own input.

use crate::common::{scratch_dir, wogan, wogan_ok};
use crate::report::{fixture, path_str, read};
use serde_json::Value;
use std::path::Path;

/// The names of the entries of `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| {
            entry
                .expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
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

#[test]
fn export_refuses_a_directory_that_holds_other_files() {
    let out = scratch_dir("export-busy");
    let dir = out.join("sbst");
    std::fs::create_dir(&dir).expect("a directory");
    std::fs::write(dir.join("notes.txt"), "mine").expect("write");
    let run = fixture("wogan.seed3.jsonl");
    for force in [false, true] {
        let (status, stderr) = export(Path::new(&run), path_str(&dir), force);
        assert_eq!(status, Some(2), "--force {force}: {stderr}");
        assert!(
            stderr.contains(path_str(&dir)) && stderr.contains("notes.txt"),
            "--force {force}: {stderr}"
        );
    }
    // Nothing was written, nothing removed.
    assert_eq!(names(&dir), ["notes.txt"]);
    assert_eq!(read(&dir.join("notes.txt")), "mine");
}

#[test]
fn export_replaces_an_earlier_export_only_with_force() {
    let out = scratch_dir("export-force");
    let dir = out.join("sbst");
    wogan_ok(
        &["export", &fixture("wogan.seed3.jsonl"), path_str(&dir)],
        "",
    );
    assert_eq!(names(&dir).len(), 31);
    // The header and the first 10 tests of the same run.
    let text = read(Path::new(&fixture("wogan.seed3.jsonl")));
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
        names(&dir).len(),
        31,
        "an export without --force removed files"
    );

    // With --force the earlier export's tests 11 to 30 do not linger beside the new one's.
    let (status, stderr) = export(&run, path_str(&dir), true);
    assert_eq!(status, Some(0), "{stderr}");
    let mut expected: Vec<String> = (1..=10).map(|id| format!("test.{id:04}.json")).collect();
    expected.insert(0, "generation_stats.csv".to_owned());
    assert_eq!(names(&dir), expected);
    let csv = read(&dir.join("generation_stats.csv"));
    let row: Vec<&str> = csv.lines().nth(1).expect("a row").split(',').collect();
    assert_eq!(row[1], "10", "{csv}");

    // Anything else in the directory stops --force before it removes anything.
    std::fs::write(dir.join("notes.txt"), "mine").expect("write");
    let (status, stderr) = export(
        Path::new(&fixture("wogan.seed3.jsonl")),
        path_str(&dir),
        true,
    );
    assert_eq!(status, Some(2), "{stderr}");
    assert!(
        stderr.contains(path_str(&dir)) && stderr.contains("notes.txt"),
        "{stderr}"
    );
    expected.push("notes.txt".to_owned());
    expected.sort();
    assert_eq!(names(&dir), expected);
}

#[test]
fn export_refuses_to_write_over_its_input() {
    let dir = scratch_dir("export-input");
    let original = read(Path::new(&fixture("wogan.seed3.jsonl")));
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
            assert_eq!(names(&dir), [name], "--force {force}");
        }
        std::fs::remove_file(&run).expect("remove");
    }
}
