//! The roads `wogan replay` drives again, read from any file that holds saved roads: a run (its
//! `test` records), a suite (its `road` entries), `wogan sample`'s roads, road files in the forms
//! `validate` reads, the competition's `test.NNNN.json` (one object, pretty-printed or not), or a
//! folder of those. Each road keeps what was recorded of its drive, so that a replay can say what
//! changed.

use super::road_input::road_reader;
use crate::files::json_lines::{json_values, open_input};
use crate::files::records::{SuiteHeader, SuiteRoad, SUITE_FORMAT, SUITE_VERSION};
use crate::files::sbst_format::test_files;
use road_sim::road::Point;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// One road to drive again.
#[derive(Debug, Clone)]
pub struct SavedRoad {
    /// The file it came from.
    pub file: PathBuf,
    /// The line of that file it begins on, from 1.
    pub line: usize,
    /// Its name: a suite entry's, `test N` for a run's or an export's test, else `line N`.
    pub name: String,
    /// Its points, metres.
    pub road_points: Vec<Point>,
    /// The outcome recorded (`PASS`, `FAIL`, `ERROR`, `INVALID`), when the file says.
    pub recorded_outcome: Option<String>,
    /// The largest BOLP recorded, when the file says.
    pub recorded_max_bolp: Option<f64>,
}

/// Every road of `paths` in order, and one message per input that could not be used (naming the
/// file, line and field); the good roads are read whatever the bad ones.
pub fn read_saved_roads(paths: &[PathBuf], map_size_m: f64) -> (Vec<SavedRoad>, Vec<String>) {
    let mut roads = Vec::new();
    let mut problems = Vec::new();
    for path in paths {
        let files = match files_of(path) {
            Ok(files) => files,
            Err(problem) => {
                problems.push(problem);
                continue;
            }
        };
        for file in files {
            read_file(&file, map_size_m, &mut roads, &mut problems);
        }
    }
    (roads, problems)
}

/// `path` itself, or for a folder its `test.NNNN.json` files (an export's) in number order.
fn files_of(path: &Path) -> Result<Vec<PathBuf>, String> {
    if !path.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let files = test_files(path).map_err(|e| format!("{}: cannot list: {e}", path.display()))?;
    if files.is_empty() {
        return Err(format!(
            "{}: a folder without test.NNNN.json files (the competition's export)",
            path.display()
        ));
    }
    Ok(files)
}

/// Reads the roads of one file into `roads`, its problems into `problems`.
fn read_file(file: &Path, map_size_m: f64, roads: &mut Vec<SavedRoad>, problems: &mut Vec<String>) {
    let input = match open_input(Some(file)) {
        Ok(input) => input,
        Err(error) => {
            problems.push(format!("{error:#}"));
            return;
        }
    };
    for value in json_values(input) {
        let line = match value {
            Ok(line) => line,
            Err(error) => {
                problems.push(format!("{}: cannot read: {error}", file.display()));
                return;
            }
        };
        let at = format!("{}:{}", file.display(), line.number);
        let parsed = line
            .text
            .and_then(|text| {
                serde_json::from_str::<Value>(&text).map_err(|e| format!("not JSON: {e}"))
            })
            .and_then(|value| saved_road(&value, map_size_m));
        match parsed {
            Ok(Some(found)) => roads.push(SavedRoad {
                file: file.to_path_buf(),
                line: line.number,
                name: found
                    .name
                    .unwrap_or_else(|| format!("line {}", line.number)),
                road_points: found.road_points,
                recorded_outcome: found.recorded_outcome,
                recorded_max_bolp: found.recorded_max_bolp,
            }),
            Ok(None) => {}
            Err(problem) => problems.push(format!("{at}: {problem}")),
        }
    }
}

/// A road found in one JSON value, before it is placed in its file.
struct Found {
    name: Option<String>,
    road_points: Vec<Point>,
    recorded_outcome: Option<String>,
    recorded_max_bolp: Option<f64>,
}

/// What one JSON value of a file holds: a road, nothing to drive (a run's header, train and
/// summary records, a suite's header), or a problem.
fn saved_road(value: &Value, map_size_m: f64) -> Result<Option<Found>, String> {
    let text = |key: &str| value.get(key).and_then(Value::as_str).map(str::to_owned);
    let number = |key: &str| value.get(key).and_then(Value::as_f64);
    let (name, recorded_outcome, recorded_max_bolp) =
        match value.get("type").and_then(Value::as_str) {
            Some("header" | "train" | "summary" | "driver") => return Ok(None),
            Some("suite") => {
                let header: SuiteHeader = serde_json::from_value(value.clone())
                    .map_err(|e| format!("a suite header: {e}"))?;
                check_suite_header(&header)?;
                return Ok(None);
            }
            Some("road") => {
                let mut fields = value.clone();
                if let Some(object) = fields.as_object_mut() {
                    object.remove("type");
                }
                let entry: SuiteRoad =
                    serde_json::from_value(fields).map_err(|e| format!("a suite road: {e}"))?;
                return Ok(Some(Found {
                    name: Some(entry.name),
                    road_points: entry.road_points,
                    recorded_outcome: Some(entry.recorded.outcome.name().to_owned()),
                    recorded_max_bolp: Some(entry.recorded.max_bolp),
                }));
            }
            Some("sample") => (
                value
                    .get("rank")
                    .and_then(Value::as_u64)
                    .map(|rank| format!("sample {rank}")),
                None,
                None,
            ),
            Some("test") => (
                value
                    .get("id")
                    .and_then(Value::as_u64)
                    .map(|id| format!("test {id}")),
                text("outcome"),
                number("max_bolp"),
            ),
            Some(other @ ("result" | "verdict" | "error" | "replay")) => {
                return Err(format!(
                    "a `{other}` record holds no road: give the file of roads it answered instead"
                ))
            }
            Some(other) => return Err(format!("type: a `{other}` record holds no road")),
            // The competition's test object, or a road in a form `validate` reads.
            None => (
                value
                    .get("id")
                    .and_then(Value::as_u64)
                    .map(|id| format!("test {id}")),
                text("test_outcome"),
                None,
            ),
        };
    let road = road_reader(map_size_m)
        .read_value(value)
        .map_err(|e| e.to_string())?;
    let points = road
        .points()
        .ok_or_else(|| "holds no road".to_owned())?
        .to_vec();
    Ok(Some(Found {
        name,
        road_points: points,
        recorded_outcome,
        recorded_max_bolp,
    }))
}

/// Refuses a suite of another format or of a newer layout than this `wogan` reads.
pub fn check_suite_header(header: &SuiteHeader) -> Result<(), String> {
    if header.format != SUITE_FORMAT {
        return Err(format!(
            "format: {:?} is not a wogan suite ({SUITE_FORMAT:?})",
            header.format
        ));
    }
    if header.version > SUITE_VERSION {
        return Err(format!(
            "version: suite layout {} is newer than this wogan reads ({SUITE_VERSION}); update wogan",
            header.version
        ));
    }
    Ok(())
}
