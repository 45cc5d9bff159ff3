//! WOGAN's learning state: the data so far, the analyzer and the WGAN, one training round and
//! the choice of the next test (the body of the paper's Algorithm 1).
//!
//! The loop around it (random phase, retraining every few tests, budget, events) is in
//! [`crate::run()`].

use rand::seq::index;
use rand::{Rng, RngExt};

use super::acceptance::Acceptance;
use super::bins::{biased_batch, bin_of, RngDraws};
use super::mutation::{mutate, parent_indices};
use super::niches::{NicheRole, Niches};
use super::novelty::is_novel;
use super::remakes::RemakeQueue;
use super::training_round::{AnalyzerSteps, TrainingData};
use crate::config::{BetweenNiches, MutationConfig, WoganConfig};
use crate::error::Error;
use crate::nets::{
    logit_target, uniform_noise, Analyzer, AnalyzerTrainer, Generator, Matrix, Wgan,
};
use crate::sut::Sut;
use crate::test_sampler::Sampler;

/// Losses reported by one training round (those of its last steps).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrainStats {
    /// Analyzer loss (MSE on logits plus L2) before its last step.
    pub analyzer_loss: f64,
    /// Critic loss of the last critic step.
    pub critic_loss: f64,
    /// Gradient penalty (coefficient included) of the last critic step.
    pub gradient_penalty: f64,
    /// Generator loss of the last generator step.
    pub generator_loss: f64,
    /// Critic's estimate of the Wasserstein distance between batch and generator.
    pub wasserstein_estimate: f64,
}

/// The next test WOGAN wants executed.
#[derive(Debug, Clone, PartialEq)]
pub struct Proposal {
    /// A valid test.
    pub test: Vec<f32>,
    /// The analyzer's prediction, `None` when no network chose the test: the generator gave up
    /// and a random test was drawn, or it is a remake.
    pub predicted: Option<f64>,
    /// Invalid candidates (generated or random) rejected on the way.
    pub invalid: usize,
    /// Valid candidates the analyzer ranked on the way: the acceptance rule's selection pressure.
    pub ranked: usize,
    /// Where the test comes from.
    pub origin: Origin,
}

/// Where a proposed test comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// The generator (or the random fallback after too many invalid candidates).
    Generator,
    /// A mutant of one of the best tests so far ([`crate::MutationConfig`]).
    Mutant,
    /// A remake of a failure ([`crate::RemakeConfig`]).
    Remake,
}

/// Whether the niches constrain a candidate ([`WoganModel::passes_novelty`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NicheRule {
    Apply,
    Ignore,
}

/// WOGAN's data and networks.
pub struct WoganModel {
    dim: usize,
    cfg: WoganConfig,
    analyzer: AnalyzerTrainer,
    wgan: Wgan,
    tests: Vec<f32>,
    targets: Vec<f32>,
    /// The tests that keep candidates away (`novelty`), flattened, when only some do (a
    /// `min_fitness` above 0); otherwise every test does, and `tests` is used as it is.
    novelty_anchors: Vec<f32>,
    /// The shapes (`Sut::shape`) of the tests that keep candidates away by `shape_novelty`,
    /// flattened.
    shape_anchors: Vec<f32>,
    /// The niches of failures (`niches`), and each test's place among them (indexed like
    /// `targets`).
    niches: Niches,
    niche_roles: Vec<NicheRole>,
    bins: Vec<Vec<usize>>,
    bin_of_test: Vec<usize>,
    rounds: usize,
    /// Generator and analyzer as they propose (the generator with its running batch statistics),
    /// refreshed after each training round rather than per candidate batch.
    inference: Option<(Generator, Analyzer)>,
    /// Whether the analyzer trains on a second thread beside the WGAN.
    concurrent_training: bool,
    /// The failures' remakes waiting to be executed (`remakes`), and the invalid ones skipped
    /// since the last proposal.
    remakes: RemakeQueue,
    invalid_remakes: usize,
}

impl WoganModel {
    /// Fresh networks (weights drawn from `rng`) and no data.
    pub fn new<R: Rng + ?Sized>(dim: usize, cfg: &WoganConfig, rng: &mut R) -> Self {
        let analyzer = AnalyzerTrainer::new(dim, &cfg.analyzer, rng);
        let wgan = Wgan::new(dim, &cfg.generator, &cfg.critic, &cfg.wgan, rng);
        Self {
            dim,
            cfg: cfg.clone(),
            analyzer,
            wgan,
            tests: Vec::new(),
            targets: Vec::new(),
            novelty_anchors: Vec::new(),
            shape_anchors: Vec::new(),
            niches: Niches::new(&cfg.niches),
            niche_roles: Vec::new(),
            bins: vec![Vec::new(); cfg.bins],
            bin_of_test: Vec::new(),
            rounds: 0,
            inference: None,
            concurrent_training: false,
            remakes: RemakeQueue::default(),
            invalid_remakes: 0,
        }
    }

    /// Test vector dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The settings the model was built with.
    pub fn config(&self) -> &WoganConfig {
        &self.cfg
    }

    /// The generator and analyzer candidates are drawn and ranked with, once trained.
    pub(super) fn inference(&self) -> Option<&(Generator, Analyzer)> {
        self.inference.as_ref()
    }

    /// Proposes with these networks from now on (a restored snapshot's).
    pub(super) fn set_inference(&mut self, generator: Generator, analyzer: Analyzer) {
        self.inference = Some((generator, analyzer));
    }

    /// Number of tests learnt from.
    pub fn len(&self) -> usize {
        self.targets.len()
    }

    /// Whether there are no tests yet.
    pub fn is_empty(&self) -> bool {
        self.targets.is_empty()
    }

    /// Records an executed test and its fitness.
    pub fn add(&mut self, test: &[f32], fitness: f64) {
        let idx = self.targets.len();
        self.tests.extend_from_slice(test);
        self.targets.push(logit_target(fitness));
        let novelty = &self.cfg.novelty;
        if novelty.distance > 0.0 && novelty.min_fitness > 0.0 && fitness >= novelty.min_fitness {
            self.novelty_anchors.extend_from_slice(test);
        }
        self.niche_roles.push(NicheRole::Outside);
        let b = bin_of(fitness, self.cfg.bins);
        self.bins[b].push(idx);
        self.bin_of_test.push(b);
    }

    /// Records a test `sut` executed and its fitness, with the test's shape when the shape
    /// novelty rule keeps candidates away from it or it is a failure that fills a niche, and its
    /// `failure_profile` ([`Sut::failure_profile`]) when niches close on repeated failures
    /// (`NicheConfig::stale`; otherwise it may be `None`).
    pub fn add_executed<S: Sut + ?Sized>(
        &mut self,
        sut: &S,
        test: &[f32],
        fitness: f64,
        failure_profile: Option<&[f32]>,
    ) {
        let idx = self.len();
        self.add(test, fitness);
        let rule = &self.cfg.shape_novelty;
        let anchors_shape = rule.distance > 0.0 && fitness >= rule.min_fitness;
        let fills_niche = self.niches.are_on() && fitness >= self.cfg.niches.min_fitness;
        let shape = if anchors_shape || fills_niche {
            sut.shape(test)
        } else {
            None
        };
        if let Some(shape) = shape.as_ref().filter(|_| anchors_shape) {
            self.shape_anchors.extend_from_slice(shape);
        }
        if self.niches.are_on() {
            let mut roles = Vec::new();
            let failure_shape = shape.as_deref().filter(|_| fills_niche);
            let failure_profile = failure_profile.filter(|_| fills_niche);
            self.niches
                .record_test(idx, failure_shape, failure_profile, &mut roles);
            for (test, role) in roles {
                self.niche_roles[test] = role;
            }
        }
    }

    /// Queues the remakes of the executed `test` when it is a failure by `remakes` (on).
    pub(crate) fn queue_remakes(&mut self, test: &[f32], fitness: f64) {
        let rule = &self.cfg.remakes;
        if rule.enabled && fitness >= rule.min_fitness {
            self.remakes.queue_remakes_of(test);
        }
    }

    /// The next waiting remake that is valid, not a test executed before and novel by the
    /// novelty rules. The niches do not constrain it: a remake is meant to leave its failure's
    /// niche (it may seed another). Invalid remakes skipped on the way are counted in the next
    /// proposal ([`Self::take_invalid_remakes`]).
    pub(crate) fn next_remake<S: Sut + ?Sized>(&mut self, sut: &S) -> Option<Proposal> {
        while let Some(remake) = self.remakes.pop() {
            if !sut.is_valid(&remake) {
                self.invalid_remakes += 1;
                continue;
            }
            let executed_before = self.tests.chunks_exact(self.dim).any(|t| t == remake);
            let anchors = self.novelty_anchors();
            if executed_before || !self.passes_novelty(sut, &remake, anchors, NicheRule::Ignore) {
                continue;
            }
            return Some(Proposal {
                test: remake,
                predicted: None,
                invalid: self.take_invalid_remakes(),
                ranked: 0,
                origin: Origin::Remake,
            });
        }
        None
    }

    /// The invalid remakes skipped since the last proposal, counted once.
    pub(crate) fn take_invalid_remakes(&mut self) -> usize {
        std::mem::take(&mut self.invalid_remakes)
    }

    /// Which tests may not be mutation parents because of the niches: while one is open, all
    /// but its failures (it is the region being exploited). Otherwise none: a reshaped mutant of
    /// any test (a mirrored road, say) may seed the next niche.
    fn niche_parents_excluded(&self) -> Vec<bool> {
        if !self.niches.is_open() {
            return Vec::new();
        }
        self.niche_roles
            .iter()
            .map(|&role| role != NicheRole::Open)
            .collect()
    }

    /// How many niches of failures were closed (0 while niches are off).
    pub fn closed_niches(&self) -> usize {
        self.niches.closed()
    }

    /// The tests that keep candidates away by the value novelty rule.
    fn novelty_anchors(&self) -> &[f32] {
        if self.cfg.novelty.min_fitness > 0.0 {
            &self.novelty_anchors
        } else {
            &self.tests
        }
    }

    /// Whether candidate `c` is far enough from `anchors` and the executed tests' shapes by both
    /// novelty rules, and, under `niches`, where the open niche (or the search between niches)
    /// admits it.
    fn passes_novelty<S: Sut + ?Sized>(
        &self,
        sut: &S,
        c: &[f32],
        anchors: &[f32],
        niches: NicheRule,
    ) -> bool {
        let rule = &self.cfg.novelty;
        if !is_novel(c, anchors, rule.distance, rule.allowed_neighbours) {
            return false;
        }
        let rule = &self.cfg.shape_novelty;
        let shape_rule_applies = rule.distance > 0.0 && !self.shape_anchors.is_empty();
        let niches_apply = niches == NicheRule::Apply && self.niches.constrain();
        if !(shape_rule_applies || niches_apply) {
            return true;
        }
        sut.shape(c).is_none_or(|shape| {
            (!shape_rule_applies
                || is_novel(
                    &shape,
                    &self.shape_anchors,
                    rule.distance,
                    rule.allowed_neighbours,
                ))
                && (!niches_apply || self.niches.admits(&shape))
        })
    }

    /// Trains the analyzer on a second thread, alongside the WGAN, from the next training round
    /// on (`false`: one thread, the default). The result is the same bit for bit: the analyzer
    /// and the WGAN share no weights, and every random draw is still made on the calling thread
    /// in the reference's order; only the analyzer's arithmetic moves.
    pub fn set_concurrent_training(&mut self, concurrent: bool) {
        self.concurrent_training = concurrent;
    }

    /// One training round with bin bias `alpha`: analyzer epochs and WGAN epochs interleaved.
    ///
    /// The first round uses the `first_*` epoch counts, later ones the `later_*` counts.
    pub fn train<R: Rng + ?Sized>(&mut self, alpha: f64, rng: &mut R) -> Result<TrainStats, Error> {
        if self.is_empty() {
            return Err(Error::Config("cannot train WOGAN without data".into()));
        }
        let (epochs, analyzer_epochs) = if self.rounds == 0 {
            (self.cfg.first_epochs, self.cfg.first_analyzer_epochs)
        } else {
            (self.cfg.later_epochs, self.cfg.later_analyzer_epochs)
        };
        let n = self.len();
        // As in the reference, the newest tests get their own chance only after the first round.
        let newest_count = if self.rounds == 0 {
            0
        } else {
            self.cfg.newest_in_batch
        };
        let newest: Vec<(usize, usize)> = (n.saturating_sub(newest_count)..n)
            .rev()
            .map(|i| (i, self.bin_of_test[i]))
            .collect();
        // The random draws of the round, in the reference's order: per epoch the analyzer's
        // batches, the WGAN's biased batch, then the WGAN's own draws as it trains.
        let concurrent = self.concurrent_training;
        let Self {
            dim,
            cfg,
            analyzer,
            wgan,
            tests,
            targets,
            bins,
            ..
        } = self;
        let data = TrainingData {
            dim: *dim,
            tests,
            targets,
        };
        let mut stats = TrainStats::default();
        let mut wgan_epoch = |rng: &mut R, stats: &mut TrainStats| {
            let idx = biased_batch(
                bins,
                &newest,
                cfg.batch_size,
                alpha,
                &mut RngDraws(&mut *rng),
            );
            let l = wgan.epoch(&data.rows(&idx), rng);
            stats.critic_loss = l.critic;
            stats.generator_loss = l.generator;
            stats.wasserstein_estimate = l.wasserstein;
            stats.gradient_penalty = l.penalty;
        };
        let max_batch = cfg.analyzer.max_batch;
        let draw =
            |rng: &mut R| (n > max_batch).then(|| index::sample(rng, n, max_batch).into_vec());
        // A round's analyzer steps in order; the last reports the loss.
        let steps = epochs * analyzer_epochs;
        if concurrent && steps > 0 {
            let (to_analyzer, batches) = std::sync::mpsc::channel::<Option<Vec<usize>>>();
            let analyzer_loss = std::thread::scope(|scope| {
                let worker = scope.spawn(|| {
                    let mut trainer = AnalyzerSteps::new(analyzer, &data, steps);
                    for batch in batches {
                        trainer.step(batch);
                    }
                    trainer.loss
                });
                for _ in 0..epochs {
                    for _ in 0..analyzer_epochs {
                        // A worker that panicked says so when joined.
                        let _ = to_analyzer.send(draw(rng));
                    }
                    wgan_epoch(rng, &mut stats);
                }
                drop(to_analyzer);
                worker
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            });
            stats.analyzer_loss = analyzer_loss;
        } else {
            let mut trainer = AnalyzerSteps::new(analyzer, &data, steps);
            for _ in 0..epochs {
                for _ in 0..analyzer_epochs {
                    trainer.step(draw(rng));
                }
                wgan_epoch(rng, &mut stats);
            }
            stats.analyzer_loss = trainer.loss;
        }
        self.rounds += 1;
        self.inference = Some((self.wgan.generator.clone(), self.analyzer.model.clone()));
        Ok(stats)
    }

    /// Chooses the next test by the `Acceptance` rule (stgem's): each valid candidate is
    /// ranked by the analyzer until the best is accepted.
    ///
    /// Candidates are generated and scored `candidate_batch` at a time (one network call for
    /// many rounds; in inference mode each is an independent draw, as stgem's one at a time);
    /// validity is checked one candidate at a time and only as far as needed, and the unused rest
    /// of a batch is dropped. After `max_invalid_streak` invalid candidates in a row, a random
    /// valid test is returned. With a mutation share above 0, that share of each batch are
    /// mutants of the highest-fitness tests, scored and validated like the generator's.
    pub fn propose<S: Sut + ?Sized, R: Rng + ?Sized>(
        &self,
        sut: &S,
        sampler: &Sampler,
        rng: &mut R,
    ) -> Result<Proposal, Error> {
        self.propose_with(sut, sampler, rng, &mut self.acceptance())
    }

    /// A fresh acceptance rule with this model's decay, for the first choice of a round.
    pub(crate) fn acceptance(&self) -> Acceptance {
        Acceptance::new(self.cfg.target_decay)
    }

    /// As [`Self::propose`], with the acceptance rule's state given: a round of several choices
    /// carries it from one to the next ([`Acceptance::next_choice`]).
    pub(crate) fn propose_with<S: Sut + ?Sized, R: Rng + ?Sized>(
        &self,
        sut: &S,
        sampler: &Sampler,
        rng: &mut R,
        acceptance: &mut Acceptance,
    ) -> Result<Proposal, Error> {
        let (generator, analyzer) = self
            .inference
            .as_ref()
            .ok_or_else(|| Error::Config("WOGAN must be trained before it proposes".into()))?;
        let noise_dim = self.cfg.generator.noise_dim;
        let batch = self.cfg.candidate_batch;
        // Between niches, when so configured, the candidates are random tests (and no mutants).
        let random_candidates =
            self.cfg.niches.between == BetweenNiches::Random && self.niches.are_between();
        let parents = if self.cfg.mutation.share > 0.0 && !random_candidates {
            parent_indices(
                &self.tests,
                self.dim,
                &self.targets,
                &self.niche_parents_excluded(),
                &self.cfg.mutation,
            )
        } else {
            Vec::new()
        };
        let anchors = self.novelty_anchors();
        let mut best: Option<(Vec<f32>, bool)> = None;
        let mut invalid = 0usize;
        let mut streak = 0usize;
        loop {
            if !sampler.should_go_on() {
                return Err(Error::Interrupted);
            }
            let (cands, is_mutant) = if random_candidates {
                let data: Vec<f32> = (0..batch).flat_map(|_| sampler.sample(rng)).collect();
                (Matrix::new(data, batch, self.dim), vec![false; batch])
            } else {
                let noise = uniform_noise(rng, batch, noise_dim);
                let mut cands = generator.infer(&noise);
                let is_mutant = self.mix_in_mutants(&mut cands.data, &parents, rng);
                (cands, is_mutant)
            };
            let pred = analyzer.predict(&cands);
            for ((c, p), mutant) in cands.data.chunks_exact(self.dim).zip(pred).zip(is_mutant) {
                let is_invalid = !sut.is_valid(c);
                // A candidate too near a test executed before is skipped like an invalid one
                // but not counted as invalid (`novelty`).
                if is_invalid || !self.passes_novelty(sut, c, anchors, NicheRule::Apply) {
                    invalid += usize::from(is_invalid);
                    streak += 1;
                    if streak >= self.cfg.max_invalid_streak {
                        let test = sampler.sample_valid(sut, rng, &mut invalid)?;
                        return Ok(Proposal {
                            test,
                            predicted: None,
                            invalid,
                            ranked: acceptance.ranked(),
                            origin: Origin::Generator,
                        });
                    }
                    continue;
                }
                streak = 0;
                let ranked = acceptance.rank(f64::from(p));
                if ranked.best {
                    best = Some((c.to_vec(), mutant));
                }
                if ranked.accept {
                    if let Some((test, mutant)) = best.take() {
                        return Ok(Proposal {
                            test,
                            predicted: Some(acceptance.best()),
                            invalid,
                            ranked: acceptance.ranked(),
                            origin: if mutant {
                                Origin::Mutant
                            } else {
                                Origin::Generator
                            },
                        });
                    }
                }
            }
        }
    }

    /// Replaces each candidate, with probability `mutation.share`, by a mutant of one of the
    /// `parents` (test indices); says which candidates are mutants.
    fn mix_in_mutants<R: Rng + ?Sized>(
        &self,
        cands: &mut [f32],
        parents: &[usize],
        rng: &mut R,
    ) -> Vec<bool> {
        // Between niches every mutant is reshaped: the search needs a jump far from the seeds
        // so far (a mirrored failure, say), not a small step beside one.
        let reshaped;
        let mutation = if self.niches.are_between() {
            reshaped = MutationConfig {
                reshape_probability: 1.0,
                ..self.cfg.mutation.clone()
            };
            &reshaped
        } else {
            &self.cfg.mutation
        };
        let mut is_mutant = vec![false; cands.len() / self.dim];
        if parents.is_empty() {
            return is_mutant;
        }
        for (cand, flag) in cands.chunks_exact_mut(self.dim).zip(&mut is_mutant) {
            if rng.random_bool(mutation.share) {
                let parent = parents[rng.random_range(0..parents.len())];
                cand.copy_from_slice(&self.tests[parent * self.dim..(parent + 1) * self.dim]);
                mutate(cand, mutation, rng);
                *flag = true;
            }
        }
        is_mutant
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::SamplerConfig;
    use crate::sut::Execution;
    use crate::wogan::niches::rms_distance;
    use rand::SeedableRng;
    use rand_chacha::ChaCha20Rng;

    /// Valid only far out at one corner, where an untrained generator does not reach.
    struct Corner;
    impl Sut for Corner {
        type Output = ();
        fn dim(&self) -> usize {
            3
        }
        fn is_valid(&self, t: &[f32]) -> bool {
            t[0] <= -0.9
        }
        fn execute(&self, _: &[f32]) -> Option<Execution<()>> {
            Some(Execution {
                fitness: 0.5,
                execution_time_s: 0.0,
                output: (),
            })
        }
    }

    #[test]
    fn concurrent_training_is_serial_training_bit_for_bit() {
        // 40 tests fit one analyzer batch; 700 exceed it, so the analyzer's batches are drawn.
        for n in [40usize, 700] {
            let train = |concurrent: bool| {
                let mut rng = ChaCha20Rng::seed_from_u64(11);
                let sampler = Sampler::new(3, SamplerConfig::default());
                let mut model = WoganModel::new(3, &WoganConfig::default(), &mut rng);
                model.set_concurrent_training(concurrent);
                for _ in 0..n {
                    let t = sampler.sample(&mut rng);
                    model.add(&t, f64::from(t[1].abs()));
                }
                let first = model.train(0.5, &mut rng).unwrap();
                let later = model.train(1.5, &mut rng).unwrap();
                let snapshot = model.snapshot().unwrap();
                let next: u64 = rand::RngExt::random(&mut rng);
                (first, later, snapshot, next)
            };
            let (serial, concurrent) = (train(false), train(true));
            assert_eq!(serial.0, concurrent.0, "first round, {n} tests");
            assert_eq!(serial.1, concurrent.1, "later round, {n} tests");
            assert!(serial.1.analyzer_loss > 0.0);
            assert_eq!(serial.2, concurrent.2, "weights, {n} tests");
            assert_eq!(serial.3, concurrent.3, "the RNG's position, {n} tests");
        }
    }

    #[test]
    fn falls_back_to_a_random_valid_test() {
        let mut rng = ChaCha20Rng::seed_from_u64(2);
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut model = WoganModel::new(3, &WoganConfig::default(), &mut rng);
        assert!(
            model.propose(&Corner, &sampler, &mut rng).is_err(),
            "untrained"
        );
        for _ in 0..10 {
            let mut invalid = 0;
            let t = sampler
                .sample_valid(&Corner, &mut rng, &mut invalid)
                .unwrap();
            model.add(&t, 0.5);
        }
        model.train(0.0, &mut rng).unwrap();
        let p = model.propose(&Corner, &sampler, &mut rng).unwrap();
        assert!(Corner.is_valid(&p.test));
        assert_eq!(p.predicted, None);
        assert!(p.invalid >= 100);
    }

    #[test]
    fn a_test_is_accepted_once_the_target_reaches_its_prediction() {
        let mut rng = ChaCha20Rng::seed_from_u64(5);
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut ranked_per_decay = Vec::new();
        for decay in [0.5, 0.95, 0.99] {
            let cfg = WoganConfig {
                target_decay: decay,
                ..WoganConfig::default()
            };
            let mut model = WoganModel::new(3, &cfg, &mut rng);
            for k in 0..12 {
                model.add(&sampler.sample(&mut rng), 0.05 * f64::from(k));
            }
            model.train(0.0, &mut rng).unwrap();
            let mut ranked = 0;
            for _ in 0..5 {
                let p = model.propose(&Anything, &sampler, &mut rng).unwrap();
                let predicted = p.predicted.expect("every candidate is valid");
                let rounds = i32::try_from(p.ranked).unwrap();
                assert!(rounds >= 1);
                assert!(
                    decay.powi(rounds) <= predicted + 1e-4 + 1e-12,
                    "accepted {predicted} at target {} ({decay}^{rounds})",
                    decay.powi(rounds)
                );
                ranked += p.ranked;
            }
            ranked_per_decay.push(ranked);
        }
        assert!(
            ranked_per_decay.windows(2).all(|w| w[0] < w[1]),
            "a slower decay ranks more candidates: {ranked_per_decay:?}"
        );
    }

    /// Every test valid; fitness is irrelevant to proposing.
    struct Anything;
    impl Sut for Anything {
        type Output = ();
        fn dim(&self) -> usize {
            3
        }
        fn is_valid(&self, _: &[f32]) -> bool {
            true
        }
        fn execute(&self, _: &[f32]) -> Option<Execution<()>> {
            Some(Execution {
                fitness: 0.0,
                execution_time_s: 0.0,
                output: (),
            })
        }
    }

    #[test]
    fn mutants_are_small_steps_from_the_best_test() {
        let mut rng = ChaCha20Rng::seed_from_u64(3);
        let cfg = WoganConfig {
            mutation: crate::MutationConfig {
                share: 1.0,
                parents: 1,
                reshape_probability: 0.0,
                ..Default::default()
            },
            ..WoganConfig::default()
        };
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut model = WoganModel::new(3, &cfg, &mut rng);
        let best = [0.8f32, -0.6, 0.1];
        for k in 0..12 {
            let t = sampler.sample(&mut rng);
            model.add(&t, 0.02 * f64::from(k));
        }
        model.add(&best, 0.9);
        model.train(0.0, &mut rng).unwrap();
        for _ in 0..5 {
            let p = model.propose(&Anything, &sampler, &mut rng).unwrap();
            assert_eq!(p.origin, Origin::Mutant);
            for (c, b) in p.test.iter().zip(best) {
                assert!(
                    (c - b).abs() <= cfg.mutation.max_step + 1e-6,
                    "{:?}",
                    p.test
                );
            }
        }
        // Without mutation every proposal is the generator's.
        let mut paper = WoganModel::new(3, &WoganConfig::default(), &mut rng);
        paper.add(&best, 0.9);
        paper.add(&[0.0, 0.0, 0.0], 0.1);
        paper.train(0.0, &mut rng).unwrap();
        assert_eq!(
            paper.propose(&Anything, &sampler, &mut rng).unwrap().origin,
            Origin::Generator
        );
    }

    #[test]
    fn with_novelty_no_proposal_lies_near_an_executed_test() {
        let novelty = crate::NoveltyConfig {
            distance: 0.3,
            min_fitness: 0.5,
            ..crate::NoveltyConfig::default()
        };
        let cfg = WoganConfig {
            novelty: novelty.clone(),
            ..WoganConfig::default()
        };
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut rng = ChaCha20Rng::seed_from_u64(5);
        let mut model = WoganModel::new(3, &cfg, &mut rng);
        let mut anchors = Vec::new();
        for k in 0..30 {
            let t = sampler.sample(&mut rng);
            // Every third test reaches the fitness that keeps candidates away.
            let fitness = if k % 3 == 0 { 0.9 } else { 0.1 };
            if fitness >= novelty.min_fitness {
                anchors.push(t.clone());
            }
            model.add(&t, fitness);
        }
        model.train(0.0, &mut rng).unwrap();
        for _ in 0..20 {
            let p = model.propose(&Anything, &sampler, &mut rng).unwrap();
            // A proposal the analyzer ranked is novel; a random fallback need not be.
            if p.predicted.is_some() {
                let nearest = anchors
                    .iter()
                    .map(|a| rms_distance(a, &p.test))
                    .fold(f32::MAX, f32::min);
                assert!(nearest >= novelty.distance, "{nearest} from {:?}", p.test);
            }
            assert_eq!(p.invalid, 0, "skipped candidates are not invalid ones");
        }
    }

    /// Every test valid; a test's shape is its running sum, as a road's heading sums its
    /// curvature.
    struct Summed;
    impl Sut for Summed {
        type Output = ();
        fn dim(&self) -> usize {
            3
        }
        fn is_valid(&self, _: &[f32]) -> bool {
            true
        }
        fn execute(&self, _: &[f32]) -> Option<Execution<()>> {
            None
        }
        fn shape(&self, test: &[f32]) -> Option<Vec<f32>> {
            Some(
                test.iter()
                    .scan(0.0, |sum, v| {
                        *sum += v;
                        Some(*sum)
                    })
                    .collect(),
            )
        }
    }

    #[test]
    fn with_shape_novelty_no_proposal_has_the_shape_of_a_failure() {
        let rule = crate::NoveltyConfig {
            distance: 0.4,
            min_fitness: 0.5,
            ..crate::NoveltyConfig::default()
        };
        let cfg = WoganConfig {
            shape_novelty: rule.clone(),
            ..WoganConfig::default()
        };
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut rng = ChaCha20Rng::seed_from_u64(6);
        let mut model = WoganModel::new(3, &cfg, &mut rng);
        let mut failure_shapes = Vec::new();
        for k in 0..30 {
            let t = sampler.sample(&mut rng);
            let fitness = if k % 3 == 0 { 0.9 } else { 0.1 };
            if fitness >= rule.min_fitness {
                failure_shapes.push(Summed.shape(&t).unwrap());
            }
            model.add_executed(&Summed, &t, fitness, None);
        }
        model.train(0.0, &mut rng).unwrap();
        let mut ranked = 0;
        for _ in 0..20 {
            let p = model.propose(&Summed, &sampler, &mut rng).unwrap();
            if p.predicted.is_some() {
                ranked += 1;
                let shape = Summed.shape(&p.test).unwrap();
                let nearest = failure_shapes
                    .iter()
                    .map(|a| rms_distance(a, &shape))
                    .fold(f32::MAX, f32::min);
                assert!(nearest >= rule.distance, "{nearest} from {:?}", p.test);
            }
        }
        assert!(ranked > 0, "every proposal fell back to random search");
    }

    /// Of 20 proposals of `model`: how many the analyzer ranked, and whether the shape of any of
    /// those lies nearer than `distance` (RMS) to one of `shapes`.
    fn ranked_proposal_nearer_than(
        model: &WoganModel,
        shapes: &[Vec<f32>],
        distance: f32,
        rng: &mut ChaCha20Rng,
    ) -> (usize, bool) {
        let sampler = Sampler::new(3, SamplerConfig::default());
        let (mut ranked, mut near) = (0, false);
        for _ in 0..20 {
            let p = model.propose(&Summed, &sampler, rng).unwrap();
            if p.predicted.is_some() {
                ranked += 1;
                let shape = Summed.shape(&p.test).unwrap();
                near |= shapes.iter().any(|a| rms_distance(a, &shape) < distance);
            }
        }
        (ranked, near)
    }

    #[test]
    fn with_niches_no_proposal_lies_in_a_closed_niche() {
        let niches = crate::NicheConfig {
            quota: 10,
            distance: 0.8,
            radius: 0.4,
            patience: 0,
            min_fitness: 0.5,
            between: BetweenNiches::Model,
            ..crate::NicheConfig::default()
        };
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut near_closed_seed = Vec::new();
        for quota in [niches.quota, 0] {
            let cfg = WoganConfig {
                niches: crate::NicheConfig {
                    quota,
                    ..niches.clone()
                },
                // Mutants of the failures would land in their niche.
                mutation: crate::MutationConfig {
                    share: 0.5,
                    ..crate::MutationConfig::default()
                },
                ..WoganConfig::default()
            };
            let mut rng = ChaCha20Rng::seed_from_u64(7);
            let mut model = WoganModel::new(3, &cfg, &mut rng);
            let mut seed_shape = None;
            // Failures near the first one fill its niche; the tenth closes it.
            let first = [0.2f32, -0.1, 0.3];
            for k in 0..30 {
                let mut t = sampler.sample(&mut rng);
                let fitness = if k % 3 == 0 { 0.9 } else { 0.1 };
                if fitness >= niches.min_fitness {
                    for (v, f) in t.iter_mut().zip(first) {
                        *v = f + 0.1 * (*v - f);
                    }
                    seed_shape.get_or_insert_with(|| Summed.shape(&t).unwrap());
                }
                model.add_executed(&Summed, &t, fitness, None);
            }
            assert_eq!(model.closed_niches(), usize::from(quota > 0));
            model.train(0.0, &mut rng).unwrap();
            let (ranked, near) = ranked_proposal_nearer_than(
                &model,
                &[seed_shape.unwrap()],
                niches.radius,
                &mut rng,
            );
            assert!(ranked > 0, "every proposal fell back to random search");
            near_closed_seed.push(near);
        }
        assert!(
            !near_closed_seed[0],
            "a ranked proposal lies in the closed niche"
        );
        // Without niches the same search proposes roads there: the rule is what keeps them out.
        assert!(near_closed_seed[1]);
    }

    #[test]
    fn the_failure_profiles_given_close_a_stale_niche() {
        let cfg = WoganConfig {
            niches: crate::NicheConfig {
                quota: 10,
                radius: 1.0,
                min_fitness: 0.5,
                stale: 2,
                repeat_distance: 0.1,
                ..crate::NicheConfig::default()
            },
            ..WoganConfig::default()
        };
        let closed_after_three_alike = |profile: Option<&[f32]>| {
            let mut rng = ChaCha20Rng::seed_from_u64(3);
            let mut model = WoganModel::new(3, &cfg, &mut rng);
            for k in 0..3 {
                let t = [0.1 * k as f32, 0.0, 0.0];
                model.add_executed(&Summed, &t, 0.9, profile);
                // A passing test's profile is never asked for; one given is not counted.
                model.add_executed(&Summed, &[0.5, 0.5, 0.5], 0.1, profile);
            }
            model.closed_niches()
        };
        // The seed and two repeats of it: stale.
        assert_eq!(closed_after_three_alike(Some(&[0.3, -0.2])), 1);
        // Without profiles no failure repeats another: the niche stays open below its quota.
        assert_eq!(closed_after_three_alike(None), 0);
    }

    #[test]
    fn between_niches_random_candidates_are_the_samplers_draws() {
        // One niche of 3 failures, closed: the next proposal comes from between niches.
        let cfg = |between| WoganConfig {
            niches: crate::NicheConfig {
                quota: 3,
                distance: 0.5,
                radius: 0.2,
                patience: 0,
                min_fitness: 0.5,
                between,
                ..crate::NicheConfig::default()
            },
            mutation: crate::MutationConfig {
                share: 0.5,
                ..crate::MutationConfig::default()
            },
            ..WoganConfig::default()
        };
        let sampler = Sampler::new(3, SamplerConfig::default());
        let proposal_and_draws = |between| {
            let mut rng = ChaCha20Rng::seed_from_u64(5);
            let mut model = WoganModel::new(3, &cfg(between), &mut rng);
            // Three failures near one another fill the first niche.
            let first = [0.2f32, -0.1, 0.3];
            for k in 0..12 {
                let mut t = sampler.sample(&mut rng);
                let fails = k < 3;
                if fails {
                    for (v, f) in t.iter_mut().zip(first) {
                        *v = f + 0.05 * (*v - f);
                    }
                }
                model.add_executed(&Summed, &t, if fails { 0.9 } else { 0.1 }, None);
            }
            model.train(0.0, &mut rng).unwrap();
            assert_eq!(model.closed_niches(), 1);
            // What the sampler would draw from here on, for as many candidates as the
            // acceptance rule can rank before its target reaches any prediction.
            let mut replay = rng.clone();
            let draws: Vec<Vec<f32>> = (0..4096).map(|_| sampler.sample(&mut replay)).collect();
            let p = model.propose(&Summed, &sampler, &mut rng).unwrap();
            (p, draws)
        };
        let (random, draws) = proposal_and_draws(BetweenNiches::Random);
        assert!(random.predicted.is_some(), "ranked, not a fallback");
        assert_eq!(random.origin, Origin::Generator);
        assert!(
            draws.contains(&random.test),
            "not one of the sampler's draws"
        );
        // The model's proposal is the generator's or a mutant's, not a random walk.
        let (model, draws) = proposal_and_draws(BetweenNiches::Model);
        assert!(!draws.contains(&model.test));
    }
}
