//! Rotational sources (spec §6.1): a torque on `flange` with the reaction on `support`
//! (implicitly grounded unless `useSupport`), and `ConstantSpeed`, a prescribed speed.

use super::decl::USE_SUPPORT;
use super::{with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::signals::reached;
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out, Rel};

// (visible to the translational sources: one law serves a torque and a force)
#[derive(Clone, Copy)]
pub(super) enum Kind {
    /// Input signal `tau`.
    Input(usize),
    Constant(f64),
    Step {
        step: f64,
        offset: f64,
        start: f64,
    },
    Linear {
        tau_nominal: f64,
        direction: bool,
        w_nominal: f64,
    },
    Quadratic {
        tau_nominal: f64,
        direction: bool,
        w_nominal: f64,
    },
    Sign {
        tau_nominal: f64,
        reg: Reg,
        w0: f64,
    },
    Inverse {
        tau_nominal: f64,
        direction: bool,
        w_nominal: f64,
        w0: f64,
    },
}

#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Reg {
    Exp,
    Sine,
    Linear,
    CoSine,
}

/// MSL's `Regularization` of `sign(w)` below `w0` (SignTorque's, RollingResistance's);
/// `outside` is the frozen relation `|w| >= w0` (Exp has none).
pub(crate) fn regularized_sign(reg: Reg, w: f64, w0: f64, outside: bool) -> f64 {
    match reg {
        Reg::Exp => 2.0 / (1.0 + (-w / (0.01 * w0)).exp()) - 1.0,
        _ if outside => w.signum(),
        Reg::Sine => (std::f64::consts::FRAC_PI_2 * w / w0).sin(),
        Reg::Linear => w / w0,
        Reg::CoSine => w.signum() * (1.0 - (std::f64::consts::FRAC_PI_2 * w / w0).cos()),
    }
}

/// The regularization parameter `reg`, as MSL's `Modelica.Blocks.Types.Regularization`.
pub(crate) fn regularization(p: &Params) -> ModelResult<Reg> {
    let choice = p.choice(
        "reg Type of regularization: Exp, Sine, Linear or CoSine",
        &["Exp", "Sine", "Linear", "CoSine"],
        "Exp",
    )?;
    Ok(match choice.as_str() {
        "Sine" => Reg::Sine,
        "Linear" => Reg::Linear,
        "CoSine" => Reg::CoSine,
        _ => Reg::Exp,
    })
}

/// The accelerating torque `tau` of the source; the element torque along `flange − support` is −tau.
pub(super) struct SourceLaw(pub(super) Kind);

impl SourceLaw {
    fn accelerating(&self, x: &LawCtx) -> f64 {
        let w = x.w_rel;
        match self.0 {
            Kind::Input(slot) => x.signals[slot],
            Kind::Constant(tau) => tau,
            Kind::Step {
                step,
                offset,
                start,
            } => {
                offset
                    + if reached(x.t, start, x.horizon) {
                        step
                    } else {
                        0.0
                    }
            }
            Kind::Linear {
                tau_nominal,
                direction,
                w_nominal,
            } => {
                if direction {
                    tau_nominal * (w / w_nominal).abs()
                } else {
                    tau_nominal * w / w_nominal
                }
            }
            Kind::Quadratic {
                tau_nominal,
                direction,
                w_nominal,
            } => {
                if direction {
                    tau_nominal * (w / w_nominal).powi(2)
                } else {
                    // smooth(1, …): no event at w = 0
                    tau_nominal * w * w.abs() / (w_nominal * w_nominal)
                }
            }
            Kind::Sign {
                tau_nominal,
                reg,
                w0,
            } => {
                let outside = x.relations.first().copied().unwrap_or(false); // |w| >= w0
                tau_nominal * regularized_sign(reg, w, w0, outside)
            }
            Kind::Inverse {
                tau_nominal,
                direction,
                w_nominal,
                w0,
            } => {
                let inside = x.relations.first().copied().unwrap_or(false); // |w| < w0
                match (direction, inside) {
                    (true, true) => tau_nominal * w_nominal / w0,
                    (true, false) => tau_nominal * w_nominal / w.abs(),
                    (false, true) => tau_nominal * w / w0,
                    (false, false) => tau_nominal * w_nominal / w,
                }
            }
        }
    }
}

impl ForceLaw for SourceLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        -self.accelerating(x)
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Source
    }
    fn relation_count(&self) -> usize {
        match self.0 {
            Kind::Sign { reg, .. } if reg != Reg::Exp => 1,
            Kind::Inverse { .. } => 1,
            _ => 0,
        }
    }
    fn relation_values(&self, x: &LawCtx, z: &mut [f64]) {
        match self.0 {
            Kind::Sign { w0, .. } => z[0] = x.w_rel.abs() - w0,
            Kind::Inverse { w0, .. } => z[0] = w0 - x.w_rel.abs(),
            _ => {}
        }
    }
    fn relation_label(&self, _i: usize) -> &'static str {
        "|w| crossed w0"
    }
}

struct TorqueSource {
    kind: Kind,
    use_support: bool,
    input: bool,
    events: Vec<f64>,
}

impl Component for TorqueSource {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange"], self.use_support),
            signal_in: if self.input { vec!["tau"] } else { vec![] },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nf, ns) = (b.node("flange")?, b.node("support")?);
        let rel = Rel::of(&[(nf, 1.0), (ns, -1.0)]);
        let kind = match self.kind {
            Kind::Input(_) => Kind::Input(b.signal_in("tau")?),
            k => k,
        };
        let law = b.add_law(rel.clone(), Box::new(SourceLaw(kind)));
        b.output("tau", Out::LawTau(law, -1.0));
        b.output("phi", Out::Angle(rel.clone()));
        b.output("w", Out::Speed(rel));
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

fn source(
    p: &Params,
    kind: Kind,
    input: bool,
    events: Vec<f64>,
) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(TorqueSource {
        kind,
        use_support: p.boolean(USE_SUPPORT, false)?,
        input,
        events,
    }))
}

fn torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    source(p, Kind::Input(0), true, vec![])
}

fn constant_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    source(
        p,
        Kind::Constant(
            p.required("tau_constant [N.m] Constant torque (negative: acting as load)")?,
        ),
        false,
        vec![],
    )
}

fn torque_step(p: &Params) -> ModelResult<Box<dyn Component>> {
    let start = p.real("startTime [s] Time of the torque step", 0.0)?;
    let kind = Kind::Step {
        step: p.real(
            "stepTorque [N.m] Height of the torque step (negative: acting as load)",
            1.0,
        )?,
        offset: p.real("offsetTorque [N.m] Offset of the torque", 0.0)?,
        start,
    };
    source(p, kind, false, vec![start])
}

fn w_nominal(p: &Params) -> ModelResult<f64> {
    p.positive("w_nominal", p.required("w_nominal [rad/s] Nominal speed")?)
}

/// The linear or the quadratic speed-dependent torque: the same parameters, in the order MSL
/// declares them (`tau_nominal`, `TorqueDirection`, `w_nominal`).
fn speed_dependent(p: &Params, quadratic: bool) -> ModelResult<Box<dyn Component>> {
    let tau_nominal = p.required("tau_nominal [N.m] Nominal torque (negative: acting as load)")?;
    let direction = p.boolean(
        "TorqueDirection true: same direction of torque in both directions of rotation",
        true,
    )?;
    let w_nominal = w_nominal(p)?;
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
    source(p, kind, false, vec![])
}

fn linear(p: &Params) -> ModelResult<Box<dyn Component>> {
    speed_dependent(p, false)
}

fn quadratic(p: &Params) -> ModelResult<Box<dyn Component>> {
    speed_dependent(p, true)
}

fn sign(p: &Params) -> ModelResult<Box<dyn Component>> {
    let reg = regularization(p)?;
    let kind = Kind::Sign {
        tau_nominal: p.required("tau_nominal [N.m] Nominal torque (negative: acting as load)")?,
        reg,
        w0: p.positive("w0", p.real("w0 [rad/s] Regularization below w0", 0.1)?)?,
    };
    source(p, kind, false, vec![])
}

fn inverse(p: &Params) -> ModelResult<Box<dyn Component>> {
    let kind = Kind::Inverse {
        tau_nominal: p.required("tau_nominal [N.m] Nominal torque (negative: acting as load)")?,
        direction: p.boolean(
            "TorqueDirection true: same direction of torque in both directions of rotation",
            true,
        )?,
        w_nominal: w_nominal(p)?,
        w0: p.positive("w0", p.real("w0 [rad/s] Regularization below w0", 0.1)?)?,
    };
    source(p, kind, false, vec![])
}

/// Prescribed speed `w = w_fixed` relative to the support: a permanent acceleration constraint
/// whose multiplier is the torque the source must deliver.
struct ConstantSpeed {
    w_fixed: f64,
    phi: InitValue,
    use_support: bool,
}

impl Component for ConstantSpeed {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange"], self.use_support),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nf, ns) = (b.node("flange")?, b.node("support")?);
        let rel = Rel::of(&[(nf, 1.0), (ns, -1.0)]);
        let k = b.add_constraint(rel.clone(), true)?;
        let fixed_speed = InitValue::fixed(self.w_fixed);
        b.init_speed(rel.clone(), fixed_speed, "w");
        b.init_angle(rel.clone(), self.phi, "phi");
        b.output("tau", Out::ConstraintTau(k, -1.0));
        b.output("phi", Out::Angle(rel.clone()));
        b.output("w", Out::Speed(rel));
        // Alike in shape to `Source::build` (flange and support outputs), over a constraint's
        // multiplier instead of a law's torque.
        b.flange("flange", nf, Some(Out::ConstraintTau(k, 1.0)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::ConstraintTau(k, -1.0)))?;
        }
        Ok(())
    }
}

fn constant_speed(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(ConstantSpeed {
        w_fixed: p.required("w_fixed [rad/s] Fixed speed of the flange relative to the support")?,
        phi: p.init(
            "phi [rad] Angle of the flange relative to the support (start value)",
            0.0,
        )?,
        use_support: p.boolean(USE_SUPPORT, false)?,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Torque",
        "Modelica.Mechanics.Rotational.Sources.Torque",
        "Input signal acting as external torque on a flange",
        torque,
    ),
    Entry::new(
        "ConstantTorque",
        "Modelica.Mechanics.Rotational.Sources.ConstantTorque",
        "Constant torque, not dependent on speed",
        constant_torque,
    ),
    Entry::new(
        "TorqueStep",
        "Modelica.Mechanics.Rotational.Sources.TorqueStep",
        "Constant torque, not dependent on speed, starting at a given time",
        torque_step,
    ),
    Entry::new(
        "LinearSpeedDependentTorque",
        "Modelica.Mechanics.Rotational.Sources.LinearSpeedDependentTorque",
        "Linear dependency of torque versus speed",
        linear,
    ),
    Entry::new(
        "QuadraticSpeedDependentTorque",
        "Modelica.Mechanics.Rotational.Sources.QuadraticSpeedDependentTorque",
        "Quadratic dependency of torque versus speed",
        quadratic,
    ),
    Entry::new(
        "SignTorque",
        "Modelica.Mechanics.Rotational.Sources.SignTorque",
        "Constant torque changing direction with speed (regularized)",
        sign,
    ),
    Entry::new(
        "InverseSpeedDependentTorque",
        "Modelica.Mechanics.Rotational.Sources.InverseSpeedDependentTorque",
        "Torque inversely proportional to speed (constant power)",
        inverse,
    ),
    Entry::new(
        "ConstantSpeed",
        "Modelica.Mechanics.Rotational.Sources.ConstantSpeed",
        "Constant speed, not dependent on torque",
        constant_speed,
    ),
];
