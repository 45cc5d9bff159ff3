//! The SBST competition's road validity rules, in the competition's order.
//!
//! 1. at least 2 road points; 2. at most 500; 3. the road polygon strictly inside the map;
//! 4. not self-intersecting; 5. centre line longer than 20 m; 6. not too sharp.
//!
//! Input no rule can judge (non-finite or repeated points) is `malformed`.
//!
//! The self-intersection rule looks at the road polygon's quads (one per centre-line segment):
//! each must be simple, adjacent quads may meet only along their shared side, and other quads
//! must not touch at all. A sort-and-sweep over the quads' boxes finds the pairs that can touch,
//! and a separating-line test on the shared sides ("rungs") settles almost all of those, so the
//! cost grows like `n log n` in the number of quads instead of the reference's pairwise `n²`.
//! (For ~75 quads the sweep is twice as fast as building parry's BVH; parry's own segment
//! intersection treats nearly parallel segments as collinear, so sides are tested with exact
//! orientation signs here, and parry answers the point-in-polygon questions.)

use crate::road::{circle, polyline, spline};
use crate::road::{Point, Road, RoadError, ROAD_WIDTH_M};
use parry2d::math::Vector2;
use parry2d::utils::point_in_poly2d;
use serde::{Deserialize, Serialize};

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

/// Why a road is invalid: a stable code for machines plus the competition's message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reason {
    /// Fewer than two road points.
    NotEnoughPoints,
    /// More than [`MAX_ROAD_POINTS`] road points.
    TooManyPoints,
    /// Non-finite coordinates, repeated consecutive points or a degenerate interpolation.
    Malformed,
    /// Part of the road polygon lies on or outside the map's border.
    OutsideMap,
    /// The road polygon overlaps itself.
    SelfIntersecting,
    /// The centre line is not longer than [`MIN_LENGTH_M`].
    TooShort,
    /// A turn is tighter than [`MIN_RADIUS_FT`].
    TooSharp,
    /// The polyline through the points is longer than [`MAX_ROAD_LENGTH_M`] (our bound, not the
    /// competition's: on its 200 m map no valid road comes near it).
    TooLong,
}

impl Reason {
    /// The stable reason code (`outside_map`, ...).
    pub fn code(self) -> &'static str {
        match self {
            Reason::NotEnoughPoints => "not_enough_points",
            Reason::TooManyPoints => "too_many_points",
            Reason::Malformed => "malformed",
            Reason::OutsideMap => "outside_map",
            Reason::SelfIntersecting => "self_intersecting",
            Reason::TooShort => "too_short",
            Reason::TooSharp => "too_sharp",
            Reason::TooLong => "too_long",
        }
    }

    /// The competition's message for this reason.
    pub fn message(self) -> &'static str {
        match self {
            Reason::NotEnoughPoints => "Not enough road points.",
            Reason::TooManyPoints => "The road definition contains too many points",
            Reason::Malformed => "The road points are malformed",
            Reason::OutsideMap => "Not entirely inside the map boundaries",
            Reason::SelfIntersecting => "The road is self-intersecting",
            Reason::TooShort => "The road is not long enough.",
            Reason::TooSharp => "The road is too sharp",
            Reason::TooLong => "The road is longer than 20 km",
        }
    }
}

impl std::fmt::Display for Reason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.code())
    }
}

/// The validator's answer for one road.
#[derive(Debug, Clone)]
pub struct Verdict {
    /// `None` when the road is valid.
    pub reason: Option<Reason>,
    /// The interpolated road, when the points could be interpolated.
    pub road: Option<Road>,
}

impl Verdict {
    /// Whether the road is valid.
    pub fn is_valid(&self) -> bool {
        self.reason.is_none()
    }

    /// The competition's message (empty for a valid road).
    pub fn message(&self) -> &'static str {
        self.reason.map_or("", Reason::message)
    }
}

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

fn vector(p: Point) -> Vector2 {
    Vector2::new(p[0], p[1])
}

/// The four sides of a quad, as segments.
fn sides(quad: &[Point; 4]) -> [(Point, Point); 4] {
    [
        (quad[0], quad[1]),
        (quad[1], quad[2]),
        (quad[2], quad[3]),
        (quad[3], quad[0]),
    ]
}

/// Twice the signed area of triangle `a b c`: positive when `c` is left of `a → b`.
fn orientation(a: Point, b: Point, c: Point) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether `p`, known to be collinear with segment `s`, lies within its bounding box.
fn within(s: (Point, Point), p: Point) -> bool {
    p[0] >= s.0[0].min(s.1[0])
        && p[0] <= s.0[0].max(s.1[0])
        && p[1] >= s.0[1].min(s.1[1])
        && p[1] <= s.0[1].max(s.1[1])
}

/// Whether two closed segments share at least one point (crossing, touching or overlapping).
fn segments_touch(x: (Point, Point), y: (Point, Point)) -> bool {
    let (o1, o2) = (orientation(x.0, x.1, y.0), orientation(x.0, x.1, y.1));
    let (o3, o4) = (orientation(y.0, y.1, x.0), orientation(y.0, y.1, x.1));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && within(x, y.0))
        || (o2 == 0.0 && within(x, y.1))
        || (o3 == 0.0 && within(y, x.0))
        || (o4 == 0.0 && within(y, x.1))
}

/// Whether the road polygon overlaps itself (see the module docs for the rules).
pub fn is_self_intersecting(quads: &[[Point; 4]]) -> bool {
    if quads.iter().any(|q| !is_simple_quad(q)) {
        return true;
    }
    if quads
        .windows(2)
        .any(|w| !rung_separates_adjacent(&w[0], &w[1]) && adjacent_quads_overlap(&w[0], &w[1]))
    {
        return true;
    }
    // Sort-and-sweep along x: only quads whose x-ranges overlap are compared further.
    let ranges: Vec<(f64, f64, f64, f64)> = quads
        .iter()
        .map(|q| {
            let (mut min_x, mut max_x) = (f64::INFINITY, f64::NEG_INFINITY);
            let (mut min_y, mut max_y) = (f64::INFINITY, f64::NEG_INFINITY);
            for p in q {
                (min_x, max_x) = (min_x.min(p[0]), max_x.max(p[0]));
                (min_y, max_y) = (min_y.min(p[1]), max_y.max(p[1]));
            }
            (min_x, max_x, min_y, max_y)
        })
        .collect();
    let mut order: Vec<usize> = (0..quads.len()).collect();
    order.sort_unstable_by(|&a, &b| ranges[a].0.total_cmp(&ranges[b].0));
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            if ranges[b].0 > ranges[a].1 {
                break;
            }
            let (first, second) = (a.min(b), a.max(b));
            let y_overlap = ranges[b].2 <= ranges[a].3 && ranges[a].2 <= ranges[b].3;
            if y_overlap
                && second > first + 1
                && !rung_separates(&quads[first], &quads[second])
                && quads_touch(&quads[first], &quads[second])
            {
                return true;
            }
        }
    }
    false
}

/// Whether a quad is convex with its corners in strict turning order (which makes it simple).
fn is_strictly_convex(quad: &[Point; 4]) -> bool {
    let turns = [0, 1, 2, 3].map(|i| orientation(quad[i], quad[(i + 1) % 4], quad[(i + 2) % 4]));
    turns.iter().all(|&t| t > 0.0) || turns.iter().all(|&t| t < 0.0)
}

/// Which side of the line `a → b` the point lies on: +1 left, -1 right, 0 on it.
fn side(a: Point, b: Point, p: Point) -> f64 {
    orientation(a, b, p).signum() * (orientation(a, b, p) != 0.0) as u8 as f64
}

/// Fast exact test for consecutive quads on a well-formed road: both convex, on opposite sides
/// of their shared side's line, so they can only meet along that side.
fn rung_separates_adjacent(a: &[Point; 4], b: &[Point; 4]) -> bool {
    let (l, r) = (a[1], a[2]);
    let behind = side(l, r, a[0]);
    behind != 0.0
        && side(l, r, a[3]) == behind
        && side(l, r, b[1]) == -behind
        && side(l, r, b[2]) == -behind
        && is_strictly_convex(a)
        && is_strictly_convex(b)
}

/// Fast exact test for quads `a` before `b` on the road: the line of `a`'s far side (or of `b`'s
/// near side) has the other quad strictly beyond it, so the two cannot meet. Each quad lies in the
/// hull of its corners, so corners on the near (closed) side keep the whole quad there.
fn rung_separates(a: &[Point; 4], b: &[Point; 4]) -> bool {
    let separated_by = |line: (Point, Point), own: [Point; 2], other: &[Point; 4]| {
        let near = side(line.0, line.1, own[0]);
        near != 0.0
            && side(line.0, line.1, own[1]) == near
            && other.iter().all(|&p| side(line.0, line.1, p) == -near)
    };
    separated_by((a[1], a[2]), [a[0], a[3]], b) || separated_by((b[0], b[3]), [b[1], b[2]], a)
}

/// A quad is simple when neither pair of opposite sides meets and it has an area.
fn is_simple_quad(quad: &[Point; 4]) -> bool {
    if is_strictly_convex(quad) {
        return true;
    }
    let s = sides(quad);
    !segments_touch(s[0], s[2]) && !segments_touch(s[1], s[3]) && polyline::signed_area(quad) != 0.0
}

/// Whether two simple quads share any point (sides crossing or touching, or one inside the other).
fn quads_touch(a: &[Point; 4], b: &[Point; 4]) -> bool {
    let (sa, sb) = (sides(a), sides(b));
    sa.iter().any(|&x| sb.iter().any(|&y| segments_touch(x, y)))
        || point_in_poly2d(vector(b[0]), &a.map(vector))
        || point_in_poly2d(vector(a[0]), &b.map(vector))
}

/// Whether consecutive quads `a` (sides `l0 l1 r1 r0`) and `b` (`l1 l2 r2 r1`) meet anywhere
/// but along their shared side `l1 r1`.
fn adjacent_quads_overlap(a: &[Point; 4], b: &[Point; 4]) -> bool {
    let (sa, sb) = (sides(a), sides(b));
    for (i, &x) in sa.iter().enumerate() {
        for (j, &y) in sb.iter().enumerate() {
            // Side 1 of `a` and side 3 of `b` are the shared side itself.
            if i == 1 && j == 3 {
                continue;
            }
            let overlap = match common_end(x, y) {
                // Sides from one corner meet elsewhere only when they fold onto each other.
                Some((corner, x_far, y_far)) => folds_back(corner, x_far, y_far),
                None => segments_touch(x, y),
            };
            if overlap {
                return true;
            }
        }
    }
    let (a_poly, b_poly) = (a.map(vector), b.map(vector));
    [b[1], b[2]]
        .iter()
        .any(|&p| point_in_poly2d(vector(p), &a_poly))
        || [a[0], a[3]]
            .iter()
            .any(|&p| point_in_poly2d(vector(p), &b_poly))
}

/// The endpoint two segments share, with each segment's other end.
fn common_end(x: (Point, Point), y: (Point, Point)) -> Option<(Point, Point, Point)> {
    [(x.0, x.1), (x.1, x.0)]
        .into_iter()
        .find_map(|(corner, x_far)| {
            [(y.0, y.1), (y.1, y.0)]
                .into_iter()
                .find(|&(y_corner, _)| y_corner == corner)
                .map(|(_, y_far)| (corner, x_far, y_far))
        })
}

/// Whether two sides leaving `corner` towards `x_far` and `y_far` lie on top of each other.
fn folds_back(corner: Point, x_far: Point, y_far: Point) -> bool {
    let (u, v) = (
        [x_far[0] - corner[0], x_far[1] - corner[1]],
        [y_far[0] - corner[0], y_far[1] - corner[1]],
    );
    let cross = u[0] * v[1] - u[1] * v[0];
    let dot = u[0] * v[0] + u[1] * v[1];
    cross == 0.0 && dot > 0.0
}

#[cfg(test)]
mod properties;

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
