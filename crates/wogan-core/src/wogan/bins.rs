//! Bin-biased WGAN batches: the GAN learns mostly from tests with high fitness.
//!
//! Fitness `[0, 1]` is cut into `B` bins. Bin `k` (0 = lowest fitness) has centre
//! `x_k = (k + 0.5)/B − 0.5` and weight `1/(1 + exp(−(x_k − α)))`; α grows during the run.
//! (stgem bins the objective `1 − fitness`, so its bin `B − 1 − k` is this bin `k`, and its weight
//! `1 − σ(h + shift)` is this one with α = shift.)
//!
//! A batch is built as stgem's `do_train` builds it. First each of the newest tests gets a chance
//! on its own: it joins when its bin is *at most* a bin drawn by the weights. (stgem's comment
//! says the newest tests should join "if and only if they have low objective", i.e. high fitness;
//! its code compares the other way, so a newest test of low fitness joins more often. The code is
//! what WOGAN's published results come from, so this follows the code.) Then the rest of the batch
//! draws a bin per slot by the weights and takes a test uniformly from that bin's tests not yet
//! taken *by these draws*; an exhausted bin passes the draw to the next lower bin, wrapping round
//! to the top. A newest test that joined may so appear twice, as in stgem.

use rand::{Rng, RngExt};

/// Bin index of a fitness value (clamped to `[0, 1]`).
///
/// Computed as stgem bins its objective `1 − fitness`, so that a fitness on a bin's edge (0.9,
/// whose objective is 0.09999999999999998) lands where stgem puts it.
pub fn bin_of(fitness: f64, bins: usize) -> usize {
    let f = if fitness.is_nan() {
        0.0
    } else {
        fitness.clamp(0.0, 1.0)
    };
    let top = bins.saturating_sub(1);
    let objective = 1.0 - f;
    let stgem_bin = if objective < 1.0 {
        ((objective * bins as f64) as usize).min(top)
    } else {
        top
    };
    top - stgem_bin
}

/// Drawing weights of the bins for bias α.
pub fn bin_weights(bins: usize, alpha: f64) -> Vec<f64> {
    (0..bins)
        .map(|k| {
            let x = (k as f64 + 0.5) / bins as f64 - 0.5;
            1.0 / (1.0 + (-(x - alpha)).exp())
        })
        .collect()
}

/// Where a batch's random choices come from.
pub trait BatchDraws {
    /// A bin, with probabilities proportional to `weights`.
    fn bin(&mut self, weights: &[f64]) -> usize;
    /// A position in `0..len` (`len >= 1`), uniformly.
    fn position(&mut self, len: usize) -> usize;
}

/// Batch draws from a random number generator.
pub struct RngDraws<'a, R: Rng + ?Sized>(pub &'a mut R);

impl<R: Rng + ?Sized> BatchDraws for RngDraws<'_, R> {
    fn bin(&mut self, weights: &[f64]) -> usize {
        let total: f64 = weights.iter().sum();
        let mut u = self.0.random::<f64>() * total;
        for (k, w) in weights.iter().enumerate() {
            if u < *w {
                return k;
            }
            u -= w;
        }
        weights.len() - 1
    }

    fn position(&mut self, len: usize) -> usize {
        self.0.random_range(0..len)
    }
}

/// Indices of a training batch of `min(size, tests)` tests.
///
/// `members[k]` lists the test indices in bin `k` in the order they were added; `newest` the
/// newest tests' `(index, bin)`, newest first.
pub fn biased_batch(
    members: &[Vec<usize>],
    newest: &[(usize, usize)],
    size: usize,
    alpha: f64,
    draws: &mut dyn BatchDraws,
) -> Vec<usize> {
    let bins = members.len();
    let total: usize = members.iter().map(Vec::len).sum();
    let size = size.min(total);
    let weights = bin_weights(bins, alpha);
    let mut batch: Vec<usize> = Vec::with_capacity(size);
    for &(idx, bin) in newest {
        if batch.len() < size && bin <= draws.bin(&weights) {
            batch.push(idx);
        }
    }
    // Positions (ascending) within each bin already taken by the draws below.
    let mut taken: Vec<Vec<usize>> = vec![Vec::new(); bins];
    while batch.len() < size {
        let mut k = draws.bin(&weights);
        // At most `total` draws, so some bin still has an untaken test.
        while taken[k].len() >= members[k].len() {
            k = if k == 0 { bins - 1 } else { k - 1 };
        }
        // The `p`-th untaken test, counting in the bin's order.
        let mut position = draws.position(members[k].len() - taken[k].len());
        let mut slot = 0;
        while slot < taken[k].len() && taken[k][slot] <= position {
            position += 1;
            slot += 1;
        }
        taken[k].insert(slot, position);
        batch.push(members[k][position]);
    }
    batch
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha20Rng;

    #[test]
    fn bins_and_weights() {
        assert_eq!(bin_of(0.0, 10), 0);
        assert_eq!(bin_of(0.95, 10), 9);
        assert_eq!(bin_of(1.0, 10), 9);
        assert_eq!(bin_of(f64::NAN, 10), 0);
        let w = bin_weights(10, 0.0);
        assert!(w.windows(2).all(|p| p[1] > p[0]), "higher bins weigh more");
        assert!(
            (w[0] + w[9] - 1.0).abs() < 1e-12,
            "symmetric around 0 at α = 0"
        );
        let w3 = bin_weights(10, 3.0);
        assert!(w3[9] / w3[0] > w[9] / w[0], "the bias grows with α");
    }

    #[test]
    fn batch_size_and_wrap_round() {
        let mut rng = ChaCha20Rng::seed_from_u64(3);
        // Only bin 0 and bin 9 are populated: draws of the middle bins fall to bin 0, and
        // once bin 0 is used up they wrap round to bin 9.
        let mut members = vec![Vec::new(); 10];
        members[0] = vec![0, 1];
        members[9] = vec![2, 3, 4];
        for _ in 0..50 {
            let b = biased_batch(&members, &[], 32, 1.0, &mut RngDraws(&mut rng));
            assert_eq!(b.len(), 5, "never larger than the tests available");
            let mut s = b.clone();
            s.sort_unstable();
            assert_eq!(s, vec![0, 1, 2, 3, 4], "without replacement");
        }
        let b = biased_batch(&members, &[], 3, 0.0, &mut RngDraws(&mut rng));
        assert_eq!(b.len(), 3);
    }

    #[test]
    fn a_newest_test_joins_when_its_bin_is_at_most_the_drawn_one() {
        let mut rng = ChaCha20Rng::seed_from_u64(4);
        let mut members = vec![Vec::new(); 10];
        members[0] = vec![100];
        members[9] = (0..100).collect();
        let mut top_joined = 0;
        for _ in 0..200 {
            // The lowest bin is at most any draw: it always joins first.
            let b = biased_batch(&members, &[(100, 0)], 4, 0.0, &mut RngDraws(&mut rng));
            assert_eq!(b.len(), 4);
            assert_eq!(b[0], 100);
            // The top bin joins only when the top bin is drawn (weight 0.62 of 5 at α = 0).
            let b = biased_batch(&members, &[(99, 9)], 4, 0.0, &mut RngDraws(&mut rng));
            top_joined += usize::from(b[0] == 99 && b.len() == 4);
        }
        assert!(
            (10..50).contains(&top_joined),
            "top bin joined {top_joined} of 200"
        );
    }

    proptest::proptest! {
        #[test]
        fn batch_is_distinct_members_of_the_right_size(
            sizes in proptest::collection::vec(0usize..80, 10),
            size in 1usize..40,
            alpha in 0.0f64..3.0,
            seed in 0u64..1000,
        ) {
            let mut rng = ChaCha20Rng::seed_from_u64(seed);
            let mut members = Vec::new();
            let mut next = 0;
            for n in sizes {
                members.push((next..next + n).collect::<Vec<usize>>());
                next += n;
            }
            let newest: Vec<(usize, usize)> = members
                .iter()
                .enumerate()
                .rev()
                .filter_map(|(k, m)| m.last().map(|i| (*i, k)))
                .take(3)
                .collect();
            let b = biased_batch(&members, &newest, size, alpha, &mut RngDraws(&mut rng));
            proptest::prop_assert_eq!(b.len(), size.min(next));
            proptest::prop_assert!(b.iter().all(|i| *i < next));
            // After the newest tests that joined, the draws take each test at most once.
            let mut joined = 0;
            for (n, _) in &newest {
                if b.get(joined) == Some(n) {
                    joined += 1;
                }
            }
            let mut s = b[joined..].to_vec();
            s.sort_unstable();
            s.dedup();
            proptest::prop_assert_eq!(s.len(), b.len() - joined);
        }
    }

    #[test]
    fn favours_high_bins() {
        let mut rng = ChaCha20Rng::seed_from_u64(5);
        let mut members = vec![Vec::new(); 10];
        for (i, m) in members.iter_mut().enumerate() {
            *m = (i * 1000..(i + 1) * 1000).collect();
        }
        let mut low = 0;
        let mut high = 0;
        for _ in 0..200 {
            for i in biased_batch(&members, &[], 32, 3.0, &mut RngDraws(&mut rng)) {
                if i < 1000 {
                    low += 1;
                } else if i >= 9000 {
                    high += 1;
                }
            }
        }
        assert!(high > 2 * low, "high {high} low {low}");
    }
}
