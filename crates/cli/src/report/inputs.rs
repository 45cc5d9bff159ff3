//! Which files a report reads: run files named one by one, folders of them (a campaign's output,
//! thousands of files that a shell glob could not pass), and lists of paths (`--from FILE`).
//!
//! A folder stands for the run files under it, at any depth, in path order: `*.jsonl`, and a
//! campaign task's unfinished `*.jsonl.part` (examples/cluster/), which the report names as a run
//! that did not end normally. Hidden entries (an atomic writer's temporary, `.git`) and linked
//! folders (which could loop) are not walked.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The ending of a run file.
const RUN_SUFFIX: &str = ".jsonl";
/// The ending of a campaign task's run file while it runs, or after it failed or was stopped.
pub const UNFINISHED_SUFFIX: &str = ".jsonl.part";

/// One file to read as a run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunInput {
    /// Where to read it.
    pub path: PathBuf,
    /// Whether it was found in a folder rather than named: a named file that cannot be read is
    /// bad usage, one found in a folder (a task's file renamed as it finished, say) a problem
    /// reported beside the rest.
    pub found: bool,
}

/// The run files `paths` stand for, in order: a file as itself, a folder as its run files.
/// Fails on a folder that holds no run file, or one that cannot be listed.
pub fn run_inputs(paths: &[PathBuf]) -> Result<Vec<RunInput>> {
    let mut inputs = Vec::new();
    for path in paths {
        if path.is_dir() {
            let before = inputs.len();
            walk(path, &mut inputs)?;
            if inputs.len() == before {
                bail!(
                    "{} holds no run file (*{RUN_SUFFIX} or *{UNFINISHED_SUFFIX}, at any depth)",
                    path.display()
                );
            }
        } else {
            inputs.push(RunInput {
                path: path.clone(),
                found: false,
            });
        }
    }
    Ok(inputs)
}

/// Adds the run files under `dir` to `inputs`, in path order.
fn walk(dir: &Path, inputs: &mut Vec<RunInput>) -> Result<()> {
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
            walk(&path, inputs)?;
        } else if is_run_file(name) && path.is_file() {
            inputs.push(RunInput { path, found: true });
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
    let text = if list == Path::new("-") {
        std::io::read_to_string(std::io::stdin())
            .context("cannot read the list of runs on stdin")?
    } else {
        std::fs::read_to_string(list)
            .with_context(|| format!("cannot read the list of runs {}", list.display()))?
    };
    let paths: Vec<PathBuf> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .map(PathBuf::from)
        .collect();
    if paths.is_empty() {
        bail!("the list of runs {} names no file", list.display());
    }
    Ok(paths)
}

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
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
