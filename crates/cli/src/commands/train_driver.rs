//! `wogan train-driver`: behaviour cloning of `dave2-proxy` from the `beamng-ai-proxy` teacher.

use super::Status;
use crate::files::json_lines::JsonLinesWriter;
use crate::files::records::{DriverRecord, Record};
use crate::options::config_file;
use anyhow::{Context, Result};
use clap::Args;
use driver_training::{train, CloningConfig, CloningProgress};
use std::path::PathBuf;

/// Options of `wogan train-driver`.
#[derive(Debug, Args)]
pub struct TrainDriverArgs {
    /// Seed of every random choice: the same seed gives the same weights (the built-in ones are
    /// seed 1 with the defaults) [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// Where to write the weights (load them with `--driver-weights FILE`).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Random roads driven for training frames (validation roads: a sixth as many)
    /// [default: 120].
    #[arg(long, allow_negative_numbers = true)]
    pub roads: Option<usize>,
    /// Largest curvature of the training roads, 1/m (the search's roads go up to 0.07)
    /// [default: 0.03].
    #[arg(long, allow_negative_numbers = true)]
    pub max_curvature: Option<f64>,
    /// Passes over the training frames [default: 4].
    #[arg(long, allow_negative_numbers = true)]
    pub epochs: Option<usize>,
    /// Wall-clock limit of the whole training, minutes (no epoch starts that would end later)
    /// [default: 28].
    #[arg(long, allow_negative_numbers = true)]
    pub minutes: Option<f64>,
    /// JSON file overriding the training defaults, e.g. `{"noise_max_rad": 0.1, "teacher":
    /// {"lookahead_base_m": 3.0}}` (the output line's `config` shows every field). Options given
    /// on the command line win over the file.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

impl TrainDriverArgs {
    /// The training settings: defaults, then the `--config` file, then the options.
    fn cloning_config(&self) -> Result<CloningConfig> {
        let patch = self
            .config
            .as_deref()
            .map(config_file::read::<serde_json::Value>)
            .transpose()?;
        let mut config =
            config_file::lay_over(patch.as_ref(), CloningConfig::default(), "training")?;
        if let Some(seed) = self.seed {
            config.seed = seed;
        }
        if let Some(roads) = self.roads {
            config.training_roads = roads;
            config.validation_roads = (roads / 6).max(1);
        }
        if let Some(max_curvature) = self.max_curvature {
            config.max_curvature_per_m = max_curvature;
        }
        if let Some(epochs) = self.epochs {
            config.epochs = epochs;
        }
        if let Some(minutes) = self.minutes {
            config.time_limit_s = minutes * 60.0;
        }
        config
            .validate()
            .map_err(|problem| anyhow::anyhow!("invalid training settings: {problem}"))?;
        Ok(config)
    }
}

/// Runs `wogan train-driver`.
pub fn run(args: &TrainDriverArgs) -> Result<Status> {
    let config = args.cloning_config()?;
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
    })?;
    std::fs::write(&args.out, weights.to_bytes())
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    JsonLinesWriter::create(None)?.write(&Record::Driver(DriverRecord {
        weights: args.out.display().to_string(),
        config,
        report,
    }))?;
    Ok(Status::AllRead)
}
