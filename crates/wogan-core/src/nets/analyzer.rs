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
//! `2·l2·w` is exactly what the term adds to the loss gradient.

use rand::Rng;

use super::adam::{Adam, AdamConfig};
use super::dense::{relu_grad, Dense, DenseGrad};
use super::matmul::Activation;
use super::matrix::Matrix;
use crate::config::AnalyzerConfig;

/// Analyzer network.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Analyzer {
    pub l1: Dense,
    pub l2: Dense,
    pub l3: Dense,
}

/// How far a fitness or prediction in `[0, 1]` is squeezed towards 0.5 before its logit.
const SQUEEZE: f64 = 0.98;

/// The logit target of a fitness value, as the analyzer is trained on it.
pub(crate) fn logit_target(fitness: f64) -> f32 {
    let y = SQUEEZE * fitness.clamp(0.0, 1.0) + (1.0 - SQUEEZE) / 2.0;
    (y / (1.0 - y)).ln() as f32
}

fn sigmoid(x: f32) -> f32 {
    1.0 / (1.0 + (-x).exp())
}

impl Analyzer {
    /// An analyzer with weights drawn from `rng`.
    pub fn new<R: Rng + ?Sized>(dim: usize, cfg: &AnalyzerConfig, rng: &mut R) -> Self {
        Self {
            l1: Dense::new(rng, dim, cfg.hidden),
            l2: Dense::new(rng, cfg.hidden, cfg.hidden),
            l3: Dense::new(rng, cfg.hidden, 1),
        }
    }

    /// Predicted fitness in `(0, 1)` of each row of `x: [n, d]`.
    pub fn predict(&self, x: &Matrix) -> Vec<f32> {
        let h = self.l1.forward(x, Activation::Relu);
        let h = self.l2.forward(&h, Activation::Relu);
        let out = self.l3.forward(&h, Activation::Identity);
        out.data.iter().map(|z| sigmoid(*z)).collect()
    }

    fn squared_norm(&self) -> f32 {
        let mut total = 0.0f32;
        for layer in [&self.l1, &self.l2, &self.l3] {
            total += layer.weight.data.iter().map(|w| w * w).sum::<f32>();
        }
        for layer in [&self.l1, &self.l2, &self.l3] {
            total += layer.bias.iter().map(|b| b * b).sum::<f32>();
        }
        total
    }

    /// Mean squared error of the predictions' squeezed logits against logit targets `[n]`, and
    /// its parameter gradients.
    fn mse(&self, x: &Matrix, target: &[f32]) -> (f32, [DenseGrad; 3]) {
        let h1 = self.l1.forward(x, Activation::Relu);
        let h2 = self.l2.forward(&h1, Activation::Relu);
        let out = self.l3.forward(&h2, Activation::Identity);
        let n = x.rows as f32;
        let squeeze = SQUEEZE as f32;
        let shift = ((1.0 - SQUEEZE) / 2.0) as f32;
        let mut sum = 0.0f32;
        let mut d = out.clone();
        for (g, t) in d.data.iter_mut().zip(target) {
            let p = sigmoid(*g);
            let q = p * squeeze + shift;
            let err = (q.ln() - (1.0 - q).ln()) - t;
            sum += err * err;
            // d/dz of err²/n through q = 0.98·σ(z) + 0.01 and logit(q).
            *g = 2.0 * err / n * (1.0 / q + 1.0 / (1.0 - q)) * squeeze * (p * (1.0 - p));
        }
        let g3 = self.l3.grad(&h2, &d);
        let mut d = self.l3.input_grad(&d);
        relu_grad(&mut d, &h2);
        let g2 = self.l2.grad(&h1, &d);
        let mut d = self.l2.input_grad(&d);
        relu_grad(&mut d, &h1);
        let g1 = self.l1.grad(x, &d);
        (sum / n, [g1, g2, g3])
    }

    /// Its parameter tensors, layer by layer (weights, bias).
    fn params_mut(&mut self) -> Vec<&mut [f32]> {
        let mut p = Vec::with_capacity(6);
        p.extend(self.l1.params_mut());
        p.extend(self.l2.params_mut());
        p.extend(self.l3.params_mut());
        p
    }
}

/// An analyzer with its optimiser.
#[derive(Debug, Clone)]
pub(crate) struct AnalyzerTrainer {
    pub model: Analyzer,
    adam: Adam,
    l2: f64,
}

impl AnalyzerTrainer {
    pub fn new<R: Rng + ?Sized>(dim: usize, cfg: &AnalyzerConfig, rng: &mut R) -> Self {
        Self::with_model(Analyzer::new(dim, cfg, rng), cfg)
    }

    /// Trains `model` as `cfg` says, with a fresh optimiser.
    pub fn with_model(model: Analyzer, cfg: &AnalyzerConfig) -> Self {
        Self {
            model,
            adam: Adam::new(AdamConfig {
                lr: cfg.lr as f32,
                beta1: cfg.beta1,
                beta2: cfg.beta2,
                epsilon: 1e-8,
                weight_decay: Some(2.0 * cfg.l2 as f32),
            }),
            l2: cfg.l2,
        }
    }

    /// One Adam step on inputs `x: [n, d]` and logit targets `[n]`; with `report`, returns the
    /// full loss (MSE plus L2) before the step.
    pub fn step(&mut self, x: &Matrix, target: &[f32], report: bool) -> Option<f64> {
        let (mse, grads) = self.model.mse(x, target);
        let value = report.then(|| f64::from(mse) + f64::from(self.model.squared_norm()) * self.l2);
        let grads: Vec<&[f32]> = grads.iter().flat_map(DenseGrad::tensors).collect();
        self.adam.step(self.model.params_mut(), &grads);
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    #[test]
    fn learns_a_simple_function() {
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
        let mut t = AnalyzerTrainer::new(d, &AnalyzerConfig::default(), &mut rng);
        let x = Matrix::new(xs, n, d);
        let first = t.step(&x, &ys, true).unwrap();
        for _ in 0..300 {
            assert!(t.step(&x, &ys, false).is_none());
        }
        let last = t.step(&x, &ys, true).unwrap();
        eprintln!("analyzer loss {first} -> {last}");
        assert!(last < 0.5 * first, "loss {first} → {last}");
        let probe = Matrix::new(vec![-0.9, 0.0, 0.0, 0.9, 0.0, 0.0], 2, d);
        let p = t.model.predict(&probe);
        assert!(p[1] > p[0] + 0.3, "predictions {p:?}");
    }
}
