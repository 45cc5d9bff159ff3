//! Checks of settings that may come from a hand-written config file, so that a bad value is
//! named up front instead of panicking or stalling deep inside a simulation.

/// A setting no simulation or training can run with: which one, and what it must be.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{setting} must be {requirement}")]
pub struct SettingsError {
    /// The setting's path in the configuration, e.g. `vehicle.mass_kg`.
    pub setting: String,
    /// What it must be, e.g. `positive`.
    pub requirement: String,
}

impl SettingsError {
    /// `setting` must be `requirement`.
    pub fn new(setting: impl Into<String>, requirement: impl Into<String>) -> Self {
        Self {
            setting: setting.into(),
            requirement: requirement.into(),
        }
    }
}

/// `Ok` when every check `(holds, setting, requirement)` holds, else the first that does not.
pub fn first_problem(checks: &[(bool, &str, &str)]) -> Result<(), SettingsError> {
    match checks.iter().find(|(holds, _, _)| !holds) {
        Some((_, setting, requirement)) => Err(SettingsError::new(*setting, *requirement)),
        None => Ok(()),
    }
}

/// `Ok` when every named value is [`positive`], else names the first that is not:
/// "`prefix``name` must be positive" (`prefix` is a section such as `"vehicle."`, or empty).
pub fn all_positive(prefix: &str, values: &[(&str, f64)]) -> Result<(), SettingsError> {
    each(prefix, values, positive, "positive")
}

/// `Ok` when every named value is `non_negative`, else names the first that is not.
pub fn all_non_negative(prefix: &str, values: &[(&str, f64)]) -> Result<(), SettingsError> {
    each(prefix, values, non_negative, "finite and not negative")
}

/// `Ok` when every `(name, value, min, max)` has `min <= value <= max`, else names the first that
/// has not, with its range: "`prefix``name` must be from `min` to `max`".
pub fn all_within(prefix: &str, values: &[(&str, f64, f64, f64)]) -> Result<(), SettingsError> {
    match values
        .iter()
        .find(|(_, value, min, max)| !(value >= min && value <= max))
    {
        Some((name, value, min, max)) => Err(SettingsError::new(
            format!("{prefix}{name}"),
            format!("from {min} to {max} (got {})", shown(*value)),
        )),
        None => Ok(()),
    }
}

/// Names the first value `holds` is false of, with the `requirement` it failed.
fn each(
    prefix: &str,
    values: &[(&str, f64)],
    holds: fn(f64) -> bool,
    requirement: &str,
) -> Result<(), SettingsError> {
    match values.iter().find(|(_, value)| !holds(*value)) {
        Some((name, _)) => Err(SettingsError::new(format!("{prefix}{name}"), requirement)),
        None => Ok(()),
    }
}

/// `value` short enough for a message: 1e308 as `1e308`, not its 309 digits.
pub fn shown(value: f64) -> String {
    if value.is_finite() && value != 0.0 && !(1e-4..1e6).contains(&value.abs()) {
        format!("{value:e}")
    } else {
        value.to_string()
    }
}

/// Finite and above zero.
pub fn positive(value: f64) -> bool {
    value.is_finite() && value > 0.0
}

/// Finite and not below zero.
fn non_negative(value: f64) -> bool {
    value.is_finite() && value >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_failing_check_is_reported() {
        assert_eq!(first_problem(&[(true, "a", "x"), (true, "b", "y")]), Ok(()));
        assert_eq!(
            first_problem(&[(true, "a", "x"), (false, "b", "y"), (false, "c", "z")]),
            Err(SettingsError::new("b", "y"))
        );
        assert!(positive(1.0) && !positive(0.0) && !positive(f64::NAN));
        assert_eq!(
            all_positive("car.", &[("a", 1.0), ("b", -1.0)])
                .unwrap_err()
                .to_string(),
            "car.b must be positive"
        );
        assert!(non_negative(0.0) && !non_negative(-1e-9) && !non_negative(f64::INFINITY));
        assert_eq!(
            all_within("", &[("a", 1e308, 0.0, 1.0)])
                .unwrap_err()
                .to_string(),
            "a must be from 0 to 1 (got 1e308)"
        );
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(-60.0), "-60");
        assert_eq!(shown(1e9), "1e9");
    }
}
