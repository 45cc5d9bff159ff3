//! Options that choose and configure the driver under test, shared by `simulate` and `run`.

use crate::options::config_file::{self, ConfigFile, SettingsSource};
use crate::options::value_parsers::{map_size_m, oracle, positive_kmh, share, Oracle};
use anyhow::{bail, Context, Result};
use clap::Args;
use road_sim::driver::{
    BeamNgAiParams, Contract, ControllerConfig, ControllerParams, Dave2DriverParams, OnnxConfig,
    OnnxParams,
};
use road_sim::setting_checks::SettingsError;
use road_sim::vision::Dave2Weights;
use road_sim::{CompetitionSetup, DriverConfig, DriverKind, SimConfig};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The map's side unless `--map-size` says otherwise, metres (the competition's).
pub const DEFAULT_MAP_SIZE_M: f64 = 200.0;

/// `--config` of the commands that drive given roads (`simulate`, `replay`, `dataset`).
#[derive(Debug, Clone, Args)]
pub struct DrivingConfig {
    /// JSON file overriding the simulation's and the driver's defaults: `{"sim": {...},
    /// "driver": {...}}`, as `wogan run --config` reads them (a `search` section is refused).
    /// Options given on the command line win over the file.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

/// `--jobs` of the commands that drive given roads (`simulate`, `replay`).
#[derive(Debug, Clone, Args)]
pub struct RoadJobs {
    /// Roads driven at once (output keeps the input order; results do not depend on it).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256), allow_negative_numbers = true)]
    pub jobs: u32,
}

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

    /// What only the command line gives the driver: a controller's command, a camera network's
    /// model, DAVE-2 weights.
    pub fn inputs(&self) -> DriverInputs<'_> {
        DriverInputs {
            command: self.oracle.command.as_deref(),
            model: self.oracle.model.as_deref(),
            weights: self.driver_weights.as_deref(),
        }
    }

    /// The simulation settings and the driver these options and `file` ask for: the driver's
    /// competition setup and default tuning, the file's `sim` and `driver` sections laid over them,
    /// then the command line's options ([`checked_settings`]); or names the first setting that
    /// cannot be used.
    pub fn resolve(&self, file: &ConfigFile) -> Result<(SimConfig, DriverConfig)> {
        checked_settings(
            SettingsSource::ConfigFile(file.path.as_deref()),
            self.kind(),
            file.sim.as_ref(),
            file.driver.as_ref(),
            self.inputs(),
            |sim| self.apply_to(sim),
        )
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

/// What only the command line gives a driver; a file (a config file, a run's header) never does.
#[derive(Debug, Clone, Copy, Default)]
pub struct DriverInputs<'a> {
    /// A controller's command (`--oracle cmd:"..."`).
    pub command: Option<&'a str>,
    /// A camera network's model (`--oracle onnx:FILE`).
    pub model: Option<&'a Path>,
    /// DAVE-2 weights (`--driver-weights`), for `dave2-proxy` only.
    pub weights: Option<&'a Path>,
}

/// A setting outside its range, named by where it was read and its path there.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{origin}, {setting} must be {requirement}")]
pub struct SettingOutOfRange {
    /// Where the setting was read: `config file x.json`, `the run's header`.
    pub origin: String,
    /// Its path there: `sim.physics_hz`, `config.driver.control_hz`.
    pub setting: String,
    /// What it must be: `from 10 to 1000 (got 0)`.
    pub requirement: String,
}

impl SettingOutOfRange {
    /// `problem` (a setting of section `section`, or of the driver's when its path begins with
    /// `driver.`) read from `source`.
    fn of(source: SettingsSource<'_>, section: &str, problem: SettingsError) -> Self {
        let setting = match problem.setting.strip_prefix("driver.") {
            Some(field) => format!("{}.{field}", source.section("driver")),
            None => format!("{}.{}", source.section(section), problem.setting),
        };
        Self {
            origin: source.name(),
            setting,
            requirement: problem.requirement,
        }
    }
}

/// The one way simulation and driver settings are read, whatever their source (a `--config` file
/// with the options over it, a run's header): the driver's competition setup and default tuning,
/// the source's `sim` and `driver` sections laid over them, `options` applied to the simulation's,
/// then every range checked ([`SimConfig::validate`], [`DriverConfig::validate`]), so that no
/// source drives with a setting another would refuse. An error names the source and the field:
/// "the run's header, config.sim.physics_hz must be from 10 to 1000 (got 0)".
pub fn checked_settings(
    source: SettingsSource<'_>,
    kind: DriverKind,
    sim: Option<&serde_json::Value>,
    driver: Option<&serde_json::Value>,
    inputs: DriverInputs<'_>,
    options: impl FnOnce(SimConfig) -> SimConfig,
) -> Result<(SimConfig, DriverConfig)> {
    let setup = CompetitionSetup::of(kind).sim_config();
    let origin = source.name();
    let sim = options(config_file::lay_over_from(
        &origin,
        sim,
        setup,
        &source.section("sim"),
    )?);
    sim.validate()
        .map_err(|problem| SettingOutOfRange::of(source, "sim", problem))?;
    let driver = driver_config(source, kind, inputs, driver)?;
    driver
        .validate()
        .map_err(|problem| SettingOutOfRange::of(source, "driver", problem))?;
    Ok((sim, driver))
}

/// Driver `kind` with its default tuning, `patch` (the source's `driver` section) laid over it,
/// and the DAVE-2 weights of the file `inputs.weights` if given (for `dave2-proxy` only). A
/// controller's command and a camera network's model come only from the command line: with none
/// (a run file's header), the driver is refused, naming what the file records, and nothing is
/// started or loaded. Ranges are checked by [`checked_settings`].
fn driver_config(
    source: SettingsSource<'_>,
    kind: DriverKind,
    inputs: DriverInputs<'_>,
    patch: Option<&serde_json::Value>,
) -> Result<DriverConfig> {
    let (origin, section) = (source.name(), source.section("driver"));
    let weights = inputs.weights.map(read_dave2_weights).transpose()?;
    if weights.is_some() && kind != DriverKind::Dave2Proxy {
        bail!("--driver-weights is for dave2-proxy, not {kind}");
    }
    if kind == DriverKind::Onnx {
        return onnx_config(source, inputs.model, patch);
    }
    let Some(mut driver) = DriverConfig::built_in(kind) else {
        let Some(command) = inputs.command else {
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
                bail!("{origin}, {section}.command: a controller's command is taken only from --oracle cmd:\"...\"");
            }
        }
        let params = config_file::lay_over_from::<ControllerParams>(
            &origin,
            patch.as_ref(),
            ControllerParams::default(),
            &section,
        )?;
        return Ok(DriverConfig::Controller(ControllerConfig::new(
            command.to_owned(),
            params,
        )));
    };
    match &mut driver {
        DriverConfig::BeamNgAiProxy(params) => {
            *params =
                config_file::lay_over_from::<BeamNgAiParams>(&origin, patch, *params, &section)?;
        }
        DriverConfig::Dave2Proxy {
            params,
            weights: built_in,
        } => {
            *params =
                config_file::lay_over_from::<Dave2DriverParams>(&origin, patch, *params, &section)?;
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
    source: SettingsSource<'_>,
    model: Option<&Path>,
    patch: Option<&serde_json::Value>,
) -> Result<DriverConfig> {
    let (origin, section) = (source.name(), source.section("driver"));
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
                "{origin}, {section}.model: a camera network's model is taken only from --oracle onnx:FILE"
            );
        }
    }
    // The named contract's settings first, then the section's own over them.
    let contract = match patch.as_ref().and_then(|p| p.get("contract")) {
        None => Contract::default(),
        Some(name) => serde_json::from_value::<Contract>(name.clone()).map_err(|_| {
            let known: Vec<&str> = Contract::ALL.iter().map(|c| c.name()).collect();
            anyhow::anyhow!(
                "{origin}, {section}.contract: {name} is not a contract; known: {}",
                known.join(", ")
            )
        })?,
    };
    let params = config_file::lay_over_from::<OnnxParams>(
        &origin,
        patch.as_ref(),
        OnnxParams::of(contract),
        &section,
    )?;
    // Checked before the model is loaded (the crop rows against the frame, say).
    params
        .validate()
        .map_err(|problem| SettingOutOfRange::of(source, "driver", problem))?;
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
