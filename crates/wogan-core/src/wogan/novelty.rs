//! A novelty rule for WOGAN's candidates (an extension; off in the paper): a candidate is ranked
//! only when it lies at least a given distance from every test executed so far (or every one of
//! at least a given fitness: the failures).
//!
//! WOGAN learns to generate roads like its best ones, so once it has found a failure it mostly
//! re-finds it: most of a run's failures are near-copies of a few roads. Skipping candidates
//! close to any executed test spends the execution budget on roads not tried before, which near
//! the high-fitness region the analyzer favours are new failures rather than repeats. A candidate
//! skipped this way counts towards the streak after which a random valid test is executed, so a
//! generator that only produces explored roads falls back to random search, as with invalid ones.

/// Whether `candidate` lies at least `min_rms_distance` (root mean square of the value
/// differences, normalised units) from each of `tests` (flattened, `candidate.len()` values
/// each). Always true for a distance of 0.
pub(crate) fn is_novel(candidate: &[f32], tests: &[f32], min_rms_distance: f32) -> bool {
    if min_rms_distance <= 0.0 || candidate.is_empty() {
        return true;
    }
    // Compare squared sums, not roots: one multiplication per test instead of a square root.
    let limit = min_rms_distance * min_rms_distance * candidate.len() as f32;
    tests.chunks_exact(candidate.len()).all(|test| {
        let squared: f32 = test
            .iter()
            .zip(candidate)
            .map(|(t, c)| (t - c) * (t - c))
            .sum();
        squared >= limit
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_candidate_is_novel_only_far_enough_from_every_test() {
        let tests = [0.0, 0.0, 1.0, 1.0];
        // RMS distance to (0, 0) of (0.3, 0.4): sqrt((0.09 + 0.16) / 2) = 0.354.
        assert!(is_novel(&[0.3, 0.4], &tests, 0.35));
        assert!(!is_novel(&[0.3, 0.4], &tests, 0.36));
        // Near the second test only.
        assert!(!is_novel(&[0.9, 1.0], &tests, 0.2));
        assert!(is_novel(&[0.5, 0.5], &tests, 0.2));
        // Off, and with no tests yet: always novel.
        assert!(is_novel(&[0.0, 0.0], &tests, 0.0));
        assert!(is_novel(&[0.0, 0.0], &[], 0.5));
    }
}
