//! Coulomb friction elements with MSL's stick/slip logic (`PartialFriction`): `Brake` (shaft
//! against its housing), `Clutch` (between two shafts) and `BearingFriction` (a torque table, no
//! normal force). They share `FrictionElem`; the Boolean logic is in `logic`.

pub(crate) mod fade;
pub mod lossy_gear;
pub(crate) mod wear;

use super::{heat_port, with_support, Component, Entry, Ports};
use crate::components::decl::{PEAK, PHI_REL, USE_HEAT_PORT, USE_SUPPORT, W_REL, W_SMALL};
use crate::error::ModelResult;
use crate::lookup_table::Table1D;
use crate::model::{InitValue, Params};
use crate::switching::fade::Fade;
use crate::switching::friction::{FrictionElem, OneWay};
use crate::switching::logic::{self, Discrete};
use crate::system::outputs::SwitchVar as V;
use crate::system::{Builder, Out, Rel};

pub(crate) struct FrictionParams {
    pub mu_pos: Table1D,
    pub peak: f64,
    pub cgeo: f64,
    pub fn_max: f64,
    pub w_small: f64,
    pub use_heat_port: bool,
    /// Beyond MSL: friction over temperature and normal force (`fade`); None: MSL's.
    pub fade: Option<Fade>,
    /// The `wear` record (a stiction extension), if given.
    pub wear: Option<wear::WearConfig>,
}

/// The names a friction element reports under, by domain (MSL's Rotational and Translational
/// `PartialFriction`): the stick/slip machinery is one, its vocabulary two.
pub(crate) struct FrictionNames {
    pub tau: &'static str,
    pub tau0: &'static str,
    pub tau0_max: &'static str,
    /// The absolute position, speed of a Brake's shaft.
    pub pos: &'static str,
    pub speed: &'static str,
    /// BearingFriction's table (the friction torque or force itself).
    pub bearing_table: &'static str,
    pub translational: bool,
}

pub(crate) const ROTATIONAL: FrictionNames = FrictionNames {
    tau: "tau",
    tau0: "tau0",
    tau0_max: "tau0_max",
    pos: "phi",
    speed: "w",
    bearing_table: "tau_pos",
    translational: false,
};

pub(crate) const TRANSLATIONAL: FrictionNames = FrictionNames {
    tau: "f",
    tau0: "f0",
    tau0_max: "f0_max",
    pos: "s",
    speed: "v",
    bearing_table: "f_pos",
    translational: true,
};

const CGEO: &str =
    "cgeo [1] Geometry constant with the friction distribution, N*(ro + ri)/2 (a length)";
const FN_MAX: &str = "fn_max [N] Maximum normal force (at f_normalized = 1)";

fn read_params(p: &Params) -> ModelResult<FrictionParams> {
    let mu_pos = friction_table(
        p,
        "mu_pos [rad/s, 1] Positive sliding friction coefficient: rows [w, mu] for w >= 0, \
         linear between rows; beyond the last row as `extrapolation` says (MSL: linearly \
         through the last two rows)",
        &[&[0.0, 0.5]],
        "coefficients",
    )?;
    let peak = p.at_least("peak", p.real(PEAK, 1.0)?, 1.0)?;
    let use_heat_port = p.boolean(USE_HEAT_PORT, false)?;
    Ok(FrictionParams {
        mu_pos,
        peak,
        cgeo: p.at_least("cgeo", p.real(CGEO, 1.0)?, 0.0)?,
        fn_max: p.at_least("fn_max", p.required(FN_MAX)?, 0.0)?,
        w_small: p.positive("w_small", p.real(W_SMALL, 1.0e10)?)?,
        use_heat_port,
        fade: fade::read_fade(p, use_heat_port, peak, false)?,
        wear: wear::read_wear(p, false)?,
    })
}

/// The declaration of a friction table's `extrapolation`.
const EXTRAPOLATION: &str = "extrapolation How the friction table continues beyond its rows: \
     LastTwoPoints (MSL's CombiTable1D: linearly through the first or last two rows; a run whose \
     slip reaches a speed where that value falls below 0 stops there with an error) or \
     HoldLastPoint (the first or last row's value)";

/// A friction characteristic (`mu_pos`, `tau_pos`): its values (`what`) never negative — a
/// negative coefficient would make the friction drive the motion —, its abscissa increasing,
/// and its value at w = 0 (`mu0`, extrapolated if the first row is not at 0) not negative
/// either; then `extrapolation`.
pub(crate) fn friction_table(
    p: &Params,
    decl: &'static str,
    default: &[&[f64]],
    what: &str,
) -> ModelResult<Table1D> {
    let rows = p.matrix(decl, 2, default)?;
    let name = crate::model::parse_decl(decl).0;
    p.table_at_least(name, &rows, 0.0, what)?;
    let table = Table1D::from_rows(p, name, &rows, 1)?;
    let extrapolation = p.choice(
        EXTRAPOLATION,
        &["LastTwoPoints", "HoldLastPoint"],
        "LastTwoPoints",
    )?;
    let table = if extrapolation == "HoldLastPoint" {
        table.holding()
    } else {
        table
    };
    let at_rest = table.eval(0.0);
    if at_rest < 0.0 && !p.in_catalogue() {
        return Err(p.error(
            name,
            format!(
                "{what} must be >= 0, but the table extrapolates to {at_rest} at w = 0 \
                 (linearly through its first two rows); add a row at w = 0"
            ),
        ));
    }
    Ok(table)
}

/// Outputs every friction element reports (MSL names), plus its heat port.
fn friction_outputs(
    b: &mut Builder,
    k: usize,
    slot: Option<usize>,
    heat: Option<usize>,
    one_way: bool,
    names: &FrictionNames,
) {
    if let Some(slot) = slot {
        b.output("mu", Out::Switch(k, V::Mu));
        b.output("fn", Out::Switch(k, V::Fn));
        b.output("f_normalized", Out::Signal(slot));
        // OneWayClutch calls its normalized force `u`; its `free` is protected in MSL
        b.output(
            if one_way { "u" } else { "free" },
            if one_way {
                Out::Signal(slot)
            } else {
                Out::Switch(k, V::Free)
            },
        );
    }
    let logic: &[(&str, V)] = if one_way {
        &[("startForward", V::StartForward), ("stuck", V::Stuck)]
    } else {
        &[
            ("mode", V::Mode),
            ("startForward", V::StartForward),
            ("startBackward", V::StartBackward),
        ]
    };
    for &(name, var) in [
        (names.tau, V::Tau),
        ("lossPower", V::LossPower),
        ("locked", V::Locked),
        ("sa", V::Sa),
        (names.tau0, V::Tau0),
        (names.tau0_max, V::Tau0Max),
    ]
    .iter()
    .chain(logic)
    {
        b.output(name, Out::Switch(k, var));
    }
    if let Some(node) = heat {
        b.output("heatPort.T", Out::HeatT(node));
        b.output(
            "heatPort.Q_flow",
            Out::Scaled(Box::new(Out::Switch(k, V::LossPower)), -1.0),
        );
    }
}

/// Brake and BearingFriction: friction between a shaft and its support.
// Ports alike in shape to IdealGear and LossyGear (see gears.rs).
pub(crate) struct Brake {
    pub p: FrictionParams,
    pub use_support: bool,
    /// BearingFriction: no `f_normalized`; `mu_pos` holds `tau_pos`.
    pub bearing: bool,
    pub names: &'static FrictionNames,
}

impl Component for Brake {
    fn ports(&self) -> Ports {
        let mech = with_support(&["flange_a", "flange_b"], self.use_support);
        Ports {
            must_connect: mech.clone(),
            translational: if self.names.translational {
                mech.clone()
            } else {
                vec![]
            },
            mech,
            joins: vec![("flange_a", "flange_b")],
            signal_in: if self.bearing {
                vec![]
            } else {
                vec!["f_normalized"]
            },
            heat: heat_port(self.p.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, ns) = (b.node("flange_a")?, b.node("support")?);
        let rel = b.rel(&[("flange_a", 1.0), ("support", -1.0)])?;
        if rel.is_zero() {
            return Err(
                b.error("its flange is rigidly connected to its support: it can never slip")
            );
        }
        let kind = if self.bearing {
            Kind::Bearing
        } else {
            Kind::Brake
        };
        let k = add_elem(b, &self.p, rel.clone(), kind, self.names)?;
        b.output(self.names.pos, Out::Angle(rel));
        b.output(self.names.speed, Out::Switch(k, V::W));
        b.output("a", Out::Switch(k, V::A));
        b.flange("flange_a", na, None)?;
        b.flange("flange_b", na, None)?;
        // flange_a.tau + flange_b.tau = tau; support.tau = −tau
        b.flange_group(&["flange_a", "flange_b"], Some(Out::Switch(k, V::Tau)))?;
        if self.use_support {
            b.flange(
                "support",
                ns,
                Some(Out::Scaled(Box::new(Out::Switch(k, V::Tau)), -1.0)),
            )?;
        }
        Ok(())
    }
}

/// Which friction element `add_elem` makes.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Brake,
    Bearing,
    Clutch,
    /// A OneWayClutch with the start values of `stuck` and `startForward`.
    OneWay {
        stuck: bool,
        start_forward: bool,
    },
}

fn add_elem(
    b: &mut Builder,
    p: &FrictionParams,
    rel: Rel,
    kind: Kind,
    names: &FrictionNames,
) -> ModelResult<usize> {
    let slot = if kind == Kind::Bearing {
        None
    } else {
        Some(b.signal_in("f_normalized")?)
    };
    let heat = if p.use_heat_port {
        Some(b.heat_node("heatPort")?)
    } else {
        None
    };
    let fade = p.fade.as_ref().map(|f| Box::new(tapped(b, f, heat)));
    let mu0 = p.mu_pos.eval(0.0);
    let (one_way, initial, peak) = match kind {
        Kind::OneWay {
            stuck,
            start_forward,
        } => (
            Some(OneWay {
                tau0_max_low: ONE_WAY_EPS * mu0 * p.cgeo * p.fn_max,
            }),
            Discrete {
                mode: if stuck { logic::STUCK } else { logic::FORWARD },
                start_forward,
                start_backward: false,
            },
            p.peak.max(1.0 + ONE_WAY_EPS),
        ),
        _ => (None, Discrete::INITIAL, p.peak),
    };
    let k = b.add_switching(Box::new(FrictionElem {
        name: b.name().to_string(),
        rel,
        mu0,
        table_name: if kind == Kind::Bearing {
            names.bearing_table
        } else {
            "mu_pos"
        },
        // a mu_table holds its edges: never negative
        negative_beyond: match fade.as_ref().and_then(|f| f.mu_table.as_ref()) {
            Some(_) => f64::INFINITY,
            None => p.mu_pos.zero_beyond_last(),
        },
        mu_pos: p.mu_pos.clone(),
        peak,
        cgeo: p.cgeo,
        fn_max: p.fn_max,
        w_small: p.w_small,
        input: slot,
        clutch_quirk: kind == Kind::Clutch,
        heat_node: heat,
        one_way,
        initial,
        stop: None,
        fade,
    }));
    friction_outputs(b, k, slot, heat, one_way.is_some(), names);
    if let Some(config) = &p.wear {
        wear::attach(b, k, config, heat)?;
    }
    Ok(k)
}

/// A fade with the heat port's temperature tapped, when a table reads it (`read_fade` has
/// checked that the port is there).
fn tapped(b: &mut Builder, f: &Fade, heat: Option<usize>) -> Fade {
    let mut f = f.clone();
    if let (Some(param), Some(node)) = (fade::thermal_param(&f), heat) {
        f.temperature = Some(b.temperature_tap_for(node, "its friction", Some(param)));
    }
    f
}

fn brake(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Brake {
        p: read_params(p)?,
        use_support: p.boolean(USE_SUPPORT, false)?,
        bearing: false,
        names: &ROTATIONAL,
    }))
}

/// BearingFriction (spec §5.4): `tau_pos` is the sliding torque itself; never free.
fn bearing_friction(p: &Params) -> ModelResult<Box<dyn Component>> {
    let params = FrictionParams {
        mu_pos: friction_table(
            p,
            "tau_pos [rad/s, N.m] Positive sliding friction torque: rows [w, tau] for w >= 0, \
             linear between rows; beyond the last row as `extrapolation` says (MSL: linearly \
             through the last two rows)",
            &[&[0.0, 1.0]],
            "torques",
        )?,
        peak: p.at_least("peak", p.real(PEAK, 1.0)?, 1.0)?,
        cgeo: 1.0,
        fn_max: 1.0,
        w_small: p.positive("w_small", p.real(W_SMALL, 1.0e10)?)?,
        use_heat_port: p.boolean(USE_HEAT_PORT, false)?,
        fade: None,
        wear: None,
    };
    Ok(Box::new(Brake {
        p: params,
        use_support: p.boolean(USE_SUPPORT, false)?,
        bearing: true,
        names: &ROTATIONAL,
    }))
}

/// Clutch and OneWayClutch (spec §5.3: a freewheel in parallel with a clutch; it slides freely
/// while `w_rel > 0` and locks when `w_rel` would turn negative).
struct Clutch {
    p: FrictionParams,
    phi_rel: InitValue,
    w_rel: InitValue,
    /// OneWayClutch: the start values of `stuck` and `startForward`.
    one_way: Option<(bool, bool)>,
}

impl Component for Clutch {
    fn ports(&self) -> Ports {
        Ports {
            mech: vec!["flange_a", "flange_b"],
            must_connect: vec!["flange_a", "flange_b"],
            signal_in: vec!["f_normalized"],
            heat: heat_port(self.p.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb) = (b.node("flange_a")?, b.node("flange_b")?);
        let rel = Rel::between(na, nb);
        if rel.is_zero() {
            return Err(b.error("flange_a and flange_b are rigidly connected: it can never slip"));
        }
        let kind = match self.one_way {
            Some((stuck, start_forward)) => Kind::OneWay {
                stuck,
                start_forward,
            },
            None => Kind::Clutch,
        };
        let k = add_elem(b, &self.p, rel.clone(), kind, &ROTATIONAL)?;
        b.init_angle(rel.clone(), self.phi_rel, "phi_rel");
        b.init_speed(rel.clone(), self.w_rel, "w_rel");
        b.output("phi_rel", Out::Angle(rel));
        b.output("w_rel", Out::Switch(k, V::W));
        b.output("a_rel", Out::Switch(k, V::A));
        b.flange(
            "flange_a",
            na,
            Some(Out::Scaled(Box::new(Out::Switch(k, V::Tau)), -1.0)),
        )?;
        b.flange("flange_b", nb, Some(Out::Switch(k, V::Tau)))?;
        Ok(())
    }
}

fn clutch(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Clutch {
        p: read_params(p)?,
        phi_rel: p.init(PHI_REL, 0.0)?,
        w_rel: p.init(W_REL, 0.0)?,
        one_way: None,
    }))
}

pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Brake",
        "Modelica.Mechanics.Rotational.Components.Brake",
        "Brake based on Coulomb friction",
        brake,
    ),
    Entry::new(
        "Clutch",
        "Modelica.Mechanics.Rotational.Components.Clutch",
        "Clutch based on Coulomb friction",
        clutch,
    ),
    Entry::new(
        "BearingFriction",
        "Modelica.Mechanics.Rotational.Components.BearingFriction",
        "Coulomb friction in bearings",
        bearing_friction,
    ),
    Entry::new(
        "OneWayClutch",
        "Modelica.Mechanics.Rotational.Components.OneWayClutch",
        "Series connection of freewheel and clutch",
        one_way_clutch,
    ),
];

/// MSL's `eps0`: the relative hysteresis of the OneWayClutch.
const ONE_WAY_EPS: f64 = 1.0e-4;

fn one_way_clutch(p: &Params) -> ModelResult<Box<dyn Component>> {
    Ok(Box::new(Clutch {
        p: read_params(p)?,
        phi_rel: p.init(PHI_REL, 0.0)?,
        w_rel: p.init(W_REL, 0.0)?,
        one_way: Some((
            p.boolean_start(
                "stuck Start value of stuck (w_rel = 0): its pre() value at initialization",
                false,
            )?,
            p.boolean_start(
                "startForward Start value of startForward: its pre() value at initialization",
                false,
            )?,
        )),
    }))
}
