//! End-to-end tests of `wogan train-driver`.

use crate::common::{records, scratch_dir, wogan, wogan_ok};

/// Writes `json` to a file `name` in the scratch directory `test`.
fn config_file(test: &str, name: &str, json: &str) -> std::path::PathBuf {
    let path = scratch_dir(test).join(name);
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn a_config_file_sets_what_the_options_do_not_and_the_weights_drive() {
    let config = config_file(
        "train-config",
        "noise.json",
        r#"{"noise_max_rad": 0.05, "epochs": 3, "teacher": {"lookahead_base_m": 4.0}}"#,
    );
    let weights = config.with_file_name("student.bin");
    let output = wogan_ok(
        &[
            "train-driver",
            "--config",
            config.to_str().unwrap(),
            "--roads",
            "2",
            "--epochs",
            "1",
            "--out",
            weights.to_str().unwrap(),
        ],
        "",
    );
    let record = &records(&output)[0];
    assert_eq!(record["type"], "driver");
    assert_eq!(record["config"]["noise_max_rad"], 0.05);
    assert_eq!(record["config"]["teacher"]["lookahead_base_m"], 4.0);
    assert_eq!(record["config"]["training_roads"], 2, "the option wins");
    assert_eq!(
        record["config"]["epochs"], 1,
        "the option wins over the file"
    );
    assert_eq!(record["config"]["max_curvature_per_m"], 0.03, "a default");
    let road = r#"{"curvature": [0.0, 0.01, 0.0, -0.01, 0.0]}"#;
    let driven = wogan_ok(
        &[
            "simulate",
            "--oracle",
            "dave2-proxy",
            "--driver-weights",
            weights.to_str().unwrap(),
        ],
        road,
    );
    assert_eq!(records(&driven).len(), 1);
}

#[test]
fn bad_settings_are_named_before_any_training() {
    for (json, named) in [
        (r#"{"noise_max": 0.05}"#, "noise_max"),
        (r#"{"noise_hold_s": [1.0, 0.5]}"#, "noise_hold_s"),
        (r#"{"max_curvature_per_m": 0.5}"#, "max_curvature_per_m"),
        (r#"{"epochs": "four"}"#, "four"),
        (
            r#"{"teacher": {"control_hz": 0}}"#,
            "teacher.control_hz must be positive",
        ),
    ] {
        let config = config_file("train-bad", "bad.json", json);
        let output = wogan(
            &[
                "train-driver",
                "--config",
                config.to_str().unwrap(),
                "--out",
                "/dev/null",
            ],
            "",
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{json}: {stderr}");
        assert!(stderr.contains(named), "{json}: {stderr}");
        assert!(output.stdout.is_empty());
    }
}
