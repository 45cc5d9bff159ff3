//! Parsers of option values shared by the commands: each accepts exactly the values the setting
//! can take and names the expected range in its error.

use road_sim::validator::{MAX_MAP_SIZE_M, MAX_ROAD_LENGTH_M};
use road_sim::{DriverKind, FitnessKind};

/// A map side in metres: above 0 and at most [`MAX_MAP_SIZE_M`] (which bounds a road's length,
/// and so the work of one road).
pub fn map_size_m(text: &str) -> Result<f64, String> {
    within(text, "metres", MAX_MAP_SIZE_M)
}

/// A distance between road points in metres: above 0 and at most 1000.
pub fn step_length_m(text: &str) -> Result<f64, String> {
    within(text, "metres", 1000.0)
}

/// Longest SBST budget: 100 days, far beyond any competition's, so that a typo cannot start a
/// run that never ends.
pub const MAX_SBST_BUDGET_S: u64 = 100 * 24 * 3600;

/// A budget as the competition's pipeline takes it (whole seconds) or as a duration (`90s`,
/// `1h`): above 0 and at most [`MAX_SBST_BUDGET_S`].
pub fn budget_duration(text: &str) -> Result<std::time::Duration, String> {
    let parsed = match text.parse::<u64>() {
        Ok(seconds) => Ok(std::time::Duration::from_secs(seconds)),
        Err(_) => humantime::parse_duration(text).map_err(|e| e.to_string()),
    };
    match parsed {
        Ok(d) if !d.is_zero() && d.as_secs_f64() <= MAX_SBST_BUDGET_S as f64 => Ok(d),
        Ok(_) => Err(format!(
            "expected a budget above 0 and at most {MAX_SBST_BUDGET_S} s (100 days), got {text:?}"
        )),
        Err(e) => Err(format!(
            "expected seconds (600) or a duration (10m, 2h), got {text:?}: {e}"
        )),
    }
}

/// Shortest wait for an executor's answer: less is no time to answer in.
pub const MIN_EXECUTOR_TIMEOUT: std::time::Duration = std::time::Duration::from_millis(100);
/// Longest wait for an executor's answer to one road: a day, far beyond any real-time drive.
pub const MAX_EXECUTOR_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(24 * 3600);

/// `--executor-timeout`: a duration (`90s`, `10m`) from [`MIN_EXECUTOR_TIMEOUT`] to
/// [`MAX_EXECUTOR_TIMEOUT`].
pub fn executor_timeout(text: &str) -> Result<std::time::Duration, String> {
    match humantime::parse_duration(text) {
        Ok(d) if (MIN_EXECUTOR_TIMEOUT..=MAX_EXECUTOR_TIMEOUT).contains(&d) => Ok(d),
        Ok(_) => Err(format!(
            "expected a duration from 100ms to 24h, got {text:?}"
        )),
        Err(e) => Err(format!("expected a duration (90s, 10m), got {text:?}: {e}")),
    }
}

/// A number above 0 and at most `max`.
fn within(text: &str, unit: &str, max: f64) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v <= max => Ok(v),
        _ => Err(format!(
            "expected a number of {unit} above 0 and at most {max}, got {text:?}"
        )),
    }
}

/// A road's least turn from its first heading in radians: from 0 (any road) to a whole turn.
pub fn turn_rad(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=std::f64::consts::TAU).contains(&v) => Ok(v),
        _ => Err(format!(
            "expected a turn in radians from 0 to a whole turn (6.283), got {text:?}"
        )),
    }
}

/// A speed in km/h, above 0 and at most 300.
pub fn positive_kmh(text: &str) -> Result<f64, String> {
    within(text, "km/h", 300.0)
}

/// A distance along a road in metres, from 0 to [`MAX_ROAD_LENGTH_M`].
pub fn distance_along_m(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=MAX_ROAD_LENGTH_M).contains(&v) => Ok(v),
        _ => Err(format!(
            "expected a distance along the road in metres, from 0 to {MAX_ROAD_LENGTH_M}, got {text:?}"
        )),
    }
}

/// Frames per simulated second, from 0.1 to 60 (the simulator's sampling).
pub fn record_hz(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.1..=60.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "expected frames per second from 0.1 to 60, got {text:?}"
        )),
    }
}

/// A largest road curvature in 1/m, above 0 and at most 0.3 (a turn radius above 3.3 m).
pub fn max_curvature_per_m(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v <= 0.3 => Ok(v),
        _ => Err(format!(
            "expected a curvature in 1/m above 0 and at most 0.3, got {text:?}"
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

/// The driver under test as `--oracle` names it: a built-in driver, `cmd:COMMAND` or
/// `onnx:FILE`.
#[derive(Debug, Clone, PartialEq)]
pub struct Oracle {
    /// Which driver.
    pub kind: DriverKind,
    /// A controller's command, as typed after `cmd:`.
    pub command: Option<String>,
    /// A camera network's model file, as typed after `onnx:`.
    pub model: Option<std::path::PathBuf>,
}

/// A driver by name, a controller process as `cmd:COMMAND`, or a camera network as `onnx:FILE`
/// (`--oracle`).
pub fn oracle(name: &str) -> Result<Oracle, String> {
    if let Some(command) = name.strip_prefix("cmd:") {
        if command.trim().is_empty() {
            return Err("cmd: names no command".into());
        }
        return Ok(Oracle {
            kind: DriverKind::Controller,
            command: Some(command.to_owned()),
            model: None,
        });
    }
    if let Some(file) = name.strip_prefix("onnx:") {
        if file.is_empty() {
            return Err("onnx: names no model file".into());
        }
        return Ok(Oracle {
            kind: DriverKind::Onnx,
            command: None,
            model: Some(file.into()),
        });
    }
    let kind = DriverKind::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = DriverKind::ALL.iter().map(|k| k.name()).collect();
        format!(
            "unknown oracle {name:?}; known: {}, onnx:FILE for a camera network in ONNX, or \
             cmd:\"COMMAND\" for a controller process",
            known.join(", ")
        )
    })?;
    Ok(Oracle {
        kind,
        command: None,
        model: None,
    })
}

/// A fitness by name (`--fitness`).
pub fn fitness_kind(name: &str) -> Result<FitnessKind, String> {
    FitnessKind::from_name(name).ok_or_else(|| {
        let known: Vec<&str> = FitnessKind::ALL.iter().map(|k| k.name()).collect();
        format!("unknown fitness {name:?}; known: {}", known.join(", "))
    })
}

/// Where roads lie on the map, by the name a run file records (`bottom-centre` or `fitted`).
pub fn road_placement(name: &str) -> Result<road_sim::RoadPlacement, String> {
    by_file_name(name, "road placement")
}

/// How a search compares roads: `headings` or `directions` (`--road-shape`).
pub fn road_shape(name: &str) -> Result<road_sim::road::RoadShape, String> {
    by_file_name(name, "road shape")
}

/// The value of a unit enum named as the run file names it: serde's names, written once on the
/// type; the error lists them.
fn by_file_name<T: serde::de::DeserializeOwned>(name: &str, what: &str) -> Result<T, String> {
    use serde::de::{value, IntoDeserializer};
    let names: value::StrDeserializer<'_, value::Error> = name.into_deserializer();
    T::deserialize(names).map_err(|e| format!("{what}: {e}"))
}

/// How WOGAN's acceptance target carries over within a round of tests chosen at once:
/// `restart` or `continue`.
pub fn round_acceptance(name: &str) -> Result<wogan_core::RoundAcceptance, String> {
    match name {
        "continue" => Ok(wogan_core::RoundAcceptance::Continue),
        "restart" => Ok(wogan_core::RoundAcceptance::Restart),
        _ => Err(format!("expected continue or restart, got {name:?}")),
    }
}

/// A camera network's contract by name.
pub fn contract(name: &str) -> Result<road_sim::driver::Contract, String> {
    use road_sim::driver::Contract;
    Contract::ALL
        .into_iter()
        .find(|c| c.name() == name)
        .ok_or_else(|| {
            let known: Vec<&str> = Contract::ALL.iter().map(|c| c.name()).collect();
            format!("unknown contract {name:?}; known: {}", known.join(", "))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_executor_timeout_is_a_duration_within_its_range() {
        use std::time::Duration;
        assert_eq!(executor_timeout("2s"), Ok(Duration::from_secs(2)));
        assert_eq!(executor_timeout("24h"), Ok(MAX_EXECUTOR_TIMEOUT));
        // 0 answers nothing; 2^64 s overflowed a deadline (a panic).
        for bad in [
            "0",
            "0s",
            "99ms",
            "25h",
            "18446744073709551615s",
            "213503982334601d",
            "-1s",
            "abc",
        ] {
            assert!(executor_timeout(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn ranges_are_enforced() {
        assert_eq!(map_size_m("200"), Ok(200.0));
        assert!(map_size_m("0").is_err() && map_size_m("inf").is_err());
        assert!(map_size_m("NaN").is_err() && map_size_m("2001").is_err());
        assert!(step_length_m("1e300").is_err() && step_length_m("15").is_ok());
        assert!(positive_kmh("301").is_err() && positive_kmh("25").is_ok());
        assert!(positive_kmh("0")
            .unwrap_err()
            .contains("above 0 and at most 300"));
        assert!(distance_along_m("NaN").is_err() && distance_along_m("-5").is_err());
        assert!(distance_along_m("2.5").is_ok());
        assert!(share("0").is_ok() && share("1").is_ok() && share("1.5").is_err());
        assert!(fraction("0").is_err() && fraction("0.2").is_ok());
        assert_eq!(
            oracle("dave2-proxy").map(|o| o.kind),
            Ok(DriverKind::Dave2Proxy)
        );
        assert!(oracle("dave3").unwrap_err().contains("beamng-ai-proxy"));
        let controller = oracle("cmd:python3 keep.py --gain 2").unwrap();
        assert_eq!(controller.kind, DriverKind::Controller);
        assert_eq!(
            controller.command.as_deref(),
            Some("python3 keep.py --gain 2")
        );
        assert!(oracle("cmd: ").is_err());
        let network = oracle("onnx:models/dave2.onnx").unwrap();
        assert_eq!(network.kind, DriverKind::Onnx);
        assert_eq!(network.model, Some("models/dave2.onnx".into()));
        assert!(oracle("onnx:").unwrap_err().contains("no model file"));
        assert_eq!(turn_rad("2.5"), Ok(2.5));
        assert_eq!(turn_rad("0"), Ok(0.0));
        for refused in ["-0.1", "6.3", "NaN", "inf", "half"] {
            assert!(
                turn_rad(refused).unwrap_err().contains("radians"),
                "{refused}"
            );
        }
        assert_eq!(fitness_kind("bolp-scaled"), Ok(FitnessKind::BolpScaled));
        assert!(fitness_kind("speed").is_err());
        assert_eq!(
            road_placement("fitted"),
            Ok(road_sim::RoadPlacement::Fitted)
        );
        assert_eq!(
            road_shape("directions"),
            Ok(road_sim::road::RoadShape::Directions)
        );
        assert!(road_shape("angles").unwrap_err().contains("headings"));
        let unknown = road_placement("centre").unwrap_err();
        assert!(
            unknown.contains("bottom-centre") && unknown.contains("fitted"),
            "{unknown}"
        );
    }
}
