//! Small statistics for comparing repetitions of runs: mean, sample standard deviation, median and
//! the Mann–Whitney U test (two-sided), exact for small groups and normal beyond.

/// Largest group size for which the U test enumerates the exact distribution of the rank sum.
pub const EXACT_MAX_GROUP: usize = 20;

/// Mean of `values`; `None` when empty.
pub fn mean(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    Some(values.iter().sum::<f64>() / values.len() as f64)
}

/// Sample standard deviation (n − 1 in the denominator); `None` with fewer than two values.
pub fn sample_sd(values: &[f64]) -> Option<f64> {
    if values.len() < 2 {
        return None;
    }
    let m = mean(values)?;
    let squares = values.iter().map(|v| (v - m) * (v - m)).sum::<f64>();
    Some((squares / (values.len() - 1) as f64).sqrt())
}

/// Median of `values`; `None` when empty.
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let mid = sorted.len() / 2;
    Some(if !sorted.len().is_multiple_of(2) {
        sorted[mid]
    } else {
        (sorted[mid - 1] + sorted[mid]) / 2.0
    })
}

/// How a Mann–Whitney p-value was computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PMethod {
    /// By enumerating every split of the pooled (mid)ranks.
    Exact,
    /// Normal approximation with tie and continuity correction.
    Normal,
}

/// The result of a Mann–Whitney U test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MannWhitney {
    /// U of the first sample (rank sum minus n1(n1+1)/2).
    pub u1: f64,
    /// Two-sided p-value.
    pub p_value: f64,
    /// How the p-value was computed.
    pub method: PMethod,
}

/// Two-sided Mann–Whitney U test of `x` against `y`; `None` when either sample is empty.
///
/// Ties get midranks. Up to [`EXACT_MAX_GROUP`] values in each sample the p-value is exact: the
/// permutation distribution of the first sample's rank sum over all splits of the pooled midranks
/// (so ties are accounted for exactly), `p = min(1, 2 min(P(R ≤ r), P(R ≥ r)))`. Beyond, the normal
/// approximation with tie correction and continuity correction (as scipy's default).
pub fn mann_whitney(x: &[f64], y: &[f64]) -> Option<MannWhitney> {
    let (n1, n2) = (x.len(), y.len());
    if n1 == 0 || n2 == 0 {
        return None;
    }
    let doubled_ranks = doubled_midranks(x, y);
    let doubled_r1: u64 = doubled_ranks[..n1].iter().sum();
    let u1 = doubled_r1 as f64 / 2.0 - (n1 * (n1 + 1)) as f64 / 2.0;
    if n1 <= EXACT_MAX_GROUP && n2 <= EXACT_MAX_GROUP {
        let p_value = exact_p(&doubled_ranks, n1, doubled_r1);
        return Some(MannWhitney {
            u1,
            p_value,
            method: PMethod::Exact,
        });
    }
    let p_value = normal_p(&doubled_ranks, n1, n2, u1);
    Some(MannWhitney {
        u1,
        p_value,
        method: PMethod::Normal,
    })
}

/// Twice the midrank of each value of `x` then `y` in the pooled sample (integers).
fn doubled_midranks(x: &[f64], y: &[f64]) -> Vec<u64> {
    let pooled: Vec<f64> = x.iter().chain(y).copied().collect();
    let mut order: Vec<usize> = (0..pooled.len()).collect();
    order.sort_by(|&a, &b| pooled[a].total_cmp(&pooled[b]));
    let mut ranks = vec![0; pooled.len()];
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        while end < order.len() && pooled[order[end]] == pooled[order[start]] {
            end += 1;
        }
        // Ranks start+1 ..= end share their mean; doubled: start + 1 + end.
        for &i in &order[start..end] {
            ranks[i] = (start + 1 + end) as u64;
        }
        start = end;
    }
    ranks
}

/// Exact two-sided p-value of the rank sum `observed` of `n1` of the pooled `doubled_ranks`.
fn exact_p(doubled_ranks: &[u64], n1: usize, observed: u64) -> f64 {
    let total: u64 = doubled_ranks.iter().sum();
    let width = total as usize + 1;
    // ways[k * width + s]: subsets of size k with doubled rank sum s.
    let mut ways = vec![0f64; (n1 + 1) * width];
    ways[0] = 1.0;
    for (seen, &rank) in doubled_ranks.iter().enumerate() {
        let rank = rank as usize;
        for k in (1..=n1.min(seen + 1)).rev() {
            for s in (rank..width).rev() {
                let from = ways[(k - 1) * width + s - rank];
                if from > 0.0 {
                    ways[k * width + s] += from;
                }
            }
        }
    }
    let row = &ways[n1 * width..];
    let all: f64 = row.iter().sum();
    let observed = observed as usize;
    let lower: f64 = row[..=observed].iter().sum();
    let upper: f64 = row[observed..].iter().sum();
    (2.0 * lower.min(upper) / all).min(1.0)
}

/// Normal-approximation two-sided p-value with tie and continuity correction.
fn normal_p(doubled_ranks: &[u64], n1: usize, n2: usize, u1: f64) -> f64 {
    let n = (n1 + n2) as f64;
    let mut sorted = doubled_ranks.to_vec();
    sorted.sort_unstable();
    let mut tie_sum = 0.0;
    let mut start = 0;
    while start < sorted.len() {
        let end = start
            + sorted[start..]
                .iter()
                .take_while(|&&r| r == sorted[start])
                .count();
        let t = (end - start) as f64;
        tie_sum += t * t * t - t;
        start = end;
    }
    let (n1, n2) = (n1 as f64, n2 as f64);
    let mu = n1 * n2 / 2.0;
    let variance = n1 * n2 / 12.0 * ((n + 1.0) - tie_sum / (n * (n - 1.0)));
    if variance <= 0.0 {
        return 1.0;
    }
    let z = ((u1 - mu).abs() - 0.5).max(0.0) / variance.sqrt();
    (erfc(z / std::f64::consts::SQRT_2)).min(1.0)
}

/// Complementary error function (Numerical Recipes' Chebyshev fit, relative error < 1.2e-7).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance
    }

    #[test]
    fn mean_and_sd_by_hand() {
        let values = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert_eq!(mean(&values), Some(5.0));
        // Squares sum to 32; 32 / 7.
        assert!(close(
            sample_sd(&values).unwrap_or(0.0),
            (32.0f64 / 7.0).sqrt(),
            1e-12
        ));
        assert_eq!(sample_sd(&[1.0]), None);
        assert_eq!(median(&[3.0, 1.0, 2.0, 10.0]), Some(2.5));
    }

    #[test]
    fn exact_separated_samples() {
        // scipy.stats.mannwhitneyu([1,2,3],[4,5,6], method='exact'): U=0, p = 2/20.
        let r = mann_whitney(&[1.0, 2.0, 3.0], &[4.0, 5.0, 6.0]).expect("samples");
        assert_eq!(r.u1, 0.0);
        assert_eq!(r.method, PMethod::Exact);
        assert!(close(r.p_value, 0.1, 1e-12));
        // [1..4] vs [5..9]: p = 2/126.
        let r = mann_whitney(&[1.0, 2.0, 3.0, 4.0], &[5.0, 6.0, 7.0, 8.0, 9.0]).expect("samples");
        assert!(close(r.p_value, 2.0 / 126.0, 1e-12));
    }

    #[test]
    fn exact_textbook_example() {
        // x ranks 5,7,3,9,8 → R1 = 32, U1 = 17, U2 = 3; P(U ≤ 3) = (1+1+2+3)/126.
        let r = mann_whitney(&[19.0, 22.0, 16.0, 29.0, 24.0], &[20.0, 11.0, 17.0, 12.0])
            .expect("samples");
        assert_eq!(r.u1, 17.0);
        assert!(close(r.p_value, 14.0 / 126.0, 1e-12));
    }

    #[test]
    fn identical_samples_give_one() {
        let r = mann_whitney(&[1.0, 1.0, 1.0], &[1.0, 1.0]).expect("samples");
        assert_eq!(r.u1, 3.0);
        assert!(close(r.p_value, 1.0, 1e-12));
    }

    #[test]
    fn exact_with_ties_matches_brute_force() {
        let x = [1.0, 2.0, 2.0, 3.0];
        let y = [2.0, 3.0, 3.0, 4.0, 4.0];
        let r = mann_whitney(&x, &y).expect("samples");
        // Brute force over every choice of 4 of the 9 pooled midranks.
        let ranks = doubled_midranks(&x, &y);
        let observed: u64 = ranks[..4].iter().sum();
        let (mut low, mut high, mut all) = (0u32, 0u32, 0u32);
        for mask in 0u32..(1 << 9) {
            if mask.count_ones() != 4 {
                continue;
            }
            let s: u64 = (0..9)
                .filter(|i| mask & (1 << i) != 0)
                .map(|i| ranks[i])
                .sum();
            all += 1;
            low += u32::from(s <= observed);
            high += u32::from(s >= observed);
        }
        let expected = (2.0 * f64::from(low.min(high)) / f64::from(all)).min(1.0);
        assert!(close(r.p_value, expected, 1e-12));
        // Midranks: 1→1, 2→3 (×3), 3→6 (×3), 4→8.5 (×2); R1 = 1+3+3+6 = 13, U1 = 3.
        assert_eq!(r.u1, 3.0);
    }

    #[test]
    fn normal_approximation_beyond_twenty() {
        // 21 vs 21 fully separated: U1 = 0, mu = 220.5, var = 21·21·43/12 = 1580.25, sd = 39.75.
        let x: Vec<f64> = (0..21).map(f64::from).collect();
        let y: Vec<f64> = (21..42).map(f64::from).collect();
        let r = mann_whitney(&x, &y).expect("samples");
        assert_eq!(r.method, PMethod::Normal);
        let z: f64 = (220.5 - 0.5) / 39.75;
        // 2 (1 − Φ(5.5346)) ≈ 3.118e-8.
        assert!(z > 5.53 && z < 5.54);
        assert!(r.p_value > 2.5e-8 && r.p_value < 3.7e-8, "{}", r.p_value);
        assert!(close(erfc(0.0), 1.0, 1e-7));
        assert!(close(erfc(1.0), 0.157_299_207, 1e-7));
    }
}
