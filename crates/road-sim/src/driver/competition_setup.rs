//! The SBST competition's two setups, by which every driver is judged unless told otherwise: the
//! tolerance a drive fails beyond, the speed limit, and the fitness a search maximises.

use super::DriverKind;
use crate::sim::{FitnessKind, SimConfig};

/// One of the SBST competition's two setups.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompetitionSetup {
    /// BeamNG.AI's: oob tolerance 0.85 at 70 km/h (`beamng-ai-proxy` and controller processes).
    BeamNgAi,
    /// DAVE-2's: oob tolerance 0.10, at its 2024 speed of 25 km/h (`dave2-proxy` and ONNX camera
    /// networks).
    Dave2,
}

impl CompetitionSetup {
    /// The setup `driver` is judged by.
    pub fn of(driver: DriverKind) -> Self {
        match driver {
            DriverKind::BeamNgAiProxy | DriverKind::Controller => Self::BeamNgAi,
            DriverKind::Dave2Proxy | DriverKind::Onnx => Self::Dave2,
        }
    }

    /// A drive fails when its BOLP exceeds this.
    pub fn oob_tolerance(self) -> f64 {
        match self {
            Self::BeamNgAi => 0.85,
            Self::Dave2 => 0.10,
        }
    }

    /// The speed limit, km/h.
    pub fn speed_limit_kmh(self) -> f64 {
        match self {
            Self::BeamNgAi => 70.0,
            Self::Dave2 => 25.0,
        }
    }

    /// What a search maximises: the paper's BOLP in both. (Against DAVE-2 the lane distance,
    /// which has a slope where BOLP is 0, found fewer failing roads against the built-in student:
    /// docs/experiments/2026-11-22-search-options.md.)
    pub fn fitness(self) -> FitnessKind {
        FitnessKind::Bolp
    }

    /// The default simulation settings with this setup's tolerance and speed limit.
    pub fn sim_config(self) -> SimConfig {
        SimConfig {
            oob_tolerance: self.oob_tolerance(),
            speed_limit_kmh: self.speed_limit_kmh(),
            ..SimConfig::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_setups_are_the_competitions() {
        let beamng = CompetitionSetup::of(DriverKind::BeamNgAiProxy);
        assert_eq!(beamng, CompetitionSetup::of(DriverKind::Controller));
        assert_eq!(
            (beamng.oob_tolerance(), beamng.speed_limit_kmh()),
            (0.85, 70.0)
        );
        assert_eq!(beamng.fitness(), FitnessKind::Bolp);
        let dave2 = CompetitionSetup::of(DriverKind::Dave2Proxy);
        assert_eq!(dave2, CompetitionSetup::of(DriverKind::Onnx));
        assert_eq!(
            (dave2.oob_tolerance(), dave2.speed_limit_kmh()),
            (0.10, 25.0)
        );
        assert_eq!(dave2.fitness(), FitnessKind::Bolp);
        assert_eq!(beamng.sim_config(), SimConfig::default());
    }
}
