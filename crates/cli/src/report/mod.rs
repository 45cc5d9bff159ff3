//! Reports on runs: reading run files, the figures of a group of runs, the statistics that
//! compare two groups (Mann–Whitney U), the SVG pictures and the Markdown that holds them, the
//! one-page HTML report; and the picture of one simulation trace.
//!
//! A group is a sample of one condition: without `--vs` runs are grouped by their configuration
//! ([`RunKey`](run_key::RunKey)); with `--vs` each of the two groups given must be of one
//! driver, failure threshold and speed limit, and a file given twice counts once.

mod group;
mod html;
mod inputs;
mod markdown;
mod pictures;
mod run_key;
mod runs_report;
mod stats;
mod tables;

pub use html::HtmlReport;
pub use inputs::listed_paths;
pub use pictures::trace_picture;
pub use runs_report::runs_report;
pub use tables::runs_tables;
