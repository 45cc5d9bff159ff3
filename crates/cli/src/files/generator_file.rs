//! The generator file (`wogan run --save-generator`, `wogan sample --generator`): a trained WOGAN's
//! proposing networks with every setting needed to use them, so that a team trains once for hours
//! and each CI run samples fresh likely-failing roads in seconds.
//!
//! One JSON object: `format` (`"wogan-generator"`), `version` (its layout, [`VERSION`]),
//! `checksum` (`crc32:` and eight hex digits over the JSON text of `payload`, as written), and
//! `payload`: the wogan version, the driver and tolerance the run searched against, its seed and
//! tests, the road settings (how test vectors become roads), the sampler's settings, and the
//! networks ([`ModelSnapshot`]). A file of another layout, a foreign or truncated file, or one
//! whose checksum does not match is refused with the reason, before anything is sampled.

use crate::files::records::VERSION as WOGAN_VERSION;
use anyhow::{bail, Context, Result};
use road_sim::road::RoadShape;
use road_sim::CurvatureRoad;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::Path;
use wogan_core::{ModelSnapshot, SamplerConfig};

/// What a generator file's `format` says.
pub const FORMAT: &str = "wogan-generator";
/// The layout this `wogan` writes and reads.
pub const VERSION: u32 = 1;

/// Everything a generator file holds but its checksum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorPayload {
    /// The `wogan` version that trained it.
    pub wogan: String,
    /// The driver the run searched against (`--oracle`).
    pub driver: String,
    /// The failure threshold of that run.
    pub oob_tolerance: f64,
    /// The run's seed.
    pub seed: u64,
    /// Tests the networks learnt from.
    pub tests: usize,
    /// Curvature values per road.
    pub curvature_points: usize,
    /// How curvature values become road points (map size, step).
    pub road: CurvatureRoad,
    /// How the niches and the shape novelty rule compared roads; not written when it is the
    /// default, so that files from before the choice keep their checksums.
    #[serde(default, skip_serializing_if = "RoadShape::is_headings")]
    pub road_shape: RoadShape,
    /// Least turn of the run's roads from their first heading, radians; not written when 0 (any
    /// road), so that files from before the choice keep their checksums.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub min_road_turn_rad: f64,
    /// The random sampler's settings (the fallback after too many invalid candidates).
    pub sampler: SamplerConfig,
    /// The networks and the settings they propose with.
    pub model: ModelSnapshot,
}

/// A generator file as written.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GeneratorFile {
    format: String,
    version: u32,
    checksum: String,
    payload: GeneratorPayload,
}

/// `crc32:XXXXXXXX` of `payload`'s JSON text.
fn checksum(payload: &GeneratorPayload) -> Result<String> {
    let text = serde_json::to_string(payload).context("cannot encode the generator")?;
    Ok(format!("crc32:{:08x}", crc32fast::hash(text.as_bytes())))
}

/// Writes `payload` to `path` (whole at once).
pub fn write(path: &Path, payload: GeneratorPayload) -> Result<()> {
    let file = GeneratorFile {
        format: FORMAT.to_owned(),
        version: VERSION,
        checksum: checksum(&payload)?,
        payload,
    };
    let text = serde_json::to_string(&file).context("cannot encode the generator")?;
    crate::files::output_file::write(path, (text + "\n").as_bytes())
        .with_context(|| format!("cannot write the generator {}", path.display()))
}

/// Reads and checks the generator file at `path`.
pub fn read(path: &Path) -> Result<GeneratorPayload> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the generator file {}", path.display()))?;
    let at = path.display();
    let value: Value = serde_json::from_str(&text).map_err(|e| {
        if e.is_eof() {
            anyhow::anyhow!(
                "{at}: not a whole generator file: it ends early ({e}); was it truncated?"
            )
        } else {
            anyhow::anyhow!("{at}: not a generator file: not JSON ({e})")
        }
    })?;
    match value.get("format").and_then(Value::as_str) {
        Some(FORMAT) => {}
        Some(other) => bail!("{at}: format: {other:?} is not a wogan generator ({FORMAT:?})"),
        None => bail!("{at}: format: missing; not a wogan generator file"),
    }
    match value.get("version").and_then(Value::as_u64) {
        Some(v) if v == u64::from(VERSION) => {}
        Some(v) => bail!(
            "{at}: version: generator layout {v}; this wogan reads layout {VERSION} (save the \
             generator again with this wogan, or use the wogan that saved it)"
        ),
        None => bail!("{at}: version: missing or not a whole number"),
    }
    let file: GeneratorFile = serde_path_to_error::deserialize(value)
        .map_err(|e| anyhow::anyhow!("{at}: {}: {}", e.path(), e.inner()))?;
    let expected = checksum(&file.payload)?;
    if file.checksum != expected {
        bail!(
            "{at}: checksum: the file says {}, its content gives {expected}: it was changed or \
             damaged after it was written",
            file.checksum
        );
    }
    if file.payload.model.dim != file.payload.curvature_points {
        bail!(
            "{at}: payload.model.dim: {} values per test, but the roads have {} curvature points",
            file.payload.model.dim,
            file.payload.curvature_points
        );
    }
    Ok(file.payload)
}

/// Whether a least turn is none (serde's `skip_serializing_if`).
fn is_zero(turn_rad: &f64) -> bool {
    *turn_rad == 0.0
}

/// The wogan version, for the payload.
pub fn wogan_version() -> String {
    WOGAN_VERSION.to_owned()
}
