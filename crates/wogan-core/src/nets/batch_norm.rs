//! Batch normalisation over a batch of rows, as PyTorch's `BatchNorm1d` computes it.
//!
//! In training each feature is normalised with the batch's mean and biased variance, and the
//! running statistics move towards the batch's by `momentum`; the running variance takes the
//! *unbiased* batch variance (`n/(n-1)` times the biased one), as PyTorch does (burn's own
//! `BatchNorm` keeps the biased one, 3% lower at a batch of 32 and half at a batch of 2, and
//! WOGAN generates its candidates with these running statistics). In inference the running
//! statistics normalise.

use super::dense::column_sums;
use super::matrix::Matrix;

/// PyTorch's default momentum of the running statistics.
const MOMENTUM: f32 = 0.1;
/// PyTorch's default epsilon added to the variance.
const EPSILON: f32 = 1e-5;

/// Batch normalisation of `features` columns with a learnt scale (`gamma`) and shift (`beta`).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BatchNorm {
    /// Learnt scale.
    pub gamma: Vec<f32>,
    /// Learnt shift.
    pub beta: Vec<f32>,
    /// Running mean (inference).
    pub running_mean: Vec<f32>,
    /// Running variance (inference).
    pub running_var: Vec<f32>,
}

/// What the backward pass needs of a training forward pass.
#[derive(Debug, Clone)]
pub(crate) struct BatchNormTape {
    /// The normalised input, `(x − mean) / std`.
    normalised: Matrix,
    /// `1 / std` per feature.
    inv_std: Vec<f32>,
}

/// The gradients of a batch normalisation's parameters.
#[derive(Debug, Clone)]
pub(crate) struct BatchNormGrad {
    /// With respect to `gamma`.
    pub gamma: Vec<f32>,
    /// With respect to `beta`.
    pub beta: Vec<f32>,
}

impl BatchNorm {
    /// Scale 1, shift 0, running mean 0 and variance 1 (PyTorch's initial state).
    pub fn new(features: usize) -> Self {
        Self {
            gamma: vec![1.0; features],
            beta: vec![0.0; features],
            running_mean: vec![0.0; features],
            running_var: vec![1.0; features],
        }
    }

    /// Normalises `x: [n, features]` with the running statistics.
    pub fn infer(&self, x: &Matrix) -> Matrix {
        let std: Vec<f32> = self
            .running_var
            .iter()
            .map(|v| (v + EPSILON).sqrt())
            .collect();
        let mut out = x.clone();
        for row in out.data.chunks_exact_mut(x.cols) {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (*v - self.running_mean[j]) / std[j] * self.gamma[j] + self.beta[j];
            }
        }
        out
    }

    /// Normalises `x: [n, features]` (`n >= 2`) with the batch's statistics and moves the
    /// running ones towards them.
    pub fn train(&mut self, x: &Matrix) -> (Matrix, BatchNormTape) {
        let n = x.rows;
        let nf = n as f32;
        let mean: Vec<f32> = column_sums(x).into_iter().map(|s| s / nf).collect();
        let mut centred = x.clone();
        for row in centred.data.chunks_exact_mut(x.cols) {
            for (v, m) in row.iter_mut().zip(&mean) {
                *v -= m;
            }
        }
        let mut var = vec![0.0f32; x.cols];
        for row in centred.data.chunks_exact(x.cols) {
            for (s, v) in var.iter_mut().zip(row) {
                *s += v * v;
            }
        }
        for v in &mut var {
            *v /= nf;
        }
        let std: Vec<f32> = var.iter().map(|v| (v + EPSILON).sqrt()).collect();
        let mut out = centred.clone();
        for (row, c_row) in out
            .data
            .chunks_exact_mut(x.cols)
            .zip(centred.data.chunks_exact_mut(x.cols))
        {
            for j in 0..row.len() {
                let normalised = c_row[j] / std[j];
                c_row[j] = normalised;
                row[j] = normalised * self.gamma[j] + self.beta[j];
            }
        }
        let unbiased = (n as f64 / (n.max(2) - 1) as f64) as f32;
        for j in 0..x.cols {
            self.running_mean[j] = self.running_mean[j] * (1.0 - MOMENTUM) + mean[j] * MOMENTUM;
            self.running_var[j] =
                self.running_var[j] * (1.0 - MOMENTUM) + (var[j] * unbiased) * MOMENTUM;
        }
        let tape = BatchNormTape {
            normalised: centred,
            inv_std: std.iter().map(|s| 1.0 / s).collect(),
        };
        (out, tape)
    }

    /// The gradients of `gamma`, `beta` and the input, given `dy`, the gradient with respect to
    /// the output of the training pass `tape` records.
    pub fn backward(&self, tape: &BatchNormTape, dy: &Matrix) -> (BatchNormGrad, Matrix) {
        let cols = dy.cols;
        let nf = dy.rows as f32;
        let beta = column_sums(dy);
        let mut gamma = vec![0.0f32; cols];
        for (d_row, x_row) in dy
            .data
            .chunks_exact(cols)
            .zip(tape.normalised.data.chunks_exact(cols))
        {
            for j in 0..cols {
                gamma[j] += d_row[j] * x_row[j];
            }
        }
        // With x̂ the normalised input and g = dy·γ the gradient reaching it:
        // dx = (g − mean(g) − x̂·mean(g·x̂)) / std, and mean(g) = γ·Σdy/n, mean(g·x̂) = γ·Σdy·x̂/n.
        let mean_g: Vec<f32> = (0..cols).map(|j| self.gamma[j] * beta[j] / nf).collect();
        let mean_gx: Vec<f32> = (0..cols).map(|j| self.gamma[j] * gamma[j] / nf).collect();
        let mut dx = dy.clone();
        for (d_row, x_row) in dx
            .data
            .chunks_exact_mut(cols)
            .zip(tape.normalised.data.chunks_exact(cols))
        {
            for j in 0..cols {
                let g = d_row[j] * self.gamma[j];
                d_row[j] = (g - mean_g[j] - x_row[j] * mean_gx[j]) * tape.inv_std[j];
            }
        }
        (BatchNormGrad { gamma, beta }, dx)
    }

    /// Its learnt parameter tensors, `gamma` then `beta`.
    pub fn params_mut(&mut self) -> [&mut [f32]; 2] {
        [&mut self.gamma, &mut self.beta]
    }
}

impl BatchNormGrad {
    /// Its tensors, in the order of [`BatchNorm::params_mut`].
    pub fn tensors(&self) -> [&[f32]; 2] {
        [&self.gamma, &self.beta]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn training_normalises_by_the_batch_and_keeps_the_unbiased_variance() {
        let mut bn = BatchNorm::new(1);
        // One feature, values 1 and 3: mean 2, biased variance 1, unbiased 2.
        let (out, _) = bn.train(&Matrix::new(vec![1.0, 3.0], 2, 1));
        let expected = 1.0 / (1.0f32 + 1e-5).sqrt();
        assert!((out.data[0] + expected).abs() < 1e-6 && (out.data[1] - expected).abs() < 1e-6);
        let (mean, var) = (bn.running_mean[0], bn.running_var[0]);
        assert!((mean - 0.2).abs() < 1e-6, "running mean {mean}");
        assert!(
            (var - (0.9 + 0.1 * 2.0)).abs() < 1e-6,
            "running variance {var}"
        );
        // Inference uses the running statistics.
        assert!(bn.infer(&Matrix::new(vec![0.2], 1, 1)).data[0].abs() < 1e-6);
    }

    #[test]
    fn the_input_gradient_matches_finite_differences() {
        let x = Matrix::new(vec![0.3, -1.0, 2.0, 0.5, -0.7, 0.1, 1.5, 0.2, -0.4], 3, 3);
        let mut bn = BatchNorm::new(3);
        bn.gamma = vec![1.5, -0.5, 0.8];
        // Loss Σ w ⊙ out with fixed weights w.
        let w: Vec<f32> = (0..9).map(|i| (i as f32 * 0.37).sin()).collect();
        let loss = |x: &Matrix| -> f64 {
            let (out, _) = bn.clone().train(x);
            out.data.iter().zip(&w).map(|(o, w)| f64::from(o * w)).sum()
        };
        let (_, tape) = bn.clone().train(&x);
        let (grad, dx) = bn.backward(&tape, &Matrix::new(w.clone(), 3, 3));
        for i in 0..9 {
            let (mut a, mut b) = (x.clone(), x.clone());
            a.data[i] += 1e-3;
            b.data[i] -= 1e-3;
            let fd = (loss(&a) - loss(&b)) / 2e-3;
            assert!(
                (fd - f64::from(dx.data[i])).abs() < 2e-3,
                "{i}: {fd} vs {}",
                dx.data[i]
            );
        }
        // β's gradient is Σ dy; γ's is Σ dy·x̂.
        assert!((grad.beta[0] - (w[0] + w[3] + w[6])).abs() < 1e-6);
        assert!(grad.gamma.iter().all(|g| g.is_finite()));
    }
}
