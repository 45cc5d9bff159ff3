//! Options that choose and configure the driver under test, shared by `simulate` and `run`.

use crate::validate::positive_metres;
use anyhow::{bail, Context, Result};
use clap::Args;
use road_sim::dave2::Dave2Weights;
use road_sim::{DriverKind, DriverSetup, SimConfig};
use std::path::PathBuf;

/// The driver under test and how it is judged.
#[derive(Debug, Clone, Args)]
pub struct SimOptions {
    /// The driver under test: beamng-ai-proxy or dave2-proxy.
    #[arg(long, default_value = "beamng-ai-proxy", value_parser = parse_oracle)]
    pub oracle: DriverKind,
    /// DAVE-2 weights written by `wogan train-driver` [default: the built-in ones].
    #[arg(long, value_name = "FILE")]
    pub driver_weights: Option<PathBuf>,
    /// The driver's speed limit, km/h [default: 70 for beamng-ai-proxy, 25 for dave2-proxy].
    #[arg(long, value_parser = positive_kmh, allow_negative_numbers = true)]
    pub speed_limit: Option<f64>,
    /// A drive fails when its BOLP exceeds this [default: 0.85 for beamng-ai-proxy, 0.10 for
    /// dave2-proxy].
    #[arg(long, value_parser = share, allow_negative_numbers = true)]
    pub oob_tolerance: Option<f64>,
    /// Side of the square map, metres.
    #[arg(long, default_value_t = 200.0, value_parser = positive_metres, allow_negative_numbers = true)]
    pub map_size: f64,
}

impl SimOptions {
    /// The chosen driver's default simulation settings.
    pub fn driver_defaults(&self) -> SimConfig {
        SimConfig {
            oob_tolerance: self.oracle.default_oob_tolerance(),
            speed_limit_kmh: self.oracle.default_speed_limit_kmh(),
            ..SimConfig::default()
        }
    }

    /// The driver to build for each drive, with the weights of `--driver-weights` if given.
    pub fn driver_setup(&self) -> Result<DriverSetup> {
        let setup = DriverSetup::new(self.oracle);
        let Some(path) = &self.driver_weights else {
            return Ok(setup);
        };
        if self.oracle != DriverKind::Dave2Proxy {
            bail!("--driver-weights is for dave2-proxy, not {}", self.oracle);
        }
        let bytes = std::fs::read(path)
            .with_context(|| format!("cannot read driver weights {}", path.display()))?;
        let weights = Dave2Weights::from_bytes(&bytes)
            .with_context(|| format!("driver weights {}", path.display()))?;
        Ok(setup.with_dave2_weights(weights))
    }

    /// The simulation settings these options ask for, on the driver's defaults.
    pub fn sim_config(&self) -> SimConfig {
        self.apply_to(self.driver_defaults())
    }

    /// `base` with the options given on the command line applied.
    pub fn apply_to(&self, base: SimConfig) -> SimConfig {
        SimConfig {
            speed_limit_kmh: self.speed_limit.unwrap_or(base.speed_limit_kmh),
            oob_tolerance: self.oob_tolerance.unwrap_or(base.oob_tolerance),
            ..base
        }
    }
}

fn parse_oracle(name: &str) -> Result<DriverKind, String> {
    DriverKind::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = DriverKind::ALL.iter().map(|k| k.name()).collect();
        format!("unknown oracle {name:?}; known: {}", known.join(", "))
    })
}

fn positive_kmh(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 300.0 => Ok(v),
        _ => Err(format!(
            "expected a speed in km/h between 0 and 300, got {text:?}"
        )),
    }
}

fn share(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("expected a number between 0 and 1, got {text:?}")),
    }
}
