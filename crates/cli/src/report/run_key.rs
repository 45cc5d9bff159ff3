//! What a run's configuration is grouped by in a report: repetitions of one configuration (same
//! algorithm, driver, fitness, conditions, way of choosing tests, roads) form one group, and the
//! key's label names the group.

use crate::files::header_settings::HeaderSettings;
use crate::files::run_file::RunHeader;
use road_sim::road::RoadShape;
use road_sim::RoadPlacement;
use serde_json::Value;
use wogan_core::{BetweenNiches, MutationConfig, RoundAcceptance};

/// What identifies a run's configuration for grouping repetitions.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RunKey {
    /// Search algorithm (`wogan`, `random`).
    pub algorithm: String,
    /// Driver under test.
    pub driver: String,
    /// Fitness function (`bolp`, `distance`).
    pub fitness: String,
    /// BOLP above which a drive fails, as text to compare exactly.
    pub oob_tolerance: String,
    /// Speed limit in km/h, as text to compare exactly.
    pub speed_limit_kmh: String,
    /// How WOGAN chose its tests (`decay 0.9816`, `decay 0.95, mutants 0.25`); empty for random
    /// search and for headers without these settings.
    pub acceptance: String,
    /// The roads' shape when it is not the paper's five curvature values 15 m apart
    /// (`8 x 15 m roads`), with a least turn when one was asked for; empty for the paper's and
    /// for runs that do not say.
    pub roads: String,
}

impl RunKey {
    /// A one-line description, e.g. `wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob
    /// 0.85 / 70 km/h`.
    pub fn label(&self) -> String {
        let acceptance = if self.acceptance.is_empty() {
            String::new()
        } else {
            format!(" / {}", self.acceptance)
        };
        let roads = if self.roads.is_empty() {
            String::new()
        } else {
            format!(" / {}", self.roads)
        };
        format!(
            "{} / {} / fitness {}{acceptance}{roads} / oob {} / {} km/h",
            self.algorithm, self.driver, self.fitness, self.oob_tolerance, self.speed_limit_kmh
        )
    }

    /// What a drive is judged under, which runs compared as one group must share: the driver,
    /// the failure threshold and the speed limit (`driver dave2-proxy, oob 0.1, 30.0 km/h`).
    pub fn conditions(&self) -> String {
        format!(
            "driver {}, oob {}, {} km/h",
            self.driver, self.oob_tolerance, self.speed_limit_kmh
        )
    }

    /// The key of the run whose header is `header`.
    pub fn of(header: &RunHeader) -> Self {
        RunKey {
            algorithm: header.algorithm.clone(),
            driver: header.simulator.clone(),
            // The pipeline's generators maximise no fitness of ours.
            fitness: header.fitness.map_or("-", |f| f.name()).to_owned(),
            oob_tolerance: number_text(header.oob_tolerance),
            speed_limit_kmh: number_text(header.speed_limit_kmh),
            acceptance: acceptance(&header.algorithm, &header.settings),
            roads: roads(&header.settings),
        }
    }
}

/// `value` to at most 4 decimals, without trailing zeros: settings written from f32 and a
/// matched decay group with the same value typed by hand.
fn four_decimals(value: f64) -> String {
    let text = format!("{value:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// WOGAN's settings for choosing tests, which change what a run finds as much as the fitness does:
/// the acceptance decay (to 4 decimals, so a matched default and the same value typed by hand
/// group together), the mutation share when there are mutants (and their step when it is not the
/// default, and their shifts), and rounds of several tests.
fn acceptance(algorithm: &str, settings: &HeaderSettings) -> String {
    let wogan = &settings.search.wogan;
    let decay = match wogan.target_decay {
        Some(decay) if algorithm == "wogan" => decay,
        _ => return String::new(),
    };
    let decay = four_decimals(decay);
    let mut text = format!("decay {decay}");
    let mutation = &wogan.mutation;
    if let Some(share) = mutation.share.filter(|&s| s > 0.0) {
        text.push_str(&format!(", mutants {share}"));
        // Older headers and the default step say nothing; another step finds other failures.
        let default_step = four_decimals(f64::from(MutationConfig::default().max_step));
        if let Some(step) = mutation.max_step.map(four_decimals) {
            if step != default_step {
                text.push_str(&format!(" of steps up to {step}"));
            }
        }
        if let Some(places) = mutation.shift_places.filter(|&p| p > 0.0) {
            text.push_str(&format!(" shifted up to {places} places"));
        }
    }
    for (rule, name) in [
        (&wogan.novelty, "novelty"),
        (&wogan.shape_novelty, "shape novelty"),
    ] {
        if let Some(distance) = rule.distance.filter(|&d| d > 0.0) {
            // Written from f32: 4 decimals, as the decay.
            text.push_str(&format!(", {name} {}", four_decimals(distance)));
            if let Some(fitness) = rule.min_fitness.filter(|&f| f > 0.0) {
                text.push_str(&format!(" from fitness {fitness}"));
            }
            if let Some(allowed) = rule.allowed_neighbours.filter(|&n| n > 0.0) {
                text.push_str(&format!(" allowing {allowed}"));
            }
        }
    }
    let niches = &wogan.niches;
    if let Some(quota) = niches.quota.filter(|&q| q > 0.0) {
        let short = |value: Option<f64>| four_decimals(value.unwrap_or(0.0));
        text.push_str(&format!(
            ", niches of {quota} within {} seeded {} apart",
            short(niches.radius),
            short(niches.distance)
        ));
        if let Some(patience) = niches.patience.filter(|&p| p > 0.0) {
            text.push_str(&format!(" or after {patience} tests"));
        }
        if niches.between == Some(BetweenNiches::Random) {
            text.push_str(", random between");
        }
        if let Some(stale) = niches.stale.filter(|&s| s > 0.0) {
            text.push_str(&format!(", closed after {stale} repeats"));
        }
    }
    // Rounds of several tests change which tests are chosen (one job is the paper's loop).
    if let Some(jobs) = settings.search.jobs.filter(|&j| j > 1) {
        text.push_str(&format!(", rounds of {jobs}"));
        if wogan.round_acceptance == Some(RoundAcceptance::Continue) {
            text.push_str(" continued");
        }
    }
    text
}

/// The roads' shape unless it is the paper's (five curvature values, 15 m apart) or unknown, their
/// placement unless it is the paper's (from the bottom centre), how the search compared them
/// unless by the heading profile, and their least turn unless any road was tested.
fn roads(settings: &HeaderSettings) -> String {
    let shape = match (settings.curvature_points, settings.road.step_m) {
        (Some(5), Some(15.0)) => String::new(),
        (Some(points), Some(step_m)) => format!("{points} x {step_m} m roads"),
        _ => String::new(),
    };
    let placed = match settings.road.placement {
        Some(RoadPlacement::Fitted) if shape.is_empty() => "fitted roads".to_owned(),
        Some(RoadPlacement::Fitted) => format!("{shape}, fitted"),
        _ => shape,
    };
    // Older headers and the default (the heading profile) say nothing.
    let compared = match settings.road_shape {
        Some(RoadShape::Directions) if placed.is_empty() => {
            "roads compared by directions".to_owned()
        }
        Some(RoadShape::Directions) => format!("{placed}, compared by directions"),
        _ => placed,
    };
    // Older headers and the default (any road) say nothing.
    match settings.min_road_turn_rad {
        Some(turn) if turn > 0.0 && compared.is_empty() => format!("roads turning {turn} rad"),
        Some(turn) if turn > 0.0 => format!("{compared}, turning {turn} rad"),
        _ => compared,
    }
}

/// A number as a [`RunKey`] holds it: as the number it is (so that a limit written `70` groups
/// with `70.0`), `?` when unknown.
fn number_text(value: Option<f64>) -> String {
    value.map_or_else(|| "?".to_owned(), |number| Value::from(number).to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::files::records::Header;

    #[test]
    fn wogan_runs_are_grouped_by_how_they_chose_tests() {
        let key_of = |algorithm: &str, wogan: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"{algorithm}","oracle":"dave2-proxy","fitness":"distance","config":{{"search":{{"wogan":{wogan}}}}}}}"#
            ))
            .unwrap();
            RunKey::of(&RunHeader::of(&header))
        };
        let matched = key_of("wogan", r#"{"target_decay":0.9816321972824553}"#);
        assert_eq!(matched.acceptance, "decay 0.9816");
        assert!(matched
            .label()
            .contains("fitness distance / decay 0.9816 / oob"));
        let paper = r#"{"target_decay":0.95,"mutation":{"share":0.0}}"#;
        assert_eq!(key_of("wogan", paper).acceptance, "decay 0.95");
        let mutants = r#"{"target_decay":0.95,"mutation":{"share":0.25}}"#;
        assert_eq!(
            key_of("wogan", mutants).acceptance,
            "decay 0.95, mutants 0.25"
        );
        let shifted = r#"{"target_decay":0.95,"mutation":{"share":0.5,"shift_places":3}}"#;
        assert_eq!(
            key_of("wogan", shifted).acceptance,
            "decay 0.95, mutants 0.5 shifted up to 3 places"
        );
        // The default step as a header writes it from f32 says nothing; another step is named.
        let default_step =
            r#"{"target_decay":0.95,"mutation":{"share":0.5,"max_step":0.15000000596046448}}"#;
        assert_eq!(
            key_of("wogan", default_step).acceptance,
            "decay 0.95, mutants 0.5"
        );
        let larger_steps =
            r#"{"target_decay":0.95,"mutation":{"share":0.5,"max_step":0.4000000059604645}}"#;
        assert_eq!(
            key_of("wogan", larger_steps).acceptance,
            "decay 0.95, mutants 0.5 of steps up to 0.4"
        );
        let no_mutants = r#"{"target_decay":0.95,"mutation":{"share":0,"shift_places":3}}"#;
        assert_eq!(key_of("wogan", no_mutants).acceptance, "decay 0.95");
        // Random search ignores these settings, and older headers lack them.
        assert_eq!(key_of("random", mutants).acceptance, "");
        let old = key_of("wogan", "{}");
        assert_eq!(old.acceptance, "");
        assert!(old.label().contains("fitness distance / oob"));
    }

    #[test]
    fn wogan_runs_in_rounds_group_apart_from_one_test_at_a_time() {
        let key_of = |search: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"wogan","oracle":"dave2-proxy","fitness":"bolp","config":{{"search":{search}}}}}"#
            ))
            .unwrap();
            RunKey::of(&RunHeader::of(&header)).acceptance
        };
        let one = r#"{"jobs":1,"wogan":{"target_decay":0.95}}"#;
        assert_eq!(key_of(one), "decay 0.95");
        let two = r#"{"jobs":2,"wogan":{"target_decay":0.95,"round_acceptance":"continue"}}"#;
        assert_eq!(key_of(two), "decay 0.95, rounds of 2 continued");
        let four = r#"{"jobs":4,"wogan":{"target_decay":0.95,"round_acceptance":"restart"}}"#;
        assert_eq!(key_of(four), "decay 0.95, rounds of 4");
    }

    #[test]
    fn novelty_road_shape_and_least_turn_group_runs_apart() {
        let key_of = |config: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"wogan","oracle":"beamng-ai-proxy","fitness":"bolp","config":{config}}}"#
            ))
            .unwrap();
            RunKey::of(&RunHeader::of(&header))
        };
        let paper = key_of(
            r#"{"curvature_points":5,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"novelty":{"distance":0.0}}}}"#,
        );
        assert_eq!(
            (paper.acceptance.as_str(), paper.roads.as_str()),
            ("decay 0.95", "")
        );
        let preset = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"novelty":{"distance":0.2,"min_fitness":0.85}}}}"#,
        );
        assert_eq!(
            preset.acceptance,
            "decay 0.95, novelty 0.2 from fitness 0.85"
        );
        assert_eq!(preset.roads, "8 x 15 m roads");
        assert!(preset
            .label()
            .ends_with("novelty 0.2 from fitness 0.85 / 8 x 15 m roads / oob ? / ? km/h"));
        assert_ne!(paper, preset);
        let shapes = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"novelty":{"distance":0.1},"shape_novelty":{"distance":0.5,"min_fitness":0.85}}}}"#,
        );
        assert_eq!(
            shapes.acceptance,
            "decay 0.95, novelty 0.1, shape novelty 0.5 from fitness 0.85"
        );
        let crowded = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"shape_novelty":{"distance":0.5,"min_fitness":0.85,"allowed_neighbours":4}}}}"#,
        );
        assert_eq!(
            crowded.acceptance,
            "decay 0.95, shape novelty 0.5 from fitness 0.85 allowing 4"
        );
        let niches = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"niches":{"quota":60,"distance":2.5,"radius":0.75,"min_fitness":0.85,"patience":40}}}}"#,
        );
        assert_eq!(
            niches.acceptance,
            "decay 0.95, niches of 60 within 0.75 seeded 2.5 apart or after 40 tests"
        );
        let stale = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0},"search":{"wogan":{"target_decay":0.95,"niches":{"quota":60,"distance":2.5,"radius":0.75,"min_fitness":0.85,"patience":0,"between":"random","stale":10,"repeat_distance":0.1}}}}"#,
        );
        assert_eq!(
            stale.acceptance,
            "decay 0.95, niches of 60 within 0.75 seeded 2.5 apart, random between, closed after 10 repeats"
        );
        let fitted = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(fitted.roads, "8 x 15 m roads, fitted");
        let directions = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"road_shape":"directions","search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(
            directions.roads,
            "8 x 15 m roads, fitted, compared by directions"
        );
        let headings = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"road_shape":"headings","search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(headings, fitted);
        let winding = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"road_shape":"headings","min_road_turn_rad":2.5,"search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(winding.roads, "8 x 15 m roads, fitted, turning 2.5 rad");
        let any_road = key_of(
            r#"{"curvature_points":8,"road":{"step_m":15.0,"placement":"fitted"},"min_road_turn_rad":0.0,"search":{"wogan":{"target_decay":0.95}}}"#,
        );
        assert_eq!(any_road, fitted);
        let paper_roads =
            key_of(r#"{"curvature_points":5,"road":{"step_m":15.0},"min_road_turn_rad":1.0}"#);
        assert_eq!(paper_roads.roads, "roads turning 1 rad");
    }

    #[test]
    fn numbers_group_as_the_numbers_they_are() {
        let key_of = |sim: &str| {
            let header: Header = serde_json::from_str(&format!(
                r#"{{"version":"0.1.0","algorithm":"random","oracle":"dave2-proxy","fitness":"distance","config":{{"sim":{sim}}}}}"#
            ))
            .unwrap();
            RunKey::of(&RunHeader::of(&header))
        };
        let typed = key_of(r#"{"oob_tolerance":0.10,"speed_limit_kmh":30}"#);
        let written = key_of(r#"{"oob_tolerance":0.1,"speed_limit_kmh":30.0}"#);
        assert_eq!(typed, written);
        assert_eq!(typed.conditions(), "driver dave2-proxy, oob 0.1, 30.0 km/h");
        assert_eq!(
            (typed.oob_tolerance.as_str(), typed.speed_limit_kmh.as_str()),
            ("0.1", "30.0")
        );
        assert_eq!(
            key_of("{}").conditions(),
            "driver dave2-proxy, oob ?, ? km/h"
        );
    }
}
