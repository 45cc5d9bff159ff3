//! How a camera network's car keeps its speed: the competition's DAVE-2 rule (by default),
//! dave2-proxy's speed controller, or the network's own second output.

use serde::{Deserialize, Serialize};

/// Which rule sets throttle and brake.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ThrottleRule {
    /// The competition's (`self_driving/nvidia_prediction.py`): throttle
    /// `1 − steering² − (speed / limit)²`, where the limit is the speed limit until the car goes
    /// faster, then the slow-down speed until it is back at or under that; no brake.
    #[default]
    Competition,
    /// dave2-proxy's: a proportional controller holding the set speed (`speed_kmh`).
    SpeedController,
    /// The network's second output: throttle when positive, brake when negative.
    Network,
}

/// The competition's rule, with its state (the limit in force).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompetitionThrottle {
    max_kmh: f64,
    slow_down_kmh: f64,
    limit_kmh: f64,
}

impl CompetitionThrottle {
    /// For a drive at most `max_kmh` that slows down to `slow_down_kmh` once above it.
    pub fn new(max_kmh: f64, slow_down_kmh: f64) -> Self {
        Self {
            max_kmh,
            slow_down_kmh,
            limit_kmh: max_kmh,
        }
    }

    /// The rule's throttle (not yet clamped: the competition hands it to BeamNG as it is) for
    /// the network's `steering` at `speed_kmh`.
    pub fn throttle(&mut self, steering: f64, speed_kmh: f64) -> f64 {
        self.limit_kmh = if speed_kmh > self.limit_kmh {
            self.slow_down_kmh
        } else {
            self.max_kmh
        };
        1.0 - steering * steering - (speed_kmh / self.limit_kmh).powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize)]
    struct Vectors {
        throttle: Vec<Sequence>,
    }

    #[derive(serde::Deserialize)]
    struct Sequence {
        max_speed_kmh: f64,
        calls: Vec<(f64, f64, f64)>,
    }

    /// `NvidiaPrediction.predict`'s throttles, call after call (its limit is state).
    #[test]
    fn matches_the_competitions_rule() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/reference/dave2_contract.json"
        );
        let vectors: Vectors =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        assert_eq!(vectors.throttle.len(), 2);
        for sequence in vectors.throttle {
            let mut rule = CompetitionThrottle::new(sequence.max_speed_kmh, 10.0);
            for (steering, speed, want) in sequence.calls {
                let got = rule.throttle(steering, speed);
                assert!(
                    (got - want).abs() < 1e-12,
                    "max {}: steering {steering} at {speed} km/h: {got} vs {want}",
                    sequence.max_speed_kmh
                );
            }
        }
    }
}
