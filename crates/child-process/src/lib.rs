//! A program wogan talks to in JSON lines (an executor of roads, a controller of the car): started
//! with `sh -c "exec COMMAND"` (so that killing it kills the program, not a shell), spoken to one
//! line at a time, read by a thread so that a deadline and a stop flag are honoured while it works,
//! its stderr's last lines kept for the message when it fails. Requests are numbered and answers
//! name the request they answer ([`Echo`]), so that a second answer to one request is never taken
//! for the answer to the next. Dropping it writes its farewell line, closes its input, and kills
//! and reaps it if it does not end at once: no zombie.
//!
//! Two users share it, each with its own protocol on top: road-sim's controller driver
//! (`--oracle cmd:...`) and the cli's executor (`wogan run --executor cmd:...`).

use serde::Serialize;
use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Longest answer line read, bytes: a longer one is a fault, not a memory sink.
const MAX_LINE_BYTES: u64 = 1 << 20;
/// Lines of the executor's stderr kept for a fault's message.
const STDERR_TAIL_LINES: usize = 20;
/// Longest stderr line kept, characters.
const STDERR_LINE_CHARS: usize = 400;
/// How often a wait for an answer looks at the stop flag.
const STOP_POLL: Duration = Duration::from_millis(50);
/// How long a program told farewell has to end before it is killed.
const GRACE: Duration = Duration::from_millis(500);

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
    /// It closed its output or ended.
    Ended,
    /// It gave no answer within the deadline.
    Timeout(Duration),
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
            Fault::Ended => write!(f, "it ended (or closed its output) before answering"),
            Fault::Timeout(t) => write!(f, "no answer within {:.3} s", t.as_secs_f64()),
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

/// A running program.
pub struct ChildProcess {
    child: Child,
    stdin: Option<ChildStdin>,
    answers: Receiver<Result<String, String>>,
    stderr_tail: Arc<Mutex<VecDeque<String>>>,
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
        let (stdout, stderr) = match (child.stdout.take(), child.stderr.take()) {
            (Some(stdout), Some(stderr)) => (stdout, stderr),
            _ => return Err(Fault::Start("its pipes could not be opened".into())),
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
                    Err(e) => Err(format!("cannot read the executor's output: {e}")),
                };
                let failed = line.is_err();
                if sender.send(line).is_err() || failed {
                    return;
                }
            }
        });
        let stderr_tail = Arc::new(Mutex::new(VecDeque::new()));
        let tail = Arc::clone(&stderr_tail);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { return };
                let mut tail = tail.lock().unwrap_or_else(|p| p.into_inner());
                if tail.len() == STDERR_TAIL_LINES {
                    tail.pop_front();
                }
                tail.push_back(line.chars().take(STDERR_LINE_CHARS).collect());
            }
        });
        let stdin = child.stdin.take();
        let mut process = Self {
            child,
            stdin,
            answers,
            stderr_tail,
            farewell: Some(line_of(farewell)?),
            answered: None,
        };
        process.send(hello)?;
        Ok(process)
    }

    /// Writes one line that is not answered.
    pub fn send<T: Serialize>(&mut self, message: &T) -> Result<(), Fault> {
        let line = line_of(message)?;
        self.write(&line)
    }

    fn write(&mut self, line: &[u8]) -> Result<(), Fault> {
        let stdin = self.stdin.as_mut().ok_or(Fault::Ended)?;
        stdin
            .write_all(line)
            .and_then(|()| stdin.flush())
            .map_err(|_| Fault::Ended)
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
        let line = self.answer_line(request, timeout, stop)?;
        let read = read(&line, self.answered);
        if read.is_ok() {
            self.answered = Some(number);
        }
        Ok(read)
    }

    /// Sends `request` and waits for its one answer line, at most `timeout`, giving up when
    /// `stop` is set.
    fn answer_line<T: Serialize>(
        &mut self,
        request: &T,
        timeout: Duration,
        stop: &AtomicBool,
    ) -> Result<String, Fault> {
        // A line left from before (an answer to nothing) breaks the one-answer rule.
        if self.answers.try_recv().is_ok() {
            return Err(Fault::ExtraLines);
        }
        self.send(request)?;
        let deadline = Instant::now() + timeout;
        loop {
            if stop.load(Ordering::SeqCst) || STOPPING.load(Ordering::SeqCst) {
                return Err(Fault::Stopped);
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(Fault::Timeout(timeout));
            }
            match self.answers.recv_timeout(left.min(STOP_POLL)) {
                Ok(Ok(line)) if line.trim().is_empty() => continue,
                Ok(Ok(line)) => return Ok(line),
                Ok(Err(problem)) => return Err(Fault::Io(problem)),
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => return Err(Fault::Ended),
            }
        }
    }

    /// Whether any request was answered: a process that has not answered one is still starting.
    pub fn has_answered(&self) -> bool {
        self.answered.is_some()
    }

    /// The last lines the program wrote to stderr, joined (empty when none).
    pub fn stderr_tail(&self) -> String {
        // The stderr thread may still be reading what the executor wrote as it failed.
        std::thread::sleep(Duration::from_millis(20));
        let tail = self.stderr_tail.lock().unwrap_or_else(|p| p.into_inner());
        tail.iter().cloned().collect::<Vec<_>>().join("\n")
    }
}

/// `message` as one JSON line.
fn line_of<T: Serialize>(message: &T) -> Result<Vec<u8>, Fault> {
    let mut line = serde_json::to_vec(message).map_err(|e| Fault::Io(e.to_string()))?;
    line.push(b'\n');
    Ok(line)
}

impl Drop for ChildProcess {
    fn drop(&mut self) {
        if let Some(farewell) = self.farewell.take() {
            let _ = self.write(&farewell);
        }
        // Closing its input is the program's sign to end.
        self.stdin = None;
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
}
