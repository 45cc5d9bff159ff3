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
        let k = Coefficients {
            lr,
            beta1,
            beta2,
            f1: 1.0 - beta1,
            f2: 1.0 - beta2,
            c: c2 / (1.0 - beta1.powi(self.time)),
            eps: epsilon * c2,
            decay: weight_decay,
        };
        for ((theta, g), (m, v)) in params.into_iter().zip(grads).zip(&mut self.moments) {
            assert_eq!(theta.len(), g.len(), "gradient shape");
            assert!(m.len() == g.len() && v.len() == g.len(), "moment shape");
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                // SAFETY: `update_avx2` is compiled for AVX2, which this CPU has; it is otherwise
                // `update`, and without fused multiply-adds it rounds exactly as `update` does.
                unsafe { update_avx2(theta, g, m, v, &k) };
                continue;
            }
            update(theta, g, m, v, &k);
        }
    }
}

/// One step's scalars.
struct Coefficients {
    lr: f32,
    beta1: f32,
    beta2: f32,
    f1: f32,
    f2: f32,
    c: f32,
    eps: f32,
    decay: Option<f32>,
}

/// The update of one tensor, element by element.
#[inline(always)]
fn update(theta: &mut [f32], g: &[f32], m: &mut [f32], v: &mut [f32], k: &Coefficients) {
    for (((t, g), m), v) in theta.iter_mut().zip(g).zip(m).zip(v) {
        let g = match k.decay {
            Some(decay) => *t * decay + g,
            None => *g,
        };
        *m = *m * k.beta1 + g * k.f1;
        *v = *v * k.beta2 + (g * g) * k.f2;
        *t -= (*m * k.c) / (v.sqrt() + k.eps) * k.lr;
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn update_avx2(theta: &mut [f32], g: &[f32], m: &mut [f32], v: &mut [f32], k: &Coefficients) {
    update(theta, g, m, v, k);
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
