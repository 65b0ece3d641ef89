//! Modelica.Thermal.HeatTransfer components: HeatCapacitor, ThermalConductor, Convection,
//! BodyRadiation, FixedTemperature (kelvin and Celsius).

use super::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, Out};
use crate::thermal::{Conductance, Link};

/// The ports of a component with one heat port, `port`.
fn one_port() -> Ports {
    Ports {
        heat: vec!["port"],
        ..Ports::default()
    }
}

struct HeatCapacitor {
    c: f64,
    t: InitValue,
}

impl Component for HeatCapacitor {
    fn ports(&self) -> Ports {
        one_port()
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.heat_node("port")?;
        b.add_heat_capacity(node, self.c, self.t);
        b.output("T", Out::HeatT(node));
        b.output("der_T", Out::HeatDerT(node));
        b.output("port.T", Out::HeatT(node));
        b.output("port.Q_flow", Out::HeatCapacitorFlow(node, self.c));
        Ok(())
    }
}

/// How a two-port element passes heat.
enum Law {
    /// `G·ΔT` with a constant G (ThermalConductor).
    Constant(f64),
    /// `Gc·ΔT` with Gc from the input (Convection).
    Input,
    /// `Gr·σ·(T_a⁴ − T_b⁴)` (BodyRadiation).
    Radiation(f64),
}

struct Conductor {
    g: Law,
    ports: (&'static str, &'static str),
}

impl Component for Conductor {
    fn ports(&self) -> Ports {
        Ports {
            heat: vec![self.ports.0, self.ports.1],
            signal_in: if matches!(self.g, Law::Input) {
                vec!["Gc"]
            } else {
                vec![]
            },
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (pa, pb) = self.ports;
        let a = b.heat_node(pa)?;
        let c = b.heat_node(pb)?;
        let g = match self.g {
            Law::Constant(g) => Conductance::Constant(g),
            Law::Input => {
                let slot = b.signal_in("Gc")?;
                b.output("Gc", Out::Signal(slot));
                Conductance::Signal(slot)
            }
            Law::Radiation(gr) => Conductance::Radiation(gr),
        };
        let link = b.add_heat_link(Link { a, b: c, g });
        b.output("Q_flow", Out::HeatLinkFlow(link, 1.0));
        b.output("dT", Out::HeatDiff(a, c));
        b.output(&format!("{pa}.T"), Out::HeatT(a));
        b.output(&format!("{pa}.Q_flow"), Out::HeatLinkFlow(link, 1.0));
        b.output(&format!("{pb}.T"), Out::HeatT(c));
        b.output(&format!("{pb}.Q_flow"), Out::HeatLinkFlow(link, -1.0));
        Ok(())
    }
}

// Alike in shape to HeatCapacitor (one heat port); the port list is `one_port`.
struct FixedTemperature {
    t: f64,
}

impl Component for FixedTemperature {
    fn ports(&self) -> Ports {
        one_port()
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let node = b.heat_node("port")?;
        b.fix_temperature(node, self.t)?;
        b.output("port.T", Out::HeatT(node));
        // The source absorbs whatever flows into its node (Q_flow is positive into a component).
        b.output("port.Q_flow", Out::HeatNodeInflow(node, 1.0));
        Ok(())
    }
}

fn heat_capacitor(p: &Params) -> ModelResult<Box<dyn Component>> {
    let c = p.positive(
        "C",
        p.required("C [J/K] Heat capacity of the element (cp*m)")?,
    )?;
    // MSL HeatCapacitor: T(start = 293.15); the start value is the initial temperature.
    let t = p.init("T [K] Temperature of the element (start value)", 293.15)?;
    Ok(Box::new(HeatCapacitor { c, t }))
}

fn thermal_conductor(p: &Params) -> ModelResult<Box<dyn Component>> {
    let g = p.at_least(
        "G",
        p.required("G [W/K] Constant thermal conductance of the material")?,
        0.0,
    )?;
    Ok(Box::new(Conductor {
        g: Law::Constant(g),
        ports: ("port_a", "port_b"),
    }))
}

fn convection(_p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Conductor {
        g: Law::Input,
        ports: ("solid", "fluid"),
    }))
}

fn body_radiation(p: &Params) -> ModelResult<Box<dyn Component>> {
    let gr = p.at_least(
        "Gr",
        p.required("Gr [m2] Net radiation conductance between two surfaces (see docu)")?,
        0.0,
    )?;
    Ok(Box::new(Conductor {
        g: Law::Radiation(gr),
        ports: ("port_a", "port_b"),
    }))
}

fn fixed_temperature(p: &Params) -> ModelResult<Box<dyn Component>> {
    let t = p.positive("T", p.required("T [K] Fixed temperature at the port")?)?;
    Ok(Box::new(FixedTemperature { t }))
}

/// Thermal.HeatTransfer.Celsius.FixedTemperature: `T` in degrees Celsius.
fn fixed_temperature_celsius(p: &Params) -> ModelResult<Box<dyn Component>> {
    let t = p.at_least(
        "T",
        p.required("T [degC] Fixed temperature at the port")?,
        -273.15,
    )? + 273.15;
    Ok(Box::new(FixedTemperature { t }))
}

// Registries are alike in shape in every family: one line per type.
pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "HeatCapacitor",
        "Modelica.Thermal.HeatTransfer.Components.HeatCapacitor",
        "Lumped thermal element storing heat",
        heat_capacitor,
    ),
    Entry::new(
        "ThermalConductor",
        "Modelica.Thermal.HeatTransfer.Components.ThermalConductor",
        "Lumped thermal element transporting heat without storing it",
        thermal_conductor,
    ),
    Entry::new(
        "Convection",
        "Modelica.Thermal.HeatTransfer.Components.Convection",
        "Lumped thermal element for heat convection (conductance from the input Gc)",
        convection,
    ),
    Entry::new(
        "BodyRadiation",
        "Modelica.Thermal.HeatTransfer.Components.BodyRadiation",
        "Lumped thermal element for radiation heat transfer: Q_flow = Gr*sigma*(port_a.T^4 - port_b.T^4)",
        body_radiation,
    ),
    Entry::new(
        "FixedTemperature",
        "Modelica.Thermal.HeatTransfer.Sources.FixedTemperature",
        "Fixed temperature boundary condition in kelvin",
        fixed_temperature,
    ),
    Entry::new(
        "Celsius.FixedTemperature",
        "Modelica.Thermal.HeatTransfer.Celsius.FixedTemperature",
        "Fixed temperature boundary condition in degrees Celsius",
        fixed_temperature_celsius,
    ),
];
