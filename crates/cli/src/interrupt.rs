//! Ctrl-C and SIGTERM as a flag: the commands that stream or search check it between pieces of
//! work (and the simulator between physics steps), write what they have, and end with exit 130.

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Set with the flag [`stop_flag`] hands out, for long computations deep in a command that no flag
/// is passed to (a report's measures); never set before the handler is installed.
static STOPPED: AtomicBool = AtomicBool::new(false);

/// A flag set by the first Ctrl-C or SIGTERM (the handler is installed once per process).
pub fn stop_flag() -> Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    let handler_stop = Arc::clone(&stop);
    ctrlc::set_handler(move || {
        handler_stop.store(true, Ordering::SeqCst);
        STOPPED.store(true, Ordering::SeqCst);
        // A controller or executor being waited for is given up at once, not at its deadline.
        child_process::stop_all();
    })
    .context("cannot install the Ctrl-C handler")?;
    Ok(stop)
}

/// The process's stop flag as a static: set with the one [`stop_flag`] returned.
pub fn stop_signal() -> &'static AtomicBool {
    &STOPPED
}

/// Whether Ctrl-C or SIGTERM came since [`stop_flag`] installed the handler.
pub fn stopped() -> bool {
    STOPPED.load(Ordering::SeqCst)
}
