//! What was typed becomes settings: each command's options and the values they accept, the
//! `--config` file laid over typed defaults, the driver options shared by the driving commands,
//! the named search presets, and `wogan run`'s plan, in which all of them are resolved once.

pub mod config_file;
pub mod driver_options;
pub mod executor_options;
pub mod run_plan;
pub mod search_preset;
pub mod value_parsers;
