//! Why an OOB cannot be processed or a set of OOBs cannot be summarised.

use crate::road::spline::SplineError;
use crate::road::Point;

/// Why an OOB cannot be processed or a set of OOBs cannot be summarised.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OobError {
    /// The cubic spline needs at least 4 road points (scipy: `m > k must hold`).
    #[error("the spline needs at least 4 road points, got {0}")]
    TooFewRoadPoints(usize),
    /// The road points span less than 1 m, so there are no sampling intervals (the pipeline
    /// divides by zero).
    #[error("the road points span {0} m, less than one sampling interval of 1 m")]
    RoadTooShort(f64),
    /// The spline cannot be fitted (scipy: `Invalid inputs.`), or the road is too long to sample.
    #[error(transparent)]
    Spline(#[from] SplineError),
    /// No resampled point lies within 0.5 m of the road point nearest the OOB, so the pipeline
    /// has no place to split the road (it then fails on `None`).
    #[error("no resampled road point within 0.5 m of {0:?}, the road point nearest the OOB")]
    NoPointNearOob(Point),
    /// A part of the segment would hold one point, a line shapely refuses (a first step of 30 m
    /// or more).
    #[error("the segment's first step from {0:?} is 30 m or more")]
    OnePointSegment(Point),
    /// A segment of fewer than two points has no steps to compare (the pipeline asserts).
    #[error("a segment needs at least 2 points to be compared, got {0}")]
    SegmentTooShort(usize),
    /// The computation was stopped (Ctrl-C) before it ended.
    #[error("stopped before it ended")]
    Stopped,
    /// The distance between two entries failed, which fails the whole sparseness.
    #[error("distance between the OOBs of tests {first} and {second}: {source}")]
    Pair {
        /// Test id of the earlier entry.
        first: u64,
        /// Test id of the later entry.
        second: u64,
        /// Why.
        source: Box<OobError>,
    },
}
