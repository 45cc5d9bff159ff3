//! Checks of settings that may come from a hand-written config file, so that a bad value is
//! named up front instead of panicking or stalling deep inside a simulation.

/// `Ok` when every check holds, else the message of the first that fails.
pub(crate) fn first_problem(checks: &[(bool, &str)]) -> Result<(), String> {
    match checks.iter().find(|(ok, _)| !ok) {
        Some((_, problem)) => Err((*problem).to_string()),
        None => Ok(()),
    }
}

/// `Ok` when every named value is [`positive`], else names the first that is not:
/// "`prefix``name` must be positive" (`prefix` is a section such as `"vehicle."`, or empty).
pub(crate) fn all_positive(prefix: &str, values: &[(&str, f64)]) -> Result<(), String> {
    each(prefix, values, positive, "positive")
}

/// `Ok` when every named value is [`non_negative`], else names the first that is not.
pub(crate) fn all_non_negative(prefix: &str, values: &[(&str, f64)]) -> Result<(), String> {
    each(prefix, values, non_negative, "finite and not negative")
}

/// Names the first value `holds` is false of, with the `requirement` it failed.
fn each(
    prefix: &str,
    values: &[(&str, f64)],
    holds: fn(f64) -> bool,
    requirement: &str,
) -> Result<(), String> {
    match values.iter().find(|(_, value)| !holds(*value)) {
        Some((name, _)) => Err(format!("{prefix}{name} must be {requirement}")),
        None => Ok(()),
    }
}

/// Finite and above zero.
pub(crate) fn positive(value: f64) -> bool {
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
        assert_eq!(first_problem(&[(true, "a"), (true, "b")]), Ok(()));
        assert_eq!(
            first_problem(&[(true, "a"), (false, "b"), (false, "c")]),
            Err("b".to_string())
        );
        assert!(positive(1.0) && !positive(0.0) && !positive(f64::NAN));
        assert_eq!(
            all_positive("car.", &[("a", 1.0), ("b", -1.0)]),
            Err("car.b must be positive".to_string())
        );
        assert!(non_negative(0.0) && !non_negative(-1e-9) && !non_negative(f64::INFINITY));
    }
}
