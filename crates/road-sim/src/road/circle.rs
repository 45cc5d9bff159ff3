//! The radius of the circle through three points, as the competition's sharpness rule and its
//! MAX_CURV feature measure it.

use super::Point;

/// Below this absolute determinant the three points count as collinear (infinite radius).
const COLLINEAR_DETERMINANT: f64 = 1e-6;
/// Points per window of the sharpness rule; the circle goes through its first, middle and last.
pub const WINDOW_POINTS: usize = 5;

/// Radius of the circle through `a`, `b`, `c`; infinite for (nearly) collinear points.
pub fn radius_through(a: Point, b: Point, c: Point) -> f64 {
    let b_sq = b[0] * b[0] + b[1] * b[1];
    let ab = (a[0] * a[0] + a[1] * a[1] - b_sq) / 2.0;
    let bc = (b_sq - c[0] * c[0] - c[1] * c[1]) / 2.0;
    let det = (a[0] - b[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (a[1] - b[1]);
    if det.abs() < COLLINEAR_DETERMINANT {
        return f64::INFINITY;
    }
    let cx = (ab * (b[1] - c[1]) - bc * (a[1] - b[1])) / det;
    let cy = ((a[0] - b[0]) * bc - (b[0] - c[0]) * ab) / det;
    (cx - a[0]).hypot(cy - a[1])
}

/// Smallest radius over the competition's windows of the interpolated line: for `i` in
/// `0 .. len - 5` (the last window is skipped), the circle through points `i`, `i + 2`, `i + 4`.
/// Infinite when there is no window or every window is straight.
pub fn min_radius(interpolated: &[Point]) -> f64 {
    let windows = interpolated.len().saturating_sub(WINDOW_POINTS);
    (0..windows)
        .map(|i| radius_through(interpolated[i], interpolated[i + 2], interpolated[i + 4]))
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_of_points_on_a_circle() {
        let on_circle = |angle: f64| [3.0 + 12.5 * angle.cos(), -4.0 + 12.5 * angle.sin()];
        let r = radius_through(on_circle(0.1), on_circle(1.0), on_circle(2.5));
        assert!((r - 12.5).abs() < 1e-9);
    }

    #[test]
    fn collinear_points_have_infinite_radius() {
        assert!(radius_through([0.0, 0.0], [1.0, 1.0], [2.0, 2.0]).is_infinite());
    }
}
