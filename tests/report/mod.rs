//! End-to-end tests of `wogan report`, by concern: [`figures`] (the measures, groups, `--vs`,
//! `--table`, distinct failures, result folders), [`pictures`] (the SVGs: every text inside, no
//! label piled on another, ten thousand roads) and [`html_page`] (the page, its size bound, a
//! real browser). They read small committed fixture runs (tests/fixtures: two WOGAN runs, seeds 3
//! and 4, 5 and 1 failures; two random runs, seeds 4 and 5, 2 failures each; 30 tests each, made
//! with `wogan run --max-tests 30 --seed N`), variants of them with other conditions in their
//! headers, and synthetic runs written here (10,000 failing roads, or roads that all end in one
//! place); this file holds what they share.

mod figures;
mod html_page;
mod pictures;

pub use html_page::{chromium_present, html_size_bound};

use crate::common::{scratch_dir, wogan_ok};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The path of a committed fixture.
pub fn fixture(name: &str) -> String {
    format!("{}/../../tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// A path as the `&str` an argument list takes.
pub fn path_str(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// A file's text.
pub fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A deterministic stream of numbers in [0, 1) (xorshift64), for synthetic runs.
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// One test of a synthetic run.
struct SyntheticTest {
    /// Curvature values, 1/m.
    curvature: Vec<f64>,
    max_bolp: f64,
    failed: bool,
    /// Where the car left its lane (a failing test's record says so; older runs' did not).
    exit: Option<[f64; 2]>,
}

/// The road points of curvature values as `wogan run` makes them: from (100, 10) 15 m north,
/// then a 15 m step for each value but the last, turned by the value times the step.
fn road_points(curvature: &[f64]) -> Vec<[f64; 2]> {
    let mut points = vec![[100.0, 10.0], [100.0, 25.0]];
    let mut heading = std::f64::consts::FRAC_PI_2;
    for c in &curvature[..curvature.len() - 1] {
        heading += c * 15.0;
        let [x, y] = points[points.len() - 1];
        points.push([x + 15.0 * heading.cos(), y + 15.0 * heading.sin()]);
    }
    points
}

/// Writes a synthetic `wogan run` file of `tests`: the header of a random search on
/// dave2-proxy at failure threshold `oob_tolerance`, a test record per test, and a summary.
/// The records have the shape `wogan run` writes; the drives were never simulated.
fn write_synthetic_run(path: &Path, oob_tolerance: f64, tests: &[SyntheticTest]) {
    let header = json!({"type": "header", "version": "0.1.0", "seed": 1, "algorithm": "random",
        "oracle": "dave2-proxy", "fitness": "distance", "config": {
            "road": {"map_size_m": 200.0, "step_m": 15.0},
            "sim": {"speed_limit_kmh": 30.0, "oob_tolerance": oob_tolerance}}});
    let mut text = header.to_string() + "\n";
    for (i, test) in tests.iter().enumerate() {
        let (outcome, reason) = if test.failed {
            ("FAIL", json!("out_of_lane"))
        } else {
            ("PASS", Value::Null)
        };
        let max_curv = test.curvature.iter().fold(0.0, |m: f64, c| m.max(c.abs()));
        let record = json!({"type": "test", "id": i + 1, "phase": "random",
            "fitness": test.max_bolp, "predicted_fitness": null, "invalid_candidates": 0,
            "generation_ms": 0.5, "curvature": test.curvature,
            "road_points": road_points(&test.curvature), "outcome": outcome, "reason": reason,
            "max_bolp": test.max_bolp, "min_lane_distance_m": 1.0 - 2.0 * test.max_bolp,
            "fitness_distance": test.max_bolp, "sim_time_s": 8.0, "execution_ms": 2.0,
            "MAX_CURV": max_curv, "DIR_COV": 0.3, "STD_SA": 2.0, "MEAN_LP": 1.5, "MAX_LP": 2.0,
            "oob": test.exit.map(|[x, y]| json!({"t_s": 4.0, "x": x, "y": y, "side": "right",
                "sbst_side": "RIGHT"}))});
        text += &record.to_string();
        text.push('\n');
    }
    let failed = tests.iter().filter(|t| t.failed).count();
    let summary = json!({"type": "summary", "executed": tests.len(), "failed": failed,
        "invalid_candidates": 0, "wall_s": 1.0, "generation_s": 0.1, "training_s": 0.0,
        "simulation_s": 0.5, "diversity": null, "diversity_pairs": "sampled",
        "interrupted": false});
    text += &summary.to_string();
    text.push('\n');
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// 10,000 failing tests of five random curvature values each (max BOLP just above the
/// threshold 0.10), then 1,000 passing ones (below it).
fn crowded_tests() -> Vec<SyntheticTest> {
    let mut numbers = Numbers(0x9E37_79B9_7F4A_7C15);
    (0..11_000)
        .map(|i| {
            let curvature = (0..5).map(|_| 0.12 * numbers.next() - 0.06).collect();
            let failed = i < 10_000;
            let max_bolp = if failed {
                0.1 + 0.04 * numbers.next()
            } else {
                0.1 * numbers.next()
            };
            SyntheticTest {
                curvature,
                max_bolp,
                failed,
                exit: None,
            }
        })
        .collect()
}

/// A copy of fixture `name` as `dir/file` whose header has `from` replaced by `to`.
fn variant(dir: &Path, name: &str, file: &str, from: &str, to: &str) -> PathBuf {
    let text = read(Path::new(&fixture(name)));
    let (header, rest) = text.split_once('\n').expect("a header line");
    assert!(header.contains(from), "{from} is not in {name}'s header");
    let path = dir.join(file);
    std::fs::write(&path, format!("{}\n{rest}", header.replace(from, to))).expect("write");
    path
}

/// Reports the WOGAN fixture runs of seeds 3 and 4 into a fresh scratch directory `name`.
fn report_of_seeds_3_and_4(name: &str) -> PathBuf {
    let out = scratch_dir(name);
    wogan_ok(
        &[
            "report",
            &fixture("wogan.seed3.jsonl"),
            &fixture("wogan.seed4.jsonl"),
            "--out",
            path_str(&out),
        ],
        "",
    );
    out
}

/// A seeded 60-test `wogan run` (beamng-ai-proxy) written to `path`, with `more` options.
fn seeded_run(path: &Path, more: &[&str]) {
    let mut args = vec![
        "run",
        "--max-tests",
        "60",
        "--seed",
        "1",
        "--out",
        path_str(path),
    ];
    args.extend_from_slice(more);
    wogan_ok(&args, "");
}
