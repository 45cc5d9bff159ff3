//! The competition pipeline's result folder, both ways: [`writer`] writes one from a run (`wogan
//! export`), [`reader`] reads one back as a run (`wogan report` on a peer generator's folder or
//! an export).

mod reader;
mod writer;

pub use reader::{is_result_folder, read_result_folder};
pub use writer::write_result_folder;
