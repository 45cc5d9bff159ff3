//! Cases known to have failed, pinned so that the sample keeps checking them once fixed.

use super::*;

pub(super) fn pinned_cases() -> Vec<Case> {
    let mut near_duplicates = Case::new(
        "pinned: validate --map-size 1e308, two points near 1e300 (panicked: capacity overflow)"
            .into(),
        Target::Validate,
    );
    near_duplicates
        .args
        .extend(["--map-size".into(), "1e308".into()]);
    near_duplicates.stdin = b"[[1e300,1e300],[1e300,1.0000000000001e300]]\n".to_vec();

    let config_case = |label: &str, config: &str| {
        let mut case = Case::new(label.into(), Target::Run);
        for arg in [
            "--config",
            "config.json",
            "--max-tests",
            "3",
            "--budget",
            "2s",
            "--quiet",
        ] {
            case.arg(arg);
        }
        case.file("config.json", config.as_bytes().to_vec());
        case.note(format!("config.json: {config}"));
        case
    };
    let mut huge_timeout = Case::new(
        "pinned: run --executor-timeout 18446744073709551615s (panicked: overflow adding to an instant)"
            .into(),
        Target::Run,
    );
    for arg in [
        "--executor",
        "cmd:true",
        "--executor-timeout",
        "18446744073709551615s",
        "--max-tests",
        "3",
        "--quiet",
    ] {
        huge_timeout.arg(arg);
    }
    vec![
        near_duplicates,
        huge_timeout,
        config_case(
            "pinned: run --config with sim.physics_hz 1e9 (hung)",
            r#"{"sim":{"physics_hz":1e9}}"#,
        ),
        config_case(
            "pinned: run --config with a generator of 4294967295 units (aborted)",
            r#"{"search":{"wogan":{"generator":{"hidden":4294967295}}}}"#,
        ),
    ]
}
