//! Input files: runs, traces, config and weights files, mutated like lines.

use super::*;

/// Fields of every test record (of a run) or sample (of a trace) that a report plots or sums.
pub(super) const COLUMNS: [&str; 22] = [
    "fitness",
    "max_bolp",
    "min_lane_distance_m",
    "fitness_distance",
    "sim_time_s",
    "execution_ms",
    "generation_ms",
    "MAX_CURV",
    "DIR_COV",
    "STD_SA",
    "MEAN_LP",
    "MAX_LP",
    "predicted_fitness",
    "invalid_candidates",
    "ranked_candidates",
    "id",
    "t",
    "x",
    "y",
    "speed_kmh",
    "bolp",
    "steering_deg",
];
/// Places in a run's header that the report and export read.
pub(super) const HEADER_FIELDS: [&str; 11] = [
    "/config/road/map_size_m",
    "/config/sim/oob_tolerance",
    "/config/sim/speed_limit_kmh",
    "/config/search/wogan/target_decay",
    "/config/max_tests",
    "/seed",
    "/algorithm",
    "/oracle",
    "/fitness",
    "/config",
    "/version",
];

/// A file of JSON lines made from `base` (a run or a trace), mutated: records changed, one field
/// of every record made extreme, the header's settings changed, records dropped, repeated,
/// shuffled or of other kinds inserted, lines spoiled as text, the file cut short.
pub(super) fn records_file(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    base: &[Value],
    name: &str,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let mut records = base.to_vec();
    let mut steps = Vec::new();
    let mut spoiled_lines = 0;
    let ops = if chance(rng, 0.2) {
        0
    } else {
        rng.random_range(1..=3)
    };
    for _ in 0..ops {
        if records.is_empty() {
            break;
        }
        match rng.random_range(0..9) {
            0 | 1 => {
                let i = rng.random_range(0..records.len());
                let how = mutate_value(rng, &mut records[i]);
                steps.push(format!("record {}: {how}", i + 1));
            }
            2 => {
                let field = *pick(rng, &COLUMNS);
                let new = if chance(rng, 0.2) {
                    Value::Null
                } else {
                    extreme_number(rng)
                };
                for record in records.iter_mut().filter(|r| r.get(field).is_some()) {
                    record[field] = new.clone();
                }
                steps.push(format!("every {field} = {new}"));
            }
            3 => {
                let at = *pick(rng, &HEADER_FIELDS);
                let new = if chance(rng, 0.6) {
                    extreme_number(rng)
                } else {
                    pick(rng, &[json!("bogus"), Value::Null, json!([]), json!({})]).clone()
                };
                if let Some(header) = records.iter_mut().find(|r| r["type"] == "header") {
                    set_pointer(header, at, new.clone());
                    steps.push(format!("header {at} = {new}"));
                }
            }
            4 => {
                let kind = *pick(rng, &["header", "summary", "road", "test"]);
                records.retain(|r| r["type"] != kind);
                steps.push(format!("{kind} records dropped"));
            }
            5 => {
                let i = rng.random_range(0..records.len());
                let times = *pick(rng, &[2usize, 10, 50]);
                let copy = records[i].clone();
                records.splice(i..i, std::iter::repeat_n(copy, times - 1));
                steps.push(format!("record {} repeated {times} times", i + 1));
            }
            6 => {
                records.shuffle(rng);
                steps.push("records shuffled".into());
            }
            7 => {
                let record = pick(rng, &corpus.records).clone();
                let at = rng.random_range(0..=records.len());
                steps.push(format!(
                    "a {} record inserted at {}",
                    record["type"].as_str().unwrap_or("?"),
                    at + 1
                ));
                records.insert(at, record);
            }
            _ => spoiled_lines += 1,
        }
    }
    let mut lines: Vec<Vec<u8>> = records
        .iter()
        .map(|r| serde_json::to_vec(r).expect("a Value encodes"))
        .collect();
    for _ in 0..spoiled_lines {
        if lines.is_empty() {
            break;
        }
        let i = rng.random_range(0..lines.len());
        let how = mutate_text(rng, &mut lines[i]);
        steps.push(format!("line {}: {how}", i + 1));
    }
    if !lines.is_empty() && chance(rng, 0.05) {
        // Lines and records still correspond: spoiling a line changed its text only.
        let i = rng.random_range(0..lines.len());
        lines[i] = serde_json::to_vec_pretty(&records[i]).expect("a Value encodes");
        steps.push(format!("line {} pretty-printed", i + 1));
    }
    let mut file = lines.join(&b'\n');
    file.push(b'\n');
    if chance(rng, 0.1) {
        let at = rng.random_range(0..=file.len());
        file.truncate(at);
        steps.push(format!("file cut at byte {at}"));
    }
    if steps.is_empty() {
        steps.push("unchanged".into());
    }
    notes.push(format!("{name}: {}", steps.join("; ")));
    file
}

/// A `run --config` file: 1 to 3 settings (any field of any section) set to extreme values or
/// values of the wrong type, sometimes with unknown fields, the old layout that kept the driver
/// under `sim`, sections of the wrong type, or spoiled as text.
pub(super) fn config_file(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    oracle: DriverKind,
    notes: &mut Vec<String>,
) -> Vec<u8> {
    let defaults = corpus.config_defaults(oracle);
    let mut config = if chance(rng, 0.15) {
        defaults.clone()
    } else {
        json!({})
    };
    let mut steps = Vec::new();
    for _ in 0..rng.random_range(1..=3) {
        let at = pick_pointer(rng, defaults, |v| !v.is_object()).expect("a leaf setting");
        let new = extreme_setting(rng, defaults.pointer(&at));
        set_pointer(&mut config, &at, new.clone());
        steps.push(format!("{at} = {new}"));
    }
    if chance(rng, 0.15) {
        match rng.random_range(0..3) {
            0 => {
                let at = *pick(
                    rng,
                    &[
                        "/bogus",
                        "/sim/bogus",
                        "/search/wogan/bogus",
                        "/driver/bogus",
                    ],
                );
                set_pointer(&mut config, at, json!(1));
                steps.push(format!("unknown {at}"));
            }
            1 => {
                // The layout before config.driver: the driver's section under `sim`.
                let old = if oracle == DriverKind::Dave2Proxy {
                    "/sim/dave2"
                } else {
                    "/sim/beamng_ai"
                };
                let driver = config.get("driver").cloned().unwrap_or_else(|| json!({}));
                if chance(rng, 0.5) {
                    if let Some(fields) = config.as_object_mut() {
                        fields.remove("driver");
                    }
                }
                set_pointer(&mut config, old, driver);
                steps.push(format!("the driver section at {old}"));
            }
            _ => {
                let section = *pick(rng, &["/sim", "/search", "/driver", "/search/wogan"]);
                let new = pick(rng, &[Value::Null, json!([]), json!("x"), json!(1)]).clone();
                set_pointer(&mut config, section, new.clone());
                steps.push(format!("{section} = {new}"));
            }
        }
    }
    let mut text = encode(rng, &config, 0.3, &mut steps);
    if chance(rng, 0.15) {
        steps.push(mutate_text(rng, &mut text));
    }
    notes.push(format!("config.json: {}", steps.join("; ")));
    text
}

/// A value for a setting whose default is `default`: integers at and beyond every integer type,
/// floats that are zero, negative, tiny, huge or beyond `f32`, other names, or the wrong type.
pub(super) fn extreme_setting(rng: &mut ChaCha8Rng, default: Option<&Value>) -> Value {
    if chance(rng, 0.1) {
        return pick(
            rng,
            &[json!("1"), Value::Null, json!([]), json!({}), json!(true)],
        )
        .clone();
    }
    match default {
        Some(v) if v.is_u64() || v.is_i64() => pick(
            rng,
            &[
                json!(0),
                json!(1),
                json!(2),
                json!(1000),
                json!(65_536),
                json!(4_294_967_295_u64),
                json!(4_294_967_296_u64),
                json!(u64::MAX),
                json!(-1),
                json!(1.5),
                json!(1e20),
            ],
        )
        .clone(),
        Some(Value::Number(_)) => Value::from(*pick(
            rng,
            &[
                0.0,
                -0.0,
                -1.0,
                1e-300,
                5e-324,
                1e-9,
                0.999_999_999,
                1.000_000_1,
                100.0,
                1e9,
                1e15,
                3.5e38,
                1e308,
                -1e308,
            ],
        )),
        Some(Value::String(_)) => pick(
            rng,
            &[json!("random"), json!("wogan"), json!("bogus"), json!("")],
        )
        .clone(),
        Some(Value::Bool(b)) => json!(!b),
        _ => extreme_number(rng),
    }
}

/// A `--driver-weights` file: valid, with weights non-finite or huge, cut short, with a spoilt
/// header, empty, random bytes, or too long; `None` for a path that is no file.
pub(super) fn weights_file(
    rng: &mut ChaCha8Rng,
    corpus: &Corpus,
    notes: &mut Vec<String>,
) -> Option<Vec<u8>> {
    let mut bytes = corpus.weights.clone();
    let how = match rng.random_range(0..9) {
        0 => "valid".to_owned(),
        1 | 2 => {
            let value = *pick(
                rng,
                &[
                    f32::NAN,
                    f32::INFINITY,
                    f32::NEG_INFINITY,
                    f32::MAX,
                    -f32::MAX,
                    1e30,
                    0.0,
                    1e-45,
                ],
            );
            let all = chance(rng, 0.3);
            // After the blob's 12-byte header (magic, version, count), one f32 per weight.
            let count = (bytes.len() - 12) / 4;
            let chosen: Vec<usize> = if all {
                (0..count).collect()
            } else {
                (0..rng.random_range(1..=100))
                    .map(|_| rng.random_range(0..count))
                    .collect()
            };
            for i in chosen {
                bytes[12 + 4 * i..16 + 4 * i].copy_from_slice(&value.to_le_bytes());
            }
            format!("{} weights = {value:e}", if all { "all" } else { "some" })
        }
        3 => {
            let at = rng.random_range(0..bytes.len());
            bytes.truncate(at);
            format!("cut at byte {at}")
        }
        4 => {
            let i = rng.random_range(0..12);
            bytes[i] ^= 0xff;
            format!("header byte {i} flipped")
        }
        5 => {
            bytes.clear();
            "empty".to_owned()
        }
        6 => {
            let len = rng.random_range(0..4096);
            bytes = (0..len).map(|_| rng.random::<u8>()).collect();
            format!("{len} random bytes")
        }
        7 => {
            bytes.extend_from_slice(&[0; 16]);
            "16 bytes too long".to_owned()
        }
        _ => {
            notes.push("weights: not a file".into());
            return None;
        }
    };
    notes.push(format!("weights.bin: {how}"));
    Some(bytes)
}

/// The ONNX models of tests/fixtures/onnx/, by name.
const ONNX_FIXTURES: [(&str, &[u8]); 5] = [
    (
        "dave2-proxy",
        include_bytes!("../fixtures/onnx/dave2-proxy.onnx"),
    ),
    ("rgb_mean", include_bytes!("../fixtures/onnx/rgb_mean.onnx")),
    (
        "nan_on_road",
        include_bytes!("../fixtures/onnx/nan_on_road.onnx"),
    ),
    ("rank2", include_bytes!("../fixtures/onnx/rank2.onnx")),
    (
        "three_outputs",
        include_bytes!("../fixtures/onnx/three_outputs.onnx"),
    ),
];

/// A model for `--oracle onnx:FILE`: a fixture as it is (good, or broken in a way the loader
/// names), or cut, with flipped bytes, empty or random; `None` for no file.
pub(super) fn onnx_model_file(rng: &mut ChaCha8Rng, notes: &mut Vec<String>) -> Option<Vec<u8>> {
    let (name, fixture) = *pick(rng, &ONNX_FIXTURES);
    let mut bytes = fixture.to_vec();
    let how = match rng.random_range(0..8) {
        0..=2 => format!("{name} as it is"),
        3 => {
            let at = rng.random_range(0..bytes.len());
            bytes.truncate(at);
            format!("{name} cut at byte {at}")
        }
        4 | 5 => {
            let flips = rng.random_range(1..=20);
            for _ in 0..flips {
                let i = rng.random_range(0..bytes.len().min(4096));
                bytes[i] ^= 1 << rng.random_range(0..8);
            }
            format!("{name} with {flips} bits flipped in its first 4 KiB")
        }
        6 => {
            let len = rng.random_range(0..4096);
            bytes = (0..len).map(|_| rng.random::<u8>()).collect();
            format!("{len} random bytes")
        }
        _ => {
            notes.push("model: not a file".into());
            return None;
        }
    };
    notes.push(format!("model.onnx: {how}"));
    Some(bytes)
}
