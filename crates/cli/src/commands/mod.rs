//! The subcommands, one module each: its options (clap) and what it does with them. Each returns
//! how it ended ([`crate::Status`]); `main` turns that into the exit status.

pub mod camera;
pub mod export;
pub mod report;
pub mod run;
pub mod simulate;
pub mod train_driver;
pub mod validate;
