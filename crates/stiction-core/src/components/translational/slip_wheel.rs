//! `SlipWheel`: stiction's own component, not MSL's (MSL's `IdealRollingWheel` never slips). A
//! wheel whose contact with the road is a Coulomb friction element between the rim speed
//! `R·(flangeR.w − supportR.w)` and the vehicle speed `flangeT.v − supportT.v`: rolling is the
//! element stuck, skidding (a locked wheel under over-braking) or spinning is it sliding. The
//! element is the Brake's and Clutch's own `FrictionElem` (MSL's `PartialFriction` logic) on a
//! relative speed that mixes the two domains, so lock-up is an ordinary stick/slip event.

use crate::components::friction::friction_table;
use crate::components::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::lookup_table::Table1D;
use crate::model::Params;
use crate::switching::friction::FrictionElem;
use crate::switching::logic::Discrete;
use crate::system::outputs::SwitchVar as V;
use crate::system::{Builder, Out};

struct SlipWheel {
    radius: f64,
    mu_pos: Table1D,
    peak: f64,
    /// The constant normal force; None: the signal input `fN`.
    fn_constant: Option<f64>,
    w_small: f64,
    use_support_r: bool,
    use_support_t: bool,
}

impl Component for SlipWheel {
    fn ports(&self) -> Ports {
        let mut mech = vec!["flangeR", "flangeT"];
        let mut translational = vec!["flangeT"];
        if self.use_support_r {
            mech.push("supportR");
        }
        if self.use_support_t {
            mech.push("supportT");
            translational.push("supportT");
        }
        Ports {
            must_connect: vec!["flangeR", "flangeT"],
            mech,
            translational,
            signal_in: match self.fn_constant {
                None => vec!["fN"],
                Some(_) => vec![],
            },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let r = self.radius;
        // v_slip = R·(flangeR.w − supportR.w) − (flangeT.v − supportT.v): > 0 spinning, < 0
        // skidding; an undeclared support is the implicit ground (the road, the hub at rest)
        let rel = b.rel(&[
            ("flangeR", r),
            ("supportR", -r),
            ("flangeT", -1.0),
            ("supportT", 1.0),
        ])?;
        if rel.is_zero() {
            return Err(b.error("its rim and its road are rigidly connected: it can never slip"));
        }
        // f_normalized·fn_max·cgeo with the input as fn (fn_max = cgeo = 1), or, with no input,
        // the constant as cgeo (the element then reads fn ≡ 1 and is never free)
        let (input, cgeo) = match self.fn_constant {
            None => (Some(b.signal_in("fN")?), 1.0),
            Some(f) => (None, f),
        };
        let k = b.add_switching(Box::new(FrictionElem {
            name: b.name().to_string(),
            rel: rel.clone(),
            mu0: self.mu_pos.eval(0.0),
            table_name: "mu_pos",
            negative_beyond: self.mu_pos.zero_beyond_last(),
            mu_pos: self.mu_pos.clone(),
            peak: self.peak,
            cgeo,
            fn_max: 1.0,
            w_small: self.w_small,
            input,
            clutch_quirk: false,
            heat_node: None,
            one_way: None,
            initial: Discrete::INITIAL,
            stop: None,
            fade: None,
        }));
        outputs(b, k, input, self.fn_constant);
        // the element's force f acts on the vehicle (+f) and brakes the wheel (−R·f); a flange
        // reports what the connection applies to the component, the opposite
        let f = |scale: f64| Some(Out::Scaled(Box::new(Out::Switch(k, V::Tau)), scale));
        let (nr, nt) = (b.node("flangeR")?, b.node("flangeT")?);
        b.flange("flangeR", nr, f(r))?;
        b.flange("flangeT", nt, f(-1.0))?;
        if self.use_support_r {
            let n = b.node("supportR")?;
            b.flange("supportR", n, f(-r))?;
        }
        if self.use_support_t {
            let n = b.node("supportT")?;
            b.flange("supportT", n, f(1.0))?;
        }
        Ok(())
    }
}

/// The contact's variables: the friction element's, named for a force and a slip speed.
fn outputs(b: &mut Builder, k: usize, input: Option<usize>, fn_constant: Option<f64>) {
    b.output(
        "fN",
        match (input, fn_constant) {
            (Some(slot), _) => Out::Signal(slot),
            (None, f) => Out::Const(f.unwrap_or(0.0)),
        },
    );
    if input.is_some() {
        b.output("free", Out::Switch(k, V::Free));
    }
    for (name, var) in [
        ("v_slip", V::W),
        ("a_slip", V::A),
        ("f", V::Tau),
        ("mu", V::Mu),
        ("lossPower", V::LossPower),
        ("locked", V::Locked),
        ("sa", V::Sa),
        ("f0", V::Tau0),
        ("f0_max", V::Tau0Max),
        ("mode", V::Mode),
        ("startForward", V::StartForward),
        ("startBackward", V::StartBackward),
    ] {
        b.output(name, Out::Switch(k, var));
    }
}

const USE_INPUT: &str = "useNormalForceInput true: the normal force is the signal input fN \
     (the vehicle's weight share, a load transfer); false: the constant fNConstant";

fn slip_wheel(p: &Params) -> ModelResult<Box<dyn Component>> {
    let radius = p.positive("radius", p.real("radius [m] Wheel radius", 0.3)?)?;
    let mu_pos = friction_table(
        p,
        "mu_pos [m/s, 1] Tyre-road sliding friction coefficient over the magnitude of the slip speed R*w - v: \
         rows [v_slip, mu] for v_slip >= 0, linear between rows; beyond the last row as \
         `extrapolation` says",
        &[&[0.0, 0.8]],
        "coefficients",
    )?;
    let peak = p.at_least(
        "peak",
        p.real(
            "peak [1] Peak for maximum friction force at v_slip = 0: f0_max = peak*f0",
            1.0,
        )?,
        1.0,
    )?;
    let use_input = p.boolean(USE_INPUT, false)?;
    // declared either way, as MSL's Vehicle declares CrConstant beside its input cr
    let fn_constant = p.real(
        "fNConstant [N] Normal force of the road on the wheel, when useNormalForceInput = false \
         (the default: a 400 kg quarter car, 400*9.81)",
        3924.0,
    )?;
    let fn_constant = match use_input {
        true => None,
        false => Some(p.positive("fNConstant", fn_constant)?),
    };
    Ok(Box::new(SlipWheel {
        radius,
        mu_pos,
        peak,
        fn_constant,
        w_small: p.positive(
            "v_small",
            p.real(
                "v_small [m/s] Slip speed above which a speed jump reverses sliding directly",
                1.0e10,
            )?,
        )?,
        use_support_r: p.boolean(
            "useSupportR true: enable the rotational support connector (the hub; else fixed at angle 0)",
            false,
        )?,
        use_support_t: p.boolean(
            "useSupportT true: enable the translational support connector (the road; else fixed at position 0)",
            false,
        )?,
    }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "SlipWheel",
    "stiction.SlipWheel",
    // stiction's own: the class says so, and the docs and help() from it
    "Wheel whose road contact is Coulomb friction (rolling = stuck, skidding = sliding)",
    slip_wheel,
)];
