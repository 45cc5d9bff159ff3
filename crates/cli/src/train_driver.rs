//! `wogan train-driver`: behaviour cloning of `dave2-proxy` from the `beamng-ai-proxy` teacher.

use crate::Status;
use anyhow::{Context, Result};
use clap::Args;
use road_sim::behaviour_cloning::{train, CloningConfig, CloningProgress};
use serde::Serialize;
use std::path::PathBuf;

/// Options of `wogan train-driver`.
#[derive(Debug, Args)]
pub struct TrainDriverArgs {
    /// Seed of every random choice: the same seed gives the same weights (the built-in ones are
    /// seed 1 with the defaults).
    #[arg(long, default_value_t = CloningConfig::default().seed)]
    pub seed: u64,
    /// Where to write the weights (load them with `--driver-weights FILE`).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Random roads driven for training frames.
    #[arg(long, default_value_t = CloningConfig::default().training_roads)]
    pub roads: usize,
    /// Largest curvature of the training roads, 1/m (the search's roads go up to 0.07).
    #[arg(long, default_value_t = CloningConfig::default().max_curvature_per_m)]
    pub max_curvature: f64,
    /// Passes over the training frames.
    #[arg(long, default_value_t = CloningConfig::default().epochs)]
    pub epochs: usize,
    /// Wall-clock limit of the whole training, minutes (no epoch starts that would end later).
    #[arg(long, default_value_t = CloningConfig::default().time_limit_s / 60.0)]
    pub minutes: f64,
}

#[derive(Serialize)]
struct ReportRecord<'a> {
    #[serde(rename = "type")]
    kind: &'static str,
    weights: String,
    config: &'a CloningConfig,
    #[serde(flatten)]
    report: &'a road_sim::behaviour_cloning::CloningReport,
}

/// Runs `wogan train-driver`.
pub fn run(args: &TrainDriverArgs) -> Result<Status> {
    let config = CloningConfig {
        seed: args.seed,
        training_roads: args.roads,
        validation_roads: (args.roads / 6).max(1),
        epochs: args.epochs,
        max_curvature_per_m: args.max_curvature,
        time_limit_s: args.minutes * 60.0,
        ..CloningConfig::default()
    };
    let (weights, report) = train(&config, &mut |progress| match progress {
        CloningProgress::Recorded { roads, of, frames } if roads == of || roads % 20 == 0 => {
            eprintln!("recorded {roads}/{of} roads, {frames} frames");
        }
        CloningProgress::Recorded { .. } => {}
        CloningProgress::Epoch {
            epoch,
            of,
            loss,
            validation_rmse_deg,
            seconds,
        } => {
            eprintln!("epoch {epoch}/{of}: training loss {loss:.5}, validation error {validation_rmse_deg:.3} deg, {seconds:.0} s");
        }
    });
    std::fs::write(&args.out, weights.to_bytes())
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    let record = ReportRecord {
        kind: "driver",
        weights: args.out.display().to_string(),
        config: &config,
        report: &report,
    };
    println!("{}", serde_json::to_string(&record)?);
    Ok(Status::AllRead)
}
