//! Adam, updating parameters in place.
//!
//! The update is burn's `Adam` (the formula WOGAN's networks were first trained with, which
//! agrees with PyTorch's up to where epsilon sits): with `t` steps taken, per element in `f32`
//!
//! ```text
//! g ← g + decay·θ                       (coupled weight decay, when set)
//! m ← β1·m + (1 − β1)·g
//! v ← β2·v + (1 − β2)·g²
//! c2 = √(1 − β2ᵗ),  c = c2 / (1 − β1ᵗ)
//! θ ← θ − lr · (m·c) / (√v + ε·c2)
//! ```
//!
//! which is PyTorch's `θ − lr·m̂ / (√v̂ + ε)` multiplied through by `c2`.

/// Adam's settings.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AdamConfig {
    /// Learning rate.
    pub lr: f32,
    /// Decay of the first moment.
    pub beta1: f32,
    /// Decay of the second moment.
    pub beta2: f32,
    /// Added to the second moment's root.
    pub epsilon: f32,
    /// Coupled weight decay: `decay·θ` is added to each gradient.
    pub weight_decay: Option<f32>,
}

/// Adam's moments for a network's parameter tensors, in the order the network lists them.
#[derive(Debug, Clone)]
pub(crate) struct Adam {
    cfg: AdamConfig,
    time: i32,
    moments: Vec<(Vec<f32>, Vec<f32>)>,
}

impl Adam {
    /// No steps taken yet.
    pub fn new(cfg: AdamConfig) -> Self {
        Self {
            cfg,
            time: 0,
            moments: Vec::new(),
        }
    }

    /// One step: `params[i] ← params[i] − update(grads[i])`, tensor by tensor.
    pub fn step(&mut self, params: Vec<&mut [f32]>, grads: &[&[f32]]) {
        assert_eq!(params.len(), grads.len(), "a gradient per parameter tensor");
        if self.moments.is_empty() {
            self.moments = grads
                .iter()
                .map(|g| (vec![0.0; g.len()], vec![0.0; g.len()]))
                .collect();
        }
        self.time += 1;
        let AdamConfig {
            lr,
            beta1,
            beta2,
            epsilon,
            weight_decay,
        } = self.cfg;
        let c2 = (1.0 - beta2.powi(self.time)).sqrt();
        let c = c2 / (1.0 - beta1.powi(self.time));
        let eps = epsilon * c2;
        let (f1, f2) = (1.0 - beta1, 1.0 - beta2);
        for ((theta, g), (m, v)) in params.into_iter().zip(grads).zip(&mut self.moments) {
            assert_eq!(theta.len(), g.len(), "gradient shape");
            for (((t, g), m), v) in theta.iter_mut().zip(*g).zip(m).zip(v) {
                let g = match weight_decay {
                    Some(decay) => *t * decay + g,
                    None => *g,
                };
                *m = *m * beta1 + g * f1;
                *v = *v * beta2 + (g * g) * f2;
                *t -= (*m * c) / (v.sqrt() + eps) * lr;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_steps_move_by_about_the_learning_rate_against_the_gradient() {
        let mut adam = Adam::new(AdamConfig {
            lr: 0.1,
            beta1: 0.9,
            beta2: 0.999,
            epsilon: 1e-8,
            weight_decay: None,
        });
        let mut theta = vec![1.0f32, 1.0, 1.0];
        adam.step(vec![&mut theta], &[&[2.0, -0.5, 0.0]]);
        // Bias-corrected, the first step is lr · g / |g| (0 where g is).
        assert!((theta[0] - 0.9).abs() < 1e-6 && (theta[1] - 1.1).abs() < 1e-6);
        assert_eq!(theta[2], 1.0);
        adam.step(vec![&mut theta], &[&[2.0, -0.5, 0.0]]);
        assert!((theta[0] - 0.8).abs() < 1e-6, "{theta:?}");
    }

    #[test]
    fn weight_decay_adds_to_the_gradient() {
        let cfg = AdamConfig {
            lr: 0.1,
            beta1: 0.0,
            beta2: 0.999,
            epsilon: 1e-8,
            weight_decay: Some(1.0),
        };
        let mut theta = vec![2.0f32];
        // Gradient −2 cancels the decay 1·θ = 2: no move.
        Adam::new(cfg).step(vec![&mut theta], &[&[-2.0]]);
        assert_eq!(theta[0], 2.0);
    }
}
