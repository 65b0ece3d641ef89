//! MSL `Translational.Components.RollingResistance` and `Components.Vehicle`. The vehicle is
//! MSL's composition written out on one node pair: an `Inertia` J on `flangeR`, an
//! `IdealRollingWheel` row `R·flangeR.phi = flangeT.s`, a `Mass` m on `flangeT`, and the three
//! driving resistances as force laws on it — drag `Cd·A·rho·(v − vWind)·|v − vWind|/2`, rolling
//! resistance `Cr·m·g·cos(alpha)` regularized linearly within `±vReg` (RollingResistance's law),
//! and the grade `m·g·sin(alpha)`, `alpha = atan(inclination)`.

use crate::components::sources::{regularization, regularized_sign, Reg};
use crate::components::{with_support, Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::{InitValue, Params};
use crate::system::{Builder, EnergyRole, ForceLaw, LawCtx, Out, Rel};

/// MSL's `Modelica.Constants.g_n`.
const G_N: f64 = 9.80665;

/// A value given by a parameter or read from a signal input.
#[derive(Clone, Copy)]
enum Source {
    Slot(usize),
    Value(f64),
}

impl Source {
    fn read(self, x: &LawCtx) -> f64 {
        match self {
            Source::Slot(slot) => x.signals[slot],
            Source::Value(v) => v,
        }
    }

    /// The input `port` if `use_input`, else the constant.
    fn of(b: &mut Builder, use_input: bool, port: &str, value: f64) -> ModelResult<Self> {
        Ok(match use_input {
            true => Source::Slot(b.signal_in(port)?),
            false => Source::Value(value),
        })
    }
}

/// RollingResistance's `flange.f = Cr·fWeight·cos(atan(inclination))·sign_reg(v)`.
struct RollLaw {
    cr: Source,
    inclination: Source,
    f_weight: f64,
    reg: Reg,
    v0: f64,
}

impl ForceLaw for RollLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        let nominal = self.cr.read(x) * self.f_weight * self.inclination.read(x).atan().cos();
        let outside = x.relations.first().copied().unwrap_or(false); // |v| >= v0
        nominal * regularized_sign(self.reg, x.w_rel, self.v0, outside)
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Dissipative
    }
    fn loss_power(&self, x: &LawCtx, tau: f64) -> f64 {
        tau * x.w_rel
    }
    fn relation_count(&self) -> usize {
        usize::from(self.reg != Reg::Exp)
    }
    fn relation_values(&self, x: &LawCtx, z: &mut [f64]) {
        if self.reg != Reg::Exp {
            z[0] = x.w_rel.abs() - self.v0;
        }
    }
    fn relation_label(&self, _i: usize) -> &'static str {
        "|v| crossed v0"
    }
}

/// The vehicle's drag (MSL: a QuadraticSpeedDependentForce whose support moves at the wind).
struct DragLaw {
    coefficient: f64,
    wind: Source,
}

impl ForceLaw for DragLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        let v = x.w_rel - self.wind.read(x);
        self.coefficient * v * v.abs()
    }
    fn role(&self) -> EnergyRole {
        // with wind, the air (MSL's windSpeed source) works on the vehicle too
        match self.wind {
            Source::Value(0.0) => EnergyRole::Dissipative,
            _ => EnergyRole::Source,
        }
    }
    fn loss_power(&self, x: &LawCtx, tau: f64) -> f64 {
        tau * x.w_rel
    }
}

/// The grade's force `m·g·sin(atan(inclination))` against the motion uphill.
struct GradeLaw {
    weight: f64,
    inclination: Source,
}

impl ForceLaw for GradeLaw {
    fn tau(&self, x: &LawCtx) -> f64 {
        self.weight * self.inclination.read(x).atan().sin()
    }
    fn role(&self) -> EnergyRole {
        EnergyRole::Source
    }
}

const USE_CR: &str = "useCrInput true: signal input cr for the rolling resistance coefficient";
const USE_INCLINATION: &str =
    "useInclinationInput true: signal input inclination = tan(angle) for the inclination";

struct RollingResistance {
    f_weight: f64,
    use_cr: bool,
    cr: f64,
    use_inclination: bool,
    inclination: f64,
    reg: Reg,
    v0: f64,
    use_support: bool,
}

impl RollingResistance {
    fn law(&self, b: &mut Builder) -> ModelResult<RollLaw> {
        Ok(RollLaw {
            cr: Source::of(b, self.use_cr, "cr", self.cr)?,
            inclination: Source::of(b, self.use_inclination, "inclination", self.inclination)?,
            f_weight: self.f_weight,
            reg: self.reg,
            v0: self.v0,
        })
    }
}

impl Component for RollingResistance {
    fn ports(&self) -> Ports {
        let mech = with_support(&["flange"], self.use_support);
        let mut signal_in = vec![];
        if self.use_inclination {
            signal_in.push("inclination");
        }
        if self.use_cr {
            signal_in.push("cr");
        }
        Ports {
            translational: mech.clone(),
            mech,
            signal_in,
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nf, ns) = (b.node("flange")?, b.node("support")?);
        let rel = b.rel(&[("flange", 1.0), ("support", -1.0)])?;
        let law = self.law(b)?;
        let law = b.add_law(rel.clone(), Box::new(law));
        // PartialForce: f = flange.f
        b.output("f", Out::LawTau(law, 1.0));
        b.output("s", Out::Angle(rel.clone()));
        b.output("v", Out::Speed(rel));
        b.output("lossPower", Out::LawLoss(law));
        b.flange("flange", nf, Some(Out::LawTau(law, 1.0)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::LawTau(law, -1.0)))?;
        }
        Ok(())
    }
}

fn rolling_resistance(p: &Params) -> ModelResult<Box<dyn Component>> {
    let f_weight = p.required("fWeight [N] Wheel load due to gravity")?;
    let f_weight = p.at_least("fWeight", f_weight, 0.0)?;
    let use_cr = p.boolean(USE_CR, false)?;
    let cr = p.real(
        "CrConstant [1] Constant rolling resistance coefficient",
        0.01,
    )?;
    let cr = p.at_least("CrConstant", cr, 0.0)?;
    let use_inclination = p.boolean(USE_INCLINATION, false)?;
    let inclination = p.real(
        "inclinationConstant [1] Constant inclination = tan(angle)",
        0.0,
    )?;
    let reg = regularization(p)?;
    let v0 = p.positive("v0", p.real("v0 [m/s] Regularization below v0", 0.1)?)?;
    let use_support = p.boolean(
        "useSupport true: enable the support connector (else the housing is fixed at position 0)",
        false,
    )?;
    Ok(Box::new(RollingResistance {
        f_weight,
        use_cr,
        cr,
        use_inclination,
        inclination,
        reg,
        v0,
        use_support,
    }))
}

struct Vehicle {
    m: f64,
    g: f64,
    j: f64,
    r: f64,
    /// `Cd·A·rho/2`.
    drag: f64,
    use_wind: bool,
    wind: f64,
    roll: RollingResistance,
    s: InitValue,
    v: InitValue,
}

impl Component for Vehicle {
    fn ports(&self) -> Ports {
        let mut signal_in = vec![];
        if self.roll.use_inclination {
            signal_in.push("inclination");
        }
        if self.roll.use_cr {
            signal_in.push("cr");
        }
        if self.use_wind {
            signal_in.push("vWind");
        }
        Ports {
            mech: vec!["flangeR", "flangeT"],
            translational: vec!["flangeT"],
            signal_in,
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (nr, nt) = (b.node("flangeR")?, b.node("flangeT")?);
        b.add_mass(nr, self.j);
        b.add_mass(nt, self.m);
        // the rolling wheel: R·flangeR.phi = flangeT.s, a permanent row (no power lost)
        let row = b.rel(&[("flangeR", self.r), ("flangeT", -1.0)])?;
        b.add_constraint(row.clone(), false)?;
        b.init_constraint(row);
        let rel = Rel::of(&[(nt, 1.0)]);
        b.init_angle(rel.clone(), self.s, "s");
        b.init_speed(rel.clone(), self.v, "v");
        b.output("s", Out::Angle(rel.clone()));
        b.output("v", Out::Speed(rel.clone()));
        b.output("a", Out::Accel(rel.clone()));
        let wind = Source::of(b, self.use_wind, "vWind", self.wind)?;
        let drag = DragLaw {
            coefficient: self.drag,
            wind,
        };
        let drag = b.add_law(rel.clone(), Box::new(drag));
        let roll = self.roll.law(b)?;
        let roll = b.add_law(rel.clone(), Box::new(roll));
        let grade = GradeLaw {
            weight: self.m * self.g,
            inclination: Source::of(
                b,
                self.roll.use_inclination,
                "inclination",
                self.roll.inclination,
            )?,
        };
        let grade = b.add_law(rel, Box::new(grade));
        // MSL's sub-components' forces: flange.f of fDrag and fRoll, and fGrav.f (= −flange.f)
        b.output("fDrag.f", Out::LawTau(drag, 1.0));
        b.output("fRoll.f", Out::LawTau(roll, 1.0));
        b.output("fGrav.f", Out::LawTau(grade, -1.0));
        // the flanges take whatever their connections need
        b.flange("flangeR", nr, None)?;
        b.flange("flangeT", nt, None)?;
        b.flange_group(&["flangeR"], None)?;
        b.flange_group(&["flangeT"], None)
    }
}

fn vehicle(p: &Params) -> ModelResult<Box<dyn Component>> {
    let m = p.positive("m", p.required("m [kg] Total mass of vehicle")?)?;
    let g = p.positive("g", p.real("g [m/s2] Constant gravity acceleration", G_N)?)?;
    let j = p.at_least(
        "J",
        p.required("J [kg.m2] Total rotational inertia of drive train")?,
        0.0,
    )?;
    let r = p.positive("R", p.required("R [m] Wheel radius")?)?;
    let a = p.at_least("A", p.real("A [m2] Cross section of vehicle", 1.0)?, 0.0)?;
    let cd = p.at_least(
        "Cd",
        p.real("Cd [1] Drag resistance coefficient", 0.5)?,
        0.0,
    )?;
    let rho = p.at_least("rho", p.real("rho [kg/m3] Density of air", 1.2)?, 0.0)?;
    let use_wind = p.boolean(
        "useWindInput true: signal input vWind for the wind velocity",
        false,
    )?;
    let wind = p.real("vWindConstant [m/s] Constant wind velocity", 0.0)?;
    let use_cr = p.boolean(USE_CR, false)?;
    let cr = p.real(
        "CrConstant [1] Constant rolling resistance coefficient",
        0.015,
    )?;
    let cr = p.at_least("CrConstant", cr, 0.0)?;
    let v_reg = p.positive(
        "vReg",
        p.real("vReg [m/s] Velocity for regularization around 0", 1e-3)?,
    )?;
    let use_inclination = p.boolean(USE_INCLINATION, false)?;
    let inclination = p.real(
        "inclinationConstant [1] Constant inclination = tan(angle)",
        0.0,
    )?;
    let s = p.init("s [m] Position of vehicle (start value)", 0.0)?;
    let v = p.init("v [m/s] Velocity of vehicle (start value)", 0.0)?;
    Ok(Box::new(Vehicle {
        m,
        g,
        j,
        r,
        drag: cd * a * rho / 2.0,
        use_wind,
        wind,
        roll: RollingResistance {
            f_weight: m * g,
            use_cr,
            cr,
            use_inclination,
            inclination,
            reg: Reg::Linear,
            v0: v_reg,
            use_support: false,
        },
        s,
        v,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.RollingResistance",
        "Modelica.Mechanics.Translational.Components.RollingResistance",
        "Resistance of a rolling wheel",
        rolling_resistance,
    ),
    Entry::new(
        "Translational.Vehicle",
        "Modelica.Mechanics.Translational.Components.Vehicle",
        "Simple vehicle model",
        vehicle,
    ),
];
