//! The executors of a run: started as roads come, each told `hello` and kept while its answers can
//! be trusted, each given as many roads at once as its reply to `hello` announced
//! (`roads_at_once`: one for a plain executor, N for a pool of N simulators such as
//! `python -m wogan.ray`), its answers matched to their roads by `id`, in any order.
//!
//! The workers waiting on one executor take turns reading its output: whoever holds it reads a
//! line and hands it to the road it names (a mailbox per road in flight), so no thread is needed
//! per executor and every wait keeps its own deadline. An answer that names its road and is wrong
//! in a field fails that road only. A fault of the stream itself (the executor ended, a line that
//! names no road in flight, a second answer to a road, no answer within the deadline) stops that
//! executor: it is killed and reaped, every road in flight with it ends with the reason, and the
//! next road starts a new one. Where exactly one road is in flight, a line naming no road in
//! flight is that road's answer, so the fault is named as the answer's (`id: 104 is not the road
//! asked (4)`).

use super::executor_protocol::{
    parse_hello_reply, ExecutorDescription, Request, PROTOCOL, VERSION, WORDS,
};
use child_process::{ChildProcess, Fault, LineError};
use road_sim::{Point, SimConfig};
use serde_json::Value;
use std::collections::{HashMap, HashSet};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};
use std::time::{Duration, Instant};

/// How long a waiting worker reads an executor's output before letting the others have it.
const READ_TURN: Duration = Duration::from_millis(5);

/// What `hello` tells a new executor.
#[derive(Debug, Clone, Copy)]
pub struct HelloSettings {
    /// Side of the map, metres.
    pub map_size_m: f64,
    /// BOLP above which a drive fails.
    pub oob_tolerance: f64,
    /// The speed limit, km/h.
    pub speed_limit_kmh: f64,
}

impl HelloSettings {
    /// What `hello` tells an executor driving roads of a `map_size_m` map under `sim`'s
    /// conditions.
    pub fn of(map_size_m: f64, sim: &SimConfig) -> Self {
        Self {
            map_size_m,
            oob_tolerance: sim.oob_tolerance,
            speed_limit_kmh: sim.speed_limit_kmh,
        }
    }
}

/// A road's answer line, and whether it named the road (else it was taken as the answer of the
/// one road in flight, and the executor cannot be trusted if it is wrong).
#[derive(Debug)]
struct AnswerLine {
    line: String,
    named: bool,
}

/// Why a road has no answer line.
#[derive(Debug)]
pub enum NoAnswer {
    /// The run is stopping (Ctrl-C): the road is abandoned.
    Stopped,
    /// The executor failed: why, with the tail of its stderr.
    Failed(String),
}

/// How the executor is run.
#[derive(Debug, Clone, PartialEq)]
pub struct ExecutorSettings {
    /// The command, as typed after `cmd:` on the command line (never read from a file).
    pub command: String,
    /// Longest wait for one road's answer (and for a new executor's reply to `hello`).
    pub timeout: Duration,
}

/// The executors of a run, started as roads need them.
pub struct ExecutorPool {
    settings: ExecutorSettings,
    hello: HelloSettings,
    executors: Mutex<Vec<Arc<Executor>>>,
    /// Held while an executor starts, when executors take several roads (or nobody knows yet):
    /// the roads of a round wait for it rather than each starting one.
    starting: Mutex<()>,
    /// How many roads at once the first executor to answer `hello` announced.
    roads_at_once: OnceLock<usize>,
    /// What the first executor to answer `hello` said of itself.
    description: OnceLock<ExecutorDescription>,
}

impl ExecutorPool {
    /// A pool that starts executors with `settings`, told `hello`.
    pub fn new(settings: ExecutorSettings, hello: HelloSettings) -> Self {
        Self {
            settings,
            hello,
            executors: Mutex::new(Vec::new()),
            starting: Mutex::new(()),
            roads_at_once: OnceLock::new(),
            description: OnceLock::new(),
        }
    }

    /// What the first executor said of itself, and how many roads at once, once one answered.
    pub fn description(&self) -> Option<(ExecutorDescription, usize)> {
        let description = self.description.get()?.clone();
        Some((description, *self.roads_at_once.get()?))
    }

    /// Sends road `id` to an executor with room for it (starting one when none has), waits for
    /// its answer line, at most the executor timeout, and reads it with `read`. A line `read`
    /// refuses fails the road; it also stops the executor when the line did not name the road.
    pub fn drive<T, E: std::fmt::Display>(
        &self,
        id: u64,
        road_points: &[Point],
        stop: &AtomicBool,
        read: impl FnOnce(&str) -> Result<T, E>,
    ) -> Result<T, NoAnswer> {
        let executor = self.executor_for(id, road_points, stop)?;
        let answered = executor
            .wait(id, self.settings.timeout, stop)
            .and_then(|answer| {
                read(&answer.line).map_err(|problem| {
                    let problem = problem.to_string();
                    if answer.named {
                        return NoAnswer::Failed(format!("road {id}: the executor: {problem}"));
                    }
                    let mut connection = lock(&executor.connection);
                    connection.break_off(&problem);
                    let reason = connection.broken.clone().unwrap_or(problem);
                    NoAnswer::Failed(format!("road {id}: the executor: {reason}"))
                })
            });
        if let Err(NoAnswer::Failed(_)) = &answered {
            lock(&self.executors).retain(|e| !e.is_finished());
        }
        answered
    }

    /// An executor that has taken road `id` (sent it): one with room, or a new one.
    fn executor_for(
        &self,
        id: u64,
        road_points: &[Point],
        stop: &AtomicBool,
    ) -> Result<Arc<Executor>, NoAnswer> {
        let request = Request::Road {
            id: id as usize,
            road_points,
        };
        loop {
            if let Some(executor) = self.take_room(id, &request) {
                return Ok(executor);
            }
            // One start at a time, unless executors are known to take one road each (then each
            // worker starts its own, as many as `--jobs`, at once).
            let _starting = (self.roads_at_once.get() != Some(&1)).then(|| lock(&self.starting));
            if let Some(executor) = self.take_room(id, &request) {
                return Ok(executor);
            }
            let executor = Arc::new(self.start(Some(id), stop)?);
            lock(&self.executors).push(executor);
        }
    }

    /// Starts the first executor before any road (so that what it says of itself is known from
    /// the start), once it has answered `hello`; its failure names no road.
    pub fn start_first(&self, stop: &AtomicBool) -> Result<(), NoAnswer> {
        let executor = Arc::new(self.start(None, stop)?);
        lock(&self.executors).push(executor);
        Ok(())
    }

    /// An executor with room that took `request` (road `id`), if any.
    fn take_room(&self, id: u64, request: &Request<'_>) -> Option<Arc<Executor>> {
        let mut executors = lock(&self.executors);
        executors.retain(|e| !e.is_finished());
        executors.iter().find(|e| e.take(id, request)).cloned()
    }

    /// A new executor, once it has answered `hello`; `id` is the road it is started for, if any,
    /// which its failure names.
    fn start(&self, id: Option<u64>, stop: &AtomicBool) -> Result<Executor, NoAnswer> {
        let hello = Request::Hello {
            protocol: PROTOCOL,
            version: VERSION,
            units: "metres, seconds",
            map_size_m: self.hello.map_size_m,
            oob_tolerance: self.hello.oob_tolerance,
            speed_limit_kmh: self.hello.speed_limit_kmh,
        };
        let mut process = ChildProcess::start(&self.settings.command, &hello, &Request::Bye)
            .map_err(|fault| NoAnswer::Failed(failure(id, None, &fault.to_string())))?;
        let reply = match process.reply(self.settings.timeout, stop, parse_hello_reply) {
            Ok(Ok(reply)) => reply,
            Err(Fault::Stopped) => return Err(NoAnswer::Stopped),
            Ok(Err(problem)) => {
                return Err(NoAnswer::Failed(failure(
                    id,
                    Some(&process),
                    &problem.to_string(),
                )))
            }
            Err(fault) => {
                let problem = format!("no reply to hello: {fault}");
                return Err(NoAnswer::Failed(failure(id, Some(&process), &problem)));
            }
        };
        let _ = self.roads_at_once.set(reply.roads_at_once);
        let _ = self.description.set(reply.description);
        Ok(Executor {
            capacity: reply.roads_at_once,
            connection: Mutex::new(Connection {
                process: Some(process),
                in_flight: HashSet::new(),
                answered: HashSet::new(),
                mailbox: HashMap::new(),
                broken: None,
            }),
        })
    }
}

/// One executor process and the roads it holds.
struct Executor {
    /// Roads it takes at once.
    capacity: usize,
    connection: Mutex<Connection>,
}

/// An executor's process and its bookkeeping, read and written by one worker at a time.
struct Connection {
    /// `None` once it is stopped.
    process: Option<ChildProcess>,
    /// Roads sent and not yet answered.
    in_flight: HashSet<u64>,
    /// Roads it answered: a second answer to one is a fault.
    answered: HashSet<u64>,
    /// Answer lines read by another road's worker, for the road they name.
    mailbox: HashMap<u64, String>,
    /// Why it was stopped: the reason every road in flight with it ends with.
    broken: Option<String>,
}

impl Executor {
    /// Whether it was stopped and holds no road any more.
    fn is_finished(&self) -> bool {
        let connection = lock(&self.connection);
        connection.broken.is_some() && connection.in_flight.is_empty()
    }

    /// Sends road `id` if it has room: whether it took it.
    fn take(&self, id: u64, request: &Request<'_>) -> bool {
        let mut connection = lock(&self.connection);
        if connection.broken.is_some() || connection.in_flight.len() >= self.capacity {
            return false;
        }
        let Some(process) = connection.process.as_mut() else {
            return false;
        };
        match process.send(request) {
            Ok(()) => {
                connection.in_flight.insert(id);
                true
            }
            Err(fault) => {
                connection.break_off(&fault.to_string());
                false
            }
        }
    }

    /// Road `id`'s answer line, read by this worker or handed over by another, within `timeout`.
    fn wait(&self, id: u64, timeout: Duration, stop: &AtomicBool) -> Result<AnswerLine, NoAnswer> {
        let start = Instant::now();
        loop {
            let mut connection = lock(&self.connection);
            if let Some(line) = connection.mailbox.remove(&id) {
                connection.done(id);
                return Ok(AnswerLine { line, named: true });
            }
            if let Some(reason) = &connection.broken {
                let reason = format!("road {id}: the executor: {reason}");
                connection.in_flight.remove(&id);
                return Err(NoAnswer::Failed(reason));
            }
            let left = timeout.saturating_sub(start.elapsed());
            let Some(process) = connection.process.as_mut() else {
                connection.in_flight.remove(&id);
                return Err(NoAnswer::Failed(format!(
                    "road {id}: the executor is stopped"
                )));
            };
            if left.is_zero() {
                let fault = if process.input_drained() {
                    Fault::Timeout(timeout)
                } else {
                    Fault::NotReading(timeout)
                };
                return Err(connection.fail(id, &fault.to_string()));
            }
            match process.poll_line(left.min(READ_TURN), stop) {
                Ok(None) => {}
                Ok(Some(line)) => {
                    if let Some(answer) = connection.hand_over(id, line) {
                        return answer;
                    }
                }
                Err(Fault::Stopped) => return Err(NoAnswer::Stopped),
                Err(fault) => return Err(connection.fail(id, &fault.to_string())),
            }
        }
    }
}

impl Connection {
    /// Road `id` is answered.
    fn done(&mut self, id: u64) {
        self.in_flight.remove(&id);
        self.answered.insert(id);
    }

    /// Gives `line`, read by road `id`'s worker, to the road it names: `Some` when that is road
    /// `id` (or the line cannot be placed, which stops the executor), `None` when it went to
    /// another road's mailbox.
    fn hand_over(&mut self, id: u64, line: String) -> Option<Result<AnswerLine, NoAnswer>> {
        let named = serde_json::from_str::<Value>(&line)
            .ok()
            .and_then(|v| v.get("id").and_then(Value::as_u64));
        match named {
            Some(n) if n == id => {
                self.done(id);
                Some(Ok(AnswerLine { line, named: true }))
            }
            Some(n) if self.in_flight.contains(&n) && !self.mailbox.contains_key(&n) => {
                self.mailbox.insert(n, line);
                None
            }
            Some(n) if self.answered.contains(&n) || self.mailbox.contains_key(&n) => {
                Some(Err(self.fail(
                    id,
                    &LineError::Second {
                        line: WORDS.line,
                        request: WORDS.request,
                        number: n,
                    }
                    .to_string(),
                )))
            }
            // One road in flight: the line is its answer, whatever it names.
            _ if self.in_flight.len() == 1 => {
                self.done(id);
                Some(Ok(AnswerLine { line, named: false }))
            }
            Some(n) => Some(Err(self.fail(
                id,
                &format!("it answered road {n}, which was not sent to it"),
            ))),
            None => Some(Err(self.fail(
                id,
                &format!(
                    "an answer that names no road: {}",
                    child_process::quoted(&line)
                ),
            ))),
        }
    }

    /// Stops the executor for `problem`, found by road `id`'s worker: road `id`'s reason.
    fn fail(&mut self, id: u64, problem: &str) -> NoAnswer {
        self.break_off(problem);
        self.in_flight.remove(&id);
        let reason = self.broken.clone().unwrap_or_default();
        NoAnswer::Failed(format!("road {id}: the executor: {reason}"))
    }

    /// Stops the executor (bye, then killed and reaped) for `problem`, kept with the tail of its
    /// stderr for every road in flight with it.
    fn break_off(&mut self, problem: &str) {
        if self.broken.is_some() {
            return;
        }
        let mut reason = problem.to_owned();
        if let Some(process) = self.process.take() {
            let stderr = process.stderr_tail();
            if !stderr.is_empty() {
                reason.push_str(&format!("; its stderr ended with:\n{stderr}"));
            }
        }
        self.broken = Some(reason);
    }
}

/// Why road `id` (if the executor was started for one) failed with `process`: `problem`, and the
/// tail of the executor's stderr.
fn failure(id: Option<u64>, process: Option<&ChildProcess>, problem: &str) -> String {
    let stderr = process.map(ChildProcess::stderr_tail).unwrap_or_default();
    let mut reason = match id {
        Some(id) => format!("road {id}: the executor: {problem}"),
        None => format!("the executor: {problem}"),
    };
    if !stderr.is_empty() {
        reason.push_str(&format!("; its stderr ended with:\n{stderr}"));
    }
    reason
}

/// `mutex` locked, whether or not a thread panicked holding it (its data stays usable).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|p| p.into_inner())
}
