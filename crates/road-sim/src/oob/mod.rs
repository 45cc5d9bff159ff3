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
//! - [`mod@sparseness`]: per-test maximum distances, their mean and SD, and the summary CSV;
//! - [`summary`]: what the pipeline's `OOBAnalyzer` does with them: which tests count and their
//!   summary. (In wogan "analyzer" is WOGAN's network; the pipeline's class keeps its name.)
//!
//! Which tests count ([`entries`]): valid tests whose `test_outcome` is exactly `"FAIL"`. Their
//! road is resampled first; if that fails the test counts as an OOB with no side and no segment
//! even when it has no `is_oob` record. Otherwise a test without an `is_oob` record is skipped,
//! and one whose segment cannot be built counts with no side and no segment. No side counts as
//! right; no segment fails the sparseness of any set of two or more OOBs ([`OobError::Pair`]).

pub mod edit_distance;
mod entry;
mod error;
pub mod geometry;
pub mod resample;
pub mod segment;
pub mod sparseness;
pub mod summary;

#[cfg(test)]
mod reference;

pub use edit_distance::segment_distance;
pub use entry::{OobEntry, OobSummary, SbstTest};
pub use error::OobError;
pub use resample::resample;
pub use segment::{interesting_segment, sbst_side, SbstSide};
pub use sparseness::{bounded_sparseness, sparseness, summary_csv, Sparseness};
pub use summary::{entries, entry_of, summarise, summarise_bounded, summarise_tests};
