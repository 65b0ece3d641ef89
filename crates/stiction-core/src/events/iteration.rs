//! The event iteration. At an event instant the continuous state is fixed; the Booleans of every
//! friction element and LossyGear are solved as MSL's mixed system (fixed point over the
//! Booleans: guess the start flags — and a gear's driving side — solve the linear system for the
//! mode they imply, recompute them, repeat), then `pre()` is updated and the whole is solved
//! again until nothing changes (spec §1.6–1.7, §10.2).

use std::collections::HashMap;
use std::rc::Rc;

use crate::components::friction::logic::{Discrete, Relations};
use crate::components::friction::lossy_gear::GearState;
use crate::components::friction::FrictionState;
use crate::error::SimError;
use crate::system::eval::{evaluate, kinematics, DiscreteState, Workspace};
use crate::system::kkt::ModeMatrix;
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
        let mm = ModeMatrix::factor(sys, &locked, &gears)
            .map_err(|message| SimError::Numerical { time: t, message })?;
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

/// The Booleans the mixed system solves for: each friction element's start flags, each gear's
/// start flags and driving side.
#[derive(Debug, Clone, PartialEq)]
struct Flags {
    friction: Vec<(bool, bool)>,
    gears: Vec<(bool, bool, bool)>,
}

impl Flags {
    /// Start flags set in either; the driving side of `self`.
    fn or(&self, other: &Flags) -> Flags {
        Flags {
            friction: self
                .friction
                .iter()
                .zip(&other.friction)
                .map(|(a, b)| (a.0 || b.0, a.1 || b.1))
                .collect(),
            gears: self
                .gears
                .iter()
                .zip(&other.gears)
                .map(|(a, b)| (a.0 || b.0, a.1 || b.1, a.2))
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
        kinematics(sys, t, x, horizon, ws);
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

    for _pass in 0..MAX_PASSES {
        let pre_f: Vec<Discrete> = disc.friction.iter().map(|f| f.pre).collect();
        let pre_g: Vec<Discrete> = disc.gears.iter().map(|g| g.pre).collect();
        // free = (fn <= 0), from the signals at the event (evaluated above).
        let free: Vec<bool> = sys
            .frictions
            .iter()
            .map(|fe| fe.normal_force(&ws.signals) <= 0.0)
            .collect();
        let guess = Flags {
            friction: pre_f
                .iter()
                .map(|p| (p.start_forward, p.start_backward))
                .collect(),
            gears: disc
                .gears
                .iter()
                .map(|g| (g.pre.start_forward, g.pre.start_backward, g.tau_eta_pos))
                .collect(),
        };
        let flags = solve_mixed(
            sys,
            cache,
            &pre_f,
            &pre_g,
            &free,
            guess,
            &disc.relations,
            t,
            x,
            initial,
            horizon,
            ws,
        )?;
        let new_f: Vec<Discrete> = (0..sys.frictions.len())
            .map(|k| {
                let (sf, sb) = flags.friction[k];
                Discrete {
                    mode: sys.frictions[k].mode(free[k], pre_f[k], sf, sb, ws.friction[k].w),
                    start_forward: sf,
                    start_backward: sb,
                }
            })
            .collect();
        let new_g: Vec<Discrete> = (0..sys.lossy_gears.len())
            .map(|k| {
                let (sf, sb, _) = flags.gears[k];
                Discrete {
                    mode: sys.lossy_gears[k].mode(pre_g[k], sf, sb, ws.gears[k].w),
                    start_forward: sf,
                    start_backward: sb,
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
            };
        }
        for (k, g) in sys.lossy_gears.iter().enumerate() {
            let p = new_g[k];
            disc.gears[k] = GearState {
                pre: p,
                locked: g.locked(p, p.start_forward, p.start_backward),
                tau_eta_pos: flags.gears[k].2,
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
    Err(SimError::Numerical {
        time: t,
        message: format!(
            "event iteration did not reach a consistent mode after {MAX_PASSES} passes (elements: {})",
            names.join(", ")
        ),
    })
}

/// One evaluation of the mixed system: the Booleans consistent with the accelerations and
/// torques they imply, for fixed `pre()` values.
#[allow(clippy::too_many_arguments)]
fn solve_mixed(
    sys: &System,
    cache: &mut ModeCache,
    pre_f: &[Discrete],
    pre_g: &[Discrete],
    free: &[bool],
    mut flags: Flags,
    relations: &[bool],
    t: f64,
    x: &[f64],
    initial: bool,
    horizon: f64,
    ws: &mut Workspace,
) -> Result<Flags, SimError> {
    let limit = 4 * (sys.frictions.len() + sys.lossy_gears.len()) + 10;
    let mut visited: Vec<Flags> = Vec::new();
    for _ in 0..limit {
        let trial = DiscreteState {
            friction: (0..sys.frictions.len())
                .map(|k| {
                    let (sf, sb) = flags.friction[k];
                    FrictionState {
                        pre: Discrete {
                            mode: pre_f[k].mode,
                            start_forward: sf,
                            start_backward: sb,
                        },
                        locked: sys.frictions[k].locked(free[k], pre_f[k], sf, sb),
                        free: free[k],
                    }
                })
                .collect(),
            gears: (0..sys.lossy_gears.len())
                .map(|k| {
                    let (sf, sb, side) = flags.gears[k];
                    GearState {
                        pre: Discrete {
                            mode: pre_g[k].mode,
                            start_forward: sf,
                            start_backward: sb,
                        },
                        locked: sys.lossy_gears[k].locked(pre_g[k], sf, sb),
                        tau_eta_pos: side,
                    }
                })
                .collect(),
            relations: relations.to_vec(),
        };
        let mm = cache.get(sys, &trial, t)?;
        evaluate(sys, &mm, &trial, t, x, horizon, ws);
        let next = Flags {
            friction: (0..sys.frictions.len())
                .map(|k| {
                    let v = &ws.friction[k];
                    sys.frictions[k].start_flags(
                        pre_f[k],
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
                .collect(),
            gears: (0..sys.lossy_gears.len())
                .map(|k| {
                    let v = &ws.gears[k];
                    let (sf, sb) =
                        sys.lossy_gears[k].start_flags(pre_g[k], v.sa, v.tau_a, v.w, initial);
                    (sf, sb, v.tau_eta >= 0.0)
                })
                .collect(),
        };
        if next == flags {
            return Ok(flags);
        }
        // Updating every element at once can cycle: when two elements hold the same motion
        // (each alone breaks away, each alone holds), or at a breakaway exactly on the limit
        // (sa = limit within round-off, no hysteresis). Starting is the consistent answer.
        visited.push(flags.clone());
        if visited.contains(&next) {
            let started = next.or(&flags);
            if visited.contains(&started) {
                return Ok(started);
            }
            flags = started;
        } else {
            flags = next;
        }
    }
    Err(SimError::Numerical {
        time: t,
        message: "the stick/slip Booleans of coupled friction elements do not settle (mixed system has no consistent solution)".into(),
    })
}
