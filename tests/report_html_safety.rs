//! `wogan report --html` on runs that carry HTML, links and pictures where a file's strings reach
//! the report (issue 74, "the page: everything from a file is text"): a header's `algorithm` and
//! `oracle`, a summary's `error`, a run file's name, a peer result folder's name and its
//! `summary.json`'s `crashed`. The page shows each as text, its own script still runs, and a
//! failing road whose points make no road keeps the page within its size bound.

use crate::common::{scratch_dir, wogan, wogan_ok};
use crate::report::{chromium_present, fixture, html_size_bound, path_str, read};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Header `algorithm`s that ran a script, made a `javascript:` link, stopped the page's script or
/// made `--html` fail (defects 1, 11 and 12 of the hostile-input report of 2026-11-29).
const ALGORITHMS: [&str; 6] = [
    "<img src=x onerror=\"document.title=1\"><script>document.title=2</script>",
    "[x](javascript:alert(1))",
    "<javascript:alert(1)>",
    "`<!--<script>`",
    "![x](nothere.svg)",
    "![i](javascript:alert(1))",
];

/// A run file's name that closed report.md's code span around it.
const FILE_NAME: &str = "a` <img src=x onerror=\"document.title=4\"> `b.jsonl";

/// The records of the committed fixture run (seed 3 of WOGAN: 30 tests, 5 failing).
fn fixture_records() -> Vec<Value> {
    read(Path::new(&fixture("wogan.seed3.jsonl")))
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect()
}

/// Writes `records` as a run file at `path`.
fn write_run(path: &Path, records: &[Value]) {
    let text: String = records.iter().map(|r| format!("{r}\n")).collect();
    std::fs::write(path, text).expect("a scratch run");
}

/// The failing tests of the fixture run.
fn fixture_failures() -> usize {
    failures_in(Path::new(&fixture("wogan.seed3.jsonl")))
}

/// The failing tests of the run file at `path`.
fn failures_in(path: &Path) -> usize {
    read(path)
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|r| r["outcome"] == "FAIL")
        .count()
}

/// Writes every carrier into `dir`: one run per hostile algorithm, a run whose header's oracle is
/// HTML (a bad line, quoted in the problems), a run whose summary's error is HTML, a run file of
/// a hostile name, and a peer's result folder of a hostile name whose `summary.json` says it
/// crashed with HTML. Returns the paths to report and how many failing roads they hold.
fn hostile_runs(dir: &Path) -> (Vec<PathBuf>, usize) {
    let records = fixture_records();
    let mut paths = Vec::new();
    for (index, algorithm) in ALGORITHMS.iter().enumerate() {
        let mut run = records.clone();
        run[0]["algorithm"] = json!(algorithm);
        let path = dir.join(format!("algorithm{index}.jsonl"));
        write_run(&path, &run);
        paths.push(path);
    }
    let mut bad_oracle = records.clone();
    bad_oracle[0]["oracle"] = json!("<img src=x onerror=\"document.title=8\">");
    let path = dir.join("oracle.jsonl");
    write_run(&path, &bad_oracle);
    paths.push(path);
    let mut failed = records.clone();
    let summary = failed.last_mut().expect("a summary");
    summary["error"] = json!(
        "stderr: <img src=x onerror=\"document.title=3\">\n# heading\n<script>document.title=3</script>"
    );
    let path = dir.join("failed.jsonl");
    write_run(&path, &failed);
    paths.push(path);
    let path = dir.join(FILE_NAME);
    write_run(&path, &records);
    paths.push(path);

    // A peer's folder: a run of this build (100 tests at seed 3 fail some), exported as the
    // competition's pipeline writes one.
    let made = dir.join("made.jsonl");
    let args = ["run", "--quiet", "--max-tests", "100", "--seed", "3"];
    wogan_ok(&[&args[..], &["--out", path_str(&made)]].concat(), "");
    let export = dir.join("export");
    wogan_ok(
        &[
            "export",
            "--format",
            "sbst",
            path_str(&made),
            path_str(&export),
        ],
        "",
    );
    let peer_failures = failures_in(&made);
    assert!(peer_failures > 0, "the peer's run must fail some tests");
    std::fs::remove_file(&made).expect("the made run, which is no input");
    let peer = dir.join("peers/<img src=x onerror=\"document.title=5\">");
    std::fs::create_dir_all(&peer).expect("the peer's folder");
    for entry in std::fs::read_dir(&export).expect("the export") {
        let entry = entry.expect("an exported file");
        let name = entry.file_name();
        if name.to_string_lossy().starts_with("test.") {
            std::fs::copy(entry.path(), peer.join(name)).expect("a test file");
        }
    }
    let crashed = json!({"type": "summary", "oracle": "beamng-ai-proxy", "oob_tolerance": 0.85,
        "speed_limit": 70, "seed": 1,
        "crashed": "<img src=x onerror=\"document.title=6\"> [y](javascript:alert(6))"});
    std::fs::write(peer.join("summary.json"), crashed.to_string()).expect("summary.json");
    paths.push(dir.join("peers"));
    // Every run but the one whose header cannot be read, each holding the fixture's failures, and
    // the peer's.
    let runs = ALGORITHMS.len() + 2;
    (paths, runs * fixture_failures() + peer_failures)
}

/// The values of every `name="…"` attribute in `page`.
fn attributes<'a>(page: &'a str, name: &str) -> Vec<&'a str> {
    let start = format!(" {name}=\"");
    page.match_indices(&start)
        .map(|(at, _)| {
            let value = &page[at + start.len()..];
            &value[..value.find('"').expect("a closed attribute")]
        })
        .collect()
}

#[test]
fn html_from_run_files_names_and_errors_shows_as_text_and_the_page_still_works() {
    let dir = scratch_dir("html-hostile");
    let (paths, failing) = hostile_runs(&dir);
    let out = dir.join("report");
    let mut args = vec!["report"];
    args.extend(paths.iter().map(|p| path_str(p)));
    args.extend(["--out", path_str(&out), "--html"]);
    let output = wogan(&args, "");
    let stderr = String::from_utf8_lossy(&output.stderr);
    // The unreadable header and the runs that failed part-way are bad inputs; the page is written.
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("oracle.jsonl:1"), "{stderr}");
    let page = read(&out.join("report.html"));
    let markdown = read(&out.join("report.md"));

    // report.md: every file's string is text in any Markdown viewer.
    assert!(!markdown.contains('<'), "{markdown}");
    assert_eq!(
        markdown.matches("](javascript").count(),
        markdown.matches("\\](javascript").count(),
        "{markdown}"
    );
    assert!(markdown.contains("a\\` &lt;img src=x onerror=\"document.title=4\"&gt; \\`b.jsonl"));
    assert!(
        markdown.contains("document.title=8"),
        "the problem is listed"
    );

    // The page: its three scripts only, pictures only its own, links only beside it or on it.
    assert_eq!(page.matches("<script").count(), 3, "{page}");
    for raw in [
        "<img src=x",
        "<javascript:",
        "<!--",
        "<script>document.title",
    ] {
        assert!(!page.contains(raw), "{raw} on the page");
    }
    let images: Vec<&str> = page
        .match_indices("<img ")
        .map(|(at, _)| &page[at..])
        .collect();
    assert!(
        images.len() >= ALGORITHMS.len() * 2,
        "{} pictures",
        images.len()
    );
    for image in images {
        let tag = &image[..image.find('>').expect("a closed tag")];
        assert!(
            tag.starts_with("<img class=\"picture\" alt=\"")
                && tag.contains("\" src=\"data:image/svg+xml;base64,"),
            "{tag}"
        );
    }
    let hrefs = attributes(&page, "href");
    assert!(!hrefs.is_empty());
    for href in hrefs {
        let beside = href.ends_with(".svg") && !href.contains([':', '/', '\\']);
        assert!(
            href.starts_with('#') || beside || href.starts_with("https://"),
            "a link to {href}"
        );
    }
    assert!(page.contains("&lt;img src=x onerror="), "shown as text");
    assert_eq!(page.matches("<tr id=\"road-").count(), failing);
    // The road data keeps the labels whole, escaped so that none ends or stalls its element.
    let data_start =
        page.find("id=\"road-data\">").expect("the road data") + "id=\"road-data\">".len();
    let data_end = data_start + page[data_start..].find("</script>").expect("its end");
    let data: Value = serde_json::from_str(&page[data_start..data_end]).expect("JSON");
    let groups: Vec<&str> = data["groups"]
        .as_array()
        .expect("groups")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    for algorithm in ALGORITHMS {
        assert!(
            groups
                .iter()
                .any(|g| g.starts_with(&format!("{algorithm} / "))),
            "{algorithm} not in {groups:?}"
        );
    }

    if !chromium_present() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let check = std::process::Command::new("python3")
        .arg(root.join("scripts/ci/browser_check.py"))
        .args(["--page", path_str(&out.join("report.html"))])
        .args(["--rows", &failing.to_string()])
        .arg("--hostile")
        .output()
        .expect("python3 runs scripts/ci/browser_check.py");
    let stdout = String::from_utf8_lossy(&check.stdout);
    let stderr = String::from_utf8_lossy(&check.stderr);
    assert!(check.status.success(), "browser check: {stdout}\n{stderr}");
    for line in [
        "the title is the page's own; no on* attribute, no script but the page's",
        "the page's script runs: the filter filters",
        "the max BOLP column sorts",
        "a click opens the detail of",
        "no console error, no exception, nothing fetched",
    ] {
        assert!(stdout.contains(line), "{line:?} not in {stdout}");
    }
}

/// A failing road of 40,000 points that make no road (27 km: longer than any road may be) is
/// drawn from at most a few of them, so the page keeps its size bound, which counts no metres for
/// it (it had its points whole: 0.6 MB).
#[test]
fn a_failing_road_whose_points_make_no_road_keeps_the_page_within_its_bound() {
    let dir = scratch_dir("html-unmade-road");
    let mut records = fixture_records();
    let first_failure = records
        .iter()
        .position(|r| r["outcome"] == "FAIL")
        .expect("a failing test");
    let points: Vec<[f64; 2]> = (0..40_000)
        .map(|i| {
            let i = f64::from(i);
            [100.0 + 50.0 * (i * 0.01).sin(), 10.0 + i * 0.6]
        })
        .collect();
    records[first_failure]["road_points"] = json!(points);
    let run = dir.join("unmade.jsonl");
    write_run(&run, &records);
    let out = dir.join("report");
    let output = wogan(
        &["report", path_str(&run), "--out", path_str(&out), "--html"],
        "",
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let page = read(&out.join("report.html"));
    let failing = fixture_failures();
    assert_eq!(page.matches("<tr id=\"road-").count(), failing);
    // The fixture's other failing roads are 75 m each.
    let bound = html_size_bound(&out, failing, (failing as u64 - 1) * 80, 0);
    assert!(
        page.len() as u64 <= bound,
        "report.html is {} bytes, over its bound {bound}",
        page.len()
    );
}
