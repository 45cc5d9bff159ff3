//! A trained WOGAN's proposing networks as plain numbers: the generator (with its batch
//! normalisation's running statistics, which candidates are drawn with) and the analyzer that
//! ranks them. Enough to propose more tests later, in another process, without the run's data or
//! training: [`WoganModel::snapshot`] takes one, [`WoganModel::from_snapshot`] proposes from one.
//! The critic and the optimisers' state are not kept, so a model restored from a snapshot
//! proposes as the run's last round did but does not continue its training.

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use serde::{Deserialize, Serialize};

use super::model::WoganModel;
use crate::config::{RunConfig, WoganConfig};
use crate::error::Error;
use crate::nets::{Analyzer, BatchNorm, Dense, Generator};

/// The layers a snapshot holds, each one prefix of its tensors' names.
const TENSOR_PREFIXES: [&str; 8] = [
    "generator.input",
    "generator.hidden",
    "generator.hidden_norm",
    "generator.output",
    "generator.output_norm",
    "analyzer.l1",
    "analyzer.l2",
    "analyzer.l3",
];

/// One named tensor: its shape and row-major values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NamedTensor {
    /// Which parameter it is, e.g. `generator.hidden.weight`.
    pub name: String,
    /// Its shape.
    pub shape: Vec<usize>,
    /// Its values, row-major.
    pub values: Vec<f32>,
}

/// The proposing networks of a trained WOGAN and the settings they propose with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelSnapshot {
    /// Test vector dimension.
    pub dim: usize,
    /// The settings the networks were built and propose with.
    pub config: WoganConfig,
    /// Every parameter and running statistic of the generator and the analyzer.
    pub tensors: Vec<NamedTensor>,
}

fn tensor(name: String, shape: Vec<usize>, values: &[f32]) -> NamedTensor {
    NamedTensor {
        name,
        shape,
        values: values.to_vec(),
    }
}

fn linear_tensors(prefix: &str, layer: &Dense, out: &mut Vec<NamedTensor>) {
    let (d_in, d_out) = (layer.d_in(), layer.d_out());
    out.push(tensor(
        format!("{prefix}.weight"),
        vec![d_in, d_out],
        &layer.weight.data,
    ));
    out.push(tensor(format!("{prefix}.bias"), vec![d_out], &layer.bias));
}

fn norm_tensors(prefix: &str, norm: &BatchNorm, out: &mut Vec<NamedTensor>) {
    for (name, values) in [
        ("gamma", &norm.gamma),
        ("beta", &norm.beta),
        ("running_mean", &norm.running_mean),
        ("running_var", &norm.running_var),
    ] {
        out.push(tensor(
            format!("{prefix}.{name}"),
            vec![values.len()],
            values,
        ));
    }
}

/// The snapshot's tensors by name, each taken once, with its shape checked against the network
/// built from the snapshot's settings.
struct Tensors<'a> {
    all: &'a [NamedTensor],
}

impl Tensors<'_> {
    fn data(&self, name: &str, shape: &[usize]) -> Result<Vec<f32>, Error> {
        let t = self
            .all
            .iter()
            .find(|t| t.name == name)
            .ok_or_else(|| Error::Snapshot(format!("{name}: missing")))?;
        if t.shape != shape {
            return Err(Error::Snapshot(format!(
                "{name}: shape {:?}, the settings make {shape:?}",
                t.shape
            )));
        }
        if t.values.len() != shape.iter().product::<usize>() {
            return Err(Error::Snapshot(format!(
                "{name}: {} values for shape {shape:?}",
                t.values.len()
            )));
        }
        if let Some(bad) = t.values.iter().find(|v| !v.is_finite()) {
            return Err(Error::Snapshot(format!(
                "{name}: a value is not a number ({bad})"
            )));
        }
        Ok(t.values.clone())
    }

    fn linear(&self, prefix: &str, layer: &mut Dense) -> Result<(), Error> {
        let (d_in, d_out) = (layer.d_in(), layer.d_out());
        layer.weight.data = self.data(&format!("{prefix}.weight"), &[d_in, d_out])?;
        layer.bias = self.data(&format!("{prefix}.bias"), &[d_out])?;
        Ok(())
    }

    fn norm(&self, prefix: &str, norm: &mut BatchNorm) -> Result<(), Error> {
        let shape = [norm.gamma.len()];
        norm.gamma = self.data(&format!("{prefix}.gamma"), &shape)?;
        norm.beta = self.data(&format!("{prefix}.beta"), &shape)?;
        norm.running_mean = self.data(&format!("{prefix}.running_mean"), &shape)?;
        norm.running_var = self.data(&format!("{prefix}.running_var"), &shape)?;
        Ok(())
    }
}

impl WoganModel {
    /// The proposing networks as they are now; an error before the first training round.
    pub fn snapshot(&self) -> Result<ModelSnapshot, Error> {
        let (generator, analyzer) = self.inference().ok_or_else(|| {
            Error::Snapshot("no generator trained yet (the run ended in its random phase)".into())
        })?;
        let mut tensors = Vec::new();
        linear_tensors("generator.input", &generator.input, &mut tensors);
        linear_tensors("generator.hidden", &generator.hidden, &mut tensors);
        norm_tensors(
            "generator.hidden_norm",
            &generator.hidden_norm,
            &mut tensors,
        );
        linear_tensors("generator.output", &generator.output, &mut tensors);
        norm_tensors(
            "generator.output_norm",
            &generator.output_norm,
            &mut tensors,
        );
        linear_tensors("analyzer.l1", &analyzer.l1, &mut tensors);
        linear_tensors("analyzer.l2", &analyzer.l2, &mut tensors);
        linear_tensors("analyzer.l3", &analyzer.l3, &mut tensors);
        Ok(ModelSnapshot {
            dim: self.dim(),
            config: self.config().clone(),
            tensors,
        })
    }

    /// A model that proposes as the snapshot's networks do, with no data; an error naming the
    /// tensor when the snapshot does not fit its own settings.
    pub fn from_snapshot(snapshot: &ModelSnapshot) -> Result<Self, Error> {
        let cfg = &snapshot.config;
        // The settings' ranges bound the networks' size: a snapshot cannot ask for more.
        RunConfig {
            wogan: cfg.clone(),
            ..RunConfig::default()
        }
        .validate()?;
        if snapshot.dim == 0 {
            return Err(Error::Snapshot("dim: 0".into()));
        }
        // The networks are built to the settings' shapes (any weights) and then overwritten.
        let mut rng = ChaCha20Rng::seed_from_u64(0);
        let mut model = WoganModel::new(snapshot.dim, cfg, &mut rng);
        let mut generator = Generator::new(snapshot.dim, &cfg.generator, &mut rng);
        let mut analyzer = Analyzer::new(snapshot.dim, &cfg.analyzer, &mut rng);
        let tensors = Tensors {
            all: &snapshot.tensors,
        };
        tensors.linear("generator.input", &mut generator.input)?;
        tensors.linear("generator.hidden", &mut generator.hidden)?;
        tensors.norm("generator.hidden_norm", &mut generator.hidden_norm)?;
        tensors.linear("generator.output", &mut generator.output)?;
        tensors.norm("generator.output_norm", &mut generator.output_norm)?;
        tensors.linear("analyzer.l1", &mut analyzer.l1)?;
        tensors.linear("analyzer.l2", &mut analyzer.l2)?;
        tensors.linear("analyzer.l3", &mut analyzer.l3)?;
        if let Some(foreign) = snapshot.tensors.iter().find(|t| {
            !TENSOR_PREFIXES
                .iter()
                .any(|p| t.name.starts_with(&format!("{p}.")))
        }) {
            return Err(Error::Snapshot(format!(
                "{}: not a tensor of WOGAN's networks",
                foreign.name
            )));
        }
        model.set_inference(generator, analyzer);
        Ok(model)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::SamplerConfig;
    use crate::sut::{Execution, Sut};
    use crate::test_sampler::Sampler;

    struct Anything;
    impl Sut for Anything {
        type Output = ();
        fn dim(&self) -> usize {
            3
        }
        fn is_valid(&self, _: &[f32]) -> bool {
            true
        }
        fn execute(&self, _: &[f32]) -> Option<Execution<()>> {
            None
        }
    }

    fn trained() -> WoganModel {
        let mut rng = ChaCha20Rng::seed_from_u64(3);
        let sampler = Sampler::new(3, SamplerConfig::default());
        let mut model = WoganModel::new(3, &WoganConfig::default(), &mut rng);
        for k in 0..12 {
            model.add(&sampler.sample(&mut rng), 0.05 * f64::from(k));
        }
        model.train(0.0, &mut rng).unwrap();
        model
    }

    #[test]
    fn a_restored_snapshot_proposes_exactly_as_the_model_did() {
        let model = trained();
        let snapshot = model.snapshot().unwrap();
        // Through JSON, as a generator file holds it.
        let text = serde_json::to_string(&snapshot).unwrap();
        let restored = WoganModel::from_snapshot(&serde_json::from_str(&text).unwrap()).unwrap();
        let sampler = Sampler::new(3, SamplerConfig::default());
        for seed in 0..3 {
            let propose = |m: &WoganModel| {
                m.propose(&Anything, &sampler, &mut ChaCha20Rng::seed_from_u64(seed))
                    .unwrap()
            };
            assert_eq!(propose(&model), propose(&restored));
        }
    }

    #[test]
    fn a_snapshot_that_does_not_fit_is_refused_naming_the_tensor() {
        let untrained = WoganModel::new(
            3,
            &WoganConfig::default(),
            &mut ChaCha20Rng::seed_from_u64(1),
        );
        assert!(matches!(untrained.snapshot(), Err(Error::Snapshot(_))));
        let snapshot = trained().snapshot().unwrap();
        let refused = |edit: &dyn Fn(&mut ModelSnapshot)| {
            let mut s = snapshot.clone();
            edit(&mut s);
            WoganModel::from_snapshot(&s)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        assert!(
            refused(&|s| s.tensors.retain(|t| t.name != "analyzer.l2.bias"))
                .contains("analyzer.l2.bias: missing")
        );
        assert!(
            refused(&|s| s.tensors[0].shape = vec![1, 2]).contains("generator.input.weight: shape")
        );
        assert!(refused(&|s| s.tensors[1].values[0] = f32::NAN).contains("not a number"));
        assert!(
            refused(&|s| s.tensors[2].values.pop().map_or((), drop)).contains("values for shape")
        );
        assert!(refused(&|s| s.tensors.push(NamedTensor {
            name: "critic.l1.weight".into(),
            shape: vec![1],
            values: vec![0.0],
        }))
        .contains("critic.l1.weight: not a tensor"));
        assert!(refused(&|s| s.config.generator.hidden = 100_000).contains("hidden"));
    }
}
