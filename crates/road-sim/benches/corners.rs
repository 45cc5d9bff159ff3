//! The most expensive work one road can cost within the settings' ranges: validating the longest
//! road the validator interpolates on the largest map, and a drive of each driver that lasts the
//! simulated-time cap at the highest physics rate (and, for DAVE-2, its highest control rate).
//! Prints wall time and the process's peak memory for each.
//!
//! `cargo bench -p road-sim --bench corners`

use road_sim::driver::{Dave2DriverParams, DriverConfig, DriverKind};
use road_sim::sim::{MAX_PHYSICS_HZ, MAX_SIM_TIME_S};
use road_sim::validator::{MAX_MAP_SIZE_M, MAX_ROAD_LENGTH_M};
use road_sim::{simulate, Point, Road, SimConfig, Validator};
use std::time::Instant;

/// Peak resident memory of this process, MiB (Linux).
fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

/// A serpentine filling the largest map: rows 1700 m long, 60 m apart, joined by half circles,
/// just under the validator's length bound.
fn longest_road() -> Vec<Point> {
    let (x0, x1, radius) = (150.0, 1850.0, 30.0);
    let mut points = Vec::new();
    for row in 0..11 {
        let y = 100.0 + 2.0 * radius * f64::from(row);
        let xs: Vec<f64> = (0..=17).map(|k| x0 + 100.0 * f64::from(k)).collect();
        let leftwards = row % 2 == 1;
        let ordered: Vec<f64> = if leftwards {
            xs.into_iter().rev().collect()
        } else {
            xs
        };
        points.extend(ordered.iter().map(|&x| [x, y]));
        if row < 10 {
            let (cx, side) = if leftwards { (x0, -1.0) } else { (x1, 1.0) };
            for step in 1..18 {
                let a = std::f64::consts::PI * f64::from(step) / 18.0;
                points.push([cx + side * radius * a.sin(), y + radius - radius * a.cos()]);
            }
        }
    }
    points
}

fn main() {
    let road_points = longest_road();
    let length_m: f64 = road_points
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    assert!(length_m < MAX_ROAD_LENGTH_M, "{length_m}");
    let started = Instant::now();
    let verdict = Validator::new(MAX_MAP_SIZE_M).validate(&road_points);
    println!(
        "validator corner ({} points, {length_m:.0} m on a {MAX_MAP_SIZE_M} m map, {:?}): {:.2} s, peak memory {:.0} MiB",
        road_points.len(),
        verdict.reason,
        started.elapsed().as_secs_f64(),
        peak_rss_mib()
    );

    // The drive lasts until the simulated-time cap: a crawl that never reaches the end, with no
    // not-moving rule and a time limit beyond the cap, at the highest physics rate.
    let road = Road::new(&[[100.0, 10.0], [100.0, 100.0], [100.0, 190.0]]).expect("a road");
    let config = SimConfig {
        speed_limit_kmh: 0.1,
        physics_hz: MAX_PHYSICS_HZ,
        timeout_base_s: MAX_SIM_TIME_S,
        not_moving_distance_m: 0.0,
        ..SimConfig::default()
    };
    config.validate().expect("the corner is accepted");
    let dave2_fastest = match DriverConfig::default_for(DriverKind::Dave2Proxy) {
        DriverConfig::Dave2Proxy { weights, .. } => DriverConfig::Dave2Proxy {
            params: Dave2DriverParams {
                control_hz: 100.0,
                ..Dave2DriverParams::default()
            },
            weights,
        },
        other => other,
    };
    dave2_fastest.validate().expect("the corner is accepted");
    for driver in [
        DriverConfig::default_for(DriverKind::BeamNgAiProxy),
        dave2_fastest,
    ] {
        let started = Instant::now();
        let result = simulate(&road, driver.build().as_mut(), &config, false, None);
        println!(
            "drive corner ({}, {MAX_PHYSICS_HZ} Hz physics, {} s simulated, {:?} {:?}): {:.1} s, peak memory {:.0} MiB",
            driver.kind(),
            result.sim_time_s,
            result.outcome,
            result.reason,
            started.elapsed().as_secs_f64(),
            peak_rss_mib()
        );
    }
}
