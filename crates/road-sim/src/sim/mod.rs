//! One drive and its verdict: the car (rapier3d), the episode loop, the lane monitor (BOLP and
//! lane distances), the outcome with its stop reason, and the fitness a search maximises.

pub mod bolp;
mod config;
mod episode;
mod fitness;
pub mod lane_monitor;
mod outcome;
pub mod vehicle;

pub use config::{SimConfig, MAX_PHYSICS_HZ, MAX_SIM_TIME_S};
pub use episode::{simulate, start_pose, Driver, Observation, END_SEGMENTS};
pub use fitness::{
    fitness_from_distance, FitnessKind, CENTRED_DISTANCE_M, FITNESS_FAILURE_DISTANCE_M,
};
pub use lane_monitor::{LaneMeasure, LaneMonitor};
pub use outcome::{LaneExit, LaneSide, Outcome, Sample, SimResult, StopReason};
pub use vehicle::{CarState, Command, Vehicle, VehicleParams};
