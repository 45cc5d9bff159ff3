//! The WGAN generator: noise uniform in `[-1, 1]` → test vector in `(-1, 1)`.
//!
//! The layers are those stgem's `GeneratorNetwork` runs with batch normalisation on (its
//! `WOGAN_NN.forward`): `Linear(noise → h) → ReLU → Linear(h → h) → BatchNorm → ReLU →
//! Linear(h → d) → BatchNorm(d) → tanh`. The first hidden layer is not normalised, and the output
//! is normalised before tanh. That last normalisation matters: it keeps every output coordinate
//! spread over the batch, so the proposals cover the test space instead of collapsing onto the
//! few tests of a batch (`tests/reference/wogan/` pins the layout to stgem's own outputs).
//!
//! In training ([`Generator::train`]) batch normalisation uses batch statistics and moves the
//! running ones (including for the fakes of every critic step, as in stgem); in inference
//! ([`Generator::infer`]) the running statistics, which is how candidates are drawn.

use rand::{Rng, RngExt};

use super::batch_norm::{BatchNorm, BatchNormGrad, BatchNormTape};
use super::dense::{relu_grad, Dense, DenseGrad};
use super::matmul::Activation;
use super::matrix::Matrix;
use crate::config::GeneratorConfig;

/// Generator network.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Generator {
    /// Noise → hidden (stgem's `top`), ReLU without normalisation.
    pub input: Dense,
    /// Hidden → hidden (stgem's `hidden.0`).
    pub hidden: Dense,
    /// Normalises `hidden` before its ReLU (stgem's `norm.0`).
    pub hidden_norm: BatchNorm,
    /// Hidden → test (stgem's `bottom`).
    pub output: Dense,
    /// Normalises `output` before tanh (stgem's `norm.2`).
    pub output_norm: BatchNorm,
}

/// What the backward pass needs of a training forward pass.
pub(crate) struct GeneratorTape {
    noise: Matrix,
    h1: Matrix,
    hidden_norm: BatchNormTape,
    h2: Matrix,
    output_norm: BatchNormTape,
    out: Matrix,
}

/// The generator's parameter gradients, in the order of [`Generator::params_mut`].
pub(crate) struct GeneratorGrad {
    input: DenseGrad,
    hidden: DenseGrad,
    hidden_norm: BatchNormGrad,
    output: DenseGrad,
    output_norm: BatchNormGrad,
}

impl Generator {
    /// A generator with weights drawn from `rng`.
    pub fn new<R: Rng + ?Sized>(dim: usize, cfg: &GeneratorConfig, rng: &mut R) -> Self {
        Self {
            input: Dense::new(rng, cfg.noise_dim, cfg.hidden),
            hidden: Dense::new(rng, cfg.hidden, cfg.hidden),
            hidden_norm: BatchNorm::new(cfg.hidden),
            output: Dense::new(rng, cfg.hidden, dim),
            output_norm: BatchNorm::new(dim),
        }
    }

    /// Noise width.
    pub fn noise_dim(&self) -> usize {
        self.input.d_in()
    }

    /// Test vectors `[n, dim]` from noise `[n, noise_dim]`, normalised by the running statistics.
    pub fn infer(&self, noise: &Matrix) -> Matrix {
        let h = self.input.forward(noise, Activation::Relu);
        let mut h = self
            .hidden_norm
            .infer(&self.hidden.forward(&h, Activation::Identity));
        relu(&mut h);
        let mut out = self
            .output_norm
            .infer(&self.output.forward(&h, Activation::Identity));
        out.data.iter_mut().for_each(|v| *v = v.tanh());
        out
    }

    /// Test vectors `[n, dim]` from noise `[n, noise_dim]` (`n >= 2`), normalised by the batch's
    /// statistics, which move the running ones; with what the backward pass needs.
    pub fn train(&mut self, noise: &Matrix) -> GeneratorTape {
        let h1 = self.input.forward(noise, Activation::Relu);
        let (mut h2, hidden_norm) = self
            .hidden_norm
            .train(&self.hidden.forward(&h1, Activation::Identity));
        relu(&mut h2);
        let (mut out, output_norm) = self
            .output_norm
            .train(&self.output.forward(&h2, Activation::Identity));
        out.data.iter_mut().for_each(|v| *v = v.tanh());
        GeneratorTape {
            noise: noise.clone(),
            h1,
            hidden_norm,
            h2,
            output_norm,
            out,
        }
    }

    /// The parameter gradients given `d_out`, the gradient with respect to the output of the
    /// pass `tape` records.
    pub fn backward(&self, tape: &GeneratorTape, d_out: &Matrix) -> GeneratorGrad {
        let mut d = d_out.clone();
        for (g, y) in d.data.iter_mut().zip(&tape.out.data) {
            *g *= 1.0 - y * y;
        }
        let (output_norm, d) = self.output_norm.backward(&tape.output_norm, &d);
        let output = self.output.grad(&tape.h2, &d);
        let mut d = self.output.input_grad(&d);
        relu_grad(&mut d, &tape.h2);
        let (hidden_norm, d) = self.hidden_norm.backward(&tape.hidden_norm, &d);
        let hidden = self.hidden.grad(&tape.h1, &d);
        let mut d = self.hidden.input_grad(&d);
        relu_grad(&mut d, &tape.h1);
        let input = self.input.grad(&tape.noise, &d);
        GeneratorGrad {
            input,
            hidden,
            hidden_norm,
            output,
            output_norm,
        }
    }

    /// Its learnt parameter tensors, layer by layer.
    pub fn params_mut(&mut self) -> Vec<&mut [f32]> {
        let mut p = Vec::with_capacity(10);
        p.extend(self.input.params_mut());
        p.extend(self.hidden.params_mut());
        p.extend(self.hidden_norm.params_mut());
        p.extend(self.output.params_mut());
        p.extend(self.output_norm.params_mut());
        p
    }
}

impl GeneratorTape {
    /// The generated tests.
    pub fn output(&self) -> &Matrix {
        &self.out
    }
}

impl GeneratorGrad {
    /// Its tensors, in the order of [`Generator::params_mut`].
    pub fn tensors(&self) -> Vec<&[f32]> {
        let mut t = Vec::with_capacity(10);
        t.extend(self.input.tensors());
        t.extend(self.hidden.tensors());
        t.extend(self.hidden_norm.tensors());
        t.extend(self.output.tensors());
        t.extend(self.output_norm.tensors());
        t
    }
}

/// Uniform noise in `[-1, 1]` from the run's RNG, `[rows, cols]`.
pub(crate) fn uniform_noise<R: Rng + ?Sized>(rng: &mut R, rows: usize, cols: usize) -> Matrix {
    let v: Vec<f32> = (0..rows * cols)
        .map(|_| rng.random_range(-1.0f32..=1.0))
        .collect();
    Matrix::new(v, rows, cols)
}

fn relu(m: &mut Matrix) {
    m.data.iter_mut().for_each(|v| *v = v.max(0.0));
}
