//! Drivers: what controls the car. A driver sees what the car knows (its pose, speed and
//! steering, the road, the time) and answers with steering, throttle and brake, at its own rate.

use crate::beamng_ai::{BeamNgAiParams, BeamNgAiProxy};
use crate::road::Road;
use crate::vehicle::{CarState, Command, VehicleParams};
use serde::{Deserialize, Serialize};

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

/// The drivers known by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum DriverKind {
    /// A path-tracking lane keeper in the spirit of BeamNG.AI (`beamng-ai-proxy`).
    #[default]
    #[serde(rename = "beamng-ai-proxy")]
    BeamNgAiProxy,
}

impl DriverKind {
    /// All known drivers.
    pub const ALL: [DriverKind; 1] = [DriverKind::BeamNgAiProxy];

    /// The driver's name.
    pub fn name(self) -> &'static str {
        match self {
            DriverKind::BeamNgAiProxy => "beamng-ai-proxy",
        }
    }

    /// The driver of that name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The default oob tolerance the competition used with this driver.
    pub fn default_oob_tolerance(self) -> f64 {
        match self {
            DriverKind::BeamNgAiProxy => 0.85,
        }
    }

    /// A new driver of this kind with its default parameters.
    pub fn build(self) -> Box<dyn Driver + Send> {
        match self {
            DriverKind::BeamNgAiProxy => Box::new(BeamNgAiProxy::new(BeamNgAiParams::default())),
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
    fn names_round_trip() {
        for kind in DriverKind::ALL {
            assert_eq!(kind.name().parse::<DriverKind>(), Ok(kind));
            assert_eq!(
                serde_json::to_string(&kind).unwrap(),
                format!("\"{}\"", kind.name())
            );
            assert_eq!(kind.build().name(), kind.name());
        }
        assert!("dave3".parse::<DriverKind>().is_err());
    }
}
