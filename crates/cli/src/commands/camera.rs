//! `wogan camera`: what `dave2-proxy`'s camera, or a camera network contract's, sees from the
//! right lane of a road, as PNG.

use super::Status;
use crate::files::json_lines::open_input;
use crate::files::road_input::roads_of_lines;
use anyhow::{bail, Context, Result};
use clap::Args;
use road_sim::driver::{Contract, OnnxParams};
use road_sim::sim::start_pose;
use road_sim::vision::{write_png, Camera, CameraParams, RoadScene};
use road_sim::Validator;
use std::path::PathBuf;

/// Options of `wogan camera`.
#[derive(Debug, Args)]
pub struct CameraArgs {
    /// JSON lines of roads (the forms `wogan validate` reads); the first road is used.
    /// Standard input when absent or `-`.
    pub file: Option<PathBuf>,
    /// Distances along the road, metres, at which the car stands on the right-lane centre.
    #[arg(long, value_delimiter = ',', default_value = "2.5", allow_negative_numbers = true, value_parser = crate::options::value_parsers::distance_along_m)]
    pub at: Vec<f64>,
    /// Where to write the pictures: `DIR/camera.<metres>.png`.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Write the network's grayscale input instead of the colour picture.
    #[arg(long)]
    pub gray: bool,
    /// The camera of a camera network's contract (`sbst2022`, `udacity`) at its render size,
    /// instead of dave2-proxy's.
    #[arg(long, value_name = "NAME", value_parser = crate::options::value_parsers::contract)]
    pub contract: Option<Contract>,
    /// Side of the square map, metres.
    #[arg(long, default_value_t = 200.0, value_parser = crate::options::value_parsers::map_size_m, allow_negative_numbers = true)]
    pub map_size: f64,
}

/// Runs `wogan camera`.
pub fn run(args: &CameraArgs) -> Result<Status> {
    let input = open_input(args.file.as_deref())?;
    let road_points = roads_of_lines(input, args.map_size, args.file.as_deref())
        .next()
        .transpose()?
        .map(|(_, points)| points);
    let Some(road_points) = road_points else {
        bail!("the input holds no road");
    };
    let verdict = Validator::new(args.map_size).validate(&road_points);
    let (Some(road), None) = (verdict.road, verdict.reason) else {
        bail!(
            "the road is invalid: {}",
            verdict.reason.map_or("malformed", |r| r.message())
        );
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let proxy = CameraParams::default();
    let camera = Camera::new(match args.contract {
        // A contract's camera renders at dave2-proxy's size when it has none of its own.
        Some(contract) => OnnxParams::of(contract)
            .camera
            .camera(proxy.width, proxy.height),
        None => proxy,
    });
    let scene = RoadScene::new(&road);
    if let Some(beyond) = args.at.iter().find(|&&at| at > road.length_m()) {
        bail!(
            "--at {beyond}: the road is only {:.1} m long",
            road.length_m()
        );
    }
    for &distance_m in &args.at {
        let (position, heading_rad) = start_pose(&road, distance_m);
        let frame = if args.gray {
            camera.render(&scene, position, heading_rad)
        } else {
            camera.render_rgb(&scene, position, heading_rad)
        };
        let path = args.out.join(format!("camera.{distance_m}.png"));
        write_png(&path, &frame).with_context(|| format!("cannot write {}", path.display()))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(Status::AllRead)
}
