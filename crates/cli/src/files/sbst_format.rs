//! The SBST competition pipeline's file formats (`se2p/tool-competition-av`, 2022): the execution
//! records of a drive (`SimulationDataRecord`) and a stored test object (`test.NNNN.json`), made
//! from our drives so that the pipeline's own analysis reads them unchanged. (The generation
//! totals, counted from a run file, are `crate::sbst::metrics::GenerationStats`.)
//!
//! Our simulator samples less than BeamNG reports; each execution record field is mapped from a
//! sample as follows (the README's table says the same for users):
//! - `timer`: the sample's simulated time; `pos`: the car centre at [`ROAD_HEIGHT_M`];
//! - `dir`, `vel`: the heading as a unit vector, and the speed along it (sideslip is not sampled);
//! - `steering`: the front wheels' angle in degrees; `steering_input`: that angle over the car's
//!   steering limit;
//! - `brake`, `brake_input`, `throttle`, `throttle_input`: the driver's command in force (the car
//!   applies commands without actuator lag, so input and applied value are the same);
//! - `wheelspeed`: the car's speed in m/s (wheel slip is not sampled); `vel_kmh`: the speed in
//!   km/h rounded to a whole number, as the pipeline rounds it;
//! - `is_oob`, `oob_counter`, `max_oob_percentage`: the pipeline's out-of-bound monitor run over
//!   our BOLP with the run's tolerance; `oob_distance`: our per-sample `MEAN_LP` value;
//!   `oob_percentage`: the BOLP (a share, as the pipeline's "percentage" is).

use road_sim::{Outcome, Point, Sample, SimResult, StopReason};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::path::{Path, PathBuf};

/// Height of the competition level's road surface, metres: the `z` of every position.
pub const ROAD_HEIGHT_M: f64 = -28.0;

/// One record of a drive as the pipeline stores it (`SimulationDataRecord`): written as an array
/// of its 17 fields in the pipeline's order, so that `SimulationDataRecord(*record)` reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExecutionRecord {
    /// Simulated time, seconds.
    pub timer: f64,
    /// Car centre, metres.
    pub pos: [f64; 3],
    /// Unit heading vector.
    pub dir: [f64; 3],
    /// Velocity, m/s.
    pub vel: [f64; 3],
    /// Front wheels' angle, degrees, positive left.
    pub steering: f64,
    /// Steering as a share of the car's limit, `[-1, 1]`.
    pub steering_input: f64,
    /// Brake applied, `[0, 1]`.
    pub brake: f64,
    /// Brake asked for, `[0, 1]`.
    pub brake_input: f64,
    /// Throttle applied, `[0, 1]`.
    pub throttle: f64,
    /// Throttle asked for, `[0, 1]`.
    pub throttle_input: f64,
    /// Wheel speed, m/s.
    pub wheelspeed: f64,
    /// Speed, whole km/h.
    pub vel_kmh: i64,
    /// Whether the share of the car outside its lane exceeds the tolerance.
    pub is_oob: bool,
    /// Out-of-bound episodes begun so far.
    pub oob_counter: u32,
    /// Largest share outside the lane in the latest episode (0 before any).
    pub max_oob_percentage: f64,
    /// Half the lane width minus the car centre's distance to the lane's centre line, metres.
    pub oob_distance: f64,
    /// Share of the car outside its lane (BOLP).
    pub oob_percentage: f64,
}

/// The pipeline's field names, in its order (`SimulationDataRecordProperties`).
pub const FIELDS: [&str; 17] = [
    "timer",
    "pos",
    "dir",
    "vel",
    "steering",
    "steering_input",
    "brake",
    "brake_input",
    "throttle",
    "throttle_input",
    "wheelspeed",
    "vel_kmh",
    "is_oob",
    "oob_counter",
    "max_oob_percentage",
    "oob_distance",
    "oob_percentage",
];

impl Serialize for ExecutionRecord {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let r = self;
        let mut t = serializer.serialize_tuple(FIELDS.len())?;
        t.serialize_element(&r.timer)?;
        t.serialize_element(&r.pos)?;
        t.serialize_element(&r.dir)?;
        t.serialize_element(&r.vel)?;
        for value in [
            r.steering,
            r.steering_input,
            r.brake,
            r.brake_input,
            r.throttle,
            r.throttle_input,
            r.wheelspeed,
        ] {
            t.serialize_element(&value)?;
        }
        t.serialize_element(&r.vel_kmh)?;
        t.serialize_element(&r.is_oob)?;
        t.serialize_element(&r.oob_counter)?;
        t.serialize_element(&r.max_oob_percentage)?;
        t.serialize_element(&r.oob_distance)?;
        t.serialize_element(&r.oob_percentage)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for ExecutionRecord {
    /// Reads the pipeline's array (rarely: answers read back in tests), naming a bad field.
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let values = Vec::<serde_json::Value>::deserialize(deserializer)?;
        if values.len() != FIELDS.len() {
            return Err(D::Error::custom(format!(
                "an execution record has {} fields, not {}",
                values.len(),
                FIELDS.len()
            )));
        }
        let mut values = values.into_iter().zip(FIELDS);
        let mut next = || values.next().expect("17 values, counted above");
        fn field<T: serde::de::DeserializeOwned, E: Error>(
            (value, name): (serde_json::Value, &str),
        ) -> Result<T, E> {
            serde_json::from_value(value).map_err(|e| E::custom(format!("field {name}: {e}")))
        }
        Ok(Self {
            timer: field(next())?,
            pos: field(next())?,
            dir: field(next())?,
            vel: field(next())?,
            steering: field(next())?,
            steering_input: field(next())?,
            brake: field(next())?,
            brake_input: field(next())?,
            throttle: field(next())?,
            throttle_input: field(next())?,
            wheelspeed: field(next())?,
            vel_kmh: field(next())?,
            is_oob: field(next())?,
            oob_counter: field(next())?,
            max_oob_percentage: field(next())?,
            oob_distance: field(next())?,
            oob_percentage: field(next())?,
        })
    }
}

/// The execution records of a drive's samples, with the pipeline's out-of-bound monitor run
/// over them at `oob_tolerance`; `max_steering_deg` is the car's steering limit.
pub fn execution_data(
    samples: &[Sample],
    oob_tolerance: f64,
    max_steering_deg: f64,
) -> Vec<ExecutionRecord> {
    let mut oob_counter = 0;
    let mut was_oob = false;
    let mut max_oob = 0.0_f64;
    samples
        .iter()
        .map(|s| {
            let is_oob = s.bolp > oob_tolerance;
            // The monitor's episode bookkeeping: a new episode starts its maximum afresh.
            if is_oob && !was_oob {
                oob_counter += 1;
                max_oob = s.bolp;
            } else if is_oob {
                max_oob = max_oob.max(s.bolp);
            }
            was_oob = is_oob;
            let (sin, cos) = s.heading.sin_cos();
            let speed_mps = s.speed_kmh / 3.6;
            ExecutionRecord {
                timer: s.t,
                pos: [s.x, s.y, ROAD_HEIGHT_M],
                dir: [cos, sin, 0.0],
                vel: [speed_mps * cos, speed_mps * sin, 0.0],
                steering: s.steering_deg,
                steering_input: (s.steering_deg / max_steering_deg).clamp(-1.0, 1.0),
                brake: s.brake,
                brake_input: s.brake,
                throttle: s.throttle,
                throttle_input: s.throttle,
                wheelspeed: speed_mps,
                vel_kmh: s.speed_kmh.round_ties_even() as i64,
                is_oob,
                oob_counter,
                max_oob_percentage: max_oob,
                oob_distance: s.oob_distance_m,
                oob_percentage: s.bolp,
            }
        })
        .collect()
}

/// The pipeline's `description` of an executed test: its BeamNG executor says "Car drove out of
/// the lane " for an out-of-bound failure (the pipeline counts those by that prefix), and
/// "Successful test" for a pass.
pub fn description(result: &SimResult, name: &str) -> String {
    match (result.outcome, result.reason) {
        (Outcome::Pass, _) => "Successful test".to_owned(),
        (Outcome::Fail, Some(StopReason::OutOfLane)) => {
            format!("Car drove out of the lane {name}")
        }
        (_, Some(reason)) => format!("{name}: {}", reason_text(reason)),
        (_, None) => name.to_owned(),
    }
}

/// What a stop reason means, in words.
fn reason_text(reason: StopReason) -> &'static str {
    match reason {
        StopReason::OutOfLane => "the car left its lane",
        StopReason::NotMoving => "the car stopped moving",
        StopReason::Timeout => "the drive ran out of time",
        StopReason::NonFinitePhysicsState => "the physics state became non-finite",
        StopReason::NonFiniteCommand => "the driver asked for a non-finite command",
        StopReason::SimTimeLimit => "the drive reached the simulated-time limit",
        StopReason::Interrupted => "the drive was interrupted",
        StopReason::DriverFailed => "the driver (a controller process, a camera network) failed",
    }
}

/// The number of a test file's name as the pipeline writes it, `test.NNNN.json` (`NNNN` the
/// test's id, zero-padded to 4 digits or more); `None` for any other name.
pub fn test_file_number(name: &str) -> Option<u64> {
    let digits = name.strip_prefix("test.")?.strip_suffix(".json")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The `test.NNNN.json` files directly in `dir` (a result folder's, or an export's), in the
/// order of their numbers, which is the order the pipeline generated the tests in.
pub fn test_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let number = entry.file_name().to_str().and_then(test_file_number);
        // A folder or a link to one under a test file's name is not a test.
        if let Some(number) = number.filter(|_| entry.path().is_file()) {
            files.push((number, entry.path()));
        }
    }
    // By number, then name, so that `test.10000.json` follows `test.9999.json`.
    files.sort();
    Ok(files.into_iter().map(|(_, path)| path).collect())
}

/// The competition's features of a test.
#[derive(Debug, Serialize)]
pub struct Features {
    /// Largest curvature, 1/m.
    #[serde(rename = "MAX_CURV")]
    pub max_curv: Option<f64>,
    /// Direction coverage.
    #[serde(rename = "DIR_COV")]
    pub dir_cov: Option<f64>,
    /// Standard deviation of the steering angle.
    #[serde(rename = "STD_SA")]
    pub std_sa: Option<f64>,
    /// Mean lateral position.
    #[serde(rename = "MEAN_LP")]
    pub mean_lp: Option<f64>,
    /// Largest lateral position.
    #[serde(rename = "MAX_LP")]
    pub max_lp: Option<f64>,
}

/// A test object as the pipeline stores it (`RoadTest.to_json`).
#[derive(Debug, Serialize)]
pub struct CompetitionTest<'a> {
    /// The test's id.
    pub id: usize,
    /// The road points.
    pub road_points: &'a [Point],
    /// The centre line as the pipeline interpolates it.
    pub interpolated_points: &'a [Point],
    /// The validator's verdict.
    pub is_valid: bool,
    /// The validator's message (empty when valid).
    pub validation_message: &'static str,
    /// PASS, FAIL or ERROR.
    pub test_outcome: Outcome,
    /// What happened, in the pipeline's words.
    pub description: String,
    /// The drive's records.
    pub execution_data: Vec<ExecutionRecord>,
    /// The competition's features.
    pub features: Features,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64, bolp: f64) -> Sample {
        Sample {
            t,
            x: 1.0,
            y: 2.0,
            heading: std::f64::consts::FRAC_PI_2,
            speed_kmh: 36.5,
            steering_deg: 15.0,
            bolp,
            dist_left_m: 2.0,
            dist_right_m: 2.0,
            oob_distance_m: 1.5,
            throttle: 0.25,
            brake: 0.0,
        }
    }

    #[test]
    fn records_follow_the_pipelines_monitor() {
        let bolps = [0.0, 0.9, 0.95, 0.5, 0.86, 0.2];
        let samples: Vec<Sample> = bolps
            .iter()
            .enumerate()
            .map(|(i, &b)| sample(i as f64, b))
            .collect();
        let records = execution_data(&samples, 0.85, 30.0);
        let oob: Vec<bool> = records.iter().map(|r| r.is_oob).collect();
        assert_eq!(oob, [false, true, true, false, true, false]);
        let counters: Vec<u32> = records.iter().map(|r| r.oob_counter).collect();
        assert_eq!(counters, [0, 1, 1, 1, 2, 2]);
        let maxima: Vec<f64> = records.iter().map(|r| r.max_oob_percentage).collect();
        // A new episode restarts the maximum; between episodes the last one's stays.
        assert_eq!(maxima, [0.0, 0.9, 0.95, 0.95, 0.86, 0.86]);
        let r = records[0];
        assert_eq!(r.vel_kmh, 36, "36.5 rounds half to even");
        assert_eq!(r.steering_input, 0.5);
        assert!((r.vel[1] - 36.5 / 3.6).abs() < 1e-12 && r.vel[0].abs() < 1e-12);
        assert_eq!(r.pos, [1.0, 2.0, ROAD_HEIGHT_M]);
    }

    #[test]
    fn a_record_is_the_pipelines_17_field_array() {
        let record = execution_data(&[sample(0.5, 0.9)], 0.85, 30.0)[0];
        let json = serde_json::to_value(record).unwrap();
        let fields = json.as_array().unwrap();
        assert_eq!(fields.len(), 17);
        assert_eq!(fields[0], 0.5);
        assert_eq!(fields[11], 36);
        assert_eq!(fields[12], true);
        assert_eq!(fields[16], 0.9);
        let back: ExecutionRecord = serde_json::from_value(json).unwrap();
        assert_eq!(back, record);
    }

    #[test]
    fn test_files_are_known_by_name_and_taken_in_number_order() {
        assert_eq!(test_file_number("test.0001.json"), Some(1));
        assert_eq!(test_file_number("test.12345.json"), Some(12345));
        for name in [
            "test..json",
            "test.1a.json",
            "test.0001.json.bak",
            "tests.jsonl",
        ] {
            assert_eq!(test_file_number(name), None, "{name}");
        }
        let dir = std::env::temp_dir().join(format!("wogan-test-files-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("test.0003.json")).unwrap();
        for name in [
            "test.10000.json",
            "test.9999.json",
            "test.0002.json",
            "summary.json",
        ] {
            std::fs::write(dir.join(name), "{}").unwrap();
        }
        let names: Vec<String> = test_files(&dir)
            .unwrap()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["test.0002.json", "test.9999.json", "test.10000.json"]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
