//! Which driver is under test and how it is set up: its name, the competition's setup it is
//! judged by unless told otherwise (tolerance, speed limit, fitness) and its tuning.

use super::beamng_ai::{BeamNgAiParams, BeamNgAiProxy};
use super::controller::{ControllerConfig, ControllerParams};
use super::dave2::{self, Dave2Driver, Dave2DriverParams};
use super::onnx::{OnnxConfig, OnnxParams};
use crate::setting_checks::SettingsError;
use crate::sim::Driver;
use crate::vision::Dave2Weights;
use serde::{Deserialize, Serialize, Serializer};
use std::sync::Arc;

/// The drivers known by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum DriverKind {
    /// A path-tracking lane keeper in the spirit of BeamNG.AI (`beamng-ai-proxy`).
    #[default]
    #[serde(rename = "beamng-ai-proxy")]
    BeamNgAiProxy,
    /// DAVE-2 steering from a front camera (`dave2-proxy`).
    #[serde(rename = "dave2-proxy")]
    Dave2Proxy,
    /// A lane keeper in another process, `--oracle cmd:"COMMAND"` (`controller`).
    #[serde(rename = "controller")]
    Controller,
    /// A camera network in ONNX, `--oracle onnx:FILE` (`onnx`).
    #[serde(rename = "onnx")]
    Onnx,
}

/// A driver name that is not one of [`DriverKind::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown driver {name:?} (known: beamng-ai-proxy, dave2-proxy)")]
pub struct UnknownDriver {
    /// The name given.
    pub name: String,
}

impl DriverKind {
    /// The built-in drivers, known by name (a controller is given by its command, a camera
    /// network by its file).
    pub const ALL: [DriverKind; 2] = [DriverKind::BeamNgAiProxy, DriverKind::Dave2Proxy];

    /// The driver's name.
    pub fn name(self) -> &'static str {
        match self {
            DriverKind::BeamNgAiProxy => "beamng-ai-proxy",
            DriverKind::Dave2Proxy => "dave2-proxy",
            DriverKind::Controller => "controller",
            DriverKind::Onnx => "onnx",
        }
    }

    /// The built-in driver of that name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl std::fmt::Display for DriverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for DriverKind {
    type Err = UnknownDriver;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s).ok_or_else(|| UnknownDriver {
            name: s.to_string(),
        })
    }
}

/// One driver, ready to be built for each drive: its tuning and, for `dave2-proxy`, the
/// network's weights. Serialises as its tuning (the weights are not configuration).
#[derive(Debug, Clone)]
pub enum DriverConfig {
    /// `beamng-ai-proxy` with its tuning.
    BeamNgAiProxy(BeamNgAiParams),
    /// `dave2-proxy` with its settings and weights.
    Dave2Proxy {
        /// Control rate, set speed and speed controller.
        params: Dave2DriverParams,
        /// The network's weights.
        weights: Arc<Dave2Weights>,
    },
    /// A controller process, its command given on the command line.
    Controller(ControllerConfig),
    /// A camera network, its model file given on the command line.
    Onnx(OnnxConfig),
}

impl DriverConfig {
    /// The built-in driver `kind` with its default tuning (and the built-in DAVE-2 weights);
    /// `None` for a controller, which needs its command, and a camera network, which needs its
    /// model.
    pub fn built_in(kind: DriverKind) -> Option<Self> {
        match kind {
            DriverKind::BeamNgAiProxy => Some(Self::BeamNgAiProxy(BeamNgAiParams::default())),
            DriverKind::Dave2Proxy => Some(Self::Dave2Proxy {
                params: Dave2DriverParams::default(),
                weights: dave2::embedded_weights(),
            }),
            DriverKind::Controller | DriverKind::Onnx => None,
        }
    }

    /// The built-in driver `kind` with its default tuning; a controller of no command (which
    /// fails its first drive, saying so) for [`DriverKind::Controller`] and for
    /// [`DriverKind::Onnx`] (which needs its model: see [`OnnxConfig::load`]).
    pub fn default_for(kind: DriverKind) -> Self {
        Self::built_in(kind).unwrap_or_else(|| {
            Self::Controller(ControllerConfig::new(
                String::new(),
                ControllerParams::default(),
            ))
        })
    }

    /// Which driver this is.
    pub fn kind(&self) -> DriverKind {
        match self {
            Self::BeamNgAiProxy(_) => DriverKind::BeamNgAiProxy,
            Self::Dave2Proxy { .. } => DriverKind::Dave2Proxy,
            Self::Controller(_) => DriverKind::Controller,
            Self::Onnx(_) => DriverKind::Onnx,
        }
    }

    /// Names the first setting the driver cannot work with.
    pub fn validate(&self) -> Result<(), SettingsError> {
        match self {
            Self::BeamNgAiProxy(params) => params.validate(),
            Self::Dave2Proxy { params, .. } => params.validate(),
            Self::Controller(config) => config.params.validate(),
            Self::Onnx(config) => config.params.validate(),
        }
    }

    /// A new driver, for one drive.
    pub fn build(&self) -> Box<dyn Driver + Send> {
        match self {
            Self::BeamNgAiProxy(params) => Box::new(BeamNgAiProxy::new(*params)),
            Self::Dave2Proxy { params, weights } => Box::new(Dave2Driver::new(weights, *params)),
            Self::Controller(config) => Box::new(config.build()),
            Self::Onnx(config) => Box::new(config.build()),
        }
    }
}

impl Serialize for DriverConfig {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::BeamNgAiProxy(params) => params.serialize(serializer),
            Self::Dave2Proxy { params, .. } => params.serialize(serializer),
            // The command is recorded, never read back to start anything.
            Self::Controller(config) => {
                #[derive(Serialize)]
                struct Recorded<'a> {
                    command: &'a str,
                    #[serde(flatten)]
                    params: &'a ControllerParams,
                }
                Recorded {
                    command: &config.command,
                    params: &config.params,
                }
                .serialize(serializer)
            }
            // The model's path and checksum are recorded: a replay names the model itself and
            // is warned when the file it names has another checksum.
            Self::Onnx(config) => {
                #[derive(Serialize)]
                struct Recorded<'a> {
                    model: String,
                    model_sha256: &'a str,
                    #[serde(flatten)]
                    params: &'a OnnxParams,
                }
                Recorded {
                    model: config.model().path().display().to_string(),
                    model_sha256: config.model().sha256(),
                    params: &config.params,
                }
                .serialize(serializer)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for kind in DriverKind::ALL {
            assert_eq!(kind.name().parse::<DriverKind>(), Ok(kind));
            assert_eq!(
                serde_json::to_string(&kind).unwrap(),
                format!("\"{}\"", kind.name())
            );
            let config = DriverConfig::default_for(kind);
            assert_eq!(config.kind(), kind);
            assert_eq!(config.build().name(), kind.name());
        }
        assert_eq!(
            "dave3".parse::<DriverKind>().unwrap_err().to_string(),
            "unknown driver \"dave3\" (known: beamng-ai-proxy, dave2-proxy)"
        );
    }
}
