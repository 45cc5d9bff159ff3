//! Agreement with the SBST pipeline's own answers (`tests/reference/sbst/oob_vectors.json`,
//! made by `scripts/reference/sbst_oob_vectors.py`). Run with `-- --nocapture` to see the counts.

use serde_json::Value;

use super::edit_distance::{angle_lengths, segment_distance, substitution_cost};
use super::sparseness::{numpy_mean_sd, percent_f};
use super::*;
use crate::road::Point;

/// The committed vectors, or the file named by `SBST_OOB_VECTORS` (to check other directories,
/// e.g. exports, without committing them).
fn vectors() -> Value {
    let committed = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/reference/sbst/oob_vectors.json"
    );
    let path = std::env::var("SBST_OOB_VECTORS").unwrap_or_else(|_| committed.to_string());
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn points(value: &Value) -> Vec<Point> {
    serde_json::from_value(value.clone()).expect("a list of [x, y] points")
}

fn number(value: &Value) -> f64 {
    // NaN is written as null.
    value.as_f64().unwrap_or(f64::NAN)
}

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a.is_nan() && b.is_nan()) || (a - b).abs() <= tolerance
}

/// Asserts agreement within `tolerance`; answers how many points agree to the bit.
fn assert_points_close(ours: &[Point], theirs: &[Point], tolerance: f64, what: &str) -> usize {
    assert_eq!(ours.len(), theirs.len(), "{what}: point counts differ");
    for (i, (a, b)) in ours.iter().zip(theirs).enumerate() {
        assert!(
            close(a[0], b[0], tolerance) && close(a[1], b[1], tolerance),
            "{what}: point {i} ours {a:?} pipeline {b:?}"
        );
    }
    ours.iter().zip(theirs).filter(|(a, b)| a == b).count()
}

/// Whether our error is the one the pipeline raised (by its Python exception type).
fn same_failure(ours: &OobError, python: &Value) -> bool {
    let kind = python["type"].as_str().unwrap_or_default();
    match ours {
        // shapely refuses a one-point line before scipy sees the points.
        OobError::TooFewRoadPoints(n) => {
            (kind == "TypeError" && python["message"] == "m > k must hold")
                || (*n == 1 && kind == "GEOSException")
        }
        OobError::RoadTooShort(_) => kind == "ZeroDivisionError",
        OobError::Spline(_) => kind == "ValueError",
        // reversed(None) in the walk before the OOB.
        OobError::NoPointNearOob(_) => {
            kind == "TypeError" && python["message"] != "m > k must hold"
        }
        OobError::OnePointSegment(_) => kind == "GEOSException",
        OobError::SegmentTooShort(_) | OobError::Pair { .. } => kind == "AssertionError",
        // Only Ctrl-C stops ours; the pipeline never stops.
        OobError::Stopped => false,
    }
}

#[test]
fn directories_agree_with_the_pipeline() {
    let vectors = vectors();
    let directories = vectors["directories"].as_array().expect("directories");
    assert!(!directories.is_empty());
    let (mut checked, mut pairs, mut resampled, mut failed_entries) = (0, 0, 0, 0);
    let (mut segment_points, mut exact_points, mut exact_distances) = (0, 0, 0);
    for dir in directories {
        let name = dir["name"].as_str().unwrap();
        if dir["error"]["stage"] == "load"
            || dir["tests"]
                .as_array()
                .unwrap()
                .iter()
                .any(|t| !t["load_error"].is_null())
        {
            // The pipeline could not read a file: outside what this module models.
            eprintln!("{name}: skipped, the pipeline failed to load a test file");
            continue;
        }
        let tests: Vec<SbstTest> =
            serde_json::from_value(dir["tests"].clone()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let ours = entries(&tests);
        let theirs = dir["entries"].as_array().unwrap();
        assert_eq!(ours.len(), theirs.len(), "{name}: entry counts differ");
        for (k, (entry, expected)) in ours.iter().zip(theirs).enumerate() {
            let what = format!("{name} entry {k} (test {})", entry.test_id);
            assert_eq!(
                entry.test_id,
                expected["test_id"].as_u64().unwrap(),
                "{what}"
            );
            let side: Option<SbstSide> = serde_json::from_value(expected["side"].clone()).unwrap();
            assert_eq!(entry.side, side, "{what}: side");
            let oob: Option<Point> = serde_json::from_value(expected["oob_point"].clone()).unwrap();
            assert_eq!(entry.oob_point, oob, "{what}: OOB point");
            let segment = points(&expected["segment"]);
            exact_points += assert_points_close(&entry.segment, &segment, 1e-9, &what);
            segment_points += segment.len();
            match &entry.failure {
                Some(failure) => {
                    failed_entries += 1;
                    assert!(
                        same_failure(failure, &expected["error"]),
                        "{what}: ours {failure:?}, pipeline {}",
                        expected["error"]
                    );
                }
                None => assert!(side.is_some(), "{what}: the pipeline failed, we did not"),
            }
            // The resampled road, for the first few entries.
            let file = expected["file"].as_str().unwrap();
            let road = &dir["tests"]
                .as_array()
                .unwrap()
                .iter()
                .find(|t| t["file"] == file)
                .unwrap()["road_points"];
            if !expected["resampled"].is_null() {
                resampled += 1;
                let line = resample(&points(road)).unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(
                    line,
                    points(&expected["resampled"]),
                    "{what}: resampled road"
                );
            } else if !expected["resampled_error"].is_null() {
                let e = resample(&points(road)).expect_err(&what);
                assert!(
                    same_failure(&e, &expected["resampled_error"]),
                    "{what}: {e:?}"
                );
            }
        }
        for pair in dir["distances"].as_array().unwrap() {
            let (i, j) = (
                pair[0].as_u64().unwrap() as usize,
                pair[1].as_u64().unwrap() as usize,
            );
            let d = segment_distance(&ours[i].segment, &ours[j].segment).unwrap();
            assert!(
                close(d, number(&pair[2]), 1e-9),
                "{name}: distance {i}-{j} ours {d} pipeline {}",
                pair[2]
            );
            pairs += 1;
            exact_distances += usize::from(d.to_bits() == number(&pair[2]).to_bits());
        }
        let summary = summarise(&ours);
        // Debug text, since NaN sparseness is not equal to itself.
        assert_eq!(
            format!("{:?}", summarise_tests(&tests)),
            format!("{summary:?}"),
            "{name}: summarise_tests and summarise differ"
        );
        if dir["error"].is_null() {
            let summary = summary.unwrap_or_else(|e| panic!("{name}: {e}"));
            let spread = sparseness(&ours).unwrap();
            let maxima = dir["max_distances"].as_array().unwrap();
            assert_eq!(spread.max_distances.len(), maxima.len(), "{name}: maxima");
            for (&(id, d), expected) in spread.max_distances.iter().zip(maxima) {
                assert_eq!(id, expected[0].as_u64().unwrap(), "{name}: maxima ids");
                assert!(close(d, number(&expected[1]), 1e-9), "{name}: max of {id}");
            }
            let analysed = &dir["analyse"];
            assert_eq!(
                summary.left as u64,
                analysed["oob_side"][0].as_u64().unwrap()
            );
            assert_eq!(
                summary.right as u64,
                analysed["oob_side"][1].as_u64().unwrap()
            );
            let (mean, sd) = (
                number(&analysed["sparseness"][0]),
                number(&analysed["sparseness"][1]),
            );
            assert!(close(summary.sparseness_mean, mean, 1e-9), "{name}: mean");
            assert!(close(summary.sparseness_sd, sd, 1e-9), "{name}: sd");
            assert_eq!(
                summary_csv(&summary),
                dir["summary_csv"].as_str().unwrap(),
                "{name}: summary"
            );
        } else {
            let error = &dir["error"];
            let ids = (error["pair"][0].as_u64(), error["pair"][1].as_u64());
            match summary {
                Err(OobError::Pair {
                    first,
                    second,
                    ref source,
                }) => {
                    assert_eq!((Some(first), Some(second)), ids, "{name}: failing pair");
                    assert_eq!(**source, OobError::SegmentTooShort(0), "{name}");
                    assert!(same_failure(&summary.clone().unwrap_err(), error));
                }
                other => panic!("{name}: the pipeline raised {error}, we answered {other:?}"),
            }
        }
        checked += 1;
    }
    eprintln!(
        "{checked} directories agree with the pipeline: {segment_points} segment points \
         ({exact_points} to the bit), {pairs} distances ({exact_distances} to the bit), \
         {resampled} resampled roads, {failed_entries} failed entries"
    );
    assert!(checked > 0);
}

#[test]
fn unit_vectors_agree_with_the_pipeline() {
    let vectors = vectors();
    let units = &vectors["units"];
    let pair = |v: &Value| (number(&v[0]), number(&v[1]));

    let mut exact_costs = 0;
    let costs = units["cost"].as_array().unwrap();
    for case in costs {
        let cost = substitution_cost(pair(&case["u"]), pair(&case["v"]));
        let expected = number(&case["cost"]);
        assert!(close(cost, expected, 1e-12), "{case}: ours {cost}");
        exact_costs += usize::from(cost.to_bits() == expected.to_bits());
    }

    for case in units["dist_angle"].as_array().unwrap() {
        let steps = angle_lengths(&points(&case["points"])).unwrap();
        let expected = case["angle_length"].as_array().unwrap();
        assert_eq!(steps.len(), expected.len());
        for (ours, theirs) in steps.iter().zip(expected) {
            let (a, l) = pair(theirs);
            assert!(close(ours.0, a, 1e-9) && close(ours.1, l, 1e-9), "{case}");
        }
    }

    let levenshtein = units["levenshtein"].as_array().unwrap();
    for case in levenshtein {
        let d = segment_distance(&points(&case["s"]), &points(&case["t"])).unwrap();
        assert!(
            close(d, number(&case["distance"]), 1e-9),
            "{case}: ours {d}"
        );
    }
    for case in units["levenshtein_errors"].as_array().unwrap() {
        let s = points(&case["s"]);
        let e = segment_distance(&s, &[[0.0, 0.0], [1.0, 0.0]]).unwrap_err();
        assert_eq!(e, OobError::SegmentTooShort(s.len()));
        assert!(same_failure(&e, &case["error"]));
    }

    for case in units["resample"].as_array().unwrap() {
        let ours = resample(&points(&case["road_points"]));
        if case["error"].is_null() {
            assert_eq!(
                ours.unwrap(),
                points(&case["resampled"]),
                "{}",
                case["road_points"]
            );
        } else {
            let e = ours.unwrap_err();
            assert!(same_failure(&e, &case["error"]), "{e:?} {}", case["error"]);
        }
    }

    for case in units["format"].as_array().unwrap() {
        let value = match &case["value"] {
            Value::Null => f64::NAN,
            Value::String(s) => s.parse().unwrap(),
            v => v.as_f64().unwrap(),
        };
        assert_eq!(percent_f(value, 0, 3), case["f3"].as_str().unwrap());
        assert_eq!(percent_f(value, 3, 0), case["width3_f0"].as_str().unwrap());
    }

    // numpy's mean and std are matched to the last bit, so printed figures round alike.
    for case in units["mean_std"].as_array().unwrap() {
        let values: Vec<f64> = case["values"]
            .as_array()
            .unwrap()
            .iter()
            .map(number)
            .collect();
        let (mean, sd) = numpy_mean_sd(&values);
        assert_eq!(
            mean.to_bits(),
            number(&case["mean"]).to_bits(),
            "{} values",
            values.len()
        );
        assert_eq!(
            sd.to_bits(),
            number(&case["std"]).to_bits(),
            "{} values",
            values.len()
        );
    }
    eprintln!(
        "{} costs ({exact_costs} to the bit), {} distances, {} formats, {} mean/SD cases agree",
        costs.len(),
        levenshtein.len(),
        units["format"].as_array().unwrap().len(),
        units["mean_std"].as_array().unwrap().len()
    );
}
