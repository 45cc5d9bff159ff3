//! The executor protocol's and the controller protocol's messages as JSON Schema (draft 2020-12),
//! written from the types below and committed in `docs/protocols/` for other programs to check
//! against (the Python client's tests check its own lines and the lines a real wogan writes);
//! beside them, `wogan-simulator-constants.json`, the road geometry and drive rules of
//! wogan's simulator that an executor mirroring them reads (examples/metadrive/) instead of
//! copying them by hand. wogan's own requests are [`Request`], the type it writes them with; the executor's
//! reply to `hello` and its answers are read by hand-written parsers, whose every bound the types
//! here take from the same constants, and whose verdicts on the protocol's example lines are
//! checked against the schema's (below).
//!
//! `WOGAN_WRITE_SCHEMAS=1 cargo test -p wogan-cli protocol_schema` writes the files again after a
//! change; without it, a file that differs from what the types give fails the test.

use super::executor_protocol::{Request, MAX_COORDINATE_M, MAX_ROADS_AT_ONCE, PROTOCOL, VERSION};
use road_sim::driver::controller::protocol as controller;
use road_sim::sim::{CENTRED_DISTANCE_M, MAX_SIM_TIME_S};
use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde_json::Value;

/// The executor's reply to `hello`: the protocol it speaks, and optionally what it is.
#[derive(JsonSchema)]
#[allow(dead_code)]
struct HelloReply {
    /// Always `hello`.
    #[serde(rename = "type")]
    #[schemars(schema_with = "hello_type")]
    kind: String,
    /// Always `wogan-executor`.
    #[schemars(schema_with = "protocol_name")]
    protocol: String,
    /// The protocol version it speaks: wogan's.
    #[schemars(schema_with = "protocol_version")]
    version: u32,
    /// How many roads it drives at once (1 when absent); wogan keeps that many in flight to it.
    #[schemars(range(min = 1, max = MAX_ROADS_AT_ONCE))]
    roads_at_once: Option<u32>,
    /// What it is (every field optional), recorded in the run's header and summary.
    executor: Option<ExecutorDescription>,
}

/// What an executor says of itself.
#[derive(JsonSchema)]
#[allow(dead_code)]
struct ExecutorDescription {
    /// Its name (how reports label its runs).
    name: Option<String>,
    /// Its own version.
    version: Option<String>,
    /// Its own settings, as it gives them.
    settings: Option<serde_json::Map<String, Value>>,
}

/// One answer: how the drive of one road went. Fields wogan does not know are ignored.
#[derive(JsonSchema)]
#[allow(dead_code)]
#[schemars(extend("dependentRequired" = {"oob_point": ["oob_side"]}))]
struct Answer {
    /// The `id` of the road it answers.
    id: u64,
    /// The drive's largest BOLP: the share of the car outside its lane.
    #[schemars(range(min = 0.0, max = 1.0))]
    max_bolp: f64,
    /// The outcome; from `max_bolp` and the tolerance when absent.
    outcome: Option<AnswerOutcome>,
    /// Simulated seconds, charged to the execution budget (0 when absent).
    #[schemars(range(min = 0.0, max = MAX_SIM_TIME_S))]
    sim_time_s: Option<f64>,
    /// The lane edge the car left over.
    oob_side: Option<OobSide>,
    /// Where the car centre was when it left, metres (with `oob_side`).
    #[serde(default)]
    #[schemars(schema_with = "oob_point")]
    oob_point: Option<[f64; 2]>,
    /// The least signed distance of the car centre to its lane's edges, metres (needed by
    /// `--fitness distance`, but for an `ERROR`).
    #[schemars(range(min = -MAX_COORDINATE_M, max = CENTRED_DISTANCE_M))]
    min_lane_distance_m: Option<f64>,
    /// Why the road could not be driven (kept in an `ERROR` test's record).
    error: Option<String>,
}

/// An answer's outcome.
#[derive(JsonSchema)]
#[allow(dead_code, clippy::upper_case_acronyms)]
enum AnswerOutcome {
    PASS,
    FAIL,
    ERROR,
}

/// A lane edge.
#[derive(JsonSchema)]
#[allow(dead_code)]
#[serde(rename_all = "snake_case")]
enum OobSide {
    Left,
    Right,
}

/// A line wogan writes to a controller (road-sim's `driver::controller::protocol::Message`).
#[derive(JsonSchema)]
#[allow(dead_code)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum ControllerRequest {
    /// Once, first (not answered).
    Hello {
        /// The protocol's name, `wogan-controller`.
        #[schemars(schema_with = "controller_protocol_name")]
        protocol: String,
        /// The protocol's version, this one.
        #[schemars(schema_with = "controller_protocol_version")]
        version: u32,
        /// Units of every number.
        units: String,
        /// Control steps per simulated second.
        control_hz: f64,
        /// Whether each step carries the camera frame.
        camera: bool,
    },
    /// A drive begins (not answered).
    Road {
        /// The road's control points, metres.
        road_points: Vec<[f64; 2]>,
        /// The centre of the right lane, where the car should drive, about a point per metre.
        lane_centre: Vec<[f64; 2]>,
        /// The speed limit, metres per second.
        speed_limit_mps: f64,
        /// The car's largest steering angle (what steering 1 means), radians.
        max_steering_rad: f64,
    },
    /// One control step: what a lane keeper sees. Answered by one [`ControllerReply`].
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
        /// Car heading minus the lane's direction, radians, positive to the left.
        heading_error_rad: f64,
        /// Points of the lane centre ahead in the car's frame (x forward, y left), metres.
        ahead: Vec<[f64; 2]>,
        /// The camera frame, when the controller asked for it.
        #[serde(default)]
        camera: Option<CameraFrame>,
    },
    /// The drive ended (not answered).
    End,
    /// No more drives (not answered); the input closes next.
    Bye,
}

/// A camera frame of a step: gray values row by row, top row first.
#[derive(JsonSchema)]
#[allow(dead_code)]
#[serde(deny_unknown_fields)]
struct CameraFrame {
    /// Pixels across.
    width: u32,
    /// Pixels down.
    height: u32,
    /// `width x height` gray values in `[0, 255]`, row-major.
    gray: Vec<u8>,
}

/// A controller's reply to one step: its command. Fields wogan does not know are ignored.
#[derive(JsonSchema)]
#[allow(dead_code)]
struct ControllerReply {
    /// The step it answers.
    step: u64,
    /// Share of the car's largest steering angle, positive to the left.
    #[schemars(range(min = -1.0, max = 1.0))]
    steering: f64,
    /// Share of full throttle.
    #[schemars(range(min = 0.0, max = 1.0))]
    throttle: f64,
    /// Share of full braking.
    #[schemars(range(min = 0.0, max = 1.0))]
    brake: f64,
}

fn controller_protocol_name(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"const": controller::PROTOCOL})
}

fn controller_protocol_version(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"const": controller::VERSION})
}

fn hello_type(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"const": "hello"})
}

pub(super) fn protocol_name(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"const": PROTOCOL})
}

pub(super) fn protocol_version(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"const": VERSION})
}

fn oob_point(_: &mut SchemaGenerator) -> Schema {
    let coordinate =
        json_schema!({"type": "number", "minimum": -MAX_COORDINATE_M, "maximum": MAX_COORDINATE_M});
    json_schema!({
        "type": ["array", "null"],
        "prefixItems": [coordinate.clone(), coordinate],
        "minItems": 2,
        "maxItems": 2,
    })
}

/// The protocol's schema files: name and content.
pub fn schema_files() -> Vec<(String, String)> {
    let executor = format!("{PROTOCOL}-v{VERSION}");
    let controller = format!("{}-v{}", controller::PROTOCOL, controller::VERSION);
    let schemas = [
        (
            format!("{executor}.request"),
            "a line wogan writes to the executor",
            schemars::schema_for!(Request<'static>),
        ),
        (
            format!("{executor}.hello-reply"),
            "the executor's reply to hello",
            schemars::schema_for!(HelloReply),
        ),
        (
            format!("{executor}.answer"),
            "the executor's answer to one road",
            schemars::schema_for!(Answer),
        ),
        (
            format!("{controller}.request"),
            "a line wogan writes to the controller",
            schemars::schema_for!(ControllerRequest),
        ),
        (
            format!("{controller}.reply"),
            "the controller's reply to one step",
            schemars::schema_for!(ControllerReply),
        ),
    ];
    schemas
        .into_iter()
        .map(|(name, what, mut schema)| {
            schema.insert("$comment".into(), format!("{name}: {what}").into());
            let text = serde_json::to_string_pretty(&schema).expect("a schema is JSON") + "\n";
            (format!("{name}.schema.json"), text)
        })
        .collect()
}

/// The road geometry and drive rules of wogan's simulator, as an executor that mirrors them reads
/// them: each from the constant or default wogan itself uses.
pub fn simulator_constants() -> String {
    use road_sim::road::spline;
    use road_sim::sim::lane_monitor::{LEAD_IN_M, PROJECTION_WINDOW, WINDOW_AHEAD, WINDOW_BEHIND};
    let sim = road_sim::SimConfig::default();
    let constants = serde_json::json!({
        "$comment": "wogan's simulator: road geometry and drive rules, written by a test from the constants wogan uses (crates/cli/src/sut/protocol_schema.rs)",
        "road_width_m": road_sim::road::ROAD_WIDTH_M,
        "lane_width_m": road_sim::road::LANE_WIDTH_M,
        "interpolation_distance_m": spline::INTERPOLATION_DISTANCE_M,
        "min_samples": spline::MIN_SAMPLES,
        "rounding_decimals": spline::ROUNDING_DECIMALS,
        "max_road_length_m": spline::MAX_LENGTH_M,
        "start_offset_m": sim.start_offset_m,
        "end_distance_m": sim.end_distance_m,
        "end_segments": road_sim::sim::END_SEGMENTS,
        "timeout_base_s": sim.timeout_base_s,
        "timeout_speed_mps": sim.timeout_speed_mps,
        "not_moving_distance_m": sim.not_moving_distance_m,
        "not_moving_window_s": sim.not_moving_window_s,
        "max_sim_time_s": MAX_SIM_TIME_S,
        "lead_in_m": LEAD_IN_M,
        "projection_window_segments": [PROJECTION_WINDOW.0, PROJECTION_WINDOW.1],
        "lane_window_points": [WINDOW_BEHIND, WINDOW_AHEAD],
        "default_speed_limit_kmh": sim.speed_limit_kmh,
        "default_oob_tolerance": sim.oob_tolerance,
        "road_height_m": crate::files::sbst_format::ROAD_HEIGHT_M,
    });
    serde_json::to_string_pretty(&constants).expect("JSON") + "\n"
}

/// Where the schema files are committed.
fn folder() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/protocols")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sut::executor_protocol::{parse_answer, parse_hello_reply};

    #[test]
    fn the_committed_schemas_are_the_ones_the_types_give() {
        let write = std::env::var_os("WOGAN_WRITE_SCHEMAS").is_some();
        let constants = (
            "wogan-simulator-constants.json".to_owned(),
            simulator_constants(),
        );
        for (name, text) in schema_files().into_iter().chain([constants]) {
            let path = folder().join(&name);
            if write {
                std::fs::write(&path, &text).expect("docs/protocols is writable");
                continue;
            }
            let committed = std::fs::read_to_string(&path).unwrap_or_default();
            assert!(
                committed == text,
                "{} differs from what the message types give: if the protocol changed on \
                 purpose, run WOGAN_WRITE_SCHEMAS=1 cargo test -p wogan-cli protocol_schema and \
                 commit the files",
                path.display()
            );
        }
    }

    #[test]
    fn the_parsers_take_the_lines_the_schema_describes_and_refuse_its_bounds() {
        // Lines the schema accepts, which the parsers must take.
        let reply = r#"{"type":"hello","protocol":"wogan-executor","version":3,"roads_at_once":1024,"executor":{"name":"m","version":"1","settings":{"policy":"idm"}}}"#;
        assert!(parse_hello_reply(reply).is_ok());
        let answer = format!(
            r#"{{"id":1,"max_bolp":1.0,"outcome":"FAIL","sim_time_s":{MAX_SIM_TIME_S},"oob_side":"left","oob_point":[{MAX_COORDINATE_M},-{MAX_COORDINATE_M}],"min_lane_distance_m":-{MAX_COORDINATE_M},"error":null,"extra":1}}"#
        );
        assert!(
            parse_answer(&answer, 1, None, 0.85, true).is_ok(),
            "{answer}"
        );
        // Just past each bound the schema states: refused.
        for bad in [
            r#"{"type":"hello","protocol":"wogan-executor","version":3,"roads_at_once":1025}"#,
            r#"{"type":"hello","protocol":"wogan-executor","version":2}"#,
            r#"{"type":"hello","protocol":"other","version":3}"#,
        ] {
            assert!(parse_hello_reply(bad).is_err(), "{bad}");
        }
        let past = [
            r#"{"id":1,"max_bolp":1.01}"#.to_owned(),
            format!(
                r#"{{"id":1,"max_bolp":0.5,"sim_time_s":{}}}"#,
                MAX_SIM_TIME_S + 1.0
            ),
            r#"{"id":1,"max_bolp":0.5,"oob_point":[1,2]}"#.to_owned(),
            format!(
                r#"{{"id":1,"max_bolp":0.5,"oob_side":"left","oob_point":[{},0]}}"#,
                MAX_COORDINATE_M + 1.0
            ),
            format!(
                r#"{{"id":1,"max_bolp":0.5,"min_lane_distance_m":{}}}"#,
                CENTRED_DISTANCE_M + 0.01
            ),
            r#"{"id":1,"max_bolp":0.5,"outcome":"pass"}"#.to_owned(),
            r#"{"max_bolp":0.5}"#.to_owned(),
        ];
        for bad in past {
            assert!(parse_answer(&bad, 1, None, 0.85, false).is_err(), "{bad}");
        }
        // And the schema states those bounds.
        let files = schema_files();
        let answer_schema: Value = serde_json::from_str(&files[2].1).unwrap();
        assert!(files[2].0.ends_with(".answer.schema.json"));
        let properties = &answer_schema["properties"];
        assert_eq!(properties["max_bolp"]["maximum"], 1.0);
        assert_eq!(properties["sim_time_s"]["maximum"], MAX_SIM_TIME_S);
        assert_eq!(
            properties["min_lane_distance_m"]["maximum"],
            CENTRED_DISTANCE_M
        );
        assert_eq!(
            answer_schema["required"],
            serde_json::json!(["id", "max_bolp"])
        );
    }

    #[test]
    fn the_controller_schema_states_every_field_road_sim_writes() {
        use controller::{CameraFrame as Frame, Message};
        let files = schema_files();
        let (_, text) = files
            .iter()
            .find(|(name, _)| name == "wogan-controller-v2.request.schema.json")
            .expect("the controller's request schema");
        let schema: Value = serde_json::from_str(text).unwrap();
        let variants = schema["oneOf"].as_array().expect("one variant per type");
        let points = [[0.0, 0.0], [1.0, 1.0]];
        let messages = [
            Message::Hello {
                protocol: controller::PROTOCOL,
                version: controller::VERSION,
                units: "metres, seconds, radians",
                control_hz: 20.0,
                camera: true,
            },
            Message::Road {
                road_points: &points,
                lane_centre: &points,
                speed_limit_mps: 19.4,
                max_steering_rad: 0.6,
            },
            Message::Step {
                step: 1,
                t: 0.05,
                speed_mps: 1.0,
                x: 0.0,
                y: 0.0,
                heading_rad: 0.0,
                lateral_offset_m: 0.0,
                heading_error_rad: 0.0,
                ahead: vec![[1.0, 0.0]],
                camera: Some(Frame {
                    width: 1,
                    height: 1,
                    gray: vec![0],
                }),
            },
            Message::End,
            Message::Bye,
        ];
        for message in messages {
            let line = serde_json::to_value(&message).unwrap();
            let kind = &line["type"];
            let variant = variants
                .iter()
                .find(|v| &v["properties"]["type"]["const"] == kind)
                .unwrap_or_else(|| panic!("no variant for {kind}"));
            let written: Vec<&String> = line.as_object().unwrap().keys().collect();
            let stated: Vec<&String> = variant["properties"].as_object().unwrap().keys().collect();
            assert_eq!(written, stated, "{kind}");
        }
    }
}
