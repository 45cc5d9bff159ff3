//! Mutants of the best tests so far, mixed into WOGAN's candidates.
//!
//! Not in the paper: its generator trains for a few small steps per round, so its proposals stay
//! close to where it started and a run can miss failures that its own data already holds. The
//! authors proposed mutating failing tests; here a share of each candidate batch are mutants of
//! the highest-fitness tests (a small random step per value, sometimes also one of Frenetic's
//! reshapes: reverse, swap halves, mirror; with `shift_places`, also a shift of every value
//! along the test, which moves a road's bends along it). The analyzer ranks them together with
//! the generator's candidates, so a mutant is executed only when it is predicted to be better.
//!
//! Parents are the best tests that lie apart from one another (`min_parent_distance`): the 8 best
//! alone are usually neighbours, so every mutant lands in one region and the failures found are
//! near copies (`docs/experiments/` has the measurements).

use crate::config::MutationConfig;
use rand::{Rng, RngExt};

/// Indices of the `count` highest `scores`, highest first (ties broken by index).
///
/// A partial selection, not a sort, when `count` is small: it runs once per proposal over every
/// test so far.
fn top_indices(scores: &[f32], count: usize) -> Vec<usize> {
    let higher_first = |a: &usize, b: &usize| scores[*b].total_cmp(&scores[*a]).then(a.cmp(b));
    let mut idx: Vec<usize> = (0..scores.len()).collect();
    if count < idx.len() {
        idx.select_nth_unstable_by(count, higher_first);
        idx.truncate(count);
    }
    idx.sort_unstable_by(higher_first);
    idx
}

/// Indices of up to `cfg.parents` parents among `tests` (`dim` values each), highest `scores`
/// first, each at least `cfg.min_parent_distance` from those before it (fewer when the tests
/// crowd together: distinct regions matter more than the count). A test marked in `excluded`
/// (indexed like `scores`; shorter means the rest are not) is never a parent.
pub(crate) fn parent_indices(
    tests: &[f32],
    dim: usize,
    scores: &[f32],
    excluded: &[bool],
    cfg: &MutationConfig,
) -> Vec<usize> {
    let eligible = |i: &usize| !excluded.get(*i).copied().unwrap_or(false);
    if cfg.min_parent_distance <= 0.0 {
        if !excluded.contains(&true) {
            return top_indices(scores, cfg.parents);
        }
        return top_indices(scores, scores.len())
            .into_iter()
            .filter(eligible)
            .take(cfg.parents)
            .collect();
    }
    let test = |i: usize| &tests[i * dim..(i + 1) * dim];
    let far_enough = |a: &[f32], b: &[f32]| {
        let squared: f32 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
        squared >= cfg.min_parent_distance * cfg.min_parent_distance
    };
    let mut parents: Vec<usize> = Vec::with_capacity(cfg.parents);
    for candidate in top_indices(scores, scores.len())
        .into_iter()
        .filter(eligible)
    {
        if parents.len() == cfg.parents {
            break;
        }
        if parents
            .iter()
            .all(|&parent| far_enough(test(candidate), test(parent)))
        {
            parents.push(candidate);
        }
    }
    parents
}

/// Turns `test`, a copy of a parent, into its mutant (sometimes reshaped, then stepped); values
/// stay in `[-1, 1]`.
pub(crate) fn mutate<R: Rng + ?Sized>(test: &mut [f32], cfg: &MutationConfig, rng: &mut R) {
    if rng.random_bool(cfg.reshape_probability.clamp(0.0, 1.0)) {
        // The shift is a fourth kind only when asked for, so that without it the draws (and
        // every run made before it existed) are unchanged.
        let kinds = if cfg.shift_places > 0 { 4 } else { 3 };
        match rng.random_range(0..kinds) {
            0 => test.reverse(),
            1 => test.rotate_left(test.len() / 2),
            2 => test.iter_mut().for_each(|v| *v = -*v),
            _ => {
                // Never all the way round: that would leave the test as it was.
                let most = cfg.shift_places.min(test.len().saturating_sub(1));
                if most > 0 {
                    let places = rng.random_range(1..=most);
                    if rng.random_bool(0.5) {
                        test.rotate_left(places);
                    } else {
                        test.rotate_right(places);
                    }
                }
            }
        }
    }
    if cfg.max_step > 0.0 {
        for v in test {
            *v = (*v + rng.random_range(-cfg.max_step..=cfg.max_step)).clamp(-1.0, 1.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha20Rng;

    fn mutant_of(parent: &[f32], cfg: &MutationConfig, rng: &mut ChaCha20Rng) -> Vec<f32> {
        let mut child = parent.to_vec();
        mutate(&mut child, cfg, rng);
        child
    }

    #[test]
    fn top_indices_are_the_highest_scores_first() {
        assert_eq!(top_indices(&[0.1, 0.9, 0.5, 0.9], 3), vec![1, 3, 2]);
        assert_eq!(top_indices(&[0.3], 5), vec![0]);
    }

    #[test]
    fn distant_parents_skip_tests_near_a_better_one_and_excluded_tests() {
        // Tests 0 and 1 are close; 2 is far from both.
        let tests = [0.0, 0.0, 0.1, 0.0, 0.9, 0.9];
        let scores = [0.9, 0.8, 0.5];
        let mut cfg = MutationConfig {
            parents: 2,
            min_parent_distance: 0.0,
            ..MutationConfig::default()
        };
        let parents = |excluded: &[bool], cfg: &MutationConfig| {
            parent_indices(&tests, 2, &scores, excluded, cfg)
        };
        let excluded = [true, false, false];
        assert_eq!(parents(&[], &cfg), vec![0, 1]);
        assert_eq!(parents(&excluded, &cfg), vec![1, 2]);
        cfg.min_parent_distance = 0.5;
        assert_eq!(parents(&[], &cfg), vec![0, 2]);
        // Test 1 is the best left; test 2 lies far from it.
        assert_eq!(parents(&excluded, &cfg), vec![1, 2]);
        assert!(parents(&[true; 3], &cfg).is_empty());
        cfg.parents = 3;
        assert_eq!(parents(&[], &cfg), vec![0, 2]);
    }

    #[test]
    fn a_mutant_stays_within_the_step_and_the_bounds() {
        let cfg = MutationConfig {
            reshape_probability: 0.0,
            ..MutationConfig::default()
        };
        let mut rng = ChaCha20Rng::seed_from_u64(1);
        let parent = [0.95, -0.99, 0.0, 0.5, -0.2];
        let mut moved = false;
        for _ in 0..200 {
            let child = mutant_of(&parent, &cfg, &mut rng);
            for (c, p) in child.iter().zip(parent) {
                assert!((-1.0..=1.0).contains(c));
                assert!((c - p).abs() <= cfg.max_step + 1e-6);
                moved |= c != &p;
            }
        }
        assert!(moved);
    }

    #[test]
    fn reshapes_are_frenetics_reverse_swap_and_mirror() {
        let cfg = MutationConfig {
            max_step: 0.0,
            reshape_probability: 1.0,
            ..MutationConfig::default()
        };
        let mut rng = ChaCha20Rng::seed_from_u64(2);
        let parent = [0.1, 0.2, 0.3, 0.4, 0.5];
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..100 {
            let child = mutant_of(&parent, &cfg, &mut rng);
            let kind = if child == [0.5, 0.4, 0.3, 0.2, 0.1] {
                "reverse"
            } else if child == [0.3, 0.4, 0.5, 0.1, 0.2] {
                "swap"
            } else if child == [-0.1, -0.2, -0.3, -0.4, -0.5] {
                "mirror"
            } else {
                panic!("unexpected mutant {child:?}")
            };
            seen.insert(kind);
        }
        assert_eq!(seen.len(), 3);
    }

    #[test]
    fn a_shift_moves_every_value_round_the_ends_by_at_most_its_places() {
        let cfg = MutationConfig {
            max_step: 0.0,
            reshape_probability: 1.0,
            shift_places: 2,
            ..MutationConfig::default()
        };
        let mut rng = ChaCha20Rng::seed_from_u64(3);
        let parent = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7];
        let rotated = |places: isize| -> Vec<f32> {
            let mut child = parent.to_vec();
            if places > 0 {
                child.rotate_left(places.unsigned_abs());
            } else {
                child.rotate_right(places.unsigned_abs());
            }
            child
        };
        let mut shifts = std::collections::BTreeSet::new();
        for _ in 0..400 {
            let child = mutant_of(&parent, &cfg, &mut rng);
            let reshaped = child == [0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1]
                || child == rotated(3)
                || child.iter().zip(parent).all(|(c, p)| *c == -p);
            if reshaped {
                continue;
            }
            let places = [-2, -1, 1, 2]
                .into_iter()
                .find(|&places| child == rotated(places))
                .unwrap_or_else(|| panic!("unexpected mutant {child:?}"));
            shifts.insert(places);
        }
        // Both ways, by one place and by two.
        assert_eq!(shifts.len(), 4);
    }
}
