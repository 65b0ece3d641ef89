//! MSL's prescribed-motion sources (`Sources.Speed`, `Position`, `Accelerate`, `Move`): the
//! flange moves relative to the support as input signals say, whatever torque that takes. Each
//! is one prescribed row (`system::Prescribed`) whose multiplier is the torque the source
//! delivers, so its work closes the energy audit as ConstantSpeed's does.
//!
//! `exact = true` follows the input exactly, which needs its time derivatives (MSL: the tool
//! differentiates the input): they come from the signal blocks' exact derivatives
//! (`signals::derivatives`), and an input without them (a model input) is refused by name.
//! `exact = false` filters the input, the filter's states being the flange's angle and speed.

use super::decl::USE_SUPPORT;
use super::{with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Accel, Builder, Held, NodeRef, Out, Prescribed, Rel};

const EXACT: &str =
    "exact true: follow the input signal exactly (needs its time derivatives), false: filter it";
const F_CRIT: &str =
    "f_crit [Hz] If exact=false, critical frequency of filter to filter input signal";
const PHI: &str = "phi [rad] Rotation angle of flange with respect to support (start value)";
const W: &str = "w [rad/s] Angular velocity of flange with respect to support (start value)";

/// MSL `Position`'s filter: the s and s² coefficients of its critically damped filter.
const AF: f64 = 1.3617;
const BF: f64 = 0.6180;

#[derive(Clone, Copy)]
enum Kind {
    Speed { exact: bool, w_crit: f64 },
    Position { exact: bool, w_crit: f64 },
    Accelerate,
    Move,
}

struct Motion {
    kind: Kind,
    use_support: bool,
    /// Start values MSL declares (used where the kind makes them states).
    phi: InitValue,
    w: InitValue,
}

impl Motion {
    fn inputs(&self) -> Vec<&'static str> {
        match self.kind {
            Kind::Speed { .. } => vec!["w_ref"],
            Kind::Position { .. } => vec!["phi_ref"],
            Kind::Accelerate => vec!["a_ref"],
            Kind::Move => vec!["u[1]", "u[2]", "u[3]"],
        }
    }

    /// The prescribed row's parts; adds the start values the signals give.
    fn prescription(&self, b: &mut Builder, rel: &Rel) -> ModelResult<(Held, Accel)> {
        Ok(match self.kind {
            Kind::Speed { exact, w_crit } => {
                let w_ref = b.signal_in("w_ref")?;
                b.init_angle(rel.clone(), self.phi, "phi");
                b.init_speed_from(rel.clone(), w_ref, "w");
                match exact {
                    true => (
                        Held::Speed(w_ref),
                        Accel::Signal(b.signal_derivative("w_ref", 1)?),
                    ),
                    false => (Held::Nothing, Accel::FirstOrder { w_ref, w_crit }),
                }
            }
            Kind::Position { exact, w_crit } => {
                let phi_ref = b.signal_in("phi_ref")?;
                b.init_angle_from(rel.clone(), phi_ref, "phi");
                if exact {
                    let w = b.signal_derivative("phi_ref", 1)?;
                    let a = b.signal_derivative("phi_ref", 2)?;
                    b.init_speed_from(rel.clone(), w, "w");
                    (
                        Held::Angle {
                            phi: phi_ref,
                            w: Some(w),
                        },
                        Accel::Signal(a),
                    )
                } else {
                    b.init_speed(rel.clone(), self.w, "w");
                    let filter = Accel::SecondOrder {
                        phi_ref,
                        w_crit,
                        af: AF,
                        bf: BF,
                    };
                    (Held::Nothing, filter)
                }
            }
            Kind::Accelerate => {
                b.init_angle(rel.clone(), self.phi, "phi");
                b.init_speed(rel.clone(), self.w, "w");
                (Held::Nothing, Accel::Signal(b.signal_in("a_ref")?))
            }
            Kind::Move => {
                let (phi, w) = (b.signal_in("u[1]")?, b.signal_in("u[2]")?);
                b.init_angle_from(rel.clone(), phi, "phi");
                b.init_speed_from(rel.clone(), w, "w");
                let held = Held::Angle { phi, w: Some(w) };
                (held, Accel::Signal(b.signal_in("u[3]")?))
            }
        })
    }

    /// MSL's variables: `phi` always; `w` and `a` are dummies (0) when the input is followed
    /// exactly (`Speed`'s `a`, `Position`'s `w` and `a`); `Move` has `phi` only.
    fn outputs(&self, b: &mut Builder, rel: &Rel) -> ModelResult<()> {
        b.output("phi", Out::Angle(rel.clone()));
        let (w, a) = match self.kind {
            Kind::Speed { exact: true, .. } => (Out::Speed(rel.clone()), Out::Const(0.0)),
            Kind::Position { exact: true, .. } => (Out::Const(0.0), Out::Const(0.0)),
            Kind::Move => (Out::Const(0.0), Out::Const(0.0)),
            _ => (Out::Speed(rel.clone()), Out::Accel(rel.clone())),
        };
        if !matches!(self.kind, Kind::Move) {
            b.output("w", w);
            b.output("a", a);
        }
        for port in self.inputs() {
            let slot = b.signal_in(port)?;
            b.output(port, Out::Signal(slot));
        }
        Ok(())
    }
}

impl Component for Motion {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange"], self.use_support),
            signal_in: self.inputs(),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nf, ns) = (b.node("flange")?, b.node("support")?);
        let node = match (nf, ns) {
            (NodeRef::Node(i), _) | (_, NodeRef::Node(i)) => i,
            _ => {
                return Err(b.error(
                    "port 'flange': held by ground like its support, so no motion can be \
                     prescribed to it",
                ))
            }
        };
        let rel = Rel::of(&[(nf, 1.0), (ns, -1.0)]);
        let (held, accel) = self.prescription(b, &rel)?;
        let k = b.add_prescribed(rel.clone(), Prescribed { node, held, accel })?;
        self.outputs(b, &rel)?;
        b.flange("flange", nf, Some(Out::ConstraintTau(k, 1.0)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::ConstraintTau(k, -1.0)))?;
        }
        Ok(())
    }
}

/// `exact` and the filter's critical frequency `w_crit = 2π·f_crit`.
fn exact_and_filter(p: &Params) -> ModelResult<(bool, f64)> {
    let exact = p.boolean(EXACT, false)?;
    let f_crit = p.positive("f_crit", p.real(F_CRIT, 50.0)?)?;
    Ok((exact, 2.0 * std::f64::consts::PI * f_crit))
}

fn motion(p: &Params, kind: Kind, phi: InitValue, w: InitValue) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Motion {
        kind,
        use_support: p.boolean(USE_SUPPORT, false)?,
        phi,
        w,
    }))
}

const UNUSED: InitValue = InitValue {
    start: 0.0,
    fixed: false,
    nominal: 1.0,
};

fn speed(p: &Params) -> ModelResult<Box<dyn Component>> {
    let (exact, w_crit) = exact_and_filter(p)?;
    let phi = p.init_fixed(PHI, 0.0)?;
    motion(p, Kind::Speed { exact, w_crit }, phi, UNUSED)
}

fn position(p: &Params) -> ModelResult<Box<dyn Component>> {
    let (exact, w_crit) = exact_and_filter(p)?;
    // MSL: w(start = 0), the filter's second state (its angle starts at phi_ref)
    let w = p.init(W, 0.0)?;
    motion(p, Kind::Position { exact, w_crit }, UNUSED, w)
}

fn accelerate(p: &Params) -> ModelResult<Box<dyn Component>> {
    let phi = p.init_fixed(PHI, 0.0)?;
    let w = p.init_fixed(W, 0.0)?;
    motion(p, Kind::Accelerate, phi, w)
}

fn move_(p: &Params) -> ModelResult<Box<dyn Component>> {
    motion(p, Kind::Move, UNUSED, UNUSED)
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Speed",
        "Modelica.Mechanics.Rotational.Sources.Speed",
        "Forced movement of a flange according to a reference angular velocity signal",
        speed,
    ),
    Entry::new(
        "Position",
        "Modelica.Mechanics.Rotational.Sources.Position",
        "Forced movement of a flange according to a reference angle signal",
        position,
    ),
    Entry::new(
        "Accelerate",
        "Modelica.Mechanics.Rotational.Sources.Accelerate",
        "Forced movement of a flange according to an acceleration signal",
        accelerate,
    ),
    Entry::new(
        "Move",
        "Modelica.Mechanics.Rotational.Sources.Move",
        "Forced movement of a flange according to an angle, speed and angular acceleration signal",
        move_,
    ),
];
