//! Dev-time evidence for the distinct-failures measure (`road_sim::distinct`): counts at several
//! δ, nearest-neighbour distances, jittered copies of failing roads to re-drive, and pictures of
//! exit profiles. Reads `wogan run` files (JSON lines); see
//! docs/experiments/2026-11-25-distinct-failures.md for how it was used.
//!
//! ```text
//! exit_distances counts DELTA,DELTA,... RUN...      per run: failures, distinct count at each δ
//!                                                   (`BEFORE=1`: over the 30 m before the exit)
//! exit_distances nearest RUN...                     per failure: distance to the nearest earlier one
//! exit_distances order DELTA RUN...                per run: count in test order, reversed, and the
//!                                                   least and most over 100 seeded shuffles
//! exit_distances turns RUN...                      per run: failures turning left, right into the exit
//! exit_distances spread K DELTA RUN...              per run: median pairwise distance, distinct of the first K
//! exit_distances jitter SIZE COPIES SEED RUN        road lines for `wogan simulate`
//! exit_distances same SIZE COPIES SEED RUN RESULTS  distance of each failing copy to its original
//! exit_distances svg OUT DELTA TITLE RUN...         exit outlines overlaid, the distinct ones bold
//! exit_distances pairs OUT DIST,DIST,... RUN...     the pair of failures nearest each distance
//! exit_distances both RUN...                        per pair of a run's failures: whole-road and
//!                                                   exit distances
//! exit_distances show OUT RUN ID,ID ID,ID ...        pairs of a run's failures: whole roads, exits
//! ```

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use road_sim::distinct::{distinct, ExitProfile};
use road_sim::road::curvature::CurvatureRoad;
use road_sim::road::heading_profile::heading_profile;
use road_sim::{Point, Road};
use serde_json::Value;
use std::fmt::Write as _;
use std::io::BufRead;

/// A failing test of a run: its id, curvature, centre line, heading profile and exit profile.
struct Failure {
    id: u64,
    curvature: Vec<f64>,
    line: Vec<Point>,
    whole: Vec<f64>,
    profile: ExitProfile,
}

fn failures(path: &str) -> Vec<Failure> {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut out = Vec::new();
    for line in std::io::BufReader::new(file).lines() {
        let v: Value = serde_json::from_str(&line.expect("a line")).expect("JSON");
        if v["type"] != "test" || v["outcome"] != "FAIL" {
            continue;
        }
        let points: Vec<Point> = serde_json::from_value(v["road_points"].clone()).expect("points");
        let exit = [
            v["oob"]["x"].as_f64().expect("x"),
            v["oob"]["y"].as_f64().expect("y"),
        ];
        let road = Road::new(&points).expect("a road");
        out.push(Failure {
            id: v["id"].as_u64().expect("id"),
            curvature: serde_json::from_value(v["curvature"].clone()).expect("curvature"),
            profile: ExitProfile::of(&road.interpolated, exit).expect("a profile"),
            whole: heading_profile(&road.interpolated),
            line: road.interpolated,
        });
    }
    out
}

fn numbers(list: &str) -> Vec<f64> {
    list.split(',')
        .map(|x| x.parse().expect("a number"))
        .collect()
}

/// The greedy count with the RMS distance over the 31 chords up to the exit only.
fn before_only(profiles: &[ExitProfile], delta: f64) -> usize {
    let distance = |a: &ExitProfile, b: &ExitProfile| {
        let half = &a.headings()[..=30];
        let sum: f64 = half
            .iter()
            .zip(&b.headings()[..=30])
            .map(|(x, y)| (x - y) * (x - y))
            .sum();
        (sum / half.len() as f64).sqrt()
    };
    let mut kept: Vec<&ExitProfile> = Vec::new();
    for p in profiles {
        if kept.iter().all(|k| distance(k, p) >= delta) {
            kept.push(p);
        }
    }
    kept.len()
}

/// Jittered copies of each failure's curvature: COPIES per failure, in failure order.
fn jittered(failures: &[Failure], size: f64, copies: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    for f in failures {
        for _ in 0..copies {
            out.push(
                f.curvature
                    .iter()
                    .map(|c| (c + rng.random_range(-size..=size)).clamp(-0.07, 0.07))
                    .collect(),
            );
        }
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("counts") => {
            let deltas = numbers(&args[1]);
            for run in &args[2..] {
                let f: Vec<ExitProfile> = failures(run).into_iter().map(|f| f.profile).collect();
                let before = std::env::var_os("BEFORE").is_some();
                let counts: Vec<String> = deltas
                    .iter()
                    .map(|&d| {
                        if before {
                            before_only(&f, d).to_string()
                        } else {
                            distinct(&f, d).len().to_string()
                        }
                    })
                    .collect();
                println!("{run},{},{}", f.len(), counts.join(","));
            }
        }
        Some("nearest") => {
            for run in &args[1..] {
                let f = failures(run);
                for (i, a) in f.iter().enumerate().skip(1) {
                    let nearest = f[..i]
                        .iter()
                        .map(|b| a.profile.distance(&b.profile))
                        .fold(f64::INFINITY, f64::min);
                    println!("{run},{},{nearest}", a.id);
                }
            }
        }
        Some("both") => {
            for run in &args[1..] {
                let f = failures(run);
                for i in 0..f.len() {
                    for j in i + 1..f.len() {
                        let whole: f64 = f[i]
                            .whole
                            .iter()
                            .zip(&f[j].whole)
                            .map(|(a, b)| (a - b) * (a - b))
                            .sum::<f64>()
                            .sqrt();
                        let local = f[i].profile.distance(&f[j].profile);
                        println!("{run},{},{},{whole},{local}", f[i].id, f[j].id);
                    }
                }
            }
        }
        Some("show") => {
            let f = failures(&args[2]);
            let find = |id: u64| f.iter().find(|x| x.id == id).expect("a failing test id");
            let mut panels = Vec::new();
            for pair in &args[3..] {
                let ids: Vec<u64> = pair.split(',').map(|x| x.parse().expect("an id")).collect();
                let (a, b) = (find(ids[0]), find(ids[1]));
                // The whole roads on the 200 m map, shrunk to fit the panel.
                let map = |line: &[Point]| -> Vec<Point> {
                    line.iter()
                        .map(|p| [(p[0] - 100.0) * 0.33, (p[1] - 100.0) * 0.33])
                        .collect()
                };
                panels.push((
                    format!("#{} (blue), #{}: whole roads", a.id, b.id),
                    vec![(map(&a.line), true), (map(&b.line), false)],
                ));
                panels.push((
                    format!("exits, distance {:.3} rad", a.profile.distance(&b.profile)),
                    vec![(a.profile.outline(), true), (b.profile.outline(), false)],
                ));
            }
            write_svg(&args[1], &args[2], &panels);
        }
        Some("order") => {
            let delta: f64 = args[1].parse().expect("DELTA");
            let mut rng = ChaCha20Rng::seed_from_u64(1);
            for run in &args[2..] {
                let mut f: Vec<ExitProfile> =
                    failures(run).into_iter().map(|f| f.profile).collect();
                let in_order = distinct(&f, delta).len();
                f.reverse();
                let reversed = distinct(&f, delta).len();
                let (mut least, mut most) = (usize::MAX, 0);
                for _ in 0..100 {
                    // Fisher–Yates with the seeded generator.
                    for i in (1..f.len()).rev() {
                        f.swap(i, rng.random_range(0..=i));
                    }
                    let n = distinct(&f, delta).len();
                    (least, most) = (least.min(n), most.max(n));
                }
                println!("{run},{},{in_order},{reversed},{least},{most}", f.len());
            }
        }
        Some("turns") => {
            for run in &args[1..] {
                let f = failures(run);
                // Heading 30 m before the exit relative to the exit's: negative when the road
                // turned left (anticlockwise) into the exit.
                let left = f.iter().filter(|x| x.profile.headings()[0] < 0.0).count();
                println!("{run},{left},{}", f.len() - left);
            }
        }
        Some("spread") => {
            let k: usize = args[1].parse().expect("K");
            let delta: f64 = args[2].parse().expect("DELTA");
            for run in &args[3..] {
                let f: Vec<ExitProfile> = failures(run).into_iter().map(|f| f.profile).collect();
                let mut pairs: Vec<f64> = (0..f.len())
                    .flat_map(|i| (i + 1..f.len()).map(move |j| (i, j)))
                    .map(|(i, j)| f[i].distance(&f[j]))
                    .collect();
                pairs.sort_by(f64::total_cmp);
                let median = pairs.get(pairs.len() / 2).copied().unwrap_or(f64::NAN);
                let first = (f.len() >= k).then(|| distinct(&f[..k], delta).len());
                println!(
                    "{run},{},{median},{}",
                    f.len(),
                    first.map_or(-1, |n| n as i64)
                );
            }
        }
        Some("jitter") | Some("same") => {
            let (size, copies, seed): (f64, usize, u64) = (
                args[1].parse().expect("SIZE"),
                args[2].parse().expect("COPIES"),
                args[3].parse().expect("SEED"),
            );
            let f = failures(&args[4]);
            let roads: Vec<Vec<Point>> = jittered(&f, size, copies, seed)
                .iter()
                .map(|c| CurvatureRoad::default().points(c))
                .collect();
            if args[0] == "jitter" {
                for points in &roads {
                    println!("{}", serde_json::json!({ "road_points": points }));
                }
                return;
            }
            let file = std::fs::File::open(&args[5]).expect("RESULTS");
            for (k, line) in std::io::BufReader::new(file).lines().enumerate() {
                let v: Value = serde_json::from_str(&line.expect("a line")).expect("JSON");
                if v["outcome"] != "FAIL" {
                    println!("{},{k},{}", f[k / copies].id, v["outcome"]);
                    continue;
                }
                let exit = [
                    v["oob"]["x"].as_f64().unwrap(),
                    v["oob"]["y"].as_f64().unwrap(),
                ];
                let road = Road::new(&roads[k]).expect("a road");
                let profile = ExitProfile::of(&road.interpolated, exit).expect("a profile");
                let d = profile.distance(&f[k / copies].profile);
                println!("{},{k},{d}", f[k / copies].id);
            }
        }
        Some("svg") => {
            let delta: f64 = args[2].parse().expect("DELTA");
            let mut panels = Vec::new();
            for run in &args[4..] {
                let f: Vec<ExitProfile> = failures(run).into_iter().map(|f| f.profile).collect();
                let kept = distinct(&f, delta);
                let name = run.rsplit('/').next().unwrap_or(run);
                let label = format!("{name}: {} failures, {} distinct", f.len(), kept.len());
                let lines = f
                    .iter()
                    .enumerate()
                    .map(|(i, p)| (p.outline(), kept.contains(&i)))
                    .collect();
                panels.push((label, lines));
            }
            write_svg(&args[1], &args[3], &panels);
        }
        Some("pairs") => {
            let targets = numbers(&args[2]);
            let all: Vec<ExitProfile> = args[3..]
                .iter()
                .flat_map(|run| failures(run).into_iter().map(|f| f.profile))
                .collect();
            let mut panels = Vec::new();
            for target in targets {
                let mut best = (f64::INFINITY, 0, 0);
                for i in 0..all.len() {
                    for j in i + 1..all.len() {
                        let d = all[i].distance(&all[j]);
                        if (d - target).abs() < best.0 {
                            best = ((d - target).abs(), i, j);
                        }
                    }
                }
                let (_, i, j) = best;
                let d = all[i].distance(&all[j]);
                panels.push((
                    format!("distance {d:.3} rad"),
                    vec![(all[i].outline(), true), (all[j].outline(), false)],
                ));
            }
            write_svg(&args[1], "pairs of failures", &panels);
        }
        _ => eprintln!("usage: see the file's documentation"),
    }
}

/// A panel of a picture: its label and its lines, each drawn bold or not.
type Panel = (String, Vec<(Vec<Point>, bool)>);

/// Panels of exit outlines (exit at the centre, road heading up there), side by side.
fn write_svg(path: &str, title: &str, panels: &[Panel]) {
    const SIDE: f64 = 260.0;
    const SCALE: f64 = SIDE / 70.0;
    let columns = panels.len().min(4);
    let rows = panels.len().div_ceil(4);
    let (width, height) = (SIDE * columns as f64, SIDE * rows as f64 + 30.0);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         font-family=\"sans-serif\"><rect width=\"100%\" height=\"100%\" fill=\"white\"/>\
         <text x=\"8\" y=\"20\" font-size=\"15\">{title}</text>"
    );
    for (n, (label, lines)) in panels.iter().enumerate() {
        let (ox, oy) = ((n % 4) as f64 * SIDE, 30.0 + (n / 4) as f64 * SIDE);
        let (cx, cy) = (ox + SIDE / 2.0, oy + SIDE / 2.0 + 8.0);
        let _ = write!(
            svg,
            "<rect x=\"{ox}\" y=\"{oy}\" width=\"{SIDE}\" height=\"{SIDE}\" fill=\"none\" \
             stroke=\"#ccc\"/><text x=\"{}\" y=\"{}\" font-size=\"11\">{label}</text>\
             <circle cx=\"{cx}\" cy=\"{cy}\" r=\"3\" fill=\"red\"/>",
            ox + 4.0,
            oy + 13.0
        );
        // Grey ones under the bold ones.
        for bold in [false, true] {
            for (outline, _) in lines.iter().filter(|(_, b)| *b == bold) {
                let points: Vec<String> = outline
                    .iter()
                    .map(|p| format!("{:.1},{:.1}", cx + SCALE * p[0], cy - SCALE * p[1]))
                    .collect();
                let (colour, w) = if bold {
                    ("#1f5fbf", 1.6)
                } else {
                    ("#999", 0.8)
                };
                let _ = write!(
                    svg,
                    "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" \
                     stroke-width=\"{w}\" opacity=\"0.8\"/>",
                    points.join(" ")
                );
            }
        }
    }
    svg.push_str("</svg>\n");
    std::fs::write(path, svg).expect("write the SVG");
}
