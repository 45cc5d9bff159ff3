//! The WGAN critic and its loss with an exact gradient penalty.
//!
//! burn's autodiff has no double backward, so the critic's gradient with respect to its input is
//! written out as a tensor expression of its weights. For
//! `x → h1 = lrelu(x W1 + b1) → h2 = lrelu(h1 W2 + b2) → out = h2 W3 + b3`,
//! `∇x out = ((W3ᵀ ⊙ s2) W2ᵀ ⊙ s1) W1ᵀ`, where `s1`, `s2` are the leaky-ReLU slopes (1 or α) at
//! the pre-activations. The slopes are piecewise constant in the weights, so treating them as
//! detached constants is exact (away from the kinks, a null set), and one ordinary backward of
//! `critic(fake) − critic(real) + penalty` yields exact parameter gradients.

use burn::nn::Linear;
use burn::prelude::*;
use rand::Rng;

use super::layers::{slopes, three_layers};
use crate::config::CriticConfig;

/// Added under the square root of the gradient norm (the reference's value).
const GP_EPS: f64 = 1e-6;

/// Critic network `d → hidden → hidden → 1` with leaky ReLU (stgem's `CriticNetwork`).
#[derive(Module, Debug)]
pub struct Critic {
    pub(crate) l1: Linear,
    pub(crate) l2: Linear,
    pub(crate) l3: Linear,
    pub(crate) slope: f64,
}

/// The critic loss and the Wasserstein estimate of one step.
pub(crate) struct CriticLoss {
    /// `mean C(fake) − mean C(real) + penalty`, with its graph.
    pub loss: Tensor<1>,
    /// The gradient penalty, coefficient included (detached).
    pub penalty: Tensor<1>,
    /// `mean C(real) − mean C(fake)` (detached).
    pub wasserstein: Tensor<1>,
}

impl Critic {
    /// A critic with weights drawn from `rng`.
    pub fn new<R: Rng + ?Sized>(
        dim: usize,
        cfg: &CriticConfig,
        rng: &mut R,
        device: &Device,
    ) -> Self {
        let [l1, l2, l3] = three_layers(rng, dim, cfg.hidden, device);
        Self {
            l1,
            l2,
            l3,
            slope: cfg.leaky_slope,
        }
    }

    /// Critic values `[n, 1]`.
    pub fn forward(&self, x: Tensor<2>) -> Tensor<2> {
        let h1 = burn::tensor::activation::leaky_relu(self.l1.forward(x), self.slope);
        let h2 = burn::tensor::activation::leaky_relu(self.l2.forward(h1), self.slope);
        self.l3.forward(h2)
    }

    /// WGAN-GP critic loss on `m` real and `m` fake rows; `eps: [m, 1]` mixes the interpolates.
    ///
    /// Real, fake and interpolates go through the network as one concatenated batch, which is
    /// what keeps this cheap: per-operation overhead dominates at these sizes.
    pub(crate) fn loss(
        &self,
        real: Tensor<2>,
        fake: Tensor<2>,
        eps: Tensor<2>,
        gp_coef: f64,
    ) -> CriticLoss {
        let m = real.dims()[0];
        let interp = real.clone() * eps.clone() + fake.clone() * eps.neg().add_scalar(1.0);
        let x = Tensor::cat(vec![real, fake, interp], 0);
        let p1 = self.l1.forward(x);
        let s1 = slopes(p1.clone(), self.slope);
        let p2 = self.l2.forward(p1 * s1.clone());
        let s2 = slopes(p2.clone(), self.slope);
        let out = self.l3.forward(p2 * s2.clone());
        let real_mean = out.clone().slice(s![0..m, ..]).mean();
        let fake_mean = out.slice(s![m..2 * m, ..]).mean();

        let s1 = s1.slice(s![2 * m..3 * m, ..]);
        let s2 = s2.slice(s![2 * m..3 * m, ..]);
        let w1 = self.l1.weight.val();
        let w2 = self.l2.weight.val();
        let w3 = self.l3.weight.val();
        let g = (s2 * w3.transpose()).matmul(w2.transpose()) * s1;
        let g = g.matmul(w1.transpose());
        // The reference's epsilon keeps sqrt differentiable should a gradient vanish exactly.
        let norm = g.powi_scalar(2).sum_dim(1).add_scalar(GP_EPS).sqrt();
        let penalty = norm
            .sub_scalar(1.0)
            .powi_scalar(2)
            .mean()
            .mul_scalar(gp_coef);

        let wasserstein = (real_mean.clone() - fake_mean.clone()).detach();
        CriticLoss {
            loss: fake_mean - real_mean + penalty.clone(),
            penalty: penalty.detach(),
            wasserstein,
        }
    }
}

#[cfg(test)]
mod tests {
    //! Gradient check: burn's autodiff gradients of the full loss against central finite
    //! differences of an independent f64 implementation of the same loss.
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    use crate::nets::layers::values;

    struct F64Critic {
        d: usize,
        h: usize,
        slope: f64,
        // w1 [d,h], b1 [h], w2 [h,h], b2 [h], w3 [h], b3
        p: Vec<f64>,
    }

    impl F64Critic {
        fn sizes(&self) -> [usize; 6] {
            [self.d * self.h, self.h, self.h * self.h, self.h, self.h, 1]
        }
        fn part(&self, p: &[f64], k: usize) -> std::ops::Range<usize> {
            let s = self.sizes();
            let start: usize = s[..k].iter().sum();
            let _ = p;
            start..start + s[k]
        }
        fn act(&self, v: f64) -> (f64, f64) {
            if v > 0.0 {
                (v, 1.0)
            } else {
                (self.slope * v, self.slope)
            }
        }
        /// Critic value and its input gradient (by the chain rule, written independently).
        fn eval(&self, p: &[f64], x: &[f64]) -> (f64, Vec<f64>) {
            let (d, h) = (self.d, self.h);
            let w1 = &p[self.part(p, 0)];
            let b1 = &p[self.part(p, 1)];
            let w2 = &p[self.part(p, 2)];
            let b2 = &p[self.part(p, 3)];
            let w3 = &p[self.part(p, 4)];
            let b3 = p[self.part(p, 5)][0];
            let mut h1 = vec![0.0; h];
            let mut s1 = vec![0.0; h];
            for j in 0..h {
                let z: f64 = b1[j] + (0..d).map(|i| x[i] * w1[i * h + j]).sum::<f64>();
                (h1[j], s1[j]) = self.act(z);
            }
            let mut h2 = vec![0.0; h];
            let mut s2 = vec![0.0; h];
            for k in 0..h {
                let z: f64 = b2[k] + (0..h).map(|j| h1[j] * w2[j * h + k]).sum::<f64>();
                (h2[k], s2[k]) = self.act(z);
            }
            let out = b3 + (0..h).map(|k| h2[k] * w3[k]).sum::<f64>();
            // d out / d h1_j = sum_k w3_k s2_k w2_jk ; d out / d x_i = sum_j (..) s1_j w1_ij
            let g2: Vec<f64> = (0..h).map(|k| w3[k] * s2[k]).collect();
            let g1: Vec<f64> = (0..h)
                .map(|j| s1[j] * (0..h).map(|k| g2[k] * w2[j * h + k]).sum::<f64>())
                .collect();
            let gx = (0..d)
                .map(|i| (0..h).map(|j| g1[j] * w1[i * h + j]).sum::<f64>())
                .collect();
            (out, gx)
        }
        fn loss(
            &self,
            p: &[f64],
            real: &[Vec<f64>],
            fake: &[Vec<f64>],
            eps: &[f64],
            coef: f64,
        ) -> f64 {
            let m = real.len() as f64;
            let mut l = 0.0;
            for (i, (r, f)) in real.iter().zip(fake).enumerate() {
                l += (self.eval(p, f).0 - self.eval(p, r).0) / m;
                let xi: Vec<f64> = r.iter().zip(f).map(|(a, b)| b + (a - b) * eps[i]).collect();
                let g = self.eval(p, &xi).1;
                let n = (g.iter().map(|v| v * v).sum::<f64>() + GP_EPS).sqrt();
                l += coef * (n - 1.0).powi(2) / m;
            }
            l
        }
    }

    fn check(with_penalty_in_burn: bool) -> f64 {
        let device = Device::flex().autodiff();
        let mut rng = ChaCha20Rng::seed_from_u64(11);
        let (d, h, m) = (3, 8, 4);
        let cfg = CriticConfig {
            hidden: h,
            leaky_slope: 0.1,
        };
        let critic = Critic::new(d, &cfg, &mut rng, &device);
        let rows = |rng: &mut ChaCha20Rng| -> Vec<Vec<f64>> {
            (0..m)
                .map(|_| {
                    (0..d)
                        .map(|_| f64::from(rng.random_range(-1.0f32..1.0)))
                        .collect()
                })
                .collect()
        };
        let real = rows(&mut rng);
        let fake = rows(&mut rng);
        let eps: Vec<f64> = (0..m)
            .map(|_| f64::from(rng.random_range(0.0f32..1.0)))
            .collect();
        let to_t = |r: &[Vec<f64>]| {
            let v: Vec<f32> = r.iter().flatten().map(|x| *x as f32).collect();
            crate::nets::layers::matrix(v, m, d, &device)
        };
        let eps_t =
            crate::nets::layers::matrix(eps.iter().map(|e| *e as f32).collect(), m, 1, &device);
        let coef = if with_penalty_in_burn { 10.0 } else { 0.0 };
        let loss = critic.loss(to_t(&real), to_t(&fake), eps_t, coef).loss;
        let grads = loss.backward();
        let tensors: Vec<Tensor<1>> = vec![
            critic.l1.weight.val().grad(&grads).unwrap().flatten(0, 1),
            critic.l1.bias.as_ref().unwrap().val().grad(&grads).unwrap(),
            critic.l2.weight.val().grad(&grads).unwrap().flatten(0, 1),
            critic.l2.bias.as_ref().unwrap().val().grad(&grads).unwrap(),
            critic.l3.weight.val().grad(&grads).unwrap().flatten(0, 1),
            critic.l3.bias.as_ref().unwrap().val().grad(&grads).unwrap(),
        ];
        let autodiff: Vec<f64> = tensors
            .into_iter()
            .flat_map(|t| values(t).unwrap())
            .map(f64::from)
            .collect();
        let params: Vec<f64> = [
            critic.l1.weight.val().flatten::<1>(0, 1),
            critic.l1.bias.as_ref().unwrap().val(),
            critic.l2.weight.val().flatten::<1>(0, 1),
            critic.l2.bias.as_ref().unwrap().val(),
            critic.l3.weight.val().flatten::<1>(0, 1),
            critic.l3.bias.as_ref().unwrap().val(),
        ]
        .into_iter()
        .flat_map(|t| values(t.detach()).unwrap())
        .map(f64::from)
        .collect();
        let reference = F64Critic {
            d,
            h,
            slope: 0.1,
            p: params.clone(),
        };

        // The f64 input gradient must itself match finite differences in x.
        let x0 = &real[0];
        let (_, gx) = reference.eval(&reference.p, x0);
        for i in 0..d {
            let mut a = x0.clone();
            let mut b = x0.clone();
            a[i] += 1e-6;
            b[i] -= 1e-6;
            let fd = (reference.eval(&params, &a).0 - reference.eval(&params, &b).0) / 2e-6;
            assert!(
                (fd - gx[i]).abs() < 1e-6,
                "input gradient {i}: {fd} vs {}",
                gx[i]
            );
        }

        let step = 1e-6;
        let mut fd = Vec::with_capacity(params.len());
        for i in 0..params.len() {
            let mut a = params.clone();
            let mut b = params.clone();
            a[i] += step;
            b[i] -= step;
            fd.push(
                (reference.loss(&a, &real, &fake, &eps, 10.0)
                    - reference.loss(&b, &real, &fake, &eps, 10.0))
                    / (2.0 * step),
            );
        }
        let norm = fd.iter().map(|v| v * v).sum::<f64>().sqrt();
        let err = autodiff
            .iter()
            .zip(&fd)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        err / norm
    }

    #[test]
    fn gradient_penalty_parameter_gradients_match_finite_differences() {
        let rel = check(true);
        eprintln!("relative gradient error with penalty {rel}");
        assert!(rel < 1e-4, "relative gradient error {rel}");
    }

    #[test]
    fn gradient_check_detects_a_missing_penalty() {
        // The same comparison with the penalty left out of burn's loss must fail clearly,
        // showing the check above has teeth.
        let rel = check(false);
        eprintln!("relative gradient error without penalty {rel}");
        assert!(rel > 1e-2, "relative gradient error {rel} should be large");
    }
}
