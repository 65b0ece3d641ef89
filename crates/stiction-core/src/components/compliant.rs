//! `Spring`, `Damper`, `SpringDamper`: torque laws between two flanges (spec §5.10–5.12).

use super::{Component, Constructor, Ports};
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
}

impl Component for Compliant {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            heat: if self.use_heat_port {
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
        let law = b.add_law(
            rel.clone(),
            Box::new(SpringDamperLaw {
                c: self.c,
                d: self.d,
                phi_rel0: self.phi_rel0,
            }),
        );
        b.init_angle(rel.clone(), self.phi_rel, "phi_rel");
        b.output("phi_rel", Out::Angle(rel.clone()));
        if self.has_damper {
            b.init_speed(rel.clone(), self.w_rel, "w_rel");
            b.output("w_rel", Out::Speed(rel.clone()));
            b.output("a_rel", Out::Accel(rel.clone()));
        }
        b.output("tau", Out::LawTau(law, 1.0));
        if self.has_damper && self.has_spring {
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

fn spring(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Compliant {
        c: p.at_least("c", p.real("c", 1e5)?, 0.0)?,
        d: 0.0,
        phi_rel0: p.real("phi_rel0", 0.0)?,
        phi_rel: p.init("phi_rel", 0.0)?,
        w_rel: InitValue {
            start: 0.0,
            fixed: false,
        },
        has_damper: false,
        has_spring: true,
        use_heat_port: false,
    }))
}

fn damper(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Compliant {
        c: 0.0,
        d: p.at_least("d", p.real("d", 0.0)?, 0.0)?,
        phi_rel0: 0.0,
        phi_rel: p.init("phi_rel", 0.0)?,
        w_rel: p.init("w_rel", 0.0)?,
        has_damper: true,
        has_spring: false,
        use_heat_port: p.boolean("useHeatPort", false)?,
    }))
}

fn spring_damper(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Compliant {
        c: p.at_least("c", p.real("c", 1e5)?, 0.0)?,
        d: p.at_least("d", p.real("d", 0.0)?, 0.0)?,
        phi_rel0: p.real("phi_rel0", 0.0)?,
        phi_rel: p.init("phi_rel", 0.0)?,
        w_rel: p.init("w_rel", 0.0)?,
        has_damper: true,
        has_spring: true,
        use_heat_port: p.boolean("useHeatPort", false)?,
    }))
}

pub const REGISTRY: &[(&str, Constructor)] = &[
    ("Spring", spring),
    ("Damper", damper),
    ("SpringDamper", spring_damper),
];
