//! Translational `Brake` and `SupportFriction`: the rotational Brake and BearingFriction
//! (`components::friction::Brake`, one `FrictionElem` with MSL's `PartialFriction` logic) under
//! MSL's translational names (`f`, `f0`, `f0_max`, `s`, `v`) and units. No stick/slip logic
//! lives here: only the parameter declarations of the translational classes.

use crate::components::friction::fade::read_fade;
use crate::components::friction::wear::read_wear;
use crate::components::friction::{friction_table, Brake, FrictionParams, TRANSLATIONAL};
use crate::components::{decl::USE_HEAT_PORT, Component, Entry};
use crate::error::ModelResult;
use crate::model::Params;

const USE_SUPPORT: &str =
    "useSupport true: enable the support connector (else the housing is fixed at position 0)";
const PEAK: &str = "peak [1] Peak for maximum value of mu at v==0 (mu0_max = peak*mu_pos[1,2])";
const V_SMALL: &str = "v_small [m/s] Relative velocity near to zero (see model info text)";

/// `v_small`: Translational's PartialFriction has 1e-3 m/s (Rotational's w_small is 1e10).
fn v_small(p: &Params) -> ModelResult<f64> {
    p.positive("v_small", p.real(V_SMALL, 1.0e-3)?)
}

fn brake(p: &Params) -> ModelResult<Box<dyn Component>> {
    let mu_pos = friction_table(
        p,
        "mu_pos [m/s, 1] Positive sliding friction coefficient [-] as function of v [m/s] \
         (v>=0): rows [v, mu], linear between rows; beyond the last row as `extrapolation` says \
         (MSL: linearly through the last two rows)",
        &[&[0.0, 0.5]],
        "coefficients",
    )?;
    let peak = p.at_least("peak", p.real(PEAK, 1.0)?, 1.0)?;
    let cgeo = p.real(
        "cgeo [1] Geometry constant containing friction distribution assumption",
        1.0,
    )?;
    let cgeo = p.at_least("cgeo", cgeo, 0.0)?;
    let fn_max = p.at_least(
        "fn_max",
        p.required("fn_max [N] Maximum normal force")?,
        0.0,
    )?;
    let use_heat_port = p.boolean(USE_HEAT_PORT, false)?;
    let params = FrictionParams {
        mu_pos,
        peak,
        cgeo,
        fn_max,
        w_small: v_small(p)?,
        use_heat_port,
        fade: read_fade(p, use_heat_port, peak, true)?,
        wear: read_wear(p, true)?,
    };
    Ok(Box::new(Brake {
        p: params,
        use_support: p.boolean(USE_SUPPORT, false)?,
        bearing: false,
        names: &TRANSLATIONAL,
    }))
}

/// SupportFriction: `f_pos` is the sliding force itself (fn ≡ 1, cgeo ≡ 1); never free.
fn support_friction(p: &Params) -> ModelResult<Box<dyn Component>> {
    let f_pos = friction_table(
        p,
        "f_pos [m/s, N] Positive sliding friction characteristic (v>=0): rows [v, f], linear \
         between rows; beyond the last row as `extrapolation` says (MSL: linearly through the \
         last two rows)",
        &[&[0.0, 1.0]],
        "forces",
    )?;
    let peak = p.at_least(
        "peak",
        p.real(
            "peak [1] Peak for maximum friction force at v==0 (f0_max = peak*f_pos[1,2])",
            1.0,
        )?,
        1.0,
    )?;
    let params = FrictionParams {
        mu_pos: f_pos,
        peak,
        cgeo: 1.0,
        fn_max: 1.0,
        w_small: v_small(p)?,
        use_heat_port: p.boolean(USE_HEAT_PORT, false)?,
        fade: None,
        wear: None,
    };
    Ok(Box::new(Brake {
        p: params,
        use_support: p.boolean(USE_SUPPORT, false)?,
        bearing: true,
        names: &TRANSLATIONAL,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Translational.Brake",
        "Modelica.Mechanics.Translational.Components.Brake",
        "Brake based on Coulomb friction",
        brake,
    ),
    Entry::new(
        "Translational.SupportFriction",
        "Modelica.Mechanics.Translational.Components.SupportFriction",
        "Coulomb friction in support",
        support_friction,
    ),
];
