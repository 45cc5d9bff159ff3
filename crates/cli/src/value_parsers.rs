//! Parsers of option values shared by the commands: each accepts exactly the values the setting
//! can take and names the expected range in its error.

use road_sim::{DriverKind, FitnessKind};

/// A strictly positive, finite length in metres.
pub fn positive_metres(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!(
            "expected a positive number of metres, got {text:?}"
        )),
    }
}

/// A speed in km/h, above 0 and at most 300.
pub fn positive_kmh(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 300.0 => Ok(v),
        _ => Err(format!(
            "expected a speed in km/h between 0 and 300, got {text:?}"
        )),
    }
}

/// A share from 0 to 1, both included.
pub fn share(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("expected a number from 0 to 1, got {text:?}")),
    }
}

/// A fraction strictly between 0 and 1.
pub fn fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v < 1.0 => Ok(v),
        _ => Err(format!(
            "expected a number strictly between 0 and 1, got {text:?}"
        )),
    }
}

/// A driver by name (`--oracle`).
pub fn driver_kind(name: &str) -> Result<DriverKind, String> {
    DriverKind::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = DriverKind::ALL.iter().map(|k| k.name()).collect();
        format!("unknown oracle {name:?}; known: {}", known.join(", "))
    })
}

/// A fitness by name (`--fitness`).
pub fn fitness_kind(name: &str) -> Result<FitnessKind, String> {
    FitnessKind::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = FitnessKind::ALL.iter().map(|k| k.name()).collect();
        format!("unknown fitness {name:?}; known: {}", known.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_enforced() {
        assert_eq!(positive_metres("15"), Ok(15.0));
        assert!(positive_metres("0").is_err() && positive_metres("inf").is_err());
        assert!(positive_kmh("301").is_err() && positive_kmh("25").is_ok());
        assert!(share("0").is_ok() && share("1").is_ok() && share("1.5").is_err());
        assert!(fraction("0").is_err() && fraction("0.2").is_ok());
        assert_eq!(driver_kind("dave2-proxy"), Ok(DriverKind::Dave2Proxy));
        assert!(driver_kind("dave3")
            .unwrap_err()
            .contains("beamng-ai-proxy"));
        assert_eq!(fitness_kind("bolp-scaled"), Ok(FitnessKind::BolpScaled));
        assert!(fitness_kind("speed").is_err());
    }
}
