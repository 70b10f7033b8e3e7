//! Progress reporting and cancellation, passed down the pipeline.
//!
//! A [`Progress`] carries an optional callback `f(fraction in [0, 1], stage) -> keep_going`
//! and a shared cancel flag. Long loops call [`Progress::report`] or
//! [`Progress::check`] at least once per optimiser step; both return
//! `Err(Error::Cancelled)` once the callback returned `false` or the flag was set.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

type Callback = dyn Fn(f64, &str) -> bool + Send + Sync;

#[derive(Clone)]
pub struct Progress {
    callback: Option<Arc<Callback>>,
    cancel: Arc<AtomicBool>,
    /// Sub-range `[lo, hi]` of the overall progress that this handle reports into.
    lo: f64,
    hi: f64,
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("has_callback", &self.callback.is_some())
            .field("cancelled", &self.is_cancelled())
            .field("range", &(self.lo, self.hi))
            .finish()
    }
}

impl Default for Progress {
    fn default() -> Self {
        Progress::none()
    }
}

impl Progress {
    /// No callback, never cancelled (unless [`Progress::cancel`] is called).
    pub fn none() -> Self {
        Progress { callback: None, cancel: Arc::new(AtomicBool::new(false)), lo: 0.0, hi: 1.0 }
    }

    /// With a callback `f(fraction, stage) -> keep_going`.
    pub fn new(f: impl Fn(f64, &str) -> bool + Send + Sync + 'static) -> Self {
        Progress { callback: Some(Arc::new(f)), ..Self::none() }
    }

    /// Use an externally owned cancel flag (e.g. from a GUI thread).
    pub fn with_cancel_flag(mut self, flag: Arc<AtomicBool>) -> Self {
        self.cancel = flag;
        self
    }

    /// The shared cancel flag; setting it cancels the running computation.
    pub fn cancel_flag(&self) -> Arc<AtomicBool> {
        self.cancel.clone()
    }

    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::SeqCst);
    }

    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::SeqCst)
    }

    /// A handle that maps its own `[0, 1]` onto `[a, b]` of this handle's range.
    pub fn sub(&self, a: f64, b: f64) -> Progress {
        let span = if self.hi >= self.lo { self.hi - self.lo } else { 0.0 };
        Progress {
            callback: self.callback.clone(),
            cancel: self.cancel.clone(),
            lo: self.lo + span * a,
            hi: self.lo + span * b,
        }
    }

    /// Report `fraction` (0..1 of this handle's range) of `stage`; `Err(Cancelled)` if asked to stop.
    pub fn report(&self, fraction: f64, stage: &str) -> Result<()> {
        // Once cancelled, the callback is not called again.
        self.check()?;
        let f = fraction.clamp(0.0, 1.0);
        if let Some(cb) = &self.callback {
            let overall = self.lo + (self.hi - self.lo) * f;
            if !cb(overall, stage) {
                self.cancel();
            }
        }
        self.check()
    }

    /// `Err(Cancelled)` if cancellation was requested.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    #[test]
    fn the_callback_is_not_called_after_it_cancelled() {
        let calls = Arc::new(AtomicUsize::new(0));
        let counter = calls.clone();
        let p = Progress::new(move |_, _| counter.fetch_add(1, Ordering::SeqCst) < 2);
        assert!(p.report(0.1, "a").is_ok() && p.report(0.2, "b").is_ok());
        assert!(matches!(p.report(0.3, "c"), Err(Error::Cancelled)));
        assert!(matches!(p.sub(0.5, 1.0).report(0.4, "d"), Err(Error::Cancelled)));
        assert_eq!(calls.load(Ordering::SeqCst), 3);
    }
}
