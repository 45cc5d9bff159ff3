//! The road as the OOB analysis sees it: the road points through FITPACK's cubic spline
//! (`splprep(s=0, k=3)`), sampled at `int(length)` equal parameter steps, 4 decimals.
//!
//! This is not the validator's interpolation ([`crate::road::spline::interpolate`]): no minimum
//! of 20 intervals, 4 decimals instead of 3, and the degree is always 3, so three points fail.
//!
//! One known difference: at `u = 0` FITPACK answers its first B-spline coefficient, the first
//! road point plus its solver's rounding noise, where we answer the point itself. When that
//! point lies exactly on a rounding tie (`x * 1e4` ends in `.5`, e.g. 93.50205) the noise decides
//! the pipeline's rounding; this happened for the first sample of 8 of 2834 reference roads.

use super::error::OobError;
use super::geometry;
use crate::road::spline::{sample_evenly, ParametricSpline, SplineError, MAX_LENGTH_M};
use crate::road::Point;

/// Decimals the resampled coordinates are rounded to (numpy's way).
pub const DECIMALS: i32 = 4;
/// Fewest road points a cubic `splprep` accepts (it needs more points than the degree).
pub const MIN_ROAD_POINTS: usize = 4;

/// The resampled centre line of a road given by its control points.
///
/// Fails where the pipeline raises: fewer than 4 points (`m > k must hold`), repeated
/// consecutive or non-finite points (`Invalid inputs.`), and a polyline shorter than 1 m (it
/// samples `int(length)` intervals and divides by that). Roads longer than
/// [`MAX_LENGTH_M`] are refused too, to bound the work; the pipeline would sample them.
pub fn resample(road_points: &[Point]) -> Result<Vec<Point>, OobError> {
    if road_points.len() < MIN_ROAD_POINTS {
        return Err(OobError::TooFewRoadPoints(road_points.len()));
    }
    let curve = ParametricSpline::fit(road_points)?;
    let length_m = geometry::length(road_points);
    // Python's int() truncates towards zero, as `as usize` does for a non-negative length.
    let intervals = length_m as usize;
    if intervals == 0 {
        return Err(OobError::RoadTooShort(length_m));
    }
    if length_m > MAX_LENGTH_M {
        return Err(SplineError::TooLong(length_m).into());
    }
    Ok(sample_evenly(&curve, intervals, DECIMALS))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_21_m_road_gets_the_extra_sample_of_numpy_arange() {
        let road = [[100.0, 10.0], [100.0, 17.0], [100.0, 24.0], [100.0, 31.0]];
        let line = resample(&road).unwrap();
        assert_eq!(line.len(), 23);
        assert_eq!(line[21], [100.0, 31.0]);
        // Extrapolated one step past the end.
        assert_eq!(line[22], [100.0, 32.0]);
    }

    #[test]
    fn roads_the_pipeline_cannot_resample_are_refused() {
        let three = [[0.0, 0.0], [10.0, 0.0], [20.0, 5.0]];
        assert_eq!(resample(&three), Err(OobError::TooFewRoadPoints(3)));
        let tiny = [[20.0, 20.0], [20.2, 20.0], [20.4, 20.1], [20.5, 20.3]];
        assert!(matches!(resample(&tiny), Err(OobError::RoadTooShort(l)) if l < 1.0));
        let repeated = [[0.0, 0.0], [10.0, 0.0], [10.0, 0.0], [20.0, 5.0]];
        assert_eq!(
            resample(&repeated),
            Err(OobError::Spline(SplineError::RepeatedPoint(1, 2)))
        );
    }
}
