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
    let angle = (mod_360((u.0 - v.0).abs() + 180.0) - 180.0).abs();
    let length = (u.1 - v.1).abs();
    if angle < ANGLE_EPS_DEG && length < LENGTH_EPS_M {
        0.0
    } else {
        0.5 * (angle / (1.0 + angle) + length / (1.0 + length))
    }
}

/// `floor_mod(x, 360.0)`, by subtraction where that is exact: for `x` above 0 and below 1080 the
/// remainder is `x`, `x - 360` or `x - 720`, and those subtractions lose nothing (Sterbenz: `x`
/// lies within a factor of two of what is taken off). Angles between steps lie within ±360°, so
/// their differences plus 180 stay below 900 and never need the division `%` makes (the
/// costliest part of comparing two segments).
fn mod_360(x: f64) -> f64 {
    // Zero is left to `floor_mod`, which gives +0 for -0.
    if x > 0.0 && x < 360.0 {
        x
    } else if (360.0..720.0).contains(&x) {
        x - 360.0
    } else if (720.0..1080.0).contains(&x) {
        x - 720.0
    } else {
        floor_mod(x, 360.0)
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

/// Tables filled side by side by [`steps_distances`].
pub const LANES: usize = 4;

/// [`steps_distance`] of `s` against each of `ts`, bit for bit, the [`LANES`] tables filled side
/// by side: each cell of one table waits on the cell above it, but the tables do not wait on
/// each other, so the processor works on a cell of each at once (about three times the speed of
/// one table after another). The tables share their rows (the steps of `s`); a table whose
/// segment has fewer steps than the longest is read when its last column is filled, and the
/// columns past it, filled with a copy of its last step, are never read.
pub fn steps_distances(s: &[(f64, f64)], ts: [&[(f64, f64)]; LANES]) -> [f64; LANES] {
    let columns = ts.iter().map(|t| t.len()).max().unwrap_or(0);
    let mut previous: Vec<[f64; LANES]> = (0..=s.len()).map(|i| [i as f64; LANES]).collect();
    let mut current = vec![[0.0; LANES]; s.len() + 1];
    let mut distances = [f64::NAN; LANES];
    for col in 0..columns {
        let tc: [(f64, f64); LANES] =
            std::array::from_fn(|k| ts[k].get(col).or(ts[k].last()).copied().unwrap_or_default());
        current[0] = [(col + 1) as f64; LANES];
        for (row, &sr) in s.iter().enumerate() {
            let (above, diagonal, left) = (current[row], previous[row], previous[row + 1]);
            let mut cell = [0.0; LANES];
            for k in 0..LANES {
                // As in `steps_distance`: Python's min keeps the first of equal values.
                let deletion = above[k] + 1.0;
                let insertion = left[k] + 1.0;
                let substitution = diagonal[k] + substitution_cost(sr, tc[k]);
                let mut best = deletion;
                if insertion < best {
                    best = insertion;
                }
                if substitution < best {
                    best = substitution;
                }
                cell[k] = best;
            }
            current[row + 1] = cell;
        }
        std::mem::swap(&mut previous, &mut current);
        for (k, t) in ts.iter().enumerate() {
            if t.len() == col + 1 {
                distances[k] = previous[s.len()][k];
            }
        }
    }
    // A segment without steps is as far as `s` has steps (`steps_distance`'s empty table).
    for (k, t) in ts.iter().enumerate() {
        if t.is_empty() {
            distances[k] = s.len() as f64;
        }
    }
    distances
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
        // The subtractions give the remainder bit for bit, boundaries and -0 included.
        let near = |v: f64| [v, v.next_down(), v.next_up()];
        let cases = [
            0.0,
            -0.0,
            180.0,
            360.0,
            720.0,
            1080.0,
            1e300,
            f64::INFINITY,
            f64::NAN,
        ]
        .into_iter()
        .flat_map(near)
        .chain((0..200_000).map(|i| f64::from(i) * 0.006_123_457));
        for x in cases {
            assert_eq!(mod_360(x).to_bits(), floor_mod(x, 360.0).to_bits(), "{x}");
        }
        // Bit for bit Python's remainder, across the range angle differences take.
        for i in 0..100_000 {
            let x = -1000.0 + f64::from(i) * 0.023_456_789;
            let r = x % 360.0;
            let python = if r < 0.0 { r + 360.0 } else { r };
            assert_eq!(floor_mod(x, 360.0).to_bits(), python.to_bits(), "{x}");
        }
    }

    #[test]
    fn tables_side_by_side_give_each_distance_bit_for_bit() {
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        // Steps as segments give them: turns within ±360°, lengths near 1 m, some repeated.
        let mut segment = |len: usize| -> Vec<(f64, f64)> {
            (0..len)
                .map(|_| (720.0 * next() - 360.0, 0.5 + next()))
                .collect()
        };
        for round in 0..200 {
            let s = segment(1 + round % 70);
            let ts: Vec<Vec<(f64, f64)>> = (0..LANES)
                .map(|k| match (round + k) % 9 {
                    0 => Vec::new(),
                    1 => s.clone(),
                    n => segment(n * 9 + round % 5),
                })
                .collect();
            let together = steps_distances(&s, std::array::from_fn(|k| ts[k].as_slice()));
            for (k, t) in ts.iter().enumerate() {
                assert_eq!(
                    together[k].to_bits(),
                    steps_distance(&s, t).to_bits(),
                    "round {round}, table {k}"
                );
            }
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
