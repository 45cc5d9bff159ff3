//! The WGAN generator: noise uniform in `[-1, 1]` → hidden → hidden → test vector in `(-1, 1)`.
//!
//! Hidden layers are linear → batch normalisation → ReLU; the output is tanh so proposals land in
//! the normalised test space. On an autodiff device batch normalisation uses batch statistics
//! (training); on a plain device (see [`burn::module::Module::valid`]) its running statistics.

use burn::nn::{BatchNorm, BatchNormConfig, Linear};
use burn::prelude::*;
use burn::tensor::activation::{relu, tanh};
use rand::Rng;

use crate::config::GeneratorConfig;
use crate::nn::linear;

/// Generator network.
#[derive(Module, Debug)]
pub struct Generator {
    l1: Linear,
    bn1: BatchNorm,
    l2: Linear,
    bn2: BatchNorm,
    out: Linear,
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
            l1: linear(rng, cfg.noise_dim, cfg.hidden, device),
            bn1: BatchNormConfig::new(cfg.hidden).init(device),
            l2: linear(rng, cfg.hidden, cfg.hidden, device),
            bn2: BatchNormConfig::new(cfg.hidden).init(device),
            out: linear(rng, cfg.hidden, dim, device),
        }
    }

    /// Test vectors `[n, dim]` from noise `[n, noise_dim]`.
    pub fn forward(&self, noise: Tensor<2>) -> Tensor<2> {
        let h = relu(self.bn1.forward(self.l1.forward(noise)));
        let h = relu(self.bn2.forward(self.l2.forward(h)));
        tanh(self.out.forward(h))
    }
}
