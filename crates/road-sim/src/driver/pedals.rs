//! The speed controller the built-in drivers share: throttle for a deficit, brake for an excess.

/// Throttle and brake, each in `[0, 1]`, of a proportional speed controller: throttle for a
/// speed deficit (`speed_error_mps > 0`), brake only for an excess beyond the deadband.
pub fn pedals(
    speed_error_mps: f64,
    throttle_gain: f64,
    brake_gain: f64,
    brake_deadband_mps: f64,
) -> (f64, f64) {
    if speed_error_mps >= 0.0 {
        ((throttle_gain * speed_error_mps).min(1.0), 0.0)
    } else if -speed_error_mps > brake_deadband_mps {
        (
            0.0,
            (brake_gain * (-speed_error_mps - brake_deadband_mps)).min(1.0),
        )
    } else {
        (0.0, 0.0)
    }
}
