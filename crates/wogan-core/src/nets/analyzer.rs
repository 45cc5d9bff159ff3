//! The analyzer: a small regression network predicting a test's fitness.
//!
//! `d → hidden → hidden → 1`, ReLU, sigmoid output. Its loss is stgem's `"MSE,logit"`: the
//! mean squared error between `logit(0.98·p + 0.01)` of the *prediction* `p` (the sigmoid's
//! output) and of the fitness `y` (squeezing into `[0.01, 0.99]` keeps both logits finite), plus
//! `l2 ×` the squared L2 norm of all its parameters (weights and biases); Adam with the
//! configured learning rate and betas. Squeezing the prediction bounds what a prediction can
//! cost, so a few confidently wrong tests do not dominate the loss as they would against the raw
//! pre-sigmoid output. One analyzer epoch is one Adam step on all tests, or on `max_batch` of
//! them sampled without replacement once there are more.
//!
//! The L2 term is applied as Adam's coupled weight decay with penalty `2·l2`: its gradient
//! `2·l2·w` is exactly what the term adds to the loss gradient, and it costs a few optimiser
//! operations instead of a dozen more graph nodes per step.

use burn::nn::Linear;
use burn::optim::decay::WeightDecayConfig;
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use burn::tensor::activation::{relu, sigmoid};
use rand::Rng;

use super::layers::{scalar, three_layers};
use crate::config::AnalyzerConfig;
use crate::error::Error;

/// Analyzer network.
#[derive(Module, Debug)]
pub struct Analyzer {
    pub(crate) l1: Linear,
    pub(crate) l2: Linear,
    pub(crate) l3: Linear,
}

/// How far a fitness or prediction in `[0, 1]` is squeezed towards 0.5 before its logit.
const SQUEEZE: f64 = 0.98;

/// The logit target of a fitness value, as the analyzer is trained on it.
pub(crate) fn logit_target(fitness: f64) -> f32 {
    let y = SQUEEZE * fitness.clamp(0.0, 1.0) + (1.0 - SQUEEZE) / 2.0;
    (y / (1.0 - y)).ln() as f32
}

/// `logit(0.98·p + 0.01)` of predictions `p` in `[0, 1]`.
fn squeezed_logit(p: Tensor<2>) -> Tensor<2> {
    let q = p.mul_scalar(SQUEEZE).add_scalar((1.0 - SQUEEZE) / 2.0);
    q.clone().log() - q.neg().add_scalar(1.0).log()
}

impl Analyzer {
    /// An analyzer with weights drawn from `rng`.
    pub fn new<R: Rng + ?Sized>(
        dim: usize,
        cfg: &AnalyzerConfig,
        rng: &mut R,
        device: &Device,
    ) -> Self {
        let [l1, l2, l3] = three_layers(rng, dim, cfg.hidden, device);
        Self { l1, l2, l3 }
    }

    /// Pre-sigmoid outputs `[n, 1]`.
    pub fn logits(&self, x: Tensor<2>) -> Tensor<2> {
        let h = relu(self.l1.forward(x));
        let h = relu(self.l2.forward(h));
        self.l3.forward(h)
    }

    /// Predicted fitness `[n, 1]` in `(0, 1)`.
    pub fn predict(&self, x: Tensor<2>) -> Tensor<2> {
        sigmoid(self.logits(x))
    }

    fn squared_norm(&self) -> Tensor<1> {
        let mut total = self.l1.weight.val().powi_scalar(2).sum();
        for w in [self.l2.weight.val(), self.l3.weight.val()] {
            total = total + w.powi_scalar(2).sum();
        }
        for b in [&self.l1.bias, &self.l2.bias, &self.l3.bias]
            .into_iter()
            .flatten()
        {
            total = total + b.val().powi_scalar(2).sum();
        }
        total
    }

    /// Mean squared error of the predictions' squeezed logits against logit targets `[n, 1]`.
    pub(crate) fn mse(&self, x: Tensor<2>, target: Tensor<2>) -> Tensor<1> {
        (squeezed_logit(self.predict(x)) - target)
            .powi_scalar(2)
            .mean()
    }
}

/// An analyzer with its optimiser.
pub(crate) struct AnalyzerTrainer {
    pub model: Analyzer,
    optim: ModuleOptimizer,
    lr: f64,
    l2: f64,
}

impl AnalyzerTrainer {
    pub fn new<R: Rng + ?Sized>(
        dim: usize,
        cfg: &AnalyzerConfig,
        rng: &mut R,
        device: &Device,
    ) -> Self {
        Self::with_model(Analyzer::new(dim, cfg, rng, device), cfg)
    }

    /// Trains `model` as `cfg` says, with a fresh optimiser.
    pub fn with_model(model: Analyzer, cfg: &AnalyzerConfig) -> Self {
        Self {
            model,
            optim: AdamConfig::new()
                .with_beta_1(cfg.beta1)
                .with_beta_2(cfg.beta2)
                .with_epsilon(1e-8)
                .with_weight_decay(Some(WeightDecayConfig::new(2.0 * cfg.l2 as f32)))
                .init(),
            lr: cfg.lr,
            l2: cfg.l2,
        }
    }

    /// One Adam step; with `report`, returns the full loss (MSE plus L2) before the step.
    pub fn step(
        &mut self,
        x: Tensor<2>,
        target: Tensor<2>,
        report: bool,
    ) -> Result<Option<f64>, Error> {
        let mse = self.model.mse(x, target);
        let grads = GradientsParams::from_grads(mse.backward(), &self.model);
        let value = if report {
            let l2 = scalar(self.model.squared_norm().detach())? * self.l2;
            Some(scalar(mse.detach())? + l2)
        } else {
            None
        };
        let model = self.model.clone();
        self.model = self.optim.step(self.lr, model, grads);
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    #[test]
    fn learns_a_simple_function() {
        let device = Device::flex().autodiff();
        let mut rng = ChaCha20Rng::seed_from_u64(7);
        let d = 3;
        let n = 128;
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for _ in 0..n {
            let x: Vec<f32> = (0..d).map(|_| rng.random_range(-1.0f32..1.0)).collect();
            // Fitness rises with the first coordinate.
            let f = f64::from((x[0] + 1.0) / 2.0);
            xs.extend(x);
            ys.push(logit_target(f));
        }
        let mut t = AnalyzerTrainer::new(d, &AnalyzerConfig::default(), &mut rng, &device);
        let x = crate::nets::layers::matrix(xs, n, d, &device);
        let y = crate::nets::layers::matrix(ys, n, 1, &device);
        let first = t.step(x.clone(), y.clone(), true).unwrap().unwrap();
        for _ in 0..300 {
            assert!(t.step(x.clone(), y.clone(), false).unwrap().is_none());
        }
        let last = t.step(x.clone(), y.clone(), true).unwrap().unwrap();
        eprintln!("analyzer loss {first} -> {last}");
        assert!(last < 0.5 * first, "loss {first} → {last}");
        let probe = crate::nets::layers::matrix(
            vec![-0.9, 0.0, 0.0, 0.9, 0.0, 0.0],
            2,
            d,
            &device.clone().without_autodiff(),
        );
        let p = crate::nets::layers::values(t.model.valid().predict(probe)).unwrap();
        assert!(p[1] > p[0] + 0.3, "predictions {p:?}");
    }
}
