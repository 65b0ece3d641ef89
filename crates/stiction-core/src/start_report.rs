//! The initialization report: every start value of a model, whether it was fixed (an initial
//! equation), a guess the initialization kept, or computed from the other equations (a guess
//! it had to override), with the value the run starts from.

use crate::error::ModelError;
use crate::simulation::initial_state_and_guesses;
use crate::system::System;

/// How a start value entered the initial state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// `fixed = true`: an initial equation the state satisfies.
    Fixed,
    /// `fixed = false` and the initialization kept the guess.
    Guessed,
    /// `fixed = false` and other equations determined the value (the guess was not used).
    Computed,
}

impl Status {
    /// `"fixed"`, `"guessed"` or `"computed"`.
    pub fn label(self) -> &'static str {
        match self {
            Status::Fixed => "fixed",
            Status::Guessed => "guessed",
            Status::Computed => "computed",
        }
    }
}

/// One start value: the variable (`J.w`), its start attribute, its status and initial value.
#[derive(Debug, Clone, PartialEq)]
pub struct StartValue {
    pub variable: String,
    pub start: f64,
    pub status: Status,
    pub value: f64,
}

/// Every start value of the assembled model, in model order (angles, speeds, temperatures).
///
/// A guess is reported used when the initialization kept it as an equation (its row was
/// independent of the fixed rows and the guesses before it): one initialization, so the report
/// costs what the initialization costs, linear in the model.
pub fn report(sys: &System) -> Result<Vec<StartValue>, ModelError> {
    let init = initial_state_and_guesses(sys)?;
    let n = sys.nodes;
    let (phi, w) = (&init.x[..n], &init.x[n..2 * n]);
    let angles = sys.init_phi.iter().zip(&init.phi_guess_used);
    let angles = angles.map(|(eq, &used)| (eq, used, eq.rel.angle(phi)));
    let speeds = sys.init_w.iter().zip(&init.w_guess_used);
    let speeds = speeds.map(|(eq, &used)| (eq, used, eq.rel.dot(w)));
    let mut out: Vec<StartValue> = angles
        .chain(speeds)
        .filter(|(eq, _, _)| !eq.constraint)
        .map(|(eq, used, value)| StartValue {
            variable: eq.variable.clone(),
            start: eq.value.start,
            status: match (eq.value.fixed, used) {
                (true, _) => Status::Fixed,
                (false, true) => Status::Guessed,
                (false, false) => Status::Computed,
            },
            value,
        })
        .collect();
    for cap in &sys.thermal.capacities {
        // a HeatCapacitor's connector is `port`; its temperature is `T`
        let ports = &sys.thermal.node_ports[cap.node];
        let port = ports
            .iter()
            .find(|p| p.ends_with(".port"))
            .or(ports.first());
        let variable = port.map_or("heat capacity".into(), |p| {
            p.strip_suffix(".port")
                .map_or(p.clone(), |c| format!("{c}.T"))
        });
        out.push(entry(
            &variable,
            cap.init.start,
            cap.init.fixed,
            cap.init.start,
        ));
    }
    Ok(out)
}

/// A heat capacity's temperature starts at its start value, fixed or not.
fn entry(variable: &str, start: f64, fixed: bool, value: f64) -> StartValue {
    let status = if fixed {
        Status::Fixed
    } else {
        Status::Guessed
    };
    StartValue {
        variable: variable.to_string(),
        start,
        status,
        value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::assemble;
    use crate::model::ModelSpec;

    /// J (w fixed at 10) and J2 (w guessed 3) joined by a clutch whose w_rel guess (1) the
    /// others override: w_rel = 3 − 10.
    const TWO_SHAFTS: &str = r#"
        name = "two_shafts"
        connect = [["J.flange_b", "c.flange_a"], ["c.flange_b", "J2.flange_a"], ["f.y", "c.f_normalized"]]
        [components]
        J = { type = "Inertia", J = 2.0, w = 10.0 }
        J2 = { type = "Inertia", J = 1.0, w = { start = 3.0, fixed = false } }
        c = { type = "Clutch", fn_max = 10.0, w_rel = { start = 1.0, fixed = false } }
        f = { type = "Constant", k = 0.0 }
    "#;

    #[test]
    fn start_values_are_fixed_guessed_or_computed() {
        let sys = assemble(&ModelSpec::from_toml(TWO_SHAFTS, ".").unwrap()).unwrap();
        let report = report(&sys).unwrap();
        let find = |v: &str| report.iter().find(|s| s.variable == v).unwrap().clone();
        assert_eq!(
            (find("J.w").status, find("J.w").value),
            (Status::Fixed, 10.0)
        );
        assert_eq!(
            (find("J2.w").status, find("J2.w").value),
            (Status::Guessed, 3.0)
        );
        let w_rel = find("c.w_rel");
        assert_eq!((w_rel.status, w_rel.start), (Status::Computed, 1.0));
        assert!((w_rel.value + 7.0).abs() < 1e-12);
    }
}
