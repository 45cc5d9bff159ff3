//! End-to-end tests of the `wogan` binary, and the checks of the simulator against the reference
//! vectors of the competition's pipeline, in one test binary (one link of burn and rapier).

mod campaign;
mod ci;
mod common;
mod controller;
mod dataset;
mod executor;
mod export;
mod fuzz;
mod keras;
mod metadrive;
mod onnx;
mod reference_vectors;
mod report;
mod report_bounds;
mod report_html_safety;
mod robustness;
mod run;
mod simulate;
mod train_driver;
mod validate;
