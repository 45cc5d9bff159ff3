//! Distances from points to polylines.

use super::Point;

/// Where a point projects onto a polyline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Index of the segment holding the closest point.
    pub segment: usize,
    /// Position of the closest point along that segment, in `[0, 1]`.
    pub along: f64,
    /// Distance from the point to the polyline, metres.
    pub distance_m: f64,
    /// Signed distance from the line through that segment, metres: positive to its left.
    pub lateral_m: f64,
}

/// The closest point of the polyline `line` (at least two points) to `point`, searched over
/// segments `first..last` (clamped to the line), or over the whole line when `None`.
pub fn project(point: Point, line: &[Point], window: Option<(usize, usize)>) -> Projection {
    let segments = line.len().saturating_sub(1);
    let (first, last) = window.map_or((0, segments), |(a, b)| (a.min(segments), b.min(segments)));
    let mut best = Projection {
        segment: first,
        along: 0.0,
        distance_m: f64::INFINITY,
        lateral_m: 0.0,
    };
    for segment in first..last {
        let (a, b) = (line[segment], line[segment + 1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let length_sq = dx * dx + dy * dy;
        let along = if length_sq > 0.0 {
            (((point[0] - a[0]) * dx + (point[1] - a[1]) * dy) / length_sq).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let distance_m = (a[0] + along * dx - point[0]).hypot(a[1] + along * dy - point[1]);
        if distance_m < best.distance_m {
            let lateral_m = (dx * (point[1] - a[1]) - dy * (point[0] - a[0])) / length_sq.sqrt();
            best = Projection {
                segment,
                along,
                distance_m,
                lateral_m,
            };
        }
    }
    best
}

/// Distance from `point` to the polyline `line`, metres.
pub fn distance_to(point: Point, line: &[Point]) -> f64 {
    project(point, line, None).distance_m
}

/// Signed area of a polygon (positive when counter-clockwise), square metres.
pub fn signed_area(polygon: &[Point]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_an_l_shaped_line() {
        let line = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]];
        assert!((distance_to([5.0, 3.0], &line) - 3.0).abs() < 1e-12);
        assert!((distance_to([12.0, 5.0], &line) - 2.0).abs() < 1e-12);
        assert!((distance_to([-3.0, -4.0], &line) - 5.0).abs() < 1e-12);
        let p = project([12.0, 5.0], &line, None);
        assert_eq!(p.segment, 1);
        assert!((p.along - 0.5).abs() < 1e-12);
        // Right of the upward segment.
        assert!((p.lateral_m + 2.0).abs() < 1e-12);
        assert!((project([5.0, 3.0], &line, None).lateral_m - 3.0).abs() < 1e-12);
    }
}
