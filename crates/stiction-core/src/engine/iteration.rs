//! The event iteration. At an event instant the continuous state is fixed; the Booleans of every
//! friction element and LossyGear are solved as MSL's mixed system (fixed point over the
//! relations: take their current values, solve the linear system for the mode they imply,
//! re-evaluate them with hysteresis, repeat), then `pre()` is updated and the whole is solved
//! again until nothing changes (spec §1.6–1.7, §10.2).

use std::collections::HashMap;
use std::rc::Rc;

use crate::engine::eval::{evaluate_switching, kinematics, DiscreteState, Workspace};
use crate::engine::kkt::ModeMatrix;
use crate::engine::mode_solver::ModeSolver;
use crate::error::SimError;
use crate::linalg::LinearSolver;
use crate::switching::element::{ModeKey, SwitchState};
use crate::switching::logic::Discrete;
use crate::switching::relation::RelationSet;
use crate::system::law::MAX_LAW_RELATIONS;
use crate::system::System;

/// Factored mode matrices by mode: a mode met again costs nothing while it is kept. At most
/// `CACHE_BYTES` of factors are kept (a drivetrain of 10⁴ elements has thousands of modes of a
/// megabyte each); beyond that the least recently used modes are dropped.
pub struct ModeCache {
    map: HashMap<Vec<u64>, (Rc<ModeMatrix>, u64)>,
    solver: ModeSolver,
    bytes: usize,
    uses: u64,
    pub factorizations: usize,
    /// The looked-up mode's keys and packed key, reused: a hit allocates nothing.
    scratch: (Vec<ModeKey>, Vec<u64>),
}

/// The factors a `ModeCache` keeps at most (bytes).
pub const CACHE_BYTES: usize = 256 << 20;

impl Default for ModeCache {
    fn default() -> Self {
        Self::with_solver(ModeSolver::default())
    }
}

impl ModeCache {
    /// Every mode factored from scratch by `solver`.
    pub fn new(solver: Box<dyn LinearSolver>) -> Self {
        Self::with_solver(ModeSolver::with(solver))
    }

    fn with_solver(solver: ModeSolver) -> Self {
        Self {
            map: HashMap::new(),
            solver,
            bytes: 0,
            uses: 0,
            factorizations: 0,
            scratch: Default::default(),
        }
    }

    pub fn get(
        &mut self,
        sys: &System,
        disc: &DiscreteState,
        t: f64,
    ) -> Result<Rc<ModeMatrix>, SimError> {
        let (mut keys, mut key) = std::mem::take(&mut self.scratch);
        disc.mode_keys(sys, &mut keys);
        pack(&keys, &mut key);
        let found = self.lookup(sys, &keys, &key, t);
        self.scratch = (keys, key);
        found
    }

    fn lookup(
        &mut self,
        sys: &System,
        keys: &[ModeKey],
        key: &[u64],
        t: f64,
    ) -> Result<Rc<ModeMatrix>, SimError> {
        self.uses += 1;
        if let Some((mm, used)) = self.map.get_mut(key) {
            *used = self.uses;
            return Ok(mm.clone());
        }
        let mm = Rc::new(ModeMatrix::factor(sys, keys, t, &mut self.solver)?);
        self.factorizations += 1;
        self.bytes += mm.bytes();
        while self.bytes > CACHE_BYTES && !self.map.is_empty() {
            self.drop_least_recent();
        }
        self.map.insert(key.to_vec(), (mm.clone(), self.uses));
        Ok(mm)
    }

    fn drop_least_recent(&mut self) {
        let oldest = (self.map.iter()).min_by_key(|(_, (_, used))| *used);
        if let Some(key) = oldest.map(|(key, _)| key.clone()) {
            if let Some((mm, _)) = self.map.remove(&key) {
                self.bytes -= mm.bytes();
            }
        }
    }
}

/// A mode's key for the map, into `key`: the locked flags as bits, then (element, slope bits)
/// for each nonzero slope — a few words to hash per lookup instead of two per element.
fn pack(keys: &[ModeKey], key: &mut Vec<u64>) {
    key.clear();
    key.resize(keys.len().div_ceil(64), 0);
    for (k, mk) in keys.iter().enumerate() {
        key[k / 64] |= (mk.locked as u64) << (k % 64);
    }
    for (k, mk) in keys.iter().enumerate() {
        if mk.slope.to_bits() != 0 {
            key.extend([k as u64, mk.slope.to_bits()]);
        }
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

/// What the mixed system iterates on: the relations of every switching element.
type RelationValues = Vec<RelationSet>;

fn relations_of(disc: &DiscreteState) -> RelationValues {
    disc.switching.iter().map(|st| st.rel).collect()
}

/// Every relation true in either (start conditions set in either), except those an element
/// takes from the first only. Speeds do not change within an event, so theirs agree anyway.
fn union(sys: &System, a: &RelationValues, b: &RelationValues) -> RelationValues {
    (sys.switching.iter().zip(a.iter().zip(b)))
        .map(|(e, (a, b))| a.union_keeping(*b, e.own_relations()))
        .collect()
}

/// The same with every start condition on `sa` false: each element that was stuck locks.
fn nothing_starts(sys: &System, r: &RelationValues) -> RelationValues {
    (sys.switching.iter().zip(r))
        .map(|(e, r)| r.cleared(e.start_relations()))
        .collect()
}

/// The relations at the values in `ws`, from `r` (from none at initialization).
fn updated(sys: &System, r: &RelationValues, ws: &Workspace, initial: bool) -> RelationValues {
    (sys.switching.iter().zip(r).zip(&ws.elements))
        .map(|((e, r), v)| e.relations(*r, v, initial))
        .collect()
}

fn element_names(sys: &System) -> Vec<String> {
    sys.switching.iter().map(|e| e.name().to_string()).collect()
}

/// Where the discrete equations are solved: the instant, the continuous state there, the
/// horizon of unhandled time events (those before it have happened, see `signals::reached`),
/// and whether this is MSL's initialization (`initial()`).
#[derive(Debug, Clone, Copy)]
pub struct EventPoint<'a> {
    pub t: f64,
    pub x: &'a [f64],
    pub horizon: f64,
    pub initial: bool,
}

/// Solves the discrete equations at an event point. At initialization this is one consistent
/// solution with the start values as `pre()`; otherwise the full event iteration: solve the
/// mixed system for fixed `pre()`, update `pre()`, repeat until the modes settle.
pub fn iterate(
    sys: &System,
    cache: &mut ModeCache,
    disc: &mut DiscreteState,
    at: &EventPoint,
    ws: &mut Workspace,
) -> Result<Vec<ModeChange>, SimError> {
    let before: Vec<i8> = disc.switching.iter().map(|st| st.pre.mode).collect();
    law_relations_at(sys, disc, at, ws);
    if !at.initial {
        switching_relations_at(sys, cache, disc, at, ws)?;
    }
    for _pass in 0..MAX_PASSES {
        let pre: Vec<Discrete> = disc.switching.iter().map(|st| st.pre).collect();
        // free = (fn <= 0), from the signals at the event (evaluated above).
        let free: Vec<bool> = (sys.switching.iter())
            .map(|e| e.is_free(&ws.signals))
            .collect();
        let ctx = Mixed {
            sys,
            pre: &pre,
            free: &free,
            carried: disc,
            at,
        };
        let (solved, evaluated_last) = solve_mixed(&ctx, cache, relations_of(disc), ws)?;
        let new = next_pre(sys, &solved, &pre, &free);
        let settled = new == pre;
        // With pre() = the new values, `locked` uses pre(mode) = mode, as between events.
        for (k, e) in sys.switching.iter().enumerate() {
            let p = new[k];
            disc.switching[k] = SwitchState {
                pre: p,
                locked: e.locked(free[k], p, p.start_forward, p.start_backward),
                free: free[k],
                rel: solved.switching[k].rel,
            };
        }
        if settled || at.initial {
            // the settled state is the last one evaluated (checked, not assumed)
            let held = evaluated_last && !at.initial && *disc == solved;
            ws.settled_at = held.then_some(ws.rhs_evals);
            return Ok(mode_changes(sys, &before, &new, at.t));
        }
    }
    Err(SimError::EventIteration {
        time: at.t,
        message: format!(
            "event iteration did not reach a consistent mode after {MAX_PASSES} passes"
        ),
        elements: element_names(sys),
    })
}

/// The relations of force laws, evaluated literally at the event (no linear solve needed: the
/// previous mode's matrix may not even be regular, e.g. before initialization).
fn law_relations_at(sys: &System, disc: &mut DiscreteState, at: &EventPoint, ws: &mut Workspace) {
    kinematics(sys, disc, at.t, at.x, at.horizon, ws);
    let mut z = [0.0; MAX_LAW_RELATIONS];
    for (k, law) in sys.laws.iter().enumerate() {
        let count = law.relation_count;
        // a relation may depend on the law's others (an ElastoBacklash's switches inside a
        // contact on the contact): evaluated again until none changes, at most once each
        for _ in 0..count {
            law.law
                .relation_values(&ws.law_ctx(sys, disc, k), &mut z[..count]);
            let mut changed = false;
            for (r, &value) in z[..count].iter().enumerate() {
                let slot = &mut disc.relations[law.relation_base + r];
                changed |= *slot != (value >= 0.0);
                *slot = value >= 0.0;
            }
            if !changed {
                break;
            }
        }
    }
}

/// The switching elements' relations as they stand at the event, in the mode before it
/// (between events only those that matter were watched).
fn switching_relations_at(
    sys: &System,
    cache: &mut ModeCache,
    disc: &mut DiscreteState,
    at: &EventPoint,
    ws: &mut Workspace,
) -> Result<(), SimError> {
    let mm = cache.get(sys, disc, at.t)?;
    evaluate_switching(sys, &mm, disc, at.t, at.x, at.horizon, ws);
    let now = updated(sys, &relations_of(disc), ws, false);
    for (st, rel) in disc.switching.iter_mut().zip(now) {
        st.rel = rel;
    }
    Ok(())
}

/// `pre()` after a pass: the start flags of the solved state and the modes they imply (F5).
fn next_pre(
    sys: &System,
    solved: &DiscreteState,
    pre: &[Discrete],
    free: &[bool],
) -> Vec<Discrete> {
    (sys.switching.iter().zip(&solved.switching))
        .zip(pre.iter().zip(free))
        .map(|((e, st), (pre, &free))| {
            let (sf, sb) = (st.pre.start_forward, st.pre.start_backward);
            Discrete {
                mode: e.mode(free, *pre, sf, sb, st.rel),
                ..st.pre
            }
        })
        .collect()
}

fn mode_changes(sys: &System, before: &[i8], after: &[Discrete], t: f64) -> Vec<ModeChange> {
    (sys.switching.iter().zip(before.iter().zip(after)))
        .filter(|(_, (old, new))| **old != new.mode)
        .map(|(e, (old, new))| ModeChange {
            time: t,
            component: e.name().to_string(),
            old_mode: *old,
            new_mode: new.mode,
        })
        .collect()
}

/// What stays fixed while the mixed system is solved at one event instant.
struct Mixed<'a> {
    sys: &'a System,
    pre: &'a [Discrete],
    free: &'a [bool],
    /// The discrete state the laws' relations and the inputs are taken from.
    carried: &'a DiscreteState,
    at: &'a EventPoint<'a>,
}

/// One evaluation of the mixed system: relation values consistent with the accelerations and
/// torques they imply, for fixed `pre()` values, and the state they imply. The fixed point starts
/// from the relations' current values (the solution closest to the state before). If that
/// cycles — an element that starts one way is pushed back the other way, each direction
/// implying the opposite — it starts again from "nothing starts" (every stuck element locked).
/// If that cycles too, the elements are updated one at a time from there: two elements that
/// each break away while the other holds (one locking makes the other's torque pass its limit,
/// both starting makes both turn back) are settled by the first starting alone. Only when that
/// cycles as well do two elements hold the same motion, each alone breaking away while each
/// alone holds: starting is then the consistent answer (the union of the cycling relations).
/// Also whether the state returned is the one `ws` was evaluated for last.
fn solve_mixed(
    ctx: &Mixed,
    cache: &mut ModeCache,
    current: RelationValues,
    ws: &mut Workspace,
) -> Result<(DiscreteState, bool), SimError> {
    let locked_start = nothing_starts(ctx.sys, &current);
    let mut from = |rels, update| fixed_point(ctx, cache, rels, ws, update, Vec::new());
    // a consistent fixed point returns the state it has just evaluated
    if let Settled::Consistent(state) = from(current, Update::All)? {
        return Ok((state, true));
    }
    let cycle = match from(locked_start.clone(), Update::All)? {
        Settled::Consistent(state) => return Ok((state, true)),
        Settled::Cycles(cycle) => cycle,
    };
    if let Settled::Consistent(state) = from(locked_start, Update::First)? {
        return Ok((state, true));
    }
    Ok((started_union(ctx, cache, cycle, ws)?, false))
}

/// How a pass of the fixed point applies the relations it re-evaluated.
#[derive(Clone, Copy, PartialEq)]
enum Update {
    /// Every element's at once.
    All,
    /// Only the first element whose relations changed (in the canonical order).
    First,
}

/// Where a fixed-point iteration ended: a consistent state, or a cycle — every set visited and
/// the one the last led back to.
enum Settled {
    Consistent(DiscreteState),
    Cycles(Cycle),
}

struct Cycle {
    visited: Vec<RelationValues>,
    next: RelationValues,
}

/// The iteration limit of one fixed point (each element's relations can change a few times).
fn pass_limit(sys: &System) -> usize {
    4 * sys.switching.len() + 10
}

/// The relations the mode implied by `rels` gives (the state that mode is, with them).
fn reevaluated(
    ctx: &Mixed,
    cache: &mut ModeCache,
    rels: &RelationValues,
    ws: &mut Workspace,
) -> Result<(DiscreteState, RelationValues), SimError> {
    let (sys, at) = (ctx.sys, ctx.at);
    let trial = implied_state(ctx, rels);
    let mm = cache.get(sys, &trial, at.t)?;
    evaluate_switching(sys, &mm, &trial, at.t, at.x, at.horizon, ws);
    Ok((trial, updated(sys, rels, ws, at.initial)))
}

/// Iterates the mixed system from `rels` until its relations reproduce themselves or revisit
/// a set (of this iteration or of those `visited` before it).
fn fixed_point(
    ctx: &Mixed,
    cache: &mut ModeCache,
    mut rels: RelationValues,
    ws: &mut Workspace,
    update: Update,
    mut visited: Vec<RelationValues>,
) -> Result<Settled, SimError> {
    for _ in 0..pass_limit(ctx.sys) {
        let (trial, mut next) = reevaluated(ctx, cache, &rels, ws)?;
        if next == rels {
            return Ok(Settled::Consistent(trial));
        }
        if update == Update::First {
            next = first_change_only(&rels, next);
        }
        visited.push(rels.clone());
        if visited.contains(&next) {
            return Ok(Settled::Cycles(Cycle { visited, next }));
        }
        rels = next;
    }
    Err(not_settling(ctx))
}

/// `rels` with only the first element's relations that differ in `next` taken from it.
fn first_change_only(rels: &RelationValues, next: RelationValues) -> RelationValues {
    let mut one = rels.clone();
    if let Some(k) = (rels.iter().zip(&next)).position(|(a, b)| a != b) {
        one[k] = next[k];
    }
    one
}

/// The last fallback: the union of the cycling relations (see `solve_mixed`), iterated on from
/// there (a union again at each cycle) until it settles or a union was seen before.
fn started_union(
    ctx: &Mixed,
    cache: &mut ModeCache,
    cycle: Cycle,
    ws: &mut Workspace,
) -> Result<DiscreteState, SimError> {
    let Cycle {
        mut visited,
        mut next,
    } = cycle;
    for _ in 0..pass_limit(ctx.sys) {
        let started = cycle_union(ctx.sys, &visited, &next);
        if visited.contains(&started) {
            return Ok(implied_state(ctx, &started));
        }
        match fixed_point(ctx, cache, started, ws, Update::All, visited)? {
            Settled::Consistent(state) => return Ok(state),
            Settled::Cycles(cycle) => (visited, next) = (cycle.visited, cycle.next),
        }
    }
    Err(not_settling(ctx))
}

/// The union of every set of the cycle `next` closes (from its visit on). A cycle of four — a
/// one-way clutch at its breakaway tie and a clutch whose locked torque passes its limit only
/// while the other starts — holds each one's start in a different set; the union of the last
/// two alone started neither with the other (a locked clutch beyond its limit).
fn cycle_union(sys: &System, visited: &[RelationValues], next: &RelationValues) -> RelationValues {
    let from = visited.iter().position(|v| v == next).unwrap_or(0);
    (visited[from..].iter()).fold(next.clone(), |acc, v| union(sys, &acc, v))
}

fn not_settling(ctx: &Mixed) -> SimError {
    SimError::EventIteration {
        time: ctx.at.t,
        message: "the stick/slip Booleans of coupled friction elements do not settle (mixed system has no consistent solution)".into(),
        elements: element_names(ctx.sys),
    }
}

/// The discrete state the relations imply with `pre()` fixed: each element's start flags and
/// whether it is locked (its `pre.mode` stays the pre-value).
fn implied_state(ctx: &Mixed, rels: &RelationValues) -> DiscreteState {
    let switching = (ctx.sys.switching.iter().zip(rels))
        .zip(ctx.pre.iter().zip(ctx.free))
        .map(|((e, &rel), (&pre, &free))| {
            let (sf, sb) = e.start_flags(pre, rel, ctx.at.initial);
            SwitchState {
                pre: Discrete {
                    mode: pre.mode,
                    start_forward: sf,
                    start_backward: sb,
                },
                locked: e.locked(free, pre, sf, sb),
                free,
                rel,
            }
        })
        .collect();
    DiscreteState {
        switching,
        relations: ctx.carried.relations.clone(),
        inputs: ctx.carried.inputs.clone(),
    }
}
