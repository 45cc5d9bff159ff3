//! A program wogan talks to in JSON lines (an executor of roads, a controller of the car): started
//! with `sh -c "exec COMMAND"` (so that killing it kills the program, not a shell), spoken to one
//! line at a time. Three threads keep every wait bounded whatever the program does: one writes its
//! input (a program that stops reading never blocks wogan), one reads its answers (so that a
//! deadline and a stop flag are honoured while it works), one reads its stderr as bytes and keeps a
//! bounded tail of it for the message when it fails (a program whose stderr is not UTF-8, or has no
//! newlines, neither dies of a closed pipe nor grows wogan's memory). Requests are numbered and
//! answers name the request they answer ([`Echo`]), so that a second answer to one request is never
//! taken for the answer to the next. Dropping it writes its farewell line, closes its input, and
//! kills and reaps it if it does not end at once: no zombie.
//!
//! Two users share it, each with its own protocol on top: road-sim's controller driver
//! (`--oracle cmd:...`) and the cli's executor (`wogan run --executor cmd:...`).

mod reply_line;

pub use reply_line::{answer_object, LineError, LineWords};

use serde::Serialize;
use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::process::ExitStatusExt;
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{channel, sync_channel, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Longest answer line read, bytes: a longer one is a fault, not a memory sink.
pub const MAX_LINE_BYTES: u64 = 1 << 20;
/// Lines of the program's stderr kept for a fault's message.
const STDERR_TAIL_LINES: usize = 20;
/// Longest stderr line kept, bytes (the rest of a longer line is read and dropped).
const STDERR_LINE_BYTES: usize = 400;
/// How much of a line a message quotes, characters.
const QUOTED_CHARS: usize = 80;
/// How often a wait for an answer looks at the stop flag and at whether the program still runs.
const POLL: Duration = Duration::from_millis(50);
/// How long a program told farewell has to end before it is killed.
const GRACE: Duration = Duration::from_millis(500);
/// How long an ended program's last lines are waited for (they may still be in the pipe).
const LAST_WORDS: Duration = Duration::from_millis(200);

/// Set once the process is being stopped (Ctrl-C): every wait for an answer ends at once.
static STOPPING: AtomicBool = AtomicBool::new(false);

/// Ends every wait for an answer, in every child, now and from now on (the process is stopping).
pub fn stop_all() {
    STOPPING.store(true, Ordering::SeqCst);
}

/// Why a request got no answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Fault {
    /// The program could not be started.
    Start(String),
    /// It ended, or closed its output, before answering: how (its exit status or signal).
    Ended(String),
    /// It gave no answer within the deadline.
    Timeout(Duration),
    /// It did not read the request within the deadline (its input is full).
    NotReading(Duration),
    /// It wrote more than one line for one request.
    ExtraLines,
    /// Its answer could not be read (too long, not UTF-8) or the request not written.
    Io(String),
    /// The caller is stopping (Ctrl-C): the request is abandoned.
    Stopped,
}

impl std::fmt::Display for Fault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fault::Start(e) => write!(f, "it could not be started: {e}"),
            Fault::Ended(how) => write!(f, "{how} before answering"),
            Fault::Timeout(t) => write!(f, "no answer within {:.3} s", t.as_secs_f64()),
            Fault::NotReading(t) => write!(
                f,
                "it did not read its input within {:.3} s (no answer)",
                t.as_secs_f64()
            ),
            Fault::ExtraLines => write!(f, "it wrote more than one line for one request"),
            Fault::Io(e) => write!(f, "{e}"),
            Fault::Stopped => write!(f, "stopped"),
        }
    }
}

/// What the request number an answer carries says of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Echo {
    /// It answers the request asked.
    Asked,
    /// It answers the request answered before: a second answer to that one.
    Repeat(u64),
    /// It names another request.
    Other(u64),
    /// Its number is not a whole number >= 0.
    NotANumber,
    /// It has no number.
    Missing,
}

impl Echo {
    /// Reads the number `field` holds (`None`: the answer has no such field) against the request
    /// `asked` and the one `answered` before it.
    pub fn of(field: Option<&serde_json::Value>, asked: u64, answered: Option<u64>) -> Self {
        match field.map(serde_json::Value::as_u64) {
            Some(Some(n)) if n == asked => Echo::Asked,
            Some(Some(n)) if Some(n) == answered => Echo::Repeat(n),
            Some(Some(n)) => Echo::Other(n),
            Some(None) => Echo::NotANumber,
            None => Echo::Missing,
        }
    }
}

/// `text` safe to print on a terminal or quote in a message: control characters (escape
/// sequences, carriage returns, bells) are written as `\xNN` / `\u{NNNN}`; tabs are kept.
pub fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\t' => out.push(c),
            c if (c as u32) < 0x100 && c.is_control() => {
                out.push_str(&format!("\\x{:02x}", c as u32))
            }
            c if c.is_control()
                || matches!(c, '\u{2028}' | '\u{2029}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}') =>
            {
                out.push_str(&format!("\\u{{{:04x}}}", c as u32))
            }
            c => out.push(c),
        }
    }
    out
}

/// The start of `line`, printable, for a message about it ("…" when cut).
pub fn quoted(line: &str) -> String {
    let mut start: String = line.chars().take(QUOTED_CHARS).collect();
    if start.len() < line.len() {
        start.push('…');
    }
    printable(&start)
}

/// The program's input, written by a thread of its own: a write never blocks the caller.
struct Input {
    lines: Sender<Vec<u8>>,
    /// Lines queued so far.
    queued: u64,
    /// Lines the program's input took whole.
    written: Arc<AtomicU64>,
    /// Set when a write failed (the program closed its input or ended).
    broken: Arc<AtomicBool>,
}

impl Input {
    fn new(mut stdin: ChildStdin) -> Self {
        let (lines, queue) = channel::<Vec<u8>>();
        let written = Arc::new(AtomicU64::new(0));
        let broken = Arc::new(AtomicBool::new(false));
        let (count, failed) = (Arc::clone(&written), Arc::clone(&broken));
        std::thread::spawn(move || {
            // Ends when the sender is dropped (the input closes with `stdin`) or a write fails.
            for line in queue {
                if stdin.write_all(&line).and_then(|()| stdin.flush()).is_err() {
                    failed.store(true, Ordering::SeqCst);
                    return;
                }
                count.fetch_add(1, Ordering::SeqCst);
            }
        });
        Self {
            lines,
            queued: 0,
            written,
            broken,
        }
    }

    /// Queues `line`; an error once the program's input is known to be closed.
    fn queue(&mut self, line: Vec<u8>) -> Result<(), ()> {
        if self.broken.load(Ordering::SeqCst) || self.lines.send(line).is_err() {
            return Err(());
        }
        self.queued += 1;
        Ok(())
    }

    /// Whether every queued line was taken by the program.
    fn drained(&self) -> bool {
        self.written.load(Ordering::SeqCst) >= self.queued
    }
}

/// The last lines of the program's stderr, read as bytes: each line cut to
/// [`STDERR_LINE_BYTES`], a line ending at `\n` or `\r`, and invalid UTF-8 replaced.
#[derive(Debug, Default)]
struct StderrTail {
    lines: VecDeque<String>,
    current: Vec<u8>,
}

impl StderrTail {
    fn take(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            if byte == b'\n' || byte == b'\r' {
                self.end_line();
            } else if self.current.len() < STDERR_LINE_BYTES {
                self.current.push(byte);
            }
        }
    }

    fn end_line(&mut self) {
        if self.current.is_empty() {
            return;
        }
        if self.lines.len() == STDERR_TAIL_LINES {
            self.lines.pop_front();
        }
        let line = printable(&String::from_utf8_lossy(&self.current));
        self.lines.push_back(line);
        self.current.clear();
    }

    fn text(&self) -> String {
        let mut lines: Vec<String> = self.lines.iter().cloned().collect();
        if !self.current.is_empty() {
            lines.push(printable(&String::from_utf8_lossy(&self.current)));
        }
        lines.join("\n")
    }
}

/// A running program.
pub struct ChildProcess {
    child: Child,
    input: Option<Input>,
    answers: Receiver<Result<String, String>>,
    stderr_tail: Arc<Mutex<StderrTail>>,
    farewell: Option<Vec<u8>>,
    /// The number of the last request answered, for [`Echo::Repeat`].
    answered: Option<u64>,
}

impl std::fmt::Debug for ChildProcess {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ChildProcess({})", self.child.id())
    }
}

impl ChildProcess {
    /// Starts `command`, writes it `hello`, and remembers `farewell` for when it is dropped.
    pub fn start<H: Serialize, F: Serialize>(
        command: &str,
        hello: &H,
        farewell: &F,
    ) -> Result<Self, Fault> {
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(format!("exec {command}"))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| Fault::Start(e.to_string()))?;
        let (stdin, stdout, stderr) =
            match (child.stdin.take(), child.stdout.take(), child.stderr.take()) {
                (Some(stdin), Some(stdout), Some(stderr)) => (stdin, stdout, stderr),
                _ => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(Fault::Start("its pipes could not be opened".into()));
                }
            };
        let (sender, answers) = sync_channel(4);
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            loop {
                let mut bytes = Vec::new();
                let read = (&mut reader)
                    .take(MAX_LINE_BYTES)
                    .read_until(b'\n', &mut bytes);
                let line = match read {
                    Ok(0) => return,
                    Ok(_)
                        if bytes.last() != Some(&b'\n') && bytes.len() as u64 >= MAX_LINE_BYTES =>
                    {
                        Err(format!("an answer line longer than {MAX_LINE_BYTES} bytes"))
                    }
                    Ok(_) => String::from_utf8(bytes)
                        .map(|s| s.trim_end().to_owned())
                        .map_err(|_| "an answer that is not UTF-8 text".to_owned()),
                    Err(e) => Err(format!("cannot read its output: {e}")),
                };
                let failed = line.is_err();
                if sender.send(line).is_err() || failed {
                    return;
                }
            }
        });
        let stderr_tail = Arc::new(Mutex::new(StderrTail::default()));
        let tail = Arc::clone(&stderr_tail);
        std::thread::spawn(move || {
            let mut stderr = stderr;
            let mut chunk = [0u8; 8192];
            // Read to the end whatever comes: a reader that stopped would close the pipe, and the
            // program's next write to stderr would kill it.
            loop {
                match stderr.read(&mut chunk) {
                    Ok(0) => return,
                    Ok(n) => tail
                        .lock()
                        .unwrap_or_else(|p| p.into_inner())
                        .take(&chunk[..n]),
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(_) => return,
                }
            }
        });
        let mut process = Self {
            child,
            input: Some(Input::new(stdin)),
            answers,
            stderr_tail,
            farewell: Some(line_of(farewell)?),
            answered: None,
        };
        process.send(hello)?;
        Ok(process)
    }

    /// Writes one line that is not answered. It is queued: a program that does not read it is
    /// found out by the next answer's deadline.
    pub fn send<T: Serialize>(&mut self, message: &T) -> Result<(), Fault> {
        let line = line_of(message)?;
        match self.input.as_mut().map(|input| input.queue(line)) {
            Some(Ok(())) => Ok(()),
            _ => Err(self.ended()),
        }
    }

    /// Sends `request`, number `number`, waits for its one answer line, at most `timeout`, giving
    /// up when `stop` is set, and reads it with `read(line, the number of the request answered
    /// before)`; a line read without error makes `number` the request answered.
    pub fn answer<T: Serialize, R, E>(
        &mut self,
        request: &T,
        number: u64,
        timeout: Duration,
        stop: &AtomicBool,
        read: impl FnOnce(&str, Option<u64>) -> Result<R, E>,
    ) -> Result<Result<R, E>, Fault> {
        // A line left from before (an answer to nothing) breaks the one-answer rule.
        if self.answers.try_recv().is_ok() {
            return Err(Fault::ExtraLines);
        }
        self.send(request)?;
        let line = self.next_line(timeout, stop)?;
        let read = read(&line, self.answered);
        if read.is_ok() {
            self.answered = Some(number);
        }
        Ok(read)
    }

    /// Waits for the next line the program writes unasked (a reply to `hello`), at most `timeout`,
    /// giving up when `stop` is set, and reads it with `read`.
    pub fn reply<R, E>(
        &mut self,
        timeout: Duration,
        stop: &AtomicBool,
        read: impl FnOnce(&str) -> Result<R, E>,
    ) -> Result<Result<R, E>, Fault> {
        let line = self.next_line(timeout, stop)?;
        Ok(read(&line))
    }

    /// The next non-blank line, at most `timeout` away, giving up when `stop` is set. A program
    /// that ended is found out at once, even when a process it started still holds its output.
    fn next_line(&mut self, timeout: Duration, stop: &AtomicBool) -> Result<String, Fault> {
        let start = Instant::now();
        loop {
            let left = timeout.saturating_sub(start.elapsed());
            if left.is_zero() {
                return Err(if self.input_drained() {
                    Fault::Timeout(timeout)
                } else {
                    Fault::NotReading(timeout)
                });
            }
            if let Some(line) = self.poll_line(left.min(POLL), stop)? {
                return Ok(line);
            }
        }
    }

    /// The next non-blank line if one comes within `wait` (`None`: none yet, the program still
    /// running), giving up when `stop` is set; for a caller that keeps its own deadlines (several
    /// requests in flight). A program that ended is found out at once.
    pub fn poll_line(
        &mut self,
        wait: Duration,
        stop: &AtomicBool,
    ) -> Result<Option<String>, Fault> {
        if stop.load(Ordering::SeqCst) || STOPPING.load(Ordering::SeqCst) {
            return Err(Fault::Stopped);
        }
        match self.answers.recv_timeout(wait) {
            Ok(Ok(line)) if line.trim().is_empty() => Ok(None),
            Ok(Ok(line)) => Ok(Some(line)),
            Ok(Err(problem)) => Err(Fault::Io(problem)),
            Err(RecvTimeoutError::Timeout) => match self.child.try_wait() {
                // Its last line may still be on its way.
                Ok(Some(_)) => match self.answers.recv_timeout(LAST_WORDS) {
                    Ok(Ok(line)) if !line.trim().is_empty() => Ok(Some(line)),
                    Ok(Err(problem)) => Err(Fault::Io(problem)),
                    _ => Err(self.ended()),
                },
                _ => Ok(None),
            },
            Err(RecvTimeoutError::Disconnected) => Err(self.ended()),
        }
    }

    /// Whether the program has read every line written to it.
    pub fn input_drained(&self) -> bool {
        self.input.as_ref().is_none_or(Input::drained)
    }

    /// How the program ended (its output closed): its exit status or signal when it has ended
    /// (waited for a moment), else that it closed its output.
    fn ended(&mut self) -> Fault {
        let deadline = Instant::now() + LAST_WORDS;
        loop {
            match self.child.try_wait() {
                Ok(Some(status)) => return Fault::Ended(describe_exit(status)),
                Ok(None) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(5))
                }
                _ => return Fault::Ended("it closed its output".into()),
            }
        }
    }

    /// Whether any request was answered: a process that has not answered one is still starting.
    pub fn has_answered(&self) -> bool {
        self.answered.is_some()
    }

    /// The last lines the program wrote to stderr, joined, control characters escaped (empty
    /// when none).
    pub fn stderr_tail(&self) -> String {
        // The stderr thread may still be reading what the program wrote as it failed.
        std::thread::sleep(Duration::from_millis(20));
        self.stderr_tail
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .text()
    }
}

/// "it ended with exit status 7", "it was killed by signal 11 (SIGSEGV)".
fn describe_exit(status: ExitStatus) -> String {
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("it ended with exit status {code}"),
        (None, Some(signal)) => match signal_name(signal) {
            Some(name) => format!("it was killed by signal {signal} ({name})"),
            None => format!("it was killed by signal {signal}"),
        },
        (None, None) => "it ended".into(),
    }
}

/// The name of a common signal on Linux.
fn signal_name(signal: i32) -> Option<&'static str> {
    Some(match signal {
        1 => "SIGHUP",
        2 => "SIGINT",
        3 => "SIGQUIT",
        4 => "SIGILL",
        6 => "SIGABRT",
        7 => "SIGBUS",
        8 => "SIGFPE",
        9 => "SIGKILL",
        11 => "SIGSEGV",
        13 => "SIGPIPE",
        15 => "SIGTERM",
        _ => return None,
    })
}

/// `message` as one JSON line.
fn line_of<T: Serialize>(message: &T) -> Result<Vec<u8>, Fault> {
    let mut line = serde_json::to_vec(message).map_err(|e| Fault::Io(e.to_string()))?;
    line.push(b'\n');
    Ok(line)
}

impl Drop for ChildProcess {
    fn drop(&mut self) {
        if let (Some(farewell), Some(input)) = (self.farewell.take(), self.input.as_mut()) {
            let _ = input.queue(farewell);
        }
        // Closing its input (once the farewell is written) is the program's sign to end.
        self.input = None;
        let deadline = Instant::now() + GRACE;
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn an_echoed_number_is_the_request_asked_the_one_before_or_another() {
        let echo = |v: serde_json::Value| Echo::of(v.get("n"), 5, Some(4));
        assert_eq!(echo(json!({"n": 5})), Echo::Asked);
        assert_eq!(echo(json!({"n": 4})), Echo::Repeat(4));
        assert_eq!(echo(json!({"n": 9})), Echo::Other(9));
        assert_eq!(echo(json!({"n": -1})), Echo::NotANumber);
        assert_eq!(echo(json!({"n": "5"})), Echo::NotANumber);
        assert_eq!(echo(json!({})), Echo::Missing);
        // Nothing answered yet: any other number is another request's.
        assert_eq!(Echo::of(json!({"n": 4}).get("n"), 5, None), Echo::Other(4));
    }

    #[test]
    fn stderr_is_read_as_bytes_into_a_bounded_tail_of_printable_lines() {
        let mut tail = StderrTail::default();
        tail.take(b"\xff bad\n");
        tail.take(&vec![b's'; 1_000_000]);
        tail.take(b"\rprogress 1\rprogress 2\r\x1b]0;TITLE\x07\n");
        let text = tail.text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "\u{fffd} bad");
        assert_eq!(lines[1].len(), STDERR_LINE_BYTES);
        assert_eq!(
            &lines[2..],
            ["progress 1", "progress 2", "\\x1b]0;TITLE\\x07"]
        );
        for i in 0..100 {
            tail.take(format!("line {i}\n").as_bytes());
        }
        assert_eq!(tail.text().lines().count(), STDERR_TAIL_LINES);
        assert!(tail.text().ends_with("line 99"));
    }

    #[test]
    fn quoted_text_is_cut_and_cannot_drive_a_terminal() {
        assert_eq!(printable("a\tb\u{1b}[2J\u{7}"), "a\tb\\x1b[2J\\x07");
        assert_eq!(printable("\u{202e}x"), "\\u{202e}x");
        let long = "é".repeat(200);
        assert_eq!(quoted(&long).chars().count(), QUOTED_CHARS + 1);
        assert_eq!(quoted("short"), "short");
    }

    /// A program that reads `hello`, then runs `then` (shell).
    fn program(then: &str) -> ChildProcess {
        let command = format!("sh -c 'read hello; {then}'");
        ChildProcess::start(&command, &json!({"type": "hello"}), &json!({"type": "bye"}))
            .expect("sh starts")
    }

    fn ask(
        process: &mut ChildProcess,
        request: &serde_json::Value,
        timeout: Duration,
    ) -> Result<u64, Fault> {
        let stop = AtomicBool::new(false);
        process
            .answer(request, 1, timeout, &stop, |line, _| {
                serde_json::from_str::<serde_json::Value>(line)
                    .map_err(|e| e.to_string())
                    .and_then(|v| v["n"].as_u64().ok_or_else(|| line.to_owned()))
            })
            .map(|read| read.expect("a numbered answer"))
    }

    #[test]
    fn a_program_whose_stderr_is_not_text_goes_on_answering() {
        let mut process = program(
            r#"printf "\377\n" >&2; while read line; do echo log >&2; echo "{\"n\": 1}"; done"#,
        );
        for _ in 0..3 {
            assert_eq!(
                ask(&mut process, &json!({"n": 1}), Duration::from_secs(30)),
                Ok(1)
            );
        }
        assert!(
            process.stderr_tail().ends_with("log"),
            "{}",
            process.stderr_tail()
        );
    }

    #[test]
    fn how_a_program_ended_is_said() {
        let mut process = program("exit 7");
        let fault = ask(&mut process, &json!({"n": 1}), Duration::from_secs(30)).unwrap_err();
        assert_eq!(fault, Fault::Ended("it ended with exit status 7".into()));
        let mut process = program("kill -SEGV $$");
        let fault = ask(&mut process, &json!({"n": 1}), Duration::from_secs(30)).unwrap_err();
        assert_eq!(
            fault,
            Fault::Ended("it was killed by signal 11 (SIGSEGV)".into())
        );
    }

    #[test]
    fn a_program_that_ended_is_found_out_though_its_child_holds_its_output() {
        // The background sleep keeps the output open: only the program's own end tells.
        let mut process = program("sleep 3 & exit 0");
        let fault = ask(&mut process, &json!({"n": 1}), Duration::from_secs(60)).unwrap_err();
        assert_eq!(fault, Fault::Ended("it ended with exit status 0".into()));
    }

    #[test]
    fn a_program_that_does_not_read_never_blocks_the_writer() {
        // The request is larger than a pipe holds, and the program never reads it.
        let mut process = program("sleep 30");
        let request = json!({"n": 1, "filler": "x".repeat(1 << 20)});
        let fault = ask(&mut process, &request, Duration::from_millis(300)).unwrap_err();
        assert_eq!(fault, Fault::NotReading(Duration::from_millis(300)));
        // Dropping it (farewell queued behind the blocked write) still ends it.
        drop(process);
    }

    #[test]
    fn a_wait_ends_when_the_caller_stops() {
        let mut process = program("sleep 30");
        let stop = AtomicBool::new(true);
        let asked = process.answer(
            &json!({"n": 1}),
            1,
            Duration::from_secs(60),
            &stop,
            |_, _| Ok::<(), ()>(()),
        );
        assert_eq!(asked.unwrap_err(), Fault::Stopped);
    }
}
