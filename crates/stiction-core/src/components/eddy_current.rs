//! MSL `Sources.EddyCurrentTorque`: a braking torque by Kloss' equation,
//! `tau = 2·tau_nominal·w_n/(1 + w_n²)` with `w_n = w/(w_nominal·(1 + alphaRef·(T − TRef)))`,
//! the disc's resistance (and so the speed of the maximum torque) shifting with the temperature
//! of the heat port (or the parameter `T` without one). Its loss `tau·w` goes to the heat port.
//! `tau` is MSL's `flange.tau`: positive while it brakes a positive speed.

use super::decl::{USE_HEAT_PORT, USE_SUPPORT};
use super::{heat_port, with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out, Rel};

/// MSL's 20 °C, the temperature `alpha20` is given at.
const T20: f64 = 293.15;

#[derive(Clone, Copy)]
enum Source {
    Slot(usize),
    Value(f64),
}

struct EddyLaw {
    tau_nominal: Source,
    temperature: Source,
    w_nominal: f64,
    t_ref: f64,
    /// `convertAlpha(alpha20, TRef)`: the coefficient at TRef.
    alpha_ref: f64,
}

impl EddyLaw {
    fn read(source: Source, x: &LawCtx) -> f64 {
        match source {
            Source::Slot(slot) => x.signals[slot],
            Source::Value(v) => v,
        }
    }

    /// `w/w_nominal` at the operating temperature.
    fn w_normalized(&self, x: &LawCtx) -> f64 {
        let t = Self::read(self.temperature, x);
        x.w_rel / (self.w_nominal * (1.0 + self.alpha_ref * (t - self.t_ref)))
    }
}

impl ForceLaw for EddyLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        let wn = self.w_normalized(x);
        2.0 * Self::read(self.tau_nominal, x) * wn / (1.0 + wn * wn)
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Dissipative
    }
    fn loss_power(&self, x: &LawCtx, tau: f64) -> f64 {
        tau * x.w_rel
    }
}

struct EddyCurrentTorque {
    /// `EddyCurrentForce`: translational flange, MSL's names `f_input`, `f`, `s`, `v`.
    translational: bool,
    use_input: bool,
    tau_nominal: f64,
    w_nominal: f64,
    t_ref: f64,
    alpha_ref: f64,
    use_support: bool,
    use_heat_port: bool,
    t_fixed: f64,
}

impl EddyCurrentTorque {
    /// The names of the input, the force, the position and the speed.
    fn names(&self) -> [&'static str; 4] {
        match self.translational {
            true => ["f_input", "f", "s", "v"],
            false => ["tau_input", "tau", "phi", "w"],
        }
    }
}

impl Component for EddyCurrentTorque {
    fn ports(&self) -> Ports {
        let mech = with_support(&["flange"], self.use_support);
        Ports {
            translational: if self.translational {
                mech.clone()
            } else {
                vec![]
            },
            mech,
            signal_in: if self.use_input {
                vec![self.names()[0]]
            } else {
                vec![]
            },
            heat: heat_port(self.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nf, ns) = (b.node("flange")?, b.node("support")?);
        let rel = Rel::of(&[(nf, 1.0), (ns, -1.0)]);
        let tau_nominal = match self.use_input {
            true => Source::Slot(b.signal_in(self.names()[0])?),
            false => Source::Value(self.tau_nominal),
        };
        let heat = match self.use_heat_port {
            true => Some(b.heat_node("heatPort")?),
            false => None,
        };
        let temperature = match heat {
            Some(node) => Source::Slot(b.temperature_tap(node)),
            None => Source::Value(self.t_fixed),
        };
        let law = b.add_law(
            rel.clone(),
            Box::new(EddyLaw {
                tau_nominal,
                temperature,
                w_nominal: self.w_nominal,
                t_ref: self.t_ref,
                alpha_ref: self.alpha_ref,
            }),
        );
        let [_, tau, phi, w] = self.names();
        b.output(tau, Out::LawTau(law, 1.0));
        b.output(phi, Out::Angle(rel.clone()));
        b.output(w, Out::Speed(rel));
        b.output("lossPower", Out::LawLoss(law));
        b.flange("flange", nf, Some(Out::LawTau(law, 1.0)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::LawTau(law, -1.0)))?;
        }
        if let Some(node) = heat {
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

/// The declarations that differ between the torque and the force.
pub(crate) struct Decls {
    pub(crate) use_input: &'static str,
    pub(crate) nominal: &'static str,
    pub(crate) speed: (&'static str, &'static str),
    pub(crate) use_support: &'static str,
}

const TORQUE: Decls = Decls {
    use_input: "useTau_nominalInput true: signal input tau_input for tau_nominal",
    nominal: "tau_nominal [N.m] Maximum torque (always braking)",
    speed: (
        "w_nominal",
        "w_nominal [rad/s] Nominal speed (leads to maximum torque) at reference temperature",
    ),
    use_support: USE_SUPPORT,
};

fn eddy_current_torque(p: &Params) -> ModelResult<Box<dyn Component>> {
    eddy_current(p, &TORQUE, false)
}

/// `EddyCurrentTorque`, or `EddyCurrentForce` with `translational` and its declarations.
pub(crate) fn eddy_current(
    p: &Params,
    d: &Decls,
    translational: bool,
) -> ModelResult<Box<dyn Component>> {
    let use_input = p.boolean(d.use_input, false)?;
    let tau_nominal = p.real(d.nominal, 0.0)?;
    let w_nominal = p.positive(d.speed.0, p.required(d.speed.1)?)?;
    let t_ref = p.positive("TRef", p.real("TRef [K] Reference temperature", T20)?)?;
    let alpha20 = p.real("alpha20 [1/K] Temperature coefficient of material", 0.0)?;
    let scale = 1.0 + alpha20 * (t_ref - T20);
    if scale <= 0.0 {
        let message = format!("1 + alpha20*(TRef - 293.15) must be > 0, got {scale}");
        return Err(p.error("alpha20", message));
    }
    let alpha_ref = alpha20 / scale;
    let use_support = p.boolean(d.use_support, false)?;
    let use_heat_port = p.boolean(USE_HEAT_PORT, false)?;
    let t_fixed = p.positive(
        "T",
        p.real("T [K] Fixed device temperature if useHeatPort = false", T20)?,
    )?;
    if 1.0 + alpha_ref * (t_fixed - t_ref) <= 0.0 && !use_heat_port {
        let message =
            "at this temperature the nominal speed·(1 + alphaRef·(T − TRef)) is not positive";
        return Err(p.error("T", message));
    }
    Ok(Box::new(EddyCurrentTorque {
        translational,
        use_input,
        tau_nominal,
        w_nominal,
        t_ref,
        alpha_ref,
        use_support,
        use_heat_port,
        t_fixed,
    }))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "EddyCurrentTorque",
    "Modelica.Mechanics.Rotational.Sources.EddyCurrentTorque",
    "Simple model of a rotational eddy current brake",
    eddy_current_torque,
)];
