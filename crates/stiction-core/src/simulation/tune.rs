//! Tunable parameters: new values for some parameters of a running simulation, without a new
//! assembly of the model. A change is an event at the current time, as a model input's jump
//! is (`set_input`): the integrator goes back to now, the left row is recorded with the old
//! values, the system with the new ones takes over, the event iteration finds the modes it
//! gives, the right row follows and the integrator restarts.
//!
//! The new system is the compiled model's variant (`CompiledModel::with`: only the changed
//! components are created anew). What a run has planned or reached must stay as it is, so a
//! parameter that fixes a position or a time event is refused by name
//! (`ParamInfo::fixed_because`), and the variant is compared with the running system: the same
//! states, elements, relations, inputs, outputs, time events and shafts without inertia.
//! Factorizations depend on inertias, gear rows and, for shafts without inertia, on
//! stiffnesses and dampings: the mode cache starts anew.

use std::sync::Arc;

use diffsol::OdeSolverMethod;

use super::integrator::{with_solver, Eqn};
use super::stepper::{max_step, EventKind, Stepper};
use super::Simulation;
use crate::assembly::CompiledModel;
use crate::engine::eval::Workspace;
use crate::engine::ModeCache;
use crate::error::{ModelError, SimError};
use crate::model::split_last;
use crate::system::System;

/// Parameters set to new values at `time`, after the first `after_inputs` input events of
/// the run (a saved state replays both lists in that order).
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterChange {
    pub time: f64,
    pub after_inputs: usize,
    /// `component.parameter` and the value as the model file writes it.
    pub values: Vec<(String, toml::Value)>,
}

/// The model a run was made from, the variant in force now and the changes between them.
pub(super) struct Tuning {
    pub(super) base: CompiledModel,
    current: CompiledModel,
    pub(super) changes: Vec<ParameterChange>,
    /// The system of the recorded rows below each index (`SimResult::with_earlier_systems`).
    pub(super) segments: Vec<(usize, Arc<System>)>,
}

impl Tuning {
    pub(super) fn new(model: CompiledModel) -> Self {
        Tuning {
            base: model.clone(),
            current: model,
            changes: Vec::new(),
            segments: Vec::new(),
        }
    }
}

impl Simulation {
    /// Sets one tunable Real parameter (`brake.fn_max`) from the current time on.
    pub fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), SimError> {
        self.set_parameters(&[(name, toml::Value::Float(value))])
    }

    /// Sets tunable parameters (`component.parameter`, the value as the model file writes it:
    /// a number, a table) from the current time on, all at one event. A fixed parameter, an
    /// unknown name or a value out of range is refused with an error naming the component
    /// and the parameter, and the run goes on unchanged; values equal to the ones in force
    /// change nothing.
    pub fn set_parameters(&mut self, changes: &[(&str, toml::Value)]) -> Result<(), SimError> {
        let Some(variant) = self.checked_variant(changes)? else {
            return Ok(());
        };
        let (sys, old) = (variant.system(), self.stepper.sys.clone());
        let cause = describe(changes);
        let Simulation { cell, stepper, .. } = self;
        let boundary = cell.with_dependent_mut(|_, integ| {
            let (order, implicit) = (integ.order(), integ.implicit());
            with_solver!(integ, s => stepper.retune(s, sys, &cause, order, implicit))
        })?;
        let record = ParameterChange {
            time: self.stepper.now,
            after_inputs: self.input_events.len(),
            values: (changes.iter())
                .map(|(n, v)| (n.to_string(), v.clone()))
                .collect(),
        };
        if let Some(tuning) = self.tuning.as_mut() {
            tuning.current = variant;
            tuning.changes.push(record);
            if boundary > 0 {
                tuning.segments.push((boundary, old));
            }
        }
        Ok(())
    }

    /// The variant of the model in force with `changes`, each checked to be tunable, in
    /// range and to keep the running structure; None if it changes no value.
    fn checked_variant(
        &self,
        changes: &[(&str, toml::Value)],
    ) -> Result<Option<CompiledModel>, SimError> {
        let Some(tuning) = self.tuning.as_ref() else {
            return Err(SimError::Usage(
                "this run was made from an assembled system: make it from a model (Simulation::from_model) to change parameters".into(),
            ));
        };
        for (name, _) in changes {
            tuning.current.check_tunable(name)?;
        }
        let variant = tuning.current.with(changes)?;
        let params = |m: &CompiledModel| -> Vec<toml::Table> {
            (m.spec().components.iter())
                .map(|c| c.params.clone())
                .collect()
        };
        if params(&variant) == params(&tuning.current) {
            return Ok(None);
        }
        let (old, new) = (&self.stepper.sys, variant.system());
        same_structure(&tuning.current, old, &new, changes)?;
        Ok(Some(variant))
    }

    /// A fresh run of the model this one was made from (its parameters before any change).
    pub(super) fn fresh(&self) -> Result<Simulation, SimError> {
        match &self.tuning {
            Some(tuning) => Simulation::from_model(tuning.base.clone()),
            None => Simulation::new(self.stepper.sys.clone()),
        }
    }

    /// The systems of the recorded rows so far (a restored run takes them over).
    pub(super) fn take_segments(&mut self) -> Vec<(usize, Arc<System>)> {
        (self.tuning.as_mut()).map_or(Vec::new(), |t| std::mem::take(&mut t.segments))
    }

    /// Takes over the rows another run recorded: `segments`, and `rows` computed with `old`
    /// if that is not this run's system.
    pub(super) fn keep_segments(
        &mut self,
        mut segments: Vec<(usize, Arc<System>)>,
        rows: usize,
        old: Arc<System>,
    ) {
        if rows > 0 && !Arc::ptr_eq(&old, &self.stepper.sys) {
            segments.push((rows, old));
        }
        if let Some(tuning) = self.tuning.as_mut() {
            tuning.segments = segments;
        }
    }

    /// The parameter changes so far, in order.
    pub fn parameter_changes(&self) -> &[ParameterChange] {
        self.tuning.as_ref().map_or(&[], |t| &t.changes)
    }
}

/// The event's cause in the log: `parameter brake.fn_max set to 200`.
fn describe(changes: &[(&str, toml::Value)]) -> String {
    let each: Vec<String> = (changes.iter())
        .map(|(n, v)| format!("{n} set to {v}"))
        .collect();
    let plural = if changes.len() > 1 { "s" } else { "" };
    format!("parameter{plural} {}", each.join(", "))
}

/// Refuses a variant whose structure differs from the running system's, naming the first
/// parameter set (a change of one parameter names it exactly).
fn same_structure(
    model: &CompiledModel,
    old: &System,
    new: &System,
    changes: &[(&str, toml::Value)],
) -> Result<(), SimError> {
    let massless = |s: &System| s.mass.iter().map(|&m| m == 0.0).collect::<Vec<_>>();
    let differs = if old.time_events != new.time_events {
        Some("it moves the time events the run has planned")
    } else if massless(old) != massless(new) {
        Some("it gives a shaft inertia or takes it away (J = 0 makes its speed algebraic)")
    } else if old.state_len() != new.state_len()
        || old.switching.len() != new.switching.len()
        || old.relation_count != new.relation_count
        || old.inputs.len() != new.inputs.len()
        || old.outputs.len() != new.outputs.len()
        || old.constraints.len() != new.constraints.len()
    {
        Some("it changes the structure of the compiled model")
    } else {
        None
    };
    let Some(why) = differs else {
        return Ok(());
    };
    let name = changes.first().map_or("", |(n, _)| *n);
    let (component, parameter) = split_last(name).unwrap_or((name, ""));
    let type_name = (model.spec().components.iter())
        .find(|c| c.name == component)
        .map_or(String::new(), |c| c.type_name.clone());
    Err(ModelError::Parameter {
        component: component.to_string(),
        type_name,
        parameter: parameter.to_string(),
        message: format!("cannot change in a running simulation: {why}"),
    }
    .into())
}

impl Stepper {
    /// The event of a parameter change at the current time: back to now (a pending step is
    /// dropped), the left row with the old parameters, `sys` takes over, the event iteration,
    /// the right row, the integrator restarted. Returns the number of rows recorded with the
    /// old parameters.
    // Alike in shape only (the signature of every method over the solver), not in logic.
    fn retune<'a, S>(
        &mut self,
        solver: &mut S,
        sys: Arc<System>,
        cause: &str,
        order: usize,
        implicit: bool,
    ) -> Result<usize, SimError>
    where
        S: OdeSolverMethod<'a, Eqn>,
    {
        let t = self.back_to_now(solver)?;
        self.skip_grid_at(t);
        if self.last_row != t {
            self.record_here(t);
        }
        let boundary = self.trajectory.rows();
        self.swap_system(sys);
        let horizon = self.phase.borrow().horizon;
        self.handle_event(t, horizon, EventKind::Parameter, cause)?;
        if !self.finished {
            self.restart(solver, t, order, implicit)?;
        }
        Ok(boundary)
    }

    /// Makes `sys` the system of the run: the right-hand side's, the factorizations' (anew)
    /// and the step limit's (a Sine's frequency sets it).
    fn swap_system(&mut self, sys: Arc<System>) {
        let factorizations = self.cache.factorizations;
        self.cache = ModeCache::default();
        self.cache.factorizations = factorizations;
        self.max_step = max_step(&sys);
        let mut phase = self.phase.borrow_mut();
        phase.ws = Workspace::new(&sys);
        phase.rhs_stamp = usize::MAX; // the new workspace counts its evaluations from 0
        phase.scratch = None;
        phase.f0_t = f64::NAN;
        phase.sys = sys.clone();
        drop(phase);
        self.guard.renew(&sys);
        self.sys = sys;
    }
}
