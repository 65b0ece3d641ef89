//! `Spring`, `Damper`, `SpringDamper`, `ElastoBacklash`, `ElastoBacklash2`: torque laws
//! between two flanges (spec §5.6, §5.10–5.12).

use super::backlash::BacklashLaw;
use super::backlash2::HardBacklashLaw;
use super::decl::{PHI_REL, USE_HEAT_PORT, W_REL};
use super::elasto_gap::GapLaw;
use super::{heat_port, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out};

/// `tau = c·(phi_rel − phi_rel0) + d·w_rel`.
struct SpringDamperLaw {
    c: f64,
    d: f64,
    phi_rel0: f64,
}

impl ForceLaw for SpringDamperLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        self.c * (x.phi_rel - self.phi_rel0) + self.d * x.w_rel
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Conservative
    }
    fn potential(&self, x: &LawCtx) -> f64 {
        0.5 * self.c * (x.phi_rel - self.phi_rel0).powi(2)
    }
    fn loss_power(&self, x: &LawCtx, _tau: f64) -> f64 {
        self.d * x.w_rel * x.w_rel
    }
    fn linear(&self) -> Option<(f64, f64)> {
        Some((self.c, self.d))
    }
}

/// The names a compliant element reports under, by domain (MSL's Rotational / Translational
/// `PartialCompliant…`): one implementation, two vocabularies.
pub(crate) struct CompliantNames {
    pub rel: &'static str,
    pub speed: &'static str,
    pub accel: &'static str,
    pub force: &'static str,
    pub force_c: &'static str,
    pub force_d: &'static str,
    pub translational: bool,
    /// The parameter declarations (name, unit, text) as the domain's MSL class writes them.
    pub c_decl: &'static str,
    pub d_decl: &'static str,
    pub rel0_decl: &'static str,
    pub rel_decl: &'static str,
    pub speed_decl: &'static str,
    /// The default spring constant (Rotational 1e5, Translational's start value 1).
    pub c_default: f64,
}

pub(crate) const ROTATIONAL: CompliantNames = CompliantNames {
    rel: "phi_rel",
    speed: "w_rel",
    accel: "a_rel",
    force: "tau",
    force_c: "tau_c",
    force_d: "tau_d",
    translational: false,
    c_decl: "c [N.m/rad] Spring constant",
    d_decl: "d [N.m.s/rad] Damping constant",
    rel0_decl: "phi_rel0 [rad] Unstretched spring angle",
    rel_decl: PHI_REL,
    speed_decl: W_REL,
    c_default: 1e5,
};

pub(crate) const TRANSLATIONAL: CompliantNames = CompliantNames {
    rel: "s_rel",
    speed: "v_rel",
    accel: "a_rel",
    force: "f",
    force_c: "f_c",
    force_d: "f_d",
    translational: true,
    c_decl: "c [N/m] Spring constant",
    d_decl: "d [N.s/m] Damping constant",
    rel0_decl: "s_rel0 [m] Unstretched spring length",
    rel_decl: "s_rel [m] Relative distance flange_b.s - flange_a.s (start value)",
    speed_decl: "v_rel [m/s] Relative velocity der(s_rel) (start value)",
    c_default: 1.0,
};

pub(crate) struct Compliant {
    pub names: &'static CompliantNames,
    /// Translational.ElastoGap: a one-sided contact with the spring exponent `n`.
    pub gap: Option<f64>,
    pub c: f64,
    pub d: f64,
    pub phi_rel0: f64,
    pub phi_rel: InitValue,
    pub w_rel: InitValue,
    /// Spring has no relative speed states and no heat port in MSL.
    pub has_damper: bool,
    pub has_spring: bool,
    pub use_heat_port: bool,
    /// ElastoBacklash(2): the total backlash `b`.
    pub backlash: Option<f64>,
    /// ElastoBacklash2: the contact's torque jumps (MSL's hard contact with events).
    pub hard_contact: bool,
}

impl Component for Compliant {
    fn ports(&self) -> Ports {
        let mech = vec!["flange_a", "flange_b"];
        Ports {
            translational: if self.names.translational {
                mech.clone()
            } else {
                vec![]
            },
            mech,
            heat: heat_port(self.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        // b.rel: the flanges' own positions (a translational Mass's flanges sit L/2 off its node)
        let rel = b.rel(&[("flange_b", 1.0), ("flange_a", -1.0)])?;
        let law: Box<dyn ForceLaw> = match self.backlash {
            _ if self.gap.is_some() => Box::new(GapLaw::new(
                self.c,
                self.d,
                self.phi_rel0,
                self.gap.unwrap_or(1.0),
            )),
            Some(width) if self.hard_contact => {
                Box::new(HardBacklashLaw::new(self.c, self.d, width, self.phi_rel0))
            }
            Some(width) => Box::new(BacklashLaw::new(self.c, self.d, width, self.phi_rel0)),
            None => Box::new(SpringDamperLaw {
                c: self.c,
                d: self.d,
                phi_rel0: self.phi_rel0,
            }),
        };
        let law = b.add_law(rel.clone(), law);
        let n = self.names;
        b.init_angle(rel.clone(), self.phi_rel, n.rel);
        b.output(n.rel, Out::Angle(rel.clone()));
        if self.has_damper {
            b.keep_relative_states(law);
            b.init_speed(rel.clone(), self.w_rel, n.speed);
            b.output(n.speed, Out::Speed(rel.clone()));
            b.output(n.accel, Out::Accel(rel.clone()));
        }
        b.output(n.force, Out::LawTau(law, 1.0));
        if self.has_damper && self.has_spring && self.backlash.is_none() && self.gap.is_none() {
            let mut stretch = rel.clone();
            stretch.offset -= self.phi_rel0;
            b.output(
                n.force_c,
                Out::Scaled(Box::new(Out::Angle(stretch)), self.c),
            );
            b.output(
                n.force_d,
                Out::Scaled(Box::new(Out::Speed(rel.clone())), self.d),
            );
        }
        if self.has_damper {
            b.output("lossPower", Out::LawLoss(law));
        }
        b.flange("flange_a", na, Some(Out::LawTau(law, -1.0)))?;
        b.flange("flange_b", nb, Some(Out::LawTau(law, 1.0)))?;
        if self.use_heat_port {
            let node = b.heat_node("heatPort")?;
            b.set_law_heat(law, node);
            b.output("heatPort.T", Out::HeatT(node));
            b.output(
                "heatPort.Q_flow",
                Out::Scaled(Box::new(Out::LawLoss(law)), -1.0),
            );
        }
        Ok(())
    }
}

/// A Spring, Damper or SpringDamper, its parameters read in MSL's order. A spring alone has
/// no `w_rel` to start (a free guess) and no heat port.
fn linear(p: &Params, has_spring: bool, has_damper: bool) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(read_linear(
        p,
        has_spring,
        has_damper,
        &ROTATIONAL,
    )?))
}

/// The rotational Spring, Damper or SpringDamper as data (the translational ones rename it).
pub(crate) fn read_linear(
    p: &Params,
    has_spring: bool,
    has_damper: bool,
    names: &'static CompliantNames,
) -> ModelResult<Compliant> {
    let c = if has_spring {
        p.at_least("c", p.real(names.c_decl, names.c_default)?, 0.0)?
    } else {
        0.0
    };
    let d = if has_damper {
        p.at_least("d", p.real(names.d_decl, 0.0)?, 0.0)?
    } else {
        0.0
    };
    let phi_rel0 = if has_spring {
        p.real(names.rel0_decl, 0.0)?
    } else {
        0.0
    };
    let phi_rel = p.init(names.rel_decl, 0.0)?;
    let (w_rel, use_heat_port) = if has_damper {
        (
            p.init(names.speed_decl, 0.0)?,
            p.boolean(USE_HEAT_PORT, false)?,
        )
    } else {
        (InitValue::guess(0.0), false)
    };
    Ok(Compliant {
        names,
        gap: None,
        c,
        d,
        phi_rel0,
        phi_rel,
        w_rel,
        has_damper,
        has_spring,
        use_heat_port,
        backlash: None,
        hard_contact: false,
    })
}

fn spring(p: &Params) -> ModelResult<Box<dyn Component>> {
    linear(p, true, false)
}

fn damper(p: &Params) -> ModelResult<Box<dyn Component>> {
    linear(p, false, true)
}

fn spring_damper(p: &Params) -> ModelResult<Box<dyn Component>> {
    linear(p, true, true)
}

fn elasto_backlash(p: &Params) -> ModelResult<Box<dyn Component>> {
    backlash(p, false)
}

fn elasto_backlash2(p: &Params) -> ModelResult<Box<dyn Component>> {
    backlash(p, true)
}

/// ElastoBacklash (soft contact) or ElastoBacklash2 (hard contact): the same parameters.
fn backlash(p: &Params, hard_contact: bool) -> ModelResult<Box<dyn Component>> {
    let b = p.real("b [rad] Total backlash", 0.0)?;
    p.range("b", ">= 0");
    if b < 0.0 {
        return Err(p.error("b", format!("the backlash must be >= 0, got {b}")));
    }
    Ok(Box::new(Compliant {
        names: &ROTATIONAL,
        gap: None,
        c: p.positive("c", p.real("c [N.m/rad] Spring constant", 1e5)?)?,
        d: p.at_least("d", p.real("d [N.m.s/rad] Damping constant", 0.0)?, 0.0)?,
        phi_rel0: p.real("phi_rel0 [rad] Unstretched spring angle", 0.0)?,
        phi_rel: p.init(PHI_REL, 0.0)?,
        w_rel: p.init(W_REL, 0.0)?,
        has_damper: true,
        has_spring: true,
        use_heat_port: p.boolean(USE_HEAT_PORT, false)?,
        backlash: Some(b),
        hard_contact,
    }))
}

/// An ElastoBacklash of checked parameters whose relative angle and speed start free at 0 (a
/// Gearbox's part: MSL sets only these four and useHeatPort).
pub(crate) fn elasto_backlash_part(
    c: f64,
    d: f64,
    b: f64,
    phi_rel0: f64,
    use_heat_port: bool,
) -> Box<dyn Component> {
    Box::new(Compliant {
        names: &ROTATIONAL,
        gap: None,
        c,
        d,
        phi_rel0,
        phi_rel: InitValue::guess(0.0),
        w_rel: InitValue::guess(0.0),
        has_damper: true,
        has_spring: true,
        use_heat_port,
        backlash: Some(b),
        hard_contact: false,
    })
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Spring",
        "Modelica.Mechanics.Rotational.Components.Spring",
        "Linear 1D rotational spring",
        spring,
    ),
    Entry::new(
        "Damper",
        "Modelica.Mechanics.Rotational.Components.Damper",
        "Linear 1D rotational damper",
        damper,
    ),
    Entry::new(
        "SpringDamper",
        "Modelica.Mechanics.Rotational.Components.SpringDamper",
        "Linear 1D rotational spring and damper in parallel",
        spring_damper,
    ),
    Entry::new(
        "ElastoBacklash",
        "Modelica.Mechanics.Rotational.Components.ElastoBacklash",
        "Backlash connected in series to linear spring and damper (soft contact)",
        elasto_backlash,
    ),
    Entry::new(
        "ElastoBacklash2",
        "Modelica.Mechanics.Rotational.Components.ElastoBacklash2",
        "Backlash connected in series to linear spring and damper (hard contact: events, torque jumps)",
        elasto_backlash2,
    ),
];
