//! Planar distances and nearest points computed with GEOS's formulas and in GEOS's order, as the
//! pipeline gets them through shapely.
//!
//! [`crate::road::polyline::project`] answers the same questions, but not to the bit: it clamps the
//! projection factor and rebuilds an end point as `a + 1.0 * (b - a)`, which can differ from `b` in
//! the last bit. The interesting segment repeats the nearest point next to a resampled point, and
//! when the two coincide the step between them must be exactly zero, because the edit distance
//! reads its direction with `atan2(0, 0) = 0`; a step of 1e-15 m would have an arbitrary direction.

use crate::road::Point;

// GEOS's point distance and line length are the spline's (`sqrt(dx² + dy²)`, summed from the
// first segment).
pub use crate::road::spline::{distance, polyline_length as length};

/// Distance from `p` to the segment `a`–`b`: to an end point when `p` projects outside the
/// segment, else the perpendicular distance from the cross product.
fn point_to_segment(p: Point, a: Point, b: Point) -> f64 {
    if a == b {
        return distance(p, a);
    }
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let r = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2;
    if r <= 0.0 {
        return distance(p, a);
    }
    if r >= 1.0 {
        return distance(p, b);
    }
    let s = ((a[1] - p[1]) * dx - (a[0] - p[0]) * dy) / len2;
    s.abs() * len2.sqrt()
}

/// The point of the segment `a`–`b` closest to `p`: the projection when it falls strictly inside,
/// otherwise the nearer end point itself (`b` on a tie).
fn closest_on_segment(p: Point, a: Point, b: Point) -> Point {
    let factor = if p == a {
        0.0
    } else if p == b {
        1.0
    } else {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)
    };
    if factor > 0.0 && factor < 1.0 {
        return [a[0] + factor * (b[0] - a[0]), a[1] + factor * (b[1] - a[1])];
    }
    if distance(a, p) < distance(b, p) {
        a
    } else {
        b
    }
}

/// Distance from `p` to the polyline `line` (at least two points).
pub fn distance_to_line(p: Point, line: &[Point]) -> f64 {
    line.windows(2)
        .map(|w| point_to_segment(p, w[0], w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// The point of the polyline `line` nearest to `p`: on the first segment whose distance is
/// strictly the smallest, as GEOS scans them. A one-point line answers its point.
pub fn nearest_on_line(p: Point, line: &[Point]) -> Point {
    let mut best = f64::INFINITY;
    let mut nearest = line.first().copied().unwrap_or(p);
    for w in line.windows(2) {
        let d = point_to_segment(p, w[0], w[1]);
        if d < best {
            best = d;
            nearest = closest_on_segment(p, w[0], w[1]);
        }
        // GEOS stops at the first segment that touches the point.
        if best <= 0.0 {
            break;
        }
    }
    nearest
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_beyond_a_corner_is_nearest_to_the_corner_itself() {
        // Outside the bend both segments project the point past their shared end.
        let line = [[0.0, 0.0], [0.1, 0.0], [0.1 + 0.3, 0.7]];
        let corner = nearest_on_line([0.35, -0.4], &line);
        assert_eq!(corner, [0.1, 0.0]);
        assert_eq!(distance(corner, line[1]), 0.0);
    }

    #[test]
    fn ties_go_to_the_first_segment_and_to_its_far_end() {
        let line = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        // Equidistant from (1, 0) over both segments: the first one answers its end point.
        assert_eq!(nearest_on_line([1.0, 3.0], &line), [1.0, 0.0]);
        assert_eq!(distance_to_line([1.0, 3.0], &line), 3.0);
        // Inside a segment the projection is returned.
        assert_eq!(nearest_on_line([0.25, -2.0], &line), [0.25, 0.0]);
        assert_eq!(distance_to_line([0.25, -2.0], &line), 2.0);
    }

    #[test]
    fn length_sums_segments_in_order() {
        let line = [[0.0, 0.0], [3.0, 4.0], [3.0, 10.0]];
        assert_eq!(length(&line), 11.0);
        assert_eq!(length(&line[..1]), 0.0);
    }
}
