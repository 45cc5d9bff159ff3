//! Body out of lane percentage (BOLP): the share of the car's footprint outside the right lane,
//! and the competition's signed distance to the lane.

pub use crate::road::polyline::signed_area;
use crate::road::{polyline, Point, Road, LANE_WIDTH_M};

/// Scratch space for clipping, reused so that a simulation allocates nothing per sample.
#[derive(Debug, Clone, Default)]
pub struct ClipBuffers {
    current: Vec<Point>,
    next: Vec<Point>,
}

/// Area of the intersection of a simple polygon with a convex polygon, square metres.
pub fn intersection_area(subject: &[Point], convex: &[Point]) -> f64 {
    intersection_area_with(subject, convex, &mut ClipBuffers::default())
}

/// [`intersection_area`] in reusable buffers.
///
/// Sutherland–Hodgman clipping of `subject` by each edge of `convex`: correct for a concave
/// subject (the result may hold zero-width bridges, which add no area).
pub fn intersection_area_with(
    subject: &[Point],
    convex: &[Point],
    buffers: &mut ClipBuffers,
) -> f64 {
    let orientation = signed_area(convex).signum();
    let ClipBuffers { current, next } = buffers;
    current.clear();
    current.extend_from_slice(subject);
    for i in 0..convex.len() {
        let (a, b) = (convex[i], convex[(i + 1) % convex.len()]);
        // Positive when p lies on the inner side of edge a→b.
        let side = |p: Point| {
            orientation * ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]))
        };
        next.clear();
        for j in 0..current.len() {
            let (p, q) = (current[j], current[(j + 1) % current.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                next.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                next.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        std::mem::swap(current, next);
        if current.is_empty() {
            return 0.0;
        }
    }
    signed_area(current).abs()
}

/// BOLP of a car footprint (a convex quadrilateral) against a right-lane polygon:
/// `1 - area(car ∩ lane) / area(car)`, in `[0, 1]`.
pub fn bolp(car_corners: &[Point; 4], right_lane: &[Point]) -> f64 {
    bolp_with(car_corners, right_lane, &mut ClipBuffers::default())
}

/// [`bolp`] in reusable buffers.
pub fn bolp_with(car_corners: &[Point; 4], right_lane: &[Point], buffers: &mut ClipBuffers) -> f64 {
    let car_area = signed_area(car_corners).abs();
    if car_area == 0.0 {
        return 0.0;
    }
    (1.0 - intersection_area_with(right_lane, car_corners, buffers) / car_area).clamp(0.0, 1.0)
}

/// The competition's `oob_distance` towards the right lane: half the lane width minus the distance
/// from the car's centre to the right lane's centre line (2 m when centred, negative outside).
pub fn oob_distance_right(car_center: Point, right_lane_centre: &[Point]) -> f64 {
    LANE_WIDTH_M / 2.0 - polyline::distance_to(car_center, right_lane_centre)
}

/// The lane distance (metres, positive inside) at which a car `width_m` wide, parallel to the
/// lane's edge, has the given BOLP: where a lane-distance fitness meets a BOLP threshold.
pub fn lane_distance_at_bolp(bolp: f64, width_m: f64) -> f64 {
    width_m * (0.5 - bolp)
}

/// BOLP of a car footprint on a road, using the whole right lane.
pub fn road_bolp(road: &Road, car_corners: &[Point; 4]) -> f64 {
    bolp(
        car_corners,
        &road.right_lane_polygon(0, road.interpolated.len() - 1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, side: f64) -> [Point; 4] {
        [[x, y], [x + side, y], [x + side, y + side], [x, y + side]]
    }

    #[test]
    fn overlap_of_two_squares() {
        let a = square(0.0, 0.0, 2.0);
        let b = square(1.0, 1.0, 2.0);
        assert!((intersection_area(&a, &b) - 1.0).abs() < 1e-12);
        // Clockwise clip polygon gives the same answer.
        let mut b_cw = b;
        b_cw.reverse();
        assert!((intersection_area(&a, &b_cw) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn concave_subject_is_clipped_correctly() {
        // A U shape: the 1 m gap between its arms is not part of it.
        let u = [
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 3.0],
            [2.0, 3.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ];
        let clip = [[0.0, 2.0], [3.0, 2.0], [3.0, 3.0], [0.0, 3.0]];
        assert!((intersection_area(&u, &clip) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_parallel_car_at_the_lane_distance_of_a_bolp_has_that_bolp() {
        // A 4 m lane along x in [0, 4]; the car is 1.9 m wide (x) and 4.6 m long (y).
        let lane = [[0.0, -50.0], [4.0, -50.0], [4.0, 50.0], [0.0, 50.0]];
        let (width, length) = (1.9, 4.6);
        for wanted in [0.0, 0.1, 0.5, 0.85, 0.95] {
            let centre_x = 4.0 - lane_distance_at_bolp(wanted, width);
            let (left, right) = (centre_x - width / 2.0, centre_x + width / 2.0);
            let car = [[left, 0.0], [right, 0.0], [right, length], [left, length]];
            assert!((bolp(&car, &lane) - wanted).abs() < 1e-12, "{wanted}");
        }
    }

    #[test]
    fn bolp_is_share_outside() {
        let lane = square(0.0, 0.0, 4.0);
        assert!(bolp(&square(1.0, 1.0, 1.0), &lane).abs() < 1e-12);
        assert!((bolp(&square(3.5, 1.0, 1.0), &lane) - 0.5).abs() < 1e-12);
        assert!((bolp(&square(10.0, 1.0, 1.0), &lane) - 1.0).abs() < 1e-12);
    }
}
