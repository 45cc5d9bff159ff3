//! The report's SVG pictures: a group's failing roads on the map ([`road_map`]), fitness over each
//! run ([`fitness_plot`]) and a histogram of max BOLP ([`bolp_histogram`]), drawn together per
//! group ([`group_pictures`]); one simulation's trace ([`trace_plot`]); and what they share
//! ([`layout`]).

mod bolp_histogram;
mod fitness_plot;
mod group_pictures;
mod layout;
mod road_map;
mod trace_plot;

pub use group_pictures::{draw_group, Pictures};
pub use trace_plot::trace_picture;
