//! `wogan sample`: valid, likely-failing roads from a saved generator (`wogan run
//! --save-generator`), in seconds and without training. Each road is chosen as WOGAN chooses a test
//! (generated candidates, invalid ones dropped, the rest ranked by the analyzer until one clears
//! the decaying acceptance target); the roads are written ranked by the analyzer's prediction, best
//! first, as JSON lines that `simulate` and `replay` read. Same file and seed, same roads. Ctrl-C
//! ends the drawing and writes the roads drawn so far.

use super::Status;
use crate::files::generator_file;
use crate::files::json_lines::JsonLinesWriter;
use crate::files::records::{Record, SampleRecord};
use crate::interrupt::stop_flag;
use crate::sut::road_sut::RoadSut;
use anyhow::{bail, Context, Result};
use clap::Args;
use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use road_sim::{DriverConfig, DriverKind, FitnessKind, SimConfig, Validator};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use wogan_core::{Sampler, WoganModel};

/// Options of `wogan sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// The generator file `wogan run --save-generator` wrote.
    #[arg(long, value_name = "FILE")]
    pub generator: PathBuf,
    /// How many roads.
    #[arg(short = 'n', long = "count", default_value_t = 50, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub count: u64,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Write the JSON lines to FILE instead of standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Runs `wogan sample`.
pub fn run(args: &SampleArgs) -> Result<Status> {
    if let Some(out) = &args.out {
        if out == &args.generator || crate::files::output_file::same_file(out, &args.generator) {
            bail!(
                "--out {} is the generator file; write the roads elsewhere",
                out.display()
            );
        }
    }
    let saved = generator_file::read(&args.generator)?;
    let model = WoganModel::from_snapshot(&saved.model)
        .with_context(|| format!("{}: payload.model", args.generator.display()))?;
    // Only the road space matters here (which vectors are valid roads, and their points): no road
    // is driven, so the driver is any.
    let stop = AtomicBool::new(false);
    let roads = RoadSut {
        roads: saved.road,
        curvature_points: saved.curvature_points,
        shape: saved.road_shape,
        min_turn_rad: saved.min_road_turn_rad,
        validator: Validator::new(saved.road.map_size_m),
        driver: DriverConfig::default_for(DriverKind::BeamNgAiProxy),
        sim: SimConfig::default(),
        fitness: FitnessKind::Bolp,
        stop: &stop,
        streak: None,
    };
    // Ctrl-C ends the drawing: the roads drawn so far are written, ranked.
    let interrupt = stop_flag()?;
    let go_on = || !interrupt.load(Ordering::SeqCst);
    let sampler = Sampler::new(saved.curvature_points, saved.sampler.clone()).interruptible(&go_on);
    let mut rng = ChaCha20Rng::seed_from_u64(args.seed);
    eprintln!(
        "wogan sample: drawing {} road(s) from {}",
        args.count,
        args.generator.display()
    );
    let mut samples = Vec::with_capacity(args.count as usize);
    for _ in 0..args.count {
        match model.propose(&roads, &sampler, &mut rng) {
            Ok(proposal) => samples.push(proposal),
            Err(wogan_core::Error::Interrupted) => break,
            Err(error) => return Err(error.into()),
        }
    }
    let interrupted = interrupt.load(Ordering::SeqCst);
    // Best first; equal predictions keep the order they were drawn in.
    samples.sort_by(|a, b| {
        let p = |s: &wogan_core::Proposal| s.predicted.unwrap_or(f64::NEG_INFINITY);
        p(b).total_cmp(&p(a))
    });
    let mut out = JsonLinesWriter::create(args.out.as_ref())?;
    let samples_written = samples.len();
    for (rank, proposal) in samples.into_iter().enumerate() {
        let curvature = roads.curvature(&proposal.test);
        let road_points = roads.roads.points(&curvature);
        out.write(&Record::Sample(SampleRecord {
            rank: rank + 1,
            predicted_fitness: proposal.predicted,
            curvature,
            road_points,
        }))?;
    }
    eprintln!(
        "wogan sample: {} road(s) from {} (trained against {} on {} tests, seed {})",
        samples_written,
        args.generator.display(),
        saved.driver,
        saved.tests,
        saved.seed
    );
    Ok(if interrupted {
        Status::Interrupted
    } else {
        Status::AllRead
    })
}
