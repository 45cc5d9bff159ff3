//! Diversity of a test suite as the WOGAN paper measures it: the median Euclidean distance over
//! pairs of feature vectors (for roads, the segments' directions the authors' code computes).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use serde::Serialize;

/// Up to this many vectors every pair is measured; beyond, [`SAMPLED_PAIRS`] random pairs.
pub const EXACT_UP_TO: usize = 2_000;
/// Pairs drawn when there are too many vectors for all pairs.
pub const SAMPLED_PAIRS: usize = 1_000_000;

/// A diversity figure and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Diversity {
    /// Median pairwise distance; `None` with fewer than two vectors.
    pub median_distance: Option<f64>,
    /// `"all"` when every pair was measured, `"sampled"` when random pairs were.
    pub pairs: &'static str,
}

/// The Euclidean distance of two feature vectors (of one length), the paper's distance of roads.
pub fn euclidean(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Median pairwise Euclidean distance of `vectors` (all of one length): exact for up to
/// [`EXACT_UP_TO`] vectors, else from [`SAMPLED_PAIRS`] distinct-index pairs drawn with `seed`.
pub fn median_pairwise_distance(vectors: &[Vec<f64>], seed: u64) -> Diversity {
    median_pairwise_distance_by(vectors, seed, euclidean)
}

/// [`median_pairwise_distance`] with another `distance` of two vectors (the same pairs).
pub fn median_pairwise_distance_by(
    vectors: &[Vec<f64>],
    seed: u64,
    distance: impl Fn(&[f64], &[f64]) -> f64,
) -> Diversity {
    let n = vectors.len();
    let (mut distances, pairs) = if n <= EXACT_UP_TO {
        let all = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .map(|(i, j)| distance(&vectors[i], &vectors[j]))
            .collect::<Vec<f64>>();
        (all, "all")
    } else {
        let mut rng = ChaCha20Rng::seed_from_u64(seed);
        let sampled = (0..SAMPLED_PAIRS)
            .map(|_| {
                let i = rng.random_range(0..n);
                let j = (i + rng.random_range(1..n)) % n;
                distance(&vectors[i], &vectors[j])
            })
            .collect::<Vec<f64>>();
        (sampled, "sampled")
    };
    if distances.is_empty() {
        return Diversity {
            median_distance: None,
            pairs,
        };
    }
    distances.sort_unstable_by(f64::total_cmp);
    let mid = distances.len() / 2;
    let median = if distances.len() % 2 == 1 {
        distances[mid]
    } else {
        (distances[mid - 1] + distances[mid]) / 2.0
    };
    Diversity {
        median_distance: Some(median),
        pairs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_three_points_on_a_line() {
        // Distances 1, 3, 2: median 2.
        let d = median_pairwise_distance(&[vec![0.0], vec![1.0], vec![3.0]], 0);
        assert_eq!(d.median_distance, Some(2.0));
        assert_eq!(d.pairs, "all");
        assert_eq!(
            median_pairwise_distance(&[vec![0.0]], 0).median_distance,
            None
        );
    }

    #[test]
    fn sampled_median_is_close_to_exact_and_seeded() {
        let vectors: Vec<Vec<f64>> = (0..2_500)
            .map(|i| vec![(i % 100) as f64, (i / 100) as f64])
            .collect();
        let sampled = median_pairwise_distance(&vectors, 7);
        assert_eq!(sampled.pairs, "sampled");
        // Another distance is taken over the same pairs: twice the distance, twice the median.
        let doubled = median_pairwise_distance_by(&vectors, 7, |a, b| 2.0 * euclidean(a, b));
        assert_eq!(
            doubled.median_distance,
            sampled.median_distance.map(|d| 2.0 * d)
        );
        assert_eq!(sampled, median_pairwise_distance(&vectors, 7));
        let exact = median_pairwise_distance(&vectors[..2_000], 7)
            .median_distance
            .unwrap();
        let estimate = sampled.median_distance.unwrap();
        // A 100 x 25 grid's median distance is close to that of its first 20 rows.
        assert!(
            (estimate - exact).abs() / exact < 0.25,
            "{estimate} vs {exact}"
        );
    }
}
