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
use crate::options::driver_options::{DriverOptions, DrivingConfig};
use anyhow::{bail, Context, Result};
use child_process::printable;
use clap::Args;
use driver_training::{RandomRoads, MAX_DRAWS_PER_ROAD};
use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use road_sim::driver::{Contract, OnnxParams};
use road_sim::vision::{write_png, Camera, CameraParams, Frame, RoadScene};
use road_sim::{simulate, Road, Sample, StopReason, Validator};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError};
use std::time::Duration;

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
/// How often a wait for the next road of a file looks at the stop flag.
const STOP_POLL: Duration = Duration::from_millis(50);

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
    /// again from the first until enough frames are recorded (a pipe's once), instead of random
    /// roads; bad lines and invalid roads are named and skipped.
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
    #[command(flatten)]
    pub driving: DrivingConfig,
    /// Drives in a row that give no frame (the driver failed at the start) before the dataset
    /// stops, naming the driver's last error.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub max_failed_drives: u32,
}

/// Where the roads come from.
enum RoadSource {
    /// Random valid roads on the map.
    Random(Box<ChaCha20Rng>, RandomRoads),
    /// The valid roads of a file, read as they are driven.
    File(FileRoads),
}

impl RoadSource {
    /// The next road to drive: `Ok(None)` when there is none (a pipe's roads are driven once) or
    /// `stop` was set while waiting for one.
    fn next(&mut self, stop: &AtomicBool) -> Result<Option<Road>> {
        match self {
            RoadSource::Random(rng, roads) => match roads.draw(rng) {
                Some(road) => Ok(Some(road)),
                None => bail!(
                    "no valid random road in {MAX_DRAWS_PER_ROAD} draws: the roads do not fit \
                     the map (--map-size, --max-curvature)"
                ),
            },
            RoadSource::File(file) => file.next(stop),
        }
    }
}

/// What the reader of a roads file hands on.
enum FileItem {
    /// A valid road.
    Road(Road),
    /// The file ended; it is read again from its start (a regular file only).
    Restart,
}

/// The valid roads of a file, read on a thread of their own (so that Ctrl-C is answered while a
/// pipe stalls) one at a time, again from the first while frames are wanted (a regular file);
/// memory holds one road at a time whatever the file's size. Bad lines and invalid roads are
/// named and skipped.
struct FileRoads {
    roads: Receiver<Result<FileItem>>,
    path: PathBuf,
    /// Valid roads met since the file was last started.
    valid: usize,
}

impl FileRoads {
    fn open(path: &Path, map_size_m: f64) -> Result<Self> {
        // Opened here first, so that a missing or unreadable file is said before anything else.
        let first = open_input(Some(path))?;
        let again = std::fs::metadata(path).is_ok_and(|m| m.is_file());
        let (sender, roads) = sync_channel(1);
        let file = path.to_owned();
        std::thread::spawn(move || {
            let validator = Validator::new(map_size_m);
            let mut input = Some(first);
            loop {
                let lines = match input.take().map_or_else(|| open_input(Some(&file)), Ok) {
                    Ok(lines) => lines,
                    Err(error) => {
                        let _ = sender.send(Err(error));
                        return;
                    }
                };
                for road in roads_of_lines(lines, map_size_m, Some(&file)) {
                    let item = match road {
                        Ok((line, points)) => {
                            let verdict = validator.validate(&points);
                            match (verdict.reason, verdict.road) {
                                (None, Some(road)) => FileItem::Road(road),
                                (reason, _) => {
                                    eprintln!(
                                        "wogan dataset: {}: line {line}: skipped, the road is \
                                         invalid: {}",
                                        file.display(),
                                        reason.map_or("malformed", |r| r.message())
                                    );
                                    continue;
                                }
                            }
                        }
                        Err(error) => {
                            eprintln!("wogan dataset: skipped: {error:#}");
                            continue;
                        }
                    };
                    // The receiver is gone once the dataset is complete or stopped.
                    if sender.send(Ok(item)).is_err() {
                        return;
                    }
                }
                if !again || sender.send(Ok(FileItem::Restart)).is_err() {
                    return;
                }
            }
        });
        Ok(Self {
            roads,
            path: path.to_owned(),
            valid: 0,
        })
    }

    fn next(&mut self, stop: &AtomicBool) -> Result<Option<Road>> {
        loop {
            if stop.load(Ordering::SeqCst) {
                return Ok(None);
            }
            match self.roads.recv_timeout(STOP_POLL) {
                Ok(Ok(FileItem::Road(road))) => {
                    self.valid += 1;
                    return Ok(Some(road));
                }
                Ok(Ok(FileItem::Restart)) if self.valid == 0 => {
                    bail!("{}: no valid road", self.path.display())
                }
                Ok(Ok(FileItem::Restart)) => self.valid = 0,
                Ok(Err(error)) => return Err(error),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) if self.valid == 0 => {
                    bail!("{}: no valid road", self.path.display())
                }
                Err(RecvTimeoutError::Disconnected) => return Ok(None),
            }
        }
    }
}

/// Creates the dataset's folders, refusing a folder that holds anything, or anything else in
/// its place.
fn create_folders(out: &Path) -> Result<()> {
    match std::fs::symlink_metadata(out) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => bail!("--out {}: cannot be read: {e}", out.display()),
        Ok(_) if !out.exists() => bail!("--out {}: a link to nothing", out.display()),
        Ok(_) if !out.is_dir() => bail!("--out {}: exists and is not a folder", out.display()),
        Ok(_) => {
            let mut entries = std::fs::read_dir(out)
                .with_context(|| format!("--out {}: cannot be read", out.display()))?;
            if entries.next().is_some() {
                bail!(
                    "--out {}: the folder is not empty (a dataset is never written over)",
                    out.display()
                );
            }
        }
    }
    std::fs::create_dir_all(out.join("IMG"))
        .with_context(|| format!("cannot create {}", out.join("IMG").display()))
}

/// `driving_log.csv`, appended a whole row at a time: a row that cannot be written whole is cut
/// off again, so the file always ends with a whole row.
struct DrivingLog {
    file: std::fs::File,
    path: PathBuf,
    /// Bytes of whole rows written.
    len: u64,
}

impl DrivingLog {
    fn create(path: PathBuf) -> Result<Self> {
        let file = std::fs::File::create(&path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        Ok(Self { file, path, len: 0 })
    }

    fn append(&mut self, row: &str) -> Result<()> {
        let line = format!("{row}\n");
        match self
            .file
            .write_all(line.as_bytes())
            .and_then(|()| self.file.flush())
        {
            Ok(()) => {
                self.len += line.len() as u64;
                Ok(())
            }
            Err(error) => {
                // A disk that filled mid-row: the partial row goes, the whole ones stay.
                let _ = self.file.set_len(self.len);
                Err(error).with_context(|| format!("cannot write {}", self.path.display()))
            }
        }
    }
}

/// Runs `wogan dataset`.
pub fn run(args: &DatasetArgs) -> Result<Status> {
    let stop = stop_flag()?;
    let (config, driver) = args
        .driver
        .resolve_for_driving(args.driving.config.as_deref(), "dataset")?;
    let map_size_m = args.driver.map_size;
    let mut source = match &args.roads {
        Some(path) => RoadSource::File(FileRoads::open(path, map_size_m)?),
        None => RoadSource::Random(
            Box::new(ChaCha20Rng::seed_from_u64(args.seed)),
            RandomRoads::new(5, args.max_curvature, map_size_m),
        ),
    };
    if let RoadSource::Random(rng, roads) = &source {
        // A map no road fits on is said before the dataset's folder is made (a copy of the
        // generator draws, so the dataset's roads are those of the seed).
        if roads.draw(&mut rng.as_ref().clone()).is_none() {
            bail!(
                "--map-size {map_size_m}: no valid random road in {MAX_DRAWS_PER_ROAD} draws: the \
                 roads do not fit the map (--max-curvature {})",
                args.max_curvature
            );
        }
    }
    create_folders(&args.out)?;
    let mut log = DrivingLog::create(args.out.join("driving_log.csv"))?;

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
    let mut frameless_in_a_row = 0;
    let ended = loop {
        if written >= args.frames {
            break Ending::Complete;
        }
        if stop.load(Ordering::SeqCst) {
            break Ending::Interrupted;
        }
        let road = match source.next(&stop)? {
            Some(road) => road,
            None if stop.load(Ordering::SeqCst) => break Ending::Interrupted,
            None => break Ending::OutOfRoads,
        };
        roads += 1;
        let result = simulate(&road, driver.build().as_mut(), &config, true, Some(&stop));
        if result.reason == Some(StopReason::Interrupted) {
            break Ending::Interrupted;
        }
        let scene = RoadScene::new(&road);
        let mut next_t = 0.0;
        let before = written;
        for sample in result.trace.unwrap_or_default() {
            if written >= args.frames || stop.load(Ordering::SeqCst) {
                break;
            }
            if sample.t + 1e-9 < next_t {
                continue;
            }
            next_t += 1.0 / args.record_hz;
            let number = written + 1;
            let mut names = Vec::with_capacity(3);
            let mut pictures = || -> Result<()> {
                for (name, camera) in &cameras {
                    camera.render_rgb_into(
                        &scene,
                        [sample.x, sample.y],
                        sample.heading,
                        &mut frame,
                    );
                    let relative = format!("IMG/{name}_{number:07}.png");
                    let path = args.out.join(&relative);
                    names.push(relative);
                    write_png(&path, &frame)
                        .with_context(|| format!("cannot write {}", path.display()))?;
                }
                log.append(&row(&names, &sample, full_steering_deg, right_positive))
            };
            if let Err(error) = pictures() {
                // The frame is not in the log: its pictures go too, so the dataset stays whole.
                for name in &names {
                    let _ = std::fs::remove_file(args.out.join(name));
                }
                eprintln!("wogan dataset: {error:#}");
                eprintln!(
                    "wogan dataset: stopped: {written} whole frames from {roads} roads kept in {}",
                    args.out.display()
                );
                return Ok(Status::Failed);
            }
            written = number;
        }
        eprintln!(
            "wogan dataset: road {roads}: {} ({:.1} s); {written}/{} frames",
            result.outcome.name(),
            result.sim_time_s,
            args.frames
        );
        if written > before {
            frameless_in_a_row = 0;
            continue;
        }
        frameless_in_a_row += 1;
        if frameless_in_a_row >= args.max_failed_drives {
            let why = result.error.as_deref().unwrap_or("no reason given");
            eprintln!(
                "wogan dataset: {frameless_in_a_row} drives in a row gave no frame (--max-failed-drives); \
                 the driver's last error: {}",
                printable(why)
            );
            break Ending::DriverFailing;
        }
    };
    let summary = format!(
        "{written} frames from {roads} roads to {}",
        args.out.display()
    );
    Ok(match ended {
        Ending::Complete => {
            eprintln!("wogan dataset: wrote {summary}");
            Status::AllRead
        }
        Ending::Interrupted => {
            eprintln!("wogan dataset: interrupted: wrote {summary}");
            Status::Interrupted
        }
        Ending::OutOfRoads => {
            eprintln!(
                "wogan dataset: the roads ran out (a pipe's roads are driven once): wrote {summary}"
            );
            Status::Failed
        }
        Ending::DriverFailing => {
            eprintln!("wogan dataset: stopped: wrote {summary}");
            Status::Failed
        }
    })
}

/// Why the recording ended.
enum Ending {
    /// Every frame asked for was recorded.
    Complete,
    /// Ctrl-C or SIGTERM.
    Interrupted,
    /// A pipe's roads were all driven.
    OutOfRoads,
    /// Too many drives in a row gave no frame.
    DriverFailing,
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
