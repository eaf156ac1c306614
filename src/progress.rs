//! How library stages report progress without depending on a terminal: the CLI supplies an indicatif bar.

/// Receives progress of a long stage. Implementations must be cheap and thread-safe.
pub trait Progress: Sync {
    /// A new phase with `total` steps begins.
    fn start(&self, phase: &str, total: u64);
    /// `n` more steps are done.
    fn advance(&self, n: u64);
    /// The phase is over.
    fn finish(&self);
    /// A one-line message for the person waiting (for example that another process holds a lock).
    fn note(&self, _message: &str) {}
}

/// Progress that goes nowhere (tests, `--quiet`).
#[derive(Debug, Default, Clone, Copy)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}
