//! The one-page HTML report (`wogan report --out DIR --html`): report.md's text and pictures in
//! one self-contained file (no network), the failing roads in a table that sorts and filters, and
//! a detail view of each road: where the car left its lane and, for roads re-driven with
//! `--traces N`, the car's path and its BOLP along the drive.
//!
//! The parts: [`failing_roads`] gathers the rows and the geometry the page carries, [`redrive`]
//! drives the worst of them again to trace them, [`page`] writes the file; `report.css` and
//! `report.js` are its style and its script, inlined (and a one-line script in its head marks that
//! scripts run, so that the rows the script pages through are hidden from the first layout).

mod failing_roads;
mod page;
mod redrive;

pub use page::{write_html_report, HtmlReport};
