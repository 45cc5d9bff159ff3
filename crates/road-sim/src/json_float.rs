//! Numbers that were not finite, through JSON: serde_json writes NaN and the infinities as `null`,
//! and these helpers read a `null` (or, with `default = "...::nan"`, a missing field) back as NaN.
//! Every record of the workspace that may hold such a number reads it through here.

use serde::{Deserialize, Deserializer};

/// NaN: the value of a number field missing from an older record.
pub fn nan() -> f64 {
    f64::NAN
}

/// Reads a number that serde_json wrote as `null` because it was not finite, as NaN.
pub fn nan_for_null<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::NAN))
}
