//! The event iteration. At an event instant the continuous state is fixed; the Booleans of every
//! friction element and LossyGear are solved as MSL's mixed system (fixed point over the
//! relations: take their current values, solve the linear system for the mode they imply,
//! re-evaluate them with hysteresis, repeat), then `pre()` is updated and the whole is solved
//! again until nothing changes (spec §1.6–1.7, §10.2).

use std::collections::HashMap;
use std::rc::Rc;

use crate::engine::eval::{evaluate, kinematics, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::error::SimError;
use crate::switching::friction::FrictionState;
use crate::switching::logic::{Discrete, Quantities, Relations};
use crate::switching::lossy_gear::{GearRelations, GearState};
use crate::system::System;

/// Factored mode matrices by mode: a mode met again costs nothing.
#[derive(Default)]
pub struct ModeCache {
    map: HashMap<Vec<u64>, Rc<ModeMatrix>>,
    pub factorizations: usize,
}

impl ModeCache {
    pub fn get(
        &mut self,
        sys: &System,
        disc: &DiscreteState,
        t: f64,
    ) -> Result<Rc<ModeMatrix>, SimError> {
        let locked = disc.locked_set();
        let gears = disc.gear_modes(sys);
        let key: Vec<u64> = locked
            .iter()
            .map(|&l| l as u64)
            .chain(gears.iter().flat_map(|g| [g.locked as u64, g.c1.to_bits()]))
            .collect();
        if let Some(mm) = self.map.get(&key) {
            return Ok(mm.clone());
        }
        let mm = ModeMatrix::factor(sys, &locked, &gears, t)?;
        self.factorizations += 1;
        let mm = Rc::new(mm);
        self.map.insert(key, mm.clone());
        Ok(mm)
    }
}

/// An element changed its mode at an event.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeChange {
    pub time: f64,
    pub component: String,
    pub old_mode: i8,
    pub new_mode: i8,
}

const MAX_PASSES: usize = 50;

/// What the mixed system iterates on: the relations of each friction element and LossyGear.
#[derive(Debug, Clone, PartialEq)]
struct RelationValues {
    friction: Vec<Relations>,
    gears: Vec<GearRelations>,
}

impl RelationValues {
    fn of(disc: &DiscreteState) -> Self {
        RelationValues {
            friction: disc.friction.iter().map(|f| f.rel).collect(),
            gears: disc.gears.iter().map(|g| g.rel).collect(),
        }
    }

    /// Every relation true in either (start conditions set in either); the driving side of
    /// `self`. Speeds do not change within an event, so their relations agree anyway.
    fn or(&self, other: &RelationValues) -> RelationValues {
        let or = |a: &[bool], b: &[bool], i: usize| a[i] || b[i];
        RelationValues {
            friction: self
                .friction
                .iter()
                .zip(&other.friction)
                .map(|(a, b)| Relations(std::array::from_fn(|i| or(&a.0, &b.0, i))))
                .collect(),
            gears: self
                .gears
                .iter()
                .zip(&other.gears)
                .map(|(a, b)| {
                    let mut r = GearRelations(std::array::from_fn(|i| or(&a.0, &b.0, i)));
                    r.0[GearRelations::TAU_ETA_POS] = a.get(GearRelations::TAU_ETA_POS);
                    r
                })
                .collect(),
        }
    }

    /// The same with every start condition on `sa` false: each element that was stuck locks.
    fn nothing_starts(&self) -> RelationValues {
        let mut r = self.clone();
        for f in &mut r.friction {
            for i in [
                Relations::SA_ABOVE_MAX,
                Relations::SA_ABOVE,
                Relations::SA_BELOW_MAX,
                Relations::SA_BELOW,
            ] {
                f.0[i] = false;
            }
        }
        for g in &mut r.gears {
            g.0[GearRelations::SA_ABOVE_MAX_P] = false;
            g.0[GearRelations::SA_BELOW_MIN_M] = false;
        }
        r
    }

    /// The relations at the values in `ws`, from these (literal at initialization).
    fn updated(&self, sys: &System, ws: &Workspace, initial: bool) -> RelationValues {
        RelationValues {
            friction: (0..sys.frictions.len())
                .map(|k| {
                    let v = &ws.friction[k];
                    let q = Quantities {
                        sa: v.sa,
                        w: v.w,
                        tau0: v.tau0,
                        tau0_max: v.tau0_max,
                        w_small: sys.frictions[k].w_small,
                    };
                    self.friction[k].update(&q, initial)
                })
                .collect(),
            gears: (0..sys.lossy_gears.len())
                .map(|k| {
                    let v = &ws.gears[k];
                    self.gears[k].update(v.sa, v.loss_max_p, v.loss_min_m, v.w, v.tau_eta, initial)
                })
                .collect(),
        }
    }
}

/// Solves the discrete equations at (t, x). With `initial`, this is MSL's initialization: one
/// consistent solution with the start values as `pre()`; otherwise the full event iteration.
/// Time events before `horizon` have happened (see `signals::reached`).
#[allow(clippy::too_many_arguments)]
pub fn iterate(
    sys: &System,
    cache: &mut ModeCache,
    disc: &mut DiscreteState,
    t: f64,
    x: &[f64],
    initial: bool,
    horizon: f64,
    ws: &mut Workspace,
) -> Result<Vec<ModeChange>, SimError> {
    let before_f: Vec<i8> = disc.friction.iter().map(|f| f.pre.mode).collect();
    let before_g: Vec<i8> = disc.gears.iter().map(|g| g.pre.mode).collect();

    // Relations of force laws are evaluated literally at the event (no linear solve needed:
    // the previous mode's matrix may not even be regular, e.g. before initialization).
    {
        kinematics(sys, disc, t, x, horizon, ws);
        let mut z = [0.0; 4];
        for (k, law) in sys.laws.iter().enumerate() {
            let count = law.law.relation_count();
            if count > 0 {
                law.law
                    .relation_values(&ws.law_ctx(sys, disc, k), &mut z[..count]);
                for (r, &value) in z[..count].iter().enumerate() {
                    disc.relations[law.relation_base + r] = value >= 0.0;
                }
            }
        }
    }
    // The friction relations as they stand at the event, in the mode before it (between events
    // only those that matter were watched).
    if !initial {
        let mm = cache.get(sys, disc, t)?;
        evaluate(sys, &mm, disc, t, x, horizon, ws);
        let now = RelationValues::of(disc).updated(sys, ws, false);
        for (st, rel) in disc.friction.iter_mut().zip(now.friction) {
            st.rel = rel;
        }
        for (st, rel) in disc.gears.iter_mut().zip(now.gears) {
            st.rel = rel;
        }
    }

    for _pass in 0..MAX_PASSES {
        let pre_f: Vec<Discrete> = disc.friction.iter().map(|f| f.pre).collect();
        let pre_g: Vec<Discrete> = disc.gears.iter().map(|g| g.pre).collect();
        // free = (fn <= 0), from the signals at the event (evaluated above).
        let free: Vec<bool> = sys
            .frictions
            .iter()
            .map(|fe| fe.normal_force(&ws.signals) <= 0.0)
            .collect();
        let solved = solve_mixed(
            sys,
            cache,
            &pre_f,
            &pre_g,
            &free,
            RelationValues::of(disc),
            disc,
            t,
            x,
            initial,
            horizon,
            ws,
        )?;
        let new_f: Vec<Discrete> = (0..sys.frictions.len())
            .map(|k| {
                let st = &solved.friction[k];
                let (sf, sb) = (st.pre.start_forward, st.pre.start_backward);
                Discrete {
                    mode: sys.frictions[k].mode(free[k], pre_f[k], sf, sb, st.rel),
                    ..st.pre
                }
            })
            .collect();
        let new_g: Vec<Discrete> = (0..sys.lossy_gears.len())
            .map(|k| {
                let st = &solved.gears[k];
                let (sf, sb) = (st.pre.start_forward, st.pre.start_backward);
                Discrete {
                    mode: sys.lossy_gears[k].mode(pre_g[k], sf, sb, st.rel),
                    ..st.pre
                }
            })
            .collect();
        let settled = new_f == pre_f && new_g == pre_g;
        // With pre() = the new values, `locked` uses pre(mode) = mode, as between events.
        for (k, fe) in sys.frictions.iter().enumerate() {
            let p = new_f[k];
            disc.friction[k] = FrictionState {
                pre: p,
                locked: fe.locked(free[k], p, p.start_forward, p.start_backward),
                free: free[k],
                rel: solved.friction[k].rel,
            };
        }
        for (k, g) in sys.lossy_gears.iter().enumerate() {
            let p = new_g[k];
            disc.gears[k] = GearState {
                pre: p,
                locked: g.locked(p, p.start_forward, p.start_backward),
                rel: solved.gears[k].rel,
            };
        }
        if settled || initial {
            let changes = sys
                .frictions
                .iter()
                .map(|f| &f.name)
                .zip(before_f.iter().zip(&new_f).map(|(b, n)| (*b, n.mode)))
                .chain(
                    sys.lossy_gears
                        .iter()
                        .map(|g| &g.name)
                        .zip(before_g.iter().zip(&new_g).map(|(b, n)| (*b, n.mode))),
                )
                .filter(|(_, (old, new))| old != new)
                .map(|(name, (old, new))| ModeChange {
                    time: t,
                    component: name.clone(),
                    old_mode: old,
                    new_mode: new,
                })
                .collect();
            return Ok(changes);
        }
    }
    let names: Vec<&str> = sys
        .frictions
        .iter()
        .map(|f| f.name.as_str())
        .chain(sys.lossy_gears.iter().map(|g| g.name.as_str()))
        .collect();
    Err(SimError::EventIteration {
        time: t,
        message: format!(
            "event iteration did not reach a consistent mode after {MAX_PASSES} passes"
        ),
        elements: names.into_iter().map(String::from).collect(),
    })
}

/// One evaluation of the mixed system: relation values consistent with the accelerations and
/// torques they imply, for fixed `pre()` values, and the state they imply. The fixed point starts from the relations'
/// current values (the solution closest to the state before); if that cycles — an element that
/// starts one way is pushed back the other way, each direction implying the opposite — it
/// starts again from "nothing starts" (every stuck element locked); if that cycles too, two
/// elements hold the same motion and each alone breaks away while each alone holds: starting
/// is then the consistent answer.
#[allow(clippy::too_many_arguments)]
fn solve_mixed(
    sys: &System,
    cache: &mut ModeCache,
    pre_f: &[Discrete],
    pre_g: &[Discrete],
    free: &[bool],
    current: RelationValues,
    carried: &DiscreteState,
    t: f64,
    x: &[f64],
    initial: bool,
    horizon: f64,
    ws: &mut Workspace,
) -> Result<DiscreteState, SimError> {
    let limit = 4 * (sys.frictions.len() + sys.lossy_gears.len()) + 10;
    let locked_start = current.nothing_starts();
    let mut visited: Vec<RelationValues> = Vec::new();
    let mut rels = current;
    let mut restarted = false;
    for _ in 0..2 * limit {
        let trial = implied_state(sys, pre_f, pre_g, free, &rels, carried, initial);
        let mm = cache.get(sys, &trial, t)?;
        evaluate(sys, &mm, &trial, t, x, horizon, ws);
        let next = rels.updated(sys, ws, initial);
        if next == rels {
            return Ok(trial);
        }
        visited.push(rels.clone());
        if !visited.contains(&next) {
            rels = next;
        } else if !restarted {
            restarted = true;
            visited.clear();
            rels = locked_start.clone();
        } else {
            let started = next.or(&rels);
            if visited.contains(&started) {
                return Ok(implied_state(
                    sys, pre_f, pre_g, free, &started, carried, initial,
                ));
            }
            rels = started;
        }
    }
    Err(SimError::EventIteration {
        time: t,
        message: "the stick/slip Booleans of coupled friction elements do not settle (mixed system has no consistent solution)".into(),
        elements: sys
            .frictions
            .iter()
            .map(|f| f.name.clone())
            .chain(sys.lossy_gears.iter().map(|g| g.name.clone()))
            .collect(),
    })
}

/// The discrete state the relations imply with `pre()` fixed: each element's start flags and
/// whether it is locked (its `pre.mode` stays the pre-value).
fn implied_state(
    sys: &System,
    pre_f: &[Discrete],
    pre_g: &[Discrete],
    free: &[bool],
    rels: &RelationValues,
    carried: &DiscreteState,
    initial: bool,
) -> DiscreteState {
    DiscreteState {
        friction: (0..sys.frictions.len())
            .map(|k| {
                let fe = &sys.frictions[k];
                let rel = rels.friction[k];
                let (sf, sb) = fe.start_flags(pre_f[k], rel, initial);
                FrictionState {
                    pre: Discrete {
                        mode: pre_f[k].mode,
                        start_forward: sf,
                        start_backward: sb,
                    },
                    locked: fe.locked(free[k], pre_f[k], sf, sb),
                    free: free[k],
                    rel,
                }
            })
            .collect(),
        gears: (0..sys.lossy_gears.len())
            .map(|k| {
                let g = &sys.lossy_gears[k];
                let rel = rels.gears[k];
                let (sf, sb) = g.start_flags(pre_g[k], rel, initial);
                GearState {
                    pre: Discrete {
                        mode: pre_g[k].mode,
                        start_forward: sf,
                        start_backward: sb,
                    },
                    locked: g.locked(pre_g[k], sf, sb),
                    rel,
                }
            })
            .collect(),
        relations: carried.relations.clone(),
        inputs: carried.inputs.clone(),
    }
}
