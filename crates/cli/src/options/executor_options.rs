//! The options that hand the driving to an executor, an external program speaking the executor
//! protocol: the same on every command that drives roads (`run`, `replay`, `simulate`).

use crate::options::value_parsers::executor_timeout;
use crate::sut::failure_streak::FailureStreak;
use crate::sut::{ExecutorDriver, ExecutorSettings, HelloSettings};
use clap::Args;
use road_sim::SimConfig;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// `--executor` and the settings that go with it.
#[derive(Debug, Clone, Args)]
pub struct ExecutorOptions {
    /// Drive each road with an external program instead of wogan's simulator: `cmd:COMMAND`
    /// (run with `sh -c`; one per worker), speaking the executor protocol (docs/reference.md).
    /// Taken only from this command line, never from a file.
    #[arg(long, value_name = "cmd:COMMAND", value_parser = executor_command)]
    pub executor: Option<String>,
    /// Longest wait for an executor's answer to one road (and for a new one's reply to `hello`),
    /// from 100ms to 24h.
    #[arg(long, default_value = "10m", value_parser = executor_timeout, requires = "executor")]
    pub executor_timeout: Duration,
    /// Drives a program outside wogan (an executor; in `run` also a controller) may fail in a
    /// row before the command stops.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub max_failed_drives: u32,
}

impl ExecutorOptions {
    /// How the executor is run, when one is asked for.
    pub fn settings(&self) -> Option<ExecutorSettings> {
        self.executor.clone().map(|command| ExecutorSettings {
            command,
            timeout: self.executor_timeout,
        })
    }

    /// For the commands that drive given roads (`replay`, `simulate`): the executor asked for,
    /// told roads on a `map_size_m` map judged as `sim` says, its first process started and its
    /// reply to `hello` read; `None` without `--executor`; or why it could not be started.
    pub fn start<'a>(
        &self,
        map_size_m: f64,
        sim: &SimConfig,
        streak: &'a FailureStreak,
        stop: &'a AtomicBool,
    ) -> Result<Option<ExecutorDriver<'a>>, String> {
        let Some(settings) = self.settings() else {
            return Ok(None);
        };
        let hello = HelloSettings::of(map_size_m, sim);
        let driver = ExecutorDriver::new(settings, hello, false, streak, stop);
        driver.start()?;
        Ok(Some(driver))
    }
}

/// `--executor`: the command after `cmd:`.
fn executor_command(value: &str) -> Result<String, String> {
    match value.strip_prefix("cmd:") {
        Some(command) if !command.trim().is_empty() => Ok(command.to_owned()),
        Some(_) => Err("cmd: names no command".into()),
        None => Err(format!(
            "{value:?}: give the executor as cmd:\"COMMAND ARGS\""
        )),
    }
}
