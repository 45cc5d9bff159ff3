//! Typed run configuration with the authors' SBST 2022 defaults.
//!
//! Every struct is `#[serde(default)]`, so a partial JSON object overrides only what it names.

use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::mutation::MutationConfig;

/// Which search algorithm a run uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Algorithm {
    /// The random sampler for the whole budget.
    Random,
    /// WOGAN: a random initial phase, then GAN proposals ranked by the analyzer.
    #[default]
    Wogan,
}

impl Algorithm {
    /// The name, as the run header spells it (`random`, `wogan`).
    pub fn name(self) -> &'static str {
        match self {
            Algorithm::Random => "random",
            Algorithm::Wogan => "wogan",
        }
    }
}

/// Everything a run needs besides the SUT, the budget and the seed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RunConfig {
    /// The search algorithm.
    pub algorithm: Algorithm,
    /// Tests executed at once in random phases (they are independent); results keep id order.
    pub jobs: usize,
    /// The random test sampler.
    pub sampler: SamplerConfig,
    /// WOGAN's settings (ignored by `random`).
    pub wogan: WoganConfig,
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            algorithm: Algorithm::default(),
            jobs: 1,
            sampler: SamplerConfig::default(),
            wogan: WoganConfig::default(),
        }
    }
}

/// The paper's random sampler: a random walk in normalised units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SamplerConfig {
    /// Largest step between consecutive values (0.05 curvature units of 0.07 = 0.714...).
    pub max_step: f32,
    /// Invalid samples tolerated in a row before the run gives up with an error.
    pub max_attempts: usize,
}

impl Default for SamplerConfig {
    fn default() -> Self {
        Self {
            max_step: 0.05 / 0.07,
            max_attempts: 1_000_000,
        }
    }
}

/// WOGAN's loop settings and its three networks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WoganConfig {
    /// Share of the budget spent on random tests before the first training.
    pub init_fraction: f64,
    /// Number of fitness bins over `[0, 1]`.
    pub bins: usize,
    /// Largest WGAN training batch of real tests.
    pub batch_size: usize,
    /// How many of the newest tests may join a training batch on their own merit.
    pub newest_in_batch: usize,
    /// Bin bias at the end of the budget (it rises linearly from 0).
    pub alpha_max: f64,
    /// Retrain after this many new tests.
    pub train_every: usize,
    /// WGAN epochs of the first training round.
    pub first_epochs: usize,
    /// Analyzer epochs per WGAN epoch in the first training round.
    pub first_analyzer_epochs: usize,
    /// WGAN epochs of later training rounds.
    pub later_epochs: usize,
    /// Analyzer epochs per WGAN epoch in later training rounds.
    pub later_analyzer_epochs: usize,
    /// Candidates generated and scored per network call (each valid one is a round).
    pub candidate_batch: usize,
    /// Factor applied to the acceptance target per valid candidate.
    pub target_decay: f64,
    /// Invalid candidates in a row after which a random valid test is executed instead.
    pub max_invalid_streak: usize,
    /// The generator network.
    pub generator: GeneratorConfig,
    /// The critic network.
    pub critic: CriticConfig,
    /// The analyzer network and its training.
    pub analyzer: AnalyzerConfig,
    /// WGAN-GP training.
    pub wgan: WganConfig,
    /// Mutants of the best tests among the candidates (an extension; off in the paper).
    pub mutation: MutationConfig,
}

impl Default for WoganConfig {
    fn default() -> Self {
        Self {
            init_fraction: 0.2,
            bins: 10,
            batch_size: 32,
            newest_in_batch: 3,
            alpha_max: 3.0,
            train_every: 3,
            first_epochs: 3,
            first_analyzer_epochs: 20,
            later_epochs: 2,
            later_analyzer_epochs: 10,
            candidate_batch: 32,
            target_decay: 0.95,
            max_invalid_streak: 100,
            generator: GeneratorConfig::default(),
            critic: CriticConfig::default(),
            analyzer: AnalyzerConfig::default(),
            wgan: WganConfig::default(),
            mutation: MutationConfig::default(),
        }
    }
}

impl WoganConfig {
    /// The decay under which the acceptance target falls to `level` after as many candidates as
    /// `target_decay` takes to fall to `reference_level`; `None` unless both are strictly
    /// between 0 and 1.
    ///
    /// The rule compares predictions with an absolute target, so its pressure depends on where a
    /// fitness puts its failures: this carries a decay tuned for one fitness to another that
    /// fails at a different level (`decay^(ln level / ln reference_level)`).
    pub fn matched_target_decay(&self, reference_level: f64, level: f64) -> Option<f64> {
        let inside = |v: f64| v > 0.0 && v < 1.0;
        (inside(reference_level) && inside(level))
            .then(|| self.target_decay.powf(level.ln() / reference_level.ln()))
    }
}

/// Generator: noise → hidden → hidden → d, ReLU; batch normalisation on the second hidden layer
/// and on the output, before tanh (stgem's layout).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GeneratorConfig {
    /// Noise dimension (noise is uniform in `[-1, 1]`).
    pub noise_dim: usize,
    /// Width of both hidden layers.
    pub hidden: usize,
}

impl Default for GeneratorConfig {
    fn default() -> Self {
        Self {
            noise_dim: 10,
            hidden: 128,
        }
    }
}

/// Critic: d → hidden → hidden → 1 with leaky ReLU.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CriticConfig {
    /// Width of both hidden layers.
    pub hidden: usize,
    /// Negative slope of the leaky ReLU (stgem calls `F.leaky_relu`, PyTorch's default 0.01).
    pub leaky_slope: f64,
}

impl Default for CriticConfig {
    fn default() -> Self {
        Self {
            hidden: 128,
            leaky_slope: 0.01,
        }
    }
}

/// Analyzer: d → hidden → hidden → 1, ReLU, sigmoid output; MSE on logits plus L2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AnalyzerConfig {
    /// Width of both hidden layers.
    pub hidden: usize,
    /// Adam learning rate.
    pub lr: f64,
    /// Adam beta 1.
    pub beta1: f32,
    /// Adam beta 2.
    pub beta2: f32,
    /// Coefficient of the squared L2 norm of all parameters.
    pub l2: f64,
    /// Most tests used by one analyzer epoch (a random sample once there are more).
    pub max_batch: usize,
}

impl Default for AnalyzerConfig {
    fn default() -> Self {
        Self {
            hidden: 32,
            lr: 0.001,
            beta1: 0.0,
            beta2: 0.9,
            l2: 0.01,
            max_batch: 512,
        }
    }
}

/// WGAN-GP training of generator and critic.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WganConfig {
    /// Adam learning rate of both networks.
    pub lr: f64,
    /// Adam beta 1.
    pub beta1: f32,
    /// Adam beta 2.
    pub beta2: f32,
    /// Gradient-penalty coefficient.
    pub gp_coef: f64,
    /// Critic steps per generator step.
    pub critic_steps: usize,
    /// Noise batch of the generator step.
    pub noise_batch: usize,
}

impl Default for WganConfig {
    fn default() -> Self {
        Self {
            lr: 0.00005,
            beta1: 0.0,
            beta2: 0.9,
            gp_coef: 10.0,
            critic_steps: 5,
            noise_batch: 32,
        }
    }
}

fn check(ok: bool, what: &str) -> Result<(), Error> {
    if ok {
        Ok(())
    } else {
        Err(Error::Config(what.to_string()))
    }
}

/// Names `field` unless `value` is a share or probability, in `[0, 1]`.
fn check_unit_interval(value: f64, field: &str) -> Result<(), Error> {
    check(
        (0.0..=1.0).contains(&value),
        &format!("{field} must be in [0, 1]"),
    )
}

/// Names `field` unless `value` is finite and not negative.
fn check_non_negative(value: f32, field: &str) -> Result<(), Error> {
    check(
        value.is_finite() && value >= 0.0,
        &format!("{field} must be finite and non-negative"),
    )
}

impl RunConfig {
    /// Rejects values the algorithms cannot work with.
    pub fn validate(&self) -> Result<(), Error> {
        check(self.jobs >= 1, "jobs must be at least 1")?;
        let s = &self.sampler;
        check_non_negative(s.max_step, "sampler.max_step")?;
        check(
            s.max_attempts >= 1,
            "sampler.max_attempts must be at least 1",
        )?;
        let w = &self.wogan;
        check_unit_interval(w.init_fraction, "wogan.init_fraction")?;
        check(w.bins >= 1, "wogan.bins must be at least 1")?;
        check(w.batch_size >= 1, "wogan.batch_size must be at least 1")?;
        check(w.alpha_max.is_finite(), "wogan.alpha_max must be finite")?;
        check(w.train_every >= 1, "wogan.train_every must be at least 1")?;
        check(
            w.candidate_batch >= 1,
            "wogan.candidate_batch must be at least 1",
        )?;
        check(
            w.target_decay > 0.0 && w.target_decay < 1.0,
            "wogan.target_decay must be in (0, 1)",
        )?;
        check(
            w.max_invalid_streak >= 1,
            "wogan.max_invalid_streak must be at least 1",
        )?;
        check(
            w.generator.noise_dim >= 1 && w.generator.hidden >= 1,
            "wogan.generator sizes must be at least 1",
        )?;
        check(
            w.critic.hidden >= 1,
            "wogan.critic.hidden must be at least 1",
        )?;
        check(
            w.critic.leaky_slope.is_finite(),
            "wogan.critic.leaky_slope must be finite",
        )?;
        check(
            w.analyzer.hidden >= 1 && w.analyzer.max_batch >= 1,
            "wogan.analyzer sizes must be at least 1",
        )?;
        check(
            w.analyzer.lr > 0.0 && w.wgan.lr > 0.0,
            "learning rates must be positive",
        )?;
        check(
            w.wgan.critic_steps >= 1 && w.wgan.noise_batch >= 2,
            "wogan.wgan.critic_steps must be >= 1 and noise_batch >= 2 (batch normalisation)",
        )?;
        let m = &w.mutation;
        check_unit_interval(m.share, "wogan.mutation.share")?;
        check(m.parents >= 1, "wogan.mutation.parents must be at least 1")?;
        check_non_negative(m.min_parent_distance, "wogan.mutation.min_parent_distance")?;
        check_non_negative(m.max_step, "wogan.mutation.max_step")?;
        check_unit_interval(m.reshape_probability, "wogan.mutation.reshape_probability")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matched_decay_reaches_its_level_in_as_many_candidates() {
        let paper = WoganConfig::default();
        assert_eq!(paper.matched_target_decay(0.1, 0.1), Some(0.95));
        let decay = paper.matched_target_decay(0.1, 0.435).unwrap();
        assert!((decay - 0.9816).abs() < 1e-4, "{decay}");
        let candidates = |decay: f64, level: f64| level.ln() / decay.ln();
        assert!((candidates(decay, 0.435) - candidates(0.95, 0.1)).abs() < 1e-9);
        // A level nearer 1 than the reference's needs a slower decay, and vice versa.
        assert!(paper.matched_target_decay(0.5, 0.9).unwrap() > 0.95);
        assert!(paper.matched_target_decay(0.5, 0.1).unwrap() < 0.95);
        for (reference, level) in [(0.0, 0.5), (0.5, 1.0), (1.0, 0.5), (0.5, -0.1)] {
            assert_eq!(paper.matched_target_decay(reference, level), None);
        }
    }

    #[test]
    fn partial_json_keeps_defaults() {
        let c: RunConfig =
            serde_json::from_str(r#"{"algorithm":"random","wogan":{"bins":5}}"#).unwrap();
        assert_eq!(c.algorithm, Algorithm::Random);
        assert_eq!(c.wogan.bins, 5);
        assert_eq!(c.wogan.batch_size, 32);
        assert!(c.validate().is_ok());
        let bad = RunConfig {
            jobs: 0,
            ..RunConfig::default()
        };
        assert!(bad.validate().is_err());
    }

    #[test]
    fn bad_mutation_settings_are_named() {
        for (json, field) in [
            (r#"{"share": 1.5}"#, "wogan.mutation.share"),
            (r#"{"parents": 0}"#, "wogan.mutation.parents"),
            (
                r#"{"min_parent_distance": -1}"#,
                "wogan.mutation.min_parent_distance",
            ),
            (r#"{"max_step": -0.1}"#, "wogan.mutation.max_step"),
            (
                r#"{"reshape_probability": 2}"#,
                "wogan.mutation.reshape_probability",
            ),
        ] {
            let mut c = RunConfig::default();
            c.wogan.mutation = serde_json::from_str(json).unwrap();
            let message = c.validate().unwrap_err().to_string();
            assert!(message.contains(field), "{json}: {message}");
        }
    }
}
