//! Niches of failures filled one after another (an extension; off in the paper).
//!
//! WOGAN learns to generate tests like its best ones, so a run's failures pile up in one region
//! of the test space: many failures, all alike. Keeping every failure away from the others
//! ([`super::novelty`]) spreads them but leaves few, since each region then yields one. Niches
//! take another way: a niche is a ball of shapes ([`crate::Sut::shape`]) around a *seed*
//! failure, and the search exploits one niche at a time.
//!
//! - While a niche is open, only candidates inside its ball are ranked, and only its failures
//!   are mutation parents: the search exploits that region, as the paper's WOGAN exploits its
//!   first one.
//! - Once the niche holds `quota` failures it is closed. Until another opens, only candidates at
//!   least `distance` from every seed so far are ranked, and the first failure found there seeds
//!   the next niche; candidates inside a closed ball stay skipped. Meanwhile every mutant is
//!   reshaped (mirrored, reversed or half-swapped): a jump away from its parent, not a step;
//!   or, with [`crate::BetweenNiches::Random`], the candidates are random tests instead.
//! - With `stale`, a niche also closes before its quota once that many of its failures in a row
//!   repeat failures found before (their [`crate::Sut::failure_profile`]s lie within
//!   `repeat_distance`): a region that only re-finds its failures is left for the next.
//! - Where no such failure is found within `patience` executed tests (the far regions are
//!   exhausted), the failure found meanwhile farthest from every seed, outside the closed balls,
//!   seeds the next niche, so that the rest of the budget is still spent exploiting.
//!
//! A run so ends with a few regions of failures of about equal size whose seeds lie far apart
//! by shape: most pairs of its failures are pairs from two niches. Failures found between niches
//! (a random test drawn after a streak of skipped candidates may land anywhere) count as failures
//! but belong to no niche.

use crate::NicheConfig;

/// A test's place among the niches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NicheRole {
    /// In no niche (not a failure, or a failure between niches).
    Outside,
    /// A failure of the open niche.
    Open,
    /// A failure of a closed niche.
    Closed,
}

/// The niches of a run: their seeds' shapes and the open one's failures.
#[derive(Debug, Clone, Default)]
pub(crate) struct Niches {
    /// The settings: quota, seed distance, radius, patience, repeats.
    config: NicheConfig,
    /// Seeds' shapes, flattened, in the order found; the last is the open niche's while one is.
    seeds: Vec<f32>,
    /// Indices of the open niche's failures (empty while none is open).
    open_members: Vec<usize>,
    /// How many niches were closed.
    closed: usize,
    /// Tests executed since the last niche closed, while none is open.
    tests_between: usize,
    /// Between niches, the failure farthest from every seed so far outside the closed balls:
    /// its index, shape and distance from the nearest seed.
    farthest_between: Option<(usize, Vec<f32>, f32)>,
    /// Profiles of the run's failures that were not repeats, flattened, in the order found.
    new_failure_profiles: Vec<f32>,
    /// Repeats in a row among the open niche's latest failures.
    open_repeats: usize,
}

/// Root mean square of the differences of two shapes of one length.
pub(crate) fn rms_distance(a: &[f32], b: &[f32]) -> f32 {
    let squared: f32 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    (squared / a.len().max(1) as f32).sqrt()
}

impl Niches {
    /// The niches a configuration asks for (off at a quota of 0).
    pub(crate) fn new(config: &NicheConfig) -> Self {
        Self {
            config: config.clone(),
            ..Self::default()
        }
    }

    /// Whether niches are on.
    pub(crate) fn are_on(&self) -> bool {
        self.config.are_on()
    }

    /// Whether a niche is open (being filled).
    pub(crate) fn is_open(&self) -> bool {
        !self.open_members.is_empty()
    }

    /// How many niches were closed.
    pub(crate) fn closed(&self) -> usize {
        self.closed
    }

    /// Whether niches constrain candidates now: one is open, or one was closed.
    pub(crate) fn constrain(&self) -> bool {
        self.is_open() || self.closed > 0
    }

    /// Whether the search is between niches: one was closed and the next is not yet open.
    pub(crate) fn are_between(&self) -> bool {
        !self.is_open() && self.closed > 0
    }

    /// Shapes of the seeds, each `len` values.
    fn seed_shapes(&self, len: usize) -> std::slice::ChunksExact<'_, f32> {
        self.seeds.chunks_exact(len.max(1))
    }

    /// Whether a candidate of this `shape` may be ranked: inside the open niche while one is
    /// open, otherwise far enough from every seed to seed a niche itself.
    pub(crate) fn admits(&self, shape: &[f32]) -> bool {
        let mut seeds = self.seed_shapes(shape.len());
        if self.is_open() {
            return seeds
                .next_back()
                .is_none_or(|open| rms_distance(open, shape) <= self.config.radius);
        }
        let limit = self.config.distance.max(self.config.radius);
        seeds.all(|seed| rms_distance(seed, shape) >= limit)
    }

    /// Records executed test `test_index`, with its shape when it is a failure and, when
    /// [`NicheConfig::want_failure_profiles`], its failure profile; `roles` receives the tests
    /// whose place among the niches this changed (the test itself when it joins or seeds a niche,
    /// a closed niche's failures, a seed chosen after the patience ran out).
    pub(crate) fn record_test(
        &mut self,
        test_index: usize,
        failure_shape: Option<&[f32]>,
        failure_profile: Option<&[f32]>,
        roles: &mut Vec<(usize, NicheRole)>,
    ) {
        if !self.are_on() {
            return;
        }
        let between = self.are_between();
        if let Some(shape) = failure_shape {
            let repeat = self.is_repeat(failure_profile);
            if self.record_failure(test_index, shape, repeat, roles) {
                return;
            }
            if between {
                self.remember_if_farthest(test_index, shape);
            }
        }
        if between {
            self.tests_between += 1;
            if self.config.patience > 0 && self.tests_between >= self.config.patience {
                if let Some((index, shape, _)) = self.farthest_between.take() {
                    self.seed(index, &shape, roles);
                }
            }
        }
    }

    /// Whether a failure of this `profile` repeats one found before (within the repeat
    /// distance); one that does not is remembered. Never a repeat without a profile, or when
    /// niches do not close on repeats.
    fn is_repeat(&mut self, profile: Option<&[f32]>) -> bool {
        let Some(profile) = profile.filter(|p| self.config.stale > 0 && !p.is_empty()) else {
            return false;
        };
        let repeat = self
            .new_failure_profiles
            .chunks_exact(profile.len())
            .any(|earlier| rms_distance(earlier, profile) < self.config.repeat_distance);
        if !repeat {
            self.new_failure_profiles.extend_from_slice(profile);
        }
        repeat
    }

    /// Places a failure (a `repeat` of an earlier one or not): in the open niche (closing it at
    /// its quota, or after `stale` repeats in a row) or as the next seed; whether it found a place.
    fn record_failure(
        &mut self,
        test_index: usize,
        shape: &[f32],
        repeat: bool,
        roles: &mut Vec<(usize, NicheRole)>,
    ) -> bool {
        if !self.admits(shape) {
            return false;
        }
        if !self.is_open() {
            self.seed(test_index, shape, roles);
            return true;
        }
        self.open_members.push(test_index);
        self.open_repeats = if repeat { self.open_repeats + 1 } else { 0 };
        let stale = self.config.stale > 0 && self.open_repeats >= self.config.stale;
        if self.open_members.len() < self.config.quota && !stale {
            roles.push((test_index, NicheRole::Open));
        } else {
            self.close(roles);
        }
        true
    }

    /// Opens a niche around the failure `test_index` of this `shape` (closed at once at a quota
    /// of 1).
    fn seed(&mut self, test_index: usize, shape: &[f32], roles: &mut Vec<(usize, NicheRole)>) {
        self.seeds.extend_from_slice(shape);
        self.tests_between = 0;
        self.farthest_between = None;
        self.open_repeats = 0;
        self.open_members.push(test_index);
        if self.config.quota == 1 {
            self.close(roles);
        } else {
            roles.push((test_index, NicheRole::Open));
        }
    }

    /// Closes the open niche: its failures become closed.
    fn close(&mut self, roles: &mut Vec<(usize, NicheRole)>) {
        self.closed += 1;
        roles.extend(self.open_members.drain(..).map(|i| (i, NicheRole::Closed)));
    }

    /// Keeps a failure found between niches when it lies outside every closed ball and farther
    /// from the nearest seed than the one kept so far.
    fn remember_if_farthest(&mut self, test_index: usize, shape: &[f32]) {
        let nearest = self
            .seed_shapes(shape.len())
            .map(|seed| rms_distance(seed, shape))
            .fold(f32::INFINITY, f32::min);
        let farther = self
            .farthest_between
            .as_ref()
            .is_none_or(|(_, _, kept)| nearest > *kept);
        if nearest > self.config.radius && farther {
            self.farthest_between = Some((test_index, shape.to_vec(), nearest));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Niches of `quota` failures within `radius` of seeds `distance` apart, with a patience.
    fn niches_of(quota: usize, distance: f32, radius: f32, patience: usize) -> Niches {
        Niches::new(&NicheConfig {
            quota,
            distance,
            radius,
            patience,
            ..NicheConfig::default()
        })
    }

    /// Records test `index` (a failure when `shape` is given): the roles it changed.
    fn record(niches: &mut Niches, index: usize, shape: Option<&[f32]>) -> Vec<(usize, NicheRole)> {
        let mut roles = Vec::new();
        niches.record_test(index, shape, None, &mut roles);
        roles
    }

    #[test]
    fn a_niche_admits_only_its_ball_until_it_closes_then_only_far_seeds() {
        let mut niches = niches_of(2, 3.0, 1.0, 0);
        assert!(niches.are_on() && !niches.constrain());
        assert!(niches.admits(&[9.0, 9.0]));
        assert_eq!(
            record(&mut niches, 0, Some(&[0.0, 0.0])),
            [(0, NicheRole::Open)]
        );
        // Open: only its ball. RMS distance of (1, 1) to (0, 0) is 1.
        assert!(niches.admits(&[1.0, 1.0]));
        assert!(!niches.admits(&[1.5, 1.0]));
        // A failure outside the ball belongs to no niche; a passing test to none either.
        assert!(record(&mut niches, 1, Some(&[2.0, 2.0])).is_empty());
        assert!(record(&mut niches, 2, None).is_empty());
        assert_eq!(
            record(&mut niches, 3, Some(&[0.5, 0.0])),
            [(0, NicheRole::Closed), (3, NicheRole::Closed)]
        );
        assert_eq!(niches.closed(), 1);
        assert!(!niches.is_open() && niches.constrain());
        // Closed: only seeds of a new niche are admitted, far from the old seed.
        assert!(!niches.admits(&[0.5, 0.5]));
        assert!(!niches.admits(&[1.5, 1.0]));
        assert!(niches.admits(&[3.0, 3.0]));
    }

    #[test]
    fn a_new_niche_is_seeded_only_far_from_every_seed() {
        let mut niches = niches_of(1, 3.0, 1.0, 0);
        assert_eq!(
            record(&mut niches, 0, Some(&[0.0])),
            [(0, NicheRole::Closed)]
        );
        // Outside the closed ball but nearer than the seed distance: no niche.
        assert!(record(&mut niches, 1, Some(&[2.0])).is_empty());
        assert!(!niches.admits(&[2.0]) && niches.admits(&[-3.0]));
        assert_eq!(
            record(&mut niches, 2, Some(&[3.5])),
            [(2, NicheRole::Closed)]
        );
        assert_eq!(niches.closed(), 2);
        assert!(!niches.admits(&[3.0]) && niches.admits(&[6.5]));
    }

    #[test]
    fn after_the_patience_the_farthest_failure_between_niches_seeds_the_next() {
        let mut niches = niches_of(2, 3.0, 1.0, 4);
        record(&mut niches, 0, Some(&[0.0]));
        record(&mut niches, 1, Some(&[0.5]));
        assert_eq!(niches.closed(), 1);
        // Between niches: inside the closed ball (not kept), then two nearer than the seed
        // distance, the farther of which is kept; the fourth test ends the patience.
        assert!(record(&mut niches, 2, Some(&[0.8])).is_empty());
        assert!(record(&mut niches, 3, Some(&[1.5])).is_empty());
        assert!(record(&mut niches, 4, Some(&[-2.5])).is_empty());
        assert_eq!(record(&mut niches, 5, None), [(4, NicheRole::Open)]);
        assert!(niches.is_open());
        assert!(niches.admits(&[-2.0]) && !niches.admits(&[0.0]));
        // Without patience nothing is seeded.
        let mut patient = niches_of(2, 3.0, 1.0, 0);
        record(&mut patient, 0, Some(&[0.0]));
        record(&mut patient, 1, Some(&[0.5]));
        record(&mut patient, 2, Some(&[-2.5]));
        for i in 3..50 {
            assert!(record(&mut patient, i, None).is_empty());
        }
        assert!(!patient.is_open());
    }

    #[test]
    fn a_niche_closes_after_its_stale_repeats_in_a_row() {
        let mut niches = Niches::new(&NicheConfig {
            quota: 10,
            distance: 3.0,
            radius: 1.0,
            stale: 2,
            repeat_distance: 0.1,
            ..NicheConfig::default()
        });
        let mut failure = |index: usize, profile: f32| {
            let mut roles = Vec::new();
            niches.record_test(index, Some(&[0.0]), Some(&[profile, 0.0]), &mut roles);
            roles
        };
        assert_eq!(failure(0, 0.0), [(0, NicheRole::Open)]);
        // One repeat (0.05 from the seed's profile), then a new failure resets the count.
        assert_eq!(failure(1, 0.05), [(1, NicheRole::Open)]);
        assert_eq!(failure(2, 0.5), [(2, NicheRole::Open)]);
        // A repeat of the second new failure, then of the first: two in a row close the niche
        // at four failures of its quota of ten.
        assert_eq!(failure(3, 0.45), [(3, NicheRole::Open)]);
        assert_eq!(
            failure(4, -0.05),
            [0, 1, 2, 3, 4].map(|i| (i, NicheRole::Closed))
        );
        assert_eq!(niches.closed(), 1);
        // Without profiles (or without `stale`) no failure is a repeat: only the quota closes.
        let mut quota_only = Niches::new(&NicheConfig {
            quota: 3,
            radius: 1.0,
            ..NicheConfig::default()
        });
        for i in 0..2 {
            let mut roles = Vec::new();
            quota_only.record_test(i, Some(&[0.0]), Some(&[0.0]), &mut roles);
            assert_eq!(roles, [(i, NicheRole::Open)]);
        }
    }

    #[test]
    fn niches_off_record_and_keep_out_nothing() {
        for mut niches in [niches_of(0, 1.0, 1.0, 0), niches_of(3, 1.0, 0.0, 0)] {
            assert!(!niches.are_on());
            for i in 0..5 {
                assert!(record(&mut niches, i, Some(&[0.0])).is_empty());
            }
            assert!(niches.admits(&[0.0]) && !niches.constrain());
        }
    }
}
