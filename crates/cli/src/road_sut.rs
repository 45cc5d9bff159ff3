//! The self-driving-car problem as a `wogan-core` system under test: a test vector in `[-1, 1]^d`
//! is `d` curvature values scaled by the paper's bound, validity is the competition's validator,
//! and executing a test drives the chosen driver along the road. This adapter is the one place
//! that knows both the search and the roads.
//!
//! A fitness's scale is not neutral in WOGAN: the acceptance target starts at 1 and shrinks by 0.95
//! per candidate, so the analyzer ranks about `ln(p) / ln(0.95)` candidates when its best
//! prediction is `p`. At DAVE-2's tolerance the BOLP fitness fails at 0.1 (about 45 candidates),
//! the distance at 0.44 (about 16). [`FitnessKind::failure_level`] says where each fitness fails,
//! so that `wogan run` can give the distance the decay that reaches its failure level after as
//! many candidates as 0.95 takes to reach BOLP's (0.9816 at 0.10). Rescaling the distance itself
//! instead was measured and did not help, because it also empties WOGAN's fitness bins: with 300
//! tests on the built-in student, seeds 1–10, median (mean) failures were 26 (40) with the distance
//! at 0.95, 24.5 (31) when a failed drive scores 1, 21 (47) with `0.1·e^(−margin/0.4 m)`, 15.5
//! (48) with the distance rescaled linearly to reach 0.1 at the failure, against 17 (37) with
//! `bolp`; rescaled to reach 1 there (2–8 candidates ranked) it found 10 on seeds 1–5.

use road_sim::bolp::lane_distance_at_bolp;
use road_sim::curvature::MAX_CURVATURE_PER_M;
use road_sim::outcome::{fitness_from_distance, Outcome};
use road_sim::{
    simulate_setup, CurvatureRoad, DriverSetup, Point, Road, SimConfig, SimResult, Validator,
};
use serde::{Deserialize, Serialize};
use wogan_core::{Execution, Sut};

/// Which simulator figure the search maximises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
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

/// Roads from curvature vectors, judged by one driver.
pub struct RoadSut {
    /// How curvature values become road points.
    pub roads: CurvatureRoad,
    /// Number of curvature values per test.
    pub curvature_points: usize,
    /// The competition's rules.
    pub validator: Validator,
    /// The driver under test.
    pub driver: DriverSetup,
    /// How drives are simulated and judged.
    pub sim: SimConfig,
    /// What the search maximises.
    pub fitness: FitnessKind,
}

/// What executing one test produced.
#[derive(Debug, Clone, Serialize)]
pub struct RoadExecution {
    /// Curvature values, 1/m.
    pub curvature: Vec<f64>,
    /// The road points they make.
    pub road_points: Vec<Point>,
    /// The interpolated centre line (not written: used for the diversity measure).
    #[serde(skip)]
    pub interpolated: Vec<Point>,
    /// The simulator's report.
    #[serde(flatten)]
    pub result: SimResult,
}

impl RoadSut {
    /// Curvature values (1/m) of a normalised test vector.
    pub fn curvature(&self, test: &[f32]) -> Vec<f64> {
        test.iter()
            .map(|&v| f64::from(v) * MAX_CURVATURE_PER_M)
            .collect()
    }

    /// The fitness of a drive, in `[0, 1]`.
    pub fn fitness_of(&self, result: &SimResult) -> f64 {
        match self.fitness {
            FitnessKind::Bolp => result.max_bolp.clamp(0.0, 1.0),
            FitnessKind::BolpScaled if self.sim.oob_tolerance > 0.0 => {
                (result.max_bolp / self.sim.oob_tolerance).min(1.0)
            }
            FitnessKind::BolpScaled => f64::from(u8::from(result.outcome == Outcome::Fail)),
            FitnessKind::Distance => result.fitness_distance,
        }
    }
}

impl Sut for RoadSut {
    type Output = RoadExecution;

    fn dim(&self) -> usize {
        self.curvature_points
    }

    fn is_valid(&self, test: &[f32]) -> bool {
        self.validator
            .validate(&self.roads.points(&self.curvature(test)))
            .is_valid()
    }

    fn execute(&self, test: &[f32]) -> Execution<RoadExecution> {
        let curvature = self.curvature(test);
        let road_points = self.roads.points(&curvature);
        // The search only executes valid tests, whose points always interpolate.
        let road = Road::new(&road_points).expect("a valid road interpolates");
        let result = simulate_setup(&road, &self.driver, &self.sim, false);
        Execution {
            fitness: self.fitness_of(&result),
            output: RoadExecution {
                curvature,
                road_points,
                interpolated: road.interpolated,
                result,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
