//! Ctrl-C and SIGTERM as a flag: the commands that stream or search check it between pieces of
//! work (and the simulator between physics steps), write what they have, and end with exit 130.

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A flag set by the first Ctrl-C or SIGTERM (the handler is installed once per process).
pub fn stop_flag() -> Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    let handler_stop = Arc::clone(&stop);
    ctrlc::set_handler(move || {
        handler_stop.store(true, Ordering::SeqCst);
        // A controller or executor being waited for is given up at once, not at its deadline.
        child_process::stop_all();
    })
    .context("cannot install the Ctrl-C handler")?;
    Ok(stop)
}
