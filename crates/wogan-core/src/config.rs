//! Typed run configuration with the authors' SBST 2022 defaults.
//!
//! Every struct is `#[serde(default)]`, so a partial JSON object overrides only what it names.

use serde::{Deserialize, Serialize};

use crate::error::Error;

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
    /// Tests executed at once: random tests in groups of `jobs`, and in the WOGAN phase rounds
    /// of up to `jobs` chosen tests; results keep id order. 1 is the paper's WOGAN.
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
    /// Candidates near tests executed before are skipped (an extension; off in the paper).
    pub novelty: NoveltyConfig,
    /// Candidates whose shape (`Sut::shape`) is near the shape of tests executed before are
    /// skipped, the distance in the shape's units (an extension; off in the paper).
    pub shape_novelty: NoveltyConfig,
    /// Failures are gathered in niches filled one after another, kept apart by shape
    /// (`Sut::shape`; an extension; off in the paper).
    pub niches: NicheConfig,
    /// Failing tests remade Frenetic's four ways, each remake executed once (an extension; off
    /// in the paper).
    pub remakes: RemakeConfig,
    /// How the acceptance target carries over between the tests of one round when several are
    /// chosen at once (`jobs` > 1); with one test per round both rules are the paper's.
    pub round_acceptance: RoundAcceptance,
}

/// How the acceptance target carries over between the tests chosen in one round.
///
/// `Restart` is the default because it keeps the quality per test of choosing one test at a
/// time, which continuing the target did not in rounds of 4 (20 seeds, docs/results.md).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RoundAcceptance {
    /// Each later test of the round is accepted against the target as the previous choice left
    /// it (decayed further per candidate): cheaper, but later tests of a round are less selected.
    Continue,
    /// Each test of the round is chosen as a test alone is, from a target of 1: as selective
    /// as one test per round, at the cost of ranking as many candidates per test.
    #[default]
    Restart,
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
            novelty: NoveltyConfig::default(),
            shape_novelty: NoveltyConfig::default(),
            niches: NicheConfig::default(),
            remakes: RemakeConfig::default(),
            round_acceptance: RoundAcceptance::default(),
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

/// How many candidates are mutants and how far they move.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MutationConfig {
    /// Share of candidates that are mutants (0 = the paper's WOGAN).
    pub share: f64,
    /// Parents are drawn uniformly from this many of the highest-fitness tests.
    pub parents: usize,
    /// A test becomes a parent only this far (Euclidean, normalised units) from every
    /// higher-fitness parent, so that mutants spread over several regions (0: the best tests,
    /// however close together).
    pub min_parent_distance: f32,
    /// Largest change of one value (normalised units).
    pub max_step: f32,
    /// Probability that a mutant is also reversed, half-swapped or mirrored.
    pub reshape_probability: f64,
    /// A reshape may also shift every value along the test by 1 to this many places, either
    /// way, round the ends: a road's bends move along it unchanged (0: no shift, only Frenetic's
    /// three reshapes).
    pub shift_places: usize,
}

impl Default for MutationConfig {
    fn default() -> Self {
        Self {
            share: 0.0,
            parents: 8,
            min_parent_distance: 0.5,
            max_step: 0.15,
            reshape_probability: 0.25,
            shift_places: 0,
        }
    }
}

/// Which candidates are too near the tests executed before to be ranked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NoveltyConfig {
    /// A candidate is ranked only at least this far (root mean square of the value differences,
    /// normalised units) from every executed test of fitness `min_fitness` or more (0: off, the
    /// paper's WOGAN).
    pub distance: f32,
    /// Only tests of at least this fitness keep candidates away (0: every test; a failure's
    /// fitness: only failures).
    pub min_fitness: f64,
    /// How many such tests may lie nearer than `distance` before a candidate is skipped (0: any
    /// one does; more: a neighbourhood fills up to this many before the search must leave it).
    pub allowed_neighbours: usize,
}

/// Niches of failures filled one after another: a niche is a ball of shapes around a seed
/// failure; the search ranks only candidates inside the open niche until it holds `quota`
/// failures, then skips that ball, and the next failure far enough from every seed opens the next.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct NicheConfig {
    /// Failures a niche holds before it is closed (0: off, the paper's WOGAN).
    pub quota: usize,
    /// A failure seeds a niche only at least this far from every seed before it (root mean
    /// square of the shape differences, the shape's units: radians for a road's heading profile).
    pub distance: f32,
    /// A niche's radius around its seed, in the same units.
    pub radius: f32,
    /// Executed tests after which, between niches, the failure farthest from every seed seeds
    /// the next niche though nearer than `distance` (0: never).
    pub patience: usize,
    /// Tests of at least this fitness are the failures that seed and fill niches (the SUT's
    /// failure threshold).
    pub min_fitness: f64,
    /// Where the candidates ranked between niches come from.
    pub between: BetweenNiches,
    /// A niche is closed before its quota once this many of its failures in a row were repeats:
    /// each within `repeat_distance` of a failure found before it, by the SUT's failure profile
    /// ([`crate::Sut::failure_profile`]; 0: never, the quota alone closes a niche).
    pub stale: usize,
    /// Two failures whose profiles lie nearer than this are one failure found twice (root mean
    /// square of the profile differences, the profile's units: radians for a road's exit profile).
    pub repeat_distance: f32,
}

impl NicheConfig {
    /// Whether these settings make niches: a quota and a radius.
    pub fn are_on(&self) -> bool {
        self.quota > 0 && self.radius > 0.0
    }

    /// Whether niches close when they stop yielding new failures, and so want failing
    /// executions' profiles ([`crate::Sut::failure_profile`]).
    pub fn want_failure_profiles(&self) -> bool {
        self.are_on() && self.stale > 0
    }

    /// The profile of a failing execution `output` of `fitness` when the niches want it.
    pub(crate) fn failure_profile<S: crate::Sut + ?Sized>(
        &self,
        sut: &S,
        fitness: f64,
        output: &S::Output,
    ) -> Option<Vec<f32>> {
        if self.want_failure_profiles() && fitness >= self.min_fitness {
            sut.failure_profile(output)
        } else {
            None
        }
    }
}

/// Frenetic's systematic use of its operators: every failing test, unless itself a remake, is
/// remade four ways (mirrored, its values reversed, driven backwards: reversed and mirrored, its
/// halves swapped), and each remake that is valid and novel is executed once, before the networks
/// propose again. A remake keeps the failure's bends and changes where and how the car meets
/// them, so it is a likely failure of another kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct RemakeConfig {
    /// Whether failing tests are remade (false: the paper's WOGAN).
    pub enabled: bool,
    /// Tests of at least this fitness are the failures remade (the SUT's failure threshold;
    /// must be above 0 when `enabled`).
    pub min_fitness: f64,
}

/// Where the candidates ranked between niches, in the search for the next seed, come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum BetweenNiches {
    /// The generator and reshaped mutants of the best tests, as inside a niche.
    #[default]
    Model,
    /// Random tests drawn as in the random phase, ranked by the analyzer: the generator has
    /// learnt the niches found so far, random tests lie anywhere.
    Random,
}

impl Default for NoveltyConfig {
    fn default() -> Self {
        Self {
            distance: 0.0,
            min_fitness: 0.0,
            allowed_neighbours: 0,
        }
    }
}

/// Upper bounds of the settings whose size sets a run's time and memory, chosen so that one
/// training round stays bounded (`cargo bench -p wogan-core --bench corners` measures the most
/// expensive round accepted): networks at most 4x the paper's width, batches at most the
/// analyzer's (16x the WGAN's), epochs and critic steps at most 1-10x the paper's.
pub mod limits {
    /// Widest hidden layer of any network.
    pub const MAX_HIDDEN: usize = 512;
    /// Largest generator noise dimension.
    pub const MAX_NOISE_DIM: usize = 256;
    /// Largest batch of any kind (training rows, candidates, noise).
    pub const MAX_BATCH: usize = 512;
    /// Most epochs or critic steps in one training round.
    pub const MAX_EPOCHS: usize = 20;
    /// Most fitness bins.
    pub const MAX_BINS: usize = 1000;
    /// Most random draws per valid test, or invalid candidates in a row.
    pub const MAX_ATTEMPTS: usize = 10_000_000;
    /// Largest `mutation.shift_places` (a shift is also at most one place fewer than the test's
    /// values).
    pub const MAX_SHIFT_PLACES: usize = 1000;
    /// Most worker threads.
    pub const MAX_JOBS: usize = 256;
    /// Largest shape novelty distance: far beyond any two roads' heading profiles (radians).
    pub const MAX_SHAPE_NOVELTY_DISTANCE: f64 = 100.0;
}

/// Names `field` and its range unless `value` lies in `[min, max]`.
fn check_count(value: usize, field: &str, min: usize, max: usize) -> Result<(), Error> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(Error::Config(format!(
            "{field} must be from {min} to {max}, got {value}"
        )))
    }
}

/// Names `field` and its range unless `value` lies in `[min, max]` (NaN never does).
fn check_real(value: f64, field: &str, min: f64, max: f64) -> Result<(), Error> {
    if value >= min && value <= max {
        Ok(())
    } else {
        Err(Error::Config(format!(
            "{field} must be from {min} to {max}, got {value}"
        )))
    }
}

/// Names `field` unless `value` lies in `(0, max]`.
fn check_positive(value: f64, field: &str, max: f64) -> Result<(), Error> {
    if value > 0.0 && value <= max {
        Ok(())
    } else {
        Err(Error::Config(format!(
            "{field} must be above 0 and at most {max}, got {value}"
        )))
    }
}

impl RunConfig {
    /// Rejects values the algorithms cannot work with, or that would make one iteration's time
    /// or memory unbounded; the error names the field and its range.
    pub fn validate(&self) -> Result<(), Error> {
        use limits::*;
        check_count(self.jobs, "jobs", 1, MAX_JOBS)?;
        let s = &self.sampler;
        check_real(f64::from(s.max_step), "sampler.max_step", 0.0, 2.0)?;
        check_count(s.max_attempts, "sampler.max_attempts", 1, MAX_ATTEMPTS)?;
        let w = &self.wogan;
        check_real(w.init_fraction, "wogan.init_fraction", 0.0, 1.0)?;
        check_count(w.bins, "wogan.bins", 1, MAX_BINS)?;
        check_count(w.batch_size, "wogan.batch_size", 1, MAX_BATCH)?;
        check_count(w.newest_in_batch, "wogan.newest_in_batch", 0, w.batch_size)?;
        check_real(w.alpha_max, "wogan.alpha_max", -100.0, 100.0)?;
        check_count(w.train_every, "wogan.train_every", 1, MAX_ATTEMPTS)?;
        for (value, field) in [
            (w.first_epochs, "wogan.first_epochs"),
            (w.first_analyzer_epochs, "wogan.first_analyzer_epochs"),
            (w.later_epochs, "wogan.later_epochs"),
            (w.later_analyzer_epochs, "wogan.later_analyzer_epochs"),
        ] {
            check_count(value, field, 0, MAX_EPOCHS)?;
        }
        check_count(w.candidate_batch, "wogan.candidate_batch", 1, MAX_BATCH)?;
        if !(w.target_decay > 0.0 && w.target_decay < 1.0) {
            return Err(Error::Config(format!(
                "wogan.target_decay must be in (0, 1), got {}",
                w.target_decay
            )));
        }
        check_count(
            w.max_invalid_streak,
            "wogan.max_invalid_streak",
            1,
            MAX_ATTEMPTS,
        )?;
        check_count(
            w.generator.noise_dim,
            "wogan.generator.noise_dim",
            1,
            MAX_NOISE_DIM,
        )?;
        check_count(w.generator.hidden, "wogan.generator.hidden", 1, MAX_HIDDEN)?;
        check_count(w.critic.hidden, "wogan.critic.hidden", 1, MAX_HIDDEN)?;
        check_real(w.critic.leaky_slope, "wogan.critic.leaky_slope", 0.0, 1.0)?;
        let a = &w.analyzer;
        check_count(a.hidden, "wogan.analyzer.hidden", 1, MAX_HIDDEN)?;
        check_count(a.max_batch, "wogan.analyzer.max_batch", 1, MAX_BATCH)?;
        check_positive(a.lr, "wogan.analyzer.lr", 1.0)?;
        check_real(f64::from(a.beta1), "wogan.analyzer.beta1", 0.0, 0.999)?;
        check_real(f64::from(a.beta2), "wogan.analyzer.beta2", 0.0, 0.999_999)?;
        check_real(a.l2, "wogan.analyzer.l2", 0.0, 1.0)?;
        let g = &w.wgan;
        check_positive(g.lr, "wogan.wgan.lr", 1.0)?;
        check_real(f64::from(g.beta1), "wogan.wgan.beta1", 0.0, 0.999)?;
        check_real(f64::from(g.beta2), "wogan.wgan.beta2", 0.0, 0.999_999)?;
        check_real(g.gp_coef, "wogan.wgan.gp_coef", 0.0, 1e6)?;
        check_count(g.critic_steps, "wogan.wgan.critic_steps", 1, MAX_EPOCHS)?;
        // Batch normalisation needs two rows.
        check_count(g.noise_batch, "wogan.wgan.noise_batch", 2, MAX_BATCH)?;
        check_real(
            f64::from(w.novelty.distance),
            "wogan.novelty.distance",
            0.0,
            2.0,
        )?;
        check_real(w.novelty.min_fitness, "wogan.novelty.min_fitness", 0.0, 1.0)?;
        check_real(
            f64::from(w.shape_novelty.distance),
            "wogan.shape_novelty.distance",
            0.0,
            MAX_SHAPE_NOVELTY_DISTANCE,
        )?;
        check_real(
            w.shape_novelty.min_fitness,
            "wogan.shape_novelty.min_fitness",
            0.0,
            1.0,
        )?;
        let n = &w.niches;
        check_count(n.quota, "wogan.niches.quota", 0, MAX_ATTEMPTS)?;
        for (value, field) in [
            (n.distance, "wogan.niches.distance"),
            (n.radius, "wogan.niches.radius"),
        ] {
            check_real(f64::from(value), field, 0.0, MAX_SHAPE_NOVELTY_DISTANCE)?;
        }
        check_real(n.min_fitness, "wogan.niches.min_fitness", 0.0, 1.0)?;
        check_count(n.patience, "wogan.niches.patience", 0, MAX_ATTEMPTS)?;
        check_count(n.stale, "wogan.niches.stale", 0, MAX_ATTEMPTS)?;
        check_real(
            f64::from(n.repeat_distance),
            "wogan.niches.repeat_distance",
            0.0,
            MAX_SHAPE_NOVELTY_DISTANCE,
        )?;
        if n.stale > 0 && n.repeat_distance <= 0.0 {
            return Err(Error::Config(format!(
                "wogan.niches.stale is {} but wogan.niches.repeat_distance ({}) must be above 0 \
                 for a failure to count as a repeat",
                n.stale, n.repeat_distance
            )));
        }
        if n.quota > 0 && (n.radius <= 0.0 || n.min_fitness <= 0.0) {
            return Err(Error::Config(format!(
                "wogan.niches.quota is {} but wogan.niches.radius ({}) and \
                 wogan.niches.min_fitness ({}) must both be above 0 to make niches",
                n.quota, n.radius, n.min_fitness
            )));
        }
        check_real(w.remakes.min_fitness, "wogan.remakes.min_fitness", 0.0, 1.0)?;
        if w.remakes.enabled && w.remakes.min_fitness <= 0.0 {
            return Err(Error::Config(
                "wogan.remakes.enabled is true but wogan.remakes.min_fitness (0) must be above 0: \
                 it says which tests are the failures remade"
                    .into(),
            ));
        }
        let m = &w.mutation;
        check_real(m.share, "wogan.mutation.share", 0.0, 1.0)?;
        check_count(m.parents, "wogan.mutation.parents", 1, MAX_BATCH)?;
        check_real(
            f64::from(m.min_parent_distance),
            "wogan.mutation.min_parent_distance",
            0.0,
            100.0,
        )?;
        check_real(f64::from(m.max_step), "wogan.mutation.max_step", 0.0, 2.0)?;
        check_real(
            m.reshape_probability,
            "wogan.mutation.reshape_probability",
            0.0,
            1.0,
        )?;
        check_count(
            m.shift_places,
            "wogan.mutation.shift_places",
            0,
            MAX_SHIFT_PLACES,
        )?;
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
            (r#"{"shift_places": 1001}"#, "wogan.mutation.shift_places"),
        ] {
            let mut c = RunConfig::default();
            c.wogan.mutation = serde_json::from_str(json).unwrap();
            let message = c.validate().unwrap_err().to_string();
            assert!(message.contains(field), "{json}: {message}");
        }
    }

    #[test]
    fn niches_closed_on_repeats_need_a_repeat_distance() {
        let niches = r#"{"quota": 10, "radius": 1, "min_fitness": 0.5, "stale": 5"#;
        for (json, field) in [
            (format!("{niches}}}"), "wogan.niches.repeat_distance"),
            (
                format!(r#"{niches}, "repeat_distance": -0.1}}"#),
                "wogan.niches.repeat_distance",
            ),
        ] {
            let mut c = RunConfig::default();
            c.wogan.niches = serde_json::from_str(&json).unwrap();
            let message = c.validate().unwrap_err().to_string();
            assert!(message.contains(field), "{json}: {message}");
        }
        let mut c = RunConfig::default();
        c.wogan.niches =
            serde_json::from_str(&format!(r#"{niches}, "repeat_distance": 0.1}}"#)).unwrap();
        assert!(c.validate().is_ok() && c.wogan.niches.want_failure_profiles());
        assert!(!RunConfig::default().wogan.niches.want_failure_profiles());
    }
}
