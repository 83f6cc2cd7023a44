//! Stopping on Ctrl-C or SIGTERM: the flag `vfd watch`, `vfd serve`, `vfd sim` and the
//! demos look at between steps.

use crate::Failure;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A Ctrl-C (or SIGTERM) flag, set once per process.
pub fn stop_flag() -> Result<Arc<AtomicBool>, Failure> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst))
        .map_err(|e| Failure::new(format!("cannot catch Ctrl-C: {e}")))?;
    Ok(stop)
}
