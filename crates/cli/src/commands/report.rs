//! `wogan report`: a Markdown report with SVG pictures of one or more runs (grouped by their
//! configuration, or two groups side by side with `--vs`), or a picture of one simulation trace;
//! with `--html`, report.html beside it; with `--table`, the figures as Markdown tables on stdout.

use super::Status;
use crate::interrupt::stop_flag;
use crate::report;
use anyhow::{bail, Context, Result};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// Options of `wogan report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// JSON lines of `wogan run` (repetitions, possibly of several configurations; a file given
    /// twice counts once), the competition's result folders (a folder of `test.NNNN.json`: one
    /// run, a peer generator's or an export's), or folders of them: every `*.jsonl` file and
    /// result folder at any depth, and a campaign task's unfinished `*.jsonl.part`.
    #[arg(value_name = "RUN")]
    pub runs: Vec<PathBuf>,
    /// Also report the runs (files or folders) listed in FILE, one path a line (`-`: standard
    /// input), for more files than a command line takes; with --vs they join group A.
    #[arg(long, value_name = "FILE", conflicts_with = "trace")]
    pub from: Option<PathBuf>,
    /// Compare the RUN files (group A) with these runs (group B), with Mann–Whitney U tests
    /// (each group must be of one driver, oob tolerance and speed limit).
    #[arg(long, num_args = 1.., value_name = "RUN")]
    pub vs: Vec<PathBuf>,
    /// Draw one `wogan simulate --trace` file instead of reporting runs.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["runs", "vs"])]
    pub trace: Option<PathBuf>,
    /// Directory to write report.md and the pictures to (created if missing).
    #[arg(long, value_name = "DIR", required_unless_present = "table")]
    pub out: Option<PathBuf>,
    /// Print the figures as Markdown tables instead (no report.md, no pictures): one row per
    /// configuration, or with --vs every measure of A against B.
    #[arg(long, conflicts_with_all = ["trace", "out"])]
    pub table: bool,
    /// Also write report.html: one self-contained page (it loads nothing) with the runs, the
    /// failing roads in a table that sorts and filters, each road's detail, and report.md's
    /// figures and pictures; for a CI job to publish or a browser to open.
    #[arg(long, requires = "out", conflicts_with_all = ["trace", "table"])]
    pub html: bool,
    /// With --html: drive the N failing roads of highest BOLP again, with the driver and settings
    /// their run recorded (built-in drivers only), so that their detail shows the car's path and
    /// its BOLP along the drive.
    #[arg(long, value_name = "N", default_value_t = 0, requires = "html", conflicts_with = "table", value_parser = clap::value_parser!(u32).range(0..=10_000))]
    pub traces: u32,
}

/// Runs `wogan report`.
pub fn run(args: &ReportArgs) -> Result<Status> {
    let mut runs = args.runs.clone();
    if let Some(list) = &args.from {
        runs.extend(report::listed_paths(list)?);
    }
    if args.trace.is_none() && runs.is_empty() {
        bail!("give RUN files or folders to report on (or --from FILE), or --trace FILE");
    }
    if let Some(out) = &args.out {
        if out.exists() && !out.is_dir() {
            bail!(
                "--out {}: is a file, not a folder (the report writes report.md and its pictures \
                 into a folder)",
                out.display()
            );
        }
    }
    if let Some(trace) = &args.trace {
        // clap requires --out without --table, which --trace excludes.
        let out = args.out.as_ref().context("--trace needs --out DIR")?;
        create_out(out)?;
        report::trace_picture(trace, out)?;
        return Ok(Status::AllRead);
    }
    // Ctrl-C and SIGTERM are answered at any point: reading and measuring stop (nothing is
    // written), drives again (`--traces`) end and the page is written with those that ended;
    // the exit status is then 130.
    let stop = stop_flag()?;
    let reported = match &args.out {
        None => report::runs_tables(&runs, &args.vs).and_then(|(tables, problems)| {
            let mut stdout = std::io::stdout().lock();
            stdout.write_all(tables.as_bytes())?;
            stdout.flush()?;
            Ok(problems)
        }),
        Some(out) => create_out(out).and_then(|()| {
            let html = args.html.then_some((
                report::HtmlReport {
                    traces: args.traces as usize,
                },
                &*stop,
            ));
            report::runs_report(&runs, &args.vs, out, html)
        }),
    };
    if stop.load(Ordering::SeqCst) {
        let done = if reported.is_ok() {
            "the report was written without the drives that did not end"
        } else {
            "nothing was written"
        };
        eprintln!("wogan report: interrupted; {done}");
        return Ok(Status::Interrupted);
    }
    Ok(if reported? == 0 {
        Status::AllRead
    } else {
        Status::SomeLinesBad
    })
}

/// Creates the report's folder `out` when missing.
fn create_out(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))
}
