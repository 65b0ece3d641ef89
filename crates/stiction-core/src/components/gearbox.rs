//! MSL `Components.Gearbox`: a LossyGear (mesh efficiency, bearing friction, sticking) in
//! series with an ElastoBacklash (elasticity, damping, backlash) on flange_b's side, joined by
//! a shaft without inertia inside the component. The two parts are the library's own
//! components, built as `gearbox.lossyGear` and `gearbox.elastoBacklash` (`Builder::within`):
//! their equations, events and variables are theirs; the internal shaft is a private flange
//! pair (`Ports::internal`) the assembly resolves to a fresh node, a massless one
//! (`engine::massless`) as MSL's connection of the two parts is.

use super::compliant::elasto_backlash_part;
use super::decl::{USE_HEAT_PORT, USE_SUPPORT};
use super::friction::lossy_gear;
use super::gears::gear_ratio;
use super::{heat_port, with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out, Rel};

/// The internal shaft: lossyGear's flange_b and elastoBacklash's flange_a, rigidly one.
const GEAR_B: &str = "lossyGear.flange_b";
const BACKLASH_A: &str = "elastoBacklash.flange_a";

struct Gearbox {
    lossy_gear: Box<dyn Component>,
    elasto_backlash: Box<dyn Component>,
    use_support: bool,
    use_heat_port: bool,
    phi_rel: InitValue,
    w_rel: InitValue,
}

impl Component for Gearbox {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange_a", "flange_b"], self.use_support),
            heat: heat_port(self.use_heat_port),
            joins: vec![(GEAR_B, BACKLASH_A)],
            internal: vec![GEAR_B, BACKLASH_A],
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nb, shaft) = (b.node("flange_b")?, b.node(GEAR_B)?);
        // MSL: phi_rel = flange_b.phi - lossyGear.flange_b.phi, states by preference
        let rel = Rel::between(shaft, nb);
        b.init_angle(rel.clone(), self.phi_rel, "phi_rel");
        b.init_speed(rel.clone(), self.w_rel, "w_rel");
        let heat: &[(&str, &str)] = match self.use_heat_port {
            true => &[("heatPort", "heatPort")],
            false => &[],
        };
        let support: &[(&str, &str)] = match self.use_support {
            true => &[("support", "support")],
            false => &[],
        };
        let gear_ports = [
            [("flange_a", "flange_a"), ("flange_b", GEAR_B)].as_slice(),
            support,
            heat,
        ];
        b.within("lossyGear", &gear_ports.concat(), |b| {
            self.lossy_gear.build(b)
        })?;
        let backlash_ports = [
            [("flange_a", BACKLASH_A), ("flange_b", "flange_b")].as_slice(),
            heat,
        ];
        let backlash = |b: &mut Builder| self.elasto_backlash.build(b);
        b.within("elastoBacklash", &backlash_ports.concat(), backlash)?;
        b.output("phi_rel", Out::Angle(rel.clone()));
        b.output("w_rel", Out::Speed(rel.clone()));
        b.output("a_rel", Out::Accel(rel));
        let loss = self.loss_power(b)?;
        b.output("lossPower", loss.clone());
        // the flanges' torques are known from the parts (lossyGear's flange_a, …)
        for port in ["flange_a", "flange_b"] {
            b.flange(port, b.node(port)?, None)?;
        }
        if self.use_support {
            b.flange("support", b.node("support")?, None)?;
        }
        if self.use_heat_port {
            let node = b.heat_node("heatPort")?;
            b.output("heatPort.T", Out::HeatT(node));
            b.output("heatPort.Q_flow", Out::Scaled(Box::new(loss), -1.0));
        }
        Ok(())
    }
}

impl Gearbox {
    /// MSL's `lossPower`: what both parts send to the internal heat port.
    fn loss_power(&self, b: &Builder) -> ModelResult<Out> {
        let part = |name: &str| {
            b.reported(name)
                .ok_or_else(|| b.error(format!("internal: '{name}' not reported")))
        };
        let gear = part("lossyGear.lossPower")?;
        let backlash = part("elastoBacklash.lossPower")?;
        Ok(Out::Formula(std::sync::Arc::new(
            crate::system::formula::Formula::sum(vec![gear, backlash]),
        )))
    }
}

fn gearbox(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = gear_ratio(p)?;
    let table = lossy_gear::loss_table(p)?;
    let c = p.real("c [N.m/rad] Gear elasticity (spring constant)", 1e5)?;
    let c = p.positive("c", c)?;
    let d = p.real("d [N.m.s/rad] Gear damping (relative damping)", 0.0)?;
    let d = p.at_least("d", d, 0.0)?;
    let width = p.real("b [rad] Total backlash", 0.0)?;
    let width = p.at_least("b", width, 0.0)?;
    let phi_rel = p.init(
        "phi_rel [rad] Relative rotation angle over gear elasticity flange_b.phi - \
         lossyGear.flange_b.phi (start value)",
        0.0,
    )?;
    let w_rel = p.init(
        "w_rel [rad/s] Relative angular velocity over gear elasticity der(phi_rel) (start value)",
        0.0,
    )?;
    let use_support = p.boolean(USE_SUPPORT, false)?;
    let use_heat_port = p.boolean(USE_HEAT_PORT, false)?;
    Ok(Box::new(Gearbox {
        lossy_gear: lossy_gear::part(ratio, table, use_support, use_heat_port),
        elasto_backlash: elasto_backlash_part(c, d, width, 0.0, use_heat_port),
        use_support,
        use_heat_port,
        phi_rel,
        w_rel,
    }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "Gearbox",
    "Modelica.Mechanics.Rotational.Components.Gearbox",
    "Realistic model of a gearbox (based on LossyGear)",
    gearbox,
)];
