//! Validator speed on the competition's reference roads (tests/reference/validator.jsonl).
//!
//! `cargo bench --bench validator` reports the time per 6-point WOGAN road (the case the search
//! validates millions of times; interpolation included) and the time for the whole file.

use criterion::{criterion_group, criterion_main, Criterion};
use road_sim::{Point, Validator};
use std::hint::black_box;

fn reference_roads() -> Vec<(String, Vec<Point>)> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/validator.jsonl"
    );
    let text = std::fs::read_to_string(path).expect("tests/reference/validator.jsonl");
    text.lines()
        .map(|line| {
            let value: serde_json::Value =
                serde_json::from_str(line).expect("reference line is JSON");
            let kind = value["kind"].as_str().unwrap_or_default().to_owned();
            let points = value["road_points"]
                .as_array()
                .expect("road_points")
                .iter()
                .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
                .collect();
            (kind, points)
        })
        .collect()
}

fn validator_speed(c: &mut Criterion) {
    let roads = reference_roads();
    let wogan_roads: Vec<&Vec<Point>> = roads
        .iter()
        .filter(|(kind, points)| kind.starts_with("wogan") && points.len() == 6)
        .map(|(_, points)| points)
        .collect();
    let validator = Validator::default();
    let mut group = c.benchmark_group("validator");
    let mut next = 0;
    group.bench_function("per 6-point WOGAN road", |b| {
        b.iter(|| {
            next = (next + 1) % wogan_roads.len();
            black_box(validator.validate(black_box(wogan_roads[next])).is_valid())
        })
    });
    group.sample_size(20);
    group.bench_function("all reference roads", |b| {
        b.iter(|| {
            roads
                .iter()
                .filter(|(_, p)| validator.validate(black_box(p)).is_valid())
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, validator_speed);
criterion_main!(benches);
