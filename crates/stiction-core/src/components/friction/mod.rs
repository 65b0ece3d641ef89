//! Coulomb friction elements with MSL's stick/slip logic: `Brake` (shaft against its housing)
//! and `Clutch` (between two shafts). Both share `FrictionElem`; the Boolean logic is in `logic`.

pub mod logic;

use logic::Discrete;

use super::{Component, Constructor, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::outputs::FrictionVar as V;
use crate::system::{Builder, Out, Rel};
use crate::table::Table1D;

/// One friction element as the engine sees it.
pub struct FrictionElem {
    pub name: String,
    /// `w_relfric = rel·w`.
    pub rel: Rel,
    pub mu_pos: Table1D,
    pub peak: f64,
    pub cgeo: f64,
    pub fn_max: f64,
    pub w_small: f64,
    /// `mu0 = T(0)`.
    pub mu0: f64,
    /// Signal slot of `f_normalized`.
    pub input: usize,
    /// Clutch reads the table at `+w_rel` while starting backward (spec §5.2).
    pub clutch_quirk: bool,
    pub heat_node: Option<usize>,
}

/// The discrete state of a friction element between events (its relations frozen).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrictionState {
    pub pre: Discrete,
    pub locked: bool,
    pub free: bool,
}

impl FrictionState {
    pub const INITIAL: FrictionState = FrictionState {
        pre: Discrete::INITIAL,
        locked: false,
        free: true,
    };
}

impl FrictionElem {
    pub fn normal_force(&self, f_normalized: f64) -> f64 {
        self.fn_max * f_normalized
    }

    /// `(tau0, tau0_max)` for a normal force.
    pub fn limits(&self, fn_: f64) -> (f64, f64) {
        let tau0 = self.mu0 * self.cgeo * fn_;
        (tau0, self.peak * tau0)
    }

    /// `mu` and the sliding torque `mu·cgeo·fn` with the sign pair of (sf, sb, pre(mode)).
    pub fn sliding(&self, w: f64, fn_: f64, pre_mode: i8, sf: bool, sb: bool) -> (f64, f64) {
        let (s_w, s_mu) = logic::table_signs(sf, sb, pre_mode, self.clutch_quirk);
        let mu = s_mu * self.mu_pos.eval(s_w * w);
        (mu, mu * self.cgeo * fn_)
    }
}

struct FrictionParams {
    mu_pos: Table1D,
    peak: f64,
    cgeo: f64,
    fn_max: f64,
    w_small: f64,
    use_heat_port: bool,
}

fn read_params(p: &Params) -> ModelResult<FrictionParams> {
    let mu_pos = Table1D::from_param(p, "mu_pos", &[&[0.0, 0.5]])?;
    let peak = p.at_least("peak", p.real("peak", 1.0)?, 1.0)?;
    Ok(FrictionParams {
        mu_pos,
        peak,
        cgeo: p.at_least("cgeo", p.real("cgeo", 1.0)?, 0.0)?,
        fn_max: p.at_least("fn_max", p.required("fn_max")?, 0.0)?,
        w_small: p.positive("w_small", p.real("w_small", 1.0e10)?)?,
        use_heat_port: p.boolean("useHeatPort", false)?,
    })
}

/// Outputs every friction element reports (MSL names), plus its heat port.
fn friction_outputs(b: &mut Builder, k: usize, slot: usize, heat: Option<usize>) {
    for (name, var) in [
        ("tau", V::Tau),
        ("mu", V::Mu),
        ("fn", V::Fn),
        ("lossPower", V::LossPower),
        ("mode", V::Mode),
        ("locked", V::Locked),
        ("startForward", V::StartForward),
        ("startBackward", V::StartBackward),
        ("free", V::Free),
        ("sa", V::Sa),
        ("tau0", V::Tau0),
        ("tau0_max", V::Tau0Max),
    ] {
        b.output(name, Out::Friction(k, var));
    }
    b.output("f_normalized", Out::Signal(slot));
    if let Some(node) = heat {
        b.output("heatPort.T", Out::HeatT(node));
        b.output(
            "heatPort.Q_flow",
            Out::Scaled(Box::new(Out::Friction(k, V::LossPower)), -1.0),
        );
    }
}

struct Brake {
    p: FrictionParams,
    use_support: bool,
}

impl Component for Brake {
    fn ports(&self) -> Ports {
        let mut mech = vec!["flange_a", "flange_b"];
        if self.use_support {
            mech.push("support");
        }
        Ports {
            mech,
            joins: vec![("flange_a", "flange_b")],
            signal_in: vec!["f_normalized"],
            heat: if self.p.use_heat_port {
                vec!["heatPort"]
            } else {
                vec![]
            },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, ns) = (b.node("flange_a")?, b.node("support")?);
        let rel = Rel::of(&[(na, 1.0), (ns, -1.0)]);
        if rel.is_zero() {
            return Err(
                b.error("its flange is rigidly connected to its support: it can never slip")
            );
        }
        let k = add_elem(b, &self.p, rel.clone(), false)?;
        b.output("phi", Out::Angle(rel));
        b.output("w", Out::Friction(k, V::W));
        b.output("a", Out::Friction(k, V::A));
        b.flange("flange_a", na, None)?;
        b.flange("flange_b", na, None)?;
        // flange_a.tau + flange_b.tau = tau; support.tau = −tau
        b.flange_group(&["flange_a", "flange_b"], Some(Out::Friction(k, V::Tau)))?;
        if self.use_support {
            b.flange(
                "support",
                ns,
                Some(Out::Scaled(Box::new(Out::Friction(k, V::Tau)), -1.0)),
            )?;
        }
        Ok(())
    }
}

fn add_elem(
    b: &mut Builder,
    p: &FrictionParams,
    rel: Rel,
    clutch_quirk: bool,
) -> ModelResult<usize> {
    let slot = b.signal_in("f_normalized")?;
    let heat = if p.use_heat_port {
        Some(b.heat_node("heatPort")?)
    } else {
        None
    };
    let k = b.add_friction(FrictionElem {
        name: b.name().to_string(),
        rel,
        mu0: p.mu_pos.eval(0.0),
        mu_pos: p.mu_pos.clone(),
        peak: p.peak,
        cgeo: p.cgeo,
        fn_max: p.fn_max,
        w_small: p.w_small,
        input: slot,
        clutch_quirk,
        heat_node: heat,
    });
    friction_outputs(b, k, slot, heat);
    Ok(k)
}

fn brake(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Brake {
        p: read_params(p)?,
        use_support: p.boolean("useSupport", false)?,
    }))
}

struct Clutch {
    p: FrictionParams,
    phi_rel: InitValue,
    w_rel: InitValue,
}

impl Component for Clutch {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            signal_in: vec!["f_normalized"],
            heat: if self.p.use_heat_port {
                vec!["heatPort"]
            } else {
                vec![]
            },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        let rel = Rel::between(na, nb);
        if rel.is_zero() {
            return Err(b.error("flange_a and flange_b are rigidly connected: it can never slip"));
        }
        let k = add_elem(b, &self.p, rel.clone(), true)?;
        b.init_angle(rel.clone(), self.phi_rel, "phi_rel");
        b.init_speed(rel.clone(), self.w_rel, "w_rel");
        b.output("phi_rel", Out::Angle(rel));
        b.output("w_rel", Out::Friction(k, V::W));
        b.output("a_rel", Out::Friction(k, V::A));
        b.flange(
            "flange_a",
            na,
            Some(Out::Scaled(Box::new(Out::Friction(k, V::Tau)), -1.0)),
        )?;
        b.flange("flange_b", nb, Some(Out::Friction(k, V::Tau)))?;
        Ok(())
    }
}

fn clutch(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Clutch {
        p: read_params(p)?,
        phi_rel: p.init("phi_rel", 0.0)?,
        w_rel: p.init("w_rel", 0.0)?,
    }))
}

pub const REGISTRY: &[(&str, Constructor)] = &[("Brake", brake), ("Clutch", clutch)];
