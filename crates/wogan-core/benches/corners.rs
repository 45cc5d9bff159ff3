//! The most expensive WOGAN iteration the settings' ranges accept ([`wogan_core::limits`]): every
//! network at its widest, every batch and epoch count at its largest, 499-value tests. Prints the
//! wall time of one training round plus one proposal, and the process's peak memory.
//!
//! `cargo bench -p wogan-core --bench corners`

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use std::time::Instant;
use wogan_core::limits::{MAX_BATCH, MAX_EPOCHS, MAX_HIDDEN, MAX_NOISE_DIM};
use wogan_core::{
    AnalyzerConfig, CriticConfig, Execution, GeneratorConfig, RunConfig, Sampler, SamplerConfig,
    Sut, WganConfig, WoganConfig, WoganModel,
};

/// Every test valid, a smooth fitness: the networks' cost does not depend on the SUT.
struct Wide;

impl Sut for Wide {
    type Output = ();
    fn dim(&self) -> usize {
        499
    }
    fn is_valid(&self, _: &[f32]) -> bool {
        true
    }
    fn execute(&self, t: &[f32]) -> Option<Execution<()>> {
        Some(Execution {
            fitness: f64::from(t.iter().map(|v| v * v).sum::<f32>() / 499.0),
            execution_time_s: 0.0,
            output: (),
        })
    }
}

/// Peak resident memory of this process, MiB (Linux).
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn main() {
    let paper = WoganConfig::default();
    let config = WoganConfig {
        batch_size: MAX_BATCH,
        candidate_batch: MAX_BATCH,
        later_epochs: MAX_EPOCHS,
        later_analyzer_epochs: MAX_EPOCHS,
        generator: GeneratorConfig {
            noise_dim: MAX_NOISE_DIM,
            hidden: MAX_HIDDEN,
        },
        critic: CriticConfig {
            hidden: MAX_HIDDEN,
            ..paper.critic
        },
        analyzer: AnalyzerConfig {
            hidden: MAX_HIDDEN,
            max_batch: MAX_BATCH,
            ..paper.analyzer
        },
        wgan: WganConfig {
            critic_steps: MAX_EPOCHS,
            noise_batch: MAX_BATCH,
            ..paper.wgan
        },
        ..paper.clone()
    };
    RunConfig {
        wogan: config.clone(),
        ..RunConfig::default()
    }
    .validate()
    .expect("the corner is accepted");
    let sut = Wide;
    let mut rng = ChaCha20Rng::seed_from_u64(1);
    let sampler = Sampler::new(sut.dim(), SamplerConfig::default());
    let mut model = WoganModel::new(sut.dim(), &config, &mut rng);
    for _ in 0..2 * MAX_BATCH {
        let t = sampler.sample(&mut rng);
        let f = sut.execute(&t).expect("not stopped").fitness;
        model.add(&t, f);
    }
    // The first round uses the first-round epoch counts (the defaults); the corner is a later one.
    model.train(0.0, &mut rng).expect("first round");
    let started = Instant::now();
    model.train(1.0, &mut rng).expect("corner round");
    let trained_s = started.elapsed().as_secs_f64();
    let started = Instant::now();
    model.propose(&sut, &sampler, &mut rng).expect("a proposal");
    let proposed_s = started.elapsed().as_secs_f64();
    println!(
        "wogan corner (hidden {MAX_HIDDEN}, batches {MAX_BATCH}, {MAX_EPOCHS} epochs x {MAX_EPOCHS} analyzer epochs, {MAX_EPOCHS} critic steps, 499 values): training round {trained_s:.1} s, proposal {proposed_s:.2} s, peak memory {:.0} MiB",
        peak_rss_mib().unwrap_or(f64::NAN)
    );
}
