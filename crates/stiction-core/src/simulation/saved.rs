//! Saving and restoring a run, bit for bit. A run is a function of its model and of the input
//! events it was given (the times and new values of `set_input`): where `advance_to` stopped
//! between them changes nothing (a run advanced in pieces is the run of one call). So a saved
//! state is that list and the time reached, and restoring it replays them on a fresh run of
//! the model: the restored run *is* the uninterrupted one, integrator and all, and continues
//! as it would have.
//!
//! Why not diffsol's own `checkpoint`/`set_state`: what the next step depends on is not all in
//! the state they hand out. Tsit45 and Esdirk34 (diffsol's `Rk`) also carry the previous error
//! norm (the step-size controller's memory) and the start of the last step (which the dense
//! output interpolates from); `set_state` keeps neither, and Bdf's and Esdirk34's `set_state`
//! reset the Jacobian the Newton iterations reuse, as a fresh checkpoint does. The states'
//! fields are private besides, so their history matrices cannot be serialized. A replay costs
//! the run's time to the saved point again; it needs only the model and the input events.
//!
//! What the run reached is kept too (state, discrete state, where it stands) and compared
//! after the replay: a state of another model, or one another build of the engine replays
//! differently, is refused rather than continued from somewhere else.

use super::integrator::with_solver;
use super::{Cursor, ParameterChange, Simulation};
use crate::engine::eval::DiscreteState;
use crate::error::SimError;

/// One input event: model input `input` (its index in `System::inputs`) set to `value` at
/// `time`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputChange {
    pub time: f64,
    pub input: usize,
    pub value: f64,
}

/// The whole state of a run at its current time: enough to continue from it later.
#[derive(Debug, Clone, PartialEq)]
// Alike in shape to `Trajectory` (a struct of documented vectors), not the same data.
pub struct SimState {
    /// Every input event from the start to now, in order.
    pub inputs: Vec<InputChange>,
    /// Every parameter change from the start to now, in order (each says how many input
    /// events came before it).
    pub parameters: Vec<ParameterChange>,
    /// What the run reached at `cursor.now` (the replay must reach the same).
    pub x: Vec<f64>,
    pub disc: DiscreteState,
    pub horizon: f64,
    pub cursor: Cursor,
}

impl SimState {
    /// The time the run had been advanced to.
    pub fn time(&self) -> f64 {
        self.cursor.now
    }
}

fn another_model(why: &str) -> SimError {
    SimError::Usage(format!("the state belongs to another model: {why}"))
}

impl Simulation {
    /// The whole state at the current time.
    pub fn state(&mut self) -> Result<SimState, SimError> {
        if self.stepper.reinits > 0 {
            return Err(SimError::Usage(
                "state(): a run whose speeds were set from outside (reinit) cannot be saved: its replay knows inputs and parameters only".to_string(),
            ));
        }
        let x = self.state_now()?;
        let phase = self.stepper.phase.borrow();
        Ok(SimState {
            inputs: self.input_events.clone(),
            parameters: self.parameter_changes().to_vec(),
            x,
            disc: phase.disc.clone(),
            horizon: phase.horizon,
            cursor: self.stepper.cursor(),
        })
    }

    /// Continues from a saved state of this model, exactly as the run that saved it went on.
    /// The rows recorded so far, the event log, the observer and the settings stay this run's.
    pub fn set_state(&mut self, state: &SimState) -> Result<(), SimError> {
        let sys = self.stepper.sys.clone();
        if state.x.len() != sys.state_len() || !state.disc.fits(&sys) {
            return Err(another_model("its states do not fit"));
        }
        let mut run = self.fresh()?;
        run.set_recording(false);
        run.replay(state)?;
        if run.state()? != *state {
            return Err(another_model(
                "replaying its input events does not reach it",
            ));
        }
        self.take_over(run);
        Ok(())
    }

    /// The state at the time the run was advanced to (inside the pending step, if any).
    fn state_now(&mut self) -> Result<Vec<f64>, SimError> {
        let Simulation { cell, stepper, .. } = self;
        cell.with_dependent_mut(|_, integ| with_solver!(integ, s => stepper.state_now(s)))
    }

    /// Advances a fresh run through the saved input events and parameter changes, in their
    /// order, to the saved time.
    fn replay(&mut self, state: &SimState) -> Result<(), SimError> {
        let mut tunes = state.parameters.iter().peekable();
        for (k, change) in state.inputs.iter().enumerate() {
            while let Some(tune) = tunes.next_if(|p| p.after_inputs <= k) {
                self.replay_parameters(tune)?;
            }
            let Some(input) = self.stepper.sys.inputs.get(change.input) else {
                return Err(another_model("an input it sets does not exist"));
            };
            let name = input.name.clone();
            self.advance_to(change.time)?;
            if self.stepper.now != change.time {
                return Err(another_model("its input events are out of order"));
            }
            self.set_input(&name, change.value)?;
        }
        for tune in tunes {
            self.replay_parameters(tune)?;
        }
        self.advance_to(state.cursor.now)
    }

    fn replay_parameters(&mut self, tune: &ParameterChange) -> Result<(), SimError> {
        self.advance_to(tune.time)?;
        if self.stepper.now != tune.time {
            return Err(another_model("its parameter changes are out of order"));
        }
        let values: Vec<(&str, toml::Value)> = (tune.values.iter())
            .map(|(n, v)| (n.as_str(), v.clone()))
            .collect();
        self.set_parameters(&values)
    }

    /// Becomes `run` (a replay), keeping what belongs to this session: the recorded rows and
    /// discrete states, the event log, the observer, the settings and the cancel flag.
    fn take_over(&mut self, mut run: Simulation) {
        let (mine, theirs) = (&mut self.stepper, &mut run.stepper);
        std::mem::swap(&mut mine.trajectory, &mut theirs.trajectory);
        std::mem::swap(&mut mine.discs, &mut theirs.discs);
        std::mem::swap(&mut mine.log, &mut theirs.log);
        std::mem::swap(&mut mine.observer, &mut theirs.observer);
        theirs.disc_recorded = false; // the last recorded discrete state is this run's
        theirs.recording = mine.recording;
        theirs.stop_at_events = mine.stop_at_events;
        theirs.cancel = mine.cancel.clone();
        theirs.started = mine.started;
        run.started = self.started;
        // the rows kept were computed with this session's systems up to now
        let (rows, old) = (theirs.trajectory.rows(), mine.sys.clone());
        let segments = self.take_segments();
        run.keep_segments(segments, rows, old);
        *self = run;
    }
}
