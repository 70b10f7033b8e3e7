//! A Python progress callback as a core [`Progress`].
//!
//! The heavy work runs with the GIL released; each report re-attaches to the interpreter,
//! checks for pending signals (Ctrl-C -> `KeyboardInterrupt`) and calls
//! `callback(fraction: float, stage: str)`. A `False` return, a pending signal or an
//! exception raised by the callback cancels the run; the exception is kept and re-raised
//! instead of `dualspectra.Cancelled`.

use dualspectra::Progress;
use pyo3::prelude::*;
use std::sync::{Arc, Mutex};

/// The exception that stopped the run, if any (shared with the callback).
#[derive(Clone, Default)]
pub struct Raised(Arc<Mutex<Option<PyErr>>>);

impl Raised {
    fn set(&self, err: PyErr) {
        if let Ok(mut slot) = self.0.lock() {
            slot.get_or_insert(err);
        }
    }
    /// Take the stored exception.
    pub fn take(&self) -> Option<PyErr> {
        self.0.lock().ok().and_then(|mut slot| slot.take())
    }
}

/// A core progress handle calling `callback` (if given) and checking signals at every report.
pub fn python_progress(callback: Option<Py<PyAny>>) -> (Progress, Raised) {
    let raised = Raised::default();
    let slot = raised.clone();
    let progress = Progress::new(move |fraction: f64, stage: &str| {
        Python::attach(|py| {
            // Only effective on the main thread; elsewhere it is a no-op.
            if let Err(e) = py.check_signals() {
                slot.set(e);
                return false;
            }
            let Some(cb) = &callback else { return true };
            match cb.call1(py, (fraction, stage)) {
                Ok(ret) if ret.is_none(py) => true,
                Ok(ret) => match ret.is_truthy(py) {
                    Ok(keep_going) => keep_going,
                    Err(e) => {
                        slot.set(e);
                        false
                    }
                },
                Err(e) => {
                    slot.set(e);
                    false
                }
            }
        })
    });
    (progress, raised)
}
