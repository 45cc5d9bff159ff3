//! A road as the WOGAN authors' diversity measure describes it (stgem's SBST results analysis,
//! `euclidean_diversity`): [`DIVERSITY_POINTS`] of the interpolated centre line's points picked by
//! index, turned so that the first of the segments between them points north, and each segment's
//! direction as an angle from north, clockwise, in (−π, π].
//!
//! This differs from [`super::heading_profile`] in two ways that change the figures: the points
//! are picked by index, not by arc length (the competition's interpolated points are about 1 m
//! apart, so the two nearly agree), and the angles are not unwrapped, so a road that turns further
//! than half a revolution from its start jumps by a whole turn. The search compares roads by the
//! unwrapped heading profile, which is continuous in the road; this module is only the measure.
//!
//! Beside the authors' distance (Euclidean over the angles as plain numbers), [`angle_distance`]
//! takes each difference as the angle between the two directions, so that two roads both heading
//! back the way they came (angles near +π and near −π) are near, as they look; `wogan report`
//! gives the median of both (docs/reference.md, "Diversity").

use super::Point;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Points picked from each road (so its description has one value fewer).
pub const DIVERSITY_POINTS: usize = 75;

/// The angles from north (radians, clockwise, in (−π, π]) of the [`DIVERSITY_POINTS`] − 1
/// segments between points picked from `interpolated` (at least one point), after turning the
/// picked points so that the first segment points north.
pub fn diversity_profile(interpolated: &[Point]) -> Vec<f64> {
    let picked = pick_by_index(interpolated, DIVERSITY_POINTS);
    let turned = turn_to_north(&picked);
    turned
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).atan2(w[1][1] - w[0][1]))
        .collect()
}

/// The distance of two descriptions (of one length) with each difference taken as the angle
/// between the two directions, folded into [−π, π]: the Euclidean norm of those angles.
pub fn angle_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let between = (x - y + PI).rem_euclid(TAU) - PI;
            between * between
        })
        .sum::<f64>()
        .sqrt()
}

/// `count` points of `line` (at least one point) at indices `i × (len − 1) / (count − 1)`
/// rounded half to even (numpy's `round` over `linspace`).
fn pick_by_index(line: &[Point], count: usize) -> Vec<Point> {
    let last = line.len() - 1;
    let step = last as f64 / (count - 1) as f64;
    // The product is within a rounding error of [0, last], so the rounded index is in range
    // (the last one `last` exactly, as numpy's `linspace` ends on its stop).
    (0..count)
        .map(|i| line[(i as f64 * step).round_ties_even() as usize])
        .collect()
}

/// `points` moved so that the first lies at the origin and turned about it so that the first
/// segment points north (+y); a single point is just moved. A first segment of no length is
/// taken to point east (`atan2(0, 0)`), as the authors' `move_road` does.
fn turn_to_north(points: &[Point]) -> Vec<Point> {
    let first = points[0];
    let Some(second) = points.get(1) else {
        return vec![[0.0, 0.0]];
    };
    let angle = FRAC_PI_2 - (second[1] - first[1]).atan2(second[0] - first[0]);
    let (sin, cos) = (angle.sin(), angle.cos());
    points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - first[0], p[1] - first[1]);
            [cos * x - sin * y, sin * x + cos * y]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `count` points on a circle of `radius` from (radius, 0) counterclockwise over `turn_rad`.
    fn arc(radius: f64, turn_rad: f64, count: usize) -> Vec<Point> {
        (0..count)
            .map(|i| {
                let a = turn_rad * i as f64 / (count - 1) as f64;
                [radius * a.cos(), radius * a.sin()]
            })
            .collect()
    }

    #[test]
    fn a_straight_road_points_north_throughout() {
        let line: Vec<Point> = (0..200).map(|i| [3.0 * i as f64, -(i as f64)]).collect();
        let profile = diversity_profile(&line);
        assert_eq!(profile.len(), DIVERSITY_POINTS - 1);
        assert!(profile.iter().all(|a| a.abs() < 1e-12), "{profile:?}");
    }

    #[test]
    fn a_left_turn_is_negative_and_wraps_past_half_a_revolution() {
        // Three quarters of a counterclockwise circle: a left turn of 270°, so the segments'
        // angles from the first fall from 0 towards −3π/2, which lies at +π/2 once wrapped.
        let profile = diversity_profile(&arc(50.0, 1.5 * PI, 7_401));
        assert!(profile[1] < 0.0);
        // The last segment lies 73/74 of the turn after the first.
        let last = *profile.last().unwrap();
        let expected = TAU - 73.0 / 74.0 * 1.5 * PI;
        assert!((last - expected).abs() < 1e-3, "{last} against {expected}");
        assert!(expected > FRAC_PI_2);
        assert!(profile.iter().all(|a| (-PI..=PI).contains(a)));
        // Exactly one jump of nearly a whole turn, where the angle passes −π.
        let jumps = profile
            .windows(2)
            .filter(|w| (w[1] - w[0]).abs() > PI)
            .count();
        assert_eq!(jumps, 1);
        assert!(profile.windows(2).any(|w| (w[1] - w[0] - TAU).abs() < 0.2));
    }

    #[test]
    fn angle_distance_takes_the_angle_between_directions() {
        // Both roads head nearly back: a whole turn apart as numbers, 0.08 rad as directions.
        let (a, b) = ([3.1, 0.0], [-3.1, 0.0]);
        assert!((angle_distance(&a, &b) - (TAU - 6.2)).abs() < 1e-12);
        // Where every difference is at most half a turn the two distances agree.
        let (c, d) = ([0.5, -1.0], [-1.0, 2.0]);
        assert!((angle_distance(&c, &d) - (1.5f64.hypot(3.0))).abs() < 1e-12);
        // Turned 2 rad left and 2 rad right, the directions are 2π − 4 apart.
        assert!((angle_distance(&[2.0], &[-2.0]) - (TAU - 4.0)).abs() < 1e-12);
        assert_eq!(angle_distance(&c, &d), angle_distance(&d, &c));
        assert_eq!(angle_distance(&a, &a), 0.0);
    }

    #[test]
    fn points_are_picked_by_index_rounding_half_to_even() {
        // 38 points: index i × 37/74 = i / 2, so odd i land on a half and round to the even index.
        let line: Vec<Point> = (0..38).map(|i| [i as f64, 0.0]).collect();
        let picked = pick_by_index(&line, DIVERSITY_POINTS);
        let indices: Vec<usize> = picked.iter().map(|p| p[0] as usize).collect();
        assert_eq!(&indices[..8], &[0, 0, 1, 2, 2, 2, 3, 4]);
        assert_eq!(*indices.last().unwrap(), 37);
    }

    #[test]
    fn repeated_points_give_a_zero_angle_and_a_quarter_turn_first() {
        // Fewer points than picked: some segments join a point to itself (angle 0). The first
        // does, so it has no direction: atan2(0, 0) = 0 turns the road by a quarter, as the
        // authors' `move_road` does, and north becomes west.
        let profile = diversity_profile(&[[0.0, 0.0], [0.0, 10.0], [10.0, 20.0]]);
        assert_eq!(profile.len(), DIVERSITY_POINTS - 1);
        assert_eq!(profile[0], 0.0);
        assert!(profile.iter().any(|&a| (a + FRAC_PI_2).abs() < 1e-12));
        assert!(profile.iter().any(|&a| (a + PI / 4.0).abs() < 1e-12));
    }
}
