//! The self-driving-car system under test: roads, the SBST competition's validator, and the
//! simulated car with its drivers.
//!
//! Data flows one way: road points (or curvature values, see [`curvature`]) are interpolated into
//! a centre line ([`spline`]), which gives the road's edges, quads and lanes ([`road`]); the
//! [`validator`] applies the competition's rules to them; [`bolp`] and [`features`] measure a car
//! against the lane and the road's shape.

pub mod beamng_ai;
pub mod behaviour_cloning;
pub mod bolp;
pub mod circle;
pub mod curvature;
pub mod driver;
pub mod features;
pub mod heading_profile;
pub mod input;
pub mod oracle;
pub mod outcome;
pub mod polyline;
pub mod road;
pub mod scenario;
mod settings_check;
pub mod simulation;
pub mod spline;
pub mod validator;
pub mod vehicle;

/// A point on the map, metres: `[x, y]`, x east, y north.
pub type Point = [f64; 2];

pub use curvature::CurvatureRoad;
pub use driver::{Driver, DriverKind, DriverSetup, Observation};
pub use features::RoadFeatures;
pub use outcome::{Outcome, Sample, SimResult};
pub use road::Road;
pub use simulation::{simulate, simulate_kind, simulate_setup, SimConfig};
pub use validator::{Reason, Validator, Verdict};
pub use vehicle::{CarState, Command, Vehicle, VehicleParams};
pub mod camera;
pub mod dave2;
pub mod dave2_driver;
pub mod dave2_inference;
