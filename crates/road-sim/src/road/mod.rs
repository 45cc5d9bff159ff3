//! Roads: points on the map, curvature values that make them, the competition's spline through
//! them, the road's lanes, polyline and circle geometry, the competition's road features, the
//! heading profile the search compares roads by, the description the paper's diversity measure
//! compares them by, and the input formats roads are read in.

pub mod circle;
pub mod curvature;
pub mod diversity_profile;
pub mod features;
mod geometry;
pub mod heading_profile;
pub mod input;
pub mod polyline;
mod road_shape;
pub mod spline;

/// A point on the map, metres: `[x, y]`, x east, y north.
pub type Point = [f64; 2];

pub use curvature::{CurvatureRoad, RoadPlacement};
pub use features::RoadFeatures;
pub use geometry::{Road, RoadError, LANE_WIDTH_M, ROAD_WIDTH_M};
pub use input::{InputError, RoadInput, RoadReader};
pub use road_shape::RoadShape;
