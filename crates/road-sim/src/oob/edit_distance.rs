//! The distance between two interesting segments: a Levenshtein distance over their steps, each
//! step an (angle, length) pair, where substituting one step for another costs by how much the
//! two differ (`self_driving/edit_distance_polyline.py`).
//!
//! A step's angle is its direction minus the previous step's, in degrees, from `atan2`
//! differences that are not wrapped (so within ±360); the first step's angle is 0. The cost
//! wraps the difference of two angles into [0, 180] before comparing.

use super::error::OobError;
use crate::road::Point;

/// Angle differences below this many degrees, with lengths within [`LENGTH_EPS_M`], cost nothing.
pub const ANGLE_EPS_DEG: f64 = 0.3;
/// Length differences below this many metres, with angles within [`ANGLE_EPS_DEG`], cost nothing.
pub const LENGTH_EPS_M: f64 = 0.2;

/// The (angle in degrees, length in metres) of each step of `points` (at least two).
pub fn angle_lengths(points: &[Point]) -> Result<Vec<(f64, f64)>, OobError> {
    if points.len() < 2 {
        return Err(OobError::SegmentTooShort(points.len()));
    }
    let step = |i: usize| {
        [
            points[i + 1][0] - points[i][0],
            points[i + 1][1] - points[i][1],
        ]
    };
    let mut previous = step(0);
    Ok((0..points.len() - 1)
        .map(|i| {
            let current = step(i);
            let turn = current[1].atan2(current[0]) - previous[1].atan2(previous[0]);
            previous = current;
            // numpy's degrees multiplies by 180/π (f64::to_degrees uses a differently rounded
            // constant).
            let angle = turn * (180.0 / std::f64::consts::PI);
            let length = (current[0] * current[0] + current[1] * current[1]).sqrt();
            (angle, length)
        })
        .collect())
}

/// What substituting step `u` for step `v` costs: 0 when both differences are small, else the
/// mean of `d / (1 + d)` over the wrapped angle difference and the length difference.
pub fn substitution_cost(u: (f64, f64), v: (f64, f64)) -> f64 {
    let angle = (floor_mod((u.0 - v.0).abs() + 180.0, 360.0) - 180.0).abs();
    let length = (u.1 - v.1).abs();
    if angle < ANGLE_EPS_DEG && length < LENGTH_EPS_M {
        0.0
    } else {
        0.5 * (angle / (1.0 + angle) + length / (1.0 + length))
    }
}

/// Python's (and numpy's) float `%`: the remainder takes the sign of the divisor.
fn floor_mod(x: f64, m: f64) -> f64 {
    let r = x % m;
    if r != 0.0 && (r < 0.0) != (m < 0.0) {
        r + m
    } else if r == 0.0 {
        0.0f64.copysign(m)
    } else {
        r
    }
}

/// The pipeline's distance between two segments: insertions and deletions cost 1, substitutions
/// [`substitution_cost`]. Segments of fewer than two points have no steps and are refused, as
/// the pipeline's assertion refuses them.
pub fn segment_distance(a: &[Point], b: &[Point]) -> Result<f64, OobError> {
    Ok(steps_distance(&angle_lengths(a)?, &angle_lengths(b)?))
}

/// [`segment_distance`] of two segments given by their [`angle_lengths`] (so that a segment met
/// in many pairs is turned into steps once).
pub fn steps_distance(s: &[(f64, f64)], t: &[(f64, f64)]) -> f64 {
    // Column by column (one column per step of `t`), as the pipeline fills its table.
    let mut previous: Vec<f64> = (0..=s.len()).map(|i| i as f64).collect();
    let mut current = vec![0.0; s.len() + 1];
    for (col, &tc) in t.iter().enumerate() {
        current[0] = (col + 1) as f64;
        for (row, &sr) in s.iter().enumerate() {
            let deletion = current[row] + 1.0;
            let insertion = previous[row + 1] + 1.0;
            let substitution = previous[row] + substitution_cost(sr, tc);
            // Python's min keeps the first of equal values.
            let mut best = deletion;
            if insertion < best {
                best = insertion;
            }
            if substitution < best {
                best = substitution;
            }
            current[row + 1] = best;
        }
        std::mem::swap(&mut previous, &mut current);
    }
    previous[s.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_turn_without_wrapping() {
        let points = [[0.0, 0.0], [-1.0, 0.01], [-2.0, -0.01]];
        let steps = angle_lengths(&points).unwrap();
        assert_eq!(steps[0].0, 0.0);
        // From just below +180° to just above -180°: almost -360°, not a small turn.
        assert!(steps[1].0 < -358.0, "{steps:?}");
    }

    #[test]
    fn a_repeated_point_is_a_step_of_angle_atan2_0_0() {
        let steps = angle_lengths(&[[0.0, 0.0], [0.0, 1.0], [0.0, 1.0]]).unwrap();
        assert_eq!(steps[1], (-90.0, 0.0));
    }

    #[test]
    fn small_differences_cost_nothing_and_angles_wrap() {
        assert_eq!(substitution_cost((0.29, 1.0), (0.0, 1.1)), 0.0);
        assert!(substitution_cost((0.3, 1.0), (0.0, 1.0)) > 0.0);
        // 1.2 - 1.0 is just under 0.2 in f64.
        assert_eq!(substitution_cost((0.0, 1.2), (0.0, 1.0)), 0.0);
        assert!(substitution_cost((0.0, 1.5), (0.0, 1.25)) > 0.0);
        assert_eq!(substitution_cost((350.0, 1.0), (-10.0, 1.0)), 0.0);
        let wrapped = substitution_cost((179.0, 1.0), (-179.0, 1.0));
        assert!((wrapped - 0.5 * (2.0 / 3.0)).abs() < 1e-12);
        assert_eq!(floor_mod(-1.0, 360.0), 359.0);
        // Bit for bit Python's remainder, across the range angle differences take.
        for i in 0..100_000 {
            let x = -1000.0 + f64::from(i) * 0.023_456_789;
            let r = x % 360.0;
            let python = if r < 0.0 { r + 360.0 } else { r };
            assert_eq!(floor_mod(x, 360.0).to_bits(), python.to_bits(), "{x}");
        }
    }

    #[test]
    fn distance_of_a_segment_to_itself_is_zero_and_lengths_count() {
        let a = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5], [3.0, 1.5]];
        assert_eq!(segment_distance(&a, &a), Ok(0.0));
        // Two steps to insert.
        assert_eq!(segment_distance(&a[..2], &a), Ok(2.0));
        assert_eq!(segment_distance(&[], &a), Err(OobError::SegmentTooShort(0)));
    }
}
