//! A dense layer `x W + b` on plain `f32` matrices: seeded initialisation, the fused forward
//! pass and the gradients of its backward pass.
//!
//! Weights are drawn from the run's own RNG (PyTorch's default `U(-1/√fan_in, 1/√fan_in)`), all
//! weights then all biases, so a run is reproducible from its seed.

use rand::{Rng, RngExt};

use super::matmul::{matmul, matmul_at, matmul_bt, Activation, Epilogue};
use super::matrix::Matrix;

/// A dense layer with `W: [d_in, d_out]` (row-major) and `b: [d_out]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Dense {
    /// `[d_in, d_out]`.
    pub weight: Matrix,
    /// `[d_out]`.
    pub bias: Vec<f32>,
}

/// A dense layer's gradients, shaped as its parameters.
#[derive(Debug, Clone)]
pub(crate) struct DenseGrad {
    /// With respect to the weights.
    pub weight: Matrix,
    /// With respect to the bias.
    pub bias: Vec<f32>,
}

impl Dense {
    /// A `d_in → d_out` layer initialised from `rng`.
    pub fn new<R: Rng + ?Sized>(rng: &mut R, d_in: usize, d_out: usize) -> Self {
        let k = 1.0 / (d_in as f32).sqrt();
        let w: Vec<f32> = (0..d_in * d_out)
            .map(|_| rng.random_range(-k..=k))
            .collect();
        let b: Vec<f32> = (0..d_out).map(|_| rng.random_range(-k..=k)).collect();
        Self {
            weight: Matrix::new(w, d_in, d_out),
            bias: b,
        }
    }

    /// Input width.
    pub fn d_in(&self) -> usize {
        self.weight.rows
    }

    /// Output width.
    pub fn d_out(&self) -> usize {
        self.weight.cols
    }

    /// `activation(x W + b)` for `x: [n, d_in]`, in one pass.
    pub fn forward(&self, x: &Matrix, activation: Activation) -> Matrix {
        matmul(x, &self.weight, Epilogue::Layer(&self.bias, activation))
    }

    /// The gradients of its parameters given the layer's input `x: [n, d_in]` and the gradient
    /// `dy: [n, d_out]` with respect to its pre-activation output.
    pub fn grad(&self, x: &Matrix, dy: &Matrix) -> DenseGrad {
        DenseGrad {
            weight: matmul_at(x, dy),
            bias: column_sums(dy),
        }
    }

    /// The gradient with respect to the layer's input, `dy Wᵀ`.
    pub fn input_grad(&self, dy: &Matrix) -> Matrix {
        matmul_bt(dy, &self.weight)
    }

    /// Its parameter tensors, weights then bias.
    pub fn params_mut(&mut self) -> [&mut [f32]; 2] {
        [&mut self.weight.data, &mut self.bias]
    }
}

impl DenseGrad {
    /// Its tensors, in the order of [`Dense::params_mut`].
    pub fn tensors(&self) -> [&[f32]; 2] {
        [&self.weight.data, &self.bias]
    }
}

/// Each column's sum over the rows, in row order.
pub(crate) fn column_sums(m: &Matrix) -> Vec<f32> {
    let mut s = vec![0.0; m.cols];
    for row in m.data.chunks_exact(m.cols.max(1)) {
        add_to(&mut s, row);
    }
    s
}

/// `a += b` elementwise.
pub(crate) fn add_to(a: &mut [f32], b: &[f32]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

/// Zeroes the gradient `d` where the ReLU's output `h` is 0 (its input was not positive).
pub(crate) fn relu_grad(d: &mut Matrix, h: &Matrix) {
    // A select rather than a branch, so that it vectorises.
    for (g, y) in d.data.iter_mut().zip(&h.data) {
        *g = if *y > 0.0 { *g } else { 0.0 };
    }
}
