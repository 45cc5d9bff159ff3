//! Sparseness of a set of OOBs and the pipeline's summary line.
//!
//! For each pair of entries in order (Python's `combinations`), the distance between their
//! segments is folded into a maximum kept under the *first* entry's test id; the last entry thus
//! has no maximum of its own, and two entries with one id share one. Sparseness is the mean and
//! the population standard deviation of those maxima, computed as numpy computes them (pairwise
//! summation) so that the printed figures round the same way.
//!
//! That is quadratic in the entries: [`sparseness`] measures every pair, as the pipeline does
//! (what `wogan export` writes); [`bounded_sparseness`] does so for up to [`EXACT_UP_TO`]
//! entries and above measures a seeded sample of that many, so that a report of a run of
//! 100,000 lane exits ends in seconds.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;

use super::edit_distance::{angle_lengths, steps_distances, LANES};
use super::entry::{OobEntry, OobSummary};
use super::error::OobError;

/// Header of the pipeline's `create_summary` CSV.
pub const SUMMARY_HEADER: &str = "total_oob,left_oob,right_oob,avg_sparseness,stdev_sparseness";

/// Up to this many entries [`bounded_sparseness`] measures every pair (the pipeline's figure);
/// above, a seeded sample of this many: at most 499,500 segment distances (the cost is theirs).
pub const EXACT_UP_TO: usize = 1_000;

/// The per-test maximum distances and their mean and standard deviation.
#[derive(Debug, Clone, PartialEq)]
pub struct Sparseness {
    /// `(test id, largest distance to a later entry)`, in order of first appearance.
    pub max_distances: Vec<(u64, f64)>,
    /// Mean of the maxima; NaN when there are none.
    pub mean: f64,
    /// Population standard deviation of the maxima; NaN when there are none.
    pub sd: f64,
    /// How many of the entries were measured, when a sample was (`None`: all of them).
    pub sample: Option<usize>,
}

/// The pipeline's sparseness of `entries`, every pair measured. An entry whose processing failed
/// has no segment, and the first pair it is part of fails the whole computation, as the
/// pipeline's assertion does.
pub fn sparseness(entries: &[OobEntry]) -> Result<Sparseness, OobError> {
    measured(entries, None)
}

/// The pipeline's sparseness of `entries` (as [`sparseness`]) when they are at most
/// [`EXACT_UP_TO`]; above, the pipeline's computation over [`EXACT_UP_TO`] of them drawn with
/// `seed` (uniformly, without repeats) and kept in their order, after all of them are checked
/// for the failure the pipeline would meet (which is the same whatever the sample). Ends early
/// with [`OobError::Stopped`] once `stop` is set.
pub fn bounded_sparseness(
    entries: &[OobEntry],
    seed: u64,
    stop: Option<&AtomicBool>,
) -> Result<Sparseness, OobError> {
    if entries.len() <= EXACT_UP_TO {
        return measured(entries, stop);
    }
    // The first failing pair needs no distance: it is the pipeline's whatever is drawn.
    let steps: Vec<Result<(), OobError>> = entries
        .iter()
        .map(|e| angle_lengths(&e.segment).map(|_| ()))
        .collect();
    first_failing_pair(entries, &steps)?;
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut drawn = rand::seq::index::sample(&mut rng, entries.len(), EXACT_UP_TO).into_vec();
    drawn.sort_unstable();
    let sample: Vec<OobEntry> = drawn.iter().map(|&i| entries[i].clone()).collect();
    let mut result = measured(&sample, stop)?;
    result.sample = Some(EXACT_UP_TO);
    Ok(result)
}

/// The error of the first pair (in the pipeline's order) one of whose entries has no steps;
/// `steps[i]` says whether entry `i` has.
fn first_failing_pair<T>(
    entries: &[OobEntry],
    steps: &[Result<T, OobError>],
) -> Result<(), OobError> {
    let Some(failed) = steps.iter().position(|s| s.is_err()) else {
        return Ok(());
    };
    // The pair (0, 1) when the first entry fails, else (0, failed): earlier pairs all succeed.
    let (first, second) = if failed == 0 { (0, 1) } else { (0, failed) };
    if second >= entries.len() {
        // A lone entry meets nobody.
        return Ok(());
    }
    let source = match &steps[failed] {
        Err(e) => e.clone(),
        Ok(_) => return Ok(()),
    };
    Err(OobError::Pair {
        first: entries[first].test_id,
        second: entries[second].test_id,
        source: Box::new(source),
    })
}

/// Every pair of `entries` measured, the rows (an entry against every later one) shared among
/// the machine's cores; the maxima folded in the pipeline's order, so the figures are the ones a
/// single loop over the pairs gives.
fn measured(entries: &[OobEntry], stop: Option<&AtomicBool>) -> Result<Sparseness, OobError> {
    // Each segment's steps once; a segment that has none fails the first pair it is in.
    let steps: Vec<Result<Vec<(f64, f64)>, OobError>> =
        entries.iter().map(|e| angle_lengths(&e.segment)).collect();
    first_failing_pair(entries, &steps)?;
    let steps: Vec<&[(f64, f64)]> = steps
        .iter()
        .map(|s| s.as_deref().unwrap_or_default())
        .collect();
    let rows = entries.len().saturating_sub(1);
    let stopped = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
    // Each row's largest distance to a later entry, rows taken one at a time by whichever thread
    // is free (the first rows are the longest).
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(rows.max(1));
    let row_max_of = |i: usize| {
        // The later entries, LANES tables at a time (the last chunk padded, its padding unread).
        let later = &steps[i + 1..];
        let mut distances = Vec::with_capacity(later.len());
        for chunk in later.chunks(LANES) {
            let ts = std::array::from_fn(|k| chunk.get(k).unwrap_or(&chunk[0]));
            let found = steps_distances(steps[i], ts.map(|t: &&[(f64, f64)]| *t));
            distances.extend_from_slice(&found[..chunk.len()]);
        }
        let mut distances = distances.into_iter();
        let first = distances.next().unwrap_or(f64::NAN);
        // Python's max(old, new) keeps the old value unless the new one is larger.
        distances.fold(
            first,
            |best, distance| if distance > best { distance } else { best },
        )
    };
    let work = || {
        let mut found = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= rows || stopped() {
                return found;
            }
            found.push((i, row_max_of(i)));
        }
    };
    let mut row_max = vec![f64::NAN; rows];
    let parts: Vec<Vec<(usize, f64)>> = if threads <= 1 || rows < 64 {
        vec![work()]
    } else {
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads).map(|_| scope.spawn(work)).collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_default())
                .collect()
        })
    };
    let mut done = 0;
    for (i, best) in parts.into_iter().flatten() {
        row_max[i] = best;
        done += 1;
    }
    if done < rows {
        return Err(OobError::Stopped);
    }
    let mut max_distances: Vec<(u64, f64)> = Vec::new();
    let mut slot_of: HashMap<u64, usize> = HashMap::new();
    for (entry, &best) in entries.iter().zip(&row_max) {
        match slot_of.get(&entry.test_id) {
            Some(&slot) => {
                if best > max_distances[slot].1 {
                    max_distances[slot].1 = best;
                }
            }
            None => {
                slot_of.insert(entry.test_id, max_distances.len());
                max_distances.push((entry.test_id, best));
            }
        }
    }
    let maxima: Vec<f64> = max_distances.iter().map(|&(_, d)| d).collect();
    let (mean, sd) = numpy_mean_sd(&maxima);
    Ok(Sparseness {
        max_distances,
        mean,
        sd,
        sample: None,
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
    fn bounded_sparseness_is_the_pipelines_up_to_its_bound_and_a_seeded_sample_above() {
        // Segments of 2 to 6 points along different bends: distances of every size.
        let segment = |i: usize| -> Vec<[f64; 2]> {
            (0..2 + i % 5)
                .map(|k| {
                    let k = k as f64;
                    [k, (i % 7) as f64 * 0.3 * k * k]
                })
                .collect()
        };
        let few: Vec<OobEntry> = (0..200).map(|i| entry(i as u64, segment(i))).collect();
        assert_eq!(
            bounded_sparseness(&few, 7, None).unwrap(),
            sparseness(&few).unwrap()
        );
        let many: Vec<OobEntry> = (0..EXACT_UP_TO + 50)
            .map(|i| entry(i as u64, segment(i)))
            .collect();
        let sampled = bounded_sparseness(&many, 7, None).unwrap();
        assert_eq!(sampled.sample, Some(EXACT_UP_TO));
        assert_eq!(sampled.max_distances.len(), EXACT_UP_TO - 1);
        assert_eq!(bounded_sparseness(&many, 7, None).unwrap(), sampled);
        assert_ne!(
            bounded_sparseness(&many, 8, None).unwrap().max_distances,
            sampled.max_distances
        );
        // A stop asked for ends it, whatever its size.
        let stop = AtomicBool::new(true);
        assert_eq!(
            bounded_sparseness(&many, 7, Some(&stop)),
            Err(OobError::Stopped)
        );
        assert_eq!(
            bounded_sparseness(&few, 7, Some(&stop)),
            Err(OobError::Stopped)
        );
        // The failure the pipeline meets is met whatever the sample: the first failed entry's.
        let mut failing = many.clone();
        failing[EXACT_UP_TO + 10].segment.clear();
        assert_eq!(
            bounded_sparseness(&failing, 7, None),
            Err(OobError::Pair {
                first: 0,
                second: (EXACT_UP_TO + 10) as u64,
                source: Box::new(OobError::SegmentTooShort(0))
            })
        );
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
            sparseness_sample: None,
        };
        assert_eq!(
            summary_csv(&summary),
            format!("{SUMMARY_HEADER}\n13,3,10,28.599,  6")
        );
    }
}
