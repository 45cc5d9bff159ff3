//! A novelty rule for WOGAN's candidates (an extension; off in the paper): a candidate is ranked
//! only when it lies at least a given distance from every test executed so far (or every one of
//! at least a given fitness: the failures), or from all but a given number of them.
//!
//! WOGAN learns to generate roads like its best ones, so once it has found a failure it mostly
//! re-finds it: most of a run's failures are near-copies of a few roads. Skipping candidates
//! close to any executed test spends the execution budget on roads not tried before, which near
//! the high-fitness region the analyzer favours are new failures rather than repeats. A candidate
//! skipped this way counts towards the streak after which a random valid test is executed, so a
//! generator that only produces explored roads falls back to random search, as with invalid ones.

/// Whether at most `allowed_neighbours` of `tests` (flattened, `candidate.len()` values each) lie
/// nearer to `candidate` than `min_rms_distance` (root mean square of the value differences,
/// normalised units). Always true for a distance of 0.
pub(crate) fn is_novel(
    candidate: &[f32],
    tests: &[f32],
    min_rms_distance: f32,
    allowed_neighbours: usize,
) -> bool {
    if min_rms_distance <= 0.0 || candidate.is_empty() {
        return true;
    }
    // Compare squared sums, not roots: one multiplication per test instead of a square root.
    let limit = min_rms_distance * min_rms_distance * candidate.len() as f32;
    let neighbours = tests.chunks_exact(candidate.len()).filter(|test| {
        let squared: f32 = test
            .iter()
            .zip(candidate)
            .map(|(t, c)| (t - c) * (t - c))
            .sum();
        squared < limit
    });
    // The iterator is lazy: counting stops at the first neighbour past the allowance.
    neighbours
        .take(allowed_neighbours.saturating_add(1))
        .count()
        <= allowed_neighbours
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_candidate_is_novel_only_far_enough_from_every_test() {
        let tests = [0.0, 0.0, 1.0, 1.0];
        // RMS distance to (0, 0) of (0.3, 0.4): sqrt((0.09 + 0.16) / 2) = 0.354.
        assert!(is_novel(&[0.3, 0.4], &tests, 0.35, 0));
        assert!(!is_novel(&[0.3, 0.4], &tests, 0.36, 0));
        // Near the second test only.
        assert!(!is_novel(&[0.9, 1.0], &tests, 0.2, 0));
        assert!(is_novel(&[0.5, 0.5], &tests, 0.2, 0));
        // Off, and with no tests yet: always novel.
        assert!(is_novel(&[0.0, 0.0], &tests, 0.0, 0));
        assert!(is_novel(&[0.0, 0.0], &[], 0.5, 0));
    }

    #[test]
    fn a_candidate_may_have_as_many_neighbours_as_allowed() {
        // Three tests near (0, 0), one far.
        let tests = [0.0, 0.0, 0.1, 0.0, 0.0, 0.1, 1.0, 1.0];
        assert!(!is_novel(&[0.0, 0.0], &tests, 0.5, 0));
        assert!(!is_novel(&[0.0, 0.0], &tests, 0.5, 2));
        assert!(is_novel(&[0.0, 0.0], &tests, 0.5, 3));
        // Near the far test only: one neighbour.
        assert!(!is_novel(&[0.9, 0.9], &tests, 0.5, 0));
        assert!(is_novel(&[0.9, 0.9], &tests, 0.5, 1));
    }
}
