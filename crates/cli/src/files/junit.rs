//! JUnit XML reports of driven roads (written by quick-junit), the verdict format CI servers read:
//! one `<testcase>` per road, a `<failure>` when the car left its lane (with BOLP, the reason,
//! where it left and the road's points), an `<error>` when the drive itself broke down, `<skipped>`
//! for an invalid road. Nothing but the `time` attributes depends on the machine, so two runs of
//! the same seed give the same report but for timings.

use anyhow::{Context, Result};
use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
use road_sim::{Outcome, Point, SimResult};
use std::path::Path;
use std::time::Duration;

/// One driven road, as a test case.
pub struct JunitCase<'a> {
    /// The case's name, unique in its suite (`test 12`, `suite road 3`).
    pub name: String,
    /// What the road came from (a run file, a suite), the case's `classname`.
    pub source: String,
    /// The road's points.
    pub road_points: &'a [Point],
    /// The drive; `None` for a road that was not driven (invalid), with `skip_reason`.
    pub result: Option<&'a SimResult>,
    /// Why the road was not driven.
    pub skip_reason: Option<String>,
    /// A line added to the case's message (e.g. the outcome recorded before).
    pub note: Option<String>,
}

/// The message of a failing or broken drive: the outcome, BOLP, reason and lane exit.
pub fn failure_message(result: &SimResult) -> String {
    let reason = result
        .reason
        .map_or_else(String::new, |r| format!(", {}", r.name()));
    let exit = result.oob.as_ref().map_or_else(String::new, |oob| {
        format!(
            "; left its lane over the {} at ({:.1}, {:.1}) m after {:.1} s",
            oob.side.name(),
            oob.x,
            oob.y,
            oob.t_s
        )
    });
    format!(
        "{}{reason}: max BOLP {:.3}{exit}",
        result.outcome.name(),
        result.max_bolp
    )
}

/// The road's points as the case's text: enough to drive it again (`wogan simulate`).
fn road_text(road_points: &[Point]) -> String {
    let points = serde_json::to_string(road_points).unwrap_or_default();
    format!("{{\"road_points\": {points}}}")
}

/// The test case of one road.
fn test_case(case: &JunitCase) -> TestCase {
    let note = case.note.as_deref();
    let with_note = |message: String| match note {
        Some(note) => format!("{message} ({note})"),
        None => message,
    };
    let (status, time_s) = match case.result {
        Some(result) if result.outcome == Outcome::Pass => {
            (TestCaseStatus::success(), result.execution_ms / 1e3)
        }
        Some(result) => {
            let kind = match result.outcome {
                Outcome::Error => NonSuccessKind::Error,
                _ => NonSuccessKind::Failure,
            };
            let mut status = TestCaseStatus::non_success(kind);
            status
                .set_message(with_note(failure_message(result)))
                .set_type(result.outcome.name())
                .set_description(road_text(case.road_points));
            (status, result.execution_ms / 1e3)
        }
        None => {
            let reason = case
                .skip_reason
                .clone()
                .unwrap_or_else(|| "not driven".to_owned());
            let mut status = TestCaseStatus::skipped();
            status
                .set_message(with_note(reason))
                .set_description(road_text(case.road_points));
            (status, 0.0)
        }
    };
    let passed = matches!(status, TestCaseStatus::Success { .. });
    let mut test_case = TestCase::new(case.name.clone(), status);
    test_case
        .set_classname(case.source.clone())
        .set_time(Duration::from_secs_f64(time_s.max(0.0)));
    // A success has no message: its note goes to the case's output.
    if let (true, Some(note)) = (passed, note) {
        test_case.set_system_out(note);
    }
    test_case
}

/// Writes a report of one suite named `suite` holding `cases` to `path`, with `properties`
/// (seed, driver, ...) on the suite.
pub fn write_report(
    path: &Path,
    suite: &str,
    properties: &[(&str, String)],
    cases: &[JunitCase],
) -> Result<()> {
    let mut test_suite = TestSuite::new(suite);
    for (name, value) in properties {
        test_suite.add_property((*name, value.as_str()));
    }
    test_suite.add_test_cases(cases.iter().map(test_case));
    let mut report = Report::new("wogan");
    report.add_test_suite(test_suite);
    let text = report
        .to_string()
        .context("cannot encode the JUnit report")?;
    crate::files::output_file::write(path, text.as_bytes())
        .with_context(|| format!("cannot write the JUnit report {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use road_sim::StopReason;

    fn result(outcome: Outcome) -> SimResult {
        let mut result: SimResult = serde_json::from_value(serde_json::json!({
            "outcome": "PASS", "reason": null, "max_bolp": 0.9, "min_lane_distance_m": -0.5,
            "fitness_distance": 0.9, "sim_time_s": 5.0, "execution_ms": 2.0, "MAX_CURV": 0.1,
            "DIR_COV": 0.1, "STD_SA": 1.0, "MEAN_LP": 1.0, "MAX_LP": 2.0
        }))
        .expect("a result");
        result.outcome = outcome;
        if outcome == Outcome::Fail {
            result.reason = Some(StopReason::OutOfLane);
        }
        result
    }

    #[test]
    fn a_failing_road_is_a_failure_with_its_road_and_bolp() {
        let road = [[10.0, 10.0], [10.0, 40.0]];
        let failed = result(Outcome::Fail);
        let passed = result(Outcome::Pass);
        let cases = [
            JunitCase {
                name: "test 1".into(),
                source: "run.jsonl".into(),
                road_points: &road,
                result: Some(&failed),
                skip_reason: None,
                note: None,
            },
            JunitCase {
                name: "test 2".into(),
                source: "run.jsonl".into(),
                road_points: &road,
                result: Some(&passed),
                skip_reason: None,
                note: Some("recorded PASS".into()),
            },
        ];
        let dir = std::env::temp_dir().join(format!("wogan-junit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("report.xml");
        write_report(&path, "wogan run", &[("seed", "7".into())], &cases).unwrap();
        let xml = std::fs::read_to_string(&path).unwrap();
        assert!(
            xml.contains(r#"tests="2""#) && xml.contains(r#"failures="1""#),
            "{xml}"
        );
        assert!(xml.contains("FAIL, out_of_lane: max BOLP 0.900"), "{xml}");
        assert!(xml.contains("[[10.0,10.0],[10.0,40.0]]"), "{xml}");
        assert!(
            xml.contains(r#"<property name="seed" value="7"/>"#),
            "{xml}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
