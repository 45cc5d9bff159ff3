//! Bin-biased WGAN batches: the GAN learns mostly from tests with high fitness.
//!
//! Fitness `[0, 1]` is cut into `B` bins. Bin `k` (0 = lowest fitness) has centre
//! `x_k = (k + 0.5)/B − 0.5` and weight `1/(1 + exp(−(x_k − α)))`; α grows during the run.
//! A batch draws a bin per slot by these weights and takes one unused test from it; an exhausted
//! bin passes the draw to the next lower bin, wrapping round to the top, so the batch is never
//! larger than the tests available. The newest tests first get a chance to enter on their own:
//! each joins when its bin is at least as high as a bin drawn by the same weights.

use rand::{Rng, RngExt};

/// Bin index of a fitness value (clamped to `[0, 1]`).
pub fn bin_of(fitness: f64, bins: usize) -> usize {
    let f = if fitness.is_nan() {
        0.0
    } else {
        fitness.clamp(0.0, 1.0)
    };
    ((f * bins as f64) as usize).min(bins.saturating_sub(1))
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

fn draw<R: Rng + ?Sized>(weights: &[f64], rng: &mut R) -> usize {
    let total: f64 = weights.iter().sum();
    let mut u = rng.random::<f64>() * total;
    for (k, w) in weights.iter().enumerate() {
        if u < *w {
            return k;
        }
        u -= w;
    }
    weights.len() - 1
}

/// Indices of a training batch of at most `size` tests.
///
/// `members[k]` lists the test indices in bin `k`; `newest` the newest tests' `(index, bin)`.
pub fn biased_batch<R: Rng + ?Sized>(
    members: &[Vec<usize>],
    newest: &[(usize, usize)],
    size: usize,
    alpha: f64,
    rng: &mut R,
) -> Vec<usize> {
    let bins = members.len();
    let total: usize = members.iter().map(Vec::len).sum();
    let size = size.min(total);
    let weights = bin_weights(bins, alpha);
    let mut batch: Vec<usize> = Vec::with_capacity(size);
    let mut used_in_bin = vec![0usize; bins];
    for &(idx, bin) in newest {
        if batch.len() >= size {
            break;
        }
        if bin < bins && bin >= draw(&weights, rng) && !batch.contains(&idx) {
            batch.push(idx);
            used_in_bin[bin] += 1;
        }
    }
    while batch.len() < size {
        let mut k = draw(&weights, rng);
        // `size <= total` guarantees some bin still has an unused test.
        while used_in_bin[k] >= members[k].len() {
            k = if k == 0 { bins - 1 } else { k - 1 };
        }
        let bin = &members[k];
        let pick = if bin.len() <= 64 {
            // A small bin: choose uniformly among its unused tests directly.
            let choices: Vec<usize> = bin.iter().copied().filter(|i| !batch.contains(i)).collect();
            choices[rng.random_range(0..choices.len())]
        } else {
            // A large bin (at most `size` of it used, so mostly free): rejection sampling
            // avoids scanning it.
            loop {
                let i = bin[rng.random_range(0..bin.len())];
                if !batch.contains(&i) {
                    break i;
                }
            }
        };
        batch.push(pick);
        used_in_bin[k] += 1;
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
            let b = biased_batch(&members, &[], 32, 1.0, &mut rng);
            assert_eq!(b.len(), 5, "never larger than the tests available");
            let mut s = b.clone();
            s.sort_unstable();
            assert_eq!(s, vec![0, 1, 2, 3, 4], "without replacement");
        }
        let b = biased_batch(&members, &[], 3, 0.0, &mut rng);
        assert_eq!(b.len(), 3);
    }

    #[test]
    fn newest_top_bin_always_enters() {
        let mut rng = ChaCha20Rng::seed_from_u64(4);
        let mut members = vec![Vec::new(); 10];
        members[0] = (0..100).collect();
        members[9] = vec![100];
        for _ in 0..20 {
            let b = biased_batch(&members, &[(100, 9)], 4, 0.0, &mut rng);
            assert_eq!(b.len(), 4);
            assert_eq!(b[0], 100);
        }
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
            let b = biased_batch(&members, &newest, size, alpha, &mut rng);
            proptest::prop_assert_eq!(b.len(), size.min(next));
            let mut s = b.clone();
            s.sort_unstable();
            s.dedup();
            proptest::prop_assert_eq!(s.len(), b.len());
            proptest::prop_assert!(b.iter().all(|i| *i < next));
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
            for i in biased_batch(&members, &[], 32, 3.0, &mut rng) {
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
