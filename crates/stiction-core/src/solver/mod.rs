//! The integration loop: continuous phases integrated by diffsol (step by step, with its dense
//! output), zero crossings located on that dense output, the event iteration at each event, and
//! output rows on the grid plus both sides of every event.

mod driver;
mod init;

use std::rc::Rc;

pub use init::initial_state;

use crate::error::SimError;
use crate::model::ModelSpec;
use crate::result::SimResult;
use crate::system::{assemble, System};

/// Assembles and simulates a model with its `[experiment]` settings.
pub fn simulate(spec: &ModelSpec) -> Result<SimResult, SimError> {
    let sys = assemble(spec)?;
    run(Rc::new(sys))
}

/// Simulates an assembled system (a sweep assembles once and runs many times).
pub fn run(sys: Rc<System>) -> Result<SimResult, SimError> {
    driver::run(sys)
}
