//! Calibration of the simulator on a set of roads: failure rate, the spread of max BOLP and of
//! the lane-distance fitness, local continuity, and speed.

use road_sim::{
    simulate, CurvatureRoad, DriverConfig, DriverKind, Outcome, Point, Road, SimConfig, SimResult,
};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Drives the driver `kind` with its default tuning on `road`.
pub fn simulate_kind(road: &Road, kind: DriverKind, config: &SimConfig, trace: bool) -> SimResult {
    simulate(
        road,
        DriverConfig::default_for(kind).build().as_mut(),
        config,
        trace,
        None,
    )
}

/// A road of a calibration set: its WOGAN curvature values (if known) and its points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CalibrationRoad {
    /// Curvature values, 1/m (empty when the road came as points only).
    #[serde(default)]
    pub curvature: Vec<f64>,
    /// The road's points.
    pub road_points: Vec<Point>,
}

/// Reads JSON lines with `road_points` and optionally `curvature` (like the reference
/// `roads.jsonl`).
pub fn read_roads(text: &str) -> Result<Vec<CalibrationRoad>, serde_json::Error> {
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(serde_json::from_str)
        .collect()
}

/// Figures of a calibration run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// Roads simulated.
    pub roads: usize,
    /// Share of roads with outcome FAIL.
    pub failure_rate: f64,
    /// Share of roads with outcome ERROR.
    pub error_rate: f64,
    /// Deciles (0%, 10%, ..., 100%) of max BOLP.
    pub max_bolp_deciles: Vec<f64>,
    /// Share of roads whose max BOLP is below 0.05.
    pub share_bolp_below_0_05: f64,
    /// Deciles of `fitness_distance`.
    pub fitness_distance_deciles: Vec<f64>,
    /// Simulated seconds per wall-clock second (one core).
    pub sim_seconds_per_wall_second: f64,
    /// Median wall time per road, milliseconds.
    pub median_ms_per_road: f64,
}

/// Deciles of `values` (nearest rank), 11 numbers from the minimum to the maximum.
pub fn deciles(values: &[f64]) -> Vec<f64> {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return vec![];
    }
    (0..=10).map(|k| v[(k * (v.len() - 1) + 5) / 10]).collect()
}

/// Simulates every road (invalid geometry counts as an error) and summarises.
pub fn calibrate(
    roads: &[CalibrationRoad],
    kind: DriverKind,
    config: &SimConfig,
) -> (Calibration, Vec<Option<SimResult>>) {
    let started = Instant::now();
    let results: Vec<Option<SimResult>> = roads
        .iter()
        .map(|r| {
            Road::new(&r.road_points)
                .ok()
                .map(|road| simulate_kind(&road, kind, config, false))
        })
        .collect();
    let wall = started.elapsed().as_secs_f64();
    let n = roads.len().max(1) as f64;
    let done: Vec<&SimResult> = results.iter().flatten().collect();
    let count = |o: Outcome| done.iter().filter(|r| r.outcome == o).count();
    let bolps: Vec<f64> = done.iter().map(|r| r.max_bolp).collect();
    let fitness: Vec<f64> = done.iter().map(|r| r.fitness_distance).collect();
    let times: Vec<f64> = done.iter().map(|r| r.execution_ms).collect();
    let sim_time: f64 = done.iter().map(|r| r.sim_time_s).sum();
    let calibration = Calibration {
        roads: roads.len(),
        failure_rate: count(Outcome::Fail) as f64 / n,
        error_rate: (count(Outcome::Error) + results.len() - done.len()) as f64 / n,
        max_bolp_deciles: deciles(&bolps),
        share_bolp_below_0_05: bolps.iter().filter(|&&b| b < 0.05).count() as f64 / n,
        fitness_distance_deciles: deciles(&fitness),
        sim_seconds_per_wall_second: sim_time / wall.max(1e-9),
        median_ms_per_road: deciles(&times).get(5).copied().unwrap_or(0.0),
    };
    (calibration, results)
}

/// Local continuity: for each road with curvature values and each value, the change of max
/// BOLP when that value moves by `delta`. Returns the absolute changes.
pub fn continuity(
    roads: &[CalibrationRoad],
    kind: DriverKind,
    config: &SimConfig,
    delta: f64,
) -> Vec<f64> {
    let shape = CurvatureRoad::default();
    let max_bolp = |curvature: &[f64]| {
        Road::new(&shape.points(curvature))
            .ok()
            .map(|road| simulate_kind(&road, kind, config, false).max_bolp)
    };
    let mut changes = Vec::new();
    for r in roads.iter().filter(|r| !r.curvature.is_empty()) {
        let Some(base) = max_bolp(&r.curvature) else {
            continue;
        };
        for i in 0..r.curvature.len() {
            let mut moved = r.curvature.clone();
            moved[i] += delta;
            if let Some(b) = max_bolp(&moved) {
                changes.push((b - base).abs());
            }
        }
    }
    changes
}
