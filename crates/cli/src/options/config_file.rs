//! JSON configuration files: partial objects laid over typed defaults, field by field.
//!
//! `wogan run --config`, `wogan simulate --config` (its `sim` and `driver` sections) and
//! `wogan train-driver --config` take such a file, so a user names only the fields they change
//! and every other field keeps the paper's (or the driver's) default.

use anyhow::{bail, Context, Result};
use road_sim::DriverKind;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::Path;

/// The sections a `--config` file may hold: partial objects, laid over the defaults.
#[derive(Debug, Default, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ConfigFile {
    /// The search's settings (`wogan run` only).
    pub search: Option<serde_json::Value>,
    /// How drives are simulated and judged.
    pub sim: Option<serde_json::Value>,
    /// The driver's tuning.
    pub driver: Option<serde_json::Value>,
}

impl ConfigFile {
    /// The file at `path` (empty when there is none), its old driver sections moved for `driver`.
    pub fn read_for(path: Option<&Path>, driver: DriverKind) -> Result<Self> {
        let mut file = match path {
            Some(path) => read::<Self>(path)?,
            None => Self::default(),
        };
        file.move_old_driver_sections(driver)?;
        Ok(file)
    }

    /// Moves the driver sections that older files kept under `sim` (`sim.beamng_ai`,
    /// `sim.dave2`) to `driver`, for the driver under test; the other driver's section is
    /// dropped, as it always went unused. Says on stderr what it moved.
    fn move_old_driver_sections(&mut self, driver: DriverKind) -> Result<()> {
        let Some(serde_json::Value::Object(sim)) = &mut self.sim else {
            return Ok(());
        };
        for (old, kind) in [
            ("beamng_ai", DriverKind::BeamNgAiProxy),
            ("dave2", DriverKind::Dave2Proxy),
        ] {
            let Some(section) = sim.remove(old) else {
                continue;
            };
            if kind != driver {
                eprintln!("wogan: config file: \"sim.{old}\" is for {kind}, not {driver}: ignored");
                continue;
            }
            if self.driver.is_some() {
                bail!("config file: both \"sim.{old}\" and \"driver\"; \"sim.{old}\" is now \"driver\"");
            }
            eprintln!("wogan: config file: \"sim.{old}\" is now \"driver\"; read as such");
            self.driver = Some(section);
        }
        Ok(())
    }
}

/// Reads `path` as one JSON value and hands it to `T`'s deserializer; an error names the field
/// by its path (`search.wogan.bins`).
pub fn read<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read config file {}", path.display()))?;
    let deserializer = &mut serde_json::Deserializer::from_str(&text);
    serde_path_to_error::deserialize(deserializer).map_err(|error| {
        anyhow::anyhow!(
            "config file {}: {}: {}",
            path.display(),
            error.path(),
            error.inner()
        )
    })
}

/// `defaults` with `patch` laid over them; `name` says where the patch came from in errors.
pub fn lay_over<T: Serialize + DeserializeOwned>(
    patch: Option<&serde_json::Value>,
    defaults: T,
    name: &str,
) -> Result<T> {
    let Some(patch) = patch else {
        return Ok(defaults);
    };
    let mut merged = serde_json::to_value(defaults).context("cannot encode the defaults")?;
    merge(&mut merged, patch);
    serde_path_to_error::deserialize(merged)
        .map_err(|error| anyhow::anyhow!("config file, {name}.{}: {}", error.path(), error.inner()))
}

/// Lays `patch` over `base`: objects merge key by key, anything else replaces.
fn merge(base: &mut serde_json::Value, patch: &serde_json::Value) {
    match (base, patch) {
        (serde_json::Value::Object(base), serde_json::Value::Object(patch)) => {
            for (key, value) in patch {
                merge(
                    base.entry(key.clone()).or_insert(serde_json::Value::Null),
                    value,
                );
            }
        }
        (base, patch) => *base = patch.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Inner {
        a: f64,
        b: f64,
    }

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Outer {
        inner: Inner,
        c: u32,
    }

    fn defaults() -> Outer {
        Outer {
            inner: Inner { a: 1.0, b: 2.0 },
            c: 3,
        }
    }

    #[test]
    fn a_patch_changes_only_the_fields_it_names() {
        let patch = serde_json::json!({"inner": {"b": 5.0}});
        let merged = lay_over(Some(&patch), defaults(), "test").unwrap();
        assert_eq!(merged.inner, Inner { a: 1.0, b: 5.0 });
        assert_eq!(merged.c, 3);
        assert_eq!(lay_over(None, defaults(), "none").unwrap(), defaults());
    }

    #[test]
    fn an_unknown_field_is_named_in_the_error() {
        let patch = serde_json::json!({"inner": {"typo": 5.0}});
        let err = lay_over(Some(&patch), defaults(), "test").unwrap_err();
        assert!(format!("{err:#}").contains("typo"), "{err:#}");
        // A value of the wrong type is named by its path, not only its section.
        let patch = serde_json::json!({"inner": {"b": "five"}});
        let err = lay_over(Some(&patch), defaults(), "test").unwrap_err();
        assert!(
            format!("{err:#}").contains("test.inner.b: invalid type"),
            "{err:#}"
        );
    }
}
