//! End-to-end test of a camera network trained elsewhere: a public Keras DAVE-2 of the Udacity
//! course (tests/fixtures/keras/), converted by examples/onnx/keras_to_onnx.py, drives wogan's car
//! under the `udacity` contract. The converter's own check (its ONNX against a numpy forward pass
//! of the `.h5` weights, and its refusals) runs first.
//!
//! The converter's Python packages are not build dependencies: `examples/onnx/setup.sh` makes
//! target/onnx-venv. Without it the test says so and checks nothing, unless WOGAN_REQUIRE_ONNX_VENV
//! is set (CI sets it, after running setup.sh), when it fails.

use crate::common::{records, scratch_dir, test_records, venv_python, wogan, write_file};
use std::process::Command;

/// The checkout.
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

#[test]
fn a_keras_dave2_from_the_udacity_course_drives_under_its_contract() {
    let Some(python) = venv_python(
        "onnx-venv",
        "examples/onnx/setup.sh",
        "WOGAN_REQUIRE_ONNX_VENV",
    ) else {
        return;
    };
    let script = |name: &str| format!("{REPO}/examples/onnx/{name}");
    let check = Command::new(&python)
        .arg(script("check_keras_to_onnx.py"))
        .output()
        .unwrap();
    assert!(
        check.status.success(),
        "{}{}",
        String::from_utf8_lossy(&check.stdout),
        String::from_utf8_lossy(&check.stderr)
    );

    let dir = scratch_dir("keras");
    let model = dir.join("dave2.onnx");
    let fixture = format!("{REPO}/tests/fixtures/keras/car-behavioral-cloning.h5");
    let converted = Command::new(&python)
        .args([
            &script("keras_to_onnx.py"),
            &fixture,
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        converted.status.success(),
        "{}",
        String::from_utf8_lossy(&converted.stderr)
    );
    let oracle = format!("onnx:{}", model.display());
    let udacity = write_file(
        &dir,
        "udacity.json",
        r#"{"driver": {"contract": "udacity"}}"#,
    );

    // Its contract's frames: it drives every road it is given to an end, no ERROR (whether it
    // keeps the lane is its own business: it learnt another world).
    let roads: String = std::fs::read_to_string(format!("{REPO}/tests/reference/roads.jsonl"))
        .unwrap()
        .lines()
        .take(12)
        .map(|l| format!("{l}\n"))
        .collect();
    let drove = wogan(
        &["simulate", "--oracle", &oracle, "--config", &udacity],
        &roads,
    );
    assert_eq!(
        drove.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&drove.stderr)
    );
    let results = records(&drove);
    assert_eq!(results.len(), 12);
    for r in &results {
        assert!(r["outcome"] == "PASS" || r["outcome"] == "FAIL", "{r}");
        assert!(r["sim_time_s"].as_f64().unwrap() > 0.0, "{r}");
    }

    // Under today's default contract the 66-row model is refused, naming the settings.
    let refused = wogan(&["simulate", "--oracle", &oracle], &roads);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_ne!(refused.status.code(), Some(0));
    assert!(
        stderr.contains("driver.crop_top_rows (80)") && stderr.contains("66-row"),
        "{stderr}"
    );

    // A run records the contract it drove under; an unknown contract is named.
    let out = dir.join("run.jsonl");
    let ran = wogan(
        &[
            "run",
            "--max-tests",
            "3",
            "--seed",
            "1",
            "--quiet",
            "--oracle",
            &oracle,
            "--config",
            &udacity,
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
    assert_eq!(test_records(&out).len(), 3);
    let header: serde_json::Value = serde_json::from_str(
        std::fs::read_to_string(&out)
            .unwrap()
            .lines()
            .next()
            .unwrap(),
    )
    .unwrap();
    assert_eq!(
        header["config"]["driver"]["contract"], "udacity",
        "{header}"
    );
    assert_eq!(
        header["config"]["driver"]["camera"]["width"], 320,
        "{header}"
    );
    let carla = write_file(&dir, "carla.json", r#"{"driver": {"contract": "carla"}}"#);
    let unknown = wogan(
        &["simulate", "--oracle", &oracle, "--config", &carla],
        &roads,
    );
    let stderr = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        stderr.contains("driver.contract: \"carla\" is not a contract; known: sbst2022, udacity"),
        "{stderr}"
    );
}
