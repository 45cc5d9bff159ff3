//! Reading one line a program wrote in answer to a numbered request: what both protocols' readers
//! share (the executor's answer to a road, the controller's reply to a step). The line must be one
//! JSON object naming the request it answers ([`Echo`]); each protocol then reads its own fields,
//! and every refusal names the field at fault in the same words.

use crate::{quoted, Echo};
use serde_json::{Map, Value};

/// What a protocol calls its lines and requests, for its messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineWords {
    /// What the program writes: `answer`, `reply`.
    pub line: &'static str,
    /// The same, more than one: `answers`, `replies`.
    pub lines: &'static str,
    /// What the program is asked about: `road`, `step`.
    pub request: &'static str,
    /// The field of the line naming its request: `id`, `step`.
    pub key: &'static str,
    /// The protocol version since which lines name their request.
    pub version: u32,
}

/// Why a line is not the answer to the request asked; each names the field at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineError {
    /// The line is not JSON: serde's reason and the line's start.
    #[error("the {line} is not JSON: {detail}")]
    NotJson {
        /// What the line was to be.
        line: &'static str,
        /// Why, with the line quoted.
        detail: String,
    },
    /// The line is JSON but not an object.
    #[error("the {line} is not a JSON object")]
    NotObject {
        /// What the line was to be.
        line: &'static str,
    },
    /// A field is missing, of the wrong kind or out of range.
    #[error("{field}: {problem}")]
    Field {
        /// The field's name.
        field: &'static str,
        /// What is wrong with it.
        problem: String,
    },
    /// A second answer to a request the program had already answered.
    #[error("it wrote more than one line for one request (a second {line} to {request} {number})")]
    Second {
        /// What the line is.
        line: &'static str,
        /// What was asked.
        request: &'static str,
        /// The request it answered again.
        number: u64,
    },
}

impl LineError {
    /// A field at fault.
    pub fn field(field: &'static str, problem: impl Into<String>) -> Self {
        LineError::Field {
            field,
            problem: problem.into(),
        }
    }
}

/// The JSON object `line` holds, read as the answer to request `asked` (the request answered
/// before it, if any, is `answered`, so that a late second answer to it is named as such).
pub fn answer_object(
    line: &str,
    words: LineWords,
    asked: u64,
    answered: Option<u64>,
) -> Result<Map<String, Value>, LineError> {
    let value: Value = serde_json::from_str(line).map_err(|e| LineError::NotJson {
        line: words.line,
        detail: format!("{e}: {}", quoted(line)),
    })?;
    let Value::Object(object) = value else {
        return Err(LineError::NotObject { line: words.line });
    };
    let LineWords {
        line: noun,
        lines,
        request,
        key,
        version,
    } = words;
    match Echo::of(object.get(key), asked, answered) {
        Echo::Asked => Ok(object),
        Echo::Repeat(number) => Err(LineError::Second {
            line: noun,
            request,
            number,
        }),
        Echo::Other(n) => Err(LineError::field(
            key,
            format!("{n} is not the {request} asked ({asked})"),
        )),
        Echo::NotANumber => Err(LineError::field(key, format!("not a {request} number"))),
        Echo::Missing => Err(LineError::field(
            key,
            format!("missing (version {version} {lines} name their {request})"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WORDS: LineWords = LineWords {
        line: "answer",
        lines: "answers",
        request: "road",
        key: "id",
        version: 3,
    };

    #[test]
    fn a_line_is_an_object_naming_the_request_asked() {
        assert!(answer_object(r#"{"id": 4, "x": 1}"#, WORDS, 4, Some(3)).is_ok());
        for (line, says) in [
            ("nope", "the answer is not JSON: "),
            ("[1]", "the answer is not a JSON object"),
            (
                r#"{"x": 1}"#,
                "id: missing (version 3 answers name their road)",
            ),
            (r#"{"id": "4"}"#, "id: not a road number"),
            (r#"{"id": 9}"#, "id: 9 is not the road asked (4)"),
            (
                r#"{"id": 3}"#,
                "it wrote more than one line for one request (a second answer to road 3)",
            ),
        ] {
            let error = answer_object(line, WORDS, 4, Some(3)).unwrap_err();
            assert!(error.to_string().starts_with(says), "{line}: {error}");
        }
    }
}
