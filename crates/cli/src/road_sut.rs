//! The self-driving-car problem as a `wogan-core` system under test: a test vector in `[-1, 1]^d`
//! is `d` curvature values scaled by the paper's bound, validity is the competition's validator,
//! and executing a test drives the chosen driver along the road. This adapter is the one place
//! that knows both the search and the roads.
//!
//! A fitness's scale is not neutral in WOGAN: the acceptance target starts at 1 and shrinks by 0.95
//! per candidate, so the analyzer ranks about `ln(p) / ln(0.95)` candidates when its best
//! prediction is `p`. On dave2-proxy the BOLP fitness (failures at 0.1) ranks 57–87 candidates per
//! test, the distance (failures at 0.44) about 20 (`ranked_candidates` in the test records: means
//! of 75 and 21 on seed 3). Rescaling the distance changes that but not the
//! result: with 300 tests on the built-in student, WOGAN found a median (mean) of 26 (40) failures
//! over seeds 1–10 with `distance`, 24.5 (31) when a failed drive scores 1, 21 (47) with
//! `0.1·e^(−margin/0.4 m)` (0.1 where the drive fails), 15.5 (48) with the distance rescaled
//! linearly to reach 0.1 there, against 17 (37) with `bolp`; rescaled to reach 1 there (2–8
//! candidates ranked) it found 10 on seeds 1–5. Between runs of one setting the spread is far wider
//! than these differences.

use road_sim::curvature::MAX_CURVATURE_PER_M;
use road_sim::outcome::Outcome;
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
