//! The executor protocol, version 3. wogan writes one JSON object per line, each with a `"type"`:
//! `hello` once when the executor starts, answered by the executor's own `hello` (the protocol and
//! version it speaks, and optionally what it is: `executor.name`, `executor.version`,
//! `executor.settings`, and `roads_at_once`: how many roads it drives at once, 1 to 1024, which
//! wogan keeps in flight to it, matching answers by `id` in any order: [`super::executor_pool`])
//! before any road is sent; `road` per road (answered by exactly one line);
//! `bye` before it closes the executor's input (not answered). An answer is one JSON object: `id`
//! (required: the road it answers) and `max_bolp` (required, in `[0, 1]`), and optionally
//! `outcome` (`PASS`, `FAIL` or `ERROR`; derived from the tolerance when absent), `sim_time_s`
//! (simulated seconds, charged to the execution budget; 0 when absent), `oob_side` (`left` or
//! `right`), `oob_point` (`[x, y]` metres: where the car centre was when it left, with `oob_side`),
//! `min_lane_distance_m` (the least signed distance of the car centre to its lane's edges, metres)
//! and `error` (text: why the road could not be driven, kept in the test record of an `ERROR`).
//! Other fields are ignored, so `wogan simulate`'s `result` lines, which echo the input's `id`, are
//! answers (and `simulate` answers `hello`).
//!
//! Version 2 added the answer's `id`: without it, a second line for one road could be taken for the
//! answer to the next, and every answer after it would be one road late. Version 3 made `hello`
//! answered: without a reply, a line an executor wrote before it had read anything was taken for
//! road 1's answer, as nothing told it from one written after.

use child_process::{answer_object, LineError, LineWords};
use road_sim::sim::CENTRED_DISTANCE_M;
use road_sim::{Outcome, Point};
use serde::Serialize;
use serde_json::Value;

/// The protocol's name in the `hello` line.
pub const PROTOCOL: &str = "wogan-executor";
/// The protocol's version.
pub const VERSION: u32 = 3;
/// Longest a drive may last in simulated seconds, as for wogan's own simulator.
pub const MAX_SIM_TIME_S: f64 = road_sim::sim::MAX_SIM_TIME_S;
/// Farthest a point an executor names may lie from the map's origin, metres: the longest road.
pub const MAX_COORDINATE_M: f64 = road_sim::validator::MAX_ROAD_LENGTH_M;

/// A line wogan writes to the executor.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(test, derive(schemars::JsonSchema))]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Request<'a> {
    /// The first line: what is spoken and how roads are judged.
    Hello {
        /// The protocol's name, `wogan-executor`.
        #[cfg_attr(test, schemars(schema_with = "super::protocol_schema::protocol_name"))]
        protocol: &'static str,
        /// The protocol's version, this one.
        #[cfg_attr(
            test,
            schemars(schema_with = "super::protocol_schema::protocol_version")
        )]
        version: u32,
        /// Units of every number: metres, seconds.
        units: &'static str,
        /// Side of the square map the roads lie on, metres.
        map_size_m: f64,
        /// A drive fails when its max BOLP exceeds this.
        oob_tolerance: f64,
        /// The speed limit of the drive, km/h.
        speed_limit_kmh: f64,
    },
    /// A road to drive: its control points, as the competition's tests give them.
    Road {
        /// The road's number, unique among the roads in flight (in `run`, the order it was sent
        /// in, from 1), which its answer names.
        id: usize,
        /// The road's points, metres.
        road_points: &'a [Point],
    },
    /// The last line: no more roads.
    Bye,
}

/// An executor's answer, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    /// Largest BOLP of the drive, `[0, 1]`.
    pub max_bolp: f64,
    /// The outcome: the executor's, or from `max_bolp` and the tolerance.
    pub outcome: Outcome,
    /// Simulated seconds.
    pub sim_time_s: f64,
    /// Which edge of its lane the car left over, when the executor says.
    pub oob_side: Option<road_sim::LaneSide>,
    /// Where the car centre was when it left its lane, metres, when the executor says.
    pub oob_point: Option<Point>,
    /// Why the road could not be driven, when the executor says (kept for an `ERROR`).
    pub error: Option<String>,
    /// The smallest signed distance of the car centre to its lane's edges over the drive, metres
    /// (2 in a 4 m lane when always centred, negative once the centre left the lane), when the
    /// executor says: what `--fitness distance` climbs.
    pub min_lane_distance_m: Option<f64>,
}

/// What an executor says of itself in its reply to `hello` (every field optional).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ExecutorDescription {
    /// Its name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Its own version.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
    /// Its own settings, as it gives them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settings: Option<serde_json::Map<String, Value>>,
}

/// Most roads one executor may take at once (`roads_at_once`).
pub const MAX_ROADS_AT_ONCE: usize = 1024;

/// The executor's reply to `hello`, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct HelloReply {
    /// Roads it drives at once: wogan keeps up to this many in flight to it (1 when it does not
    /// say), answered in any order.
    pub roads_at_once: usize,
    /// What it says of itself.
    pub description: ExecutorDescription,
}

/// Reads the executor's reply to `hello`: its own `hello`, of this protocol and version.
pub fn parse_hello_reply(line: &str) -> Result<HelloReply, AnswerError> {
    let value: Value = serde_json::from_str(line).map_err(|e| not_json(line, &e))?;
    let object = value
        .as_object()
        .ok_or(LineError::NotObject { line: WORDS.line })?;
    if object.get("type").and_then(Value::as_str) != Some("hello") {
        return Err(AnswerError::NoHello(child_process::quoted(line)));
    }
    match object.get("protocol") {
        Some(Value::String(p)) if p == PROTOCOL => {}
        other => {
            return Err(field(
                "protocol",
                format!("{} is not \"{PROTOCOL}\"", shown(other)),
            ))
        }
    }
    match object.get("version").and_then(Value::as_u64) {
        Some(v) if v == u64::from(VERSION) => {}
        _ => {
            return Err(field(
                "version",
                format!(
                    "{} is not {VERSION}, the version this wogan speaks",
                    shown(object.get("version"))
                ),
            ))
        }
    }
    let roads_at_once = match object.get("roads_at_once") {
        None | Some(Value::Null) => 1,
        Some(value) => match value.as_u64() {
            Some(n) if (1..=MAX_ROADS_AT_ONCE as u64).contains(&n) => n as usize,
            _ => {
                return Err(field(
                    "roads_at_once",
                    format!(
                        "{} is not a whole number from 1 to {MAX_ROADS_AT_ONCE}",
                        shown(Some(value))
                    ),
                ))
            }
        },
    };
    let description = executor_description(object.get("executor"))?;
    Ok(HelloReply {
        roads_at_once,
        description,
    })
}

/// The reply's `executor` object: what the executor says of itself.
fn executor_description(executor: Option<&Value>) -> Result<ExecutorDescription, AnswerError> {
    let Some(executor) = executor.filter(|e| !e.is_null()) else {
        return Ok(ExecutorDescription::default());
    };
    let executor = executor
        .as_object()
        .ok_or_else(|| field("executor", "not an object"))?;
    let text = |name: &'static str, key: &str| match executor.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(other) => Err(field(name, format!("{} is not text", shown(Some(other))))),
    };
    let settings = match executor.get("settings") {
        None | Some(Value::Null) => None,
        Some(Value::Object(settings)) => Some(settings.clone()),
        Some(other) => {
            return Err(field(
                "executor.settings",
                format!("{} is not an object", shown(Some(other))),
            ))
        }
    };
    Ok(ExecutorDescription {
        name: text("executor.name", "name")?,
        version: text("executor.version", "version")?,
        settings,
    })
}

/// A value as a message quotes it: its JSON, cut and printable ("nothing" when absent).
fn shown(value: Option<&Value>) -> String {
    value.map_or("nothing".into(), |v| child_process::quoted(&v.to_string()))
}

/// A line that is not JSON: serde's reason and the line's start.
fn not_json(line: &str, error: &serde_json::Error) -> AnswerError {
    AnswerError::Line(LineError::NotJson {
        line: WORDS.line,
        detail: format!("{error}: {}", child_process::quoted(line)),
    })
}

/// How the executor protocol names its lines, for the reading it shares with the controller
/// protocol ([`answer_object`]).
pub const WORDS: LineWords = LineWords {
    line: "answer",
    lines: "answers",
    request: "road",
    key: "id",
    version: VERSION,
};

/// Why a line is not the executor's reply to `hello` or its answer to the road asked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnswerError {
    /// Not a JSON object naming the road asked, or a field at fault (read as every protocol's
    /// answers are: [`LineError`]).
    #[error(transparent)]
    Line(#[from] LineError),
    /// The executor's first line is not its reply to `hello`.
    #[error(
        "its first line is not its reply to hello (version {VERSION} executors answer hello before \
         any road; see wogan's docs/reference.md): {0}"
    )]
    NoHello(String),
}

fn field(field: &'static str, problem: impl Into<String>) -> AnswerError {
    AnswerError::Line(LineError::field(field, problem))
}

/// Reads one answer line to road `asked`; `answered` is the road this executor answered before it,
/// if any, so that a late second answer to it is named as such. `needs_lane_distance`: the search
/// climbs the lane distance, so an answer without `min_lane_distance_m` is no answer (but for an
/// `ERROR`, which may have no drive to measure).
pub fn parse_answer(
    line: &str,
    asked: u64,
    answered: Option<u64>,
    oob_tolerance: f64,
    needs_lane_distance: bool,
) -> Result<Answer, AnswerError> {
    let object = answer_object(line, WORDS, asked, answered)?;
    let max_bolp = match object.get("max_bolp").map(Value::as_f64) {
        Some(Some(b)) if (0.0..=1.0).contains(&b) => b,
        Some(Some(b)) => return Err(field("max_bolp", format!("{b} is outside [0, 1]"))),
        Some(None) => return Err(field("max_bolp", "not a number")),
        None => return Err(field("max_bolp", "missing")),
    };
    let outcome = match object.get("outcome") {
        None | Some(Value::Null) if max_bolp > oob_tolerance => Outcome::Fail,
        None | Some(Value::Null) => Outcome::Pass,
        Some(Value::String(s)) if s == "PASS" => Outcome::Pass,
        Some(Value::String(s)) if s == "FAIL" => Outcome::Fail,
        Some(Value::String(s)) if s == "ERROR" => Outcome::Error,
        Some(other) => {
            return Err(field(
                "outcome",
                format!("{other} is not PASS, FAIL or ERROR"),
            ))
        }
    };
    let sim_time_s = match object.get("sim_time_s") {
        None | Some(Value::Null) => 0.0,
        Some(v) => match v.as_f64() {
            Some(t) if (0.0..=MAX_SIM_TIME_S).contains(&t) => t,
            _ => {
                return Err(field(
                    "sim_time_s",
                    format!("{v} is not a number of seconds from 0 to {MAX_SIM_TIME_S}"),
                ))
            }
        },
    };
    let oob_side = match object.get("oob_side") {
        None | Some(Value::Null) => None,
        Some(Value::String(s)) if s == "left" => Some(road_sim::LaneSide::Left),
        Some(Value::String(s)) if s == "right" => Some(road_sim::LaneSide::Right),
        Some(other) => {
            return Err(field(
                "oob_side",
                format!("{other} is not \"left\" or \"right\""),
            ))
        }
    };
    let oob_point = match object.get("oob_point") {
        None | Some(Value::Null) => None,
        Some(value) => {
            let point = value
                .as_array()
                .filter(|xy| xy.len() == 2)
                .and_then(|xy| Some([xy[0].as_f64()?, xy[1].as_f64()?]))
                .filter(|p| p.iter().all(|v| v.abs() <= MAX_COORDINATE_M));
            match point {
                Some(_) if oob_side.is_none() => {
                    return Err(field("oob_point", "given without oob_side"))
                }
                Some(p) => Some(p),
                None => {
                    return Err(field(
                        "oob_point",
                        format!(
                            "{} is not [x, y] in metres within {MAX_COORDINATE_M} of the origin",
                            shown(Some(value))
                        ),
                    ))
                }
            }
        }
    };
    let error = match object.get("error") {
        None | Some(Value::Null) => None,
        Some(Value::String(text)) => Some(text.clone()),
        Some(other) => return Err(field("error", format!("{other} is not text"))),
    };
    let min_lane_distance_m = match object.get("min_lane_distance_m") {
        // An executor's own ERROR may have no drive to measure.
        None | Some(Value::Null) if needs_lane_distance && outcome != Outcome::Error => {
            return Err(field(
                "min_lane_distance_m",
                "missing (the search climbs the lane distance: --fitness distance)",
            ))
        }
        None | Some(Value::Null) => None,
        Some(v) => match v.as_f64() {
            Some(d) if (-MAX_COORDINATE_M..=CENTRED_DISTANCE_M + 1e-6).contains(&d) => Some(d),
            _ => {
                return Err(field(
                    "min_lane_distance_m",
                    format!(
                        "{v} is not a number of metres from -{MAX_COORDINATE_M} to \
                         {CENTRED_DISTANCE_M} (the most a car centre can be from the edges of a 4 m \
                         lane)"
                    ),
                ))
            }
        },
    };
    Ok(Answer {
        max_bolp,
        outcome,
        sim_time_s,
        oob_side,
        oob_point,
        error,
        min_lane_distance_m,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_without_a_road_are_passed_over_by_the_road_readers() {
        // `wogan simulate` serves as an executor: it must pass over `hello` and `bye`.
        let hello = Request::Hello {
            protocol: PROTOCOL,
            version: VERSION,
            units: "m,s",
            map_size_m: 200.0,
            oob_tolerance: 0.85,
            speed_limit_kmh: 70.0,
        };
        for request in [hello, Request::Bye] {
            let line = serde_json::to_value(&request).unwrap();
            let kind = line["type"].as_str().unwrap();
            assert!(
                crate::files::road_input::PASSED_OVER.contains(&kind),
                "{kind}"
            );
        }
    }

    #[test]
    fn answers_are_checked_field_by_field() {
        let a = parse_answer(r#"{"id": 3, "max_bolp": 0.9}"#, 3, None, 0.85, false).unwrap();
        assert_eq!(
            (a.outcome, a.sim_time_s, a.oob_side),
            (Outcome::Fail, 0.0, None)
        );
        let a = parse_answer(r#"{"id": 3, "max_bolp": 0.5, "outcome": "ERROR", "sim_time_s": 7.5, "oob_side": "right", "x": 1}"#, 3, None, 0.85, false).unwrap();
        assert_eq!(a.outcome, Outcome::Error);
        assert_eq!(a.oob_side, Some(road_sim::LaneSide::Right));
        assert_eq!((a.oob_point, a.error), (None, None));
        // Where the car left, with its side.
        let a = parse_answer(
            r#"{"id": 3, "max_bolp": 0.9, "oob_side": "left", "oob_point": [101.5, 40.25]}"#,
            3,
            None,
            0.85,
            false,
        )
        .unwrap();
        assert_eq!(a.oob_point, Some([101.5, 40.25]));
        // An ERROR's reason, in the executor's words.
        let a = parse_answer(
            r#"{"id": 3, "max_bolp": 0, "outcome": "ERROR", "error": "MetaDrive: no lane"}"#,
            3,
            None,
            0.85,
            false,
        )
        .unwrap();
        assert_eq!(a.error.as_deref(), Some("MetaDrive: no lane"));
        // The lane distance, which a search on `--fitness distance` requires.
        let line = r#"{"id": 3, "max_bolp": 0, "min_lane_distance_m": 1.25}"#;
        let a = parse_answer(line, 3, None, 0.85, true).unwrap();
        assert_eq!(a.min_lane_distance_m, Some(1.25));
        let without = parse_answer(r#"{"id": 3, "max_bolp": 0}"#, 3, None, 0.85, true);
        assert!(without
            .unwrap_err()
            .to_string()
            .starts_with("min_lane_distance_m: missing"));
        let error = r#"{"id": 3, "max_bolp": 0, "outcome": "ERROR", "error": "no world"}"#;
        assert!(parse_answer(error, 3, None, 0.85, true).is_ok());
        assert_eq!(
            parse_answer(r#"{"id": 3, "max_bolp": 0}"#, 3, None, 0.85, false)
                .unwrap()
                .min_lane_distance_m,
            None
        );
        // `wogan simulate`'s answers are answers.
        let a = parse_answer(r#"{"type":"result","line":2,"id":3,"outcome":"PASS","reason":null,"max_bolp":1e-14,"sim_time_s":6.5}"#, 3, None, 0.85, false).unwrap();
        assert_eq!((a.outcome, a.sim_time_s), (Outcome::Pass, 6.5));
        for (line, says) in [
            ("nope", "not JSON"),
            ("[1]", "not a JSON object"),
            (
                r#"{"max_bolp": 0.1}"#,
                "id: missing (version 3 answers name their road)",
            ),
            (r#"{"id": "3", "max_bolp": 0.1}"#, "id: not a road number"),
            (
                r#"{"id": 4, "max_bolp": 0.1}"#,
                "id: 4 is not the road asked (3)",
            ),
            (
                r#"{"id": 2, "max_bolp": 0.1}"#,
                "more than one line for one request (a second answer to road 2)",
            ),
            (r#"{"id": 3}"#, "max_bolp: missing"),
            (r#"{"id": 3, "max_bolp": 1.5}"#, "outside [0, 1]"),
            (r#"{"id": 3, "max_bolp": "high"}"#, "max_bolp: not a number"),
            (
                r#"{"id": 3, "max_bolp": 0.1, "outcome": "MAYBE"}"#,
                "outcome:",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.1, "sim_time_s": -1}"#,
                "sim_time_s:",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.1, "oob_side": "up"}"#,
                "oob_side:",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.9, "oob_side": "left", "oob_point": [1]}"#,
                "oob_point: [1] is not [x, y] in metres within",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.9, "oob_side": "left", "oob_point": "here"}"#,
                "oob_point:",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.9, "oob_point": [1, 2]}"#,
                "oob_point: given without oob_side",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.1, "error": 7}"#,
                "error: 7 is not text",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.1, "min_lane_distance_m": 2.5}"#,
                "min_lane_distance_m: 2.5 is not",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.1, "min_lane_distance_m": "near"}"#,
                "min_lane_distance_m:",
            ),
            // Numbers that are JSON but no drive's: the run's sums would overflow.
            (
                r#"{"id": 3, "max_bolp": 0.1, "sim_time_s": 1e308}"#,
                "sim_time_s: 1e+308 is not a number of seconds from 0 to 3600",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.1, "min_lane_distance_m": -1e308}"#,
                "min_lane_distance_m: -1e+308 is not",
            ),
            (
                r#"{"id": 3, "max_bolp": 0.9, "oob_side": "left", "oob_point": [1e308, 0]}"#,
                "oob_point:",
            ),
            (
                "garbage \u{1b}[2J",
                "expected value at line 1 column 1: garbage \\x1b[2J",
            ),
        ] {
            let error = parse_answer(line, 3, Some(2), 0.85, false)
                .unwrap_err()
                .to_string();
            assert!(error.contains(says), "{line}: {error}");
        }
    }

    #[test]
    fn the_reply_to_hello_names_the_protocol_and_may_describe_the_executor() {
        let reply = parse_hello_reply(
            r#"{"type": "hello", "protocol": "wogan-executor", "version": 3, "roads_at_once": 32,
                "executor": {"name": "metadrive", "version": "0.4", "settings": {"policy": "idm"}}}"#,
        )
        .unwrap();
        assert_eq!(reply.roads_at_once, 32);
        let described = reply.description;
        assert_eq!(described.name.as_deref(), Some("metadrive"));
        assert_eq!(described.version.as_deref(), Some("0.4"));
        assert_eq!(described.settings.unwrap()["policy"], "idm");
        let bare = r#"{"type": "hello", "protocol": "wogan-executor", "version": 3}"#;
        assert_eq!(
            parse_hello_reply(bare).unwrap(),
            HelloReply {
                roads_at_once: 1,
                description: ExecutorDescription::default()
            }
        );
        for (line, says) in [
            // An answer written before anything was read is no reply (defect 19).
            (
                r#"{"id": 1, "max_bolp": 0.99}"#,
                "its first line is not its reply to hello",
            ),
            ("not json", "not JSON"),
            (
                r#"{"type": "hello", "protocol": "other", "version": 3}"#,
                "protocol:",
            ),
            (
                r#"{"type": "hello", "protocol": "wogan-executor", "version": 2}"#,
                "version: 2 is not 3",
            ),
            (
                r#"{"type": "hello", "protocol": "wogan-executor"}"#,
                "version: nothing is not 3",
            ),
            (
                r#"{"type": "hello", "protocol": "wogan-executor", "version": 3, "executor": {"name": 7}}"#,
                "executor.name: 7 is not text",
            ),
            (
                r#"{"type": "hello", "protocol": "wogan-executor", "version": 3, "executor": {"settings": []}}"#,
                "executor.settings: [] is not an object",
            ),
            (
                r#"{"type": "hello", "protocol": "wogan-executor", "version": 3, "roads_at_once": 0}"#,
                "roads_at_once: 0 is not a whole number from 1 to 1024",
            ),
            (
                r#"{"type": "hello", "protocol": "wogan-executor", "version": 3, "roads_at_once": 2.5}"#,
                "roads_at_once: 2.5 is not",
            ),
        ] {
            let error = parse_hello_reply(line).unwrap_err().to_string();
            assert!(error.contains(says), "{line}: {error}");
        }
    }
}
