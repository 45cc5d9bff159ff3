//! Speed of the DAVE-2 camera and network on one core.
//!
//! `cargo bench -p road-sim --bench camera`: the median time to render one 66 x 200 grayscale
//! frame on a curved road, one DAVE-2 forward pass ([`Dave2Net`]), and both together (one
//! `dave2-proxy` control step).

use criterion::Criterion;
use road_sim::vision::{Camera, Dave2Net, Dave2Weights, RoadScene};
use road_sim::Road;
use std::hint::black_box;

fn main() {
    let pts = [[100.0, 10.0], [100.0, 40.0], [120.0, 70.0], [150.0, 80.0]];
    let road = Road::new(&pts).expect("a road");
    let scene = RoadScene::new(&road);
    let camera = Camera::default();
    let mut net = Dave2Net::new(&Dave2Weights::from_seed(1));
    let mut c = Criterion::default().configure_from_args();
    let mut frame = camera.render(&scene, [102.0, 20.0], 1.5);
    c.bench_function("camera/render_gray_66x200", |b| {
        b.iter(|| {
            camera.render_into(&scene, black_box([102.0, 20.0]), black_box(1.5), &mut frame);
            black_box(frame.data[0])
        })
    });
    c.bench_function("dave2/inference", |b| {
        b.iter(|| black_box(net.predict(black_box(&frame.data))))
    });
    c.bench_function("dave2/render_and_inference", |b| {
        b.iter(|| {
            camera.render_into(&scene, black_box([102.0, 20.0]), black_box(1.5), &mut frame);
            black_box(net.predict(&frame.data))
        })
    });
    c.final_summary();
}
