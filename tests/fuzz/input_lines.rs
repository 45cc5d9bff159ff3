//! Input lines: real records mutated (truncated, flipped, huge numbers, nesting, binary, ...).

use super::*;

/// One to six input lines, some blank, some ending in CRLF, the last sometimes without a newline.
/// Lines that hold nothing.
pub(super) const BLANK_LINES: [&[u8]; 3] = [b"", b"   ", b"\t"];

pub(super) fn input_lines(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let count = *pick(rng, &[1, 1, 2, 3, 4, 6]);
    let eol: &[u8] = if chance(rng, 0.1) { b"\r\n" } else { b"\n" };
    let mut out = Vec::new();
    for i in 0..count {
        if chance(rng, 0.1) {
            let blank = *pick(rng, &BLANK_LINES);
            out.extend_from_slice(blank);
            out.extend_from_slice(eol);
            notes.push(format!("blank line before input {}", i + 1));
        }
        let line = input_line(rng, corpus, &format!("input {}", i + 1), notes);
        out.extend_from_slice(&line);
        if i + 1 < count || chance(rng, 0.85) {
            out.extend_from_slice(eol);
        }
    }
    out
}

/// A road in one of the forms `validate` reads, or a record of another kind, mutated.
pub(super) fn input_line(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    label: &str,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let (mut value, base) = if chance(rng, 0.6) {
        road_value(rng, corpus)
    } else {
        let record = pick(rng, &corpus.records).clone();
        let kind = format!("{} record", record["type"].as_str().unwrap_or("?"));
        (record, kind)
    };
    let mut steps = vec![base];
    let mutations = if chance(rng, 0.25) {
        0
    } else {
        rng.random_range(1..=3)
    };
    let text_mutations = (0..mutations).filter(|_| chance(rng, 0.4)).count();
    for _ in text_mutations..mutations {
        steps.push(mutate_value(rng, &mut value));
    }
    let mut text = encode(rng, &value, 0.1, &mut steps);
    for _ in 0..text_mutations {
        steps.push(mutate_text(rng, &mut text));
    }
    notes.push(format!("{label}: {}", steps.join("; ")));
    text
}

/// `value` as JSON text: compact, or pretty-printed over many lines with probability `pretty`.
pub(super) fn encode(
    rng: &mut ChaCha8Rng,
    value: &Value,
    pretty: f64,
    steps: &mut Vec<String>,
) -> Vec<u8> {
    if chance(rng, pretty) {
        steps.push("pretty-printed".into());
        serde_json::to_vec_pretty(value).expect("a Value encodes")
    } else {
        serde_json::to_vec(value).expect("a Value encodes")
    }
}

/// A reference road in one of the forms `validate` reads.
pub(super) fn road_value(rng: &mut ChaCha8Rng, corpus: &Corpus) -> (Value, String) {
    let road = pick(rng, &corpus.roads);
    let points = road["road_points"].clone();
    let (value, form) = match rng.random_range(0..6) {
        0 => (road.clone(), "reference road"),
        1 => (points, "bare points"),
        2 => (json!({"curvature": road["curvature"]}), "curvature road"),
        3 => (
            json!({"curvature": road["curvature"], "step": 15.0}),
            "curvature road with step",
        ),
        4 => {
            let with_z: Vec<Value> = points
                .as_array()
                .into_iter()
                .flatten()
                .map(|p| json!([p[0], p[1], -28.0, 8.0]))
                .collect();
            (
                json!({"road_points": with_z, "interpolated_points": []}),
                "competition test",
            )
        }
        _ => {
            let run = pick(rng, &corpus.runs);
            let tests: Vec<&Value> = run.iter().filter(|r| r["type"] == "test").collect();
            let test = tests.choose(rng).map_or(Value::Null, |t| (*t).clone());
            (test, "run test record")
        }
    };
    (value, form.to_owned())
}

/// JSON numbers at the edges of `f64`, `u64` and `i64`.
pub(super) fn extreme_number(rng: &mut ChaCha8Rng) -> Value {
    match rng.random_range(0..3) {
        0 => Value::from(*pick(
            rng,
            &[
                0.0,
                -0.0,
                -1.0,
                1e308,
                -1e308,
                f64::MAX,
                f64::MIN,
                f64::MIN_POSITIVE,
                5e-324,
                1e300,
                -1e300,
                1e-300,
                1e15,
                1e9,
                3.5e38,
                1.000_000_000_000_1e300,
                0.5,
            ],
        )),
        1 => Value::from(*pick(
            rng,
            &[
                u64::MAX,
                4_294_967_295,
                4_294_967_296,
                9_007_199_254_740_993,
                0,
                1,
            ],
        )),
        _ => Value::from(*pick(rng, &[i64::MIN, -1, -4_294_967_296, i64::MAX])),
    }
}

/// Mutates `value` once, in one of the ways that change its meaning but keep it JSON; says how.
pub(super) fn mutate_value(rng: &mut ChaCha8Rng, value: &mut Value) -> String {
    match rng.random_range(0..10) {
        0 | 1 => {
            let new = extreme_number(rng);
            match pick_pointer(rng, value, Value::is_number) {
                Some(at) => {
                    set_pointer(value, &at, new.clone());
                    format!("{at} = {new}")
                }
                None => "no number to change".into(),
            }
        }
        2 => {
            let factor = *pick(rng, &[1e300, 1e10, -1.0, 1e-300, 0.0, 1e308, 1e15]);
            scale_numbers(value, factor);
            format!("every number times {factor:e}")
        }
        3 => {
            let Some(at) = pick_pointer(rng, value, is_point_list) else {
                return "no points to collapse".into();
            };
            let points = value
                .pointer_mut(&at)
                .and_then(Value::as_array_mut)
                .expect("a point list just found");
            match rng.random_range(0..3) {
                0 => {
                    let first = points[0].clone();
                    points.iter_mut().for_each(|p| *p = first.clone());
                    format!("{at}: every point the same")
                }
                1 => {
                    // Points a few ulps apart, as large as coordinates get: the spline and the
                    // distances between points divide by almost nothing.
                    let c = *pick(rng, &[1e300, -1e300, 1e15, 100.0]);
                    for (i, p) in points.iter_mut().enumerate() {
                        *p = json!([c, c * (1.0 + i as f64 * 1e-13)]);
                    }
                    format!("{at}: near-duplicate points at {c:e}")
                }
                _ => {
                    let i = rng.random_range(0..points.len());
                    let copy = points[i].clone();
                    points.insert(i, copy);
                    format!("{at}: point {i} repeated")
                }
            }
        }
        4 => {
            let Some(at) = pick_pointer(rng, value, Value::is_array) else {
                return "no array to resize".into();
            };
            let len = *pick(rng, &[0usize, 1, 2, 3, 50, 499, 500, 1000, 20_000]);
            let items = value
                .pointer_mut(&at)
                .and_then(Value::as_array_mut)
                .expect("an array just found");
            if items.is_empty() {
                items.push(json!(0.0));
            }
            let cycle: Vec<Value> = items.iter().cycle().take(len).cloned().collect();
            *items = cycle;
            format!("{at}: {len} items")
        }
        5 => {
            let kind = pick(
                rng,
                &[
                    json!("header"),
                    json!("test"),
                    json!("train"),
                    json!("summary"),
                    json!("error"),
                    json!("result"),
                    json!("verdict"),
                    json!("driver"),
                    json!("road"),
                    json!("sample"),
                    json!("future"),
                    json!(""),
                    json!("TEST"),
                    json!(7),
                    Value::Null,
                    json!(["test"]),
                ],
            )
            .clone();
            match value.as_object_mut() {
                Some(object) => {
                    object.insert("type".into(), kind.clone());
                    format!("type = {kind}")
                }
                None => "no object to retype".into(),
            }
        }
        6 => {
            let Some(at) =
                pick_pointer(rng, value, |v| v.as_object().is_some_and(|o| !o.is_empty()))
            else {
                return "no key to drop".into();
            };
            let object = value
                .pointer_mut(&at)
                .and_then(Value::as_object_mut)
                .expect("an object just found");
            let keys: Vec<String> = object.keys().cloned().collect();
            let key = pick(rng, &keys);
            object.remove(key);
            format!("{at}/{key} dropped")
        }
        7 => {
            let new = pick(
                rng,
                &[
                    json!("x"),
                    json!(true),
                    Value::Null,
                    json!([]),
                    json!({}),
                    json!([[]]),
                    json!(1),
                    json!("1.5"),
                    json!([1.0, 2.0]),
                ],
            )
            .clone();
            let at = pick_pointer(rng, value, |_| true).unwrap_or_default();
            set_pointer(value, &at, new.clone());
            format!("{at:?} replaced by {new}")
        }
        8 => {
            let (key, new) = match rng.random_range(0..4) {
                0 => ("step", extreme_number(rng)),
                1 => ("road_points", json!([[0.0, 0.0]])),
                2 => ("curvature", json!([])),
                _ => ("zz", json!({"a": [1, {"b": null}]})),
            };
            match value.as_object_mut() {
                Some(object) => {
                    object.insert(key.into(), new.clone());
                    format!("{key} = {new}")
                }
                None => "no object to extend".into(),
            }
        }
        _ => {
            let Some(at) = pick_pointer(rng, value, is_point) else {
                return "no point to reshape".into();
            };
            let point = value.pointer(&at).cloned().unwrap_or_default();
            let new = match rng.random_range(0..5) {
                0 => json!([point[0]]),
                1 => json!([point[0], point[1], 0.0, 8.0, 1.0]),
                2 => json!(["1", "2"]),
                3 => json!([null, null]),
                _ => json!([point[0], point[1], [1]]),
            };
            set_pointer(value, &at, new.clone());
            format!("{at} = {new}")
        }
    }
}

/// A point: an array of at least two numbers.
pub(super) fn is_point(value: &Value) -> bool {
    value
        .as_array()
        .is_some_and(|a| a.len() >= 2 && a.iter().all(Value::is_number))
}

/// A list of at least two points.
pub(super) fn is_point_list(value: &Value) -> bool {
    value
        .as_array()
        .is_some_and(|a| a.len() >= 2 && a.iter().all(is_point))
}

/// Multiplies every number in `value` by `factor` (a product that overflows becomes `null`).
pub(super) fn scale_numbers(value: &mut Value, factor: f64) {
    if let Some(x) = value.as_f64() {
        *value = Value::from(x * factor);
        return;
    }
    match value {
        Value::Array(items) => items.iter_mut().for_each(|v| scale_numbers(v, factor)),
        Value::Object(fields) => fields.values_mut().for_each(|v| scale_numbers(v, factor)),
        _ => {}
    }
}

/// The JSON pointer of a random node of `value` that `keep` accepts.
pub(super) fn pick_pointer(
    rng: &mut ChaCha8Rng,
    value: &Value,
    keep: fn(&Value) -> bool,
) -> Option<String> {
    pub(super) fn walk(
        value: &Value,
        at: &mut String,
        keep: fn(&Value) -> bool,
        found: &mut Vec<String>,
    ) {
        if keep(value) {
            found.push(at.clone());
        }
        let len = at.len();
        match value {
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    write!(at, "/{i}").expect("a String takes text");
                    walk(item, at, keep, found);
                    at.truncate(len);
                }
            }
            Value::Object(fields) => {
                for (key, item) in fields {
                    at.push('/');
                    at.push_str(&key.replace('~', "~0").replace('/', "~1"));
                    walk(item, at, keep, found);
                    at.truncate(len);
                }
            }
            _ => {}
        }
    }
    let mut found = Vec::new();
    walk(value, &mut String::new(), keep, &mut found);
    found.choose(rng).cloned()
}

/// Sets the node at `pointer` to `new`, making objects on the way where there are none (keys are
/// this harness's own, never escaped).
pub(super) fn set_pointer(root: &mut Value, pointer: &str, new: Value) {
    let mut node = root;
    for key in pointer.split('/').skip(1) {
        node = match node {
            Value::Array(items) => {
                let i = key.parse::<usize>().unwrap_or(0).min(items.len());
                if i == items.len() {
                    items.push(Value::Null);
                }
                &mut items[i]
            }
            other => {
                if !other.is_object() {
                    *other = json!({});
                }
                other
                    .as_object_mut()
                    .expect("an object just made")
                    .entry(key.to_owned())
                    .or_insert(Value::Null)
            }
        };
    }
    *node = new;
}

/// Numbers as JSON does not write them.
pub(super) const NON_JSON_NUMBERS: [&str; 16] = [
    "NaN",
    "-NaN",
    "Infinity",
    "-Infinity",
    "inf",
    "1e999",
    "-1e999",
    "1e-999",
    "0x10",
    "01",
    "1.",
    ".5",
    "+1",
    "1e",
    "--1",
    "1e+",
];

/// Mutates JSON text once, in one of the ways that may leave it not JSON; says how.
pub(super) fn mutate_text(rng: &mut ChaCha8Rng, text: &mut Vec<u8>) -> String {
    match rng.random_range(0..8) {
        0 => {
            let at = rng.random_range(0..=text.len());
            text.truncate(at);
            format!("truncated to {at} bytes")
        }
        1 => {
            let count = rng.random_range(1..=4);
            for _ in 0..count {
                if text.is_empty() {
                    break;
                }
                let i = rng.random_range(0..text.len());
                text[i] = *pick(rng, b"[]{},:\"-+.eE0123456789 \\nul");
            }
            format!("{count} bytes flipped")
        }
        2 => {
            let starts: Vec<usize> = (0..text.len())
                .filter(|&i| text[i].is_ascii_digit() && (i == 0 || !is_number_byte(text[i - 1])))
                .collect();
            let Some(&start) = starts.choose(rng) else {
                return "no number to spoil".into();
            };
            let end = (start..text.len())
                .find(|&i| !is_number_byte(text[i]))
                .unwrap_or(text.len());
            let long = "9".repeat(400);
            let new = if chance(rng, 0.1) {
                long.as_str()
            } else {
                *pick(rng, &NON_JSON_NUMBERS)
            };
            text.splice(start..end, new.bytes());
            format!("a number spelt {}", preview(new.as_bytes(), 20))
        }
        3 => {
            let at = rng.random_range(0..=text.len());
            let count = rng.random_range(1..=16);
            let bytes: Vec<u8> = (0..count).map(|_| rng.random::<u8>()).collect();
            text.splice(at..at, bytes);
            format!("{count} binary bytes at {at}")
        }
        4 => {
            let len = *pick(rng, &[10_000usize, 100_000, 1_000_000, 4_000_000]);
            match rng.random_range(0..3) {
                0 => {
                    let at = text.iter().position(|&b| b == b'{').map_or(0, |i| i + 1);
                    let pad = format!("\"pad\":\"{}\",", "x".repeat(len));
                    text.splice(at..at, pad.bytes());
                    format!("a {len}-byte string field")
                }
                1 => {
                    text.extend(std::iter::repeat_n(b' ', len));
                    format!("{len} trailing spaces")
                }
                _ => {
                    let at = text
                        .iter()
                        .position(u8::is_ascii_digit)
                        .unwrap_or(text.len());
                    let digits = format!("1{}", "0".repeat(len));
                    text.splice(at..at, digits.bytes());
                    format!("a {len}-digit number")
                }
            }
        }
        5 => {
            let depth = *pick(rng, &[2usize, 64, 127, 128, 129, 1000, 100_000]);
            let (open, close): (&[u8], &[u8]) = if chance(rng, 0.5) {
                (b"[", b"]")
            } else {
                (b"{\"a\":", b"}")
            };
            let mut nested = open.repeat(depth);
            nested.append(text);
            nested.extend(close.repeat(depth));
            *text = nested;
            format!("nested {depth} deep")
        }
        6 => {
            let whole = *pick(
                rng,
                &[
                    "",
                    " ",
                    "null",
                    "[]",
                    "{}",
                    "[[]]",
                    "\"\"",
                    "0",
                    "-1",
                    "[1,2]",
                    "{\"type\":\"test\"}",
                    "{\"type\":null}",
                    "[[0,0]]",
                    "\u{feff}{}",
                    "{\"road_points\":null}",
                    "{\"curvature\":[]}",
                ],
            );
            *text = whole.as_bytes().to_vec();
            format!("replaced by {whole:?}")
        }
        _ => {
            let copy = text.clone();
            text.push(b' ');
            text.extend(copy);
            "written twice on the line".into()
        }
    }
}

pub(super) fn is_number_byte(b: u8) -> bool {
    b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-')
}
