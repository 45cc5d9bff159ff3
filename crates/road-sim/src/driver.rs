//! Drivers: what controls the car. A driver sees what the car knows (its pose, speed and
//! steering, the road, the time) and answers with steering, throttle and brake, at its own rate.

use crate::beamng_ai::BeamNgAiProxy;
use crate::dave2::Dave2Weights;
use crate::dave2_driver::Dave2Driver;
use crate::road::Road;
use crate::simulation::SimConfig;
use crate::vehicle::{CarState, Command, VehicleParams};
use serde::{Deserialize, Serialize};
use std::sync::{Arc, OnceLock};

/// What a driver is told at each of its control ticks.
#[derive(Debug, Clone, Copy)]
pub struct Observation<'a> {
    /// Simulated time since the start, seconds.
    pub time_s: f64,
    /// The car's pose, speed and steering.
    pub car: CarState,
    /// The road being driven.
    pub road: &'a Road,
}

/// A lane-keeping driver.
pub trait Driver {
    /// The driver's name, as the CLI's `--oracle` spells it.
    fn name(&self) -> &'static str;
    /// How often the driver acts, hertz (the simulation holds the last command in between).
    fn control_hz(&self) -> f64;
    /// Prepares for a drive on `road` with a car of `vehicle`'s build and a speed limit.
    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64);
    /// The command for the next control period.
    fn act(&mut self, observation: &Observation<'_>) -> Command;
}

/// Throttle and brake, each in `[0, 1]`, of a proportional speed controller: throttle for a
/// speed deficit (`speed_error_mps > 0`), brake only for an excess beyond the deadband.
pub fn pedals(
    speed_error_mps: f64,
    throttle_gain: f64,
    brake_gain: f64,
    brake_deadband_mps: f64,
) -> (f64, f64) {
    if speed_error_mps >= 0.0 {
        ((throttle_gain * speed_error_mps).min(1.0), 0.0)
    } else if -speed_error_mps > brake_deadband_mps {
        (
            0.0,
            (brake_gain * (-speed_error_mps - brake_deadband_mps)).min(1.0),
        )
    } else {
        (0.0, 0.0)
    }
}

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
}

impl DriverKind {
    /// All known drivers.
    pub const ALL: [DriverKind; 2] = [DriverKind::BeamNgAiProxy, DriverKind::Dave2Proxy];

    /// The driver's name.
    pub fn name(self) -> &'static str {
        match self {
            DriverKind::BeamNgAiProxy => "beamng-ai-proxy",
            DriverKind::Dave2Proxy => "dave2-proxy",
        }
    }

    /// The driver of that name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The oob tolerance the competition used with this driver (0.85 BeamNG.AI, 0.10 DAVE-2).
    pub fn default_oob_tolerance(self) -> f64 {
        match self {
            DriverKind::BeamNgAiProxy => 0.85,
            DriverKind::Dave2Proxy => 0.10,
        }
    }

    /// The speed limit this driver is run at by default, km/h (70; 25 for DAVE-2, the
    /// competition's 2024 setting).
    pub fn default_speed_limit_kmh(self) -> f64 {
        match self {
            DriverKind::BeamNgAiProxy => 70.0,
            DriverKind::Dave2Proxy => 25.0,
        }
    }
}

/// The weights of `dave2-proxy` trained by `wogan train-driver` and built into the binary.
const EMBEDDED_DAVE2_WEIGHTS: &[u8] = include_bytes!("../weights/dave2-proxy.bin");

/// The built-in `dave2-proxy` weights, decoded once.
pub fn embedded_dave2_weights() -> Arc<Dave2Weights> {
    static WEIGHTS: OnceLock<Arc<Dave2Weights>> = OnceLock::new();
    WEIGHTS
        .get_or_init(|| {
            // A test decodes the embedded blob, so this cannot fail in a released binary.
            Arc::new(
                Dave2Weights::from_bytes(EMBEDDED_DAVE2_WEIGHTS)
                    .expect("the embedded DAVE-2 weights decode"),
            )
        })
        .clone()
}

/// What is needed to build a driver for each drive: its kind and, for `dave2-proxy`, the
/// network's weights (the built-in ones unless others are given).
#[derive(Debug, Clone)]
pub struct DriverSetup {
    /// Which driver.
    pub kind: DriverKind,
    /// Weights of the DAVE-2 network; `None` for the built-in ones (unused by other drivers).
    pub dave2_weights: Option<Arc<Dave2Weights>>,
}

impl DriverSetup {
    /// The driver `kind` with the built-in weights.
    pub fn new(kind: DriverKind) -> Self {
        Self {
            kind,
            dave2_weights: None,
        }
    }

    /// The same driver with other DAVE-2 weights.
    pub fn with_dave2_weights(self, weights: Dave2Weights) -> Self {
        Self {
            dave2_weights: Some(Arc::new(weights)),
            ..self
        }
    }

    /// A new driver tuned by `config`.
    pub fn build(&self, config: &SimConfig) -> Box<dyn Driver + Send> {
        match self.kind {
            DriverKind::BeamNgAiProxy => Box::new(BeamNgAiProxy::new(config.beamng_ai)),
            DriverKind::Dave2Proxy => {
                let weights = self
                    .dave2_weights
                    .clone()
                    .unwrap_or_else(embedded_dave2_weights);
                Box::new(Dave2Driver::new(&weights, config.dave2))
            }
        }
    }
}

impl std::fmt::Display for DriverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for DriverKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s).ok_or_else(|| {
            let known: Vec<&str> = Self::ALL.iter().map(|k| k.name()).collect();
            format!("unknown driver {s:?} (known: {})", known.join(", "))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_dave2_weights_decode() {
        assert_eq!(
            Dave2Weights::from_bytes(EMBEDDED_DAVE2_WEIGHTS).map(|w| w.to_bytes().len()),
            Ok(EMBEDDED_DAVE2_WEIGHTS.len())
        );
    }

    #[test]
    fn names_round_trip() {
        for kind in DriverKind::ALL {
            assert_eq!(kind.name().parse::<DriverKind>(), Ok(kind));
            assert_eq!(
                serde_json::to_string(&kind).unwrap(),
                format!("\"{}\"", kind.name())
            );
            assert_eq!(
                DriverSetup::new(kind).build(&SimConfig::default()).name(),
                kind.name()
            );
        }
        assert!("dave3".parse::<DriverKind>().is_err());
    }
}
