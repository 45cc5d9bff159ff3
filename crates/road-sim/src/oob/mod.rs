//! The SBST competition's analysis of out-of-bound episodes (OOBs): their sides, the road around
//! each and how much those stretches of road differ.
//!
//! The SBST 2022 tool competition summarised a generator's failed tests with its pipeline's
//! `OOBAnalyzer` (`code_pipeline/tests_evaluation.py` of se2p/tool-competition-av) as
//! `total_oob,left_oob,right_oob,avg_sparseness,stdev_sparseness`. This module gives the same
//! summary for tests in that pipeline's result layout, quirks included, so that a WOGAN run can
//! be scored the way the competition scored its entries. `tests/reference/sbst/oob_vectors.json`
//! holds the pipeline's own answers (made by `scripts/reference/sbst_oob_vectors.py`).
//!
//! - [`mod@resample`]: the road's control points through the cubic spline, a sample per metre;
//! - [`geometry`]: distances and nearest points as GEOS (shapely) computes them;
//! - [`segment`]: the side of an OOB and its interesting segment, 30 m each way;
//! - [`edit_distance`]: the weighted Levenshtein distance between two segments;
//! - [`mod@sparseness`]: per-test maximum distances, their mean and SD, and the summary CSV.
//!
//! Which tests count ([`entries`]): valid tests whose `test_outcome` is exactly `"FAIL"`. Their
//! road is resampled first; if that fails the test counts as an OOB with no side and no segment
//! even when it has no `is_oob` record. Otherwise a test without an `is_oob` record is skipped,
//! and one whose segment cannot be built counts with no side and no segment. No side counts as
//! right; no segment fails the sparseness of any set of two or more OOBs ([`OobError::Pair`]).

pub mod edit_distance;
pub mod geometry;
pub mod resample;
pub mod segment;
pub mod sparseness;

#[cfg(test)]
mod reference;

use serde::{Deserialize, Serialize};

use crate::road::spline::SplineError;
use crate::road::Point;

pub use edit_distance::segment_distance;
pub use resample::resample;
pub use segment::{interesting_segment, sbst_side};
pub use sparseness::{sparseness, summary_csv, Sparseness};

/// The side of the road the pipeline assigns an OOB.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum SbstSide {
    /// Less than 2 m from the centre line.
    Left,
    /// 2 m or more from the centre line.
    Right,
}

/// What the analysis reads of one test file (`test.NNNN.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SbstTest {
    /// The test's `id`; sparseness keys its maxima by it.
    pub id: u64,
    /// The test's `is_valid`.
    pub is_valid: bool,
    /// The test's `test_outcome` (`"PASS"`, `"FAIL"`, `"ERROR"`, `"INVALID"`).
    pub test_outcome: Option<String>,
    /// The road's control points (`road_points`), not the interpolated ones.
    pub road_points: Vec<Point>,
    /// Position of the first execution record with `is_oob` true, if any.
    pub oob_point: Option<Point>,
}

/// One OOB as the pipeline records it.
#[derive(Debug, Clone, PartialEq)]
pub struct OobEntry {
    /// The test's id.
    pub test_id: u64,
    /// Where the car left the lane; `None` when the processing failed.
    pub oob_point: Option<Point>,
    /// `None` when the processing failed (counted as right).
    pub side: Option<SbstSide>,
    /// The interesting segment; empty when the processing failed.
    pub segment: Vec<Point>,
    /// Why the processing failed (the pipeline swallows the reason).
    pub failure: Option<OobError>,
}

/// The pipeline's OOB summary of a result directory.
#[derive(Debug, Clone, PartialEq)]
pub struct OobSummary {
    /// OOB entries, failed ones included.
    pub total: usize,
    /// Entries on the left.
    pub left: usize,
    /// Entries on the right, failed ones included.
    pub right: usize,
    /// Mean of the per-test maximum distances; NaN with fewer than two entries.
    pub sparseness_mean: f64,
    /// Population SD of the per-test maximum distances; NaN with fewer than two entries.
    pub sparseness_sd: f64,
}

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

/// The entry the pipeline makes of one test, or `None` when it skips the test.
pub fn entry_of(test: &SbstTest) -> Option<OobEntry> {
    if !test.is_valid || test.test_outcome.as_deref() != Some("FAIL") {
        return None;
    }
    let failed = |failure: OobError| OobEntry {
        test_id: test.id,
        oob_point: None,
        side: None,
        segment: Vec::new(),
        failure: Some(failure),
    };
    // The road is resampled before the records are searched for an OOB.
    let line = match resample(&test.road_points) {
        Ok(line) => line,
        Err(e) => return Some(failed(e)),
    };
    let oob = test.oob_point?;
    Some(match segment::segment_of(&line, oob) {
        Ok(segment) => OobEntry {
            test_id: test.id,
            oob_point: Some(oob),
            side: Some(segment::side_of(&line, oob)),
            segment,
            failure: None,
        },
        Err(e) => failed(e),
    })
}

/// The pipeline's entries of `tests`, given in its order (the file paths sorted).
pub fn entries(tests: &[SbstTest]) -> Vec<OobEntry> {
    tests.iter().filter_map(entry_of).collect()
}

/// The pipeline's summary of `entries`: fails as the pipeline does when an entry without a
/// segment meets another.
pub fn summarise(entries: &[OobEntry]) -> Result<OobSummary, OobError> {
    let sparseness = sparseness(entries)?;
    let left = entries
        .iter()
        .filter(|e| e.side == Some(SbstSide::Left))
        .count();
    Ok(OobSummary {
        total: entries.len(),
        left,
        right: entries.len() - left,
        sparseness_mean: sparseness.mean,
        sparseness_sd: sparseness.sd,
    })
}

/// The pipeline's summary of a result directory's tests, given in its order.
pub fn analyse(tests: &[SbstTest]) -> Result<OobSummary, OobError> {
    summarise(&entries(tests))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test(id: u64, outcome: &str, road: &[Point], oob: Option<Point>) -> SbstTest {
        SbstTest {
            id,
            is_valid: true,
            test_outcome: Some(outcome.to_string()),
            road_points: road.to_vec(),
            oob_point: oob,
        }
    }

    const STRAIGHT: [Point; 4] = [[50.0, 10.0], [50.0, 30.0], [50.0, 50.0], [50.0, 70.0]];
    const THREE: [Point; 3] = [[100.0, 10.0], [100.0, 60.0], [130.0, 90.0]];

    #[test]
    fn only_failed_tests_with_an_oob_or_a_bad_road_count() {
        let mut invalid = test(4, "FAIL", &STRAIGHT, Some([52.0, 30.0]));
        invalid.is_valid = false;
        let tests = [
            test(1, "PASS", &STRAIGHT, None),
            test(2, "FAILED", &STRAIGHT, Some([52.0, 30.0])),
            test(3, "FAIL", &STRAIGHT, None),
            invalid,
            test(5, "FAIL", &STRAIGHT, Some([51.0, 30.0])),
            test(6, "FAIL", &THREE, None),
        ];
        let found = entries(&tests);
        assert_eq!(found.iter().map(|e| e.test_id).collect::<Vec<_>>(), [5, 6]);
        assert_eq!(found[0].side, Some(SbstSide::Left));
        assert_eq!(found[1].failure, Some(OobError::TooFewRoadPoints(3)));
        // The failed entry meets the good one.
        assert!(matches!(
            analyse(&tests),
            Err(OobError::Pair {
                first: 5,
                second: 6,
                ..
            })
        ));
        // Alone, it is one OOB on the right with no sparseness.
        let alone = analyse(&tests[5..]).unwrap();
        assert_eq!((alone.total, alone.left, alone.right), (1, 0, 1));
        assert_eq!(
            summary_csv(&alone),
            format!("{}\n1,0,1,nan,nan", sparseness::SUMMARY_HEADER)
        );
    }

    #[test]
    fn sides_serialise_as_the_pipeline_writes_them() {
        assert_eq!(serde_json::to_string(&SbstSide::Left).unwrap(), "\"LEFT\"");
        assert_eq!(
            serde_json::from_str::<SbstSide>("\"RIGHT\"").unwrap(),
            SbstSide::Right
        );
    }
}
