//! The controller protocol, version 2: what wogan writes to a controller process and what it reads
//! back. Every line wogan writes is one JSON object with a `"type"`: `hello` once when the
//! controller starts, `road` when a drive begins, `step` per control step (numbered from 1 in each
//! drive), `end` when a drive ends, `bye` before its input closes. Only `step` is answered, by
//! exactly one line `{"step": n, "steering": s, "throttle": t, "brake": b}`: the step it answers,
//! steering in `[-1, 1]` of the car's largest steering angle, positive to the left; throttle and
//! brake in `[0, 1]`. docs/reference.md has the specification with a full exchange.
//!
//! Version 2 added the step's number to both lines: without it, a second reply to one step could
//! pass for the reply to the next, and the car would be steered one step late from then on.

use crate::road::Point;
use child_process::{answer_object, LineError, LineWords};
use serde::Serialize;
use serde_json::Value;

/// The protocol's name in the `hello` line.
pub const PROTOCOL: &str = "wogan-controller";
/// The protocol's version.
pub const VERSION: u32 = 2;

/// The camera frame of a step, when asked for: gray values row by row, top row first.
#[derive(Debug, Clone, Serialize)]
pub struct CameraFrame {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// `width × height` gray values in `[0, 255]`, row-major.
    pub gray: Vec<u8>,
}

/// A line wogan writes to the controller.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Message<'a> {
    /// Once, first.
    Hello {
        /// Always [`PROTOCOL`].
        protocol: &'static str,
        /// Always [`VERSION`].
        version: u32,
        /// Units of every number.
        units: &'static str,
        /// Steps per simulated second.
        control_hz: f64,
        /// Whether each step carries the camera frame.
        camera: bool,
    },
    /// A drive begins (not answered).
    Road {
        /// The road's control points, metres.
        road_points: &'a [Point],
        /// The centre of the right lane, where the car should drive, about a point per metre.
        lane_centre: &'a [Point],
        /// The speed limit, metres per second.
        speed_limit_mps: f64,
        /// The car's largest steering angle (what steering 1 means), radians.
        max_steering_rad: f64,
    },
    /// One control step: what a lane keeper sees. Answered by one command line.
    Step {
        /// The step's number in the drive, from 1; the reply names it.
        step: u64,
        /// Simulated time since the drive began, seconds.
        t: f64,
        /// Speed over ground, metres per second.
        speed_mps: f64,
        /// Car centre, metres.
        x: f64,
        /// Car centre, metres.
        y: f64,
        /// Heading, radians counter-clockwise from east.
        heading_rad: f64,
        /// Distance from the lane centre, metres, positive when the car is left of it.
        lateral_offset_m: f64,
        /// Car heading minus the lane's direction, radians in `(-π, π]`, positive to the left.
        heading_error_rad: f64,
        /// Points of the lane centre ahead in the car's frame (x forward, y left), metres.
        ahead: Vec<Point>,
        /// The camera frame, when the controller asked for it.
        #[serde(skip_serializing_if = "Option::is_none")]
        camera: Option<CameraFrame>,
    },
    /// The drive ended (not answered).
    End,
    /// No more drives (not answered); the input closes next.
    Bye,
}

/// A controller's command, checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reply {
    /// Share of the largest steering angle, `[-1, 1]`, positive left.
    pub steering: f64,
    /// `[0, 1]`.
    pub throttle: f64,
    /// `[0, 1]`.
    pub brake: f64,
}

/// How the controller protocol names its lines, for the reading it shares with the executor
/// protocol ([`answer_object`]).
const WORDS: LineWords = LineWords {
    line: "reply",
    lines: "replies",
    request: "step",
    key: "step",
    version: VERSION,
};

/// Why a reply line is not a reply to the step asked; each names the field at fault.
pub type ReplyError = LineError;

/// Reads one reply line to step `asked`; `answered` is the step this controller replied to before
/// it, if any (in this drive or the one before), so that a late second reply is named as such.
pub fn parse_reply(line: &str, asked: u64, answered: Option<u64>) -> Result<Reply, ReplyError> {
    let object = answer_object(line, WORDS, asked, answered)?;
    let field = |name: &'static str, lo: f64| -> Result<f64, ReplyError> {
        match object.get(name).map(Value::as_f64) {
            Some(Some(v)) if (lo..=1.0).contains(&v) => Ok(v),
            Some(Some(v)) => Err(LineError::field(name, format!("{v} is outside [{lo}, 1]"))),
            Some(None) => Err(LineError::field(name, "not a number")),
            None => Err(LineError::field(name, "missing")),
        }
    };
    Ok(Reply {
        steering: field("steering", -1.0)?,
        throttle: field("throttle", 0.0)?,
        brake: field("brake", 0.0)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replies_are_checked_field_by_field() {
        let r = parse_reply(
            r#"{"step": 3, "steering": -0.5, "throttle": 1, "brake": 0, "note": "x"}"#,
            3,
            Some(2),
        )
        .unwrap();
        assert_eq!((r.steering, r.throttle, r.brake), (-0.5, 1.0, 0.0));
        for (line, says) in [
            ("nope", "not JSON"),
            ("[]", "not a JSON object"),
            (
                r#"{"steering": 0, "throttle": 0, "brake": 0}"#,
                "step: missing (version 2 replies name their step)",
            ),
            (
                r#"{"step": 2, "steering": 0, "throttle": 0, "brake": 0}"#,
                "more than one line for one request (a second reply to step 2)",
            ),
            (
                r#"{"step": 9, "steering": 0, "throttle": 0, "brake": 0}"#,
                "step: 9 is not the step asked (3)",
            ),
            (
                r#"{"step": -3, "steering": 0, "throttle": 0, "brake": 0}"#,
                "step: not a step number",
            ),
            (
                r#"{"step": 3, "throttle": 0, "brake": 0}"#,
                "steering: missing",
            ),
            (
                r#"{"step": 3, "steering": 2, "throttle": 0, "brake": 0}"#,
                "steering: 2 is outside [-1, 1]",
            ),
            (
                r#"{"step": 3, "steering": 0, "throttle": -0.1, "brake": 0}"#,
                "throttle: -0.1 is outside [0, 1]",
            ),
            (
                r#"{"step": 3, "steering": 0, "throttle": 0, "brake": "hard"}"#,
                "brake: not a number",
            ),
        ] {
            let error = parse_reply(line, 3, Some(2)).unwrap_err().to_string();
            assert!(error.contains(says), "{line}: {error}");
        }
        let step = Message::Step {
            step: 11,
            t: 0.5,
            speed_mps: 3.0,
            x: 1.0,
            y: 2.0,
            heading_rad: 0.1,
            lateral_offset_m: -0.2,
            heading_error_rad: 0.05,
            ahead: vec![[3.0, 0.1]],
            camera: None,
        };
        let text = serde_json::to_string(&step).unwrap();
        assert!(
            text.starts_with(r#"{"type":"step","step":11,"t":0.5,"#),
            "{text}"
        );
        assert!(!text.contains("camera"));
    }
}
