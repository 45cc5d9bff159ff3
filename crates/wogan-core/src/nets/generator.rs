//! The WGAN generator: noise uniform in `[-1, 1]` → test vector in `(-1, 1)`.
//!
//! The layers are those stgem's `GeneratorNetwork` runs with batch normalisation on (its
//! `WOGAN_NN.forward`): `Linear(noise → h) → ReLU → Linear(h → h) → BatchNorm → ReLU →
//! Linear(h → d) → BatchNorm(d) → tanh`. The first hidden layer is not normalised, and the output
//! is normalised before tanh. That last normalisation matters: it keeps every output coordinate
//! spread over the batch, so the proposals cover the test space instead of collapsing onto the
//! few tests of a batch (`tests/reference/wogan/` pins the layout to stgem's own outputs).
//!
//! On an autodiff device batch normalisation uses batch statistics and moves the running ones
//! (training, including the fakes of every critic step, as in stgem); on a plain device (see
//! [`burn::module::Module::valid`]) the running statistics, which is how candidates are drawn.

use burn::nn::Linear;
use burn::prelude::*;
use burn::tensor::activation::{relu, tanh};
use rand::Rng;

use super::batch_norm::BatchNorm;
use super::layers::linear;
use crate::config::GeneratorConfig;

/// Generator network.
#[derive(Module, Debug)]
pub struct Generator {
    /// Noise → hidden (stgem's `top`), ReLU without normalisation.
    pub(crate) input: Linear,
    /// Hidden → hidden (stgem's `hidden.0`).
    pub(crate) hidden: Linear,
    /// Normalises `hidden` before its ReLU (stgem's `norm.0`).
    pub(crate) hidden_norm: BatchNorm,
    /// Hidden → test (stgem's `bottom`).
    pub(crate) output: Linear,
    /// Normalises `output` before tanh (stgem's `norm.2`).
    pub(crate) output_norm: BatchNorm,
}

impl Generator {
    /// A generator with weights drawn from `rng`.
    pub fn new<R: Rng + ?Sized>(
        dim: usize,
        cfg: &GeneratorConfig,
        rng: &mut R,
        device: &Device,
    ) -> Self {
        Self {
            input: linear(rng, cfg.noise_dim, cfg.hidden, device),
            hidden: linear(rng, cfg.hidden, cfg.hidden, device),
            hidden_norm: BatchNorm::new(cfg.hidden, device),
            output: linear(rng, cfg.hidden, dim, device),
            output_norm: BatchNorm::new(dim, device),
        }
    }

    /// Test vectors `[n, dim]` from noise `[n, noise_dim]`.
    pub fn forward(&self, noise: Tensor<2>) -> Tensor<2> {
        let h = relu(self.input.forward(noise));
        let h = relu(self.hidden_norm.forward(self.hidden.forward(h)));
        tanh(self.output_norm.forward(self.output.forward(h)))
    }
}
