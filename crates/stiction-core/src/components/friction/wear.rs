//! The `wear` parameter of the friction elements (an extension of MSL): a record naming a wear
//! model and its constants, read and checked before any run, and attached to the element at
//! build time as a state of the run (`crate::wear`), reported as `wearVolume` (and `thickness`
//! where the pad's area and thickness are given).

use crate::components::decl::USE_HEAT_PORT;
use crate::error::ModelResult;
use crate::model::Params;
use crate::system::{Builder, Out};
use crate::wear::{Wear, WearModel};

const WEAR: &str = "wear Wear model (a stiction extension): { model = \"archard\", k, H, r_eff }, \
     { model = \"energy\", alpha } or { model = \"arrhenius\", alpha0, k0, E, T_threshold }, \
     each optionally with A [m2] and thickness [m] (then `thickness` is reported), \
     thickness_min [m] (the run stops with an error when reached) and nominal [m3]";

/// The checked `wear` record of one element.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WearConfig {
    /// Its model; an Arrhenius model's temperature slot is filled in at build time.
    model: WearModel,
    nominal: f64,
    /// Pad area, initial thickness and the limit thickness.
    pad: Option<(f64, f64, f64)>,
}

/// The keys of each model besides the common ones.
fn model_keys(model: &str, translational: bool) -> Option<&'static [&'static str]> {
    Some(match model {
        "archard" if translational => &["k", "H"],
        "archard" => &["k", "H", "r_eff"],
        "energy" => &["alpha"],
        "arrhenius" => &["alpha0", "k0", "E", "T_threshold"],
        _ => return None,
    })
}

const COMMON: &[&str] = &["model", "A", "thickness", "thickness_min", "nominal"];

/// Reads `wear` (after `useHeatPort`: the Arrhenius model reads the heat port's temperature);
/// None when not given.
pub(crate) fn read_wear(p: &Params, translational: bool) -> ModelResult<Option<WearConfig>> {
    let Some(t) = p.record(WEAR)? else {
        return Ok(None);
    };
    let use_heat_port = p.boolean(USE_HEAT_PORT, false)?;
    let err = |m: String| p.error("wear", m);
    let model = match t.get("model").map(|v| v.as_str()) {
        Some(Some(m)) => m,
        Some(None) => return Err(err("'model' must be a string".into())),
        None => {
            return Err(err(
                "'model' missing (\"archard\", \"energy\" or \"arrhenius\")".into(),
            ))
        }
    };
    let keys = model_keys(model, translational).ok_or_else(|| {
        err(format!(
            "unknown model \"{model}\" (\"archard\", \"energy\" or \"arrhenius\")"
        ))
    })?;
    if let Some(key) = t
        .keys()
        .find(|k| !keys.contains(&k.as_str()) && !COMMON.contains(&k.as_str()))
    {
        let known: Vec<&str> = keys.iter().chain(&COMMON[1..]).copied().collect();
        return Err(err(format!(
            "unknown key '{key}' for model \"{model}\" (known: {})",
            known.join(", ")
        )));
    }
    let get = |key: &str, min: f64, strict: bool, default: Option<f64>| -> ModelResult<f64> {
        let x = match t.get(key) {
            Some(v) => (v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
                .filter(|x| x.is_finite())
                .ok_or_else(|| err(format!("'{key}' must be a finite number, got {v}")))?,
            None => default.ok_or_else(|| err(format!("model \"{model}\" needs '{key}'")))?,
        };
        let bad = if strict { x <= min } else { x < min };
        if bad && !p.in_catalogue() {
            let op = if strict { ">" } else { ">=" };
            return Err(err(format!("'{key}' must be {op} {min}, got {x}")));
        }
        Ok(x)
    };
    let model = match model {
        "archard" => WearModel::Archard {
            k: get("k", 0.0, false, None)?,
            h: get("H", 0.0, true, None)?,
            r_eff: if translational {
                1.0
            } else {
                get("r_eff", 0.0, true, None)?
            },
        },
        "energy" => WearModel::Energy {
            alpha: get("alpha", 0.0, false, None)?,
        },
        _ => {
            if !use_heat_port && !p.in_catalogue() {
                return Err(err(
                    "model \"arrhenius\" reads the heat port's temperature: set useHeatPort = \
                     true and connect heatPort to a HeatCapacitor or a FixedTemperature"
                        .into(),
                ));
            }
            WearModel::Arrhenius {
                alpha0: get("alpha0", 0.0, false, Some(0.0))?,
                k0: get("k0", 0.0, false, None)?,
                e_a: get("E", 0.0, false, None)?,
                t_threshold: get("T_threshold", 0.0, true, None)?,
                slot: usize::MAX,
            }
        }
    };
    let pad = match (t.contains_key("A"), t.contains_key("thickness")) {
        (true, true) => {
            let (area, h0) = (
                get("A", 0.0, true, None)?,
                get("thickness", 0.0, true, None)?,
            );
            let h_min = get("thickness_min", 0.0, false, Some(0.0))?;
            if h_min >= h0 && !p.in_catalogue() {
                return Err(err(format!(
                    "'thickness_min' ({h_min}) must be below 'thickness' ({h0})"
                )));
            }
            Some((area, h0, h_min))
        }
        (false, false) if t.contains_key("thickness_min") => {
            return Err(err(
                "'thickness_min' needs the pad's 'A' and 'thickness'".into()
            ))
        }
        (false, false) => None,
        _ => {
            return Err(err(
                "'A' and 'thickness' go together (the pad's area and thickness)".into(),
            ))
        }
    };
    let nominal = match pad {
        Some((area, h0, _)) => get("nominal", 0.0, true, Some(area * h0))?,
        None => get("nominal", 0.0, true, Some(DEFAULT_NOMINAL))?,
    };
    Ok(Some(WearConfig {
        model,
        nominal,
        pad,
    }))
}

/// The volume scale without a pad: a cubic centimetre.
const DEFAULT_NOMINAL: f64 = 1e-6;

/// Attaches the wear of switching element `k` (heat node `heat`) to the run and reports it.
pub(crate) fn attach(
    b: &mut Builder,
    k: usize,
    config: &WearConfig,
    heat: Option<usize>,
) -> ModelResult<()> {
    let mut model = config.model.clone();
    if let WearModel::Arrhenius { slot, .. } = &mut model {
        let node = heat.ok_or_else(|| b.error("wear: model \"arrhenius\" needs the heat port"))?;
        *slot = b.temperature_tap_for(node, "its wear", None);
    }
    let wear = Wear {
        element: k,
        name: b.name().to_string(),
        model,
        nominal: config.nominal,
        limit: (config.pad).map(|(area, h0, h_min)| (area * (h0 - h_min), h_min)),
    };
    let i = b.add_wear(wear);
    b.output("wearVolume", Out::Wear(i, 1.0, 0.0));
    if let Some((area, h0, _)) = config.pad {
        b.output("thickness", Out::Wear(i, -1.0 / area, h0));
    }
    Ok(())
}
