//! `wogan dataset`: frames and steering labels to train a camera network on, recorded from a driver
//! in wogan's world, in the Udacity simulator's recording layout (`IMG/` pictures and
//! `driving_log.csv`), so that the course's training scripts and their many descendants read it.
//!
//! Each road (random valid roads by `--seed`, or the roads of a file) is driven by the driver under
//! test (beamng-ai-proxy by default) with the run's sampling; every `1 / --record-hz` seconds of
//! the drive the contract's camera renders three pictures at the car's pose: the centre camera and
//! the left and right ones, offset sideways as the simulator's recording cameras are
//! (udacity/self-driving-car-sim `CarWaypointBased.prefab`: 0.806 m left, 0.825 m right). A row is
//! appended to `driving_log.csv` only once its three pictures are written, and flushed: a dataset
//! cut short by Ctrl-C is a valid, shorter one.
//!
//! Labels, in the simulator's units: `steering` the car's wheel angle over the contract's full
//! steering (±25° under `udacity`), positive the way the contract's networks turn (right under
//! `udacity`), clamped to `[-1, 1]`; `throttle` and `brake` the driver's pedals in `[0, 1]`;
//! `speed` in miles per hour. No header row, as the simulator writes none; picture paths relative
//! to the dataset's folder.

use super::Status;
use crate::files::json_lines::open_input;
use crate::files::road_input::roads_of_lines;
use crate::interrupt::stop_flag;
use crate::options::driver_options::DriverOptions;
use anyhow::{bail, Context, Result};
use clap::Args;
use driver_training::random_valid_roads;
use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use road_sim::driver::{Contract, OnnxParams};
use road_sim::vision::{write_png, Camera, CameraParams, Frame, RoadScene};
use road_sim::{simulate, Road, Sample, StopReason, Validator};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// Sideways offsets of the simulator's left and right recording cameras from its centre one,
/// metres, positive left.
const SIDE_CAMERAS_LEFT_M: [f64; 2] = [0.806, -0.825];
/// Kilometres per hour in a mile per hour.
const KMH_PER_MPH: f64 = 1.609_344;
/// The render size of a contract whose camera renders at the model's size (`sbst2022`): the
/// competition's camera.
const DEFAULT_FRAME: [usize; 2] = [320, 160];
/// Most frames one dataset may hold.
const MAX_FRAMES: u64 = 10_000_000;

/// Options of `wogan dataset`.
#[derive(Debug, Args)]
pub struct DatasetArgs {
    /// The dataset's folder: created, or an empty one (a dataset is never written over).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Frames to record (each three pictures and a row).
    #[arg(long, default_value_t = 5000, value_parser = clap::value_parser!(u64).range(1..=MAX_FRAMES))]
    pub frames: u64,
    /// Seed of the random roads.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Drive the roads of this file (JSON lines, the forms `wogan validate` reads) in order,
    /// again from the first until enough frames are recorded, instead of random roads.
    #[arg(long, value_name = "FILE")]
    pub roads: Option<PathBuf>,
    /// The camera network contract whose camera and steering convention the frames and labels
    /// follow (`udacity`, `sbst2022`).
    #[arg(long, default_value = "udacity", value_parser = crate::options::value_parsers::contract)]
    pub contract: Contract,
    /// Frames per simulated second (the simulator records about 15).
    #[arg(long, default_value_t = 15.0, value_parser = crate::options::value_parsers::record_hz)]
    pub record_hz: f64,
    /// Largest curvature of the random roads, 1/m (the search's roads go up to 0.07).
    #[arg(long, default_value_t = 0.03, value_parser = crate::options::value_parsers::max_curvature_per_m)]
    pub max_curvature: f64,
    #[command(flatten)]
    pub driver: DriverOptions,
    /// JSON file overriding the simulation's and the driver's defaults, as `wogan simulate
    /// --config` reads it.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// Where the roads come from.
enum RoadSource {
    Random(Box<ChaCha20Rng>),
    File { roads: Vec<Road>, next: usize },
}

impl RoadSource {
    fn next(&mut self, max_curvature_per_m: f64) -> Road {
        match self {
            RoadSource::Random(rng) => random_valid_roads(1, 5, max_curvature_per_m, rng).remove(0),
            RoadSource::File { roads, next } => {
                let road = roads[*next % roads.len()].clone();
                *next += 1;
                road
            }
        }
    }
}

/// The valid roads of `path`, in order; bad lines and invalid roads are named and skipped.
fn file_roads(path: &Path, map_size_m: f64) -> Result<Vec<Road>> {
    let validator = Validator::new(map_size_m);
    let mut roads = Vec::new();
    for road in roads_of_lines(open_input(Some(path))?, map_size_m, Some(path)) {
        let (line, points) = road?;
        let verdict = validator.validate(&points);
        match (verdict.reason, verdict.road) {
            (None, Some(road)) => roads.push(road),
            (reason, _) => eprintln!(
                "wogan dataset: {}: line {line}: skipped, the road is invalid: {}",
                path.display(),
                reason.map_or("malformed", |r| r.message())
            ),
        }
    }
    if roads.is_empty() {
        bail!("{}: no valid road", path.display());
    }
    Ok(roads)
}

/// Creates the dataset's folders, refusing a folder that holds anything.
fn create_folders(out: &Path) -> Result<()> {
    if out.exists() {
        let mut entries =
            std::fs::read_dir(out).with_context(|| format!("cannot read {}", out.display()))?;
        if entries.next().is_some() {
            bail!(
                "--out {}: the folder is not empty (a dataset is never written over)",
                out.display()
            );
        }
    }
    std::fs::create_dir_all(out.join("IMG"))
        .with_context(|| format!("cannot create {}", out.join("IMG").display()))
}

/// Runs `wogan dataset`.
pub fn run(args: &DatasetArgs) -> Result<Status> {
    let stop = stop_flag()?;
    let (config, driver) = args
        .driver
        .resolve_for_driving(args.config.as_deref(), "dataset")?;
    let mut source = match &args.roads {
        Some(path) => RoadSource::File {
            roads: file_roads(path, args.driver.map_size)?,
            next: 0,
        },
        None => RoadSource::Random(Box::new(ChaCha20Rng::seed_from_u64(args.seed))),
    };
    create_folders(&args.out)?;
    let log_path = args.out.join("driving_log.csv");
    let mut log = std::fs::File::create(&log_path)
        .with_context(|| format!("cannot create {}", log_path.display()))?;

    let params = OnnxParams::of(args.contract);
    let [width, height] = DEFAULT_FRAME;
    let centre = params.camera.camera(width, height);
    let cameras: Vec<(&str, Camera)> = [("center", 0.0)]
        .into_iter()
        .chain([
            ("left", SIDE_CAMERAS_LEFT_M[0]),
            ("right", SIDE_CAMERAS_LEFT_M[1]),
        ])
        .map(|(name, left_m)| (name, Camera::new(CameraParams { left_m, ..centre })))
        .collect();
    let full_steering_deg = params
        .max_steering_deg
        .unwrap_or(config.vehicle.max_steering_rad.to_degrees());
    let right_positive = params.steering_positive == road_sim::driver::SteeringSide::Right;
    let mut frame = Frame::new(centre.width, centre.height, 3);

    let mut written: u64 = 0;
    let mut roads = 0;
    while written < args.frames {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        let road = source.next(args.max_curvature);
        roads += 1;
        let result = simulate(&road, driver.build().as_mut(), &config, true, Some(&stop));
        if result.reason == Some(StopReason::Interrupted) {
            break;
        }
        let scene = RoadScene::new(&road);
        let mut next_t = 0.0;
        for sample in result.trace.unwrap_or_default() {
            if written >= args.frames || stop.load(Ordering::SeqCst) {
                break;
            }
            if sample.t + 1e-9 < next_t {
                continue;
            }
            next_t += 1.0 / args.record_hz;
            written += 1;
            let mut names = Vec::with_capacity(3);
            for (name, camera) in &cameras {
                camera.render_rgb_into(&scene, [sample.x, sample.y], sample.heading, &mut frame);
                let relative = format!("IMG/{name}_{written:07}.png");
                let path = args.out.join(&relative);
                write_png(&path, &frame)
                    .with_context(|| format!("cannot write {}", path.display()))?;
                names.push(relative);
            }
            writeln!(
                log,
                "{}",
                row(&names, &sample, full_steering_deg, right_positive)
            )
            .and_then(|()| log.flush())
            .with_context(|| format!("cannot write {}", log_path.display()))?;
        }
        eprintln!(
            "wogan dataset: road {roads}: {} ({:.1} s); {written}/{} frames",
            result.outcome.name(),
            result.sim_time_s,
            args.frames
        );
    }
    eprintln!(
        "wogan dataset: wrote {written} frames from {roads} roads to {}",
        args.out.display()
    );
    Ok(if written < args.frames {
        Status::Interrupted
    } else {
        Status::AllRead
    })
}

/// One `driving_log.csv` row for `sample`'s pictures.
fn row(names: &[String], sample: &Sample, full_steering_deg: f64, right_positive: bool) -> String {
    let turn = if right_positive { -1.0 } else { 1.0 };
    let steering = (turn * sample.steering_deg / full_steering_deg).clamp(-1.0, 1.0);
    format!(
        "{},{},{},{steering:.6},{:.6},{:.6},{:.4}",
        names[0],
        names[1],
        names[2],
        sample.throttle,
        sample.brake,
        sample.speed_kmh / KMH_PER_MPH
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(steering_deg: f64) -> Sample {
        Sample {
            t: 1.0,
            x: 0.0,
            y: 0.0,
            heading: 0.0,
            speed_kmh: 40.233_6,
            steering_deg,
            bolp: 0.0,
            dist_left_m: 1.0,
            dist_right_m: 1.0,
            oob_distance_m: 1.0,
            throttle: 0.5,
            brake: 0.0,
        }
    }

    #[test]
    fn rows_are_the_simulators_units_and_sign() {
        let names: Vec<String> = ["IMG/c.png", "IMG/l.png", "IMG/r.png"]
            .map(String::from)
            .into();
        // 12.5° to the left is -0.5 of the Udacity car's 25°, right-positive.
        assert_eq!(
            row(&names, &sample(12.5), 25.0, true),
            "IMG/c.png,IMG/l.png,IMG/r.png,-0.500000,0.500000,0.000000,25.0000"
        );
        assert!(row(&names, &sample(-40.0), 25.0, true).contains(",1.000000,"));
        assert!(row(&names, &sample(12.5), 25.0, false).contains(",0.500000,"));
    }
}
