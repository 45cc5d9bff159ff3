//! Sparseness of a set of OOBs and the pipeline's summary line.
//!
//! For each pair of entries in order (Python's `combinations`), the distance between their
//! segments is folded into a maximum kept under the *first* entry's test id; the last entry thus
//! has no maximum of its own, and two entries with one id share one. Sparseness is the mean and
//! the population standard deviation of those maxima, computed as numpy computes them (pairwise
//! summation) so that the printed figures round the same way.

use std::collections::HashMap;

use super::edit_distance::{angle_lengths, steps_distance};
use super::entry::{OobEntry, OobSummary};
use super::error::OobError;

/// Header of the pipeline's `create_summary` CSV.
pub const SUMMARY_HEADER: &str = "total_oob,left_oob,right_oob,avg_sparseness,stdev_sparseness";

/// The per-test maximum distances and their mean and standard deviation.
#[derive(Debug, Clone, PartialEq)]
pub struct Sparseness {
    /// `(test id, largest distance to a later entry)`, in order of first appearance.
    pub max_distances: Vec<(u64, f64)>,
    /// Mean of the maxima; NaN when there are none.
    pub mean: f64,
    /// Population standard deviation of the maxima; NaN when there are none.
    pub sd: f64,
}

/// The pipeline's sparseness of `entries`. An entry whose processing failed has no segment, and
/// the first pair it is part of fails the whole computation, as the pipeline's assertion does.
pub fn sparseness(entries: &[OobEntry]) -> Result<Sparseness, OobError> {
    let mut max_distances: Vec<(u64, f64)> = Vec::new();
    let mut slot_of: HashMap<u64, usize> = HashMap::new();
    // Each segment's steps once; a segment that has none fails the first pair it is in.
    let steps: Vec<Result<Vec<(f64, f64)>, OobError>> =
        entries.iter().map(|e| angle_lengths(&e.segment)).collect();
    for (i, first) in entries.iter().enumerate() {
        for (j, second) in entries.iter().enumerate().skip(i + 1) {
            let distance = match (&steps[i], &steps[j]) {
                (Ok(s), Ok(t)) => steps_distance(s, t),
                (Err(e), _) | (_, Err(e)) => {
                    return Err(OobError::Pair {
                        first: first.test_id,
                        second: second.test_id,
                        source: Box::new(e.clone()),
                    })
                }
            };
            match slot_of.get(&first.test_id) {
                // Python's max(old, new) keeps the old value unless the new one is larger.
                Some(&slot) => {
                    if distance > max_distances[slot].1 {
                        max_distances[slot].1 = distance;
                    }
                }
                None => {
                    slot_of.insert(first.test_id, max_distances.len());
                    max_distances.push((first.test_id, distance));
                }
            }
        }
    }
    let maxima: Vec<f64> = max_distances.iter().map(|&(_, d)| d).collect();
    let (mean, sd) = numpy_mean_sd(&maxima);
    Ok(Sparseness {
        max_distances,
        mean,
        sd,
    })
}

/// numpy's `mean` and `std` (population) of `values`; NaN for both when empty.
pub fn numpy_mean_sd(values: &[f64]) -> (f64, f64) {
    if values.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let n = values.len() as f64;
    let mean = pairwise_sum(values) / n;
    let squares: Vec<f64> = values
        .iter()
        .map(|v| {
            let d = v - mean;
            d * d
        })
        .collect();
    (mean, (pairwise_sum(&squares) / n).sqrt())
}

/// numpy's float summation of a contiguous array: blocks of up to 128 values summed with eight
/// interleaved accumulators, larger arrays split in two (at a multiple of 8) and summed apart.
fn pairwise_sum(values: &[f64]) -> f64 {
    let n = values.len();
    if n < 8 {
        return values.iter().fold(0.0, |acc, v| acc + v);
    }
    if n <= 128 {
        let mut acc = [0.0; 8];
        acc.copy_from_slice(&values[..8]);
        let whole = n - n % 8;
        for block in values[8..whole].chunks_exact(8) {
            for (a, v) in acc.iter_mut().zip(block) {
                *a += v;
            }
        }
        let mut sum =
            ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
        for v in &values[whole..] {
            sum += v;
        }
        return sum;
    }
    let half = n / 2;
    let half = half - half % 8;
    pairwise_sum(&values[..half]) + pairwise_sum(&values[half..])
}

/// The `create_summary` CSV: the header, then `"%d,%d,%d,%.3f,%3.f"` of the totals and the
/// sparseness (so the SD is printed as a whole number, at least 3 wide).
pub fn summary_csv(summary: &OobSummary) -> String {
    format!(
        "{SUMMARY_HEADER}\n{},{},{},{},{}",
        summary.total,
        summary.left,
        summary.right,
        percent_f(summary.sparseness_mean, 0, 3),
        percent_f(summary.sparseness_sd, 3, 0),
    )
}

/// Python's `"%{width}.{precision}f" % value`: correctly rounded (ties to even on the exact
/// binary value, as Rust's formatting rounds), right-aligned, and NaN written `nan`.
pub fn percent_f(value: f64, width: usize, precision: usize) -> String {
    if value.is_nan() {
        format!("{:>width$}", "nan")
    } else {
        format!("{value:>width$.precision$}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::oob::OobSummary;

    fn entry(test_id: u64, segment: Vec<[f64; 2]>) -> OobEntry {
        OobEntry {
            test_id,
            oob_point: Some([0.0, 0.0]),
            side: Some(crate::oob::SbstSide::Right),
            segment,
            failure: None,
        }
    }

    #[test]
    fn maxima_are_kept_under_the_first_entrys_id() {
        let a = entry(1, vec![[0.0, 0.0], [1.0, 0.0]]);
        let b = entry(2, vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]);
        let c = entry(1, vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
        let s = sparseness(&[a, b, c]).unwrap();
        // Pairs (1,2): 2, (1,1): 1, (2,1): 1; both id-1 pairs fold into one maximum.
        assert_eq!(s.max_distances, vec![(1, 2.0), (2, 1.0)]);
        assert_eq!((s.mean, s.sd), (1.5, 0.5));
    }

    #[test]
    fn a_failed_entry_fails_the_first_pair_it_is_in() {
        let good = entry(1, vec![[0.0, 0.0], [1.0, 0.0]]);
        let mut failed = entry(2, Vec::new());
        failed.side = None;
        assert_eq!(
            sparseness(&[good.clone(), failed.clone()]),
            Err(OobError::Pair {
                first: 1,
                second: 2,
                source: Box::new(OobError::SegmentTooShort(0))
            })
        );
        // Alone it meets nobody.
        let alone = sparseness(&[failed]).unwrap();
        assert!(alone.max_distances.is_empty() && alone.mean.is_nan() && alone.sd.is_nan());
    }

    #[test]
    fn pairwise_sum_blocks_like_numpy() {
        let values: Vec<f64> = (0..300).map(|i| 0.1 * i as f64).collect();
        let naive: f64 = values.iter().sum();
        assert!((pairwise_sum(&values) - naive).abs() < 1e-9);
        assert_eq!(pairwise_sum(&[]), 0.0);
        assert_eq!(numpy_mean_sd(&[2.0, 4.0]), (3.0, 1.0));
    }

    #[test]
    fn python_percent_formatting() {
        assert_eq!(percent_f(f64::NAN, 3, 0), "nan");
        assert_eq!(percent_f(f64::NAN, 0, 3), "nan");
        assert_eq!(percent_f(2.5, 3, 0), "  2");
        assert_eq!(percent_f(3.5, 3, 0), "  4");
        assert_eq!(percent_f(1234.5, 3, 0), "1234");
        assert_eq!(percent_f(0.125, 0, 2), "0.12");
        assert_eq!(percent_f(28.5986, 0, 3), "28.599");
        let summary = OobSummary {
            total: 13,
            left: 3,
            right: 10,
            sparseness_mean: 28.5986,
            sparseness_sd: 6.5,
        };
        assert_eq!(
            summary_csv(&summary),
            format!("{SUMMARY_HEADER}\n13,3,10,28.599,  6")
        );
    }
}
