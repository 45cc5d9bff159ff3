//! `wogan export --format sbst`: a run in the SBST competition's result layout, as its pipeline
//! writes it: one `test.NNNN.json` per kept test with its `execution_data`, `generation_stats.csv`
//! and `oob_stats.csv` (the pipeline's `OOBAnalyzer` summary).
//!
//! The execution records come from driving each test again with the run's settings (its header)
//! and checking that the drive replays the recorded one exactly; a run that does not replay is
//! refused, naming the test, rather than exported with records of another drive.
//!
//! The directory written to must be new or empty, so that an export is never mixed with files
//! of another (an earlier, longer export's `test.0031.json` would read as part of this one).
//! `--force` replaces an earlier export, and removes nothing else. The run file must not be in
//! that directory, where the export could write over it.

use crate::files::run_file::read_run;
use crate::sbst::write_result_folder;
use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

use super::Status;

/// The layouts `wogan export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// The SBST tool competition's results: test.NNNN.json, generation_stats.csv, oob_stats.csv.
    Sbst,
}

/// Options of `wogan export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The layout to write.
    #[arg(long, value_enum, default_value_t = ExportFormat::Sbst)]
    pub format: ExportFormat,
    /// JSON lines of one `wogan run`.
    #[arg(value_name = "RUN")]
    pub run: PathBuf,
    /// Directory to write to: new (created) or empty.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Replace an earlier export in DIR: remove its test.NNNN.json, generation_stats.csv and
    /// oob_stats.csv first (refused, removing nothing, when DIR holds anything else).
    #[arg(long)]
    pub force: bool,
    /// The DAVE-2 weights the run was made with, when not the built-in ones (the header does
    /// not hold them).
    #[arg(long, value_name = "FILE")]
    pub driver_weights: Option<PathBuf>,
}

/// Runs `wogan export`.
pub fn run(args: &ExportArgs) -> Result<Status> {
    refuse_input_in_dir(&args.run, &args.dir)?;
    let run = read_run(&args.run)?;
    for problem in &run.problems {
        eprintln!("wogan export: {problem}");
    }
    let Some(header) = &run.header else {
        bail!(
            "{} has no header: the export drives each test again with the run's settings, \
             which the header holds",
            args.run.display()
        );
    };
    if let Some(executor) = &header.settings.executor {
        let command = executor.command.as_deref().unwrap_or("COMMAND");
        bail!(
            "{} was driven by an external executor ({command}); export drives each test again \
             with wogan's simulator, which would not give that executor's drives. wogan never \
             starts a command a file names: to drive the roads with it, give it yourself, e.g. \
             `wogan run --executor cmd:\"{command}\" ...`",
            args.run.display()
        );
    }
    write_result_folder(
        &run,
        header,
        &args.dir,
        args.force,
        args.driver_weights.as_deref(),
    )?;
    eprintln!(
        "wogan export: wrote {} tests to {}",
        run.tests.len(),
        args.dir.display()
    );
    Ok(if run.problems.is_empty() {
        Status::AllRead
    } else {
        Status::SomeLinesBad
    })
}

/// Refuses a run file in `dir` itself, where the export writes: it could be written over
/// (`wogan export dir/test.0001.json dir`), or read as part of the export.
fn refuse_input_in_dir(run: &Path, dir: &Path) -> Result<()> {
    // A file or directory that cannot be resolved (a missing one, standard input) is no clash;
    // reading the run reports a missing file.
    let (Ok(run_file), Ok(dir_resolved)) = (std::fs::canonicalize(run), std::fs::canonicalize(dir))
    else {
        return Ok(());
    };
    if run_file.parent() == Some(dir_resolved.as_path()) {
        bail!(
            "cannot export {} into {}: the run file is in that directory, where the export \
             writes its files (it could write over its input); export to another directory",
            run.display(),
            dir.display()
        );
    }
    Ok(())
}
