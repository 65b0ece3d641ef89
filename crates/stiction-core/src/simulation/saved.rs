//! Saving and restoring a run. A restored run restarts the integrator at the saved time, so it
//! agrees with the uninterrupted run to the solver's tolerance; what it does from there depends
//! only on the saved state, never on where the run stood when it was restored: the same state
//! restored in this run later, in a fresh run of the same model or after `reset` continues
//! bit for bit alike (an FMU's serialized state relies on it).

use diffsol::OdeSolverMethod;

use super::integrator::{solver_for, with_solver};
use super::{Cursor, Simulation};
use crate::engine::eval::DiscreteState;
use crate::error::SimError;

/// What of the integrator the continuation depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverState {
    /// The step size when saved: the restart's first step is no longer than it (`restart_at`).
    pub h: f64,
    /// Whether the method is the implicit one (an "auto" run may have changed to it).
    pub implicit: bool,
    /// The stiffness check's window of explicit steps ("auto"): steps counted, their span, and
    /// whether a change of method is due.
    pub window_steps: usize,
    pub window_span: f64,
    pub switch_due: bool,
}

/// The whole state of a run at its current time: enough to continue from it later.
#[derive(Debug, Clone, PartialEq)]
pub struct SimState {
    pub x: Vec<f64>,
    pub disc: DiscreteState,
    pub horizon: f64,
    pub cursor: Cursor,
    pub solver: SolverState,
}

impl Simulation {
    /// The whole state at the current time.
    pub fn state(&mut self) -> Result<SimState, SimError> {
        let Simulation { cell, stepper, .. } = self;
        let (x, h, implicit) = cell.with_dependent_mut(|_, integ| {
            let implicit = integ.implicit();
            with_solver!(integ, s => Ok::<_, SimError>((stepper.state_now(s)?, s.state().h, implicit)))
        })?;
        let phase = stepper.phase.borrow();
        let watch = &stepper.stiffness;
        Ok(SimState {
            x,
            disc: phase.disc.clone(),
            horizon: phase.horizon,
            cursor: stepper.cursor(),
            solver: SolverState {
                h,
                implicit,
                window_steps: watch.steps,
                window_span: watch.span,
                switch_due: watch.switch_due,
            },
        })
    }

    /// Continues from a saved state (of this model): the integrator restarts there.
    pub fn set_state(&mut self, state: &SimState) -> Result<(), SimError> {
        let sys = self.stepper.sys.clone();
        if state.x.len() != sys.state_len() || !state.disc.fits(&sys) {
            return Err(SimError::Usage("the state belongs to another model".into()));
        }
        self.renew_integrator(state.solver.implicit)?;
        let t = state.cursor.now;
        let mm = self.stepper.cache.get(&sys, &state.disc, t)?;
        {
            let mut phase = self.stepper.phase.borrow_mut();
            phase.disc = state.disc.clone();
            phase.f0_t = f64::NAN;
            phase.horizon = state.horizon;
            phase.mm = mm;
        }
        let Simulation { cell, stepper, .. } = self;
        stepper.x.copy_from_slice(&state.x);
        stepper.set_cursor(&state.cursor);
        stepper.evaluate_here(t, true);
        stepper.z_prev.copy_from_slice(&stepper.z);
        stepper.dz.fill(f64::NAN);
        stepper.hump_back = None; // a sample of the run before the restore
        let watch = &mut stepper.stiffness;
        (watch.steps, watch.span) = (state.solver.window_steps, state.solver.window_span);
        watch.switch_due = state.solver.switch_due;
        if stepper.finished {
            return Ok(());
        }
        cell.with_dependent_mut(|_, integ| {
            let (order, implicit) = (integ.order(), integ.implicit());
            with_solver!(integ, s => {
                *s.state_mut().h = state.solver.h; // what `restart_at` takes as the step so far
                stepper.restart_at(s, t, order, implicit, false)
            })
        })
    }

    /// A new integrator of the saved state's method: an "auto" run changes method (either
    /// way) if it must; another run's method is fixed, so a state of the other kind belongs to
    /// another model. New even where the method is the same: an implicit method keeps its
    /// factored iteration matrix across a restart, and a restored run must not depend on it.
    fn renew_integrator(&mut self, implicit: bool) -> Result<(), SimError> {
        let Simulation { cell, stepper, .. } = self;
        let auto = stepper.sys.experiment.solver == "auto";
        if !auto && cell.with_dependent(|_, integ| integ.implicit()) != implicit {
            return Err(SimError::Usage(
                "the state was saved with another integration method".into(),
            ));
        }
        let method = match (auto, implicit) {
            (true, true) => "esdirk34",
            (true, false) => "tsit45",
            (false, _) => stepper.sys.experiment.solver.as_str(),
        };
        cell.with_dependent_mut(|problem, integ| {
            with_solver!(integ, s => stepper.stiffness.retired.add(s.get_statistics()));
            *integ = solver_for(problem, method)?;
            stepper.fit_steps = integ.polynomial_dense_output();
            stepper.stiffness.active = auto && !implicit;
            Ok(())
        })
    }
}
