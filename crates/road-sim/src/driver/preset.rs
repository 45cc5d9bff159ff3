//! What each driver is judged by unless told otherwise: the competition's setting for it. Every
//! driver names its own [`DriverPreset`]; the built-in drivers' are `beamng_ai::PRESET` and
//! `dave2::PRESET`.

use crate::sim::{FitnessKind, SimConfig};

/// What a driver is judged by unless told otherwise: the competition's setting for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriverPreset {
    /// A drive fails when its BOLP exceeds this.
    pub oob_tolerance: f64,
    /// The speed limit, km/h.
    pub speed_limit_kmh: f64,
    /// What a search maximises.
    pub fitness: FitnessKind,
}

impl DriverPreset {
    /// The default simulation settings with this preset's tolerance and speed limit.
    pub fn sim_config(&self) -> SimConfig {
        SimConfig {
            oob_tolerance: self.oob_tolerance,
            speed_limit_kmh: self.speed_limit_kmh,
            ..SimConfig::default()
        }
    }
}
