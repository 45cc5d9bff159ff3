//! The road problem with an external executor as the simulator: validity and roads are wogan's
//! (the competition's validator), driving is the executor's ([`ExecutorDriver`]). The protocol's
//! road `id` is the order a road was sent in (with `--jobs N` not always its test's id).

use super::executor_driver::ExecutorDriver;
use crate::files::records::RoadExecution;
use crate::sut::road_sut::RoadSut;
use road_sim::{FitnessKind, Road, SimConfig};
use std::sync::atomic::{AtomicUsize, Ordering};
use wogan_core::{Execution, Sut};

/// Roads from test vectors, driven by an executor.
pub struct ExecutorSut<'a> {
    /// Validity and the vector-to-road mapping (its driver is not used).
    pub roads: RoadSut<'a>,
    /// How roads are judged (tolerance, speed limit), as told to the executor.
    pub sim: SimConfig,
    /// What the search maximises (the lane distance only from executors that answer with it).
    pub fitness: FitnessKind,
    /// The executors.
    pub driver: &'a ExecutorDriver<'a>,
    roads_sent: AtomicUsize,
}

impl<'a> ExecutorSut<'a> {
    /// A SUT whose roads `driver` drives.
    pub fn new(
        roads: RoadSut<'a>,
        sim: SimConfig,
        fitness: FitnessKind,
        driver: &'a ExecutorDriver<'a>,
    ) -> Self {
        Self {
            roads,
            sim,
            fitness,
            driver,
            roads_sent: AtomicUsize::new(0),
        }
    }
}

impl Sut for ExecutorSut<'_> {
    type Output = RoadExecution;

    fn dim(&self) -> usize {
        self.roads.dim()
    }

    fn is_valid(&self, test: &[f32]) -> bool {
        self.roads.is_valid(test)
    }

    fn execute(&self, test: &[f32]) -> Option<Execution<RoadExecution>> {
        let curvature = self.roads.curvature(test);
        let road_points = self.roads.roads.points(&curvature);
        // The search executes valid tests only, whose points always interpolate.
        let road = Road::new(&road_points).ok()?;
        let id = self.roads_sent.fetch_add(1, Ordering::SeqCst) as u64 + 1;
        let result = self.driver.drive(id, &road_points, &road)?;
        Some(Execution {
            fitness: self.fitness.of(&result, &self.sim),
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
