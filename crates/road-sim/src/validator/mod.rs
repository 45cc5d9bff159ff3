//! The SBST competition's road validity rules, in the competition's order.
//!
//! 1. at least 2 road points; 2. at most 500; 3. the road polygon strictly inside the map;
//! 4. not self-intersecting; 5. centre line longer than 20 m; 6. not too sharp.
//!
//! Input no rule can judge (non-finite or repeated points) is `malformed`.
//!

mod rules;
mod self_intersection;
mod verdict;

#[cfg(test)]
mod properties;

pub use rules::{
    is_too_sharp, Validator, FEET_PER_METRE, MAX_MAP_SIZE_M, MAX_ROAD_LENGTH_M, MAX_ROAD_POINTS,
    MIN_LENGTH_M, MIN_RADIUS_FT,
};
pub use self_intersection::is_self_intersecting;
pub use verdict::{Reason, Verdict};
