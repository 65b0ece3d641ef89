//! The event iteration. At an event instant the continuous state is fixed; the Booleans of every
//! friction element are solved as MSL's mixed system (fixed point over the Booleans: guess the
//! start flags, solve the linear system for that locked set, recompute the flags, repeat), then
//! `pre()` is updated and the whole is solved again until nothing changes (spec §1.6–1.7).

use std::collections::HashMap;
use std::rc::Rc;

use crate::components::friction::logic::{Discrete, Relations};
use crate::components::friction::FrictionState;
use crate::error::SimError;
use crate::system::eval::{evaluate, DiscreteState, Workspace};
use crate::system::kkt::ModeMatrix;
use crate::system::System;

/// Factored mode matrices by locked set: a mode met again costs nothing.
#[derive(Default)]
pub struct ModeCache {
    map: HashMap<Vec<bool>, Rc<ModeMatrix>>,
    pub factorizations: usize,
}

impl ModeCache {
    pub fn get(
        &mut self,
        sys: &System,
        locked: &[bool],
        t: f64,
    ) -> Result<Rc<ModeMatrix>, SimError> {
        if let Some(mm) = self.map.get(locked) {
            return Ok(mm.clone());
        }
        let mm = ModeMatrix::factor(sys, locked)
            .map_err(|message| SimError::Numerical { time: t, message })?;
        self.factorizations += 1;
        let mm = Rc::new(mm);
        self.map.insert(locked.to_vec(), mm.clone());
        Ok(mm)
    }
}

/// A friction element changed its mode at an event.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeChange {
    pub time: f64,
    pub component: String,
    pub old_mode: i8,
    pub new_mode: i8,
}

const MAX_PASSES: usize = 50;

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
    let before: Vec<i8> = disc.friction.iter().map(|f| f.pre.mode).collect();

    // Relations of force laws are evaluated literally at the event.
    {
        let locked = disc.locked_set();
        let mm = cache.get(sys, &locked, t)?;
        evaluate(sys, &mm, disc, t, x, horizon, ws);
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

    let nf = sys.frictions.len();
    for _pass in 0..MAX_PASSES {
        let pre: Vec<Discrete> = disc.friction.iter().map(|f| f.pre).collect();
        // free = (fn <= 0), from the signals at the event (evaluated above).
        let free: Vec<bool> = sys
            .frictions
            .iter()
            .map(|fe| fe.normal_force(&ws.signals) <= 0.0)
            .collect();
        let flags = solve_mixed(
            sys,
            cache,
            &pre,
            &free,
            &disc.relations,
            t,
            x,
            initial,
            horizon,
            ws,
        )?;
        let new: Vec<Discrete> = (0..nf)
            .map(|k| {
                let (sf, sb) = flags[k];
                Discrete {
                    mode: sys.frictions[k].mode(free[k], pre[k], sf, sb, ws.friction[k].w),
                    start_forward: sf,
                    start_backward: sb,
                }
            })
            .collect();
        let settled = new == pre;
        for k in 0..nf {
            disc.friction[k] = FrictionState {
                pre: new[k],
                locked: sys.frictions[k].locked(
                    free[k],
                    new[k],
                    new[k].start_forward,
                    new[k].start_backward,
                ),
                free: free[k],
            };
        }
        if settled || initial {
            // With pre() = the new values, `locked` uses pre(mode) = mode, as between events.
            let changes = (0..nf)
                .filter(|&k| before[k] != new[k].mode)
                .map(|k| ModeChange {
                    time: t,
                    component: sys.frictions[k].name.clone(),
                    old_mode: before[k],
                    new_mode: new[k].mode,
                })
                .collect();
            return Ok(changes);
        }
    }
    let names: Vec<&str> = sys.frictions.iter().map(|f| f.name.as_str()).collect();
    Err(SimError::Numerical {
        time: t,
        message: format!(
            "event iteration did not reach a consistent mode after {MAX_PASSES} passes (friction elements: {})",
            names.join(", ")
        ),
    })
}

/// One evaluation of the mixed system: the start flags consistent with the accelerations and
/// friction torques they imply, for fixed `pre()` values.
#[allow(clippy::too_many_arguments)]
fn solve_mixed(
    sys: &System,
    cache: &mut ModeCache,
    pre: &[Discrete],
    free: &[bool],
    relations: &[bool],
    t: f64,
    x: &[f64],
    initial: bool,
    horizon: f64,
    ws: &mut Workspace,
) -> Result<Vec<(bool, bool)>, SimError> {
    let nf = sys.frictions.len();
    let mut flags: Vec<(bool, bool)> = pre
        .iter()
        .map(|p| (p.start_forward, p.start_backward))
        .collect();
    let limit = 4 * nf + 10;
    for _ in 0..limit {
        let trial = DiscreteState {
            friction: (0..nf)
                .map(|k| {
                    let (sf, sb) = flags[k];
                    FrictionState {
                        pre: Discrete {
                            mode: pre[k].mode,
                            start_forward: sf,
                            start_backward: sb,
                        },
                        locked: sys.frictions[k].locked(free[k], pre[k], sf, sb),
                        free: free[k],
                    }
                })
                .collect(),
            relations: relations.to_vec(),
        };
        let mm = cache.get(sys, &trial.locked_set(), t)?;
        evaluate(sys, &mm, &trial, t, x, horizon, ws);
        let next: Vec<(bool, bool)> = (0..nf)
            .map(|k| {
                let v = &ws.friction[k];
                sys.frictions[k].start_flags(
                    pre[k],
                    Relations {
                        sa: v.sa,
                        w: v.w,
                        tau0: v.tau0,
                        tau0_max: v.tau0_max,
                        w_small: sys.frictions[k].w_small,
                        initial,
                    },
                )
            })
            .collect();
        if next == flags {
            return Ok(flags);
        }
        flags = next;
    }
    Err(SimError::Numerical {
        time: t,
        message: "the stick/slip Booleans of coupled friction elements do not settle (mixed system has no consistent solution)".into(),
    })
}
