//! Named sets of search settings (`wogan run --preset`): what a preset changes from the paper's
//! WOGAN, laid under the config file and the options, which still win.
//!
//! The defaults stay the paper's WOGAN, so that parity with the authors' implementation holds;
//! a preset is a measured choice for a purpose, and its figures are in docs/results.md.

use road_sim::distinct::DELTA_RAD;
use road_sim::driver::CompetitionSetup;
use road_sim::road::curvature::DEFAULT_STEP_M;
use road_sim::road::RoadShape;
use road_sim::{DriverKind, RoadPlacement};
use wogan_core::{BetweenNiches, MutationConfig, NicheConfig, NoveltyConfig, RunConfig};

/// A named set of search settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SearchPreset {
    /// Failures many, distinct and varied as whole roads under the SBST competition's rules:
    /// niches of failures far apart by road shape, each exploited in turn, with no candidate near
    /// a test executed before and mutants of the best tests; in the competition's BeamNG.AI setup
    /// on roads of 22 curvature values 12 m apart fitted to the map, in its DAVE-2 setup of 16
    /// values 10 m apart, each turning at least 2.5 rad (docs/results.md, "The sbst preset").
    Sbst,
    /// `sbst` without niches, on shorter roads: more failures, all alike as whole roads
    /// (docs/results.md, "The SBST 2022 field").
    SbstNoNiches,
}

/// The roads a preset makes, each setting unless its option says otherwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PresetRoads {
    /// Curvature values per road (`--curvature-points`).
    pub curvature_points: u32,
    /// Distance between road points, metres (`--step-length`).
    pub step_m: f64,
    /// Where roads lie on the map (`--road-placement`).
    pub placement: RoadPlacement,
    /// How the niches compare roads (`--road-shape`).
    pub shape: RoadShape,
    /// Least turn from a road's first heading, radians (`--min-road-turn`; 0: any road).
    pub min_turn_rad: f64,
}

/// What an SBST preset sets in one setup.
struct SbstSettings {
    /// The roads.
    roads: PresetRoads,
    /// Novelty distance over every executed test (root mean square, normalised units).
    novelty_distance: f32,
    /// The share of mutants among the candidates.
    mutation_share: f64,
    /// Largest change of one of a mutant's values (normalised units).
    mutation_max_step: f32,
    /// The niches of failures (a quota of 0: none); their failure level is the run's.
    niches: NicheConfig,
}

/// The `sbst-no-niches` preset's share of mutants among the candidates, in both setups.
const SBST_MUTATION_SHARE: f64 = 0.25;

/// The BeamNG.AI setup's roads: 16 curvature values 10 m apart, fitted to the map.
const BEAMNG_AI_ROADS: PresetRoads = PresetRoads {
    curvature_points: 16,
    step_m: 10.0,
    placement: RoadPlacement::Fitted,
    shape: RoadShape::Headings,
    min_turn_rad: 0.0,
};

/// The DAVE-2 setup's roads with niches: the BeamNG.AI setup's, each turning at least 2.5 rad
/// (143°) from its first heading somewhere.
const DAVE2_NICHE_ROADS: PresetRoads = PresetRoads {
    min_turn_rad: 2.5,
    ..BEAMNG_AI_ROADS
};

/// The BeamNG.AI setup's roads with niches: 22 curvature values 12 m apart (264 m), fitted,
/// compared by the WOGAN authors' directions.
const BEAMNG_AI_NICHE_ROADS: PresetRoads = PresetRoads {
    curvature_points: 22,
    step_m: 12.0,
    shape: RoadShape::Directions,
    ..BEAMNG_AI_ROADS
};

impl SbstSettings {
    /// The settings `sbst-no-niches` chose for `setup` (docs/experiments/2026-11-25-sbst-field.md
    /// and 2026-11-25-sbst-diversity.md).
    fn without_niches(setup: CompetitionSetup) -> Self {
        match setup {
            // Longer roads give a failure several bends before the exit to differ in, shorter
            // steps more ways to bend into it (the Frenetic tools' 10 m); fitted to the map, the
            // roads that swing far are kept, and the failures differ more as wholes.
            CompetitionSetup::BeamNgAi => Self {
                roads: BEAMNG_AI_ROADS,
                novelty_distance: 0.1,
                mutation_share: SBST_MUTATION_SHARE,
                mutation_max_step: MutationConfig::default().max_step,
                niches: NicheConfig::default(),
            },
            // At 25 km/h a long road costs nearly three times the simulated seconds it costs at
            // 70 km/h, and the driver fails in fewer ways: the paper's road length keeps the
            // tests in the budget, a closer novelty keeps the failures.
            CompetitionSetup::Dave2 => Self {
                roads: PresetRoads {
                    curvature_points: 5,
                    step_m: DEFAULT_STEP_M,
                    placement: RoadPlacement::BottomCentre,
                    shape: RoadShape::Headings,
                    min_turn_rad: 0.0,
                },
                novelty_distance: 0.05,
                mutation_share: SBST_MUTATION_SHARE,
                mutation_max_step: MutationConfig::default().max_step,
                niches: NicheConfig::default(),
            },
        }
    }

    /// The settings `sbst` chose for `setup`: those without niches, with niches and roads of
    /// their own (docs/experiments/2026-11-26-niches.md and 2026-11-26-niche-roads.md).
    fn with_niches(setup: CompetitionSetup) -> Self {
        match setup {
            // Niches of 100 failures about three of a run's, seeds 3 rad (RMS) apart; mutants
            // keep a niche productive, and a search between niches that finds no far seed in 40
            // tests settles for the farthest failure it met, so the budget still exploits. Longer
            // roads swing further (the niches' seeds lie further apart as whole roads); a closer
            // novelty distance fills each niche sooner, winning back the tests longer roads cost.
            // The niches compare roads as the paper's diversity does (directions not unwrapped),
            // so seeds far apart are far apart by that measure; there a niche's fills spread
            // wider (radius 1.5), and random roads between niches find seeds where the generator,
            // having learnt the niches so far, would not propose
            // (docs/experiments/2026-11-28-niches-by-directions.md).
            CompetitionSetup::BeamNgAi => Self {
                roads: BEAMNG_AI_NICHE_ROADS,
                novelty_distance: 0.075,
                mutation_share: 0.75,
                niches: NicheConfig {
                    quota: 100,
                    distance: 3.0,
                    radius: 1.5,
                    patience: 40,
                    min_fitness: 0.0,
                    between: BetweenNiches::Random,
                    stale: 0,
                    repeat_distance: DELTA_RAD as f32,
                },
                ..Self::without_niches(setup)
            },
            // The paper's 75 m roads all fail alike on this driver (out of one long right-hand
            // bend), so no niche finds room: the longer roads give the bends before the exit
            // room to differ (longer still, of more values or longer steps, adds little here:
            // such roads cost tests at 25 km/h; docs/experiments/2026-11-26-sbst-preset.md).
            // This driver fails in few far regions, and a niche's fills are near copies of one
            // another as whole roads: many niches of 12, their seeds drawn at random where the
            // run has not been (the generator proposes roads like the niches it learnt), keep
            // the near copies' share of the failures' pairs low; mutant steps up to 0.4 (not
            // 0.15) make a niche's fills differ where the car leaves its lane
            // (docs/experiments/2026-11-27-tiny-niches-larger-steps.md). Only roads that turn
            // at least 2.5 rad somewhere are tested: this driver also fails on gentler roads, but
            // those failures lie close together, as whole roads and where driven, and the winding
            // ones do not; the budget the gentle roads no longer take finds about as many
            // failures among the winding ones (docs/experiments/2026-11-28-winding-roads.md).
            CompetitionSetup::Dave2 => Self {
                roads: DAVE2_NICHE_ROADS,
                mutation_share: 0.5,
                mutation_max_step: 0.4,
                niches: NicheConfig {
                    quota: 12,
                    distance: 1.5,
                    radius: 1.0,
                    patience: 0,
                    min_fitness: 0.0,
                    between: BetweenNiches::Random,
                    stale: 0,
                    repeat_distance: DELTA_RAD as f32,
                },
                ..Self::without_niches(setup)
            },
        }
    }
}

impl SearchPreset {
    /// The roads the preset makes for `driver`.
    pub fn roads(self, driver: DriverKind) -> PresetRoads {
        self.settings(driver).roads
    }

    /// What the preset sets for `driver`.
    fn settings(self, driver: DriverKind) -> SbstSettings {
        let setup = CompetitionSetup::of(driver);
        match self {
            Self::Sbst => SbstSettings::with_niches(setup),
            Self::SbstNoNiches => SbstSettings::without_niches(setup),
        }
    }

    /// Lays the preset's search settings for `driver` over `search` (the paper's, before the
    /// config file and the options are applied).
    pub fn apply(self, search: &mut RunConfig, driver: DriverKind) {
        let settings = self.settings(driver);
        // Every executed test keeps candidates away, not only the failures: near-copies of a road
        // that nearly failed are spent budget too, and keeping away from failures only cost more
        // failing roads than it gained distinct ones (docs/experiments).
        search.wogan.novelty = NoveltyConfig {
            distance: settings.novelty_distance,
            ..NoveltyConfig::default()
        };
        // The novelty rule costs failing roads; mutants of the best tests win them back (and
        // more) while the rule keeps the mutants from repeating those tests.
        search.wogan.mutation.share = settings.mutation_share;
        search.wogan.mutation.max_step = settings.mutation_max_step;
        search.wogan.niches = settings.niches;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sbst_no_niches_changes_only_the_roads_the_novelty_and_the_mutants() {
        let paper = RunConfig::default();
        for (driver, points, step_m, placement, distance) in [
            (
                DriverKind::BeamNgAiProxy,
                16,
                10.0,
                RoadPlacement::Fitted,
                0.1,
            ),
            (DriverKind::Controller, 16, 10.0, RoadPlacement::Fitted, 0.1),
            (
                DriverKind::Dave2Proxy,
                5,
                15.0,
                RoadPlacement::BottomCentre,
                0.05,
            ),
            (DriverKind::Onnx, 5, 15.0, RoadPlacement::BottomCentre, 0.05),
        ] {
            let mut search = RunConfig::default();
            SearchPreset::SbstNoNiches.apply(&mut search, driver);
            assert_eq!(search.wogan.novelty.distance, distance, "{driver}");
            assert_eq!(search.wogan.mutation.share, SBST_MUTATION_SHARE);
            assert_eq!(search.wogan.niches, NicheConfig::default());
            search.wogan.novelty = paper.wogan.novelty.clone();
            search.wogan.mutation.share = paper.wogan.mutation.share;
            assert_eq!(search, paper);
            let roads = SearchPreset::SbstNoNiches.roads(driver);
            assert_eq!(roads.curvature_points, points);
            assert_eq!(roads.placement, placement);
            assert_eq!(roads.step_m, step_m);
        }
    }

    #[test]
    fn sbst_adds_niches_to_sbst_no_niches_on_roads_of_its_own() {
        // (driver, its roads' curvature values, step, shape and least turn, its novelty
        // distance, its mutants' largest step); both search random roads between niches
        for (driver, points, step_m, shape, min_turn_rad, novelty, max_step) in [
            (
                DriverKind::BeamNgAiProxy,
                22,
                12.0,
                RoadShape::Directions,
                0.0,
                0.075,
                MutationConfig::default().max_step,
            ),
            (
                DriverKind::Dave2Proxy,
                16,
                10.0,
                RoadShape::Headings,
                2.5,
                0.05,
                0.4,
            ),
        ] {
            let (mut sbst, mut niches) = (RunConfig::default(), RunConfig::default());
            SearchPreset::SbstNoNiches.apply(&mut sbst, driver);
            SearchPreset::Sbst.apply(&mut niches, driver);
            assert!(niches.wogan.niches.quota > 0, "{driver}");
            assert!(niches.wogan.niches.distance > niches.wogan.niches.radius);
            assert!(niches.wogan.mutation.share > sbst.wogan.mutation.share);
            assert_eq!(niches.wogan.novelty.distance, novelty, "{driver}");
            assert_eq!(niches.wogan.mutation.max_step, max_step, "{driver}");
            assert_eq!(niches.wogan.niches.between, BetweenNiches::Random);
            niches.wogan.niches = sbst.wogan.niches.clone();
            niches.wogan.mutation.share = sbst.wogan.mutation.share;
            niches.wogan.mutation.max_step = sbst.wogan.mutation.max_step;
            niches.wogan.novelty = sbst.wogan.novelty.clone();
            assert_eq!(niches, sbst, "{driver}");
            let roads = SearchPreset::Sbst.roads(driver);
            assert_eq!(
                (roads.curvature_points, roads.step_m, roads.shape),
                (points, step_m, shape),
                "{driver}"
            );
            assert_eq!(roads.min_turn_rad, min_turn_rad, "{driver}");
            assert_eq!(roads.placement, RoadPlacement::Fitted, "{driver}");
            // Without niches nothing compares roads by shape (the default), and any road is
            // tested.
            assert!(SearchPreset::SbstNoNiches.roads(driver).shape.is_headings());
            assert_eq!(SearchPreset::SbstNoNiches.roads(driver).min_turn_rad, 0.0);
        }
    }
}
