//! End-to-end tests of a camera network in ONNX as the driver (`--oracle onnx:FILE`): our
//! dave2-proxy exported to ONNX (tests/fixtures/onnx/, made by
//! scripts/reference/export_dave2_onnx.py) drives every reference road as dave2-proxy does; bad
//! models are refused before any drive, naming the file; a NaN answer ends that drive as ERROR;
//! a run records the model and its checksum, and no file names the model to load.

use crate::common::{records, scratch_dir, wogan, write_file};
use serde_json::Value;

/// The repository's root.
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

fn fixture(name: &str) -> String {
    format!("{REPO}/tests/fixtures/onnx/{name}")
}

/// The settings under which the fixture is dave2-proxy: no crop, dave2-proxy's speed controller.
const AS_DAVE2_PROXY: &str =
    r#"{"driver": {"crop_top_rows": 0, "crop_bottom_rows": 0, "throttle": "speed-controller"}}"#;

#[test]
fn the_exported_student_drives_every_reference_road_as_dave2_proxy() {
    let dir = scratch_dir("onnx-reference");
    let config = write_file(&dir, "as-proxy.json", AS_DAVE2_PROXY);
    let roads = std::fs::read_to_string(format!("{REPO}/tests/reference/roads.jsonl")).unwrap();
    let oracle = format!("onnx:{}", fixture("dave2-proxy.onnx"));
    let network = wogan(
        &[
            "simulate", "--oracle", &oracle, "--config", &config, "--jobs", "2",
        ],
        &roads,
    );
    assert_eq!(
        network.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&network.stderr)
    );
    let proxy = wogan(
        &["simulate", "--oracle", "dave2-proxy", "--jobs", "2"],
        &roads,
    );
    assert_eq!(proxy.status.code(), Some(0));
    let (a, b) = (records(&network), records(&proxy));
    assert_eq!(a.len(), 300);
    assert_eq!(b.len(), 300);
    let mut failed = 0;
    for (i, (a, b)) in a.iter().zip(&b).enumerate() {
        assert_eq!(a["outcome"], b["outcome"], "road {i}: {a} vs {b}");
        let (x, y) = (
            a["max_bolp"].as_f64().unwrap(),
            b["max_bolp"].as_f64().unwrap(),
        );
        assert!((x - y).abs() <= 1e-3, "road {i}: max_bolp {x} vs {y}");
        failed += usize::from(a["outcome"] == "FAIL");
    }
    // Both outcomes occur, so agreement says something.
    assert!(failed > 0 && failed < 300, "{failed} of 300 failed");
}

#[test]
fn bad_models_are_refused_before_any_drive_naming_the_file() {
    let dir = scratch_dir("onnx-bad");
    let road = std::fs::read_to_string(format!("{REPO}/tests/reference/roads.jsonl"))
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_owned();
    let garbage = write_file(
        &dir,
        "garbage.onnx",
        "this is not a protobuf \u{1}\u{2}\u{3}",
    );
    let config = write_file(&dir, "as-proxy.json", AS_DAVE2_PROXY);
    for (model, says) in [
        (garbage.clone(), "is not an ONNX model wogan can run"),
        (fixture("rank2.onnx"), "rank 4"),
        (fixture("three_outputs.onnx"), "its outputs hold 3 numbers"),
        (
            format!("{}/missing.onnx", dir.display()),
            "cannot read ONNX model",
        ),
    ] {
        let oracle = format!("onnx:{model}");
        for command in [
            vec!["simulate", "--oracle", &oracle, "--config", &config],
            vec![
                "run",
                "--oracle",
                &oracle,
                "--config",
                &config,
                "--max-tests",
                "3",
            ],
        ] {
            let output = wogan(&command, &format!("{road}\n"));
            assert_eq!(output.status.code(), Some(2), "{command:?}");
            assert!(output.stdout.is_empty(), "{command:?}: nothing driven");
            let stderr = String::from_utf8_lossy(&output.stderr);
            let file = std::path::Path::new(&model)
                .file_name()
                .unwrap()
                .to_str()
                .unwrap();
            assert!(stderr.contains(says) && stderr.contains(file), "{stderr}");
        }
    }
    // The competition's crop does not fit the 66-row fixture: named before any drive.
    let oracle = format!("onnx:{}", fixture("dave2-proxy.onnx"));
    let output = wogan(&["simulate", "--oracle", &oracle], &format!("{road}\n"));
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("driver.crop_top_rows"), "{stderr}");
    // A NaN at run time ends that drive as ERROR with the reason.
    let oracle = format!("onnx:{}", fixture("nan_on_road.onnx"));
    let output = wogan(
        &["simulate", "--oracle", &oracle, "--config", &config],
        &format!("{road}\n{road}\n"),
    );
    assert_eq!(output.status.code(), Some(0));
    let answers = records(&output);
    assert_eq!(answers.len(), 2);
    for a in &answers {
        assert_eq!(
            (&a["outcome"], &a["reason"]),
            (&Value::from("ERROR"), &Value::from("driver_failed"))
        );
        let error = a["error"].as_str().unwrap();
        assert!(error.contains("nan_on_road.onnx answered NaN"), "{error}");
    }
}

#[test]
fn a_run_records_the_model_and_no_file_names_one() {
    let dir = scratch_dir("onnx-trust");
    let config = write_file(&dir, "as-proxy.json", AS_DAVE2_PROXY);
    let out = dir.join("run.jsonl");
    let oracle = format!("onnx:{}", fixture("dave2-proxy.onnx"));
    let output = wogan(
        &[
            "run",
            "--oracle",
            &oracle,
            "--config",
            &config,
            "--max-tests",
            "6",
            "--seed",
            "3",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let header: Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    assert_eq!(header["oracle"], "onnx");
    // Judged as the competition's DAVE-2 experiment.
    assert_eq!(header["config"]["sim"]["oob_tolerance"], 0.10);
    assert_eq!(header["config"]["sim"]["speed_limit_kmh"], 25.0);
    let driver = &header["config"]["driver"];
    assert_eq!(driver["model"], fixture("dave2-proxy.onnx").as_str());
    let sha = driver["model_sha256"].as_str().unwrap();
    assert_eq!(sha.len(), 64);
    assert_eq!(driver["throttle"], "speed-controller");
    // A config file may tune the network, never name the model.
    let naming = write_file(
        &dir,
        "naming.json",
        r#"{"driver": {"model": "other.onnx"}}"#,
    );
    let refused = wogan(&["simulate", "--oracle", &oracle, "--config", &naming], "");
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("driver.model"));
    // Export does not load the model the run file names.
    let export = wogan(
        &[
            "export",
            out.to_str().unwrap(),
            dir.join("export").to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(export.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&export.stderr).contains("--oracle onnx:"));
    // Replaying with another model than the run's warns; with the same, it does not.
    let same = wogan(
        &[
            "replay",
            "--oracle",
            &oracle,
            "--config",
            &config,
            out.to_str().unwrap(),
        ],
        "",
    );
    assert!(!String::from_utf8_lossy(&same.stderr).contains("SHA-256"));
    let other = dir.join("copy.onnx");
    let mut bytes = std::fs::read(fixture("dave2-proxy.onnx")).unwrap();
    // The producer name's last byte: another file, the same network.
    let at = bytes.windows(5).position(|w| w == b"onnx.").unwrap() + 5;
    bytes[at] = b'P';
    std::fs::write(&other, bytes).unwrap();
    let changed = wogan(
        &[
            "replay",
            "--oracle",
            &format!("onnx:{}", other.display()),
            "--config",
            &config,
            out.to_str().unwrap(),
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&changed.stderr);
    assert!(
        stderr.contains("SHA-256") && stderr.contains(sha),
        "{stderr}"
    );
}
