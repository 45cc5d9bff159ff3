//! End-to-end tests of `wogan dataset`: frames and labels in the Udacity simulator's layout, the
//! same for the same seed, from a road file too; bad settings refused naming them; Ctrl-C leaves a
//! valid, shorter dataset.

use crate::common::{scratch_dir, signal_and_wait, spawn, watchdog, wogan, write_file};
use std::path::Path;
use std::time::Duration;

fn rows(dir: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(dir.join("driving_log.csv"))
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

/// Every row names three pictures that exist, and labels in the simulator's ranges.
fn assert_valid(dir: &Path) -> usize {
    let rows = rows(dir);
    for row in &rows {
        assert_eq!(row.len(), 7, "{row:?}");
        for picture in &row[..3] {
            let bytes = std::fs::read(dir.join(picture)).unwrap_or_default();
            assert!(bytes.starts_with(b"\x89PNG"), "{picture} of {row:?}");
        }
        let value = |i: usize| row[i].parse::<f64>().unwrap();
        assert!((-1.0..=1.0).contains(&value(3)), "steering {row:?}");
        assert!((0.0..=1.0).contains(&value(4)) && (0.0..=1.0).contains(&value(5)));
        assert!((0.0..60.0).contains(&value(6)), "speed in mph {row:?}");
    }
    rows.len()
}

/// Makes a dataset in `out` with `options`, which must succeed.
fn make(out: &Path, options: &[&str]) {
    let made = wogan(
        &[&["dataset", "--out", out.to_str().unwrap()][..], options].concat(),
        "",
    );
    assert_eq!(
        made.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
}

#[test]
fn a_dataset_is_the_simulators_layout_and_the_same_for_the_same_seed() {
    let dir = scratch_dir("dataset");
    let (a, b) = (dir.join("a"), dir.join("b"));
    for out in [&a, &b] {
        make(out, &["--frames", "40", "--seed", "2"]);
    }
    assert_eq!(assert_valid(&a), 40);
    assert_eq!(rows(&a), rows(&b));
    assert_eq!(
        rows(&a)[0][..3],
        [
            "IMG/center_0000001.png",
            "IMG/left_0000001.png",
            "IMG/right_0000001.png"
        ]
    );
    for picture in ["IMG/center_0000040.png", "IMG/left_0000017.png"] {
        assert_eq!(
            std::fs::read(a.join(picture)).unwrap(),
            std::fs::read(b.join(picture)).unwrap()
        );
    }
    // The side cameras see other pictures than the centre one.
    assert_ne!(
        std::fs::read(a.join("IMG/left_0000020.png")).unwrap(),
        std::fs::read(a.join("IMG/center_0000020.png")).unwrap()
    );
    // Another seed, other roads.
    let c = dir.join("c");
    make(&c, &["--frames", "40", "--seed", "3"]);
    assert_ne!(rows(&a), rows(&c));

    // A road file's roads, a non-empty folder and bad settings.
    let roads = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/roads.jsonl"
    ))
    .unwrap();
    let file = write_file(
        &dir,
        "roads.jsonl",
        &roads.lines().take(2).collect::<Vec<_>>().join("\n"),
    );
    let d = dir.join("d");
    make(&d, &["--frames", "200", "--roads", &file]);
    assert_eq!(assert_valid(&d), 200);
    for (args, says) in [
        (
            vec!["--out", a.to_str().unwrap()],
            "the folder is not empty",
        ),
        (vec!["--out", "x", "--frames", "0"], "--frames"),
        (vec!["--out", "x", "--record-hz", "100"], "--record-hz"),
        (
            vec!["--out", "x", "--contract", "carla"],
            "unknown contract \"carla\"",
        ),
    ] {
        let refused = wogan(&[&["dataset"][..], &args].concat(), "");
        let stderr = String::from_utf8_lossy(&refused.stderr);
        assert_ne!(refused.status.code(), Some(0), "{args:?}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

#[test]
fn ctrl_c_leaves_a_valid_shorter_dataset() {
    let dir = scratch_dir("dataset-interrupted");
    let out = dir.join("d");
    let mut child = spawn(&[
        "dataset",
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "1000000",
    ]);
    let done = watchdog(&child, Duration::from_secs(120));
    let log = out.join("driving_log.csv");
    let mut waited = 0;
    while std::fs::read_to_string(&log).map_or(0, |t| t.lines().count()) < 30 {
        std::thread::sleep(Duration::from_millis(50));
        waited += 1;
        assert!(waited < 2400, "no 30th frame");
    }
    let (status, stderr) = signal_and_wait(&mut child, "-INT", &done);
    assert_eq!(status.code(), Some(130), "{stderr}");
    let frames = assert_valid(&out);
    assert!((30..1_000_000).contains(&frames), "{frames}");
    assert!(
        stderr.contains(&format!("wrote {frames} frames")),
        "{stderr}"
    );
}
