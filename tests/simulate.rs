//! End-to-end tests of `wogan simulate`.

use crate::common::{records, scratch_dir, wogan, wogan_ok, write_file};
use serde_json::{json, Value};

fn reference_roads(count: usize) -> String {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/roads.jsonl"
    );
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().take(count).collect::<Vec<_>>().join("\n")
}

fn without_timing(mut record: Value) -> Value {
    record.as_object_mut().unwrap().remove("execution_ms");
    record
}

#[test]
fn results_are_identical_with_any_number_of_jobs() {
    let roads = reference_roads(40);
    let one = records(&wogan(&["simulate"], &roads));
    let two = records(&wogan(&["simulate", "--jobs", "2"], &roads));
    assert_eq!(one.len(), 40);
    for (i, (a, b)) in one.iter().zip(&two).enumerate() {
        assert_eq!(a["line"], i + 1);
        assert_eq!(without_timing(a.clone()), without_timing(b.clone()));
        for field in [
            "max_bolp",
            "min_lane_distance_m",
            "fitness_distance",
            "sim_time_s",
            "MAX_CURV",
            "DIR_COV",
            "STD_SA",
            "MEAN_LP",
            "MAX_LP",
        ] {
            assert!(a[field].is_number(), "line {} lacks {field}", i + 1);
        }
    }
}

#[test]
fn a_config_file_tunes_the_driver_and_names_what_it_cannot_use() {
    let dir = scratch_dir("simulate-config");
    let write = |name: &str, text: &str| write_file(&dir, name, text);
    let roads = reference_roads(20);
    let plain = records(&wogan_ok(&["simulate"], &roads));
    // Planned for twice the lateral acceleration, the driver takes bends faster and nearer the
    // lane's edge.
    let bold = write(
        "bold.json",
        r#"{"driver": {"lateral_grip_per_aggression": 1.5}}"#,
    );
    let tuned = records(&wogan_ok(&["simulate", "--config", &bold], &roads));
    let total = |records: &[Value]| -> f64 {
        records
            .iter()
            .map(|r| r["max_bolp"].as_f64().unwrap())
            .sum()
    };
    assert!(
        total(&tuned) > total(&plain) + 1.0,
        "{} vs {}",
        total(&tuned),
        total(&plain)
    );

    for (name, text, expected) in [
        (
            "search.json",
            r#"{"search": {}}"#,
            "\"search\" is for `wogan run`",
        ),
        (
            "typo.json",
            r#"{"driver": {"agression": 0.5}}"#,
            "driver.agression",
        ),
        (
            "range.json",
            r#"{"driver": {"aggression": -1}}"#,
            "driver.aggression",
        ),
    ] {
        let path = write(name, text);
        let output = wogan(&["simulate", "--config", &path], &roads);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(expected), "{name}: {stderr}");
        assert!(output.stdout.is_empty(), "{name}");
    }
}

#[test]
fn invalid_roads_are_not_driven_and_bad_lines_reported() {
    let input = "{\"id\": \"t1\", \"road_points\": [[1, 10], [1, 50]]}\nnot json\n{\"id\": 7, \"curvature\": [0, 0, 0]}\n{\"curvature\": [0, 0, 0]}";
    let output = wogan(&["simulate"], input);
    assert_eq!(output.status.code(), Some(1));
    let records = records(&output);
    assert_eq!(records[0]["outcome"], "INVALID");
    assert_eq!(records[0]["reason"], "outside_map");
    assert_eq!(records[1]["type"], "error");
    assert_eq!(records[1]["line"], 2);
    assert_eq!(records[2]["outcome"], "PASS");
    // Answers echo the input's `id` (an executor's answer names its road so), and only then.
    assert_eq!(
        (&records[0]["id"], &records[2]["id"]),
        (&json!("t1"), &json!(7))
    );
    assert!(records[3].get("id").is_none(), "{}", records[3]);
}

#[test]
fn trace_files_hold_the_road_and_the_samples() {
    let dir = std::env::temp_dir().join(format!("wogan-trace-{}", std::process::id()));
    let roads = reference_roads(2);
    let output = wogan(&["simulate", "--trace", dir.to_str().unwrap()], &roads);
    assert_eq!(output.status.code(), Some(0));
    let text = std::fs::read_to_string(dir.join("trace.2.jsonl")).expect("trace of line 2");
    let lines: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines[0]["type"], "road");
    assert!(lines[0]["interpolated_points"].as_array().unwrap().len() > 60);
    let samples = &lines[1..];
    assert!(samples.len() > 100, "20 Hz or more over several seconds");
    assert!(samples
        .iter()
        .all(|s| s["type"] == "sample" && s["speed_kmh"].is_number() && s["bolp"].is_number()));
    let times: Vec<f64> = samples.iter().map(|s| s["t"].as_f64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn camera_writes_the_drivers_view_as_png() {
    let dir = std::env::temp_dir().join(format!("wogan-camera-{}", std::process::id()));
    let road = reference_roads(1);
    let out = dir.to_str().unwrap();
    for (args, channels) in [
        (&["camera", "--at", "2.5,40", "--out", out][..], 2u8),
        (&["camera", "--at", "10", "--gray", "--out", out], 0),
    ] {
        let output = wogan(args, &road);
        assert_eq!(
            output.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let name = if channels == 2 {
            "camera.40.png"
        } else {
            "camera.10.png"
        };
        let png = std::fs::read(dir.join(name)).expect("a PNG was written");
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        // IHDR: width 200, height 66, 8 bits, colour type 2 (RGB) or 0 (gray).
        assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 200);
        assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 66);
        assert_eq!(png[25], channels);
    }
    let invalid = wogan(&["camera", "--out", out], "[[1, 1], [2, 2]]");
    assert_eq!(invalid.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn dave2_proxy_drives_with_its_own_defaults() {
    let output = wogan(
        &[
            "simulate",
            "--oracle",
            "dave2-proxy",
            "--trace",
            std::env::temp_dir()
                .join(format!("wogan-dave2-{}", std::process::id()))
                .to_str()
                .unwrap(),
        ],
        &reference_roads(3),
    );
    assert_eq!(output.status.code(), Some(0));
    for record in records(&output) {
        assert!(
            ["PASS", "FAIL"].contains(&record["outcome"].as_str().unwrap()),
            "{record}"
        );
        assert!(record["STD_SA"].is_number());
    }
    let trace = std::env::temp_dir()
        .join(format!("wogan-dave2-{}", std::process::id()))
        .join("trace.1.jsonl");
    let text = std::fs::read_to_string(&trace).unwrap();
    let top_speed = text
        .lines()
        .skip(1)
        .map(|l| {
            serde_json::from_str::<Value>(l).unwrap()["speed_kmh"]
                .as_f64()
                .unwrap()
        })
        .fold(0.0, f64::max);
    // Its speed limit is 25 km/h, not beamng-ai-proxy's 70.
    assert!(top_speed > 15.0 && top_speed < 27.5, "{top_speed}");
}

#[test]
fn execution_data_in_the_answer_is_the_drive_in_the_pipelines_layout() {
    let dir = crate::common::scratch_dir("execution-data");
    let roads = reference_roads(100);
    // At a tolerance of 0.3 a few of these roads push beamng-ai-proxy out of its lane.
    let tolerance = ["--oob-tolerance", "0.3"];
    let plain = records(&wogan(&["simulate", tolerance[0], tolerance[1]], &roads));
    let with = records(&wogan(
        &[
            "simulate",
            tolerance[0],
            tolerance[1],
            "--execution-data",
            "--trace",
            dir.to_str().unwrap(),
        ],
        &roads,
    ));
    assert_eq!(plain.len(), 100);
    let mut exits = 0;
    for (line, (a, b)) in plain.iter().zip(&with).enumerate() {
        // The option adds the records and changes nothing else.
        let mut b = b.clone();
        let data = b.as_object_mut().unwrap().remove("execution_data");
        assert_eq!(without_timing(a.clone()), without_timing(b.clone()));
        let data = data.expect("execution_data");
        let data = data.as_array().unwrap();
        let trace = std::fs::read_to_string(dir.join(format!("trace.{}.jsonl", line + 1))).unwrap();
        let samples: Vec<Value> = trace
            .lines()
            .skip(1)
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        // One record per sample: the sample's time, position and BOLP.
        assert_eq!(data.len(), samples.len());
        for (record, sample) in data.iter().zip(&samples) {
            assert_eq!(record[0], sample["t"]);
            assert_eq!((&record[1][0], &record[1][1]), (&sample["x"], &sample["y"]));
            assert_eq!(record[16], sample["bolp"]);
        }
        assert_eq!(data.last().unwrap()[0], b["sim_time_s"]);
        // Where the car first left its lane: the first record the pipeline marks `is_oob`.
        let first_oob = data.iter().find(|r| r[12] == true);
        match (&b["oob"], first_oob) {
            (Value::Null, None) => assert_ne!(b["reason"], "out_of_lane"),
            (exit, Some(record)) => {
                exits += 1;
                assert_eq!(b["reason"], "out_of_lane");
                assert_eq!((&exit["x"], &exit["y"]), (&record[1][0], &record[1][1]));
                assert_eq!(exit["t_s"], record[0]);
                assert!(exit["side"] == "left" || exit["side"] == "right");
                assert!(exit["sbst_side"] == "LEFT" || exit["sbst_side"] == "RIGHT");
            }
            (exit, None) => panic!("line {}: exit {exit} without an is_oob record", line + 1),
        }
    }
    assert!(
        exits > 0,
        "some of the reference roads push beamng-ai-proxy out at 0.3"
    );
}

#[test]
fn the_example_pipeline_executor_drives_through_one_child() {
    // The example executor for the competition's pipeline, against a stand-in of its interface.
    crate::common::python_check("check_example_executor.py");
}
