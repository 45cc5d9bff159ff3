//! Interpolation of road points exactly as the SBST competition pipeline does it.
//!
//! The competition passes the road points to FITPACK's `splprep(s=0)` with a chord-length
//! parameter and samples the result at `1/n` steps. With `s = 0` FITPACK places its interior
//! knots at the data parameters except the second and second-to-last ones, which makes its
//! interpolant the unique *not-a-knot* cubic spline (degree 2 through three points, a line through
//! two). We build that same interpolant directly from its defining linear system, in f64, and
//! sample it with the same float steps (including numpy's `arange` quirk that sometimes adds one
//! sample just past `u = 1`, where the last polynomial piece is extrapolated).

use super::Point;

/// Target spacing of interpolated points, metres (the competition's `interpolation_distance`).
pub const INTERPOLATION_DISTANCE_M: f64 = 1.0;
/// Fewest samples of the spline (the competition's `min_num_nodes`).
pub const MIN_SAMPLES: usize = 20;
/// Interpolated coordinates are rounded to this many decimals, as the competition does.
pub const ROUNDING_DECIMALS: i32 = 3;
/// Longest polyline the spline is sampled along, metres: one sample per metre, so this bounds the
/// memory and time of any interpolation whatever the points.
pub const MAX_LENGTH_M: f64 = 20_000.0;

/// Why a point list cannot be interpolated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SplineError {
    /// Fewer than two points.
    #[error("at least 2 points are needed to interpolate, got {0}")]
    TooFewPoints(usize),
    /// A coordinate is NaN or infinite.
    #[error("point {0} has a non-finite coordinate")]
    NonFinite(usize),
    /// Two consecutive points coincide, so the chord-length parameter does not increase.
    #[error("points {0} and {1} coincide")]
    RepeatedPoint(usize, usize),
    /// The polyline through the points is longer than [`MAX_LENGTH_M`].
    #[error("the points span {0} m, more than the {MAX_LENGTH_M} m a road may")]
    TooLong(f64),
}

/// Length of the polyline through `points`, metres.
pub fn polyline_length(points: &[Point]) -> f64 {
    points.windows(2).map(|w| distance(w[0], w[1])).sum()
}

/// Euclidean distance between two points, as FITPACK's chord lengths and GEOS's (shapely's)
/// lengths compute it: `sqrt(dx² + dy²)`. Not `hypot`, which rounds differently in the last bit:
/// a 75 m WOGAN road then measures 74.99999999999999 m where the pipeline's measures 75, and is
/// sampled at 74 intervals instead of 75.
pub fn distance(a: Point, b: Point) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (dx * dx + dy * dy).sqrt()
}

/// Interpolates road points as the competition does: chord-length spline sampled about every
/// metre (at least [`MIN_SAMPLES`] intervals), coordinates rounded to 3 decimals.
pub fn interpolate(points: &[Point]) -> Result<Vec<Point>, SplineError> {
    let curve = ParametricSpline::fit(points)?;
    let length_m = polyline_length(points);
    if length_m > MAX_LENGTH_M {
        return Err(SplineError::TooLong(length_m));
    }
    let intervals = sample_intervals(length_m);
    Ok(sample_evenly(&curve, intervals, ROUNDING_DECIMALS))
}

/// Samples `curve` at numpy's `arange(0, 1 + 1/n, 1/n)` for `n = intervals`, each coordinate
/// rounded to `decimals` decimals the numpy way.
pub fn sample_evenly(curve: &ParametricSpline, intervals: usize, decimals: i32) -> Vec<Point> {
    let step = 1.0 / intervals as f64;
    // numpy's arange(0, 1 + step, step) has ceil((stop - start) / step) elements, computed in
    // floating point; for some n this is n + 2 and the last sample lies past u = 1.
    let count = ((1.0 + step) / step).ceil() as usize;
    (0..count)
        .map(|i| {
            let [x, y] = curve.eval(i as f64 * step);
            [round_like_numpy(x, decimals), round_like_numpy(y, decimals)]
        })
        .collect()
}

/// Of the samples [`interpolate`] would make, the one nearest (in the curve's parameter) to each
/// point, without making the others: enough to see that a road leaves the map, at the cost of
/// one evaluation per point.
pub fn samples_at_points(points: &[Point]) -> Result<Vec<Point>, SplineError> {
    let curve = ParametricSpline::fit(points)?;
    let step = sample_step(polyline_length(points));
    Ok(curve
        .knots
        .iter()
        .map(|&u| curve.sample((u / step).round() * step))
        .collect())
}

/// The parameter step between samples of a spline through points `length_m` apart in all.
fn sample_step(length_m: f64) -> f64 {
    1.0 / sample_intervals(length_m) as f64
}

/// How many parameter intervals the spline through points `length_m` apart is sampled at.
fn sample_intervals(length_m: f64) -> usize {
    ((length_m / INTERPOLATION_DISTANCE_M) as usize).max(MIN_SAMPLES)
}

/// Rounds to `decimals` decimals the way numpy does: scale, round half to even, unscale.
fn round_like_numpy(value: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    (value * scale).round_ties_even() / scale
}

/// A planar curve through the road points: one cubic Hermite piece per pair of consecutive
/// points, in the chord-length parameter `u ∈ [0, 1]`.
#[derive(Debug, Clone)]
pub struct ParametricSpline {
    /// Parameter value of each road point (0 for the first, 1 for the last).
    knots: Vec<f64>,
    /// The road points.
    values: Vec<Point>,
    /// `d(point)/du` at each road point.
    slopes: Vec<Point>,
}

impl ParametricSpline {
    /// The point at parameter `u`, rounded as the competition rounds its samples.
    fn sample(&self, u: f64) -> Point {
        let [x, y] = self.eval(u);
        [
            round_like_numpy(x, ROUNDING_DECIMALS),
            round_like_numpy(y, ROUNDING_DECIMALS),
        ]
    }

    /// Fits the interpolant of FITPACK's `splprep(s=0)` through `points`.
    pub fn fit(points: &[Point]) -> Result<Self, SplineError> {
        if points.len() < 2 {
            return Err(SplineError::TooFewPoints(points.len()));
        }
        if let Some(i) = points
            .iter()
            .position(|p| !p[0].is_finite() || !p[1].is_finite())
        {
            return Err(SplineError::NonFinite(i));
        }
        let mut knots = Vec::with_capacity(points.len());
        let mut arc = 0.0;
        knots.push(0.0);
        for (i, w) in points.windows(2).enumerate() {
            let chord = distance(w[0], w[1]);
            if chord == 0.0 {
                return Err(SplineError::RepeatedPoint(i, i + 1));
            }
            arc += chord;
            knots.push(arc);
        }
        if !arc.is_finite() {
            return Err(SplineError::NonFinite(points.len() - 1));
        }
        for knot in &mut knots {
            *knot /= arc;
        }
        let mut slopes = vec![[0.0; 2]; points.len()];
        for axis in 0..2 {
            let values: Vec<f64> = points.iter().map(|p| p[axis]).collect();
            for (slope, s) in slopes.iter_mut().zip(axis_slopes(&knots, &values)) {
                slope[axis] = s;
            }
        }
        Ok(Self {
            knots,
            values: points.to_vec(),
            slopes,
        })
    }

    /// The point at parameter `u`; outside `[0, 1]` the first or last piece is extrapolated.
    pub fn eval(&self, u: f64) -> Point {
        let last_piece = self.knots.len() - 2;
        // Knots are strictly increasing, so this finds the piece whose interval holds `u`.
        let piece = self.knots[1..=last_piece].partition_point(|&k| k <= u);
        let (u0, u1) = (self.knots[piece], self.knots[piece + 1]);
        let h = u1 - u0;
        let t = (u - u0) / h;
        // Cubic Hermite basis on [u0, u1].
        let h00 = (1.0 + 2.0 * t) * (1.0 - t) * (1.0 - t);
        let h10 = t * (1.0 - t) * (1.0 - t);
        let h01 = t * t * (3.0 - 2.0 * t);
        let h11 = t * t * (t - 1.0);
        let (p0, p1) = (self.values[piece], self.values[piece + 1]);
        let (m0, m1) = (self.slopes[piece], self.slopes[piece + 1]);
        let coord = |a: usize| h00 * p0[a] + h10 * h * m0[a] + h01 * p1[a] + h11 * h * m1[a];
        [coord(0), coord(1)]
    }
}

/// Slopes at the knots of the interpolating spline of one coordinate: a line for two points, the
/// parabola through three, and the not-a-knot cubic spline for four or more.
fn axis_slopes(knots: &[f64], values: &[f64]) -> Vec<f64> {
    let n = knots.len();
    let widths: Vec<f64> = knots.windows(2).map(|w| w[1] - w[0]).collect();
    let secants: Vec<f64> = values
        .windows(2)
        .zip(&widths)
        .map(|(v, h)| (v[1] - v[0]) / h)
        .collect();
    match n {
        2 => vec![secants[0]; 2],
        3 => {
            // The parabola through three points, differentiated at each of them.
            let (h0, h1) = (widths[0], widths[1]);
            let curvature = (secants[1] - secants[0]) / (h0 + h1);
            vec![
                secants[0] - curvature * h0,
                secants[0] + curvature * h0,
                secants[1] + curvature * h1,
            ]
        }
        _ => {
            // Continuity of the second derivative at interior knots; not-a-knot at both ends
            // (the third derivative is continuous at the second and second-to-last knots).
            let mut sub = vec![0.0; n];
            let mut diag = vec![0.0; n];
            let mut sup = vec![0.0; n];
            let mut rhs = vec![0.0; n];
            for i in 1..n - 1 {
                sub[i] = widths[i];
                diag[i] = 2.0 * (widths[i - 1] + widths[i]);
                sup[i] = widths[i - 1];
                rhs[i] = 3.0 * (widths[i] * secants[i - 1] + widths[i - 1] * secants[i]);
            }
            let (h0, h1) = (widths[0], widths[1]);
            let span = h0 + h1;
            diag[0] = h1;
            sup[0] = span;
            rhs[0] = ((h0 + 2.0 * span) * h1 * secants[0] + h0 * h0 * secants[1]) / span;
            let (ha, hb) = (widths[n - 3], widths[n - 2]);
            let span = ha + hb;
            sub[n - 1] = span;
            diag[n - 1] = ha;
            rhs[n - 1] =
                (hb * hb * secants[n - 3] + (2.0 * span + hb) * ha * secants[n - 2]) / span;
            solve_tridiagonal(&sub, &diag, &sup, rhs)
        }
    }
}

/// Solves a tridiagonal system by Gaussian elimination with partial pivoting (as LAPACK's
/// `gtsv`): the not-a-knot end rows are not diagonally dominant, so plain Thomas is not enough.
/// `sub[i]` multiplies `x[i-1]` in row `i`, `sup[i]` multiplies `x[i+1]`.
fn solve_tridiagonal(sub: &[f64], diag: &[f64], sup: &[f64], mut rhs: Vec<f64>) -> Vec<f64> {
    let n = diag.len();
    // Row i after elimination: d[i] x[i] + u1[i] x[i+1] + u2[i] x[i+2] = rhs[i].
    let mut d = diag.to_vec();
    let mut u1: Vec<f64> = sup.to_vec();
    let mut u2 = vec![0.0; n];
    // The not-yet-eliminated subdiagonal entry of the next row.
    for i in 0..n - 1 {
        let below = sub[i + 1];
        if below.abs() > d[i].abs() {
            // Swap rows i and i+1 (row i+1 is: below, diag[i+1], sup[i+1]).
            let (next_d, next_u1) = (d[i + 1], u1[i + 1]);
            let factor = d[i] / below;
            d[i] = below;
            let old_u1 = u1[i];
            u1[i] = next_d;
            u2[i] = if i + 1 < n - 1 { next_u1 } else { 0.0 };
            d[i + 1] = old_u1 - factor * next_d;
            u1[i + 1] = -factor * u2[i];
            rhs.swap(i, i + 1);
            rhs[i + 1] -= factor * rhs[i];
        } else {
            let factor = below / d[i];
            d[i + 1] -= factor * u1[i];
            rhs[i + 1] -= factor * rhs[i];
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut acc = rhs[i];
        if i + 1 < n {
            acc -= u1[i] * x[i + 1];
        }
        if i + 2 < n {
            acc -= u2[i] * x[i + 2];
        }
        x[i] = acc / d[i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tridiagonal_solver_matches_dense_solution() {
        // A system that needs pivoting in its first row.
        let sub = [0.0, 5.0, 1.0, 2.0];
        let diag = [1.0, 2.0, 4.0, 1.0];
        let sup = [3.0, 1.0, 1.0, 0.0];
        let x_true = [1.0, -2.0, 0.5, 3.0];
        let rhs: Vec<f64> = (0..4)
            .map(|i| {
                let mut r = diag[i] * x_true[i];
                if i > 0 {
                    r += sub[i] * x_true[i - 1];
                }
                if i < 3 {
                    r += sup[i] * x_true[i + 1];
                }
                r
            })
            .collect();
        let x = solve_tridiagonal(&sub, &diag, &sup, rhs);
        for (a, b) in x.iter().zip(x_true) {
            assert!((a - b).abs() < 1e-12, "{x:?}");
        }
    }

    #[test]
    fn cubic_data_is_reproduced_exactly() {
        // Points on a cubic in the chord parameter are not what we get (u is chord length), but a
        // straight line sampled unevenly must stay on the line.
        let points = [[0.0, 0.0], [1.0, 2.0], [3.0, 6.0], [4.0, 8.0], [7.0, 14.0]];
        let curve = ParametricSpline::fit(&points).unwrap();
        for i in 0..=50 {
            let [x, y] = curve.eval(i as f64 / 50.0);
            assert!((y - 2.0 * x).abs() < 1e-9);
        }
        assert!((curve.eval(1.0)[0] - 7.0).abs() < 1e-12);
    }

    #[test]
    fn not_a_knot_spline_has_one_cubic_over_each_pair_of_end_intervals() {
        // Uneven chords, so the end conditions are exercised asymmetrically.
        let points = [
            [0.0, 0.0],
            [10.0, 3.0],
            [13.0, 9.0],
            [30.0, 4.0],
            [33.0, -8.0],
            [60.0, 0.0],
        ];
        let curve = ParametricSpline::fit(&points).unwrap();
        for (knot, point) in curve.knots.iter().zip(&points) {
            let p = curve.eval(*knot);
            assert!((p[0] - point[0]).abs() < 1e-9 && (p[1] - point[1]).abs() < 1e-9);
        }
        // Third differences of equally spaced samples are constant within one cubic: across the
        // second knot and across the second-to-last knot.
        for (from, to) in [(0.0, curve.knots[2]), (curve.knots[3], 1.0)] {
            let h = (to - from) / 3.0;
            let samples: Vec<Point> = (0..4).map(|i| curve.eval(from + i as f64 * h)).collect();
            let third = |a: usize| {
                samples[3][a] - 3.0 * samples[2][a] + 3.0 * samples[1][a] - samples[0][a]
            };
            let h2 = h / 2.0;
            let half: Vec<Point> = (0..4).map(|i| curve.eval(from + i as f64 * h2)).collect();
            let third_half =
                |a: usize| half[3][a] - 3.0 * half[2][a] + 3.0 * half[1][a] - half[0][a];
            for a in 0..2 {
                assert!(
                    (third(a) - 8.0 * third_half(a)).abs() < 1e-6,
                    "not one cubic on [{from}, {to}]"
                );
            }
        }
    }

    #[test]
    fn repeated_and_non_finite_points_are_rejected() {
        assert_eq!(
            ParametricSpline::fit(&[[0.0, 0.0], [0.0, 0.0], [1.0, 1.0]]).unwrap_err(),
            SplineError::RepeatedPoint(0, 1)
        );
        assert_eq!(
            ParametricSpline::fit(&[[0.0, 0.0], [f64::NAN, 1.0]]).unwrap_err(),
            SplineError::NonFinite(1)
        );
        assert_eq!(
            ParametricSpline::fit(&[[0.0, 0.0]]).unwrap_err(),
            SplineError::TooFewPoints(1)
        );
    }

    #[test]
    fn lengths_are_measured_as_the_pipeline_measures_them() {
        // A WOGAN road of five 15 m steps: sqrt(dx² + dy²) sums to exactly 75 (as shapely's
        // length does, so the pipeline samples 75 intervals, 76 points), where hypot sums to
        // 74.99999999999999.
        let points = [
            [100.0, 10.0],
            [100.0, 25.0],
            [107.78367620599062, 37.82241727289731],
            [114.76011678809492, 51.101320721765674],
            [113.16958939972879, 66.01675643872873],
            [113.30957956732293, 81.01610318293653],
        ];
        assert_eq!(polyline_length(&points), 75.0);
        assert_eq!(interpolate(&points).unwrap().len(), 76);
    }

    #[test]
    fn sample_count_follows_numpy_arange() {
        // A 21 m straight road: n = 21, and arange(0, 1 + 1/21, 1/21) has 23 elements.
        let points = [[100.0, 10.0], [100.0, 31.0]];
        assert_eq!(interpolate(&points).unwrap().len(), 23);
        let points = [[100.0, 10.0], [100.0, 30.0]];
        assert_eq!(interpolate(&points).unwrap().len(), 21);
    }
}
