//! The self-driving-car problem as a `wogan-core` system under test: a test vector in `[-1, 1]^d`
//! is `d` curvature values scaled by the paper's bound, validity is the competition's validator
//! (and, when asked, a least turn from the road's first heading), and executing a test drives the
//! chosen driver along the road and scores the drive with the chosen fitness. This adapter is the
//! one place that knows both the search and the roads.

use crate::files::records::RoadExecution;
use crate::sut::failure_streak::FailureStreak;
use road_sim::distinct::ExitProfile;
use road_sim::road::curvature::MAX_CURVATURE_PER_M;
use road_sim::road::heading_profile::largest_turn_rad;
use road_sim::road::RoadShape;
use road_sim::{
    simulate, CurvatureRoad, DriverConfig, FitnessKind, Road, SimConfig, StopReason, Validator,
};
use std::sync::atomic::AtomicBool;
use wogan_core::{Execution, Sut};

/// Roads from curvature vectors, judged by one driver.
#[derive(Clone)]
pub struct RoadSut<'a> {
    /// How curvature values become road points.
    pub roads: CurvatureRoad,
    /// Number of curvature values per test.
    pub curvature_points: usize,
    /// How the niches and the shape novelty rule compare roads.
    pub shape: RoadShape,
    /// Roads that never turn this far from their first heading are not tested (radians; 0:
    /// every valid road is).
    pub min_turn_rad: f64,
    /// The competition's rules.
    pub validator: Validator,
    /// The driver under test.
    pub driver: DriverConfig,
    /// How drives are simulated and judged.
    pub sim: SimConfig,
    /// What the search maximises.
    pub fitness: FitnessKind,
    /// Set by Ctrl-C or SIGTERM: a drive in progress is cut short and not reported.
    pub stop: &'a AtomicBool,
    /// Drives a controller process or camera network failed in a row (none counted when
    /// `None`).
    pub streak: Option<&'a FailureStreak>,
}

impl RoadSut<'_> {
    /// Curvature values (1/m) of a normalised test vector.
    pub fn curvature(&self, test: &[f32]) -> Vec<f64> {
        test.iter()
            .map(|&v| f64::from(v) * MAX_CURVATURE_PER_M)
            .collect()
    }
}

impl Sut for RoadSut<'_> {
    type Output = RoadExecution;

    fn dim(&self) -> usize {
        self.curvature_points
    }

    /// Valid by the competition's rules and, when a least turn is asked for, turning that far.
    fn is_valid(&self, test: &[f32]) -> bool {
        let verdict = self
            .validator
            .validate(&self.roads.points(&self.curvature(test)));
        // A valid verdict carries the road the validator interpolated: no second interpolation.
        match verdict.road {
            Some(road) if verdict.reason.is_none() => {
                self.min_turn_rad <= 0.0
                    || largest_turn_rad(&road.interpolated) >= self.min_turn_rad
            }
            _ => false,
        }
    }

    /// The road's profile by the [`RoadShape`] the SUT was given (radians).
    fn shape(&self, test: &[f32]) -> Option<Vec<f32>> {
        let road = Road::new(&self.roads.points(&self.curvature(test))).ok()?;
        Some(
            self.shape
                .profile(&road.interpolated)
                .into_iter()
                .map(|h| h as f32)
                .collect(),
        )
    }

    /// The exit profile around where the car left its lane (radians; the distinct failures'
    /// measure, so that a repeat is what `wogan report` would not count as a new failure).
    fn failure_profile(&self, output: &RoadExecution) -> Option<Vec<f32>> {
        let exit = output.result.oob?;
        let profile = ExitProfile::of(&output.interpolated, [exit.x, exit.y])?;
        Some(profile.headings().iter().map(|&h| h as f32).collect())
    }

    fn execute(&self, test: &[f32]) -> Option<Execution<RoadExecution>> {
        let curvature = self.curvature(test);
        let road_points = self.roads.points(&curvature);
        // The search only executes valid tests, whose points always interpolate.
        let road = Road::new(&road_points).expect("a valid road interpolates");
        let mut driver = self.driver.build();
        let result = simulate(&road, driver.as_mut(), &self.sim, false, Some(self.stop));
        if result.reason == Some(StopReason::Interrupted) {
            return None;
        }
        if let Some(streak) = self.streak {
            match (&result.reason, &result.error) {
                (Some(StopReason::DriverFailed), Some(error)) => {
                    let what = match self.driver.kind() {
                        road_sim::DriverKind::Onnx => "the camera network",
                        _ => "the controller",
                    };
                    streak.failed(what, error, self.stop)
                }
                _ => streak.passed(),
            }
        }
        Some(Execution {
            fitness: self.fitness.of(&result, &self.sim),
            // The competition charges a test's simulated time to its execution budget.
            execution_time_s: result.sim_time_s,
            output: RoadExecution {
                curvature,
                road_points,
                interpolated: road.interpolated,
                result,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_least_turn_rejects_valid_roads_that_turn_less() {
        let stop = AtomicBool::new(false);
        let sut = |min_turn_rad: f64| RoadSut {
            roads: CurvatureRoad {
                step_m: 10.0,
                placement: road_sim::RoadPlacement::Fitted,
                ..CurvatureRoad::default()
            },
            curvature_points: 16,
            shape: RoadShape::Headings,
            min_turn_rad,
            validator: Validator::new(200.0),
            driver: DriverConfig::default_for(road_sim::DriverKind::BeamNgAiProxy),
            sim: SimConfig::default(),
            fitness: FitnessKind::Bolp,
            stop: &stop,
            streak: None,
        };
        // Straight, and a bend of about 2.2 rad (0.028 1/m over 80 m) then straight.
        let straight = [0.0_f32; 16];
        let mut bend = [0.0_f32; 16];
        bend[..8].fill(0.4);
        let anything = sut(0.0);
        assert!(anything.is_valid(&straight) && anything.is_valid(&bend));
        let points = anything.roads.points(&anything.curvature(&bend));
        let turn = largest_turn_rad(&Road::new(&points).unwrap().interpolated);
        assert!((2.0..2.5).contains(&turn), "{turn}");
        assert!(!sut(0.5).is_valid(&straight));
        assert!(sut(turn - 0.05).is_valid(&bend));
        assert!(!sut(turn + 0.05).is_valid(&bend));
    }
}
