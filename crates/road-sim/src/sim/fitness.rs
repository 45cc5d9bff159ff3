//! Fitness: how close a drive came to failing, in `[0, 1]`, higher is worse for the car. A search
//! maximises one of these figures of the drive.
//!
//! A fitness's scale is not neutral in WOGAN: the acceptance target starts at 1 and shrinks by a
//! decay per candidate, so the analyzer ranks about `ln(p) / ln(decay)` candidates when its best
//! prediction is `p`. At DAVE-2's tolerance BOLP fails at 0.1 and the distance at 0.44, so
//! [`FitnessKind::failure_level`] says where each fitness fails and `wogan run` gives the distance
//! the decay that reaches its failure level after as many candidates as the paper's 0.95 takes to
//! reach BOLP's. Rescaling the distance itself instead was measured and did not help, because it
//! also empties WOGAN's fitness bins (`docs/experiments/` has the figures).

use super::bolp::lane_distance_at_bolp;
use super::config::SimConfig;
use super::outcome::{Outcome, SimResult};
use serde::{Deserialize, Serialize};

/// Which figure of a drive a search maximises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FitnessKind {
    /// The paper's fitness: the drive's maximum BOLP.
    Bolp,
    /// `min(1, max_bolp / oob_tolerance)`: 1 exactly when the drive fails, so that a small
    /// tolerance (DAVE-2's 0.10) still spreads BOLP over `[0, 1]`.
    BolpScaled,
    /// The simulator's `fitness_distance`, informative even when BOLP stays 0.
    Distance,
}

impl FitnessKind {
    /// All fitnesses.
    pub const ALL: [FitnessKind; 3] = [Self::Bolp, Self::BolpScaled, Self::Distance];

    /// The name, as `--fitness` and the run header spell it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Bolp => "bolp",
            Self::BolpScaled => "bolp-scaled",
            Self::Distance => "distance",
        }
    }

    /// The fitness of that name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The fitness of a drive judged by `sim`, in `[0, 1]`.
    pub fn of(self, result: &SimResult, sim: &SimConfig) -> f64 {
        match self {
            Self::Bolp => result.max_bolp.clamp(0.0, 1.0),
            Self::BolpScaled if sim.oob_tolerance > 0.0 => {
                (result.max_bolp / sim.oob_tolerance).min(1.0)
            }
            Self::BolpScaled => f64::from(u8::from(result.outcome == Outcome::Fail)),
            Self::Distance => result.fitness_distance,
        }
    }

    /// The fitness of a drive that just fails (BOLP at `sim.oob_tolerance`, the car parallel to
    /// the lane's edge).
    pub fn failure_level(self, sim: &SimConfig) -> f64 {
        match self {
            Self::Bolp => sim.oob_tolerance,
            Self::BolpScaled => 1.0,
            Self::Distance => fitness_from_distance(lane_distance_at_bolp(
                sim.oob_tolerance,
                sim.vehicle.width_m,
            )),
        }
    }
}

/// Lane distance (metres, signed, positive inside) at which `fitness_distance` reaches 1.
pub const FITNESS_FAILURE_DISTANCE_M: f64 = -0.85;
/// Lane distance of a centred car.
pub const CENTRED_DISTANCE_M: f64 = 2.0;

/// The lane-distance fitness of a minimum lane distance: linear from 0 (centred, 2 m) to 1
/// (0.85 m outside the lane, where a 1.9 m wide car's BOLP reaches 0.95), clamped. The WOGAN
/// authors scaled their BeamNG distance the same way: to reach 1 where BOLP reaches 0.95.
pub fn fitness_from_distance(min_lane_distance_m: f64) -> f64 {
    if min_lane_distance_m.is_nan() {
        return 1.0;
    }
    ((CENTRED_DISTANCE_M - min_lane_distance_m) / (CENTRED_DISTANCE_M - FITNESS_FAILURE_DISTANCE_M))
        .clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitness_scale() {
        assert_eq!(fitness_from_distance(2.0), 0.0);
        assert_eq!(fitness_from_distance(2.5), 0.0);
        assert!((fitness_from_distance(-0.85) - 1.0).abs() < 1e-12);
        assert!((fitness_from_distance(0.575) - 0.5).abs() < 1e-12);
        assert_eq!(fitness_from_distance(-5.0), 1.0);
    }

    #[test]
    fn names_round_trip() {
        for kind in FitnessKind::ALL {
            assert_eq!(FitnessKind::from_name(kind.name()), Some(kind));
            assert_eq!(
                serde_json::to_string(&kind).unwrap(),
                format!("\"{}\"", kind.name())
            );
        }
    }

    #[test]
    fn each_fitness_fails_where_bolp_reaches_the_tolerance() {
        let sim = SimConfig {
            oob_tolerance: 0.1,
            ..SimConfig::default()
        };
        assert_eq!(FitnessKind::Bolp.failure_level(&sim), 0.1);
        assert_eq!(FitnessKind::BolpScaled.failure_level(&sim), 1.0);
        // A 1.9 m car's centre 0.76 m inside the edge: (2 - 0.76) / 2.85.
        let distance = FitnessKind::Distance.failure_level(&sim);
        assert!((distance - 1.24 / 2.85).abs() < 1e-12, "{distance}");
        // At the paper's own threshold the distance was scaled to fail at its top.
        let paper = SimConfig {
            oob_tolerance: 0.95,
            ..sim
        };
        assert_eq!(FitnessKind::Distance.failure_level(&paper), 1.0);
    }
}
