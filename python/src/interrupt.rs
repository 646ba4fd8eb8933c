//! Running Rust work off the Python thread: the GIL released, Ctrl-C still heard.

use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting Python thread checks for signals (Ctrl-C).
const POLL: Duration = Duration::from_millis(50);

/// Runs `work` on its own thread while the calling thread, GIL released, waits for it and
/// checks Python's signal handlers every [`POLL`]: a Ctrl-C raises `KeyboardInterrupt` at once
/// and the call returns. The abandoned work runs to its end in the background and its result
/// is dropped (mining writes each file atomically, so an interrupted run leaves no partial
/// file, and `resume=True` continues it). A panic in `work` becomes a `RuntimeError`.
pub fn interruptible<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    interruptible_with(py, None, work)
}

/// As [`interruptible`], for work that watches `cancel`: on Ctrl-C the flag is set and the call
/// waits for the work to stop (the mining run finishes the pairs in flight and starts no
/// other), so nothing runs on after the `KeyboardInterrupt`; a second Ctrl-C stops waiting.
pub fn interruptible_with<T, F>(
    py: Python<'_>,
    cancel: Option<Arc<AtomicBool>>,
    work: F,
) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    let (tx, rx) = channel();
    std::thread::Builder::new()
        .name("scenalog".to_string())
        .spawn(move || {
            let result = std::panic::catch_unwind(AssertUnwindSafe(work));
            // The receiver is gone when the call was interrupted: nobody wants the result.
            let _ = tx.send(result);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a thread: {e}")))?;
    let mut rx = rx;
    loop {
        // The receiver moves into the GIL-free wait and back (it cannot be shared).
        let (got, back) = py.allow_threads(move || (rx.recv_timeout(POLL), rx));
        rx = back;
        match got {
            Ok(Ok(value)) => return Ok(value),
            Ok(Err(panic)) => {
                let what = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "unknown".to_string());
                return Err(PyRuntimeError::new_err(format!(
                    "internal error in scenalog (please report it): {what}"
                )));
            }
            Err(RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    if let Some(flag) = &cancel {
                        flag.store(true, Ordering::Relaxed);
                        wait_for_stop(py, rx);
                    }
                    return Err(interrupt);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "internal error in scenalog: the worker thread ended without a result",
                ))
            }
        }
    }
}

/// Waits for cancelled work to end, until it does or another signal arrives.
fn wait_for_stop<T: Send>(py: Python<'_>, rx: Receiver<T>) {
    let mut rx = rx;
    loop {
        let (got, back) = py.allow_threads(move || (rx.recv_timeout(POLL), rx));
        rx = back;
        match got {
            Ok(_) | Err(RecvTimeoutError::Disconnected) => return,
            Err(RecvTimeoutError::Timeout) => {
                if py.check_signals().is_err() {
                    return;
                }
            }
        }
    }
}
