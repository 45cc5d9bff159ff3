//! Calibration figures and speed of the simulator on the 300 random WOGAN roads of
//! `tests/reference/roads.jsonl` (70 km/h, oob tolerance 0.85, `beamng-ai-proxy`).
//!
//! `cargo bench -p road-sim --bench simulate` first prints the calibration figures
//! (failure rate, max BOLP and fitness deciles, the share of max BOLP below 0.05, local continuity,
//! simulated seconds per wall second), then measures the wall time per road on one core.
//!
//! Environment: `ROAD_SIM_CONFIG` = a JSON `SimConfig` (fields may be left out) to try other
//! settings; `ROAD_SIM_CALIBRATE_ONLY=1` skips the timing; `ROAD_SIM_LIST=1` lists every road's
//! result; `ROAD_SIM_TRACE=i` prints the trace of road `i` (JSON lines) and stops.

use criterion::Criterion;
mod scenario;

use road_sim::driver::dave2::embedded_weights;
use road_sim::driver::Dave2DriverParams;
use road_sim::vision::{Camera, CameraParams, Dave2Net, RoadScene};
use road_sim::{CompetitionSetup, DriverKind, Road, SimConfig};
use scenario::{calibrate, continuity, deciles, read_roads, simulate_kind, CalibrationRoad};
use std::hint::black_box;
use std::time::Instant;

fn reference_roads() -> Vec<CalibrationRoad> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/roads.jsonl"
    );
    let text = std::fs::read_to_string(path).expect("tests/reference/roads.jsonl");
    read_roads(&text).expect("roads.jsonl lines")
}

fn config() -> SimConfig {
    match std::env::var("ROAD_SIM_CONFIG") {
        Ok(json) => serde_json::from_str(&json).expect("ROAD_SIM_CONFIG is a SimConfig"),
        Err(_) => SimConfig::default(),
    }
}

fn fmt(values: &[f64]) -> String {
    let v: Vec<String> = values.iter().map(|x| format!("{x:.3}")).collect();
    v.join(" ")
}

fn print_calibration(roads: &[CalibrationRoad], config: &SimConfig) {
    let kind = DriverKind::BeamNgAiProxy;
    let (c, results) = calibrate(roads, kind, config);
    if std::env::var_os("ROAD_SIM_LIST").is_some() {
        for (i, r) in results.iter().enumerate() {
            if let Some(r) = r {
                println!(
                    "road {i:3} {:?} {:?} max_bolp {:.3} min_dist {:.2} t {:.1} MAX_CURV {:.4}",
                    r.outcome,
                    r.reason,
                    r.max_bolp,
                    r.min_lane_distance_m,
                    r.sim_time_s,
                    r.max_curv
                );
            }
        }
    }
    println!(
        "calibration on {} roads (speed limit {} km/h, oob tolerance {}):",
        c.roads, config.speed_limit_kmh, config.oob_tolerance
    );
    println!(
        "  failure rate            {:.1}% (errors {:.1}%)",
        100.0 * c.failure_rate,
        100.0 * c.error_rate
    );
    println!("  max BOLP deciles        {}", fmt(&c.max_bolp_deciles));
    println!(
        "  share max BOLP < 0.05   {:.1}%",
        100.0 * c.share_bolp_below_0_05
    );
    println!(
        "  fitness_distance deciles {}",
        fmt(&c.fitness_distance_deciles)
    );
    println!(
        "  simulated s / wall s    {:.0}",
        c.sim_seconds_per_wall_second
    );
    println!("  median ms per road      {:.2}", c.median_ms_per_road);
    // Continuity on the 30 roads of highest max BOLP below the tolerance and 30 spread roads.
    let mut order: Vec<usize> = (0..roads.len()).collect();
    order.sort_by(|&a, &b| {
        let bolp = |i: usize| results[i].as_ref().map_or(0.0, |r| r.max_bolp);
        bolp(b).total_cmp(&bolp(a))
    });
    let picked: Vec<CalibrationRoad> = order
        .iter()
        .step_by(10)
        .map(|&i| roads[i].clone())
        .collect();
    let changes = continuity(&picked, kind, config, 0.001);
    println!(
        "  continuity: |change of max BOLP| when one curvature value moves by 0.001 ({} moves on {} roads): deciles {}",
        changes.len(),
        picked.len(),
        fmt(&deciles(&changes))
    );
}

fn main() {
    let roads = reference_roads();
    let config = config();
    if let Some(i) = std::env::var("ROAD_SIM_TRACE")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        let road = Road::new(&roads[i].road_points).expect("a valid road");
        let r = simulate_kind(&road, DriverKind::BeamNgAiProxy, &config, true);
        for s in r.trace.iter().flatten() {
            println!("{}", serde_json::to_string(s).expect("a sample"));
        }
        return;
    }
    print_calibration(&roads, &config);
    if std::env::var_os("ROAD_SIM_CALIBRATE_ONLY").is_some() {
        return;
    }
    let built: Vec<Road> = roads
        .iter()
        .filter_map(|r| Road::new(&r.road_points).ok())
        .collect();
    let mut criterion = Criterion::default().configure_from_args().sample_size(30);
    let dave2_config = SimConfig {
        speed_limit_kmh: CompetitionSetup::Dave2.speed_limit_kmh(),
        oob_tolerance: CompetitionSetup::Dave2.oob_tolerance(),
        ..SimConfig::default()
    };
    print_dave2_split(&built, &dave2_config);
    let mut next = 0;
    for (kind, config) in [
        (DriverKind::BeamNgAiProxy, &config),
        (DriverKind::Dave2Proxy, &dave2_config),
    ] {
        let name = format!("simulate one roads.jsonl road ({})", kind.name());
        criterion.bench_function(&name, |b| {
            b.iter(|| {
                next = (next + 1) % built.len();
                black_box(simulate_kind(black_box(&built[next]), kind, config, false).max_bolp)
            })
        });
    }
    criterion.final_summary();
}

/// Where a `dave2-proxy` drive spends its time: the median road's wall time, split into camera
/// rendering and network inference (per-frame costs times frames) and the rest (physics, oracle).
fn print_dave2_split(roads: &[Road], config: &SimConfig) {
    let results: Vec<_> = roads
        .iter()
        .map(|road| simulate_kind(road, DriverKind::Dave2Proxy, config, false))
        .collect();
    let mut wall_ms: Vec<f64> = results.iter().map(|r| r.execution_ms).collect();
    wall_ms.sort_by(f64::total_cmp);
    let median_ms = wall_ms[wall_ms.len() / 2];
    let mut sim_s: Vec<f64> = results.iter().map(|r| r.sim_time_s).collect();
    sim_s.sort_by(f64::total_cmp);
    let frames = sim_s[sim_s.len() / 2] * Dave2DriverParams::default().control_hz;
    let camera = Camera::new(CameraParams::default());
    let scene = RoadScene::new(&roads[0]);
    let mut net = Dave2Net::new(&embedded_weights());
    let (pose, heading) = road_sim::sim::start_pose(&roads[0], 10.0);
    let repeats = 300;
    let started = Instant::now();
    let mut frame = camera.render(&scene, pose, heading);
    for _ in 0..repeats {
        camera.render_into(&scene, pose, heading, &mut frame);
    }
    let render_ms = started.elapsed().as_secs_f64() * 1e3 / repeats as f64;
    let started = Instant::now();
    let mut steering = 0.0;
    for _ in 0..repeats {
        steering += net.predict(black_box(&frame.data));
    }
    black_box(steering);
    let inference_ms = started.elapsed().as_secs_f64() * 1e3 / repeats as f64;
    let failures = results
        .iter()
        .filter(|r| r.outcome == road_sim::Outcome::Fail)
        .count();
    println!(
        "dave2-proxy on {} roads (speed limit {} km/h, oob tolerance {}):",
        roads.len(),
        config.speed_limit_kmh,
        config.oob_tolerance
    );
    println!(
        "  failure rate            {:.1}%",
        100.0 * failures as f64 / roads.len() as f64
    );
    println!(
        "  median ms per road      {median_ms:.1} ({frames:.0} frames at {} Hz)",
        Dave2DriverParams::default().control_hz
    );
    println!(
        "  rendering               {:.1} ms ({render_ms:.3} ms per frame)",
        render_ms * frames
    );
    println!(
        "  inference               {:.1} ms ({inference_ms:.3} ms per frame)",
        inference_ms * frames
    );
    println!(
        "  physics, oracle, rest   {:.1} ms",
        median_ms - (render_ms + inference_ms) * frames
    );
}
