//! The paper's random test sampler (used by WOGAN's initial phase and the random baseline).
//!
//! A random walk: the first value is uniform in `[-1, 1]`, each next value moves by a uniform
//! step of at most `max_step`, clipped to `[-1, 1]`. Smooth vectors like these are far more
//! often valid roads than independent uniform values.

use rand::{Rng, RngExt};

use crate::config::SamplerConfig;
use crate::error::Error;
use crate::sut::Sut;

/// Validity checks between two looks at [`Sampler::should_go_on`]: a search for a valid test
/// can take millions of them, and a stop or an expired budget must end it.
const CHECKS_BETWEEN_LOOKS: usize = 1024;

/// Draws random test vectors, optionally until one is valid.
#[derive(Clone)]
pub struct Sampler<'a> {
    dim: usize,
    config: SamplerConfig,
    go_on: Option<&'a (dyn Fn() -> bool + Sync)>,
}

impl std::fmt::Debug for Sampler<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Sampler")
            .field("dim", &self.dim)
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

impl<'a> Sampler<'a> {
    /// A sampler of `dim`-long vectors.
    pub fn new(dim: usize, config: SamplerConfig) -> Self {
        Self {
            dim,
            config,
            go_on: None,
        }
    }

    /// The same sampler, giving up a search for valid tests (with [`Error::Interrupted`]) once
    /// `go_on` says no; `go_on` is asked every `CHECKS_BETWEEN_LOOKS` validity checks.
    pub fn interruptible(self, go_on: &'a (dyn Fn() -> bool + Sync)) -> Self {
        Self {
            go_on: Some(go_on),
            ..self
        }
    }

    /// Whether a search may go on (always, unless made [`Sampler::interruptible`]).
    pub fn should_go_on(&self) -> bool {
        self.go_on.is_none_or(|go_on| go_on())
    }

    /// One random walk, valid or not.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> Vec<f32> {
        let uniforms: Vec<f32> = (0..self.dim)
            .map(|_| rng.random_range(-1.0f32..=1.0))
            .collect();
        self.walk(&uniforms)
    }

    /// The walk made of `uniforms` in `[-1, 1]` (stgem's `UniformDependent` draws them in this
    /// order): the first is the first value, each next moves by `max_step` times its uniform.
    pub fn walk(&self, uniforms: &[f32]) -> Vec<f32> {
        let mut out: Vec<f32> = Vec::with_capacity(uniforms.len());
        for &u in uniforms {
            let next = match out.last() {
                None => u,
                Some(prev) => (prev + self.config.max_step * u).clamp(-1.0, 1.0),
            };
            out.push(next);
        }
        out
    }

    /// Samples until the SUT accepts a test; adds the rejected ones to `invalid`.
    pub fn sample_valid<S: Sut + ?Sized, R: Rng + ?Sized>(
        &self,
        sut: &S,
        rng: &mut R,
        invalid: &mut usize,
    ) -> Result<Vec<f32>, Error> {
        for attempt in 0..self.config.max_attempts {
            if attempt % CHECKS_BETWEEN_LOOKS == CHECKS_BETWEEN_LOOKS - 1 && !self.should_go_on() {
                return Err(Error::Interrupted);
            }
            let t = self.sample(rng);
            if sut.is_valid(&t) {
                return Ok(t);
            }
            *invalid += 1;
        }
        Err(Error::NoValidTest {
            attempts: self.config.max_attempts,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha20Rng;

    #[test]
    fn stays_in_range_with_bounded_steps() {
        let s = Sampler::new(7, SamplerConfig::default());
        let mut rng = ChaCha20Rng::seed_from_u64(1);
        let bound = 0.05 / 0.07 + 1e-6;
        let mut hit_edge = false;
        for _ in 0..5000 {
            let t = s.sample(&mut rng);
            assert_eq!(t.len(), 7);
            for w in t.windows(2) {
                assert!((w[1] - w[0]).abs() <= bound);
            }
            for v in &t {
                assert!((-1.0..=1.0).contains(v));
                hit_edge |= v.abs() == 1.0;
            }
        }
        assert!(hit_edge, "clipping at the edges should occur");
    }

    struct Never;
    impl Sut for Never {
        type Output = ();
        fn dim(&self) -> usize {
            2
        }
        fn is_valid(&self, _: &[f32]) -> bool {
            false
        }
        fn execute(&self, _: &[f32]) -> Option<crate::Execution<()>> {
            unreachable!()
        }
    }

    #[test]
    fn gives_up_after_max_attempts() {
        let s = Sampler::new(
            2,
            SamplerConfig {
                max_attempts: 10,
                ..SamplerConfig::default()
            },
        );
        let mut rng = ChaCha20Rng::seed_from_u64(1);
        let mut invalid = 0;
        assert!(s.sample_valid(&Never, &mut rng, &mut invalid).is_err());
        assert_eq!(invalid, 10);
    }
}
