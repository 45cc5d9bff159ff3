//! End-to-end tests of campaigns beyond one machine (examples/cluster/): the GNU parallel recipe
//! run here on a task list of tiny runs, resumed after a failed and a crashed task, and
//! `wogan report` on the folder it fills (folders, `--from` lists, unfinished runs named); the
//! Slurm scripts with a stand-in `sbatch` that records the submission, each array index then run
//! as Slurm would start it (there is no scheduler here), and every script through `bash -n`.
//!
//! GNU parallel is not a build dependency: without it the recipe's test says so and checks
//! nothing, unless WOGAN_REQUIRE_PARALLEL is set (CI sets it, and installs parallel).

use crate::common::{entry_names, scratch_dir, wogan, write_file};
use crate::report::{fixture, path_str, read};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The checkout.
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
/// The recipes' folder.
const CLUSTER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/cluster");

/// Runs `examples/cluster/SCRIPT ARGS` with `wogan` the binary under test.
fn cluster_script(script: &str, args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new("bash")
        .arg(format!("{CLUSTER}/{script}"))
        .args(args)
        .env("WOGAN", env!("CARGO_BIN_EXE_wogan"))
        .envs(env.iter().copied())
        .output()
        .expect("bash runs")
}

/// Whether GNU parallel can be run; when not, says so (and fails where CI requires it).
fn parallel_available(test: &str) -> bool {
    let found = Command::new("parallel")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        assert!(
            std::env::var_os("WOGAN_REQUIRE_PARALLEL").is_none(),
            "{test}: GNU parallel is required (WOGAN_REQUIRE_PARALLEL is set) but not installed"
        );
        eprintln!(
            "{test}: GNU parallel is not installed (apt-get install parallel): the recipe was not \
             run"
        );
    }
    found
}

/// Each test's outcome and max BOLP (what a rerun of the same seed must reproduce; timings
/// differ).
fn drives(path: &Path) -> Vec<(String, String)> {
    read(path)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).expect("JSON"))
        .filter(|r| r["type"] == "test")
        .map(|r| (r["outcome"].to_string(), r["max_bolp"].to_string()))
        .collect()
}

/// What a command printed on stdout.
fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The cells of the configuration rows of `wogan report --table`.
fn rows(table: &str) -> Vec<Vec<String>> {
    table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| configuration"))
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_owned())
                .collect()
        })
        .collect()
}

/// The runs column of the row of the configuration that starts with `label`.
fn runs_of(table: &str, label: &str) -> String {
    rows(table)
        .into_iter()
        .find(|r| r[0].starts_with(label))
        .unwrap_or_else(|| panic!("no row {label}: {table}"))[1]
        .clone()
}

#[test]
fn parallel_campaign_runs_resumes_and_reports_as_one_folder() {
    if !parallel_available("parallel_campaign_runs_resumes_and_reports_as_one_folder") {
        return;
    }
    let dir = scratch_dir("campaign");
    let settings = write_file(
        &dir,
        "settings.txt",
        "# tiny runs\ntiny.random --algorithm random --max-tests 10\n\ntiny.wogan --max-tests 10\n",
    );
    let made = cluster_script("tasks.sh", &[&settings], &[("SEEDS", "1 2")]);
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    // A fifth task whose driver fails every drive: the run gives up after two (exit 1).
    let tasks = format!(
        "{}broken.controller 1 --oracle \"cmd:sh -c 'exit 3'\" --max-tests 10 --max-failed-drives 2\n",
        stdout(&made)
    );
    assert_eq!(tasks.lines().count(), 5, "{tasks}");
    let tasks = write_file(&dir, "tasks.txt", &tasks);
    let results = dir.join("results");
    let campaign = |args: &[&str]| {
        let mut all = vec![tasks.as_str(), path_str(&results)];
        all.extend_from_slice(args);
        cluster_script("parallel/campaign.sh", &all, &[])
    };

    // First submission: four runs finish, the broken one is left as a .part file.
    let first = campaign(&["--jobs", "2"]);
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert_eq!(first.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("5 of 5 tasks to run"), "{stderr}");
    assert!(stderr.contains("4 of 5 tasks finished"), "{stderr}");
    let runs = [
        "beamng-ai-proxy.tiny.random.1.jsonl",
        "beamng-ai-proxy.tiny.random.2.jsonl",
        "beamng-ai-proxy.tiny.wogan.1.jsonl",
        "beamng-ai-proxy.tiny.wogan.2.jsonl",
    ];
    let mut expected: Vec<String> = runs.iter().map(|r| r.to_string()).collect();
    expected.push("broken.controller.1.jsonl.part".to_owned());
    expected.push("joblog".to_owned());
    assert_eq!(entry_names(&results), expected);
    let joblog = read(&results.join("joblog"));
    assert_eq!(
        joblog.lines().count(),
        6,
        "a header and a line per task: {joblog}"
    );

    // A task killed mid-write (a node lost): its run is cut in the middle of a line and not
    // renamed.
    let cut = results.join(runs[1]);
    let finished = drives(&cut);
    let text = read(&cut);
    let without_summary = &text[..text.trim_end().rfind('\n').expect("lines")];
    let half_line = &without_summary[..without_summary.len() - 40];
    let part = results.join(format!("{}.part", runs[1]));
    std::fs::write(&part, half_line).expect("write");
    std::fs::remove_file(&cut).expect("remove");

    // The folder reports as one: every run counted with what it has, the unfinished named.
    let report = wogan(&["report", path_str(&results), "--table"], "");
    let table = stdout(&report);
    let errors = String::from_utf8_lossy(&report.stderr);
    assert_eq!(report.status.code(), Some(1), "{errors}");
    assert!(
        errors.contains(".tiny.random.2.jsonl.part:11: not JSON"),
        "{errors}"
    );
    assert!(
        errors.contains("2 of 5 runs did not end normally"),
        "{errors}"
    );
    assert_eq!(rows(&table).len(), 3, "{table}");
    assert_eq!(runs_of(&table, "random / beamng-ai-proxy"), "2");
    assert_eq!(runs_of(&table, "wogan / beamng-ai-proxy"), "2");
    assert_eq!(runs_of(&table, "wogan / controller"), "1");
    assert!(
        table.contains("broken.controller.1.jsonl.part: failed part-way")
            && table.contains("tiny.random.2.jsonl.part: truncated: no summary record"),
        "{table}"
    );

    // Resubmitted: only the broken and the cut tasks run; the cut one is made again, the same
    // drives as before, and the finished runs are left as they were.
    let before = std::fs::metadata(results.join(runs[0]))
        .and_then(|m| m.modified())
        .expect("mtime");
    let second = campaign(&[]);
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("2 of 5 tasks to run"), "{stderr}");
    assert!(stderr.contains("1 left"), "{stderr}");
    assert_eq!(drives(&cut), finished);
    assert!(!part.exists());
    let after = std::fs::metadata(results.join(runs[0]))
        .and_then(|m| m.modified())
        .expect("mtime");
    assert_eq!(before, after);
    let joblog = read(&results.join("joblog"));
    assert_eq!(joblog.lines().count(), 3, "{joblog}");

    // The finished runs alone, listed in a file: exit 0, two runs per configuration.
    let list: String = runs
        .iter()
        .map(|r| format!("{}\n", results.join(r).display()))
        .collect();
    let list = write_file(&dir, "finished.txt", &list);
    let report = wogan(&["report", "--from", &list, "--table"], "");
    assert_eq!(
        report.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&report.stderr)
    );
    let table = stdout(&report);
    assert_eq!(rows(&table).len(), 2, "{table}");
    assert_eq!(runs_of(&table, "random / beamng-ai-proxy"), "2");
    assert_eq!(runs_of(&table, "wogan / beamng-ai-proxy"), "2");
    assert!(!table.contains("did not end normally"), "{table}");
}

#[test]
fn a_folder_or_a_list_reports_as_the_files_it_holds() {
    let dir = scratch_dir("report-folder");
    let runs = dir.join("runs");
    std::fs::create_dir_all(runs.join("random")).expect("mkdir");
    let files = [
        ("wogan.seed3.jsonl", "runs/wogan.3.jsonl"),
        ("wogan.seed4.jsonl", "runs/wogan.4.jsonl"),
        ("random.seed4.jsonl", "runs/random/random.4.jsonl"),
        ("random.seed5.jsonl", "runs/random/random.5.jsonl"),
    ];
    let mut paths: Vec<PathBuf> = Vec::new();
    for (fixture_name, to) in files {
        let path = dir.join(to);
        std::fs::copy(fixture(fixture_name), &path).expect("copy");
        paths.push(path);
    }
    // Not runs: a note, and the temporary of an atomic write.
    std::fs::write(runs.join("notes.txt"), "seeds 3-5\n").expect("write");
    std::fs::write(runs.join(".wogan.5.jsonl.77.tmp"), "{").expect("write");
    let named: Vec<&str> = paths.iter().map(|p| path_str(p)).collect();
    let mut args = vec!["report", "--table"];
    args.extend(&named);
    let by_files = wogan(&args, "");
    assert_eq!(by_files.status.code(), Some(0));
    let by_folder = wogan(&["report", "--table", path_str(&runs)], "");
    assert_eq!(
        by_folder.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&by_folder.stderr)
    );
    assert_eq!(stdout(&by_folder), stdout(&by_files));
    assert_eq!(runs_of(&stdout(&by_folder), "wogan / beamng-ai-proxy"), "2");
    // A list on standard input, one path a line; a file named again counts once.
    let list = format!("{}\n\n{}\n", path_str(&runs), named[0]);
    let by_list = wogan(&["report", "--table", "--from", "-"], &list);
    assert_eq!(by_list.status.code(), Some(0));
    assert_eq!(stdout(&by_list), stdout(&by_files));
    assert!(String::from_utf8_lossy(&by_list.stderr).contains("counts once"));
    // A folder against a folder.
    let vs = wogan(
        &[
            "report",
            "--table",
            path_str(&runs.join("random")),
            "--vs",
            path_str(&dir.join("runs/wogan.3.jsonl")),
            path_str(&dir.join("runs/wogan.4.jsonl")),
        ],
        "",
    );
    assert_eq!(vs.status.code(), Some(0));
    assert!(stdout(&vs).contains("- A: random / beamng-ai-proxy"));
    // Hundreds of files under an open-file limit far below their number: read a few at a time.
    let many = dir.join("many");
    for i in 0..300 {
        let sub = many.join(format!("part{}", i % 7));
        std::fs::create_dir_all(&sub).expect("mkdir");
        let (fixture_name, _) = files[i % files.len()];
        std::fs::copy(fixture(fixture_name), sub.join(format!("run.{i}.jsonl"))).expect("copy");
    }
    let limited = Command::new("sh")
        .args(["-c", "ulimit -n 20 && exec \"$0\" report --table \"$1\""])
        .arg(env!("CARGO_BIN_EXE_wogan"))
        .arg(&many)
        .env("RAYON_NUM_THREADS", "4")
        .output()
        .expect("sh runs");
    let table = stdout(&limited);
    assert_eq!(
        limited.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&limited.stderr)
    );
    assert_eq!(runs_of(&table, "wogan / beamng-ai-proxy"), "150");
    assert_eq!(runs_of(&table, "random / beamng-ai-proxy"), "150");
    // A folder without runs, and a list that names none, are bad usage.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).expect("mkdir");
    let output = wogan(&["report", "--table", path_str(&empty)], "");
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("holds no run file"));
    let output = wogan(&["report", "--table", "--from", "-"], "\n");
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn slurm_submission_sizes_the_array_and_each_index_runs_its_task() {
    let dir = scratch_dir("slurm");
    // A stand-in for sbatch that records what it was asked to submit.
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).expect("mkdir");
    let submitted = dir.join("submitted.txt");
    write_file(
        &bin,
        "sbatch",
        &format!("#!/bin/sh\necho \"$@\" > '{}'\n", submitted.display()),
    );
    let chmod = Command::new("chmod")
        .args(["+x", path_str(&bin.join("sbatch"))])
        .status()
        .expect("chmod");
    assert!(chmod.success());
    let tasks = write_file(
        &dir,
        "tasks.txt",
        "tiny.random 1 --algorithm random --max-tests 5\ntiny.random 2 --algorithm random --max-tests 5\n",
    );
    let results = dir.join("results");
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let submit = cluster_script(
        "slurm/submit.sh",
        &[&tasks, path_str(&results), "--time=00:10:00"],
        &[("PATH", &path), ("MAX_RUNNING", "5")],
    );
    assert!(
        submit.status.success(),
        "{}",
        String::from_utf8_lossy(&submit.stderr)
    );
    let args = read(&submitted);
    let args: Vec<&str> = args.split_whitespace().collect();
    assert_eq!(args[..2], ["--array=1-2%5", "--time=00:10:00"]);
    assert!(args[2].ends_with("examples/cluster/slurm/campaign.sbatch"));
    let pending = args[3];
    assert!(pending.contains("/results/pending.") && pending.ends_with(".txt"));
    // Each array index as Slurm would start it, from the checkout's root.
    for index in ["2", "1", "2"] {
        let task = Command::new("bash")
            .arg(args[2])
            .args([pending, args[4]])
            .env("WOGAN", env!("CARGO_BIN_EXE_wogan"))
            .env("SLURM_ARRAY_TASK_ID", index)
            .env("SLURM_SUBMIT_DIR", REPO)
            .current_dir(REPO)
            .output()
            .expect("bash runs");
        assert!(
            task.status.success(),
            "{}",
            String::from_utf8_lossy(&task.stderr)
        );
    }
    assert_eq!(
        entry_names(&results),
        [
            pending.rsplit('/').next().expect("a name"),
            "tiny.random.1.jsonl",
            "tiny.random.2.jsonl"
        ]
    );
    // Everything finished: nothing more to submit.
    std::fs::remove_file(&submitted).expect("remove");
    let again = cluster_script(
        "slurm/submit.sh",
        &[&tasks, path_str(&results)],
        &[("PATH", &path)],
    );
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("every task"));
    assert!(!submitted.exists());
}

#[test]
fn cluster_scripts_parse_and_task_lines_are_checked() {
    for script in [
        "tasks.sh",
        "task.sh",
        "parallel/campaign.sh",
        "slurm/campaign.sbatch",
        "slurm/submit.sh",
    ] {
        let output = Command::new("bash")
            .args(["-n", &format!("{CLUSTER}/{script}")])
            .output()
            .expect("bash runs");
        assert!(
            output.status.success(),
            "{script}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
    let dir = scratch_dir("task-lines");
    // A finished run is one whose last line is a summary of a run neither interrupted nor failed.
    let finished = |name: &str, text: &str| {
        let path = write_file(&dir, name, text);
        cluster_script("task.sh", &["finished", &path], &[])
            .status
            .success()
    };
    let fixture_text = read(Path::new(&fixture("wogan.seed3.jsonl")));
    assert!(finished("whole.jsonl", &fixture_text));
    let cut = &fixture_text[..fixture_text.trim_end().rfind('\n').expect("lines")];
    assert!(!finished("cut.jsonl", cut));
    assert!(!finished(
        "stopped.jsonl",
        &fixture_text.replace("\"interrupted\":false", "\"interrupted\":true")
    ));
    assert!(!finished("empty.jsonl", ""));
    // Task lines name their output; a line without a seed is refused, naming it.
    let tasks = write_file(&dir, "tasks.txt", "a 1 --max-tests 5\n# b 2\nc seven\n");
    let pending = cluster_script("task.sh", &["pending", &tasks, path_str(&dir)], &[]);
    assert_eq!(stdout(&pending), "a 1 --max-tests 5\nc seven\n");
    assert!(String::from_utf8_lossy(&pending.stderr).contains("not a task line"));
    let bad = cluster_script("task.sh", &["run", path_str(&dir), "c seven"], &[]);
    assert_eq!(bad.status.code(), Some(2));
    let settings = write_file(&dir, "settings.txt", "# nothing\n");
    let none = cluster_script("tasks.sh", &[&settings], &[]);
    assert_eq!(none.status.code(), Some(2));
}
