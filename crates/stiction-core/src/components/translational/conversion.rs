//! Rotational components that join a rotational flange to a translational one
//! (`PartialElementaryRotationalToTranslational`): `IdealRollingWheel` and `IdealGearR2T`.
//! Each is one permanent constraint row across the two domains — the engine sees a gear — whose
//! multiplier gives the torque on `flangeR` and the force on `flangeT`.

use crate::components::{Component, Entry, Ports};
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out};

/// `(flangeR.phi − supportR.phi)·k_r = (flangeT.s − supportT.s)·k_t`.
struct RotToTrans {
    /// The wheel: `k_r = radius`, `k_t = 1`; the gear: `k_r = 1`, `k_t = ratio`.
    k_r: f64,
    k_t: f64,
    use_support_r: bool,
    use_support_t: bool,
}

impl Component for RotToTrans {
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
            mech,
            translational,
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        // an undeclared support is the implicit ground (MSL's internal Fixed)
        let (nr, nt) = (b.node("flangeR")?, b.node("flangeT")?);
        let (nsr, nst) = (b.node("supportR")?, b.node("supportT")?);
        let (kr, kt) = (self.k_r, self.k_t);
        let row = b.rel(&[
            ("flangeR", kr),
            ("supportR", -kr),
            ("flangeT", -kt),
            ("supportT", kt),
        ])?;
        // multiplier λ: flangeR.tau = k_r·λ, flangeT.f = −k_t·λ, so that
        // k_t·flangeR.tau + k_r·flangeT.f = 0 (no power is lost or stored)
        let k = b.add_constraint(row.clone(), false)?;
        b.init_constraint(row);
        b.flange("flangeR", nr, Some(Out::ConstraintTau(k, kr)))?;
        b.flange("flangeT", nt, Some(Out::ConstraintTau(k, -kt)))?;
        if self.use_support_r {
            b.flange("supportR", nsr, Some(Out::ConstraintTau(k, -kr)))?;
        }
        if self.use_support_t {
            b.flange("supportT", nst, Some(Out::ConstraintTau(k, kt)))?;
        }
        Ok(())
    }
}

fn supports(p: &Params, k_r: f64, k_t: f64) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(RotToTrans {
        k_r,
        k_t,
        use_support_r: p.boolean(
            "useSupportR true: enable the rotational support connector (else it is fixed at angle 0)",
            false,
        )?,
        use_support_t: p.boolean(
            "useSupportT true: enable the translational support connector (else it is fixed at position 0)",
            false,
        )?,
    }))
}

fn rolling_wheel(p: &Params) -> ModelResult<Box<dyn Component>> {
    let radius = p.positive("radius", p.real("radius [m] Wheel radius", 0.3)?)?;
    supports(p, radius, 1.0)
}

fn gear_r2t(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = p.real(
        "ratio [rad/m] Transmission ratio (flangeR.phi/flangeT.s)",
        1.0,
    )?;
    let ratio = p.nonzero("ratio", ratio)?;
    supports(p, 1.0, ratio)
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "IdealRollingWheel",
        "Modelica.Mechanics.Rotational.Components.IdealRollingWheel",
        "Simple 1-dim. model of an ideal rolling wheel without inertia",
        rolling_wheel,
    ),
    Entry::new(
        "IdealGearR2T",
        "Modelica.Mechanics.Rotational.Components.IdealGearR2T",
        "Gearbox transforming rotational into translational motion",
        gear_r2t,
    ),
];
