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
const S: &str = "s [m] Distance between flange and support (= flange.s - support.s) (start value)";
const V: &str = "v [m/s] Velocity of flange with respect to support (= der(s)) (start value)";

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
    /// Translational flanges (`s`, `v`, `v_ref`, `s_ref`): the same rows, MSL's other names.
    translational: bool,
    use_support: bool,
    /// Start values MSL declares (used where the kind makes them states).
    phi: InitValue,
    w: InitValue,
}

impl Motion {
    fn inputs(&self) -> Vec<&'static str> {
        match (self.kind, self.translational) {
            (Kind::Speed { .. }, false) => vec!["w_ref"],
            (Kind::Speed { .. }, true) => vec!["v_ref"],
            (Kind::Position { .. }, false) => vec!["phi_ref"],
            (Kind::Position { .. }, true) => vec!["s_ref"],
            (Kind::Accelerate, _) => vec!["a_ref"],
            (Kind::Move, _) => vec!["u[1]", "u[2]", "u[3]"],
        }
    }

    /// The names of the position and the speed variables.
    fn names(&self) -> (&'static str, &'static str) {
        match self.translational {
            true => ("s", "v"),
            false => ("phi", "w"),
        }
    }

    /// The prescribed row's parts; adds the start values the signals give.
    fn prescription(&self, b: &mut Builder, rel: &Rel) -> ModelResult<(Held, Accel)> {
        let (phi_name, w_name) = self.names();
        let input = self.inputs()[0];
        Ok(match self.kind {
            Kind::Speed { exact, w_crit } => {
                let w_ref = b.signal_in(input)?;
                b.init_angle(rel.clone(), self.phi, phi_name);
                b.init_speed_from(rel.clone(), w_ref, w_name);
                match exact {
                    true => (
                        Held::Speed(w_ref),
                        Accel::Signal(b.signal_derivative(input, 1)?),
                    ),
                    false => (Held::Nothing, Accel::FirstOrder { w_ref, w_crit }),
                }
            }
            Kind::Position { exact, w_crit } => {
                let phi_ref = b.signal_in(input)?;
                b.init_angle_from(rel.clone(), phi_ref, phi_name);
                if exact {
                    let w = b.signal_derivative(input, 1)?;
                    let a = b.signal_derivative(input, 2)?;
                    b.init_speed_from(rel.clone(), w, w_name);
                    (
                        Held::Angle {
                            phi: phi_ref,
                            w: Some(w),
                        },
                        Accel::Signal(a),
                    )
                } else {
                    b.init_speed(rel.clone(), self.w, w_name);
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
                b.init_angle(rel.clone(), self.phi, phi_name);
                b.init_speed(rel.clone(), self.w, w_name);
                (Held::Nothing, Accel::Signal(b.signal_in("a_ref")?))
            }
            Kind::Move => {
                let (phi, w) = (b.signal_in("u[1]")?, b.signal_in("u[2]")?);
                b.init_angle_from(rel.clone(), phi, phi_name);
                b.init_speed_from(rel.clone(), w, w_name);
                let held = Held::Angle { phi, w: Some(w) };
                (held, Accel::Signal(b.signal_in("u[3]")?))
            }
        })
    }

    /// MSL's variables: `phi` always; `w` and `a` are dummies (0) when the input is followed
    /// exactly (`Speed`'s `a`, `Position`'s `w` and `a`); `Move` has `phi` only.
    fn outputs(&self, b: &mut Builder, rel: &Rel) -> ModelResult<()> {
        let (phi_name, w_name) = self.names();
        b.output(phi_name, Out::Angle(rel.clone()));
        let (w, a) = match self.kind {
            Kind::Speed { exact: true, .. } => (Out::Speed(rel.clone()), Out::Const(0.0)),
            Kind::Position { exact: true, .. } => (Out::Const(0.0), Out::Const(0.0)),
            Kind::Move => (Out::Const(0.0), Out::Const(0.0)),
            _ => (Out::Speed(rel.clone()), Out::Accel(rel.clone())),
        };
        if !matches!(self.kind, Kind::Move) {
            b.output(w_name, w);
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
        let mech = with_support(&["flange"], self.use_support);
        Ports {
            translational: if self.translational {
                mech.clone()
            } else {
                vec![]
            },
            mech,
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

fn motion(
    p: &Params,
    kind: Kind,
    translational: bool,
    phi: InitValue,
    w: InitValue,
) -> ModelResult<Box<dyn Component>> {
    let use_support = match translational {
        true => p.boolean(USE_SUPPORT_T, false)?,
        false => p.boolean(USE_SUPPORT, false)?,
    };
    Ok(Box::new(Motion {
        kind,
        translational,
        use_support,
        phi,
        w,
    }))
}

const USE_SUPPORT_T: &str =
    "useSupport true: enable the support connector (else the housing is fixed at position 0)";

const UNUSED: InitValue = InitValue {
    start: 0.0,
    fixed: false,
    nominal: 1.0,
};

/// The start-value declarations of the domain: (position, speed).
fn starts(translational: bool) -> (&'static str, &'static str) {
    match translational {
        true => (S, V),
        false => (PHI, W),
    }
}

/// `Speed` of either domain (`Translational.Speed`: `v_ref`, `s`, `v`).
pub(crate) fn speed_of(p: &Params, translational: bool) -> ModelResult<Box<dyn Component>> {
    let (exact, w_crit) = exact_and_filter(p)?;
    let phi = p.init_fixed(starts(translational).0, 0.0)?;
    motion(p, Kind::Speed { exact, w_crit }, translational, phi, UNUSED)
}

/// `Position` of either domain.
pub(crate) fn position_of(p: &Params, translational: bool) -> ModelResult<Box<dyn Component>> {
    let (exact, w_crit) = exact_and_filter(p)?;
    // MSL: w(start = 0), the filter's second state (its angle starts at phi_ref)
    let w = p.init(starts(translational).1, 0.0)?;
    let kind = Kind::Position { exact, w_crit };
    motion(p, kind, translational, UNUSED, w)
}

/// `Accelerate` of either domain.
pub(crate) fn accelerate_of(p: &Params, translational: bool) -> ModelResult<Box<dyn Component>> {
    let (phi, w) = starts(translational);
    let phi = p.init_fixed(phi, 0.0)?;
    let w = p.init_fixed(w, 0.0)?;
    motion(p, Kind::Accelerate, translational, phi, w)
}

/// `Move` of either domain.
pub(crate) fn move_of(p: &Params, translational: bool) -> ModelResult<Box<dyn Component>> {
    motion(p, Kind::Move, translational, UNUSED, UNUSED)
}

fn speed(p: &Params) -> ModelResult<Box<dyn Component>> {
    speed_of(p, false)
}

fn position(p: &Params) -> ModelResult<Box<dyn Component>> {
    position_of(p, false)
}

fn accelerate(p: &Params) -> ModelResult<Box<dyn Component>> {
    accelerate_of(p, false)
}

fn move_(p: &Params) -> ModelResult<Box<dyn Component>> {
    move_of(p, false)
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
