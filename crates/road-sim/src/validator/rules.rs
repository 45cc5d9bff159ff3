//! The rules and their order: [`Validator::validate`] interpolates the road as the competition
//! does and applies each rule in turn.

use crate::road::{circle, spline};
use crate::road::{Point, Road, RoadError, ROAD_WIDTH_M};

use super::self_intersection::is_self_intersecting;
use super::verdict::{Reason, Verdict};

/// Most road points a test may have.
pub const MAX_ROAD_POINTS: usize = 500;
/// Shortest allowed centre line, metres (the road must be strictly longer).
pub const MIN_LENGTH_M: f64 = 20.0;
/// The sharpness rule's smallest allowed turning radius, in feet (the competition works in feet).
pub const MIN_RADIUS_FT: f64 = 47.0;
/// Feet per metre, as the competition converts.
pub const FEET_PER_METRE: f64 = 3.280839895;

/// Largest map side the tool accepts, metres (10x the competition's 200 m).
pub const MAX_MAP_SIZE_M: f64 = 2000.0;
/// Longest road the validator interpolates, metres: bounds the work of one road (one point per
/// metre) whatever its points or the map.
pub const MAX_ROAD_LENGTH_M: f64 = spline::MAX_LENGTH_M;

/// Checks roads against the competition's rules on a square map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Validator {
    /// Side of the square map, metres.
    pub map_size_m: f64,
}

impl Default for Validator {
    fn default() -> Self {
        Self { map_size_m: 200.0 }
    }
}

impl Validator {
    /// A validator for a `map_size_m` × `map_size_m` map (at most [`MAX_MAP_SIZE_M`]; callers check
    /// the range where the size is typed).
    pub fn new(map_size_m: f64) -> Self {
        Self { map_size_m }
    }

    /// The verdict for a road given by its points.
    pub fn validate(&self, road_points: &[Point]) -> Verdict {
        let invalid = |reason, road| Verdict {
            reason: Some(reason),
            road,
        };
        if road_points.len() < 2 {
            return invalid(Reason::NotEnoughPoints, None);
        }
        if road_points.len() > MAX_ROAD_POINTS {
            return invalid(Reason::TooManyPoints, None);
        }
        if road_points.iter().flatten().any(|v| !v.is_finite())
            || road_points.windows(2).any(|w| w[0] == w[1])
        {
            return invalid(Reason::Malformed, None);
        }
        // A centre-line sample more than half the road's width outside the map puts both edge
        // points made from it outside, so the interpolated road would fail the map rule: say so
        // from the samples at the road points alone, without interpolating every metre (most
        // random roads leave the map, and a search checks millions).
        let half_width_m = ROAD_WIDTH_M / 2.0;
        if spline::samples_at_points(road_points).is_ok_and(|samples| {
            samples
                .iter()
                .flatten()
                .any(|&v| v < -half_width_m || v > self.map_size_m + half_width_m)
        }) {
            return invalid(Reason::OutsideMap, None);
        }
        let length_m = spline::polyline_length(road_points);
        if length_m.is_nan() || length_m > self.longest_possible_road_m().min(MAX_ROAD_LENGTH_M) {
            // Too long to be valid, and too long to interpolate every metre: the spline is at
            // least as long as the polyline through its points.
            let off_map = road_points
                .iter()
                .flatten()
                .any(|&v| v <= 0.0 || v >= self.map_size_m);
            let reason = if off_map {
                Reason::OutsideMap
            } else if length_m > self.longest_possible_road_m() {
                Reason::SelfIntersecting
            } else {
                Reason::TooLong
            };
            return invalid(reason, None);
        }
        let road = match Road::new(road_points) {
            Ok(road) => road,
            Err(RoadError::Spline(_) | RoadError::DegenerateSegment(..)) => {
                return invalid(Reason::Malformed, None)
            }
        };
        let reason = self.judge(&road);
        Verdict {
            reason,
            road: Some(road),
        }
    }

    /// An upper bound on the centre-line length of a valid road: its polygon, a band of
    /// [`ROAD_WIDTH_M`] without overlaps, would otherwise cover more than the map (twice over, for
    /// slack), metres.
    pub fn longest_possible_road_m(&self) -> f64 {
        2.0 * self.map_size_m * self.map_size_m / ROAD_WIDTH_M
    }

    /// The first rule an interpolated road breaks, if any.
    pub fn judge(&self, road: &Road) -> Option<Reason> {
        let quads = road.quads();
        if !self.is_inside_map(&quads) {
            Some(Reason::OutsideMap)
        } else if is_self_intersecting(&quads) {
            Some(Reason::SelfIntersecting)
        } else if road.length_m() <= MIN_LENGTH_M {
            Some(Reason::TooShort)
        } else if is_too_sharp(&road.interpolated) {
            Some(Reason::TooSharp)
        } else {
            None
        }
    }

    /// Whether every corner of the road polygon lies strictly inside the map.
    fn is_inside_map(&self, quads: &[[Point; 4]]) -> bool {
        let inside = |v: f64| v > 0.0 && v < self.map_size_m;
        quads.iter().flatten().all(|p| inside(p[0]) && inside(p[1]))
    }
}

/// The competition's sharpness rule: the smallest radius, in feet, is positive and below 47.
/// An all-straight road (infinite radius) counts as not sharp.
pub fn is_too_sharp(interpolated: &[Point]) -> bool {
    let radius = circle::min_radius(interpolated);
    let radius_ft = if radius.is_finite() {
        radius * FEET_PER_METRE
    } else {
        0.0
    };
    radius_ft > 0.0 && radius_ft < MIN_RADIUS_FT
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reason(points: &[Point]) -> Option<Reason> {
        Validator::default().validate(points).reason
    }

    #[test]
    fn a_road_too_long_to_interpolate_is_refused_before_interpolation() {
        // On a huge map these points are inside and the area bound is infinite: only the length
        // bound keeps the spline from asking for 1e297 samples.
        let huge = Validator::new(1e308);
        let verdict = huge.validate(&[[1e300, 1e300], [1e300, 1.0000000000001e300]]);
        assert_eq!(verdict.reason, Some(Reason::TooLong));
        let large = Validator::new(MAX_MAP_SIZE_M);
        let zigzag: Vec<Point> = (0..30)
            .map(|i| [10.0 + 1900.0 * f64::from(i % 2), 10.0 + 60.0 * f64::from(i)])
            .collect();
        assert_eq!(large.validate(&zigzag).reason, Some(Reason::TooLong));
    }

    #[test]
    fn rules_in_order() {
        assert_eq!(reason(&[]), Some(Reason::NotEnoughPoints));
        assert_eq!(reason(&[[50.0, 50.0]]), Some(Reason::NotEnoughPoints));
        assert_eq!(
            reason(&vec![[50.0, 50.0]; 501]),
            Some(Reason::TooManyPoints)
        );
        assert_eq!(
            reason(&[[50.0, 50.0], [f64::NAN, 60.0]]),
            Some(Reason::Malformed)
        );
        assert_eq!(
            reason(&[[50.0, 50.0], [50.0, 50.0], [60.0, 70.0]]),
            Some(Reason::Malformed)
        );
        assert_eq!(
            reason(&[[1.0, 10.0], [1.0, 50.0]]),
            Some(Reason::OutsideMap)
        );
        assert_eq!(
            reason(&[[100.0, 100.0], [100.0, 110.0]]),
            Some(Reason::TooShort)
        );
        assert_eq!(reason(&[[50.0, 50.0], [10.0, 10.0]]), None);
    }

    #[test]
    fn a_road_entirely_beyond_any_side_is_outside() {
        for points in [
            [[250.0, 50.0], [300.0, 50.0]],
            [[50.0, 250.0], [50.0, 300.0]],
            [[-50.0, 50.0], [-90.0, 50.0]],
            [[50.0, -50.0], [50.0, -90.0]],
        ] {
            assert_eq!(reason(&points), Some(Reason::OutsideMap), "{points:?}");
        }
    }

    #[test]
    fn a_crossing_road_intersects_itself() {
        let points = [[10.0, 10.0], [20.0, 20.0], [10.0, 20.0], [20.0, 10.0]];
        assert_eq!(reason(&points), Some(Reason::SelfIntersecting));
    }
}
