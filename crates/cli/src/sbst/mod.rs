//! The SBST 2022 tool competition's side of the binary, as its pipeline
//! (`se2p/tool-competition-av`) has it: the measures it scores a generator by ([`metrics`]:
//! generation totals, effectiveness, efficiency, the `OOBAnalyzer`'s sides and sparseness) and
//! its result folder ([`result_folder`]: written by `wogan export`, read back as a run by `wogan
//! report`). Its file formats are [`crate::files::sbst_format`]; the validity rules and the OOB
//! analysis themselves are `road_sim::validator` and `road_sim::oob`.

pub mod metrics;
mod result_folder;

pub use result_folder::{is_result_folder, read_result_folder, write_result_folder};
