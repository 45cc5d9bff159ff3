//! The loop shared by the commands that answer one record per input road (`validate`,
//! `simulate`): read numbered lines, parse each as a road, answer it, and write the answer as soon
//! as it is known, in input order.
//!
//! Answers stream: a line is answered as soon as it has been read, so another program can keep one
//! `wogan simulate` as a child and feed it one road at a time. With `--jobs N`, the lines already
//! read (up to N) are answered in parallel ([`crate::jobs`]). A reader thread reads ahead, so the
//! loop can notice Ctrl-C or SIGTERM while waiting for input; then it writes what it has answered
//! and ends. A JSON value spread over several lines (a pretty-printed competition test) is read as
//! one input, answered under the number of its first line.

use super::Status;
use crate::files::json_lines::{json_values, InputLine, JsonLinesWriter};
use crate::files::records::{ErrorRecord, Record};
use crate::files::road_input::road_reader;
use crate::jobs::{Ended, Jobs, Next};
use crate::sut::executor_protocol;
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use road_sim::road::input::{InputError, RoadInput};
use serde_json::Value;
use std::io::{BufRead, IsTerminal};
use std::sync::atomic::AtomicBool;
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError};
use std::time::Duration;

/// How often the loop looks at the stop flag while it waits for input (not a result's timing).
const STOP_POLL: Duration = Duration::from_millis(50);

/// Where a road came from: what its answer names it by.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadSource {
    /// The input line, from 1 (a value spread over several lines: its first).
    pub line: usize,
    /// The input object's `id`, when it has one: echoed in the answer, so that a program feeding
    /// roads can match answers to roads.
    pub id: Option<Value>,
}

/// What answering one input produced.
pub enum Answer {
    /// Write this record.
    Record(Box<Record>),
    /// The line was cut short by a stop: write nothing for it.
    Dropped,
}

/// Answers every road of `input` with `answer(source, road)`, `jobs` at a time; a line that
/// holds no road gets an `error` record and makes the status [`Status::SomeLinesBad`]. Ends early,
/// with [`Status::Interrupted`], once `stop` is set. The executor protocol's `hello` is answered
/// with `hello_reply` when there is one (`simulate` serving as an executor), else passed over.
pub fn answer_each_road<F>(
    input: Box<dyn BufRead + Send>,
    out: &mut JsonLinesWriter,
    map_size_m: f64,
    jobs: usize,
    stop: &AtomicBool,
    hello_reply: Option<Record>,
    answer: F,
) -> Result<Status>
where
    F: Fn(&RoadSource, &RoadInput) -> Answer + Sync,
{
    let jobs = Jobs::new(jobs)?;
    let lines = read_ahead(input, jobs.count() * 2);
    let progress = Progress::new();
    let mut status = Status::AllRead;
    // Wait for one line, then take the others already read, up to one per job.
    let next = |asked: usize| -> Result<Next<InputLine>> {
        let mut batch = match lines.recv_timeout(STOP_POLL) {
            Ok(line) => vec![line?],
            Err(RecvTimeoutError::Timeout) => return Ok(Next::Waiting),
            Err(RecvTimeoutError::Disconnected) => return Ok(Next::End),
        };
        while batch.len() < asked {
            match lines.try_recv() {
                Ok(line) => batch.push(line?),
                Err(_) => break,
            }
        }
        Ok(Next::Items(batch))
    };
    let reader = road_reader(map_size_m);
    let answer_line = |line: &InputLine| -> Option<Result<Answer, String>> {
        let text = match &line.text {
            Ok(text) => text,
            Err(error) => return Some(Err(error.clone())),
        };
        let value: Value = match serde_json::from_str(text) {
            Ok(value) => value,
            Err(error) => return Some(Err(InputError::NotJson(error.to_string()).to_string())),
        };
        if let Some(reply) = hello_reply.as_ref().filter(|_| is_executor_hello(&value)) {
            return Some(Ok(Answer::Record(Box::new(reply.clone()))));
        }
        match reader.read_value(&value) {
            Ok(RoadInput::Skip) => None,
            Ok(road) => {
                let source = RoadSource {
                    line: line.number,
                    id: value.get("id").filter(|id| !id.is_null()).cloned(),
                };
                Some(Ok(answer(&source, &road)))
            }
            Err(error) => Some(Err(error.to_string())),
        }
    };
    let write = |line: &InputLine, answer: Option<Result<Answer, String>>| -> Result<()> {
        match answer {
            None => {}
            Some(Ok(Answer::Record(record))) => out.write(&record)?,
            // Cut short by a stop, which ends the loop before the next batch.
            Some(Ok(Answer::Dropped)) => {}
            Some(Err(error)) => {
                status = Status::SomeLinesBad;
                out.write(&Record::Error(ErrorRecord {
                    line: line.number,
                    error,
                }))?;
            }
        }
        progress.answered();
        Ok(())
    };
    let ended = jobs.answer_in_order(stop, next, answer_line, write)?;
    progress.finish();
    Ok(match ended {
        Ended::Stopped => Status::Interrupted,
        Ended::AllAnswered => status,
    })
}

/// Whether `value` is the executor protocol's `hello`.
fn is_executor_hello(value: &Value) -> bool {
    value.get("type").and_then(Value::as_str) == Some("hello")
        && value.get("protocol").and_then(Value::as_str) == Some(executor_protocol::PROTOCOL)
}

/// Reads `input` on its own thread, joining a JSON value spread over several lines, at most
/// `ahead` inputs ahead of the answers.
fn read_ahead(
    input: Box<dyn BufRead + Send>,
    ahead: usize,
) -> Receiver<std::io::Result<InputLine>> {
    let (sender, receiver) = sync_channel(ahead);
    std::thread::spawn(move || {
        for line in json_values(input) {
            let failed = line.is_err();
            // The receiver is gone when the command ended (a stop): nothing left to do.
            if sender.send(line).is_err() || failed {
                return;
            }
        }
    });
    receiver
}

/// A count of answered lines on stderr, shown only on a terminal.
struct Progress {
    bar: Option<ProgressBar>,
}

impl Progress {
    fn new() -> Self {
        if !std::io::stderr().is_terminal() {
            return Self { bar: None };
        }
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} {pos} lines answered")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        Self { bar: Some(bar) }
    }

    fn answered(&self) {
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
