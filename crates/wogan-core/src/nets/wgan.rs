//! WGAN-GP training of the generator against the critic on one (bin-biased) batch.
//!
//! One epoch = `critic_steps` critic steps on the batch (fresh noise and interpolation weights
//! each step) followed by one generator step on a fresh noise batch, as in the reference.

use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use rand::{Rng, RngExt};

use super::critic::Critic;
use super::generator::Generator;
use super::layers::{matrix, scalar, uniform_noise};
use crate::config::{CriticConfig, GeneratorConfig, WganConfig};
use crate::error::Error;

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
    opt_g: ModuleOptimizer,
    opt_c: ModuleOptimizer,
    cfg: WganConfig,
    noise_dim: usize,
    device: Device,
}

impl Wgan {
    pub fn new<R: Rng + ?Sized>(
        dim: usize,
        g: &GeneratorConfig,
        c: &CriticConfig,
        cfg: &WganConfig,
        rng: &mut R,
        device: &Device,
    ) -> Self {
        let generator = Generator::new(dim, g, rng, device);
        let critic = Critic::new(dim, c, rng, device);
        Self::from_networks(generator, critic, cfg, device)
    }

    /// Both networks as given, with fresh optimisers.
    pub fn from_networks(
        generator: Generator,
        critic: Critic,
        cfg: &WganConfig,
        device: &Device,
    ) -> Self {
        // PyTorch's Adam epsilon: stgem passes only the learning rate and betas.
        let adam = AdamConfig::new()
            .with_beta_1(cfg.beta1)
            .with_beta_2(cfg.beta2)
            .with_epsilon(1e-8);
        Self {
            noise_dim: generator.input.weight.dims()[0],
            generator,
            critic,
            opt_g: adam.init(),
            opt_c: adam.init(),
            cfg: cfg.clone(),
            device: device.clone(),
        }
    }

    /// One epoch on `real: [m, d]`: `critic_steps` critic steps, then a generator step.
    pub fn epoch<R: Rng + ?Sized>(
        &mut self,
        real: Tensor<2>,
        rng: &mut R,
    ) -> Result<WganLosses, Error> {
        let m = real.dims()[0];
        let mut losses = WganLosses::default();
        // Batch normalisation needs two rows; the fake batch matches the real one for the
        // interpolates, but never drops below that.
        let fakes = m.max(2);
        for _ in 0..self.cfg.critic_steps {
            let noise = uniform_noise(rng, fakes, self.noise_dim, &self.device);
            let eps: Vec<f32> = (0..m).map(|_| rng.random::<f32>()).collect();
            let step = self.critic_step(real.clone(), noise, matrix(eps, m, 1, &self.device))?;
            losses.critic = step.loss;
            losses.penalty = step.penalty;
            losses.wasserstein = step.wasserstein;
        }
        let noise = uniform_noise(rng, self.cfg.noise_batch, self.noise_dim, &self.device);
        losses.generator = self.generator_step(noise)?;
        Ok(losses)
    }

    /// One critic step on `real: [m, d]` against the generator's output for `noise: [>= m,
    /// noise_dim]` (its first `m` rows), interpolating with `eps: [m, 1]`.
    ///
    /// The generator runs in training mode, so its batch statistics move with every critic
    /// step, as in stgem.
    pub fn critic_step(
        &mut self,
        real: Tensor<2>,
        noise: Tensor<2>,
        eps: Tensor<2>,
    ) -> Result<CriticStep, Error> {
        let m = real.dims()[0];
        let fake = self.generator.forward(noise).detach().slice(s![0..m, ..]);
        let out = self.critic.loss(real, fake, eps, self.cfg.gp_coef);
        let grads = GradientsParams::from_grads(out.loss.backward(), &self.critic);
        let step = CriticStep {
            loss: scalar(out.loss.detach())?,
            penalty: scalar(out.penalty)?,
            wasserstein: scalar(out.wasserstein)?,
        };
        let critic = self.critic.clone();
        self.critic = self.opt_c.step(self.cfg.lr, critic, grads);
        Ok(step)
    }

    /// One generator step on `noise: [n, noise_dim]`; returns its loss `−mean C(G(noise))`.
    pub fn generator_step(&mut self, noise: Tensor<2>) -> Result<f64, Error> {
        let loss = self
            .critic
            .forward(self.generator.forward(noise))
            .mean()
            .neg();
        // Only the generator's parameters are stepped; the critic's gradients are dropped.
        let grads = GradientsParams::from_grads(loss.backward(), &self.generator);
        let value = scalar(loss.detach())?;
        let generator = self.generator.clone();
        self.generator = self.opt_g.step(self.cfg.lr, generator, grads);
        Ok(value)
    }
}
