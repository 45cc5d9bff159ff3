//! One WOGAN iteration (a training round plus choosing one test; no simulation) at growing data
//! sizes, on a cheap synthetic SUT, on one thread and with the analyzer training on a second
//! thread; and where a round's time goes (`iteration_parts`). Run with one rayon thread so that
//! the one-thread figures use one core:
//! `RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use wogan_core::{Execution, Sampler, SamplerConfig, Sut, WoganConfig, WoganModel};

/// A smooth bump as fitness; valid = a half-space (about 80% of random walks).
struct Synthetic;

impl Sut for Synthetic {
    type Output = ();
    fn dim(&self) -> usize {
        5
    }
    fn is_valid(&self, t: &[f32]) -> bool {
        t.iter().sum::<f32>() <= 2.0
    }
    fn execute(&self, t: &[f32]) -> Option<Execution<()>> {
        let d2: f32 = t.iter().map(|v| (v - 0.4).powi(2)).sum();
        Some(Execution {
            fitness: f64::from((-d2).exp()),
            execution_time_s: 0.0,
            output: (),
        })
    }
}

fn iteration(c: &mut Criterion) {
    // One thread, then the analyzer on a second thread beside the WGAN (as runs with --jobs 2
    // train): the same numbers, so the two time the same work.
    for (group_name, concurrent) in [
        ("wogan_iteration", false),
        ("wogan_iteration_two_threads", true),
    ] {
        let mut group = c.benchmark_group(group_name);
        group
            .sample_size(20)
            .measurement_time(Duration::from_secs(4));
        for &n in &[300usize, 3_000, 30_000, 100_000] {
            let mut rng = ChaCha20Rng::seed_from_u64(1);
            let sut = Synthetic;
            let (mut model, sampler) = filled_model(n, &WoganConfig::default(), &mut rng);
            model.set_concurrent_training(concurrent);
            let alpha = rng.random_range(0.0..3.0);
            group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
                b.iter(|| {
                    let stats = model.train(alpha, &mut rng).expect("training");
                    let p = model.propose(&sut, &sampler, &mut rng).expect("proposal");
                    black_box((stats, p))
                })
            });
        }
        group.finish();
    }
}

/// A model holding `n` tests of the synthetic SUT, after its first (longer) training round.
fn filled_model(
    n: usize,
    cfg: &WoganConfig,
    rng: &mut ChaCha20Rng,
) -> (WoganModel, Sampler<'static>) {
    let sut = Synthetic;
    let sampler = Sampler::new(sut.dim(), SamplerConfig::default());
    let mut model = WoganModel::new(sut.dim(), cfg, rng);
    for _ in 0..n {
        let t = sampler.sample(rng);
        let f = sut.execute(&t).expect("not stopped").fitness;
        model.add(&t, f);
    }
    model.train(0.0, rng).expect("first training");
    (model, sampler)
}

/// Where an iteration's time goes, from the public API: a training round alone; the same without
/// analyzer epochs (so the analyzer's share is the difference); with one critic step per
/// generator step instead of 5 (so one critic step is a quarter of the difference); and choosing
/// one test alone.
fn iteration_parts(c: &mut Criterion) {
    let mut group = c.benchmark_group("iteration_parts");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(3));
    let paper = WoganConfig::default();
    let mut no_analyzer = paper.clone();
    no_analyzer.later_analyzer_epochs = 0;
    let mut one_critic_step = paper.clone();
    one_critic_step.wgan.critic_steps = 1;
    for &n in &[300usize, 30_000] {
        for (name, cfg) in [
            ("train", &paper),
            ("train_without_analyzer", &no_analyzer),
            ("train_one_critic_step", &one_critic_step),
        ] {
            let mut rng = ChaCha20Rng::seed_from_u64(1);
            let (mut model, _) = filled_model(n, cfg, &mut rng);
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| black_box(model.train(1.5, &mut rng).expect("training")))
            });
        }
        let mut rng = ChaCha20Rng::seed_from_u64(1);
        let (model, sampler) = filled_model(n, &paper, &mut rng);
        group.bench_with_input(BenchmarkId::new("propose", n), &n, |b, _| {
            b.iter(|| {
                black_box(
                    model
                        .propose(&Synthetic, &sampler, &mut rng)
                        .expect("proposal"),
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, iteration, iteration_parts);
criterion_main!(benches);
