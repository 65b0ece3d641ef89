//! The integration loop: continuous phases integrated by diffsol (step by step, with its dense
//! output), zero crossings located on that dense output, the event iteration at each event, and
//! output rows on the grid plus both sides of every event.

mod driver;
mod init;

use std::sync::Arc;

pub use init::initial_state;

use crate::error::SimError;
use crate::model::ModelSpec;
use crate::result::SimResult;
use crate::system::{assemble, System};

/// Assembles and simulates a model with its `[experiment]` settings.
pub fn simulate(spec: &ModelSpec) -> Result<SimResult, SimError> {
    let sys = assemble(spec)?;
    run(Arc::new(sys))
}

/// Simulates an assembled system (a sweep assembles once and runs many times).
pub fn run(sys: Arc<System>) -> Result<SimResult, SimError> {
    driver::run(sys)
}
