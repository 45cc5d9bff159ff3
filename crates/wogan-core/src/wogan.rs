//! WOGAN's learning state: the data so far, the analyzer and the WGAN, one training round and
//! the choice of the next test (the body of the paper's Algorithm 1).
//!
//! The loop around it (random phase, retraining every few tests, budget, events) is in
//! [`crate::run`].

use burn::prelude::*;
use rand::seq::index;
use rand::Rng;

use crate::analyzer::{logit_target, AnalyzerTrainer};
use crate::bins::{bin_of, biased_batch};
use crate::config::WoganConfig;
use crate::error::Error;
use crate::nn::matrix;
use crate::sampler::Sampler;
use crate::sut::Sut;
use crate::wgan::Wgan;

/// Losses reported by one training round (those of its last steps).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrainStats {
    /// Analyzer loss (MSE on logits plus L2) before its last step.
    pub analyzer_loss: f64,
    /// Critic loss of the last critic step.
    pub critic_loss: f64,
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
    /// The analyzer's prediction, `None` when the generator gave up and a random test was drawn.
    pub predicted: Option<f64>,
    /// Invalid candidates (generated or random) rejected on the way.
    pub invalid: usize,
}

/// WOGAN's data and networks.
pub struct WoganModel {
    dim: usize,
    cfg: WoganConfig,
    device: Device,
    plain: Device,
    analyzer: AnalyzerTrainer,
    wgan: Wgan,
    tests: Vec<f32>,
    targets: Vec<f32>,
    bins: Vec<Vec<usize>>,
    bin_of_test: Vec<usize>,
    rounds: usize,
}

impl WoganModel {
    /// Fresh networks (weights drawn from `rng`) and no data.
    pub fn new<R: Rng + ?Sized>(dim: usize, cfg: &WoganConfig, rng: &mut R) -> Self {
        let device = Device::flex().autodiff();
        let analyzer = AnalyzerTrainer::new(dim, &cfg.analyzer, rng, &device);
        let wgan = Wgan::new(dim, &cfg.generator, &cfg.critic, &cfg.wgan, rng, &device);
        Self {
            dim,
            cfg: cfg.clone(),
            plain: device.clone().without_autodiff(),
            device,
            analyzer,
            wgan,
            tests: Vec::new(),
            targets: Vec::new(),
            bins: vec![Vec::new(); cfg.bins],
            bin_of_test: Vec::new(),
            rounds: 0,
        }
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
        let b = bin_of(fitness, self.cfg.bins);
        self.bins[b].push(idx);
        self.bin_of_test.push(b);
    }

    fn rows(&self, idx: &[usize]) -> Tensor<2> {
        let mut v = Vec::with_capacity(idx.len() * self.dim);
        for &i in idx {
            v.extend_from_slice(&self.tests[i * self.dim..(i + 1) * self.dim]);
        }
        matrix(v, idx.len(), self.dim, &self.device)
    }

    fn analyzer_batch<R: Rng + ?Sized>(&self, rng: &mut R) -> (Tensor<2>, Tensor<2>) {
        let n = self.len();
        if n <= self.cfg.analyzer.max_batch {
            let x = matrix(self.tests.clone(), n, self.dim, &self.device);
            let y = matrix(self.targets.clone(), n, 1, &self.device);
            (x, y)
        } else {
            let idx = index::sample(rng, n, self.cfg.analyzer.max_batch).into_vec();
            let y: Vec<f32> = idx.iter().map(|&i| self.targets[i]).collect();
            (self.rows(&idx), matrix(y, idx.len(), 1, &self.device))
        }
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
        let full = self.len() <= self.cfg.analyzer.max_batch;
        let mut fixed = if full { Some(self.analyzer_batch(rng)) } else { None };
        let mut stats = TrainStats::default();
        let n = self.len();
        let newest: Vec<(usize, usize)> = (n.saturating_sub(self.cfg.newest_in_batch)..n)
            .rev()
            .map(|i| (i, self.bin_of_test[i]))
            .collect();
        for _ in 0..epochs {
            for _ in 0..analyzer_epochs {
                let (x, y) = match &mut fixed {
                    Some((x, y)) => (x.clone(), y.clone()),
                    None => self.analyzer_batch(rng),
                };
                stats.analyzer_loss = self.analyzer.step(x, y)?;
            }
            let idx = biased_batch(&self.bins, &newest, self.cfg.batch_size, alpha, rng);
            let real = self.rows(&idx);
            let l = self.wgan.epoch(real, rng)?;
            stats.critic_loss = l.critic;
            stats.generator_loss = l.generator;
            stats.wasserstein_estimate = l.wasserstein;
        }
        self.rounds += 1;
        Ok(stats)
    }

    /// Chooses the next test: generator candidates, invalid ones dropped, the analyzer's best
    /// accepted once its prediction reaches a target that starts at 1 and decays each round.
    ///
    /// After `max_invalid_streak` invalid candidates in a row, a random valid test is returned.
    pub fn propose<S: Sut + ?Sized, R: Rng + ?Sized>(
        &self,
        sut: &S,
        sampler: &Sampler,
        rng: &mut R,
    ) -> Result<Proposal, Error> {
        let mut target = 1.0f64;
        let mut best: Option<(Vec<f32>, f64)> = None;
        let mut invalid = 0usize;
        let mut streak = 0usize;
        let batch = self.cfg.candidate_batch.max(2);
        loop {
            let cands = self.wgan.sample(batch, rng)?;
            let mut valid: Vec<f32> = Vec::new();
            for c in cands.chunks_exact(self.dim) {
                if sut.is_valid(c) {
                    streak = 0;
                    valid.extend_from_slice(c);
                } else {
                    invalid += 1;
                    streak += 1;
                    if streak >= self.cfg.max_invalid_streak {
                        let test = sampler.sample_valid(sut, rng, &mut invalid)?;
                        return Ok(Proposal {
                            test,
                            predicted: None,
                            invalid,
                        });
                    }
                }
            }
            if !valid.is_empty() {
                let n = valid.len() / self.dim;
                let x = matrix(valid.clone(), n, self.dim, &self.plain);
                let pred = self.analyzer.predict(x)?;
                for (c, p) in valid.chunks_exact(self.dim).zip(pred) {
                    let p = f64::from(p);
                    if best.as_ref().is_none_or(|(_, b)| p > *b) {
                        best = Some((c.to_vec(), p));
                    }
                }
            }
            if let Some((test, p)) = &best {
                if *p >= target {
                    return Ok(Proposal {
                        test: test.clone(),
                        predicted: Some(*p),
                        invalid,
                    });
                }
            }
            target *= self.cfg.target_decay;
        }
    }
}
