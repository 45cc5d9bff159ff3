//! The campaign: many cases at once, their failures grouped into classes, and its report.

use super::*;

/// A case to run: pinned, or made from the campaign's seed and this index.
pub(super) enum Job {
    Pinned(Box<Case>),
    Generated(usize),
}

/// Counts of one command.
#[derive(Debug, Default, Clone)]
pub(super) struct Tally {
    pub(super) tried: usize,
    pub(super) panics: usize,
    pub(super) aborts: usize,
    pub(super) hangs: usize,
    pub(super) non_json_lines: usize,
    pub(super) exit_0: usize,
    pub(super) exit_1: usize,
    pub(super) exit_2: usize,
    pub(super) other: usize,
}

/// The outcome of a campaign.
pub(super) struct Report {
    pub(super) settings: Settings,
    pub(super) pinned: usize,
    pub(super) planned: usize,
    pub(super) elapsed: Duration,
    pub(super) root: PathBuf,
    pub(super) tallies: BTreeMap<Target, Tally>,
    pub(super) failures: Vec<Failure>,
}

impl Report {
    /// Failing cases.
    pub(super) fn failing(&self) -> usize {
        self.failures.len()
    }
}

/// Runs the pinned cases and the campaign's cases, `settings.jobs` at a time.
pub(super) fn fuzz(settings: &Settings, pinned: Vec<Case>) -> Report {
    let corpus = Corpus::load();
    let root = scratch_dir(settings.dir_name);
    let indices: Vec<usize> = match settings.only {
        Some(index) => vec![index],
        None => (0..settings.cases)
            .filter(|&i| settings.targets.contains(&Target::of_case(i)))
            .collect(),
    };
    let pinned_count = pinned.len();
    let jobs: Vec<Job> = pinned
        .into_iter()
        .map(|case| Job::Pinned(Box::new(case)))
        .chain(indices.into_iter().map(Job::Generated))
        .collect();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Ran>> = Mutex::new(Vec::new());
    let started = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..settings.jobs {
            scope.spawn(|| loop {
                let order = next.fetch_add(1, Ordering::SeqCst);
                let Some(job) = jobs.get(order) else { break };
                if settings.deadline.is_some_and(|d| started.elapsed() >= d) {
                    break;
                }
                let case = match job {
                    Job::Pinned(case) => (**case).clone(),
                    Job::Generated(index) => generate(&corpus, settings.seed, *index),
                };
                let ran = run_one(&case, order, &root.join(case.slug()), settings);
                results.lock().expect("no worker panicked").push(ran);
            });
        }
    });
    // Only the directories of failing cases are left; an empty root goes too.
    let _ = std::fs::remove_dir(&root);
    let mut results = results.into_inner().expect("no worker panicked");
    results.sort_by_key(|r| r.order);
    let mut tallies: BTreeMap<Target, Tally> = BTreeMap::new();
    let mut failures = Vec::new();
    for ran in results {
        let tally = tallies.entry(ran.target).or_default();
        tally.tried += 1;
        match ran.end {
            End::Exited(0) => tally.exit_0 += 1,
            End::Exited(1) => tally.exit_1 += 1,
            End::Exited(2) => tally.exit_2 += 1,
            _ => tally.other += 1,
        }
        tally.non_json_lines += ran.bad_line_count;
        if let Some(failure) = ran.failure {
            let has = |kind: Kind| failure.found.iter().any(|(k, _)| *k == kind);
            tally.panics += usize::from(has(Kind::Panic));
            tally.aborts += usize::from(has(Kind::Abort));
            tally.hangs += usize::from(has(Kind::Hang));
            failures.push(failure);
        }
    }
    Report {
        settings: settings.clone(),
        pinned: pinned_count,
        planned: jobs.len(),
        elapsed: started.elapsed(),
        root,
        tallies,
        failures,
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.settings;
        let tried: usize = self.tallies.values().map(|t| t.tried).sum();
        writeln!(
            f,
            "wogan fuzz: seed {}, {tried} of {} inputs ({} pinned) in {:.1} s; {} at once, \
             watchdog {} s, memory limit {} MiB",
            s.seed,
            self.planned,
            self.pinned,
            self.elapsed.as_secs_f64(),
            s.jobs,
            s.watchdog.as_secs(),
            s.memory_mb
        )?;
        if tried < self.planned {
            writeln!(f, "(stopped at FUZZ_MINUTES before every input was tried)")?;
        }
        writeln!(
            f,
            "{:<9} {:>7} {:>7} {:>7} {:>6} {:>15} | {:>7} {:>7} {:>7} {:>6}",
            "command",
            "inputs",
            "panics",
            "aborts",
            "hangs",
            "non-JSON lines",
            "exit 0",
            "exit 1",
            "exit 2",
            "other"
        )?;
        let mut total = Tally::default();
        for (target, t) in &self.tallies {
            writeln!(f, "{}", tally_row(target.name(), t))?;
            total.tried += t.tried;
            total.panics += t.panics;
            total.aborts += t.aborts;
            total.hangs += t.hangs;
            total.non_json_lines += t.non_json_lines;
            total.exit_0 += t.exit_0;
            total.exit_1 += t.exit_1;
            total.exit_2 += t.exit_2;
            total.other += t.other;
        }
        writeln!(f, "{}", tally_row("total", &total))?;
        if self.failures.is_empty() {
            return writeln!(f, "no failures");
        }
        let mut classes: BTreeMap<(Kind, &str), Vec<&Failure>> = BTreeMap::new();
        for failure in &self.failures {
            for (kind, class) in &failure.found {
                classes
                    .entry((*kind, class.as_str()))
                    .or_default()
                    .push(failure);
            }
        }
        writeln!(
            f,
            "\n{} failing inputs in {} classes (their directories are kept under {}):",
            self.failures.len(),
            classes.len(),
            self.root.display()
        )?;
        for ((kind, class), failures) in &classes {
            writeln!(f, "\n[{}] {class}: {} inputs", kind.name(), failures.len())?;
            for failure in failures.iter().take(EXAMPLES_PER_CLASS) {
                write_failure(f, failure)?;
            }
        }
        Ok(())
    }
}

pub(super) fn tally_row(name: &str, t: &Tally) -> String {
    format!(
        "{name:<9} {:>7} {:>7} {:>7} {:>6} {:>15} | {:>7} {:>7} {:>7} {:>6}",
        t.tried,
        t.panics,
        t.aborts,
        t.hangs,
        t.non_json_lines,
        t.exit_0,
        t.exit_1,
        t.exit_2,
        t.other
    )
}

pub(super) fn write_failure(f: &mut fmt::Formatter<'_>, failure: &Failure) -> fmt::Result {
    writeln!(f, "  - {} ({})", failure.label, failure.target.name())?;
    if let Some((seed, index)) = failure.replay {
        writeln!(
            f,
            "    replay:  FUZZ_SEED={seed} FUZZ_ONLY={index} scripts/runs/fuzz_campaign.sh"
        )?;
    }
    writeln!(f, "    command: {}", failure.command)?;
    for note in &failure.notes {
        writeln!(
            f,
            "    fuzzed:  {}",
            preview(note.as_bytes(), PREVIEW_BYTES)
        )?;
    }
    for input in &failure.inputs {
        writeln!(f, "    input:   {input}")?;
    }
    for line in &failure.bad_lines {
        writeln!(f, "    output:  {line}")?;
    }
    for line in failure.stderr_tail.lines() {
        writeln!(f, "    stderr | {line}")?;
    }
    Ok(())
}
