//! Which side of the road an OOB is on, and the stretch of road around it that the analysis
//! compares.
//!
//! The pipeline calls an OOB "LEFT" when it lies less than 2 m from the centre line, which is
//! a guess from the car driving in the right lane: a car leaving by the left edge, more than
//! 2 m beyond the centre, is "RIGHT" too.
//!
//! The interesting segment is built around the point `np` of the resampled line nearest to the
//! OOB. The pipeline looks for the *last* resampled point less than 0.5 m from `np` and splits
//! the line there: before = the samples up to it, excluded, then `np`; after = the samples from
//! it, included. Samples are a little over a metre apart (the spline's length over `int` of the
//! polyline's), so when `np` falls mid-step no sample matches and the pipeline fails on that OOB.
//! It then keeps the points within 30 m walked from `np` backwards and from the matched sample
//! forwards. So `np` and that sample both appear, adjacent, in that order even when the sample
//! lies before `np` (a step back along the road), and they are the same point when `np` is a
//! sample (a step of length zero).

use super::error::OobError;
use super::geometry;
use super::resample::resample;
use crate::road::Point;

/// The side of the road the pipeline assigns an OOB.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum SbstSide {
    /// Less than 2 m from the centre line.
    Left,
    /// 2 m or more from the centre line.
    Right,
}
/// An OOB closer than this to the centre line is on the left, metres.
pub const LEFT_BELOW_M: f64 = 2.0;
/// A resampled point closer than this to the nearest point splits the line there, metres.
pub const MATCH_RADIUS_M: f64 = 0.5;
/// Distance walked from the OOB in each direction, metres (the analyser's 30 m before and after).
pub const REACH_M: f64 = 30.0;

/// The pipeline's side of an OOB at `oob` on the road through `road_points`; `None` when the
/// road cannot be resampled (fewer than 4 points, shorter than 1 m, repeated points).
pub fn sbst_side(road_points: &[Point], oob: Point) -> Option<SbstSide> {
    resample(road_points).ok().map(|line| side_of(&line, oob))
}

/// The side of an OOB at `oob` next to the resampled centre line `line`.
pub fn side_of(line: &[Point], oob: Point) -> SbstSide {
    if geometry::distance_to_line(oob, line) < LEFT_BELOW_M {
        SbstSide::Left
    } else {
        SbstSide::Right
    }
}

/// The pipeline's interesting segment of an OOB at `oob` on the road through `road_points`.
pub fn interesting_segment(road_points: &[Point], oob: Point) -> Result<Vec<Point>, OobError> {
    segment_of(&resample(road_points)?, oob)
}

/// The interesting segment of an OOB at `oob` next to the resampled centre line `line`.
pub fn segment_of(line: &[Point], oob: Point) -> Result<Vec<Point>, OobError> {
    let nearest = geometry::nearest_on_line(oob, line);
    // Every match overwrites the split in the pipeline, so the last one counts.
    let split = line
        .iter()
        .rposition(|&p| geometry::distance(p, nearest) < MATCH_RADIUS_M)
        .ok_or(OobError::NoPointNearOob(nearest))?;
    let before_from_oob = std::iter::once(nearest).chain(line[..split].iter().rev().copied());
    let mut before = walk(before_from_oob)?;
    before.reverse();
    let after = walk(line[split..].iter().copied())?;
    before.extend(after);
    Ok(before)
}

/// The points of `path` from its first while the distance walked stays under [`REACH_M`] (the
/// point that reaches it is left out). A path of one point gives none.
fn walk(mut path: impl Iterator<Item = Point>) -> Result<Vec<Point>, OobError> {
    let Some(mut previous) = path.next() else {
        return Ok(Vec::new());
    };
    let mut kept = Vec::new();
    let mut walked = 0.0;
    for point in path {
        if kept.is_empty() {
            kept.push(previous);
        }
        walked += geometry::distance(point, previous);
        if walked >= REACH_M {
            break;
        }
        kept.push(point);
        previous = point;
    }
    // shapely refuses a line of one point; that happens when the first step is 30 m or more.
    if kept.len() == 1 {
        return Err(OobError::OnePointSegment(kept[0]));
    }
    Ok(kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The resampled line of the straight road x = 50 from y = 10 to y = 70: a point a metre.
    fn straight() -> Vec<Point> {
        (0..=60).map(|i| [50.0, 10.0 + i as f64]).collect()
    }

    #[test]
    fn two_metres_from_the_centre_is_right() {
        let line = straight();
        assert_eq!(side_of(&line, [52.0, 30.0]), SbstSide::Right);
        assert_eq!(side_of(&line, [48.0, 40.4]), SbstSide::Right);
        assert_eq!(side_of(&line, [51.9999, 45.3]), SbstSide::Left);
        // Far to the left of the road counts as right.
        assert_eq!(side_of(&line, [47.0, 45.0]), SbstSide::Right);
    }

    #[test]
    fn a_nearest_point_on_a_sample_is_repeated() {
        let segment = segment_of(&straight(), [52.0, 30.0]).unwrap();
        // Back to the start (20 m), the nearest point, then 29 m ahead from the same sample (the
        // step that reaches 30 m is left out).
        assert_eq!(segment.len(), 20 + 1 + 30);
        assert_eq!(segment[0], [50.0, 10.0]);
        assert_eq!(segment[19], [50.0, 29.0]);
        assert_eq!(segment[20], [50.0, 30.0]);
        assert_eq!(segment[21], [50.0, 30.0]);
        assert_eq!(*segment.last().unwrap(), [50.0, 59.0]);
    }

    #[test]
    fn a_nearest_point_just_past_a_sample_steps_back_to_it() {
        let segment = segment_of(&straight(), [48.0, 40.4]).unwrap();
        let np = segment.iter().position(|p| *p == [50.0, 40.4]).unwrap();
        assert_eq!(segment[np - 1], [50.0, 39.0]);
        assert_eq!(segment[np + 1], [50.0, 40.0]);
    }

    #[test]
    fn at_the_ends_one_side_is_empty() {
        let before_start = segment_of(&straight(), [50.0, 5.0]).unwrap();
        assert_eq!(before_start.first(), Some(&[50.0, 10.0]));
        assert_eq!(before_start.len(), 30);
        let past_end = segment_of(&straight(), [50.0, 80.0]).unwrap();
        assert_eq!(past_end.last(), Some(&[50.0, 70.0]));
        assert_eq!(past_end.len(), 30);
    }

    #[test]
    fn a_nearest_point_half_a_metre_from_both_samples_matches_none() {
        assert_eq!(
            segment_of(&straight(), [48.0, 40.5]),
            Err(OobError::NoPointNearOob([50.0, 40.5]))
        );
    }

    #[test]
    fn a_first_step_of_30_m_leaves_one_point() {
        let line = [[0.0, 0.0], [0.0, 40.0], [0.0, 41.0]];
        assert_eq!(
            segment_of(&line, [1.0, 40.0]),
            Err(OobError::OnePointSegment([0.0, 40.0]))
        );
    }

    #[test]
    fn three_road_points_have_no_side() {
        assert_eq!(
            sbst_side(&[[0.0, 0.0], [0.0, 50.0], [30.0, 80.0]], [1.0, 1.0]),
            None
        );
    }
}
