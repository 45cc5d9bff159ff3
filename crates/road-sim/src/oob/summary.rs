//! What the pipeline's `OOBAnalyzer` makes of a set of tests: which count as OOBs, the entry of
//! each, and the summary (`total_oob,left_oob,right_oob,avg_sparseness,stdev_sparseness`) of a set
//! of them.

use super::entry::{OobEntry, OobSummary, SbstTest};
use super::error::OobError;
use super::resample::resample;
use super::segment::{self, SbstSide};
use super::sparseness::{bounded_sparseness, sparseness, Sparseness};
use std::sync::atomic::AtomicBool;

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
    summary_of(entries, sparseness(entries)?)
}

/// [`summarise`] with its work bounded: the sides of every entry, the sparseness of at most
/// [`EXACT_UP_TO`](super::sparseness::EXACT_UP_TO) of them ([`bounded_sparseness`], a sample
/// drawn with `seed` above that); stopped early once `stop` is set.
pub fn summarise_bounded(
    entries: &[OobEntry],
    seed: u64,
    stop: Option<&AtomicBool>,
) -> Result<OobSummary, OobError> {
    summary_of(entries, bounded_sparseness(entries, seed, stop)?)
}

/// The summary of `entries` whose sparseness is `sparseness`.
fn summary_of(entries: &[OobEntry], sparseness: Sparseness) -> Result<OobSummary, OobError> {
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
        sparseness_sample: sparseness.sample,
    })
}

/// The pipeline's summary of a result directory's tests, given in its order.
pub fn summarise_tests(tests: &[SbstTest]) -> Result<OobSummary, OobError> {
    summarise(&entries(tests))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::oob::{sparseness, summary_csv};
    use crate::road::Point;

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
            summarise_tests(&tests),
            Err(OobError::Pair {
                first: 5,
                second: 6,
                ..
            })
        ));
        // Alone, it is one OOB on the right with no sparseness.
        let alone = summarise_tests(&tests[5..]).unwrap();
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
