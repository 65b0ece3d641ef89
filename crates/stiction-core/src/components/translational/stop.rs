//! `MassWithStopAndFriction`: a translational `Mass` and a SupportFriction-like element with
//! MSL's Stribeck law (`F_prop·v + F_Coulomb + F_Stribeck·exp(−fexp·|v|)`, `f0 = F_Coulomb +
//! F_Stribeck`, `f0_max = 1.001·f0`) whose start and sliding rules are gated by two hard stops;
//! reaching one is a state event whose reset (`switching::stop`) puts the mass on the stop at
//! rest. The stick/slip logic is the one `FrictionElem`.

use crate::components::friction::TRANSLATIONAL;
use crate::components::{decl::USE_HEAT_PORT, heat_port, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::lookup_table::Table1D;
use crate::model::{InitValue, Params};
use crate::switching::friction::FrictionElem;
use crate::switching::logic::Discrete;
use crate::switching::stop::StopFriction;
use crate::system::formula::Formula;
use crate::system::outputs::SwitchVar as V;
use crate::system::{Builder, Out};
use std::sync::Arc;

/// MSL: `f0_max = f0·1.001`.
const PEAK: f64 = 1.001;

struct MassWithStop {
    m: f64,
    length: f64,
    smax: f64,
    smin: f64,
    v_small: f64,
    f_prop: f64,
    f_coulomb: f64,
    f_stribeck: f64,
    fexp: f64,
    s: InitValue,
    v: InitValue,
    use_heat_port: bool,
}

impl Component for MassWithStop {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            translational: vec!["flange_a", "flange_b"],
            joins: vec![("flange_a", "flange_b")],
            offsets: vec![
                ("flange_a", -self.length / 2.0),
                ("flange_b", self.length / 2.0),
            ],
            heat: heat_port(self.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let na = b.node("flange_a")?;
        // the friction acts on flange_a's own position (a node state, no offset), so that
        // the reset puts it on the stop exactly and the stop relations see it there
        let motion = b.rel(&[("flange_a", 1.0)])?;
        let node = match motion.terms.as_slice() {
            [(node, c)] if *c == 1.0 && motion.offset == 0.0 => *node,
            _ => return Err(b.error("its flanges are held: the mass can never slide")),
        };
        b.add_mass(na, self.m);
        let mut center = motion.clone();
        center.offset += self.length / 2.0;
        b.init_angle(center.clone(), self.s, "s");
        b.init_speed(center.clone(), self.v, "v");
        let f0 = self.f_coulomb + self.f_stribeck;
        let heat = if self.use_heat_port {
            Some(b.heat_node("heatPort")?)
        } else {
            None
        };
        let k = b.add_switching(Box::new(FrictionElem {
            name: b.name().to_string(),
            rel: motion,
            mu_pos: Table1D::from_points(&[vec![0.0, f0]]),
            peak: PEAK,
            cgeo: 1.0,
            fn_max: 1.0,
            w_small: self.v_small,
            mu0: f0,
            table_name: "F_Coulomb",
            negative_beyond: f64::INFINITY,
            input: None,
            clutch_quirk: false,
            heat_node: heat,
            one_way: None,
            initial: Discrete::INITIAL,
            fade: None,
            stop: Some(Box::new(StopFriction {
                f_prop: self.f_prop,
                f_coulomb: self.f_coulomb,
                f_stribeck: self.f_stribeck,
                fexp: self.fexp,
                lower: self.smin,
                upper: self.smax - self.length,
                node,
                length: self.length,
            })),
        }));
        b.output("s", Out::Angle(center.clone()));
        b.output("v", Out::Speed(center.clone()));
        b.output("a", Out::Accel(center.clone()));
        for (name, var) in [
            (TRANSLATIONAL.tau, V::Tau),
            ("lossPower", V::LossPower),
            ("locked", V::Locked),
            ("sa", V::Sa),
            (TRANSLATIONAL.tau0, V::Tau0),
            (TRANSLATIONAL.tau0_max, V::Tau0Max),
            ("mode", V::Mode),
            ("startForward", V::StartForward),
            ("startBackward", V::StartBackward),
        ] {
            b.output(name, Out::Switch(k, var));
        }
        b.flange("flange_a", na, None)?;
        let nb = b.node("flange_b")?;
        b.flange("flange_b", nb, None)?;
        // m·a + f = flange_a.f + flange_b.f
        let inertial = Out::Scaled(Box::new(Out::Accel(center)), self.m);
        let total = Out::Formula(Arc::new(Formula::sum(vec![
            inertial,
            Out::Switch(k, V::Tau),
        ])));
        b.flange_group(&["flange_a", "flange_b"], Some(total))
    }
}

/// A force parameter that must not be negative.
fn force(p: &Params, name: &str, decl: &'static str, default: f64) -> ModelResult<f64> {
    p.at_least(name, p.real(decl, default)?, 0.0)
}

fn mass_with_stop(p: &Params) -> ModelResult<Box<dyn Component>> {
    let m = p.positive("m", p.real("m [kg] Mass", 1.0)?)?;
    let length = p.at_least(
        "L",
        p.real(
            "L [m] Length of component, from left flange to right flange (= flange_b.s - flange_a.s)",
            0.0,
        )?,
        0.0,
    )?;
    let smax = p.real("smax [m] Right stop for (right end of) sliding mass", 25.0)?;
    let smin = p.real("smin [m] Left stop for (left end of) sliding mass", -25.0)?;
    if smax < smin + length {
        return Err(p.error(
            "smax",
            format!(
                "smax = {smax} is below smin + L = {}: the mass does not fit between its stops",
                smin + length
            ),
        ));
    }
    let v_small = p.positive(
        "v_small",
        p.real(
            "v_small [m/s] Relative velocity near to zero (see model info text)",
            1e-3,
        )?,
    )?;
    let stop = MassWithStop {
        m,
        length,
        smax,
        smin,
        v_small,
        f_prop: force(
            p,
            "F_prop",
            "F_prop [N.s/m] Velocity dependent friction",
            1.0,
        )?,
        f_coulomb: force(
            p,
            "F_Coulomb",
            "F_Coulomb [N] Constant friction: Coulomb force",
            5.0,
        )?,
        f_stribeck: force(p, "F_Stribeck", "F_Stribeck [N] Stribeck effect", 10.0)?,
        fexp: force(p, "fexp", "fexp [s/m] Exponential decay", 2.0)?,
        s: p.init(
            "s [m] Absolute position of center of component (start value)",
            0.0,
        )?,
        v: p.init(
            "v [m/s] Absolute velocity of flange_a and flange_b (start value)",
            0.0,
        )?,
        use_heat_port: p.boolean(USE_HEAT_PORT, false)?,
    };
    Ok(Box::new(stop))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "Translational.MassWithStopAndFriction",
    "Modelica.Mechanics.Translational.Components.MassWithStopAndFriction",
    "Sliding mass with hard stop and Stribeck friction",
    mass_with_stop,
)];
