//! JSON configuration files: partial objects laid over typed defaults, field by field.
//!
//! `wogan run --config`, `wogan simulate --config` (its `sim` and `driver` sections) and
//! `wogan train-driver --config` take such a file, so a user names only the fields they change
//! and every other field keeps the paper's (or the driver's) default. A run file's header holds
//! the same sections (`config.sim`, `config.driver`), read back the same way
//! ([`SettingsSource`] says which of the two an error is about).

use anyhow::{bail, Context, Result};
use road_sim::DriverKind;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Where simulation and driver settings were read from, as their errors name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SettingsSource<'a> {
    /// A `--config` file (`None`: none was given), with the command line's options over it.
    ConfigFile(Option<&'a Path>),
    /// A run file's header, whose `config` holds the `sim` and `driver` sections.
    RunHeader,
}

impl SettingsSource<'_> {
    /// The source as an error names it: `config file x.json`, `the run's header`.
    pub fn name(&self) -> String {
        match self {
            Self::ConfigFile(Some(path)) => format!("config file {}", path.display()),
            Self::ConfigFile(None) => "the options".to_owned(),
            Self::RunHeader => "the run's header".to_owned(),
        }
    }

    /// A section's path in this source: `sim` in a config file, `config.sim` in a header.
    pub fn section(&self, name: &str) -> String {
        match self {
            Self::ConfigFile(_) => name.to_owned(),
            Self::RunHeader => format!("config.{name}"),
        }
    }
}

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
    /// Where the file was read from (`None`: no file was given).
    #[serde(skip)]
    pub path: Option<PathBuf>,
}

impl ConfigFile {
    /// The file at `path` (empty when there is none), its old driver sections moved for `driver`.
    pub fn read_for(path: Option<&Path>, driver: DriverKind) -> Result<Self> {
        let mut file = match path {
            Some(path) => read::<Self>(path)?,
            None => Self::default(),
        };
        file.path = path.map(Path::to_path_buf);
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
    let text = read_bounded(path)?;
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

/// Largest config file read, bytes: a settings file is a few kilobytes; a path given by mistake
/// (a run file, `/dev/zero`) is refused before it is read whole.
pub const MAX_CONFIG_BYTES: u64 = 1 << 20;

/// The text of config file `path`, at most [`MAX_CONFIG_BYTES`].
fn read_bounded(path: &Path) -> Result<String> {
    use std::io::Read;
    let cannot = || format!("cannot read config file {}", path.display());
    if path.is_dir() {
        bail!(
            "cannot read config file {}: it is a directory",
            path.display()
        );
    }
    let file = std::fs::File::open(path).with_context(cannot)?;
    let mut bytes = Vec::new();
    file.take(MAX_CONFIG_BYTES + 1)
        .read_to_end(&mut bytes)
        .with_context(cannot)?;
    if bytes.len() as u64 > MAX_CONFIG_BYTES {
        bail!(
            "config file {}: larger than {} KiB, which no settings file is",
            path.display(),
            MAX_CONFIG_BYTES >> 10
        );
    }
    // A byte order mark (an editor's) is no JSON but says nothing either.
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(&bytes);
    String::from_utf8(bytes.to_vec())
        .map_err(|e| anyhow::anyhow!("config file {}: not UTF-8 text: {e}", path.display()))
}

/// `defaults` with `patch` (a config file's section) laid over them; `name` says which section
/// in errors.
pub fn lay_over<T: Serialize + DeserializeOwned>(
    patch: Option<&serde_json::Value>,
    defaults: T,
    name: &str,
) -> Result<T> {
    lay_over_from("config file", patch, defaults, name)
}

/// `defaults` with `patch` laid over them; errors say `source` (`config file`, `the run's
/// header`) and the field's path from `section` (`config.sim.vehicle.mass_kg`).
pub fn lay_over_from<T: Serialize + DeserializeOwned>(
    source: &str,
    patch: Option<&serde_json::Value>,
    defaults: T,
    section: &str,
) -> Result<T> {
    let Some(patch) = patch else {
        return Ok(defaults);
    };
    let mut merged = serde_json::to_value(defaults).context("cannot encode the defaults")?;
    merge(&mut merged, patch);
    serde_path_to_error::deserialize(merged)
        .map_err(|error| anyhow::anyhow!("{source}, {section}.{}: {}", error.path(), error.inner()))
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

    #[test]
    fn a_config_file_is_read_within_its_bound_and_a_bom_is_dropped() {
        let dir = std::env::temp_dir().join(format!("wogan-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bom = dir.join("bom.json");
        std::fs::write(
            &bom,
            b"\xef\xbb\xbf{\"inner\": {\"a\": 1, \"b\": 2}, \"c\": 4}",
        )
        .unwrap();
        assert_eq!(read::<Outer>(&bom).unwrap().c, 4);
        let big = dir.join("big.json");
        std::fs::write(&big, vec![b' '; MAX_CONFIG_BYTES as usize + 1]).unwrap();
        let err = read::<Outer>(&big).unwrap_err().to_string();
        assert!(err.contains("larger than 1024 KiB"), "{err}");
        // No end to read: refused at the bound, not read on.
        let err = read::<Outer>(Path::new("/dev/zero"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("larger than"), "{err}");
        let err = read::<Outer>(&dir).unwrap_err().to_string();
        assert!(err.contains("it is a directory"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
