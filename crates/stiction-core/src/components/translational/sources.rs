//! Translational sources: a force on `flange` with the reaction on `support` (implicitly
//! grounded unless `useSupport`). The force laws are the rotational sources' own
//! (`components::sources::SourceLaw`): one implementation acts as a torque or as a force.

use crate::components::eddy_current::{eddy_current, Decls};
use crate::components::sources::{regularization, Kind, SourceLaw};
use crate::components::torque2::Torque2;
use crate::components::{with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out};

const USE_SUPPORT: &str =
    "useSupport true: enable the support connector (else the housing is fixed at position 0)";

struct ForceSource {
    kind: Kind,
    use_support: bool,
    /// `Force`: the input signal `f` is the accelerating force (`flange.f = -f`); the others
    /// report MSL's `PartialForce.f = flange.f`, the opposite sign.
    input: bool,
    /// `ForceStep`'s step instant.
    events: Vec<f64>,
}

impl Component for ForceSource {
    fn ports(&self) -> Ports {
        let mech = with_support(&["flange"], self.use_support);
        Ports {
            translational: mech.clone(),
            mech,
            signal_in: if self.input { vec!["f"] } else { vec![] },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nf, ns) = (b.node("flange")?, b.node("support")?);
        let rel = b.rel(&[("flange", 1.0), ("support", -1.0)])?;
        let kind = match self.kind {
            Kind::Input(_) => Kind::Input(b.signal_in("f")?),
            k => k,
        };
        // the law's force along flange − support is −(accelerating force) = flange.f
        let law = b.add_law(rel.clone(), Box::new(SourceLaw(kind)));
        let sign = if self.input { -1.0 } else { 1.0 };
        b.output("f", Out::LawTau(law, sign));
        b.output("s", Out::Angle(rel.clone()));
        b.output("v", Out::Speed(rel));
        b.flange("flange", nf, Some(Out::LawTau(law, 1.0)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::LawTau(law, -1.0)))?;
        }
        Ok(())
    }

    fn time_events(&self, _from: f64, _until: f64) -> Vec<f64> {
        self.events.clone()
    }
}

fn source(p: &Params, kind: Kind, input: bool) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(ForceSource {
        kind,
        use_support: p.boolean(USE_SUPPORT, false)?,
        input,
        events: vec![],
    }))
}

fn force(p: &Params) -> ModelResult<Box<dyn Component>> {
    source(p, Kind::Input(0), true)
}

fn constant_force(p: &Params) -> ModelResult<Box<dyn Component>> {
    let f = p.required(
        "f_constant [N] Nominal force (negative: acting as load in positive direction of motion)",
    )?;
    source(p, Kind::Constant(f), false)
}

/// The linear or the quadratic speed-dependent force, parameters in MSL's order.
fn speed_dependent(p: &Params, quadratic: bool) -> ModelResult<Box<dyn Component>> {
    let tau_nominal = p.required(
        "f_nominal [N] Nominal force (negative: acting as load in positive direction of motion)",
    )?;
    let direction = p.boolean(
        "ForceDirection true: same direction of force in both directions of motion",
        true,
    )?;
    let w_nominal = p.positive("v_nominal", p.required("v_nominal [m/s] Nominal speed")?)?;
    let kind = match quadratic {
        false => Kind::Linear {
            tau_nominal,
            direction,
            w_nominal,
        },
        true => Kind::Quadratic {
            tau_nominal,
            direction,
            w_nominal,
        },
    };
    source(p, kind, false)
}

fn linear(p: &Params) -> ModelResult<Box<dyn Component>> {
    speed_dependent(p, false)
}

fn quadratic(p: &Params) -> ModelResult<Box<dyn Component>> {
    speed_dependent(p, true)
}

fn force2(_: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Torque2 {
        translational: true,
    }))
}

fn force_step(p: &Params) -> ModelResult<Box<dyn Component>> {
    let start = p.real("startTime [s] Time of the force step", 0.0)?;
    let kind = Kind::Step {
        step: p.real(
            "stepForce [N] Height of the force step (negative: acting as load in positive direction of motion)",
            1.0,
        )?,
        offset: p.real("offsetForce [N] Offset of the force", 0.0)?,
        start,
    };
    Ok(Box::new(ForceSource {
        kind,
        use_support: p.boolean(USE_SUPPORT, false)?,
        input: false,
        events: vec![start],
    }))
}

fn sign_force(p: &Params) -> ModelResult<Box<dyn Component>> {
    let reg = regularization(p)?;
    let kind = Kind::Sign {
        tau_nominal: p.required(
            "f_nominal [N] Nominal force (negative: acting as load in positive direction of motion)",
        )?,
        reg,
        w0: p.positive("v0", p.real("v0 [m/s] Regularization below v0", 0.1)?)?,
    };
    source(p, kind, false)
}

const EDDY: Decls = Decls {
    use_input: "useF_nominalInput true: signal input f_input for f_nominal",
    nominal: "f_nominal [N] Constant maximum force (always braking)",
    speed: (
        "v_nominal",
        "v_nominal [m/s] Nominal speed (leads to maximum force) at reference temperature",
    ),
    use_support: USE_SUPPORT,
};

fn eddy_current_force(p: &Params) -> ModelResult<Box<dyn Component>> {
    eddy_current(p, &EDDY, true)
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.Force2",
        "Modelica.Mechanics.Translational.Sources.Force2",
        "Input signal acting as torque on two flanges",
        force2,
    ),
    Entry::new(
        "Translational.ForceStep",
        "Modelica.Mechanics.Translational.Sources.ForceStep",
        "Constant force, not dependent on speed",
        force_step,
    ),
    Entry::new(
        "Translational.SignForce",
        "Modelica.Mechanics.Translational.Sources.SignForce",
        "Constant force changing sign with speed",
        sign_force,
    ),
    Entry::new(
        "Translational.EddyCurrentForce",
        "Modelica.Mechanics.Translational.Sources.EddyCurrentForce",
        "Simple model of a translational eddy current brake",
        eddy_current_force,
    ),
    Entry::new(
        "Translational.Force",
        "Modelica.Mechanics.Translational.Sources.Force",
        "External force acting on a drive train element as input signal",
        force,
    ),
    Entry::new(
        "Translational.ConstantForce",
        "Modelica.Mechanics.Translational.Sources.ConstantForce",
        "Constant force, not dependent on speed",
        constant_force,
    ),
    Entry::new(
        "Translational.LinearSpeedDependentForce",
        "Modelica.Mechanics.Translational.Sources.LinearSpeedDependentForce",
        "Linear dependency of force versus speed",
        linear,
    ),
    Entry::new(
        "Translational.QuadraticSpeedDependentForce",
        "Modelica.Mechanics.Translational.Sources.QuadraticSpeedDependentForce",
        "Quadratic dependency of force versus speed",
        quadratic,
    ),
];
