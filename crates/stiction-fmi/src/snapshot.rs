//! What an FMU instance saves and what its parts share, below them all: the error type, the
//! experiment settings, a saved state (`Snapshot`) and the fingerprint a serialized state must
//! carry. `instance.rs` makes and restores snapshots, `serial.rs` turns them into bytes,
//! `values.rs` binds the variables; none of them imports another for these.

use stiction_core::SimState;

pub type Fallible<T> = Result<T, String>;

/// The experiment settings of `setupExperiment` / `enterInitializationMode`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Experiment {
    pub start: Option<f64>,
    pub stop: Option<f64>,
    pub tolerance: Option<f64>,
}

/// A saved state: the run's (with its parameter changes), the values of the variables now and
/// when the run was built, and the experiment settings (a state restored into a fresh
/// instance builds its run from the values it started with, then replays the changes).
pub struct Snapshot {
    pub(crate) sim: SimState,
    pub(crate) values: Vec<Vec<f64>>,
    pub(crate) base: Vec<Vec<f64>>,
    pub(crate) experiment: Experiment,
}

/// What a state must have been saved with to be restored here: the FMU's GUID and the
/// runtime's version.
pub fn fingerprint(guid: &str) -> String {
    format!("{guid} stiction-fmi {}", env!("CARGO_PKG_VERSION"))
}
