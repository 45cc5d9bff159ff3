//! The regression suite file (`wogan suite`): the failing roads a team keeps in its repository and
//! `wogan replay` drives on every commit. JSON lines, versioned: a header line
//! (`{"type": "suite", "format": "wogan-suite", "version": 1}`), then one `road` line per road
//! ([`SuiteRoad`]: name, points, the recorded drive, the run it came from). Written whole at once,
//! so a suite is never left half written; read strictly, naming the line and field at fault.

use crate::files::json_lines::{json_values, open_input};
use crate::files::records::{Record, SuiteHeader, SuiteRoad, SUITE_FORMAT, SUITE_VERSION};
use crate::files::saved_roads::check_suite_header;
use anyhow::{Context, Result};
use road_sim::road::heading_profile::heading_profile;
use road_sim::Road;
use serde_json::Value;
use std::path::Path;
use wogan_core::diversity::euclidean;

/// The roads of a suite, in file order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Suite {
    /// Its roads.
    pub roads: Vec<SuiteRoad>,
}

/// Reads the suite at `path`; every problem found, each naming its line, is an error (a suite
/// that cannot be read whole cannot be rewritten without losing what it holds).
pub fn read(path: &Path) -> Result<Suite> {
    let input = open_input(Some(path))?;
    let mut roads = Vec::new();
    let mut problems = Vec::new();
    let mut header_seen = false;
    for value in json_values(input) {
        let line = value.with_context(|| format!("cannot read {}", path.display()))?;
        let at = format!("{}:{}", path.display(), line.number);
        let value = line.text.and_then(|text| {
            serde_json::from_str::<Value>(&text).map_err(|e| format!("not JSON: {e}"))
        });
        // What the line says it is comes first: a foreign file is named as such, not by the
        // fields its records would lack.
        let record = value.and_then(|value| {
            if !header_seen && value.get("type").and_then(Value::as_str) != Some("suite") {
                return Err(format!(
                    "not a wogan suite: its first line must be {{\"type\": \"suite\", \"format\": \"{SUITE_FORMAT}\", ...}}"
                ));
            }
            serde_json::from_value::<Record>(value).map_err(|e| e.to_string())
        });
        match record {
            Ok(Record::Suite(header)) if !header_seen && roads.is_empty() => {
                if let Err(problem) = check_suite_header(&header) {
                    problems.push(format!("{at}: {problem}"));
                }
                header_seen = true;
            }
            Ok(Record::Road(road)) if header_seen => roads.push(road),
            Ok(_) if !header_seen => problems.push(format!(
                "{at}: not a wogan suite: its first line must be {{\"type\": \"suite\", \"format\": \"{SUITE_FORMAT}\", ...}}"
            )),
            Ok(_) => problems.push(format!("{at}: type: a suite holds only `road` lines after its header")),
            Err(problem) => problems.push(format!("{at}: {problem}")),
        }
        if !header_seen && !problems.is_empty() {
            break;
        }
    }
    if !header_seen && problems.is_empty() {
        problems.push(format!("{}: empty: not a wogan suite", path.display()));
    }
    if !problems.is_empty() {
        anyhow::bail!("{}", problems.join("\n"));
    }
    Ok(Suite { roads })
}

/// Writes `suite` to `path`, whole at once.
pub fn write(path: &Path, suite: &Suite) -> Result<()> {
    let mut text = serde_json::to_string(&Record::<serde_json::Value>::Suite(SuiteHeader {
        format: SUITE_FORMAT.to_owned(),
        version: SUITE_VERSION,
    }))?;
    text.push('\n');
    for road in &suite.roads {
        text.push_str(&serde_json::to_string(&Record::<serde_json::Value>::Road(
            road.clone(),
        ))?);
        text.push('\n');
    }
    crate::files::output_file::write(path, text.as_bytes())
        .with_context(|| format!("cannot write the suite {}", path.display()))
}

/// A road's description for comparing roads: its heading profile (unwrapped); `None` for
/// points that make no road.
pub fn profile_of(road_points: &[road_sim::Point]) -> Option<Vec<f64>> {
    Road::new(road_points)
        .ok()
        .map(|road| heading_profile(&road.interpolated))
}

/// Farthest-point selection: which of `candidates` to add to `kept` so that together they are at
/// most `total`, each added one the candidate farthest (the Euclidean distance of heading
/// profiles) from every road kept or added so far. With nothing kept, the first pick is the
/// candidate of highest `priority` (the earliest of equals). Ties go to the earliest candidate.
/// Returns candidate indices in the order picked.
pub fn farthest_points(
    kept: &[Vec<f64>],
    candidates: &[Vec<f64>],
    priority: &[f64],
    total: usize,
) -> Vec<usize> {
    let room = total.saturating_sub(kept.len()).min(candidates.len());
    let mut picked: Vec<usize> = Vec::with_capacity(room);
    // Each candidate's distance to the nearest road kept or picked.
    let mut nearest: Vec<f64> = candidates
        .iter()
        .map(|c| {
            kept.iter()
                .map(|k| euclidean(c, k))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    while picked.len() < room {
        let score = |i: usize| {
            if kept.is_empty() && picked.is_empty() {
                priority.get(i).copied().unwrap_or(0.0)
            } else {
                nearest[i]
            }
        };
        let best = (0..candidates.len()).filter(|i| !picked.contains(i)).fold(
            None,
            |best: Option<usize>, i| match best {
                Some(b) if score(b) >= score(i) => Some(b),
                _ => Some(i),
            },
        );
        let Some(best) = best else { break };
        picked.push(best);
        for (i, distance) in nearest.iter_mut().enumerate() {
            *distance = distance.min(euclidean(&candidates[i], &candidates[best]));
        }
    }
    picked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn farthest_points_spread_over_the_space_and_keep_what_is_kept() {
        let points = |xs: &[f64]| xs.iter().map(|x| vec![*x]).collect::<Vec<_>>();
        let candidates = points(&[0.0, 0.1, 5.0, 10.0, 9.9]);
        // Nothing kept: the highest priority first, then the farthest from it, and so on.
        let picked = farthest_points(&[], &candidates, &[0.1, 0.9, 0.2, 0.3, 0.4], 3);
        assert_eq!(picked, vec![1, 3, 2]);
        // A kept road near 10 makes 0 the farthest; the cap counts the kept ones.
        let picked = farthest_points(&points(&[10.0]), &candidates, &[0.0; 5], 3);
        assert_eq!(picked, vec![0, 2]);
        // No room: nothing added, whatever the candidates.
        assert!(farthest_points(&points(&[1.0, 2.0]), &candidates, &[0.0; 5], 2).is_empty());
    }

    #[test]
    fn a_suite_round_trips_and_a_foreign_file_is_named_by_line() {
        let dir = std::env::temp_dir().join(format!("wogan-suite-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("suite.jsonl");
        let road: SuiteRoad = serde_json::from_value(serde_json::json!({
            "name": "run#3", "road_points": [[10.0, 10.0], [10.0, 40.0], [20.0, 60.0]],
            "recorded": {"outcome": "FAIL", "max_bolp": 0.93},
            "origin": {"run": "run.jsonl", "test": 3, "seed": 7, "driver": "beamng-ai-proxy",
                       "oob_tolerance": 0.85, "wogan": "0.1.0"}
        }))
        .unwrap();
        let suite = Suite { roads: vec![road] };
        write(&path, &suite).unwrap();
        assert_eq!(read(&path).unwrap(), suite);
        std::fs::write(&path, "{\"type\":\"header\",\"version\":\"0.1.0\"}\n").unwrap();
        let error = read(&path).unwrap_err().to_string();
        assert!(
            error.contains("suite.jsonl:1: not a wogan suite"),
            "{error}"
        );
        std::fs::write(
            &path,
            "{\"type\":\"suite\",\"format\":\"wogan-suite\",\"version\":9}\n",
        )
        .unwrap();
        let error = read(&path).unwrap_err().to_string();
        assert!(
            error.contains(":1: version: suite layout 9 is newer"),
            "{error}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
