//! A run header's settings read back typed. A header is written from the run's resolved settings
//! (`options::run_plan::RunSettings`), but read from files of every version: older layouts lack
//! fields, and a reader must group them anyway. So every field here is optional, and a field of
//! an unexpected type reads as absent instead of making the header unreadable.

use road_sim::road::RoadShape;
use road_sim::RoadPlacement;
use serde::de::{DeserializeOwned, Deserializer};
use serde::Deserialize;
use serde_json::Value;
use wogan_core::{BetweenNiches, RoundAcceptance};

/// What a header's `config` says that reports use.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct HeaderSettings {
    /// The executor, when one drove the roads.
    #[serde(deserialize_with = "lenient")]
    pub executor: Option<ExecutorRead>,
    /// Curvature values per road.
    #[serde(deserialize_with = "lenient")]
    pub curvature_points: Option<u64>,
    /// How the search compared roads.
    #[serde(deserialize_with = "lenient")]
    pub road_shape: Option<RoadShape>,
    /// The least turn a tested road had to make, radians.
    #[serde(deserialize_with = "lenient")]
    pub min_road_turn_rad: Option<f64>,
    /// How test vectors became roads.
    #[serde(deserialize_with = "lenient_or_default")]
    pub road: RoadRead,
    /// How drives were judged.
    #[serde(deserialize_with = "lenient_or_default")]
    pub sim: SimRead,
    /// The search's settings.
    #[serde(deserialize_with = "lenient_or_default")]
    pub search: SearchRead,
}

impl HeaderSettings {
    /// The settings of a header's `config` (none when it is not an object).
    pub fn of(config: &Value) -> Self {
        if !config.is_object() {
            return Self::default();
        }
        serde_json::from_value(config.clone()).unwrap_or_default()
    }
}

/// A header's `executor`: the command and what the executor said of itself (older runs recorded
/// the command alone, as text).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(from = "ExecutorWritten")]
pub struct ExecutorRead {
    /// The command, as typed after `cmd:`.
    pub command: Option<String>,
    /// Its name, as its reply to `hello` gave it.
    pub name: Option<String>,
    /// Its version.
    pub version: Option<String>,
    /// Its own settings.
    pub settings: Option<serde_json::Map<String, Value>>,
}

impl ExecutorRead {
    /// How a report names the executor: its name and settings, or its command when it said
    /// nothing of itself. The settings wogan tells every executor (tolerance, speed limit) are a
    /// report's own columns and left out.
    pub fn label(&self) -> String {
        let Some(name) = &self.name else {
            return match &self.command {
                Some(command) => format!("executor ({command})"),
                None => "executor".to_owned(),
            };
        };
        let settings: Vec<String> = self
            .settings
            .iter()
            .flatten()
            .filter(|(key, _)| !matches!(key.as_str(), "oob_tolerance" | "speed_limit_kmh"))
            .map(|(key, value)| match value {
                Value::String(text) => format!("{key} {text}"),
                other => format!("{key} {other}"),
            })
            .collect();
        match settings.is_empty() {
            true => name.clone(),
            false => format!("{name} ({})", settings.join(", ")),
        }
    }
}

/// The two ways `executor` was written.
#[derive(Deserialize)]
#[serde(untagged)]
enum ExecutorWritten {
    Command(String),
    Described {
        #[serde(default, deserialize_with = "lenient")]
        command: Option<String>,
        #[serde(default, deserialize_with = "lenient")]
        name: Option<String>,
        #[serde(default, deserialize_with = "lenient")]
        version: Option<String>,
        #[serde(default, deserialize_with = "lenient")]
        settings: Option<serde_json::Map<String, Value>>,
    },
}

impl From<ExecutorWritten> for ExecutorRead {
    fn from(written: ExecutorWritten) -> Self {
        match written {
            ExecutorWritten::Command(command) => ExecutorRead {
                command: Some(command),
                ..Self::default()
            },
            ExecutorWritten::Described {
                command,
                name,
                version,
                settings,
            } => ExecutorRead {
                command,
                name,
                version,
                settings,
            },
        }
    }
}

/// A header's `road` section.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct RoadRead {
    /// Distance between road points, metres.
    #[serde(deserialize_with = "lenient")]
    pub step_m: Option<f64>,
    /// Where roads lay on the map.
    #[serde(deserialize_with = "lenient")]
    pub placement: Option<RoadPlacement>,
    /// Side of the map, metres.
    #[serde(deserialize_with = "lenient")]
    pub map_size_m: Option<f64>,
}

/// A header's `sim` section.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct SimRead {
    /// BOLP above which a drive failed.
    #[serde(deserialize_with = "lenient")]
    pub oob_tolerance: Option<f64>,
    /// The speed limit, km/h.
    #[serde(deserialize_with = "lenient")]
    pub speed_limit_kmh: Option<f64>,
}

/// A header's `search` section.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct SearchRead {
    /// Tests run at once.
    #[serde(deserialize_with = "lenient")]
    pub jobs: Option<u64>,
    /// WOGAN's settings.
    #[serde(deserialize_with = "lenient_or_default")]
    pub wogan: WoganRead,
}

/// A header's `search.wogan` section: how WOGAN chose its tests.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct WoganRead {
    /// The acceptance target's decay.
    #[serde(deserialize_with = "lenient")]
    pub target_decay: Option<f64>,
    /// How the target carried over within a round.
    #[serde(deserialize_with = "lenient")]
    pub round_acceptance: Option<RoundAcceptance>,
    /// The mutants among the candidates.
    #[serde(deserialize_with = "lenient_or_default")]
    pub mutation: MutationRead,
    /// The novelty rule over test vectors.
    #[serde(deserialize_with = "lenient_or_default")]
    pub novelty: NoveltyRead,
    /// The novelty rule over road shapes.
    #[serde(deserialize_with = "lenient_or_default")]
    pub shape_novelty: NoveltyRead,
    /// The niches of failures.
    #[serde(deserialize_with = "lenient_or_default")]
    pub niches: NichesRead,
}

/// A header's mutation settings.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct MutationRead {
    /// The share of mutants among the candidates.
    #[serde(deserialize_with = "lenient")]
    pub share: Option<f64>,
    /// Largest change of one value (normalised units; written from f32).
    #[serde(deserialize_with = "lenient")]
    pub max_step: Option<f64>,
    /// Largest shift of a mutant's values, places.
    #[serde(deserialize_with = "lenient")]
    pub shift_places: Option<f64>,
}

/// A header's novelty settings (of test vectors or of road shapes).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct NoveltyRead {
    /// The least distance to a kept test (written from f32).
    #[serde(deserialize_with = "lenient")]
    pub distance: Option<f64>,
    /// The fitness from which the rule applies.
    #[serde(deserialize_with = "lenient")]
    pub min_fitness: Option<f64>,
    /// Neighbours allowed within the distance.
    #[serde(deserialize_with = "lenient")]
    pub allowed_neighbours: Option<f64>,
}

/// A header's niche settings.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(default)]
pub struct NichesRead {
    /// Tests per niche (0: none).
    #[serde(deserialize_with = "lenient")]
    pub quota: Option<f64>,
    /// A niche's radius.
    #[serde(deserialize_with = "lenient")]
    pub radius: Option<f64>,
    /// The least distance between niche seeds.
    #[serde(deserialize_with = "lenient")]
    pub distance: Option<f64>,
    /// Tests without a new failure before a niche closes.
    #[serde(deserialize_with = "lenient")]
    pub patience: Option<f64>,
    /// What is searched between niches.
    #[serde(deserialize_with = "lenient")]
    pub between: Option<BetweenNiches>,
    /// Repeats after which a niche closes.
    #[serde(deserialize_with = "lenient")]
    pub stale: Option<f64>,
}

/// A field's value, or `None` when it is null or of another type.
fn lenient<'de, D: Deserializer<'de>, T: DeserializeOwned>(
    deserializer: D,
) -> Result<Option<T>, D::Error> {
    Ok(serde_json::from_value(Value::deserialize(deserializer)?).ok())
}

/// A section's value, or its default when it is of another type.
fn lenient_or_default<'de, D: Deserializer<'de>, T: DeserializeOwned + Default>(
    deserializer: D,
) -> Result<T, D::Error> {
    Ok(serde_json::from_value(Value::deserialize(deserializer)?).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_field_of_another_type_reads_as_absent_and_the_rest_is_kept() {
        let settings = HeaderSettings::of(&json!({
            "curvature_points": "eight",
            "road": {"step_m": 10.0, "placement": "fitted"},
            "sim": 3,
            "search": {"jobs": 2, "wogan": {"target_decay": null, "niches": {"between": "random"}}}
        }));
        assert_eq!(settings.curvature_points, None);
        assert_eq!(settings.road.step_m, Some(10.0));
        assert_eq!(settings.road.placement, Some(RoadPlacement::Fitted));
        assert_eq!(settings.sim, SimRead::default());
        assert_eq!(settings.search.jobs, Some(2));
        assert_eq!(settings.search.wogan.target_decay, None);
        assert_eq!(
            settings.search.wogan.niches.between,
            Some(BetweenNiches::Random)
        );
        assert_eq!(
            HeaderSettings::of(&json!([1, 2])),
            HeaderSettings::default()
        );
    }
}
