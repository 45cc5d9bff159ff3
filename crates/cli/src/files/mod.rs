//! What wogan writes and reads: the JSON-lines record schema ([`records`], the one owner of the
//! wire format) and the line reader and writer; roads read from input; run, suite and generator
//! files; the SBST pipeline's execution records and test files; the saved roads `replay` drives
//! again; JUnit reports; and writing any output whole, never over an input.

pub mod generator_file;
pub mod header_settings;
pub mod json_lines;
pub mod junit;
pub mod output_file;
pub mod records;
pub mod road_input;
pub mod run_file;
pub mod saved_roads;
pub mod sbst_format;
pub mod suite_file;
