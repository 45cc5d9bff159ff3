//! What the search drives: the self-driving-car problem as `wogan-core`'s system under test, in
//! two kinds. [`road_sut`] drives a road in wogan's simulator with a built-in or plugged-in
//! driver; [`executor_sut`] hands it to an executor, an external program that drives it in any
//! simulator and answers with the result (`--executor cmd:"COMMAND"`), through
//! [`executor_driver`] (which `replay` and `simulate` use too), over the versioned protocol of
//! [`executor_protocol`] (docs/reference.md has the specification and a full exchange), through
//! the executors [`executor_pool`] starts and feeds. Both give up after a streak of failed drives
//! ([`failure_streak`]).

pub mod executor_driver;
pub mod executor_pool;
pub mod executor_protocol;
pub mod executor_sut;
pub mod failure_streak;
#[cfg(test)]
mod protocol_schema;
pub mod road_sut;

pub use executor_driver::ExecutorDriver;
pub use executor_pool::{ExecutorSettings, HelloSettings};
pub use executor_sut::ExecutorSut;
