//! One FMU instance: the compiled model, the values of its parameters and inputs, and (from
//! the end of initialization) the running `Simulation`. Pure Rust: every operation returns
//! `Result<_, String>`; `fmi2.rs` turns an error into a logged `fmi2Error`.

use std::path::Path;

use stiction_core::{CompiledModel, ModelSpec, Simulation};

use crate::layout::{resource_dir, Kind, Layout};
use crate::snapshot::{fingerprint, Experiment, Fallible, Snapshot};
use crate::values::{bind, overrides, setting, settings_of, Var};

/// The FMI 2.0 Co-Simulation state machine, as far as a caller can tell states apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    Initialization,
    Step,
    Terminated,
    /// After an error in `doStep`: only reset, terminate or free are allowed.
    Failed,
}

pub struct Instance {
    model: CompiledModel,
    vars: Vec<Var>,
    pub mode: Mode,
    start_time: Option<f64>,
    stop_time: Option<f64>,
    tolerance: Option<f64>,
    sim: Option<Simulation>,
    /// The variables' values the run was built with (tunable parameters set in step mode
    /// change `vars`, not these).
    base: Vec<Vec<f64>>,
    /// What a serialized state must carry to be restored here (`snapshot::fingerprint`).
    pub fingerprint: String,
    /// FMI 3.0 `earlyReturnAllowed`: `doStep` stops at the first friction event in the step.
    pub early_return: bool,
    /// Whether the last `doStep` stopped at such an event before its end.
    pub returned_early: bool,
}

/// What a set-up variable is, in messages.
fn what(kind: Kind) -> &'static str {
    match kind {
        Kind::Start { .. } | Kind::FlagStart => "the start value of",
        Kind::Element { .. } => "table element",
        _ => "parameter",
    }
}

fn read(dir: &Path, file: &str) -> Fallible<String> {
    std::fs::read_to_string(dir.join(file))
        .map_err(|e| format!("cannot read {}: {e}", dir.join(file).display()))
}

impl Instance {
    /// Loads `model.toml` and `variables.tsv` from the resource folder the URI names.
    pub fn load(resource_uri: &str, guid: &str) -> Fallible<Self> {
        let dir = resource_dir(resource_uri)?;
        let layout = Layout::parse(&read(&dir, "variables.tsv")?)?;
        if layout.guid != guid {
            return Err(format!(
                "GUID {guid} does not match the FMU's resources ({})",
                layout.guid
            ));
        }
        let spec =
            ModelSpec::from_toml(&read(&dir, "model.toml")?, &dir).map_err(|e| e.to_string())?;
        let model = CompiledModel::new(spec).map_err(|e| e.to_string())?;
        let vars = bind(layout, &model)?;
        Ok(Instance {
            model,
            vars,
            mode: Mode::Instantiated,
            start_time: None,
            stop_time: None,
            tolerance: None,
            sim: None,
            base: Vec::new(),
            fingerprint: fingerprint(guid),
            early_return: false,
            returned_early: false,
        })
    }

    pub fn setup_experiment(
        &mut self,
        tol: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Fallible<()> {
        self.expect(&[Mode::Instantiated], "setupExperiment")?;
        if !start.is_finite() || stop.is_some_and(|s| s.is_nan() || s <= start) {
            return Err(format!("setupExperiment: bad interval [{start}, {stop:?}]"));
        }
        (self.start_time, self.stop_time, self.tolerance) = (Some(start), stop, tol);
        Ok(())
    }

    fn expect(&self, modes: &[Mode], call: &str) -> Fallible<()> {
        if modes.contains(&self.mode) {
            return Ok(());
        }
        Err(format!("{call} is not allowed in state {:?}", self.mode))
    }

    pub fn enter_initialization(&mut self) -> Fallible<()> {
        self.expect(&[Mode::Instantiated], "enterInitializationMode")?;
        self.mode = Mode::Initialization;
        Ok(())
    }

    pub fn exit_initialization(&mut self) -> Fallible<()> {
        self.expect(&[Mode::Initialization], "exitInitializationMode")?;
        self.ensure_sim()?;
        self.mode = Mode::Step;
        Ok(())
    }

    /// The model variant with the parameters and experiment settings set so far.
    fn variant(&self) -> Fallible<CompiledModel> {
        let set = overrides(&self.vars);
        let mut overrides: Vec<(&str, toml::Value)> =
            set.iter().map(|(n, v)| (n.as_str(), v.clone())).collect();
        let experiment = [
            ("StartTime", self.start_time),
            ("StopTime", self.stop_time),
            ("Tolerance", self.tolerance),
        ];
        for (name, value) in experiment {
            overrides.extend(value.map(|v| (name, toml::Value::Float(v))));
        }
        self.model.with(&overrides).map_err(|e| e.to_string())
    }

    /// Builds the run from the current parameters and inputs, once.
    fn ensure_sim(&mut self) -> Fallible<&mut Simulation> {
        if self.sim.is_none() {
            let mut sim = Simulation::from_model(self.variant()?).map_err(|e| e.to_string())?;
            sim.set_recording(false);
            sim.set_stop_at_events(self.early_return);
            for v in self.vars.iter().filter(|v| v.kind == Kind::Input) {
                sim.set_input(&v.name, v.value[0])
                    .map_err(|e| e.to_string())?;
            }
            self.sim = Some(sim);
            self.base = self.vars.iter().map(|v| v.value.clone()).collect();
        }
        Ok(self.sim.as_mut().expect("built above"))
    }

    fn var(&self, vr: u32) -> Fallible<&Var> {
        self.vars
            .get(vr as usize)
            .ok_or(format!("unknown value reference {vr}"))
    }

    /// The variables `vrs` of the FMI type `boolean` or Real, each checked.
    fn typed(&self, vrs: &[u32], boolean: bool) -> Fallible<Vec<&Var>> {
        let what = if boolean { "Boolean" } else { "Real (Float64)" };
        (vrs.iter())
            .map(|&vr| match self.var(vr)? {
                v if v.kind.is_boolean() == boolean => Ok(v),
                v => Err(format!(
                    "{} (value reference {vr}) is not a {what} variable",
                    v.name
                )),
            })
            .collect()
    }

    /// The values of `vrs` (a table: all its elements, row after row) into `out`, which
    /// holds exactly as many; Booleans as 0 or 1.
    pub fn get_values(&mut self, vrs: &[u32], boolean: bool, out: &mut [f64]) -> Fallible<()> {
        let vars = self.typed(vrs, boolean)?;
        let size: usize = vars.iter().map(|v| v.kind.size()).sum();
        if size != out.len() {
            return Err(format!(
                "{} values asked for, the variables hold {size}",
                out.len()
            ));
        }
        let row = match vars.iter().any(|v| v.is_computed()) {
            true => self.ensure_sim()?.values().map_err(|e| e.to_string())?,
            false => Vec::new(),
        };
        let mut at = 0;
        for &vr in vrs {
            let v = self.var(vr)?; // checked above
            let n = v.kind.size();
            match v.is_computed() {
                true => out[at] = row[v.column],
                false => out[at..at + n].copy_from_slice(&v.value),
            }
            at += n;
        }
        Ok(())
    }

    /// Sets `vrs` from `values` (a table takes all its elements, row after row; its shape is
    /// the FMU's). The types and the count are checked before anything is set.
    pub fn set_values(&mut self, vrs: &[u32], boolean: bool, values: &[f64]) -> Fallible<()> {
        let vars = self.typed(vrs, boolean)?;
        let size: usize = vars.iter().map(|v| v.kind.size()).sum();
        if size != values.len() {
            let shapes: Vec<String> = (vars.iter())
                .filter_map(|v| match v.kind {
                    Kind::Table { rows, cols } => Some(format!("{} is {rows}×{cols}", v.name)),
                    _ => None,
                })
                .collect();
            return Err(format!(
                "{} values given for {size} (a table's shape is fixed in the FMU{}{})",
                values.len(),
                if shapes.is_empty() { "" } else { ": " },
                shapes.join(", ")
            ));
        }
        if self.mode == Mode::Step && vars.iter().any(|v| v.kind.is_setup()) {
            return self.tune(vrs, values);
        }
        let mut at = 0;
        for &vr in vrs {
            let n = self.var(vr)?.kind.size();
            self.set_value(vr, &values[at..at + n])?;
            at += n;
        }
        Ok(())
    }

    /// Step mode: the tunable parameters among `vrs` change together, at one event at the
    /// communication point (a table's FMI 2.0 elements with it); inputs follow, each its
    /// event. A fixed parameter refuses the whole call and changes nothing.
    fn tune(&mut self, vrs: &[u32], values: &[f64]) -> Fallible<()> {
        let mut next: Vec<Vec<f64>> = self.vars.iter().map(|v| v.value.clone()).collect();
        let mut parameters: Vec<String> = Vec::new();
        let mut at = 0;
        for &vr in vrs {
            let v = self.var(vr)?;
            let value = &values[at..at + v.kind.size()];
            at += v.kind.size();
            if let Some(bad) = value.iter().find(|x| !x.is_finite()) {
                return Err(format!("{}: {bad} is not a finite number", v.name));
            }
            match v.kind {
                Kind::Output | Kind::Independent => {
                    return Err(format!(
                        "{} is computed by the FMU: it cannot be set",
                        v.name
                    ))
                }
                Kind::Input => {}
                _ => {
                    let parameter = v.parameter().to_string();
                    if let Err(e) = self.model.check_tunable(&parameter) {
                        return Err(format!(
                            "setting {} {} is not allowed in state Step: {e}",
                            what(v.kind),
                            v.name
                        ));
                    }
                    if !parameters.contains(&parameter) {
                        parameters.push(parameter);
                    }
                }
            }
            next[vr as usize] = value.to_vec();
        }
        let settings = settings_of(&self.vars, &next, &parameters);
        let sim = self.sim.as_mut().expect("a run exists in step mode");
        let set: Vec<(&str, toml::Value)> = settings
            .iter()
            .map(|(n, v)| (n.as_str(), v.clone()))
            .collect();
        sim.set_parameters(&set).map_err(|e| e.to_string())?;
        for &vr in vrs {
            let v = &self.vars[vr as usize];
            if v.kind == Kind::Input {
                sim.set_input(&v.name, next[vr as usize][0])
                    .map_err(|e| e.to_string())?;
            }
            self.vars[vr as usize].value.clone_from(&next[vr as usize]);
        }
        Ok(())
    }

    fn set_value(&mut self, vr: u32, value: &[f64]) -> Fallible<()> {
        let (kind, name) = (self.var(vr)?.kind, self.var(vr)?.name.clone());
        let settable = [Mode::Instantiated, Mode::Initialization, Mode::Step];
        self.expect(&settable, &format!("setting {name}"))?;
        if let Some(bad) = value.iter().find(|v| !v.is_finite()) {
            return Err(format!("{name}: {bad} is not a finite number"));
        }
        match kind {
            Kind::Output | Kind::Independent => {
                return Err(format!("{name} is computed by the FMU: it cannot be set"))
            }
            Kind::Input if self.mode == Mode::Step => {
                let sim = self.sim.as_mut().expect("a run exists in step mode");
                sim.set_input(&name, value[0]).map_err(|e| e.to_string())?;
            }
            Kind::Input => self.sim = None,
            _ => self.set_parameter(&name, kind, value)?,
        }
        self.vars[vr as usize].value = value.to_vec();
        Ok(())
    }

    /// Parameters and start values are set before the end of initialization; a value is
    /// checked at once.
    fn set_parameter(&mut self, name: &str, kind: Kind, value: &[f64]) -> Fallible<()> {
        let allowed = [Mode::Instantiated, Mode::Initialization];
        self.expect(&allowed, &format!("setting {} {name}", what(kind)))?;
        // an element is checked with its table at the end of initialization: one element at
        // a time, a table passes through shapes the model refuses (x no longer increasing)
        if let Some(setting) = setting(kind, value) {
            (self.model.with(&[(name, setting)])).map_err(|e| e.to_string())?;
        }
        self.sim = None;
        Ok(())
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> Fallible<()> {
        self.expect(&[Mode::Step], "doStep")?;
        let sim = self.sim.as_mut().expect("a run exists in step mode");
        let now = sim.time();
        if !h.is_finite() || h < 0.0 {
            return Err(format!(
                "doStep: the step size {h} must be a finite number ≥ 0"
            ));
        }
        let within = (t - now).abs() <= 1e-9 * now.abs().max(1.0);
        if !within || t.is_nan() {
            return Err(format!(
                "doStep: currentCommunicationPoint {t} is not the FMU's time {now}"
            ));
        }
        let target = now.max(t + h);
        let outcome = sim.advance_to(target).map_err(|e| e.to_string());
        let stop = sim.system().experiment.stop_time;
        self.returned_early = outcome.is_ok() && sim.time() < target.min(stop);
        if outcome.is_err() {
            self.mode = Mode::Failed;
        }
        outcome
    }

    pub fn time(&self) -> Option<f64> {
        self.sim.as_ref().map(|s| s.time())
    }

    pub fn terminate(&mut self) -> Fallible<()> {
        self.expect(&[Mode::Step, Mode::Failed], "terminate")?;
        // the run stays until reset or free: FMI 2.0 lets the host read the final values
        self.mode = Mode::Terminated;
        Ok(())
    }

    /// Back to the state after instantiation: default values, no run.
    pub fn reset(&mut self) {
        for v in &mut self.vars {
            v.value.clone_from(&v.start);
        }
        (self.start_time, self.stop_time, self.tolerance) = (None, None, None);
        self.sim = None;
        self.mode = Mode::Instantiated;
    }

    fn experiment(&self) -> Experiment {
        Experiment {
            start: self.start_time,
            stop: self.stop_time,
            tolerance: self.tolerance,
        }
    }

    pub fn snapshot(&mut self) -> Fallible<Snapshot> {
        self.expect(&[Mode::Step], "getFMUstate")?;
        let experiment = self.experiment();
        let sim = self.sim.as_mut().expect("a run exists in step mode");
        Ok(Snapshot {
            sim: sim.state().map_err(|e| e.to_string())?,
            values: self.vars.iter().map(|v| v.value.clone()).collect(),
            base: self.base.clone(),
            experiment,
        })
    }

    /// Continues from a saved state, in step mode. An instance not yet initialized, or set up
    /// with other parameters or experiment settings (a state deserialized into a new instance),
    /// first builds its run from the state's.
    pub fn restore(&mut self, snap: &Snapshot) -> Fallible<()> {
        let allowed = [
            Mode::Instantiated,
            Mode::Initialization,
            Mode::Step,
            Mode::Terminated,
            Mode::Failed,
        ];
        self.expect(&allowed, "setFMUstate")?;
        let fits = |values: &[Vec<f64>]| {
            values.len() == self.vars.len()
                && (self.vars.iter().zip(values)).all(|(v, s)| s.len() == v.kind.size())
        };
        if !fits(&snap.values) || !fits(&snap.base) {
            return Err("the FMU state belongs to another model".into());
        }
        let bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        // the run this instance has was built from `self.base`; the state's from `snap.base`
        let same_setup = self.sim.is_some()
            && self.experiment() == snap.experiment
            && (self.vars.iter().zip(&self.base).zip(&snap.base))
                .all(|((v, mine), saved)| !v.kind.is_setup() || bits(mine, saved));
        if !same_setup || self.mode == Mode::Failed {
            for (v, value) in self.vars.iter_mut().zip(&snap.base) {
                v.value.clone_from(value);
            }
            let e = snap.experiment;
            (self.start_time, self.stop_time, self.tolerance) = (e.start, e.stop, e.tolerance);
            self.sim = None;
        }
        let sim = self.ensure_sim()?;
        sim.set_state(&snap.sim).map_err(|e| e.to_string())?;
        for (v, value) in self.vars.iter_mut().zip(&snap.values) {
            v.value.clone_from(value);
        }
        self.mode = Mode::Step;
        Ok(())
    }
}
