//! Named sets of search settings (`wogan run --preset`): what a preset changes from the paper's
//! WOGAN, laid under the config file and the options, which still win.
//!
//! The defaults stay the paper's WOGAN, so that parity with the authors' implementation holds;
//! a preset is a measured choice for a purpose, and its figures are in docs/results.md.

use wogan_core::{NoveltyConfig, RunConfig};

/// A named set of search settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SearchPreset {
    /// Many distinct failures under the SBST competition's rules: longer roads (8 curvature
    /// values, 120 m), no candidate near a test executed before, and a quarter of the candidates
    /// mutants of the best tests (docs/results.md, "The SBST 2022 field").
    Sbst,
}

/// Curvature values per road of the `sbst` preset.
const SBST_CURVATURE_POINTS: u32 = 8;
/// The `sbst` preset's novelty distance (root mean square, normalised units).
const SBST_NOVELTY_DISTANCE: f32 = 0.1;
/// The `sbst` preset's share of mutants among the candidates.
const SBST_MUTATION_SHARE: f64 = 0.25;

impl SearchPreset {
    /// Curvature values per road, unless `--curvature-points` says otherwise.
    pub fn curvature_points(self) -> u32 {
        match self {
            Self::Sbst => SBST_CURVATURE_POINTS,
        }
    }

    /// Lays the preset's search settings over `search` (the paper's, before the config file and
    /// the options are applied).
    pub fn apply(self, search: &mut RunConfig) {
        match self {
            Self::Sbst => {
                // Every executed test keeps candidates away, not only the failures: near-copies of
                // a road that nearly failed are spent budget too, and keeping away from failures
                // only cost more failing roads than it gained distinct ones (docs/experiments).
                search.wogan.novelty = NoveltyConfig {
                    distance: SBST_NOVELTY_DISTANCE,
                    min_fitness: 0.0,
                };
                // The novelty rule costs failing roads; mutants of the best tests win them back
                // (and more) while the rule keeps the mutants from repeating those tests.
                search.wogan.mutation.share = SBST_MUTATION_SHARE;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sbst_preset_changes_only_the_road_length_the_novelty_and_the_mutants() {
        let mut search = RunConfig::default();
        SearchPreset::Sbst.apply(&mut search);
        let paper = RunConfig::default();
        assert_eq!(search.wogan.novelty.distance, SBST_NOVELTY_DISTANCE);
        assert_eq!(search.wogan.mutation.share, SBST_MUTATION_SHARE);
        search.wogan.novelty = paper.wogan.novelty.clone();
        search.wogan.mutation.share = paper.wogan.mutation.share;
        assert_eq!(search, paper);
        assert_eq!(SearchPreset::Sbst.curvature_points(), 8);
    }
}
