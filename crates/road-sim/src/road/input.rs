//! Reading roads from JSON: the competition's test objects, any object with `road_points` (as
//! `wogan run`'s `test` records), `{"curvature": [...], "step": 15}` and bare `[[x, y], ...]`
//! arrays. The reader is told which object types hold no road and pass through unanswered (its
//! caller's own records); this crate knows no one's wire format.

use super::curvature::{CurvatureRoad, DEFAULT_STEP_M};
use super::Point;
use serde_json::Value;

/// What one input line holds.
#[derive(Debug, Clone, PartialEq)]
pub enum RoadInput {
    /// A road given by its points.
    Points(Vec<Point>),
    /// A road given by curvature values (1/m), turned into points.
    Curvature {
        /// Curvature values, 1/m.
        curvature: Vec<f64>,
        /// The road points they make.
        points: Vec<Point>,
    },
    /// An object of a type the reader passes over ([`RoadReader::passed_over`]) that holds no
    /// road: nothing to do.
    Skip,
}

impl RoadInput {
    /// The road points, if the input holds a road.
    pub fn points(&self) -> Option<&[Point]> {
        match self {
            RoadInput::Points(points) | RoadInput::Curvature { points, .. } => Some(points),
            RoadInput::Skip => None,
        }
    }
}

/// Why an input line holds no road; the text names the field at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    /// The line is not JSON.
    #[error("not JSON: {0}")]
    NotJson(String),
    /// The JSON has none of the accepted road forms.
    #[error("no road: expected an object with \"road_points\" or \"curvature\", or an array of [x, y] points")]
    NoRoad,
    /// A field holds the wrong kind of value.
    #[error("{field}: {problem}")]
    BadField {
        /// Where in the object, e.g. `road_points[3]`.
        field: String,
        /// What is wrong with it.
        problem: String,
    },
}

fn bad(field: impl Into<String>, problem: impl Into<String>) -> InputError {
    InputError::BadField {
        field: field.into(),
        problem: problem.into(),
    }
}

/// How roads are read: where curvature roads are placed, and which objects hold no road.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadReader<'a> {
    /// The map's side, metres: curvature roads start at its bottom centre.
    pub map_size_m: f64,
    /// Object `type`s that hold no road (a caller's own records): such an object without a road
    /// is [`RoadInput::Skip`], not an error.
    pub passed_over: &'a [&'a str],
}

impl RoadReader<'_> {
    /// Reads one line of input.
    pub fn read_line(&self, line: &str) -> Result<RoadInput, InputError> {
        let value: Value =
            serde_json::from_str(line).map_err(|e| InputError::NotJson(e.to_string()))?;
        self.read_value(&value)
    }

    /// Reads a road from an already parsed JSON value.
    pub fn read_value(&self, value: &Value) -> Result<RoadInput, InputError> {
        let map_size_m = self.map_size_m;
        match value {
            Value::Array(_) => Ok(RoadInput::Points(points_of(value, "road")?)),
            Value::Object(object) => {
                if let Some(points) = object.get("road_points") {
                    return Ok(RoadInput::Points(points_of(points, "road_points")?));
                }
                if let Some(curvature) = object.get("curvature") {
                    let curvature = numbers_of(curvature, "curvature")?;
                    let step_m = match object.get("step") {
                        None | Some(Value::Null) => DEFAULT_STEP_M,
                        Some(step) => step
                            .as_f64()
                            .filter(|s| s.is_finite() && *s > 0.0)
                            .ok_or_else(|| bad("step", "expected a positive number of metres"))?,
                    };
                    let points = CurvatureRoad {
                        map_size_m,
                        step_m,
                        ..CurvatureRoad::default()
                    }
                    .points(&curvature);
                    return Ok(RoadInput::Curvature { curvature, points });
                }
                // A run's own records pass through a pipe without an answer, unless they hold a road.
                match object.get("type").and_then(Value::as_str) {
                    Some(kind) if self.passed_over.contains(&kind) => Ok(RoadInput::Skip),
                    _ => Err(InputError::NoRoad),
                }
            }
            _ => Err(InputError::NoRoad),
        }
    }
}

fn numbers_of(value: &Value, field: &str) -> Result<Vec<f64>, InputError> {
    let items = value
        .as_array()
        .ok_or_else(|| bad(field, "expected an array of numbers"))?;
    items
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.as_f64()
                .ok_or_else(|| bad(format!("{field}[{i}]"), "expected a number"))
        })
        .collect()
}

/// Points as `[x, y]` (extra entries, like the competition's z and width, are ignored).
fn points_of(value: &Value, field: &str) -> Result<Vec<Point>, InputError> {
    let items = value
        .as_array()
        .ok_or_else(|| bad(field, "expected an array of [x, y] points"))?;
    items
        .iter()
        .enumerate()
        .map(|(i, point)| {
            let coords = point.as_array().filter(|c| c.len() >= 2);
            match coords.map(|c| (c[0].as_f64(), c[1].as_f64())) {
                Some((Some(x), Some(y))) => Ok([x, y]),
                _ => Err(bad(format!("{field}[{i}]"), "expected [x, y] with numbers")),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads `line` on a 200 m map passing over `summary` and `header` objects.
    fn parse_line(line: &str, map_size_m: f64) -> Result<RoadInput, InputError> {
        let reader = RoadReader {
            map_size_m,
            passed_over: &["summary", "header"],
        };
        reader.read_line(line)
    }

    #[test]
    fn accepts_every_road_form() {
        let bare = parse_line("[[1, 2], [3, 4]]", 200.0).unwrap();
        assert_eq!(bare, RoadInput::Points(vec![[1.0, 2.0], [3.0, 4.0]]));
        let competition = parse_line(
            r#"{"road_points": [[1, 2, -28, 8], [3, 4, -28, 8]]}"#,
            200.0,
        )
        .unwrap();
        assert_eq!(competition, bare);
        let record = parse_line(
            r#"{"type": "test", "id": 3, "road_points": [[1, 2], [3, 4]]}"#,
            200.0,
        )
        .unwrap();
        assert_eq!(record, bare);
        let curvature = parse_line(r#"{"curvature": [0, 0], "step": 10}"#, 100.0).unwrap();
        assert_eq!(
            curvature.points().unwrap(),
            &[[50.0, 10.0], [50.0, 20.0], [50.0, 30.0]]
        );
        assert_eq!(
            parse_line(r#"{"type": "summary"}"#, 200.0).unwrap(),
            RoadInput::Skip
        );
        // A record of a kind without a road that holds one anyway is a road.
        assert_eq!(
            parse_line(
                r#"{"type": "header", "road_points": [[1, 2], [3, 4]]}"#,
                200.0
            )
            .unwrap(),
            RoadInput::Points(vec![[1.0, 2.0], [3.0, 4.0]])
        );
    }

    #[test]
    fn errors_name_the_field() {
        let err = parse_line(r#"{"road_points": [[1, 2], [3, "x"]]}"#, 200.0).unwrap_err();
        assert_eq!(
            err.to_string(),
            "road_points[1]: expected [x, y] with numbers"
        );
        let err = parse_line(r#"{"curvature": [0.1, null]}"#, 200.0).unwrap_err();
        assert_eq!(err.to_string(), "curvature[1]: expected a number");
        assert!(matches!(
            parse_line("{nope", 200.0),
            Err(InputError::NotJson(_))
        ));
        assert_eq!(parse_line(r#"{"a": 1}"#, 200.0), Err(InputError::NoRoad));
        // A type the reader was not told to pass over is no road.
        assert_eq!(
            parse_line(r#"{"type": "train"}"#, 200.0),
            Err(InputError::NoRoad)
        );
        assert_eq!(parse_line("42", 200.0), Err(InputError::NoRoad));
    }
}
