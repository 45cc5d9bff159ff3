//! Which files a report reads: run files named one by one, result folders of the competition's
//! pipeline (a peer generator's run, or `wogan export`'s), folders of them (a campaign's output,
//! thousands of files that a shell glob could not pass), and lists of paths (`--from FILE`).
//!
//! A folder that holds `test.NNNN.json` files directly is a result folder: one run, read by
//! [`crate::sbst::read_result_folder`]; nothing else in it is read (our harness's `tests.jsonl`
//! and `failing_roads.jsonl` are no run files). Any other folder stands for the runs under it, at
//! any depth, in path order: result folders, `*.jsonl`, and a campaign task's unfinished
//! `*.jsonl.part` (examples/cluster/), which the report names as a run that did not end normally.
//! Hidden entries (an atomic writer's temporary, `.git`) and linked folders (which could loop) are
//! not walked.

use crate::files::json_lines::{numbered_lines, open_input};
use crate::sbst::is_result_folder;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The ending of a run file.
const RUN_SUFFIX: &str = ".jsonl";
/// The ending of a campaign task's run file while it runs, or after it failed or was stopped.
pub const UNFINISHED_SUFFIX: &str = ".jsonl.part";

/// What an input is read as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputKind {
    /// JSON lines of `wogan run`.
    RunFile,
    /// The competition's result folder of `test.NNNN.json` files.
    ResultFolder,
}

/// One file (or result folder) to read as a run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunInput {
    /// Where to read it.
    pub path: PathBuf,
    /// What it is read as.
    pub kind: InputKind,
    /// Whether it was found in a folder rather than named: a named file that cannot be read is
    /// bad usage, one found in a folder (a task's file renamed as it finished, say) a problem
    /// reported beside the rest.
    pub found: bool,
}

/// The runs `paths` stand for, in order: a file as itself, a result folder as one run, any other
/// folder as the runs under it. Fails on a folder that holds no run, or one that cannot be listed.
pub fn run_inputs(paths: &[PathBuf]) -> Result<Vec<RunInput>> {
    let mut inputs = Vec::new();
    for path in paths {
        if path.is_dir() {
            let before = inputs.len();
            walk(path, false, &mut inputs)?;
            if inputs.len() == before {
                bail!(
                    "{} holds no run file (*{RUN_SUFFIX}, *{UNFINISHED_SUFFIX}, or a result folder of \
                     test.NNNN.json files, at any depth)",
                    path.display()
                );
            }
        } else {
            inputs.push(RunInput {
                path: path.clone(),
                kind: InputKind::RunFile,
                found: false,
            });
        }
    }
    Ok(inputs)
}

/// Adds the runs `dir` stands for to `inputs`, in path order; `found` when `dir` was found in a
/// folder rather than named.
fn walk(dir: &Path, found: bool, inputs: &mut Vec<RunInput>) -> Result<()> {
    if is_result_folder(dir) {
        inputs.push(RunInput {
            path: dir.to_path_buf(),
            kind: InputKind::ResultFolder,
            found,
        });
        return Ok(());
    }
    let listing =
        std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))?;
    let mut entries = Vec::new();
    for entry in listing {
        let entry = entry.with_context(|| format!("cannot list {}", dir.display()))?;
        entries.push(entry);
    }
    // Path order, so that a report of a folder is the same whatever order the file system lists.
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if name.starts_with('.') {
            continue;
        }
        let path = entry.path();
        // The entry itself: a linked folder is not followed; a link to a file is read.
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if is_dir {
            walk(&path, true, inputs)?;
        } else if is_run_file(name) && path.is_file() {
            inputs.push(RunInput {
                path,
                kind: InputKind::RunFile,
                found: true,
            });
        }
    }
    Ok(())
}

/// Whether a file of this name is a run file a folder stands for.
fn is_run_file(name: &str) -> bool {
    name.ends_with(RUN_SUFFIX) || name.ends_with(UNFINISHED_SUFFIX)
}

/// The paths listed in `list` (`--from FILE`, `-` for standard input), one a line; blank lines
/// are skipped and a line's surrounding spaces are not part of its path.
pub fn listed_paths(list: &Path) -> Result<Vec<PathBuf>> {
    // Read line by line, each line bounded, so that a list that is no list (`/dev/zero`, a run
    // file given by mistake) neither fills memory nor runs on.
    let input = open_input(Some(list))
        .with_context(|| format!("cannot read the list of runs {}", list.display()))?;
    let mut paths = Vec::new();
    for line in numbered_lines(input) {
        let line =
            line.with_context(|| format!("cannot read the list of runs {}", list.display()))?;
        match line.text {
            Ok(text) => paths.push(PathBuf::from(text.trim())),
            Err(problem) => bail!(
                "the list of runs {}, line {}: {problem}",
                list.display(),
                line.number
            ),
        }
        if paths.len() > MAX_LISTED_RUNS {
            bail!(
                "the list of runs {} names more than {MAX_LISTED_RUNS} files",
                list.display()
            );
        }
    }
    if paths.is_empty() {
        bail!("the list of runs {} names no file", list.display());
    }
    Ok(paths)
}

/// Most files a list of runs (`--from`) may name: far beyond any campaign (20 seeds of 50
/// searches is 1,000), small enough that the list's reading is bounded.
pub const MAX_LISTED_RUNS: usize = 100_000;

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("wogan-inputs-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_folder_stands_for_its_run_files_at_any_depth_in_path_order() {
        let dir = scratch("walk");
        std::fs::create_dir_all(dir.join("b/deep")).unwrap();
        std::fs::create_dir_all(dir.join(".hidden")).unwrap();
        for file in [
            "b/deep/x.2.jsonl",
            "a.1.jsonl",
            "a.10.jsonl.part",
            "notes.txt",
            ".a.1.jsonl.123.tmp",
            ".hidden/h.jsonl",
            "b/y.jsonl.bak",
        ] {
            std::fs::write(dir.join(file), "").unwrap();
        }
        let named = dir.join("b/y.jsonl.bak");
        let inputs = run_inputs(&[dir.clone(), named.clone()]).unwrap();
        assert!(inputs.iter().all(|i| i.kind == InputKind::RunFile));
        let got: Vec<(String, bool)> = inputs
            .iter()
            .map(|i| {
                let relative = i.path.strip_prefix(&dir).unwrap();
                (relative.display().to_string(), i.found)
            })
            .collect();
        assert_eq!(
            got,
            [
                ("a.1.jsonl".to_owned(), true),
                ("a.10.jsonl.part".to_owned(), true),
                ("b/deep/x.2.jsonl".to_owned(), true),
                // A file named is read whatever its name.
                ("b/y.jsonl.bak".to_owned(), false),
            ]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_without_run_files_is_bad_usage() {
        let dir = scratch("empty");
        std::fs::write(dir.join("notes.txt"), "").unwrap();
        let error = run_inputs(std::slice::from_ref(&dir))
            .unwrap_err()
            .to_string();
        assert!(error.contains("holds no run file"), "{error}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_list_names_one_path_a_line() {
        let dir = scratch("list");
        let list = dir.join("runs.txt");
        std::fs::write(&list, "a.jsonl\n\n  b/c.jsonl  \r\n").unwrap();
        assert_eq!(
            listed_paths(&list).unwrap(),
            [PathBuf::from("a.jsonl"), PathBuf::from("b/c.jsonl")]
        );
        std::fs::write(&list, "\n \n").unwrap();
        assert!(listed_paths(&list)
            .unwrap_err()
            .to_string()
            .contains("names no file"));
        assert!(listed_paths(&dir.join("missing")).is_err());
        // A list that is no list is refused at its first overlong line, not read whole.
        let err = listed_paths(Path::new("/dev/zero"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("/dev/zero, line 1: the line is longer than 16 MiB"),
            "{err}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_of_test_files_is_one_run_and_nothing_in_it_is_walked() {
        let dir = scratch("results");
        for sub in ["peers/freneticv.1", "peers/ambiegen.1/nested", "wogan"] {
            std::fs::create_dir_all(dir.join(sub)).unwrap();
        }
        for file in [
            "peers/freneticv.1/test.0001.json",
            "peers/freneticv.1/tests.jsonl",
            "peers/freneticv.1/failing_roads.jsonl",
            "peers/ambiegen.1/test.0001.json",
            "peers/ambiegen.1/nested/x.jsonl",
            "wogan/run.jsonl",
        ] {
            std::fs::write(dir.join(file), "").unwrap();
        }
        let inputs = run_inputs(std::slice::from_ref(&dir)).unwrap();
        let got: Vec<(String, InputKind, bool)> = inputs
            .iter()
            .map(|i| {
                let relative = i.path.strip_prefix(&dir).unwrap();
                (relative.display().to_string(), i.kind, i.found)
            })
            .collect();
        let folder = InputKind::ResultFolder;
        assert_eq!(
            got,
            [
                ("peers/ambiegen.1".to_owned(), folder, true),
                ("peers/freneticv.1".to_owned(), folder, true),
                ("wogan/run.jsonl".to_owned(), InputKind::RunFile, true),
            ]
        );
        // Named, a result folder is itself.
        let named = run_inputs(&[dir.join("peers/freneticv.1")]).unwrap();
        assert_eq!(named.len(), 1);
        assert_eq!((named[0].kind, named[0].found), (folder, false));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
