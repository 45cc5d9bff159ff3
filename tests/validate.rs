//! End-to-end tests of `wogan validate`.

use crate::common::{records, wogan};

#[test]
fn validates_the_reference_file_in_order() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/validator.jsonl"
    );
    let output = wogan(&["validate", path], "");
    assert_eq!(output.status.code(), Some(0));
    let records = records(&output);
    assert_eq!(records.len(), 2115);
    for (i, record) in records.iter().enumerate() {
        assert_eq!(record["type"], "verdict");
        assert_eq!(record["line"], i + 1);
        assert_eq!(
            record["valid"].as_bool().unwrap(),
            record["reason"].is_null()
        );
    }
}

#[test]
fn every_input_form_and_bad_lines_on_stdin() {
    let input = [
        r#"[[50, 50], [10, 10]]"#,
        "",
        r#"{"road_points": [[1, 10, -28, 8], [1, 50, -28, 8]], "interpolated_points": []}"#,
        "{not json",
        r#"{"type": "header", "seed": 1}"#,
        r#"{"type": "test", "id": 1, "road_points": [[100, 100], [100, 110]]}"#,
        r#"{"curvature": [0.0, 0.01, 0.02], "step": 15}"#,
        r#"{"road_points": [[1, 2], [3, "x"]]}"#,
    ]
    .join("\n");
    let output = wogan(&["validate", "-", "--details"], &input);
    assert_eq!(
        output.status.code(),
        Some(1),
        "bad lines give exit status 1"
    );
    let records = records(&output);
    let summary: Vec<(u64, &str, Option<&str>)> = records
        .iter()
        .map(|r| {
            (
                r["line"].as_u64().unwrap(),
                r["type"].as_str().unwrap(),
                r["reason"].as_str(),
            )
        })
        .collect();
    assert_eq!(
        summary,
        [
            (1, "verdict", None),
            (3, "verdict", Some("outside_map")),
            (4, "error", None),
            (6, "verdict", Some("too_short")),
            (7, "verdict", None),
            (8, "error", None),
        ]
    );
    assert!(records[0]["interpolated_points"].as_array().unwrap().len() > 20);
    assert_eq!(
        records[5]["error"],
        "road_points[1]: expected [x, y] with numbers"
    );
}

#[test]
fn map_size_changes_the_verdict() {
    let road = r#"[[150, 20], [150, 60]]"#;
    assert_eq!(records(&wogan(&["validate"], road))[0]["valid"], true);
    let small = records(&wogan(&["validate", "--map-size", "100"], road));
    assert_eq!(small[0]["reason"], "outside_map");
}

#[test]
fn bad_usage_exits_2_with_a_message() {
    let missing = wogan(&["validate", "no/such/file.jsonl"], "");
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("no/such/file.jsonl"));
    let bad_option = wogan(&["validate", "--map-size", "-3"], "");
    assert_eq!(bad_option.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad_option.stderr).contains("map-size"));
}
