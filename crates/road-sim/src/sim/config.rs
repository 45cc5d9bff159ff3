//! How a drive is simulated and judged: physics and sampling rates, the start, the end and time
//! limits, the failure threshold and the car.

use super::vehicle::VehicleParams;
use crate::road::Road;
use crate::settings::{all_non_negative, all_positive, SettingsError};
use serde::{Deserialize, Serialize};

/// How a drive is simulated and judged. The defaults are `beamng-ai-proxy`'s; each driver's
/// preset ([`crate::driver::DriverPreset`]) sets its own speed limit and tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// The driver's speed limit, km/h.
    pub speed_limit_kmh: f64,
    /// The drive fails when BOLP exceeds this.
    pub oob_tolerance: f64,
    /// Physics steps per simulated second.
    pub physics_hz: f64,
    /// Oracle samples per simulated second (rounded to a whole number of physics steps).
    pub sample_hz: f64,
    /// Distance along the road from its first point to the car's start, metres.
    pub start_offset_m: f64,
    /// The drive passes when the car centre is this close to the road's last point, metres.
    pub end_distance_m: f64,
    /// Time limit: this many seconds ...
    pub timeout_base_s: f64,
    /// ... plus the road's length driven at this speed, metres per second.
    pub timeout_speed_mps: f64,
    /// The drive fails `not_moving` when the car moves less than `not_moving_distance_m` ...
    pub not_moving_distance_m: f64,
    /// ... within this many simulated seconds.
    pub not_moving_window_s: f64,
    /// The car.
    pub vehicle: VehicleParams,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            speed_limit_kmh: 70.0,
            oob_tolerance: 0.85,
            physics_hz: 60.0,
            sample_hz: 60.0,
            start_offset_m: 2.5,
            end_distance_m: 8.0,
            timeout_base_s: 20.0,
            timeout_speed_mps: 2.0,
            not_moving_distance_m: 1.0,
            not_moving_window_s: 10.0,
            vehicle: VehicleParams::default(),
        }
    }
}

impl SimConfig {
    /// Names the first setting no simulation can run with (from a hand-written config file).
    pub fn validate(&self) -> Result<(), SettingsError> {
        if !(0.0..=1.0).contains(&self.oob_tolerance) {
            return Err(SettingsError::new("oob_tolerance", "in [0, 1]"));
        }
        all_positive(
            "",
            &[
                ("speed_limit_kmh", self.speed_limit_kmh),
                ("physics_hz", self.physics_hz),
                ("sample_hz", self.sample_hz),
                ("timeout_base_s", self.timeout_base_s),
                ("not_moving_window_s", self.not_moving_window_s),
            ],
        )?;
        all_non_negative(
            "",
            &[
                ("start_offset_m", self.start_offset_m),
                ("end_distance_m", self.end_distance_m),
                ("timeout_speed_mps", self.timeout_speed_mps),
                ("not_moving_distance_m", self.not_moving_distance_m),
            ],
        )?;
        self.vehicle.validate()
    }

    /// The time limit for `road`: `timeout_base_s + length / timeout_speed_mps`, seconds.
    pub fn timeout_s(&self, road: &Road) -> f64 {
        self.timeout_base_s + road.length_m() / self.timeout_speed_mps
    }
}
