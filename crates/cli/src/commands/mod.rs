//! The subcommands, one module each: its options (clap) and what it does with them. Each returns
//! how it ended ([`Status`]); `main` turns that into the exit status.

pub mod camera;
pub mod dataset;
pub mod export;
pub mod replay;
pub mod report;
mod road_stream;
pub mod run;
pub mod sample;
pub mod simulate;
mod status;
pub mod suite;
pub mod train_driver;
pub mod validate;

pub use status::{Status, EXIT_USAGE};
