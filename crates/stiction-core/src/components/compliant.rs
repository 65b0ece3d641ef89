//! `Spring`, `Damper`, `SpringDamper`, `ElastoBacklash`, `ElastoBacklash2`: torque laws
//! between two flanges (spec §5.6, §5.10–5.12).

use super::backlash::BacklashLaw;
use super::backlash2::HardBacklashLaw;
use super::decl::{PHI_REL, USE_HEAT_PORT, W_REL};
use super::{heat_port, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out, Rel};

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

struct Compliant {
    c: f64,
    d: f64,
    phi_rel0: f64,
    phi_rel: InitValue,
    w_rel: InitValue,
    /// Spring has no relative speed states and no heat port in MSL.
    has_damper: bool,
    has_spring: bool,
    use_heat_port: bool,
    /// ElastoBacklash(2): the total backlash `b`.
    backlash: Option<f64>,
    /// ElastoBacklash2: the contact's torque jumps (MSL's hard contact with events).
    hard_contact: bool,
}

impl Component for Compliant {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            heat: heat_port(self.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        let rel = Rel::between(na, nb);
        let law: Box<dyn ForceLaw> = match self.backlash {
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
        b.init_angle(rel.clone(), self.phi_rel, "phi_rel");
        b.output("phi_rel", Out::Angle(rel.clone()));
        if self.has_damper {
            b.init_speed(rel.clone(), self.w_rel, "w_rel");
            b.output("w_rel", Out::Speed(rel.clone()));
            b.output("a_rel", Out::Accel(rel.clone()));
        }
        b.output("tau", Out::LawTau(law, 1.0));
        if self.has_damper && self.has_spring && self.backlash.is_none() {
            let mut stretch = rel.clone();
            stretch.offset -= self.phi_rel0;
            b.output("tau_c", Out::Scaled(Box::new(Out::Angle(stretch)), self.c));
            b.output(
                "tau_d",
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
    let c = if has_spring {
        p.at_least("c", p.real("c [N.m/rad] Spring constant", 1e5)?, 0.0)?
    } else {
        0.0
    };
    let d = if has_damper {
        p.at_least("d", p.real("d [N.m.s/rad] Damping constant", 0.0)?, 0.0)?
    } else {
        0.0
    };
    let phi_rel0 = if has_spring {
        p.real("phi_rel0 [rad] Unstretched spring angle", 0.0)?
    } else {
        0.0
    };
    let phi_rel = p.init(PHI_REL, 0.0)?;
    let (w_rel, use_heat_port) = if has_damper {
        (p.init(W_REL, 0.0)?, p.boolean(USE_HEAT_PORT, false)?)
    } else {
        (InitValue::guess(0.0), false)
    };
    Ok(Box::new(Compliant {
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
    }))
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
