//! Running a case in a child under limits and a watchdog, and judging how it ended.

use super::*;

/// How a child ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum End {
    Exited(i32),
    Signalled(i32),
    /// Still running when the watchdog killed it.
    Hung,
}

/// The kinds of failure counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Kind {
    Panic,
    Abort,
    Hang,
    NonJson,
}

impl Kind {
    pub(super) fn name(self) -> &'static str {
        match self {
            Kind::Panic => "panic",
            Kind::Abort => "abort",
            Kind::Hang => "hang",
            Kind::NonJson => "non-JSON output",
        }
    }
}

/// Everything the report says about a failing case; a case that passes leaves only its counts.
#[derive(Debug, Clone)]
pub(super) struct Failure {
    /// The kind and class of each failure of the case.
    pub(super) found: Vec<(Kind, String)>,
    pub(super) label: String,
    pub(super) replay: Option<(u64, usize)>,
    pub(super) target: Target,
    /// The shell command that runs the case again in its kept directory.
    pub(super) command: String,
    pub(super) notes: Vec<String>,
    /// Standard input and the input files, shortened.
    pub(super) inputs: Vec<String>,
    pub(super) stderr_tail: String,
    /// Output lines that are not JSON records, shortened.
    pub(super) bad_lines: Vec<String>,
}

/// What one case did.
pub(super) struct Ran {
    pub(super) order: usize,
    pub(super) target: Target,
    pub(super) end: End,
    pub(super) bad_line_count: usize,
    pub(super) failure: Option<Failure>,
}

pub(super) const STDIN: &str = "stdin";
pub(super) const STDOUT: &str = "stdout";
pub(super) const STDERR: &str = "stderr";

/// The shell script that limits the child's address space, then becomes the binary (`$0`).
pub(super) fn limit_script(settings: &Settings) -> String {
    format!(
        "ulimit -v {}; exec \"$0\" \"$@\"",
        settings.memory_mb * 1024
    )
}

/// Runs `case` in `dir`, judges it, and removes `dir` unless the case failed.
pub(super) fn run_one(case: &Case, order: usize, dir: &Path, settings: &Settings) -> Ran {
    let binary = env!("CARGO_BIN_EXE_wogan");
    std::fs::create_dir_all(dir).expect("a case directory");
    for (name, bytes) in &case.files {
        std::fs::write(dir.join(name), bytes).expect("a case's input file is written");
    }
    std::fs::write(dir.join(STDIN), &case.stdin).expect("a case's standard input is written");
    let file = |name: &str| File::create(dir.join(name)).expect("an output file");
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(limit_script(settings))
        .arg(binary)
        .args(&case.args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .stdin(File::open(dir.join(STDIN)).expect("standard input reads"))
        .stdout(file(STDOUT))
        .stderr(file(STDERR))
        .spawn()
        .expect("sh starts");
    let started = Instant::now();
    let mut pause = Duration::from_millis(1);
    let end = loop {
        if let Some(status) = child.try_wait().expect("the child can be waited for") {
            break match (status.code(), status.signal()) {
                (Some(code), _) => End::Exited(code),
                (None, Some(signal)) => End::Signalled(signal),
                (None, None) => End::Exited(-1),
            };
        }
        // The watchdog detects hangs: its limit is far above any case's normal time, so it says
        // nothing about speed.
        if started.elapsed() >= settings.watchdog {
            let _ = child.kill();
            let _ = child.wait();
            break End::Hung;
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(50));
    };
    let stdout = std::fs::read(dir.join(STDOUT)).unwrap_or_default();
    let stderr =
        String::from_utf8_lossy(&std::fs::read(dir.join(STDERR)).unwrap_or_default()).into_owned();
    let mut bad_lines = Vec::new();
    if case.target.writes_json_lines() {
        bad_lines.extend(non_json_lines("stdout", &stdout, end == End::Hung));
        for output in &case.json_outputs {
            for path in json_files(&dir.join(output)) {
                let bytes = std::fs::read(&path).unwrap_or_default();
                let name = path
                    .strip_prefix(dir)
                    .unwrap_or(&path)
                    .display()
                    .to_string();
                bad_lines.extend(non_json_lines(&name, &bytes, end == End::Hung));
            }
        }
    }
    let found = judge(case.target, end, &stderr, bad_lines.len());
    let failure = (!found.is_empty()).then(|| Failure {
        found,
        label: case.label.clone(),
        replay: case.replay,
        target: case.target,
        command: command_line(case, dir, binary, settings),
        notes: case.notes.clone(),
        inputs: inputs_shown(case),
        stderr_tail: tail(&stderr, 14),
        bad_lines: bad_lines.iter().take(2).cloned().collect(),
    });
    if failure.is_none() && !settings.keep_all {
        let _ = std::fs::remove_dir_all(dir);
    }
    Ran {
        order,
        target: case.target,
        end,
        bad_line_count: bad_lines.len(),
        failure,
    }
}

/// `path` if it is a file, or the files in it if it is a directory (a trace directory).
pub(super) fn json_files(path: &Path) -> Vec<PathBuf> {
    if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        files.sort();
        files
    } else if path.is_file() {
        vec![path.to_path_buf()]
    } else {
        Vec::new()
    }
}

/// The lines of `bytes` that are not a JSON object with a string `"type"`, named by `source` and
/// line number. A last line cut short because the watchdog killed the writer is left out.
pub(super) fn non_json_lines(source: &str, bytes: &[u8], killed: bool) -> Vec<String> {
    let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
    let last = lines.pop().unwrap_or_default();
    if !last.is_empty() && !killed {
        lines.push(last);
    }
    lines
        .iter()
        .enumerate()
        .filter(|(_, line)| !is_record(line))
        .map(|(i, line)| format!("{source}:{}: {}", i + 1, preview(line, 200)))
        .collect()
}

pub(super) fn is_record(line: &[u8]) -> bool {
    serde_json::from_slice::<Value>(line)
        .ok()
        .is_some_and(|v| v.get("type").is_some_and(Value::is_string))
}

/// The failures a case showed: each with a class that groups failures of one cause.
pub(super) fn judge(
    target: Target,
    end: End,
    stderr: &str,
    bad_lines: usize,
) -> Vec<(Kind, String)> {
    let name = target.name();
    let mut found = Vec::new();
    let panicked = end == End::Exited(101) || stderr.contains("panicked");
    if panicked {
        found.push((Kind::Panic, format!("{name}: {}", signature(stderr))));
    }
    match end {
        End::Signalled(signal) => found.push((
            Kind::Abort,
            format!("{name}: {}: {}", signal_name(signal), signature(stderr)),
        )),
        End::Exited(134) => found.push((
            Kind::Abort,
            format!("{name}: exit 134: {}", signature(stderr)),
        )),
        End::Hung => found.push((Kind::Hang, format!("{name}: still running at the watchdog"))),
        End::Exited(_) => {}
    }
    if bad_lines > 0 {
        found.push((
            Kind::NonJson,
            format!("{name}: an output line is not a JSON record"),
        ));
    }
    found
}

/// A failure's message (digits replaced by `N`, so that one cause makes one class) and the first
/// frame of this workspace in its backtrace.
pub(super) fn signature(stderr: &str) -> String {
    let lines: Vec<&str> = stderr.lines().collect();
    let message = match lines.iter().position(|l| l.contains("panicked at")) {
        Some(i) => {
            let location = lines[i].split("panicked at ").nth(1).unwrap_or("");
            let message = lines.get(i + 1).copied().unwrap_or("").trim();
            // A location in the standard library (capacity overflow, slicing) says less than the
            // frame below; one in this workspace says where.
            if location.starts_with("/rustc/") || location.contains("/.cargo/") {
                message.to_owned()
            } else {
                format!("{message} at {}", location.trim_end_matches(':'))
            }
        }
        None => lines
            .iter()
            .rev()
            .find(|l| is_message(l))
            .map_or_else(|| "(nothing on stderr)".to_owned(), |l| l.trim().to_owned()),
    };
    let mut message: String = message
        .chars()
        .map(|c| if c.is_ascii_digit() { 'N' } else { c })
        .collect();
    // Runs of digits become one N.
    while message.contains("NN") {
        message = message.replace("NN", "N");
    }
    let message: String = message.chars().take(160).collect();
    let frame = lines.iter().filter_map(|l| frame_symbol(l)).find(|symbol| {
        let symbol = symbol.trim_start_matches('<');
        OUR_CRATES
            .iter()
            .any(|c| symbol.starts_with(&format!("{c}::")))
    });
    match frame {
        Some(frame) => format!("{message} (in {frame})"),
        None => message,
    }
}

/// The symbol of a backtrace frame line (`  12: road_sim::road::spline::interpolate`).
pub(super) fn frame_symbol(line: &str) -> Option<&str> {
    let (number, symbol) = line.trim_start().split_once(": ")?;
    (!number.is_empty() && number.chars().all(|c| c.is_ascii_digit())).then_some(symbol.trim())
}

/// A line of stderr that says something (not backtrace or its notes).
pub(super) fn is_message(line: &str) -> bool {
    let line = line.trim();
    !line.is_empty()
        && line != "stack backtrace:"
        && !line.starts_with("note:")
        && !line.starts_with("at ")
        && frame_symbol(line).is_none()
}

pub(super) fn signal_name(signal: i32) -> String {
    match signal {
        4 => "SIGILL".into(),
        6 => "SIGABRT".into(),
        7 => "SIGBUS".into(),
        8 => "SIGFPE".into(),
        9 => "SIGKILL".into(),
        11 => "SIGSEGV".into(),
        15 => "SIGTERM".into(),
        other => format!("signal {other}"),
    }
}

/// The command that runs the case again, from any shell.
pub(super) fn command_line(case: &Case, dir: &Path, binary: &str, settings: &Settings) -> String {
    let args: Vec<String> = case.args.iter().map(|a| shell_quote(a)).collect();
    format!(
        "cd {} && (ulimit -v {}; exec {} {}) < {STDIN}",
        shell_quote(&dir.display().to_string()),
        settings.memory_mb * 1024,
        shell_quote(binary),
        args.join(" ")
    )
}

pub(super) fn shell_quote(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_./=,:+-%@".contains(c));
    if plain {
        text.to_owned()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// The case's standard input and input files, shortened.
pub(super) fn inputs_shown(case: &Case) -> Vec<String> {
    let mut shown = Vec::new();
    if !case.stdin.is_empty() {
        shown.push(format!("stdin: {}", preview(&case.stdin, PREVIEW_BYTES)));
    }
    for (name, bytes) in &case.files {
        shown.push(format!("{name}: {}", preview(bytes, PREVIEW_BYTES)));
    }
    shown
}

/// Up to `max` bytes of `bytes` as one line of text: control characters escaped, the length said
/// when cut.
pub(super) fn preview(bytes: &[u8], max: usize) -> String {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(max)]);
    let mut shown = String::new();
    for c in text.chars() {
        match c {
            '\n' => shown.push_str("\\n"),
            '\r' => shown.push_str("\\r"),
            '\t' => shown.push_str("\\t"),
            c if c.is_control() => write!(shown, "\\u{{{:x}}}", u32::from(c)).expect("text"),
            c => shown.push(c),
        }
    }
    if bytes.len() > max {
        write!(shown, "... ({} bytes in all)", bytes.len()).expect("text");
    }
    shown
}

/// The last `count` lines of `text`, each shortened.
pub(super) fn tail(text: &str, count: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(count)..]
        .iter()
        .map(|l| preview(l.as_bytes(), 240))
        .collect::<Vec<_>>()
        .join("\n")
}
