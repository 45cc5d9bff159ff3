//! The executor protocol's messages as JSON Schema (draft 2020-12), written from the types below
//! and committed in `docs/protocols/` for other programs to check against (the Python client's
//! tests do). wogan's own requests are [`Request`], the type it writes them with; the executor's
//! reply to `hello` and its answers are read by hand-written parsers, whose every bound the types
//! here take from the same constants, and whose verdicts on the protocol's example lines are
//! checked against the schema's (below).
//!
//! `WOGAN_WRITE_SCHEMAS=1 cargo test -p wogan-cli protocol_schema` writes the files again after a
//! change; without it, a file that differs from what the types give fails the test.

use super::executor_protocol::{Request, MAX_COORDINATE_M, MAX_ROADS_AT_ONCE, PROTOCOL, VERSION};
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
    let mut request = schemars::schema_for!(Request<'static>);
    request.insert(
        "$comment".into(),
        format!("{PROTOCOL} protocol, version {VERSION}: a line wogan writes to the executor")
            .into(),
    );
    let mut files = vec![("request", request)];
    let mut reply = schemars::schema_for!(HelloReply);
    reply.insert(
        "$comment".into(),
        format!("{PROTOCOL} protocol, version {VERSION}: the executor's reply to hello").into(),
    );
    files.push(("hello-reply", reply));
    let mut answer = schemars::schema_for!(Answer);
    answer.insert(
        "$comment".into(),
        format!("{PROTOCOL} protocol, version {VERSION}: the executor's answer to one road").into(),
    );
    files.push(("answer", answer));
    files
        .into_iter()
        .map(|(name, schema)| {
            let text = serde_json::to_string_pretty(&schema).expect("a schema is JSON") + "\n";
            (format!("{PROTOCOL}-v{VERSION}.{name}.schema.json"), text)
        })
        .collect()
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
        for (name, text) in schema_files() {
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
}
