//! WGAN-GP training of the generator against the critic on one (bin-biased) batch.
//!
//! One epoch = `critic_steps` critic steps on the batch (fresh noise and interpolation weights
//! each step) followed by one generator step on a fresh noise batch, as in the reference.

use rand::{Rng, RngExt};

use super::adam::{Adam, AdamConfig};
use super::critic::Critic;
use super::generator::{uniform_noise, Generator};
use super::matrix::Matrix;
use crate::config::{CriticConfig, GeneratorConfig, WganConfig};

/// What one critic step measured.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct CriticStep {
    /// `mean C(fake) − mean C(real) + penalty`.
    pub loss: f64,
    /// The gradient penalty, coefficient included.
    pub penalty: f64,
    /// `mean C(real) − mean C(fake)`.
    pub wasserstein: f64,
}

/// Losses of the last steps of one epoch.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct WganLosses {
    pub critic: f64,
    pub penalty: f64,
    pub generator: f64,
    pub wasserstein: f64,
}

/// Generator, critic and their optimisers.
pub(crate) struct Wgan {
    pub generator: Generator,
    pub critic: Critic,
    opt_g: Adam,
    opt_c: Adam,
    cfg: WganConfig,
}

impl Wgan {
    pub fn new<R: Rng + ?Sized>(
        dim: usize,
        g: &GeneratorConfig,
        c: &CriticConfig,
        cfg: &WganConfig,
        rng: &mut R,
    ) -> Self {
        let generator = Generator::new(dim, g, rng);
        let critic = Critic::new(dim, c, rng);
        Self::from_networks(generator, critic, cfg)
    }

    /// Both networks as given, with fresh optimisers.
    pub fn from_networks(generator: Generator, critic: Critic, cfg: &WganConfig) -> Self {
        // PyTorch's Adam epsilon: stgem passes only the learning rate and betas.
        let adam = AdamConfig {
            lr: cfg.lr as f32,
            beta1: cfg.beta1,
            beta2: cfg.beta2,
            epsilon: 1e-8,
            weight_decay: None,
        };
        Self {
            generator,
            critic,
            opt_g: Adam::new(adam),
            opt_c: Adam::new(adam),
            cfg: cfg.clone(),
        }
    }

    /// One epoch on `real: [m, d]`: `critic_steps` critic steps, then a generator step.
    pub fn epoch<R: Rng + ?Sized>(&mut self, real: &Matrix, rng: &mut R) -> WganLosses {
        let m = real.rows;
        let noise_dim = self.generator.noise_dim();
        let mut losses = WganLosses::default();
        // Batch normalisation needs two rows; the fake batch matches the real one for the
        // interpolates, but never drops below that.
        let fakes = m.max(2);
        for _ in 0..self.cfg.critic_steps {
            let noise = uniform_noise(rng, fakes, noise_dim);
            let eps: Vec<f32> = (0..m).map(|_| rng.random::<f32>()).collect();
            let step = self.critic_step(real, &noise, &eps);
            losses.critic = step.loss;
            losses.penalty = step.penalty;
            losses.wasserstein = step.wasserstein;
        }
        let noise = uniform_noise(rng, self.cfg.noise_batch, noise_dim);
        losses.generator = self.generator_step(&noise);
        losses
    }

    /// One critic step on `real: [m, d]` against the generator's output for `noise: [>= m,
    /// noise_dim]` (its first `m` rows), interpolating with `eps: [m]`.
    ///
    /// The generator runs in training mode, so its batch statistics move with every critic
    /// step, as in stgem.
    pub fn critic_step(&mut self, real: &Matrix, noise: &Matrix, eps: &[f32]) -> CriticStep {
        let m = real.rows;
        let fake = self.generator.train(noise).output().row_range(0, m);
        let (loss, grads) = self.critic.loss(real, &fake, eps, self.cfg.gp_coef as f32);
        self.opt_c.step(self.critic.params_mut(), &grads.tensors());
        CriticStep {
            loss: f64::from(loss.loss),
            penalty: f64::from(loss.penalty),
            wasserstein: f64::from(loss.wasserstein),
        }
    }

    /// One generator step on `noise: [n, noise_dim]`; returns its loss `−mean C(G(noise))`.
    pub fn generator_step(&mut self, noise: &Matrix) -> f64 {
        let tape = self.generator.train(noise);
        // Only the generator's parameters are stepped; the critic only passes the gradient on.
        let (mean, d_out) = self.critic.mean_and_input_grad(tape.output(), -1.0);
        let grads = self.generator.backward(&tape, &d_out);
        self.opt_g
            .step(self.generator.params_mut(), &grads.tensors());
        f64::from(-mean)
    }
}
