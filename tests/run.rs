//! End-to-end tests of `wogan run`.

use crate::common::{records, scratch_dir, wogan, write_file};
use road_sim::road::heading_profile::largest_turn_rad;
use road_sim::{Road, Validator};
use serde_json::Value;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

/// Runs `wogan run ARGS`: its exit status and JSON lines.
fn run(args: &[&str]) -> (Option<i32>, Vec<Value>) {
    let args: Vec<&str> = std::iter::once("run").chain(args.iter().copied()).collect();
    let output = wogan(&args, "");
    (output.status.code(), records(&output))
}

fn of_type<'a>(records: &'a [Value], kind: &str) -> Vec<&'a Value> {
    records.iter().filter(|r| r["type"] == kind).collect()
}

/// WOGAN's acceptance decay as a run's header reports it.
fn target_decay(header: &Value) -> f64 {
    header["config"]["search"]["wogan"]["target_decay"]
        .as_f64()
        .expect("a header with the acceptance decay")
}

/// The parts of a test record that must not depend on timing.
fn deterministic_part(test: &Value) -> Value {
    let mut test = test.clone();
    for timing in ["generation_ms", "sbst_generation_ms", "execution_ms"] {
        test.as_object_mut().unwrap().remove(timing);
    }
    test
}

/// Asserts that `wogan run --config PATH` exits 2 before any output, its message naming `named`.
fn assert_config_refused(path: &str, named: &str) {
    let output = wogan(&["run", "--config", path], "");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{path}: {stderr}");
    assert!(stderr.contains(named), "{path}: {stderr}");
    assert!(output.stdout.is_empty());
}

fn check_run(algorithm: &str) {
    let args = [
        "--algorithm",
        algorithm,
        "--max-tests",
        "30",
        "--seed",
        "11",
    ];
    let (code, records) = run(&args);
    assert_eq!(code, Some(0));
    assert_eq!(records[0]["type"], "header");
    assert_eq!(records[0]["algorithm"], algorithm);
    assert_eq!(records[0]["seed"], 11);
    let tests = of_type(&records, "test");
    assert_eq!(tests.len(), 30);
    let validator = Validator::default();
    for (i, test) in tests.iter().enumerate() {
        assert_eq!(test["id"], i + 1);
        let points: Vec<[f64; 2]> = serde_json::from_value(test["road_points"].clone()).unwrap();
        assert!(
            validator.validate(&points).is_valid(),
            "test {} is invalid",
            i + 1
        );
        let fitness = test["fitness"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&fitness));
        assert!(["PASS", "FAIL", "ERROR"].contains(&test["outcome"].as_str().unwrap()));
    }
    let summary = records.last().unwrap();
    assert_eq!(summary["type"], "summary");
    assert_eq!(summary["executed"], 30);
    let failed = tests.iter().filter(|t| t["outcome"] == "FAIL").count();
    assert_eq!(summary["failed"], failed);

    let (_, again) = run(&args);
    let again = of_type(&again, "test");
    for (a, b) in tests.iter().zip(&again) {
        assert_eq!(
            deterministic_part(a),
            deterministic_part(b),
            "same seed, same tests"
        );
    }
}

#[test]
fn wogan_run_of_30_tests() {
    check_run("wogan");
}

#[test]
fn random_run_of_30_tests() {
    check_run("random");
}

#[test]
fn wogan_in_rounds_of_two_is_reproducible_and_recorded() {
    let args = ["--max-tests", "30", "--seed", "11", "--jobs", "2"];
    let (code, first) = run(&args);
    assert_eq!(code, Some(0));
    assert_eq!(first[0]["config"]["search"]["jobs"], 2);
    assert_eq!(
        first[0]["config"]["search"]["wogan"]["round_acceptance"],
        "restart"
    );
    let (_, again) = run(&args);
    let deterministic = |records: &[Value]| -> Vec<Value> {
        of_type(records, "test")
            .into_iter()
            .map(deterministic_part)
            .collect()
    };
    assert_eq!(deterministic(&first), deterministic(&again));
    let tests = of_type(&first, "test");
    assert_eq!(tests.len(), 30);
    assert!(tests[6..].iter().all(|t| t["phase"] == "wogan"));
    // Rounds choose other tests than one at a time does (the random phase is the same).
    let (_, one_job) = run(&["--max-tests", "30", "--seed", "11"]);
    let one_job = deterministic(&one_job);
    assert_eq!(deterministic(&first)[..6], one_job[..6]);
    assert_ne!(deterministic(&first)[6..], one_job[6..]);
}

#[test]
fn wogan_phases_and_training_records() {
    let (_, records) = run(&["--max-tests", "30", "--seed", "2"]);
    let tests = of_type(&records, "test");
    // 20% of 30 tests are random, the rest are WOGAN's.
    assert!(tests[..6].iter().all(|t| t["phase"] == "random"));
    assert!(tests[6..].iter().all(|t| t["phase"] == "wogan"));
    assert!(!of_type(&records, "train").is_empty());
}

#[test]
fn mutants_join_the_candidates_when_asked_for() {
    let (code, records) = run(&[
        "--max-tests",
        "40",
        "--seed",
        "3",
        "--mutation-share",
        "0.5",
    ]);
    assert_eq!(code, Some(0));
    assert_eq!(
        records[0]["config"]["search"]["wogan"]["mutation"]["share"],
        0.5
    );
    let tests = of_type(&records, "test");
    assert_eq!(tests.len(), 40);
    let mutants = tests.iter().filter(|t| t["phase"] == "mutant").count();
    assert!(mutants > 0, "no mutant was chosen");
    assert!(tests[8..].iter().all(|t| t["phase"] != "random"));
}

#[test]
fn the_sbst_presets_set_their_roads_novelty_mutants_and_niches_per_setup_and_options_still_win() {
    let (code, records) = run(&[
        "--max-tests",
        "12",
        "--seed",
        "3",
        "--preset",
        "sbst-no-niches",
    ]);
    assert_eq!(code, Some(0));
    let config = &records[0]["config"];
    assert_eq!(config["preset"], "sbst-no-niches");
    assert_eq!(config["curvature_points"], 16);
    assert_eq!(config["road"]["step_m"], 10.0);
    assert_eq!(config["road"]["placement"], "fitted");
    assert_eq!(config["search"]["wogan"]["novelty"]["distance"], 0.1);
    assert_eq!(config["search"]["wogan"]["mutation"]["share"], 0.25);
    let tests = of_type(&records, "test");
    assert_eq!(tests.len(), 12);
    // Seventeen road points: sixteen curvature values.
    assert!(tests
        .iter()
        .all(|t| t["road_points"].as_array().unwrap().len() == 17));
    // The header's configuration of a short run that succeeds.
    let config_of = |args: &[&str]| {
        let (code, records) = run(&[&["--max-tests", "3"], args].concat());
        assert_eq!(code, Some(0));
        records[0]["config"].clone()
    };
    let config = config_of(&[
        "--preset",
        "sbst-no-niches",
        "--curvature-points",
        "6",
        "--mutation-share",
        "0",
    ]);
    assert_eq!(config["curvature_points"], 6);
    assert_eq!(config["search"]["wogan"]["mutation"]["share"], 0.0);
    // The competition's DAVE-2 setup: the paper's roads, a closer novelty, the same mutants.
    let config = config_of(&["--oracle", "dave2-proxy", "--preset", "sbst-no-niches"]);
    assert_eq!(config["curvature_points"], 5);
    assert_eq!(config["road"]["step_m"], 15.0);
    assert_eq!(config["road"]["placement"], "bottom-centre");
    assert_eq!(config["search"]["wogan"]["novelty"]["distance"], 0.05);
    assert_eq!(config["search"]["wogan"]["mutation"]["share"], 0.25);
    // `sbst`, with niches: in the BeamNG.AI setup on roads of 22 values 12 m apart compared by
    // the paper's directions, in the DAVE-2 setup on the BeamNG.AI `sbst-no-niches` roads, filled
    // by each driver's failures.
    // The DAVE-2 setup tests only roads that turn at least 2.5 rad.
    for (oracle, level, points, step_m, shape, min_turn_rad) in [
        ("beamng-ai-proxy", 0.85, 22, 12.0, "directions", 0.0),
        ("dave2-proxy", 0.1, 16, 10.0, "headings", 2.5),
    ] {
        let config = config_of(&["--oracle", oracle, "--preset", "sbst"]);
        assert_eq!(config["preset"], "sbst");
        assert_eq!(config["curvature_points"], points, "{oracle}");
        assert_eq!(config["road"]["step_m"], step_m, "{oracle}");
        assert_eq!(config["road"]["placement"], "fitted");
        assert_eq!(config["road_shape"], shape, "{oracle}");
        assert_eq!(config["min_road_turn_rad"], min_turn_rad, "{oracle}");
        let niches = &config["search"]["wogan"]["niches"];
        assert!(niches["quota"].as_u64().unwrap() > 0, "{oracle}");
        assert_eq!(niches["min_fitness"], level, "{oracle}");
    }
    let config = config_of(&["--preset", "sbst", "--road-shape", "headings"]);
    assert_eq!(config["road_shape"], "headings");
    let config = config_of(&[
        "--oracle",
        "dave2-proxy",
        "--preset",
        "sbst",
        "--min-road-turn",
        "0",
    ]);
    assert_eq!(config["min_road_turn_rad"], 0.0);
    // The paper's WOGAN has neither.
    let (_, records) = run(&["--max-tests", "3"]);
    let config = &records[0]["config"];
    assert!(config.get("preset").is_none());
    assert_eq!(config["road_shape"], "headings");
    assert_eq!(config["min_road_turn_rad"], 0.0);
    assert_eq!(config["search"]["wogan"]["novelty"]["distance"], 0.0);
    assert_eq!(config["search"]["wogan"]["niches"]["quota"], 0);
}

#[test]
fn a_slower_target_decay_ranks_more_candidates() {
    let ranked_per_test = |decay: &str| {
        let (code, records) = run(&["--max-tests", "20", "--seed", "4", "--target-decay", decay]);
        assert_eq!(code, Some(0));
        assert_eq!(target_decay(&records[0]), decay.parse::<f64>().unwrap());
        let ranked: Vec<u64> = of_type(&records, "test")
            .iter()
            .map(|t| t["ranked_candidates"].as_u64().unwrap())
            .collect();
        assert!(
            ranked[..4].iter().all(|&r| r == 0),
            "the random phase ranks nothing"
        );
        assert!(
            ranked[4..].iter().all(|&r| r > 0),
            "WOGAN ranks its choices"
        );
        ranked.iter().sum::<u64>() as f64 / 16.0
    };
    // The target falls below any prediction within a few candidates at 0.5, but only after
    // dozens at 0.99.
    let (fast, slow) = (ranked_per_test("0.5"), ranked_per_test("0.99"));
    assert!(slow > 5.0 * fast, "0.99 ranks {slow} per test, 0.5 {fast}");
}

#[test]
fn sigint_writes_a_summary_and_exits_130() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_wogan"))
        .args([
            "run",
            "--algorithm",
            "random",
            "--max-tests",
            "1000000",
            "--seed",
            "1",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("wogan starts");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    // Wait until tests are being executed, then interrupt.
    for _ in 0..3 {
        lines.next().expect("a line").expect("text");
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let rest: Vec<Value> = lines
        .map(|l| serde_json::from_str(&l.unwrap()).unwrap())
        .collect();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let summary = rest.last().expect("a summary line");
    assert_eq!(summary["type"], "summary");
    assert_eq!(summary["interrupted"], true);
    assert!(summary["executed"].as_u64().unwrap() >= 2);
}

#[test]
fn bad_options_exit_2() {
    for args in [
        &["--algorithm", "annealing"][..],
        &["--budget", "soon"],
        &["--oracle", "nobody"],
        &["--oob-tolerance", "1.5"],
        &["--max-tests", "0"],
        &["--mutation-share", "1.5"],
        &["--algorithm", "random", "--mutation-share", "0.5"],
        &["--target-decay", "1"],
        &["--algorithm", "random", "--target-decay", "0.99"],
        &["--round-acceptance", "sometimes"],
        &["--algorithm", "random", "--round-acceptance", "restart"],
        &["--preset", "fast"],
        &["--algorithm", "random", "--preset", "sbst"],
        &["--road-shape", "wrapped"],
        &["--min-road-turn", "7"],
        &["--min-road-turn", "-1"],
        // The competition's budgets go together, in seconds or as durations, and not with the
        // one real-time budget.
        &["--generation-budget", "3600"],
        &["--execution-budget", "7200"],
        &["--generation-budget", "1h", "--execution-budget", "0"],
        &["--generation-budget", "-5", "--execution-budget", "10"],
        &[
            "--generation-budget",
            "1h",
            "--execution-budget",
            "2h",
            "--budget",
            "1h",
        ],
        &[
            "--generation-budget",
            "1h",
            "--execution-budget",
            "9999999999",
        ],
    ] {
        let (code, records) = run(args);
        assert_eq!(code, Some(2), "{args:?}");
        assert!(records.is_empty());
    }
}

#[test]
fn a_config_file_overrides_the_defaults_and_typos_are_named() {
    let dir = scratch_dir("config");
    let good = dir.join("good.json");
    std::fs::write(
        &good,
        r#"{"search": {"wogan": {"analyzer": {"max_batch": 64}}}, "sim": {"speed_limit_kmh": 50}}"#,
    )
    .unwrap();
    let (code, records) = run(&["--max-tests", "12", "--config", good.to_str().unwrap()]);
    assert_eq!(code, Some(0));
    let config = &records[0]["config"];
    assert_eq!(config["search"]["wogan"]["analyzer"]["max_batch"], 64);
    assert_eq!(config["sim"]["speed_limit_kmh"], 50.0);
    // The file's other settings keep the paper's defaults.
    assert_eq!(config["search"]["wogan"]["bins"], 10);
    assert_eq!(config["sim"]["oob_tolerance"], 0.85);

    // A typo, and values that parse but no simulation can run with, are named before any output.
    for (name, json, named) in [
        (
            "typo.json",
            r#"{"search": {"wogan": {"analyser": {}}}}"#,
            "analyser",
        ),
        ("rate.json", r#"{"sim": {"physics_hz": 0}}"#, "physics_hz"),
        (
            "car.json",
            r#"{"sim": {"vehicle": {"mass_kg": -1}}}"#,
            "vehicle.mass_kg",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, json).unwrap();
        assert_config_refused(path.to_str().unwrap(), named);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn driver_settings_are_read_from_driver_and_older_files_still_read() {
    let dir = scratch_dir("driver-config");
    let write = |name: &str, text: &str| write_file(&dir, name, text);
    let header_of = |oracle: &str, file: &str| {
        let output = wogan(
            &[
                "run",
                "--oracle",
                oracle,
                "--max-tests",
                "2",
                "--quiet",
                "--config",
                file,
            ],
            "",
        );
        assert_eq!(output.status.code(), Some(0), "{file}");
        let header: Value = serde_json::from_str(
            String::from_utf8_lossy(&output.stdout)
                .lines()
                .next()
                .unwrap(),
        )
        .unwrap();
        (header, String::from_utf8_lossy(&output.stderr).into_owned())
    };

    // The driver under test's settings, and nothing of the other driver's, under config.driver.
    let (header, _) = header_of(
        "beamng-ai-proxy",
        &write("new.json", r#"{"driver": {"aggression": 0.5}}"#),
    );
    assert_eq!(header["config"]["driver"]["aggression"], 0.5);
    assert_eq!(header["config"]["driver"]["control_hz"], 30.0);
    assert!(header["config"]["sim"].get("beamng_ai").is_none());
    assert!(header["config"]["sim"].get("dave2").is_none());
    let (header, _) = header_of(
        "dave2-proxy",
        &write("dave2.json", r#"{"driver": {"speed_kmh": 20}}"#),
    );
    assert_eq!(header["config"]["driver"]["speed_kmh"], 20.0);

    // A file written for the old layout is read, and stderr says where its sections went.
    let old = write(
        "old.json",
        r#"{"sim": {"speed_limit_kmh": 60, "beamng_ai": {"aggression": 0.5}, "dave2": {"speed_kmh": 20}}}"#,
    );
    let (header, stderr) = header_of("beamng-ai-proxy", &old);
    assert_eq!(header["config"]["driver"]["aggression"], 0.5);
    assert_eq!(header["config"]["sim"]["speed_limit_kmh"], 60.0);
    assert!(
        stderr.contains(r#""sim.beamng_ai" is now "driver""#),
        "{stderr}"
    );
    assert!(
        stderr.contains(r#""sim.dave2" is for dave2-proxy"#),
        "{stderr}"
    );

    // Both layouts at once, a typo and an unusable value are named.
    for (name, json, named) in [
        (
            "both.json",
            r#"{"sim": {"beamng_ai": {}}, "driver": {}}"#,
            r#""sim.beamng_ai" is now "driver""#,
        ),
        ("typo.json", r#"{"driver": {"agression": 1}}"#, "agression"),
        (
            "rate.json",
            r#"{"driver": {"control_hz": 0}}"#,
            "driver.control_hz must be positive",
        ),
    ] {
        assert_config_refused(&write(name, json), named);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn niches_fill_with_the_runs_own_failures_unless_told_and_bad_settings_are_named() {
    let dir = scratch_dir("niches");
    let write = |name: &str, json: &str| {
        let path = dir.join(name);
        std::fs::write(&path, json).unwrap();
        path.to_str().unwrap().to_string()
    };
    let niches = write(
        "niches.json",
        r#"{"search": {"wogan": {"niches": {"quota": 5, "distance": 2.5, "radius": 1.0}}}}"#,
    );
    // The failure threshold of each driver's fitness, unless the file names one.
    for (oracle, level) in [("beamng-ai-proxy", 0.85), ("dave2-proxy", 0.1)] {
        let (code, records) = run(&["--oracle", oracle, "--max-tests", "3", "--config", &niches]);
        assert_eq!(code, Some(0), "{oracle}");
        let set = &records[0]["config"]["search"]["wogan"]["niches"];
        assert_eq!(set["min_fitness"], level, "{oracle}");
        assert_eq!(set["quota"], 5);
    }
    for (name, json, named) in [
        (
            "flat.json",
            r#"{"search": {"wogan": {"niches": {"quota": 5, "distance": 2.5}}}}"#,
            "wogan.niches.radius",
        ),
        (
            "far.json",
            r#"{"search": {"wogan": {"niches": {"quota": 5, "radius": 1000}}}}"#,
            "wogan.niches.radius must be from 0 to 100",
        ),
        (
            "typo.json",
            r#"{"search": {"wogan": {"niches": {"qouta": 5}}}}"#,
            "qouta",
        ),
        (
            "stale.json",
            r#"{"search": {"wogan": {"niches": {"quota": 5, "radius": 1.0, "stale": 3}}}}"#,
            "wogan.niches.repeat_distance",
        ),
    ] {
        assert_config_refused(&write(name, json), named);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn niches_closed_on_repeats_compare_the_roads_exit_profiles() {
    let dir = scratch_dir("stale-niches");
    let stale = dir.join("stale.json");
    // Over the preset's niches (which give the repeat distance): the first repeat closes one.
    std::fs::write(&stale, r#"{"search": {"wogan": {"niches": {"stale": 1}}}}"#).unwrap();
    let tests_of = |extra: &[&str]| {
        let mut args = vec!["--preset", "sbst", "--max-tests", "150", "--seed", "1"];
        args.extend_from_slice(extra);
        let (code, records) = run(&args);
        assert_eq!(code, Some(0));
        let tests: Vec<Value> = of_type(&records, "test")
            .into_iter()
            .map(|t| t["curvature"].clone())
            .collect();
        (
            records[0]["config"]["search"]["wogan"]["niches"].clone(),
            tests,
        )
    };
    let (preset, preset_tests) = tests_of(&[]);
    let (closing, closing_tests) = tests_of(&["--config", stale.to_str().unwrap()]);
    assert_eq!(preset["stale"], 0);
    assert_eq!(closing["stale"], 1);
    assert_eq!(closing["repeat_distance"], preset["repeat_distance"]);
    // The random phase is the same; the search parts once a failure repeats an earlier one by
    // its exit profile (without profiles from the roads nothing would ever repeat).
    assert_eq!(closing_tests[..20], preset_tests[..20]);
    assert_ne!(closing_tests, preset_tests);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn niches_compare_roads_by_the_shape_asked_for() {
    let tests_of = |shape: &str| {
        let args = ["--preset", "sbst", "--max-tests", "150", "--seed", "1"];
        let (code, records) = run(&[&args[..], &["--road-shape", shape]].concat());
        assert_eq!(code, Some(0));
        assert_eq!(records[0]["config"]["road_shape"], shape);
        of_type(&records, "test")
            .into_iter()
            .map(|t| t["curvature"].clone())
            .collect::<Vec<Value>>()
    };
    let (directions, headings) = (tests_of("directions"), tests_of("headings"));
    // The random phase is the same; which candidates a niche admits is not.
    assert_eq!(directions[..20], headings[..20]);
    assert_ne!(directions, headings);
}

#[test]
fn a_least_turn_tests_only_roads_that_turn_that_far() {
    // How far each executed road turns from its first heading at most, radians.
    let turns_of = |extra: &[&str]| {
        let args = ["--max-tests", "25", "--seed", "3"];
        let (code, records) = run(&[&args[..], extra].concat());
        assert_eq!(code, Some(0), "{extra:?}");
        let turns = of_type(&records, "test")
            .into_iter()
            .map(|test| {
                let points: Vec<[f64; 2]> = test["road_points"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
                    .collect();
                largest_turn_rad(&Road::new(&points).unwrap().interpolated)
            })
            .collect::<Vec<f64>>();
        (records[0]["config"]["min_road_turn_rad"].clone(), turns)
    };
    let (any, any_turns) = turns_of(&[]);
    let (least, winding_turns) = turns_of(&["--min-road-turn", "2"]);
    assert_eq!((any, least), (Value::from(0.0), Value::from(2.0)));
    assert_eq!(winding_turns.len(), 25);
    assert!(winding_turns.iter().all(|&t| t >= 2.0), "{winding_turns:?}");
    assert!(any_turns.iter().any(|&t| t < 2.0), "{any_turns:?}");
}

#[test]
fn a_wall_clock_budget_ends_the_run_with_a_summary() {
    let (code, records) = run(&["--budget", "1s", "--algorithm", "random"]);
    assert_eq!(code, Some(0));
    let summary = records.last().unwrap();
    assert_eq!(summary["type"], "summary");
    assert!(summary["executed"].as_u64().unwrap() > 0);
    assert_eq!(records[0]["config"]["budget_s"], 1.0);
}

#[test]
fn an_execution_budget_ends_the_run_as_the_pipeline_does() {
    // A generous generation budget: the 600 simulated seconds bind.
    let (code, records) = run(&[
        "--generation-budget",
        "1h",
        "--execution-budget",
        "600",
        "--seed",
        "3",
    ]);
    assert_eq!(code, Some(0));
    let config = &records[0]["config"];
    assert_eq!(config["execution_budget_s"], 600.0);
    assert_eq!(config["generation_budget_s"], 3600.0);
    assert!(
        config["max_tests"].is_null(),
        "the budgets lift the 300 tests"
    );
    let tests = of_type(&records, "test");
    let sim_s = |t: &&Value| t["sim_time_s"].as_f64().unwrap();
    let (last, kept) = tests.split_last().expect("tests");
    // The test that spent the budget is reported, marked, and not kept; the kept tests' simulated
    // time stays under the budget, and with the last one reaches it.
    assert_eq!(last["beyond_budget"], true);
    assert!(kept.iter().all(|t| t.get("beyond_budget").is_none()));
    let kept_s: f64 = kept.iter().map(sim_s).sum();
    assert!(kept_s < 600.0 && kept_s + sim_s(last) >= 600.0, "{kept_s}");
    assert!(kept.len() > 50, "WOGAN's roads take seconds each");
    assert!(
        tests
            .iter()
            .all(|t| t["sbst_generation_ms"].as_f64().unwrap()
                >= t["generation_ms"].as_f64().unwrap())
    );
    let summary = records.last().unwrap();
    assert_eq!(summary["executed"], kept.len());
    assert_eq!(summary["beyond_budget"], 1);
    let charged = summary["execution_time_s"].as_f64().unwrap();
    assert!((charged - kept_s - sim_s(last)).abs() < 1e-6);
}

#[test]
fn a_dave2_proxy_run_searches_bolp_at_the_papers_decay() {
    let (code, records) = run(&[
        "--oracle",
        "dave2-proxy",
        "--max-tests",
        "10",
        "--seed",
        "4",
    ]);
    assert_eq!(code, Some(0));
    let header = &records[0];
    assert_eq!(header["oracle"], "dave2-proxy");
    assert_eq!(header["fitness"], "bolp");
    assert_eq!(header["config"]["sim"]["oob_tolerance"], 0.1);
    assert_eq!(header["config"]["sim"]["speed_limit_kmh"], 25.0);
    assert_eq!(target_decay(header), 0.95);
    let tests = of_type(&records, "test");
    assert_eq!(tests.len(), 10);
    for test in &tests {
        assert_eq!(test["fitness"], test["max_bolp"]);
    }
    assert_eq!(records.last().unwrap()["type"], "summary");
}

#[test]
fn the_distance_gets_a_decay_matched_to_bolps_unless_one_is_given() {
    let dir = scratch_dir("decay");
    let file = dir.join("decay.json");
    std::fs::write(&file, r#"{"search": {"wogan": {"target_decay": 0.97}}}"#).unwrap();
    let file = file.to_str().unwrap();
    for (args, expected) in [
        (vec!["--fitness", "bolp"], 0.95),
        (vec!["--fitness", "bolp-scaled"], 0.95),
        // beamng-ai-proxy's tolerance 0.85: BOLP fails at 0.85, the distance at 0.935.
        (vec!["--fitness", "distance"], 0.97904),
        (
            vec!["--fitness", "distance", "--oob-tolerance", "0.1"],
            0.98163,
        ),
        // Near the distance's top the match is capped.
        (
            vec!["--fitness", "distance", "--oob-tolerance", "0.94"],
            0.99,
        ),
        (vec!["--fitness", "distance", "--config", file], 0.97),
        (
            vec![
                "--fitness",
                "distance",
                "--config",
                file,
                "--target-decay",
                "0.96",
            ],
            0.96,
        ),
    ] {
        let mut all = vec!["--max-tests", "1"];
        all.extend(&args);
        let (code, records) = run(&all);
        assert_eq!(code, Some(0), "{args:?}");
        let decay = target_decay(&records[0]);
        assert!((decay - expected).abs() < 1e-5, "{args:?}: {decay}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bolp_fitness_is_the_papers_and_bolp_scaled_divides_by_the_tolerance() {
    for (fitness, tolerance) in [("bolp", 1.0), ("bolp-scaled", 0.3)] {
        let tolerance_arg = tolerance.to_string();
        let (code, records) = run(&[
            "--algorithm",
            "random",
            "--max-tests",
            "20",
            "--seed",
            "5",
            "--fitness",
            fitness,
            "--oob-tolerance",
            &tolerance_arg,
        ]);
        assert_eq!(code, Some(0));
        assert_eq!(records[0]["fitness"], fitness);
        let tests = of_type(&records, "test");
        assert!(tests.iter().any(|t| t["max_bolp"].as_f64().unwrap() > 0.01));
        for test in tests {
            let expected = (test["max_bolp"].as_f64().unwrap() / tolerance).min(1.0);
            let got = test["fitness"].as_f64().unwrap();
            assert!(
                (got - expected).abs() <= 1e-12 * expected,
                "{fitness}: {test}"
            );
        }
    }
}

#[test]
fn driver_weights_must_be_dave2_weights() {
    let dir = scratch_dir("weights");
    let junk = dir.join("junk.bin");
    std::fs::write(&junk, b"not weights").unwrap();
    let (code, records) = run(&[
        "--oracle",
        "dave2-proxy",
        "--driver-weights",
        junk.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(2));
    assert!(records.is_empty());
    let (code, _) = run(&["--driver-weights", junk.to_str().unwrap()]);
    assert_eq!(code, Some(2), "beamng-ai-proxy takes no weights");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_runs_test_records_replay_exactly_and_report_the_same_diversity() {
    let dir = scratch_dir("replay");
    let run_file = dir.join("run.jsonl");
    let run_path = run_file.to_str().unwrap();
    // At a tolerance of 0.3 the run fails enough tests to have a diversity.
    let (code, _) = run(&[
        "--quiet",
        "--max-tests",
        "300",
        "--seed",
        "3",
        "--oob-tolerance",
        "0.3",
        "--out",
        run_path,
    ]);
    assert_eq!(code, Some(0));
    let text = std::fs::read_to_string(&run_file).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let tests: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.contains(r#""type":"test""#))
        .collect();
    assert_eq!(tests.len(), 300);
    let replayed = records(&crate::common::wogan_ok(
        &["simulate", "--oob-tolerance", "0.3"],
        &tests.join("\n"),
    ));
    assert_eq!(replayed.len(), tests.len());
    let mut failures = 0;
    for (line, answer) in tests.iter().zip(&replayed) {
        let test: Value = serde_json::from_str(line).unwrap();
        assert_eq!(answer["outcome"], test["outcome"], "test {}", test["id"]);
        // Numbers compare exactly: JSON numbers read back to the f64 that was written.
        assert_eq!(answer["max_bolp"], test["max_bolp"], "test {}", test["id"]);
        failures += usize::from(test["outcome"] == "FAIL");
    }
    assert!(
        failures >= 2,
        "the run should fail some tests to measure diversity"
    );

    let summary: Value = serde_json::from_str(lines.last().unwrap()).unwrap();
    let diversity = summary["diversity"].as_f64().expect("a diversity");
    let out = dir.join("report");
    crate::common::wogan_ok(&["report", run_path, "--out", out.to_str().unwrap()], "");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let row = report
        .lines()
        .find(|l| l.starts_with("| diversity"))
        .expect("a diversity row");
    let reported = row.split('|').nth(2).unwrap().trim();
    assert_eq!(reported, format!("{diversity:.3}"), "{row}");
}
