//! The failing roads a page shows: one row per failing test of every run reported, and the
//! geometry its detail view draws (the centre line thinned, the lane exit, a trace when re-driven).

use crate::files::run_file::RunFile;
use road_sim::{Point, Road};
use serde_json::{json, Value};

/// Spacing the centre line is thinned to for the page, metres: the chord of a 10 m-radius bend
/// over 2 m strays 5 cm from the arc, well under a lane's width, and a long road stays small.
pub const CENTRE_LINE_STEP_M: f64 = 2.0;
/// Most samples a trace keeps for the page (evenly taken, the last always kept).
pub const TRACE_SAMPLES: usize = 400;
/// Most points the page keeps of a failing road whose points make no road (too long, a point
/// repeated): its recorded points thinned to [`CENTRE_LINE_STEP_M`], then evenly taken. Such a
/// road has no length to count in the page's size bound, so what it carries must fit in its share
/// of it, [`super::page::BYTES_PER_ROAD`], however many points the run recorded (at most 14 bytes
/// a point, as on the map, leaves room for its row).
pub const UNMADE_ROAD_POINTS: usize = 32;

/// One failing road as the page shows it.
#[derive(Debug, Clone)]
pub struct FailingRoad {
    /// The group (0-based, as the report orders them).
    pub group: usize,
    /// The run within its group (0-based, input order).
    pub run: usize,
    /// The run's file name.
    pub run_file: String,
    /// The test's id in its run.
    pub test: usize,
    /// The largest share of the car outside its lane over the drive.
    pub max_bolp: f64,
    /// The edge the car crossed (`left`, `right`), when the record says.
    pub side: Option<&'static str>,
    /// The road's centre-line length, metres (NaN when its points make no road).
    pub length_m: f64,
    /// The centre line, thinned to [`CENTRE_LINE_STEP_M`] (when the road's points make no road, at
    /// most [`UNMADE_ROAD_POINTS`] of them).
    pub centre_line: Vec<Point>,
    /// Where the car's centre was when it left its lane, when the record says.
    pub exit: Option<[f64; 2]>,
    /// The road's points as recorded (what a re-drive drives).
    pub road_points: Vec<Point>,
    /// The drive again, when re-driven ([`super::redrive`]).
    pub trace: Option<RoadTrace>,
}

/// A re-driven failing road's trace.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadTrace {
    /// The driver that drove it (the run's).
    pub driver: String,
    /// The outcome of the drive now (`PASS`, `FAIL`, `ERROR`).
    pub outcome: String,
    /// The drive's largest BOLP now.
    pub max_bolp: f64,
    /// Samples: simulated time (s), car centre x and y (m), BOLP; at most [`TRACE_SAMPLES`].
    pub samples: Vec<[f64; 4]>,
}

/// The failing roads of `groups` (each a group's runs), in group, run and test order.
pub fn failing_roads(groups: &[&[RunFile]]) -> Vec<FailingRoad> {
    let mut roads = Vec::new();
    for (group, runs) in groups.iter().enumerate() {
        for (run, file) in runs.iter().enumerate() {
            let run_file = file.path.file_name().map_or_else(
                || file.path.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            for test in file.tests.iter().filter(|t| t.failed()) {
                let points = &test.execution.road_points;
                let (length_m, centre_line) = match Road::new(points) {
                    Ok(road) => (
                        road.length_m(),
                        thinned(&road.interpolated, CENTRE_LINE_STEP_M),
                    ),
                    Err(_) => (
                        f64::NAN,
                        evenly_taken(&thinned(points, CENTRE_LINE_STEP_M), UNMADE_ROAD_POINTS),
                    ),
                };
                let oob = test.execution.result.oob.as_ref();
                roads.push(FailingRoad {
                    group,
                    run,
                    run_file: run_file.clone(),
                    test: test.id,
                    max_bolp: test.execution.result.max_bolp,
                    side: oob.map(|o| o.side.name()),
                    length_m,
                    centre_line,
                    exit: oob.and_then(|o| o.place()),
                    road_points: points.clone(),
                    trace: None,
                });
            }
        }
    }
    roads
}

/// `line` with points dropped so that those kept lie about `step_m` apart along it; the first and
/// last are always kept.
pub fn thinned(line: &[Point], step_m: f64) -> Vec<Point> {
    let Some((&first, rest)) = line.split_first() else {
        return Vec::new();
    };
    let mut kept = vec![first];
    let mut since_m = 0.0;
    let mut previous = first;
    for (index, &point) in rest.iter().enumerate() {
        since_m += (point[0] - previous[0]).hypot(point[1] - previous[1]);
        previous = point;
        if since_m >= step_m || index + 1 == rest.len() {
            kept.push(point);
            since_m = 0.0;
        }
    }
    kept
}

/// At most `most` of `points`, evenly spaced by index, the first and last always among them.
fn evenly_taken(points: &[Point], most: usize) -> Vec<Point> {
    if points.len() <= most {
        return points.to_vec();
    }
    if most < 2 {
        return points[..most].to_vec();
    }
    let last = points.len() - 1;
    (0..most).map(|i| points[i * last / (most - 1)]).collect()
}

/// `value` rounded to `decimals` (what the page carries: centimetres are below what it draws).
fn rounded(value: f64, decimals: i32) -> Value {
    if !value.is_finite() {
        return Value::Null;
    }
    let scale = 10f64.powi(decimals);
    json!((value * scale).round() / scale)
}

/// A point as `[x, y]` in decimetres' precision.
fn point_json(point: [f64; 2]) -> Value {
    json!([rounded(point[0], 1), rounded(point[1], 1)])
}

impl FailingRoad {
    /// What the detail view needs, as the page's JSON carries it (short keys: a page of thousands
    /// of roads stays small).
    pub fn to_json(&self) -> Value {
        let mut value = json!({
            "line": self.centre_line.iter().map(|&p| point_json(p)).collect::<Vec<_>>(),
            "exit": self.exit.map(point_json),
        });
        if let Some(trace) = &self.trace {
            value["trace"] = json!({
                "driver": trace.driver,
                "outcome": trace.outcome,
                "max_bolp": rounded(trace.max_bolp, 3),
                "t": trace.samples.iter().map(|s| rounded(s[0], 2)).collect::<Vec<_>>(),
                "xy": trace.samples.iter().map(|s| point_json([s[1], s[2]])).collect::<Vec<_>>(),
                "bolp": trace.samples.iter().map(|s| rounded(s[3], 3)).collect::<Vec<_>>(),
            });
        }
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_ends_and_points_about_a_step_apart() {
        let line: Vec<Point> = (0..=100).map(|i| [f64::from(i) * 0.5, 0.0]).collect();
        let kept = thinned(&line, 2.0);
        assert_eq!(kept.first(), Some(&[0.0, 0.0]));
        assert_eq!(kept.last(), Some(&[50.0, 0.0]));
        assert_eq!(kept.len(), 26);
        assert!(kept.windows(2).all(|w| (w[1][0] - w[0][0]) <= 2.0 + 1e-9));
        assert!(thinned(&[], 2.0).is_empty());
        assert_eq!(thinned(&[[1.0, 1.0]], 2.0), vec![[1.0, 1.0]]);
    }

    #[test]
    fn even_taking_keeps_the_ends_and_at_most_so_many() {
        let line: Vec<Point> = (0..=100).map(|i| [f64::from(i), 0.0]).collect();
        let kept = evenly_taken(&line, 5);
        assert_eq!(
            kept,
            vec![
                [0.0, 0.0],
                [25.0, 0.0],
                [50.0, 0.0],
                [75.0, 0.0],
                [100.0, 0.0]
            ]
        );
        assert_eq!(evenly_taken(&line[..3], 5), line[..3].to_vec());
        assert_eq!(evenly_taken(&line, 1), vec![[0.0, 0.0]]);
        assert!(evenly_taken(&line, 0).is_empty());
    }

    #[test]
    fn a_million_points_that_make_no_road_fit_a_roads_share_of_the_page() {
        // 31.8 km of points 3 cm apart: longer than any road (20 km), so no road.
        let points: Vec<Point> = (0..1_000_000)
            .map(|i| {
                let i = f64::from(i);
                [100.0 + 50.0 * (i * 0.001).sin(), 10.0 + i * 0.00018]
            })
            .collect();
        assert!(Road::new(&points).is_err());
        // A failing test of a fixture run, with those points.
        let fixture = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/fixtures/wogan.seed3.jsonl"
        );
        let mut record: Value = std::fs::read_to_string(fixture)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str::<Value>(l).unwrap())
            .find(|r| r["outcome"] == "FAIL")
            .expect("a failing test");
        record["road_points"] = json!(points);
        let run = RunFile {
            path: "run.jsonl".into(),
            header: None,
            tests: vec![serde_json::from_value(record).unwrap()],
            beyond_budget: vec![],
            train_ms: 0.0,
            pipeline_invalid: 0,
            summary: None,
            problems: vec![],
        };
        let roads = failing_roads(&[std::slice::from_ref(&run)]);
        assert_eq!(roads.len(), 1);
        let road = &roads[0];
        assert!(road.length_m.is_nan());
        assert_eq!(road.centre_line.len(), UNMADE_ROAD_POINTS);
        assert_eq!(road.centre_line.first(), points.first());
        assert_eq!(road.centre_line.last(), points.last());
        // The points a re-drive would drive are kept whole; only the page's line is bounded.
        assert_eq!(road.road_points.len(), 1_000_000);
        let json = road.to_json().to_string();
        assert!(json.len() < 600, "{} bytes: {json}", json.len());
    }

    #[test]
    fn the_page_json_rounds_to_decimetres_and_writes_absent_values_as_null() {
        let road = FailingRoad {
            group: 0,
            run: 0,
            run_file: "a.jsonl".into(),
            test: 3,
            max_bolp: 0.9,
            side: Some("right"),
            length_m: f64::NAN,
            centre_line: vec![[1.04, 2.06], [3.0, f64::NAN]],
            exit: None,
            road_points: vec![],
            trace: None,
        };
        let value = road.to_json();
        assert_eq!(value["line"], json!([[1.0, 2.1], [3.0, null]]));
        assert_eq!(value["exit"], Value::Null);
        assert!(value.get("trace").is_none());
    }
}
