//! Options that choose and configure the driver under test, shared by `simulate` and `run`.

use crate::options::config_file::{self, ConfigFile};
use crate::options::value_parsers::{map_size_m, oracle, positive_kmh, share, Oracle};
use anyhow::{bail, Context, Result};
use clap::Args;
use road_sim::driver::{
    BeamNgAiParams, Contract, ControllerConfig, ControllerParams, Dave2DriverParams, OnnxConfig,
    OnnxParams,
};
use road_sim::vision::Dave2Weights;
use road_sim::{CompetitionSetup, DriverConfig, DriverKind, SimConfig};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The map's side unless `--map-size` says otherwise, metres (the competition's).
pub const DEFAULT_MAP_SIZE_M: f64 = 200.0;

/// The driver under test and how it is judged.
#[derive(Debug, Clone, Args)]
pub struct DriverOptions {
    /// The driver under test: beamng-ai-proxy, dave2-proxy, onnx:FILE for a camera network in
    /// ONNX (its contract: docs/reference.md), or cmd:"COMMAND" for a controller process (the
    /// controller protocol, docs/reference.md); a model or command is taken only from here.
    #[arg(long = "oracle", value_name = "ORACLE", default_value = "beamng-ai-proxy", value_parser = oracle)]
    pub oracle: Oracle,
    /// DAVE-2 weights written by `wogan train-driver` [default: the built-in ones].
    #[arg(long, value_name = "FILE")]
    pub driver_weights: Option<PathBuf>,
    /// The driver's speed limit, km/h [default: 70 for beamng-ai-proxy and controllers, 25 for
    /// dave2-proxy and onnx:FILE].
    #[arg(long, value_parser = positive_kmh, allow_negative_numbers = true)]
    pub speed_limit: Option<f64>,
    /// A drive fails when its BOLP exceeds this [default: 0.85 for beamng-ai-proxy and
    /// controllers, 0.10 for dave2-proxy and onnx:FILE].
    #[arg(long, value_parser = share, allow_negative_numbers = true)]
    pub oob_tolerance: Option<f64>,
    /// Side of the square map, metres.
    #[arg(long, default_value_t = DEFAULT_MAP_SIZE_M, value_parser = map_size_m, allow_negative_numbers = true)]
    pub map_size: f64,
}

impl DriverOptions {
    /// Which driver is under test.
    pub fn kind(&self) -> DriverKind {
        self.oracle.kind
    }

    /// The chosen driver with its default tuning, `patch` (a config file's `driver` section)
    /// laid over it, and the weights of `--driver-weights` if given.
    pub fn driver_config(&self, patch: Option<&serde_json::Value>) -> Result<DriverConfig> {
        driver_config(
            self.kind(),
            self.oracle.command.as_deref(),
            self.oracle.model.as_deref(),
            patch,
            self.driver_weights.as_deref(),
            "driver",
        )
    }

    /// The simulation settings and the driver these options and `file` ask for: the driver's
    /// competition setup and default tuning, the file's `sim` and `driver` sections laid over them,
    /// then the command line's options; or names the first setting that cannot be used.
    pub fn resolve(&self, file: &ConfigFile) -> Result<(SimConfig, DriverConfig)> {
        let setup = CompetitionSetup::of(self.kind()).sim_config();
        let sim = self.apply_to(config_file::lay_over(file.sim.as_ref(), setup, "sim")?);
        sim.validate().context("invalid simulation settings")?;
        let driver = self.driver_config(file.driver.as_ref())?;
        driver.validate().context("invalid driver settings")?;
        Ok((sim, driver))
    }

    /// The simulation and driver settings of a command that drives roads (`simulate`, `replay`):
    /// these options laid over the `sim` and `driver` sections of the `--config` file at
    /// `config`, which may not hold a `search` section.
    pub fn resolve_for_driving(
        &self,
        config: Option<&Path>,
        command: &str,
    ) -> Result<(SimConfig, DriverConfig)> {
        let file = ConfigFile::read_for(config, self.kind())?;
        if file.search.is_some() {
            bail!(
                "config file: \"search\" is for `wogan run`; `wogan {command}` reads \"sim\" and \"driver\""
            );
        }
        self.resolve(&file)
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

/// Driver `kind` with its default tuning, `patch` (named `section` in errors) laid over it, and
/// the DAVE-2 weights of the file `weights` if given (for `dave2-proxy` only). A controller's
/// `command` and a camera network's `model` come only from the command line: with none (a run
/// file's header), the driver is refused, naming what the file records, and nothing is started
/// or loaded.
pub fn driver_config(
    kind: DriverKind,
    command: Option<&str>,
    model: Option<&Path>,
    patch: Option<&serde_json::Value>,
    weights: Option<&Path>,
    section: &str,
) -> Result<DriverConfig> {
    let weights = weights.map(read_dave2_weights).transpose()?;
    if weights.is_some() && kind != DriverKind::Dave2Proxy {
        bail!("--driver-weights is for dave2-proxy, not {kind}");
    }
    if kind == DriverKind::Onnx {
        return onnx_config(model, patch, section);
    }
    let Some(mut driver) = DriverConfig::built_in(kind) else {
        let Some(command) = command else {
            let recorded = patch
                .and_then(|p| p.get("command"))
                .and_then(|c| c.as_str())
                .unwrap_or("?");
            bail!(
                "the driver is a controller process ({recorded}); wogan never starts a command a \
                 file names: give it yourself, e.g. --oracle cmd:\"{recorded}\""
            );
        };
        let mut patch = patch.cloned();
        if let Some(serde_json::Value::Object(fields)) = &mut patch {
            // A config file may tune a controller, never name what is run.
            if fields.contains_key("command") {
                bail!("{section}.command: a controller's command is taken only from --oracle cmd:\"...\"");
            }
        }
        let params = config_file::lay_over::<ControllerParams>(
            patch.as_ref(),
            ControllerParams::default(),
            section,
        )?;
        return Ok(DriverConfig::Controller(ControllerConfig::new(
            command.to_owned(),
            params,
        )));
    };
    match &mut driver {
        DriverConfig::BeamNgAiProxy(params) => {
            *params = config_file::lay_over::<BeamNgAiParams>(patch, *params, section)?;
        }
        DriverConfig::Dave2Proxy {
            params,
            weights: built_in,
        } => {
            *params = config_file::lay_over::<Dave2DriverParams>(patch, *params, section)?;
            if let Some(weights) = weights {
                *built_in = weights;
            }
        }
        DriverConfig::Controller(_) | DriverConfig::Onnx(_) => {}
    }
    Ok(driver)
}

/// A camera network: the model of `--oracle onnx:FILE`, loaded and checked, with `patch` laid
/// over the contract's defaults. A file may tune the network, never name the model.
fn onnx_config(
    model: Option<&Path>,
    patch: Option<&serde_json::Value>,
    section: &str,
) -> Result<DriverConfig> {
    let Some(model) = model else {
        let recorded = patch
            .and_then(|p| p.get("model"))
            .and_then(|c| c.as_str())
            .unwrap_or("?");
        bail!(
            "the driver is a camera network ({recorded}); wogan loads a model only from the \
             command line: give it yourself, e.g. --oracle onnx:{recorded}"
        );
    };
    let mut patch = patch.cloned();
    if let Some(serde_json::Value::Object(fields)) = &mut patch {
        if fields.contains_key("model") || fields.contains_key("model_sha256") {
            bail!(
                "{section}.model: a camera network's model is taken only from --oracle onnx:FILE"
            );
        }
    }
    // The named contract's settings first, then the section's own over them.
    let contract = match patch.as_ref().and_then(|p| p.get("contract")) {
        None => Contract::default(),
        Some(name) => serde_json::from_value::<Contract>(name.clone()).map_err(|_| {
            let known: Vec<&str> = Contract::ALL.iter().map(|c| c.name()).collect();
            anyhow::anyhow!(
                "config file, {section}.contract: {name} is not a contract; known: {}",
                known.join(", ")
            )
        })?,
    };
    let params =
        config_file::lay_over::<OnnxParams>(patch.as_ref(), OnnxParams::of(contract), section)?;
    params.validate().context("invalid driver settings")?;
    let config = OnnxConfig::load(model, params)?;
    Ok(DriverConfig::Onnx(config))
}

/// DAVE-2 weights written by `wogan train-driver`.
fn read_dave2_weights(path: &Path) -> Result<Arc<Dave2Weights>> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read driver weights {}", path.display()))?;
    let weights = Dave2Weights::from_bytes(&bytes)
        .with_context(|| format!("driver weights {}", path.display()))?;
    Ok(Arc::new(weights))
}
