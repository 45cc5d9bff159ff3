//! Agreement with the WOGAN authors' own code: vectors made by stgem's classes with its SBST 2022
//! parameters (`tests/reference/wogan/`, written by `scripts/reference/stgem_vectors.py`).
//!
//! Networks are loaded with stgem's weights and must give its outputs; training steps replay the
//! random draws stgem made and must give its losses and weights; the algorithm's batches replay
//! its bin and test choices and must give the same tests; the acceptance rule must pick the same
//! candidate after as many candidates. Numbers agree within `|a − b| <= 1e-6 + 1e-5·|b|` (f32).

use std::collections::VecDeque;
use std::path::PathBuf;

use serde_json::Value;

use crate::budget::Budget;
use crate::config::{AnalyzerConfig, RunConfig, WganConfig};
use crate::nets::{
    logit_target, Analyzer, AnalyzerTrainer, BatchNorm, Critic, Dense, Generator, Matrix, Wgan,
};
use crate::test_sampler::Sampler;
use crate::wogan::{biased_batch, bin_of, bin_weights, Acceptance, BatchDraws};

fn vectors(name: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/reference/wogan")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn flat(v: &Value) -> Vec<f32> {
    match v {
        Value::Array(items) => items.iter().flat_map(flat).collect(),
        Value::Number(n) => vec![n.as_f64().expect("a number") as f32],
        other => panic!("not a number array: {other}"),
    }
}

fn rows_of(v: &Value) -> usize {
    v.as_array().expect("an array").len()
}

fn tensor(v: &Value) -> Matrix {
    let values = flat(v);
    let rows = rows_of(v);
    let cols = values.len() / rows;
    Matrix::new(values, rows, cols)
}

/// A PyTorch `Linear` (weight `[out, in]`) as ours (`[in, out]`).
fn linear(state: &Value, name: &str) -> Dense {
    Dense {
        weight: tensor(&state[format!("{name}.weight")]).transpose(),
        bias: flat(&state[format!("{name}.bias")]),
    }
}

fn batch_norm(state: &Value, name: &str) -> BatchNorm {
    let get = |field: &str| flat(&state[format!("{name}.{field}")]);
    BatchNorm {
        gamma: get("weight"),
        beta: get("bias"),
        running_mean: get("running_mean"),
        running_var: get("running_var"),
    }
}

fn generator(state: &Value) -> Generator {
    Generator {
        input: linear(state, "top"),
        hidden: linear(state, "hidden.0"),
        hidden_norm: batch_norm(state, "norm.0"),
        output: linear(state, "bottom"),
        output_norm: batch_norm(state, "norm.2"),
    }
}

fn critic(state: &Value) -> Critic {
    Critic {
        l1: linear(state, "top"),
        l2: linear(state, "hidden.0"),
        l3: linear(state, "bottom"),
        slope: crate::config::CriticConfig::default().leaky_slope as f32,
    }
}

fn analyzer(state: &Value) -> Analyzer {
    Analyzer {
        l1: linear(state, "top"),
        l2: linear(state, "hidden.0"),
        l3: linear(state, "bottom"),
    }
}

/// Asserts `|a − b| <= 1e-6 + 1e-5·|b|` elementwise, or within `abs` where given.
fn assert_close_within(actual: &[f32], expected: &[f32], abs: f32, what: &str) {
    assert_eq!(actual.len(), expected.len(), "{what}: lengths");
    let mut worst = (0.0f32, 0usize);
    for (i, (a, b)) in actual.iter().zip(expected).enumerate() {
        let excess = (a - b).abs() - (abs + 1e-5 * b.abs());
        if excess > worst.0 || !a.is_finite() {
            worst = (excess.max(f32::MIN_POSITIVE), i);
        }
    }
    let i = worst.1;
    assert!(
        worst.0 <= 0.0,
        "{what}: element {i} is {} where stgem has {}",
        actual[i],
        expected[i]
    );
}

fn assert_close(actual: &[f32], expected: &[f32], what: &str) {
    assert_close_within(actual, expected, 1e-6, what);
}

fn assert_scalar(actual: f64, expected: &Value, what: &str) {
    assert_close(&[actual as f32], &flat(expected), what);
}

fn running(bn: &BatchNorm) -> (Vec<f32>, Vec<f32>) {
    (bn.running_mean.clone(), bn.running_var.clone())
}

fn linear_values(l: &Dense) -> (Vec<f32>, Vec<f32>) {
    (l.weight.transpose().take(), l.bias.clone())
}

#[test]
fn generator_matches_stgem_in_training_and_inference_mode() {
    let v = vectors("networks.json");
    let g = &v["generator"];
    let mut net = generator(&g["state"]);
    let out = net.train(&tensor(&g["noise"])).output().data.clone();
    assert_close(&out, &flat(&g["train_output"]), "training-mode output");
    for batch in g["passes"].as_array().unwrap() {
        net.train(&tensor(batch));
    }
    let after = &g["state_after_passes"];
    for (bn, name) in [(&net.hidden_norm, "norm.0"), (&net.output_norm, "norm.2")] {
        let (mean, var) = running(bn);
        assert_close(&mean, &flat(&after[format!("{name}.running_mean")]), name);
        assert_close(&var, &flat(&after[format!("{name}.running_var")]), name);
    }
    let out = net.infer(&tensor(&g["probe"])).take();
    assert_close(&out, &flat(&g["eval_output"]), "inference-mode output");
}

#[test]
fn critic_and_analyzer_match_stgem() {
    let v = vectors("networks.json");
    let c = &v["critic"];
    let out = critic(&c["state"]).forward(&tensor(&c["input"])).take();
    assert_close(&out, &flat(&c["output"]), "critic output");
    let a = &v["analyzer"];
    let net = analyzer(&a["state"]);
    let out = net.predict(&tensor(&a["input"]));
    assert_close(&out, &flat(&a["output"]), "analyzer output");
}

/// Noise `2u − 1` from stgem's `torch.rand` draw `u`, as stgem computes it.
fn noise_of(draw: &Value) -> Matrix {
    let mut m = tensor(draw);
    m.data.iter_mut().for_each(|u| *u = *u * 2.0 - 1.0);
    m
}

#[test]
fn wgan_steps_match_stgem() {
    let v = vectors("wgan_steps.json");
    let cfg = WganConfig::default();
    assert_eq!(v["critic_steps"], cfg.critic_steps);
    assert_eq!(v["noise_batch"], cfg.noise_batch);
    let lr = v["lr"].as_f64().unwrap();
    assert_eq!(lr, cfg.lr);
    let mut wgan = Wgan::from_networks(
        generator(&v["initial"]["generator"]),
        critic(&v["initial"]["critic"]),
        &cfg,
    );
    let real = tensor(&v["real"]);
    let epochs = v["epochs"].as_array().unwrap();
    for (e, epoch) in epochs.iter().enumerate() {
        let draws = epoch["draws"].as_array().unwrap();
        for k in 0..cfg.critic_steps {
            let step = wgan.critic_step(&real, &noise_of(&draws[2 * k]), &flat(&draws[2 * k + 1]));
            let what = format!("epoch {e} critic step {k}");
            assert_scalar(step.loss, &epoch["critic_losses"][k], &what);
            assert_scalar(step.penalty, &epoch["gradient_penalties"][k], &what);
        }
        let noise = noise_of(&draws[2 * cfg.critic_steps]);
        let loss = wgan.generator_step(&noise);
        // The critic it is measured against carries the bias noise described below.
        assert_close_within(
            &[loss as f32],
            &flat(&epoch["generator_losses"][0]),
            1e-5,
            &format!("epoch {e} generator"),
        );
    }
    // Adam with β1 = 0 moves a parameter by about ±lr whatever the size of its gradient, so
    // where the exact gradient is 0 or nearly so, rounding noise (different in any two
    // implementations, or in PyTorch with the batch's rows permuted) decides the sign of each
    // step. Such parameters agree within those steps:
    // - a bias feeding batch normalisation (its exact gradient is 0: normalisation removes it),
    //   and the running mean that follows it (generator);
    // - the critic's second hidden bias, whose gradient is a batch sum that nearly cancels
    //   (PyTorch against itself with the rows permuted differs there by up to 1.4e-5). Its
    //   weights, whose gradients share every backpropagated term with it, agree tightly.
    let critic_steps = (epochs.len() * cfg.critic_steps) as f32;
    let after = &v["after"];
    for (layer, name, near_zero) in [
        (&wgan.critic.l1, "top", false),
        (&wgan.critic.l2, "hidden.0", true),
        (&wgan.critic.l3, "bottom", false),
    ] {
        let (w, b) = linear_values(layer);
        let state = &after["critic"];
        assert_close(&w, &flat(&state[format!("{name}.weight")]), name);
        let bound = if near_zero {
            2.0 * lr as f32 * critic_steps
        } else {
            1e-6
        };
        assert_close_within(&b, &flat(&state[format!("{name}.bias")]), bound, name);
    }
    let generator_steps = epochs.len() as f32;
    let noise_bound = 2.0 * lr as f32 * generator_steps;
    let g = &wgan.generator;
    let state = &after["generator"];
    for (layer, name, normalised) in [
        (&g.input, "top", false),
        (&g.hidden, "hidden.0", true),
        (&g.output, "bottom", true),
    ] {
        let (w, b) = linear_values(layer);
        assert_close(&w, &flat(&state[format!("{name}.weight")]), name);
        let bias_bound = if normalised { noise_bound } else { 1e-6 };
        assert_close_within(&b, &flat(&state[format!("{name}.bias")]), bias_bound, name);
    }
    for (bn, name) in [(&g.hidden_norm, "norm.0"), (&g.output_norm, "norm.2")] {
        let (gamma, beta) = (bn.gamma.clone(), bn.beta.clone());
        assert_close(&gamma, &flat(&state[format!("{name}.weight")]), name);
        assert_close(&beta, &flat(&state[format!("{name}.bias")]), name);
        let (mean, var) = running(bn);
        let m = flat(&state[format!("{name}.running_mean")]);
        assert_close_within(&mean, &m, noise_bound, name);
        assert_close(&var, &flat(&state[format!("{name}.running_var")]), name);
    }
}

#[test]
fn analyzer_steps_match_stgem() {
    let v = vectors("analyzer_steps.json");
    let cfg = AnalyzerConfig::default();
    assert_eq!(v["lr"].as_f64().unwrap(), cfg.lr);
    assert_eq!(v["l2"].as_f64().unwrap(), cfg.l2);
    let mut trainer = AnalyzerTrainer::with_model(analyzer(&v["initial"]), &cfg);
    let x = tensor(&v["x"]);
    // stgem's targets are objectives; the analyzer is indifferent to what its target means.
    let y: Vec<f32> = flat(&v["y"])
        .into_iter()
        .map(|o| logit_target(f64::from(o)))
        .collect();
    for (k, expected) in v["losses"].as_array().unwrap().iter().enumerate() {
        let loss = trainer.step(&x, &y, true).unwrap();
        assert_scalar(loss, expected, &format!("analyzer loss {k}"));
    }
    let after = &v["after"];
    let m = &trainer.model;
    for (layer, name) in [(&m.l1, "top"), (&m.l2, "hidden.0"), (&m.l3, "bottom")] {
        let (w, b) = linear_values(layer);
        assert_close(&w, &flat(&after[format!("{name}.weight")]), name);
        assert_close(&b, &flat(&after[format!("{name}.bias")]), name);
    }
}

#[test]
fn defaults_are_stgem_sbst_parameters() {
    let v = vectors("algorithm.json");
    let p = &v["parameters"];
    let (wp, mp) = (&p["wogan_parameters"], &p["wogan_model_parameters"]);
    let w = RunConfig::default().wogan;
    assert_eq!(wp["bins"], w.bins);
    assert_eq!(wp["wgan_batch_size"], w.batch_size);
    assert_eq!(wp["fitness_coef"].as_f64(), Some(w.target_decay));
    assert_eq!(wp["train_delay"], w.train_every);
    assert_eq!(wp["train_delay"], w.newest_in_batch);
    assert_eq!(wp["shift_function_parameters"]["final"], w.alpha_max as u64);
    assert_eq!(v["invalid_threshold"], w.max_invalid_streak);
    let init = &mp["train_settings_init"];
    let later = &mp["train_settings"];
    assert_eq!(init["epochs"], w.first_epochs);
    assert_eq!(init["analyzer_epochs"], w.first_analyzer_epochs);
    assert_eq!(later["epochs"], w.later_epochs);
    assert_eq!(later["analyzer_epochs"], w.later_analyzer_epochs);
    assert_eq!(later["critic_steps"], w.wgan.critic_steps);
    assert_eq!(mp["noise_batch_size"], w.wgan.noise_batch);
    assert_eq!(mp["gp_coefficient"].as_f64(), Some(w.wgan.gp_coef));
    assert_eq!(mp["generator_lr"].as_f64(), Some(w.wgan.lr));
    assert_eq!(mp["critic_lr"].as_f64(), Some(w.wgan.lr));
    for betas in [&mp["generator_betas"], &mp["critic_betas"]] {
        assert_eq!(flat(betas), vec![w.wgan.beta1, w.wgan.beta2]);
    }
    let g = &mp["generator_mlm_parameters"];
    assert_eq!(g["noise_dim"], w.generator.noise_dim);
    assert_eq!(
        flat(&g["hidden_neurons"]),
        vec![w.generator.hidden as f32; 2]
    );
    assert_eq!(g["batch_normalization"], true);
    assert_eq!(
        flat(&mp["critic_mlm_parameters"]["hidden_neurons"]),
        vec![w.critic.hidden as f32; 2]
    );
    let a = &mp["analyzer_parameters"];
    assert_eq!(a["lr"].as_f64(), Some(w.analyzer.lr));
    assert_eq!(flat(&a["betas"]), vec![w.analyzer.beta1, w.analyzer.beta2]);
    assert_eq!(a["l2_regularization_coef"].as_f64(), Some(w.analyzer.l2));
    assert_eq!(a["loss"], "MSE,logit");
    assert_eq!(
        flat(&a["analyzer_mlm_parameters"]["hidden_neurons"]),
        vec![w.analyzer.hidden as f32; 2]
    );
}

#[test]
fn bins_and_their_weights_match_stgem() {
    let v = vectors("algorithm.json");
    let bins = v["bins"].as_u64().unwrap() as usize;
    for case in v["bin_weights"].as_array().unwrap() {
        // stgem's bins are of the objective: its bin `b` is our fitness bin `bins − 1 − b`.
        let mut expected = flat(&case["weights"]);
        expected.reverse();
        let ours = bin_weights(bins, case["shift"].as_f64().unwrap());
        let total: f64 = ours.iter().sum();
        let ours: Vec<f32> = ours.iter().map(|w| (w / total) as f32).collect();
        assert_close(&ours, &expected, "bin weights");
    }
    for pair in v["get_bin"].as_array().unwrap() {
        let fitness = pair[0].as_f64().unwrap();
        let theirs = pair[1].as_u64().unwrap() as usize;
        assert_eq!(bin_of(fitness, bins), bins - 1 - theirs, "{fitness}");
    }
}

/// Batch choices recorded from stgem, replayed in order (bins already turned into fitness bins).
struct Recorded {
    bins: VecDeque<usize>,
    positions: VecDeque<usize>,
}

impl BatchDraws for Recorded {
    fn bin(&mut self, _weights: &[f64]) -> usize {
        self.bins.pop_front().expect("stgem drew as many bins")
    }
    fn position(&mut self, len: usize) -> usize {
        let p = self
            .positions
            .pop_front()
            .expect("stgem picked as many tests");
        assert!(p < len, "stgem picked position {p} of {len}");
        p
    }
}

#[test]
fn training_batches_match_stgem_given_its_draws() {
    let v = vectors("algorithm.json");
    let bins = v["bins"].as_u64().unwrap() as usize;
    let size = v["batch_size"].as_u64().unwrap() as usize;
    let newest_count = v["train_delay"].as_u64().unwrap() as usize;
    let fitness: Vec<f64> = v["fitness"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .collect();
    let budget = Budget {
        max_tests: Some(300),
        wall: None,
        sbst: None,
    };
    let w = RunConfig::default().wogan;
    let rounds = v["training_rounds"].as_array().unwrap();
    assert!(rounds.len() >= 4);
    for (r, round) in rounds.iter().enumerate() {
        let executed = round["executed"].as_u64().unwrap() as usize;
        let shift = round["shift"].as_f64().unwrap();
        let alpha = budget.alpha(
            w.init_fraction,
            w.alpha_max,
            executed,
            Default::default(),
            &Default::default(),
        );
        assert!((alpha - shift).abs() < 1e-12, "α {alpha} vs shift {shift}");
        let bin_of_test: Vec<usize> = fitness[..executed]
            .iter()
            .map(|f| bin_of(*f, bins))
            .collect();
        let mut members = vec![Vec::new(); bins];
        for (i, b) in bin_of_test.iter().enumerate() {
            members[*b].push(i);
        }
        let newest: Vec<(usize, usize)> = if r == 0 {
            Vec::new()
        } else {
            (executed - newest_count..executed)
                .rev()
                .map(|i| (i, bin_of_test[i]))
                .collect()
        };
        let mut draws = Recorded {
            bins: flat(&round["draws"]["bins"])
                .iter()
                .map(|b| bins - 1 - *b as usize)
                .collect(),
            positions: flat(&round["draws"]["picks"])
                .iter()
                .map(|p| *p as usize)
                .collect(),
        };
        for (e, expected) in round["batches"].as_array().unwrap().iter().enumerate() {
            let batch = biased_batch(&members, &newest, size, alpha, &mut draws);
            let expected: Vec<usize> = flat(expected).iter().map(|i| *i as usize).collect();
            assert_eq!(batch, expected, "round at {executed} tests, epoch {e}");
        }
        assert!(
            draws.bins.is_empty() && draws.positions.is_empty(),
            "all draws used"
        );
    }
}

#[test]
fn acceptance_matches_stgem_on_scripted_candidates() {
    let v = vectors("algorithm.json");
    let decay = v["fitness_coef"].as_f64().unwrap();
    let mut compared = 0;
    for case in v["acceptance"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        if let Some(error) = case.get("error") {
            // stgem gives up after `invalid_threshold` invalid candidates by raising an exception
            // it never imported (a NameError that ends the run); WOGAN here falls back to a
            // random valid test instead (see the crate docs).
            assert!(
                error.as_str().unwrap().contains("NameError"),
                "{name}: {error}"
            );
            continue;
        }
        let mut acceptance = Acceptance::new(decay);
        let (mut invalid, mut chosen, mut best) = (0, None, None);
        for (k, (valid, predicted)) in case["valid"]
            .as_array()
            .unwrap()
            .iter()
            .zip(case["predicted_objective"].as_array().unwrap())
            .enumerate()
        {
            if valid != true {
                invalid += 1;
                continue;
            }
            let ranked = acceptance.rank(1.0 - predicted.as_f64().unwrap());
            if ranked.best {
                best = Some(k);
            }
            if ranked.accept {
                chosen = best.map(|b| (b, k + 1));
                break;
            }
        }
        let (chosen, generated) = chosen.unwrap_or_else(|| panic!("{name}: nothing accepted"));
        assert_eq!(chosen, case["chosen"].as_u64().unwrap() as usize, "{name}");
        assert_eq!(
            generated,
            case["generated"].as_u64().unwrap() as usize,
            "{name}"
        );
        assert_eq!(
            invalid,
            case["invalid"].as_u64().unwrap() as usize,
            "{name}"
        );
        compared += 1;
    }
    assert!(compared >= 3);
}

#[test]
fn random_walk_matches_uniform_dependent() {
    let v = vectors("algorithm.json");
    let dim = v["dim"].as_u64().unwrap() as usize;
    let sampler = Sampler::new(dim, Default::default());
    for walk in v["uniform_dependent"].as_array().unwrap() {
        let ours = sampler.walk(&flat(&walk["uniforms"]));
        assert_close(&ours, &flat(&walk["test"]), "UniformDependent walk");
    }
}
