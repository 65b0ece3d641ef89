//! A run that records every variable as it goes (`run_recording_all`): the run advances in
//! short slices, and after each one hands the rows it recorded to the pool's threads, which
//! compute their variables (`result::recorded_while`), so that most of the table is done when
//! the run ends. The run itself is that of one `advance_to`, bit for bit (the slices pause
//! between integrator steps).

use std::sync::Arc;
use std::time::Duration;

use super::stepper::expected_rows;
use super::Simulation;
use crate::error::SimError;
use crate::result::{recorded_while, SimResult, MAX_TABLE_VALUES};
use crate::system::System;

/// The run's time between two hand-overs of rows: the pool's threads start this long after the
/// run, and each hand-over costs a copy of the rows, a lock and a wake-up.
const SLICE: Duration = Duration::from_micros(100);

/// The first slice: short, so that the pool's threads start early (CoupledClutches' run takes
/// 0.25 ms).
const FIRST_SLICE: Duration = Duration::from_micros(25);

/// Simulates `sys` from start to stop with every variable of every row computed by the time
/// it returns (`SimResult::table` is then at hand), on the pool's other threads while the run
/// goes on. `between` is called between slices of the run; returning false cancels it
/// (`SimError::Cancelled`).
pub fn run_recording_all(
    sys: Arc<System>,
    between: impl FnMut() -> bool,
) -> Result<SimResult, SimError> {
    let rows = expected_rows(&sys);
    run_with_room(sys, (rows, MAX_TABLE_VALUES), between)
}

/// `run_recording_all` with a table of room for about `rows` rows while the run goes on, and
/// of at most `limit` values.
fn run_with_room(
    sys: Arc<System>,
    room: (usize, f64),
    mut between: impl FnMut() -> bool,
) -> Result<SimResult, SimError> {
    let mut sim = Simulation::new(sys.clone())?;
    let stop = sys.experiment.stop_time;
    recorded_while(&sys, room, |feed| {
        let mut slice = FIRST_SLICE;
        while !sim.advance_for(stop, slice)? {
            slice = SLICE;
            feed.send(&sim.stepper.trajectory, &sim.stepper.discs);
            if !between() {
                return Err(SimError::Cancelled {
                    time: sim.stepper.now,
                });
            }
        }
        Ok(sim.into_result())
    })
}

#[cfg(test)]
mod tests;
