//! How a drive is simulated and judged: physics and sampling rates, the start, the end and time
//! limits, the failure threshold and the car.

use super::vehicle::VehicleParams;
use crate::road::Road;
use crate::setting_checks::{all_within, SettingsError};
use serde::{Deserialize, Serialize};

/// Most physics steps per simulated second.
pub const MAX_PHYSICS_HZ: f64 = 1000.0;
/// Most simulated seconds of one drive: a drive still running then ends in ERROR
/// (`sim_time_limit`), whatever its time limit, so that no setting makes a drive unbounded.
pub const MAX_SIM_TIME_S: f64 = 3600.0;

/// How a drive is simulated and judged. The defaults are `beamng-ai-proxy`'s; each driver's
/// competition setup ([`crate::driver::CompetitionSetup`]) sets its own speed limit and tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// The driver's speed limit, km/h.
    pub speed_limit_kmh: f64,
    /// The drive fails when BOLP exceeds this.
    pub oob_tolerance: f64,
    /// Physics steps per simulated second.
    pub physics_hz: f64,
    /// Lane-monitor samples per simulated second (rounded to a whole number of physics steps).
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
    ///
    /// The ranges bound one drive's work: at most [`MAX_PHYSICS_HZ`] steps per simulated second,
    /// and never more than [`MAX_SIM_TIME_S`] simulated seconds whatever the time limit says
    /// (`cargo bench -p road-sim --bench simulate` measures that corner).
    pub fn validate(&self) -> Result<(), SettingsError> {
        all_within(
            "",
            &[
                ("speed_limit_kmh", self.speed_limit_kmh, 0.1, 300.0),
                ("oob_tolerance", self.oob_tolerance, 0.0, 1.0),
                ("physics_hz", self.physics_hz, 10.0, MAX_PHYSICS_HZ),
                ("sample_hz", self.sample_hz, 1.0, MAX_PHYSICS_HZ),
                ("start_offset_m", self.start_offset_m, 0.0, 100.0),
                ("end_distance_m", self.end_distance_m, 0.0, 100.0),
                ("timeout_base_s", self.timeout_base_s, 1.0, MAX_SIM_TIME_S),
                ("timeout_speed_mps", self.timeout_speed_mps, 0.1, 100.0),
                (
                    "not_moving_distance_m",
                    self.not_moving_distance_m,
                    0.0,
                    100.0,
                ),
                (
                    "not_moving_window_s",
                    self.not_moving_window_s,
                    1.0,
                    MAX_SIM_TIME_S,
                ),
            ],
        )?;
        self.vehicle.validate()
    }

    /// The time limit for `road`: `timeout_base_s + length / timeout_speed_mps`, seconds.
    pub fn timeout_s(&self, road: &Road) -> f64 {
        self.timeout_base_s + road.length_m() / self.timeout_speed_mps
    }
}
