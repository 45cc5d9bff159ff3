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

/// `wogan dataset --out OUT --frames FRAMES EXTRA...`.
fn dataset(out: &Path, frames: &str, extra: &[&str]) -> std::process::Output {
    let out = out.to_str().expect("a UTF-8 path");
    wogan(
        &[&["dataset", "--out", out, "--frames", frames][..], extra].concat(),
        "",
    )
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

#[test]
fn a_driver_that_gives_no_frame_stops_the_dataset_naming_its_error() {
    // A controller that is not one fails every drive before its first sample: the dataset used
    // to start one road after another for ever (hostile input, defect 3).
    let dir = scratch_dir("dataset-no-frame");
    for (limit, says) in [
        (None, "5 drives in a row"),
        (Some("2"), "2 drives in a row"),
    ] {
        let out = dir.join(format!("d{}", limit.unwrap_or("5")));
        let mut args = vec![
            "dataset",
            "--out",
            out.to_str().unwrap(),
            "--frames",
            "3",
            "--oracle",
            "cmd:false",
        ];
        if let Some(limit) = limit {
            args.extend(["--max-failed-drives", limit]);
        }
        let child = spawn(&args);
        let done = watchdog(&child, Duration::from_secs(120));
        let ended = child.wait_with_output().unwrap();
        done.store(true, std::sync::atomic::Ordering::SeqCst);
        let stderr = String::from_utf8_lossy(&ended.stderr);
        assert_eq!(ended.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(says), "{stderr}");
        assert!(
            stderr.contains("the driver's last error: the controller: "),
            "{stderr}"
        );
        assert_eq!(assert_valid(&out), 0);
    }
}

#[test]
fn hostile_road_files_are_named_and_skipped_or_refused() {
    let dir = scratch_dir("dataset-hostile-roads");
    let road = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/roads.jsonl"
    ))
    .unwrap()
    .lines()
    .next()
    .unwrap()
    .to_owned();
    // A byte order mark, a line that is not JSON and one that holds no road: the road is driven,
    // the bad lines named (defect 21).
    let file = write_file(
        &dir,
        "bom.jsonl",
        &format!("\u{feff}{road}\nnot json\n{{\"x\": 1}}\n"),
    );
    let out = dir.join("bom");
    let made = dataset(&out, "20", &["--roads", &file]);
    let stderr = String::from_utf8_lossy(&made.stderr);
    assert_eq!(made.status.code(), Some(0), "{stderr}");
    assert_eq!(assert_valid(&out), 20);
    assert!(
        stderr.contains("line 2") && stderr.contains("skipped"),
        "{stderr}"
    );
    // A line with no end is refused past 16 MiB, in bounded memory (it aborted at 2 GB, defect 6).
    let zero = dir.join("zero");
    let refused = dataset(&zero, "5", &["--roads", "/dev/zero"]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("longer than 16 MiB") && stderr.contains("no valid road"),
        "{stderr}"
    );
    // `--out` that is a file, or a link to nothing, is said as such.
    let plain = write_file(&dir, "afile", "");
    let dangling = dir.join("dangling");
    let _ = std::os::unix::fs::symlink(dir.join("nothing-here"), &dangling);
    for (out, says) in [
        (plain.as_str(), "exists and is not a folder"),
        (dangling.to_str().unwrap(), "a link to nothing"),
    ] {
        let refused = wogan(&["dataset", "--out", out, "--frames", "5"], "");
        let stderr = String::from_utf8_lossy(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(says), "{out}: {stderr}");
    }
}

#[test]
fn ctrl_c_is_answered_while_a_pipe_of_roads_stalls() {
    // A FIFO whose writer sends nothing: the roads never come (defect 14).
    let dir = scratch_dir("dataset-fifo");
    let fifo = dir.join("roads");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let mut writer = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!("exec sleep 120 > '{}'", fifo.display()))
        .spawn()
        .unwrap();
    let out = dir.join("d");
    let mut child = spawn(&[
        "dataset",
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "100",
        "--roads",
        fifo.to_str().unwrap(),
    ]);
    let done = watchdog(&child, Duration::from_secs(60));
    // The dataset's log exists once the roads file is open and the folders are made.
    let mut waited = 0;
    while !out.join("driving_log.csv").exists() {
        std::thread::sleep(Duration::from_millis(50));
        waited += 1;
        assert!(waited < 1200, "the dataset never started");
    }
    let (status, stderr) = signal_and_wait(&mut child, "-INT", &done);
    let _ = writer.kill();
    let _ = writer.wait();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted: wrote 0 frames"), "{stderr}");
}

#[test]
fn a_map_too_small_for_random_roads_is_said_and_a_fitting_one_is_used() {
    // `--map-size` was ignored for random roads (defect 21).
    let dir = scratch_dir("dataset-map-size");
    let small = dir.join("small");
    let refused = dataset(&small, "5", &["--map-size", "50"]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--map-size 50: no valid random road"),
        "{stderr}"
    );
    assert!(
        !small.exists(),
        "no folder is made for a dataset that cannot be"
    );
    let (wide, usual) = (dir.join("wide"), dir.join("usual"));
    make(&wide, &["--frames", "20", "--map-size", "1000"]);
    make(&usual, &["--frames", "20"]);
    assert_ne!(rows(&wide), rows(&usual));
}

#[test]
fn a_full_disk_leaves_whole_rows_and_their_pictures_only() {
    // A row cut by a full disk was left half written (defect 13). The disk: a small tmpfs in a
    // mount namespace of its own (root, as CI runs).
    let dir = scratch_dir("dataset-full-disk");
    let mounted = std::process::Command::new("unshare")
        .args(["-m", "true"])
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI runs as root: unshare -m must work"
        );
        eprintln!("unshare -m is not permitted here (not root): the full-disk test needs it");
        return;
    }
    let disk = dir.join("disk");
    let kept = dir.join("kept");
    std::fs::create_dir_all(&disk).unwrap();
    let script = format!(
        "mount -t tmpfs -o size=496k tmpfs '{disk}' && '{wogan}' dataset --out '{disk}/ds' --frames 5000; \
         status=$?; cp -r '{disk}/ds' '{kept}'; exit $status",
        disk = disk.display(),
        kept = kept.display(),
        wogan = env!("CARGO_BIN_EXE_wogan"),
    );
    let ran = std::process::Command::new("unshare")
        .args(["-m", "sh", "-c", &script])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&ran.stderr);
    assert_eq!(ran.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("No space left on device"), "{stderr}");
    let log = std::fs::read(kept.join("driving_log.csv")).unwrap();
    assert_eq!(log.last(), Some(&b'\n'), "the log ends with a whole row");
    let frames = assert_valid(&kept);
    assert!(frames > 0, "{stderr}");
    let pictures = std::fs::read_dir(kept.join("IMG")).unwrap().count();
    assert_eq!(pictures, 3 * frames, "every picture belongs to a row");
    assert!(
        stderr.contains(&format!("{frames} whole frames")),
        "{stderr}"
    );
}
