//! What the analysis reads and makes: a test as its result file holds it, the OOB entry made of
//! it, and the summary of a result directory.

use serde::{Deserialize, Serialize};

use super::error::OobError;
use super::segment::SbstSide;
use crate::road::Point;

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
    /// How many entries the sparseness was measured on when a sample was
    /// ([`crate::oob::bounded_sparseness`]); `None` when every pair was measured.
    pub sparseness_sample: Option<usize>,
}
