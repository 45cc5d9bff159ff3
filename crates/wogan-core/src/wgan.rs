//! WGAN-GP training of the generator against the critic on one (bin-biased) batch.
//!
//! One epoch = `critic_steps` critic steps on the batch (fresh noise and interpolation weights
//! each step) followed by one generator step on a fresh noise batch, as in the reference.

use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use rand::{Rng, RngExt};

use crate::config::{CriticConfig, GeneratorConfig, WganConfig};
use crate::critic::Critic;
use crate::error::Error;
use crate::generator::Generator;
use crate::nn::{matrix, scalar, uniform_noise};

/// Losses of the last steps of one epoch.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct WganLosses {
    pub critic: f64,
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
        let adam = AdamConfig::new()
            .with_beta_1(cfg.beta1)
            .with_beta_2(cfg.beta2)
            .with_epsilon(1e-8);
        Self {
            generator: Generator::new(dim, g, rng, device),
            critic: Critic::new(dim, c, rng, device),
            opt_g: adam.init(),
            opt_c: adam.init(),
            cfg: cfg.clone(),
            noise_dim: g.noise_dim,
            device: device.clone(),
        }
    }

    /// One epoch on `real: [m, d]`.
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
        for step in 0..self.cfg.critic_steps {
            let noise = uniform_noise(rng, fakes, self.noise_dim, &self.device);
            let fake = self.generator.forward(noise).detach().slice(s![0..m, ..]);
            let eps: Vec<f32> = (0..m).map(|_| rng.random::<f32>()).collect();
            let eps = matrix(eps, m, 1, &self.device);
            let out = self.critic.loss(real.clone(), fake, eps, self.cfg.gp_coef);
            let grads = GradientsParams::from_grads(out.loss.backward(), &self.critic);
            if step + 1 == self.cfg.critic_steps {
                losses.critic = scalar(out.loss.detach())?;
                losses.wasserstein = scalar(out.wasserstein)?;
            }
            let critic = self.critic.clone();
            self.critic = self.opt_c.step(self.cfg.lr, critic, grads);
        }
        let noise = uniform_noise(rng, self.cfg.noise_batch, self.noise_dim, &self.device);
        let loss = self
            .critic
            .forward(self.generator.forward(noise))
            .mean()
            .neg();
        // Only the generator's parameters are stepped; the critic's gradients are dropped.
        let grads = GradientsParams::from_grads(loss.backward(), &self.generator);
        losses.generator = scalar(loss.detach())?;
        let generator = self.generator.clone();
        self.generator = self.opt_g.step(self.cfg.lr, generator, grads);
        Ok(losses)
    }
}
