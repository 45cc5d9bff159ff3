//! Agreement with vectors produced by the SBST competition's own pipeline and by the WOGAN
//! authors' diversity measure (tests/reference/).
//!
//! Run with `cargo test --release --test end_to_end reference_vectors -- --nocapture` to see the figures.
//! `WOGAN_REFERENCE_DIR` replaces the directory (same file names).

use road_sim::road::diversity_profile::diversity_profile;
use road_sim::road::features;
use road_sim::sim::bolp;
use road_sim::{CurvatureRoad, Reason, Road, Validator};
use serde_json::Value;
use std::path::PathBuf;
use wogan_core::diversity::{euclidean, median_pairwise_distance};

fn reference_dir() -> PathBuf {
    std::env::var_os("WOGAN_REFERENCE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/reference"))
}

/// Every line of a reference file, parsed; panics if the file is missing or empty.
fn records(name: &str) -> Vec<Value> {
    let path = reference_dir().join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let records: Vec<Value> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| serde_json::from_str(l).unwrap_or_else(|e| panic!("{name}:{}: {e}", i + 1)))
        .collect();
    assert!(!records.is_empty(), "{} holds no vectors", path.display());
    records
}

fn points(value: &Value) -> Vec<[f64; 2]> {
    value
        .as_array()
        .expect("an array of points")
        .iter()
        .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
        .collect()
}

fn reason_of_message(message: &str) -> Option<Reason> {
    Some(match message {
        "Not enough road points." => Reason::NotEnoughPoints,
        "The road definition contains too many points" => Reason::TooManyPoints,
        "Not entirely inside the map boundaries" => Reason::OutsideMap,
        "The road is self-intersecting" => Reason::SelfIntersecting,
        "The road is not long enough." => Reason::TooShort,
        "The road is too sharp" => Reason::TooSharp,
        _ => return None,
    })
}

#[test]
fn validator_agrees_with_the_competition() {
    let validator = Validator::default();
    let (mut same_verdict, mut both_invalid, mut same_reason, mut total) = (0, 0, 0, 0);
    for record in records("validator.jsonl") {
        total += 1;
        let road_points = points(&record["road_points"]);
        let expected_valid = record["valid"].as_bool().unwrap();
        let message = record["message"].as_str().unwrap();
        let verdict = validator.validate(&road_points);
        if verdict.is_valid() == expected_valid {
            same_verdict += 1;
        } else {
            eprintln!(
                "verdict differs: {} ours {:?} reference {message:?}",
                record["kind"], verdict.reason
            );
        }
        if let (false, Some(ours)) = (expected_valid, verdict.reason) {
            both_invalid += 1;
            let matches = message.starts_with("reference raised:")
                || reason_of_message(message) == Some(ours);
            if matches {
                same_reason += 1;
            } else {
                eprintln!(
                    "reason differs: {} ours {ours} reference {message:?}",
                    record["kind"]
                );
            }
        }
    }
    println!("validator: {same_verdict}/{total} verdicts, {same_reason}/{both_invalid} reasons");
    assert!(same_verdict as f64 >= 0.998 * total as f64);
    assert!(same_reason as f64 >= 0.99 * both_invalid as f64);
}

#[test]
fn interpolation_agrees_with_the_competition() {
    let (mut roads, mut worst) = (0, 0.0f64);
    for record in records("spline.jsonl") {
        let road = Road::new(&points(&record["road_points"])).expect("reference roads interpolate");
        let expected = points(&record["interpolated_points"]);
        assert_eq!(
            road.interpolated.len(),
            expected.len(),
            "{:?}",
            record["road_points"]
        );
        let mut road_worst = 0.0f64;
        for (ours, theirs) in road.interpolated.iter().zip(&expected) {
            road_worst = road_worst
                .max((ours[0] - theirs[0]).abs())
                .max((ours[1] - theirs[1]).abs());
        }
        if road_worst > 0.002 {
            eprintln!(
                "spline differs by {road_worst:.4} m: {}",
                record["road_points"]
            );
        }
        worst = worst.max(road_worst);
        roads += 1;
    }
    println!("spline: {roads} roads, largest coordinate difference {worst:.6} m");
    assert!(worst <= 0.002);
}

#[test]
fn features_agree_with_the_competition() {
    let (mut count, mut worst_curv, mut worst_cov) = (0, 0.0f64, 0.0f64);
    for record in records("features.jsonl") {
        let road = Road::new(&points(&record["road_points"])).unwrap();
        let ours = features::RoadFeatures::of(&road.interpolated);
        worst_curv =
            worst_curv.max((ours.max_curvature - record["MAX_CURV"].as_f64().unwrap()).abs());
        worst_cov =
            worst_cov.max((ours.direction_coverage - record["DIR_COV"].as_f64().unwrap()).abs());
        count += 1;
    }
    println!(
        "features: {count} roads, MAX_CURV within {worst_curv:.2e}, DIR_COV within {worst_cov:.2e}"
    );
    assert!(worst_curv <= 1e-6 && worst_cov <= 1e-6);
}

#[test]
fn bolp_and_lane_distance_agree_with_the_competition() {
    let (mut count, mut worst_bolp, mut worst_distance) = (0, 0.0f64, 0.0f64);
    for record in records("bolp.jsonl") {
        let road = Road::new(&points(&record["road_points"])).unwrap();
        let corners = points(&record["car_corners"]);
        let corners = [corners[0], corners[1], corners[2], corners[3]];
        let ours = bolp::road_bolp(&road, &corners);
        worst_bolp = worst_bolp.max((ours - record["bolp"].as_f64().unwrap()).abs());
        let center = points(&Value::Array(vec![record["car_center"].clone()]))[0];
        let distance = bolp::oob_distance_right(center, &road.right_lane_centre());
        worst_distance =
            worst_distance.max((distance - record["oob_distance_right"].as_f64().unwrap()).abs());
        count += 1;
    }
    println!("bolp: {count} cars, BOLP within {worst_bolp:.2e}, lane distance within {worst_distance:.2e} m");
    assert!(worst_bolp <= 1e-4 && worst_distance <= 1e-4);
}

#[test]
fn curvature_roads_agree_with_the_reference() {
    let (mut count, mut worst) = (0, 0.0f64);
    for record in records("roads.jsonl") {
        let curvature: Vec<f64> = record["curvature"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let ours = CurvatureRoad::default().points(&curvature);
        let expected = points(&record["road_points"]);
        assert_eq!(ours.len(), expected.len());
        for (a, b) in ours.iter().zip(&expected) {
            worst = worst.max((a[0] - b[0]).abs()).max((a[1] - b[1]).abs());
        }
        assert!(
            Validator::default().validate(&expected).is_valid(),
            "reference road judged invalid"
        );
        count += 1;
    }
    println!("roads: {count} curvature roads, points within {worst:.2e} m, all valid");
    assert!(worst <= 1e-5);
}

#[test]
fn diversity_agrees_with_the_wogan_authors_measure() {
    // One JSON document (tests/reference/README.md): roads, distances of pairs, medians of groups.
    let path = reference_dir().join("wogan/diversity.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let reference: Value = serde_json::from_str(&text).expect("diversity.json is JSON");
    let profiles: Vec<Vec<f64>> = reference["roads"]
        .as_array()
        .unwrap()
        .iter()
        .map(|road| diversity_profile(&points(&road["interpolated_points"])))
        .collect();
    let mut worst = 0.0f64;
    let pairs = reference["pairs"].as_array().unwrap();
    for pair in pairs {
        let (i, j) = (
            pair[0].as_u64().unwrap() as usize,
            pair[1].as_u64().unwrap() as usize,
        );
        let ours = euclidean(&profiles[i], &profiles[j]);
        worst = worst.max((ours - pair[2].as_f64().unwrap()).abs());
    }
    let groups = reference["groups"].as_array().unwrap();
    for group in groups {
        let members: Vec<Vec<f64>> = group["roads"]
            .as_array()
            .unwrap()
            .iter()
            .map(|i| profiles[i.as_u64().unwrap() as usize].clone())
            .collect();
        let ours = median_pairwise_distance(&members, 0)
            .median_distance
            .unwrap();
        worst = worst.max((ours - group["median"].as_f64().unwrap()).abs());
    }
    println!(
        "diversity: {} roads, {} pairs and {} groups within {worst:.2e}",
        profiles.len(),
        pairs.len(),
        groups.len()
    );
    assert!(pairs.len() > 100 && !groups.is_empty());
    assert!(worst <= 1e-9);
}
