//! The search as a service: `wogan run --executor cmd:"COMMAND"` hands each valid road the search
//! proposes to an external program that drives it in any simulator and answers with the result.
//! [`protocol`] owns the wire format (versioned; docs/reference.md has the specification and a
//! full exchange), [`sut`] the system under test the search sees; each executor is a
//! [`road_sim::child_process::ChildProcess`] (its pipes, a deadline per road, the tail of its
//! stderr, killed and reaped when dropped).

pub mod protocol;
pub mod sut;

pub use sut::{ExecutorSettings, ExecutorSut};
