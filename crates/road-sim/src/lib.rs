//! The self-driving-car system under test: roads, the SBST competition's validator, and the
//! simulated car with its drivers.
//!
//! Data flows one way: road points (or curvature values, see [`curvature`]) are interpolated into
//! a centre line ([`spline`]), which gives the road's edges, quads and lanes ([`road`]); the
//! [`validator`] applies the competition's rules to them; [`bolp`] and [`features`] measure a car
//! against the lane and the road's shape.

pub mod bolp;
pub mod circle;
pub mod curvature;
pub mod features;
pub mod input;
pub mod polyline;
pub mod road;
pub mod spline;
pub mod validator;

/// A point on the map, metres: `[x, y]`, x east, y north.
pub type Point = [f64; 2];

pub use curvature::CurvatureRoad;
pub use features::RoadFeatures;
pub use road::Road;
pub use validator::{Reason, Validator, Verdict};
