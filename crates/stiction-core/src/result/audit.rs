//! The energy audit per element: at every result row, the power entering a component through
//! its flanges (its reported cut torques times the flange speeds) must equal what its parts take
//! out of the drivetrain: an inertia `J·w·a`, a force law `tau·w_rel` (stored or dissipated), a
//! constraint its multiplier times its speed (an ideal gear: nothing), a friction element or
//! lossy gear its `lossPower`. The flange torques come from the torque balances of the
//! connection sets, the parts from the component's own equations, so the two sides are computed
//! independently. A passive element (no source law, no working constraint) must never dissipate
//! negative power: it never delivers net energy.
//!
//! A reset at a state event (MSL's `reinit` of a MassWithStopAndFriction at its stop) takes
//! kinetic energy out in an instant, between the event's left and right rows, where no power
//! integral sees it: the jump of the kinetic energy of the masses of a component with a
//! switching element over such a pair is that component's `reset_loss`, and part of its
//! `dissipated`, as the run's `system.dissipatedEnergy` counts it.
//!
//! A friction element's `tau·w_rel` that its `lossPower` leaves out is kept apart as `withheld`:
//! MSL's OneWayClutch reports no loss while stuck (`w_rel ≤ 0`), including a forward start
//! whose integrated relative speed drifts a little below 0. That power is the element's torque
//! times an error of the integrator, so it is judged against `slip_bound`, not round-off.

use super::SimResult;
use crate::engine::eval::{DiscreteState, Workspace};
use crate::model::split_last;
use crate::rel::Rel;
use crate::system::{Domain, EnergyRole, Out, System};

/// The energy balance of one component over a run.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementAudit {
    pub component: String,
    /// The largest |power in − power taken by its parts| over the rows [W].
    pub residual: f64,
    /// The largest power term of the component over the rows [W] (for a relative figure).
    pub scale: f64,
    /// The largest cut torque at its flanges [N·m]: a stuck element's slip stays inside the
    /// ±1e-10 rad/s event band, so its held torque may show up to about 1e-10 of this in power.
    pub torque: f64,
    /// The largest |tau·w_rel − lossPower| of its switching elements [W]: what MSL's loss law
    /// leaves out (a OneWayClutch while stuck); 0 for every other element.
    pub withheld: f64,
    /// How far its relative speed may be off [rad/s]: the event band plus the integrator's
    /// error bound on a difference of two speeds, `2·Tolerance·(1 + largest flange speed)`.
    /// `withheld` is within `torque·slip_bound` where the slip is the integrator's error.
    pub slip_bound: f64,
    /// No source law and no constraint that does work.
    pub passive: bool,
    /// The least power it dissipated over the rows [W] (negative: it delivered energy).
    pub min_dissipation: f64,
    /// Energy that entered through the flanges and energy dissipated over the run [J]
    /// (trapezoid rule over the rows: off by order `Interval²` where a power oscillates within
    /// an interval, 0.18 % on a Gearbox at 0.01 s; `system.dissipatedEnergy` is exact).
    pub energy_in: f64,
    pub dissipated: f64,
    /// Kinetic energy its resets removed (MSL's `reinit` at a stop) [J], included in
    /// `dissipated`; 0 for a component that never resets.
    pub reset_loss: f64,
}

/// Where each component's power goes, as indices into the system.
#[derive(Default)]
struct Parts {
    name: String,
    ports: Vec<(usize, Rel)>,
    masses: Vec<(usize, f64)>,
    laws: Vec<usize>,
    constraints: Vec<usize>,
    switching: Vec<usize>,
}

impl SimResult {
    /// The per-element energy audit, one entry per component with flanges, in model order.
    pub fn audit(&self) -> Vec<ElementAudit> {
        let sys = &*self.system;
        let parts = parts_of(sys);
        let mut audits: Vec<ElementAudit> = parts.iter().map(|p| empty(&p.name)).collect();
        let mut last: Vec<Option<(f64, f64, f64)>> = vec![None; parts.len()];
        let mut last_kinetic = vec![0.0; parts.len()];
        let tr = &self.trajectory;
        let mut flange_tau = vec![0.0; sys.flange_torques.ports()];
        let mut scratch = Vec::new();
        self.visit_rows(|r, sys, row| {
            let Some((ws, disc)) = row else {
                return;
            };
            let value = |out: &Out| super::output_expr::value(out, sys, ws, disc, &[]);
            sys.flange_torques
                .solve(value, &mut flange_tau, &mut scratch);
            for (k, p) in parts.iter().enumerate() {
                let (power_in, taken, dissipation) = balance(sys, ws, disc, p, &flange_tau);
                let withheld = withheld(ws, p);
                let a = &mut audits[k];
                a.residual = a.residual.max((power_in - taken - withheld).abs());
                a.withheld = a.withheld.max(withheld.abs());
                a.scale = a.scale.max(power_in.abs()).max(taken.abs());
                a.torque = (p.ports.iter()).fold(a.torque, |m, (i, _)| m.max(flange_tau[*i].abs()));
                a.slip_bound = (p.ports.iter()).fold(a.slip_bound, |m, (_, rel)| {
                    m.max(slip_bound(sys.experiment.tolerance, rel.dot(&ws.w)))
                });
                a.min_dissipation = a.min_dissipation.min(dissipation);
                let kinetic = kinetic_energy(ws, p);
                if let Some((t0, p0, d0)) = last[k] {
                    let dt = tr.t[r] - t0;
                    a.energy_in += 0.5 * (p0 + power_in) * dt;
                    a.dissipated += 0.5 * (d0 + dissipation) * dt;
                    // the two rows of one event: a reset's loss (speeds are states, else equal)
                    if dt == 0.0 && !p.switching.is_empty() {
                        let removed = last_kinetic[k] - kinetic;
                        a.dissipated += removed;
                        a.reset_loss += removed;
                    }
                }
                last[k] = Some((tr.t[r], power_in, dissipation));
                last_kinetic[k] = kinetic;
            }
        });
        for (a, p) in audits.iter_mut().zip(&parts) {
            a.passive = is_passive(sys, p);
        }
        audits
    }
}

fn empty(name: &str) -> ElementAudit {
    ElementAudit {
        component: name.to_string(),
        residual: 0.0,
        scale: 0.0,
        torque: 0.0,
        withheld: 0.0,
        slip_bound: 0.0,
        passive: true,
        min_dissipation: f64::INFINITY,
        energy_in: 0.0,
        dissipated: 0.0,
        reset_loss: 0.0,
    }
}

/// The kinetic energy of a component's masses at one row (`½·J·w²`, `½·m·v²`).
fn kinetic_energy(ws: &Workspace, p: &Parts) -> f64 {
    (p.masses.iter())
        .map(|&(n, j)| 0.5 * j * ws.w[n] * ws.w[n])
        .sum()
}

/// (power in through the flanges, power taken by the parts, power dissipated) at one row.
fn balance(
    sys: &System,
    ws: &Workspace,
    disc: &DiscreteState,
    p: &Parts,
    flange_tau: &[f64],
) -> (f64, f64, f64) {
    let power_in: f64 = p
        .ports
        .iter()
        .map(|(i, rel)| flange_tau[*i] * rel.dot(&ws.w))
        .sum();
    let mut taken: f64 = p.masses.iter().map(|&(n, j)| j * ws.w[n] * ws.a[n]).sum();
    let mut dissipation = 0.0;
    for &k in &p.laws {
        let law = &sys.laws[k];
        taken += ws.law_tau[k] * ws.law_w[k];
        if law.law.role() != EnergyRole::Source {
            let ctx = ws.law_ctx(sys, disc, k);
            dissipation += law.law.dissipation(&ctx, ws.law_tau[k]);
        }
    }
    for &k in &p.constraints {
        taken += ws.constraint_tau[k] * sys.constraints[k].rel.dot(&ws.w);
    }
    for &k in &p.switching {
        taken += ws.elements[k].loss;
        dissipation += ws.elements[k].loss;
    }
    (power_in, taken, dissipation)
}

/// The power its switching elements' loss laws leave out at one row (`tau·w_rel − lossPower`).
fn withheld(ws: &Workspace, p: &Parts) -> f64 {
    p.switching.iter().map(|&k| ws.elements[k].withheld).sum()
}

/// The event band (a stuck slip stays within ±1e-10 rad/s) plus the integrator's error bound
/// on the difference of two states of speed `w` (absolute and relative tolerance both
/// `tolerance`).
fn slip_bound(tolerance: f64, w: f64) -> f64 {
    2.0 * crate::switching::relation::EVENT_EPSILON + 2.0 * tolerance * (1.0 + w.abs())
}

fn is_passive(sys: &System, p: &Parts) -> bool {
    p.laws
        .iter()
        .all(|&k| sys.laws[k].law.role() != EnergyRole::Source)
        && p.constraints.iter().all(|&k| !sys.constraints[k].does_work)
}

/// The flange of a flange output `port.phi` / `port.s` (`last`: `Domain::position`) or
/// `port.tau` / `port.f` (`Domain::force`), in either domain.
fn flange_of(name: &str, last: fn(Domain) -> &'static str) -> Option<&str> {
    [Domain::Rotational, Domain::Translational]
        .into_iter()
        .find_map(|d| name.strip_suffix(last(d))?.strip_suffix('.'))
}

/// Each component's flanges (from its `.phi`/`.tau` or `.s`/`.f` outputs), masses, laws, constraints and
/// switching elements, in the order the components appear in the outputs.
fn parts_of(sys: &System) -> Vec<Parts> {
    let mut parts: Vec<Parts> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut of = |name: &str, parts: &mut Vec<Parts>| -> usize {
        *index.entry(name.to_string()).or_insert_with(|| {
            parts.push(Parts {
                name: name.to_string(),
                ..Parts::default()
            });
            parts.len() - 1
        })
    };
    let angles: std::collections::HashMap<&str, &Rel> = (sys.outputs.iter())
        .filter_map(|(n, out)| match out {
            Out::Angle(rel) => flange_of(n, Domain::position).map(|port| (port, rel)),
            _ => None,
        })
        .collect();
    for (name, out) in &sys.outputs {
        let (Out::FlangeTau(i), Some(port)) = (out, flange_of(name, Domain::force)) else {
            continue;
        };
        let (Some(rel), Some((component, _))) = (angles.get(port), split_last(port)) else {
            continue;
        };
        let k = of(component, &mut parts);
        parts[k].ports.push((*i, (*rel).clone()));
    }
    for (owner, node, j) in &sys.masses {
        let k = of(owner, &mut parts);
        parts[k].masses.push((*node, *j));
    }
    for (i, law) in sys.laws.iter().enumerate() {
        let k = of(&law.owner, &mut parts);
        parts[k].laws.push(i);
    }
    for (i, c) in sys.constraints.iter().enumerate() {
        let k = of(&c.owner, &mut parts);
        parts[k].constraints.push(i);
    }
    for (i, e) in sys.switching.iter().enumerate() {
        let k = of(e.name(), &mut parts);
        parts[k].switching.push(i);
    }
    parts.retain(|p| !p.ports.is_empty());
    // A composite (a Gearbox) is audited through its parts (`gearbox.lossyGear`, …), which
    // report the same flanges: the composite's own entry would hold the flanges alone.
    let names: Vec<String> = parts.iter().map(|p| format!("{}.", p.name)).collect();
    let composite = |p: &Parts| {
        let empty = p.masses.is_empty() && p.laws.is_empty();
        let empty = empty && p.constraints.is_empty() && p.switching.is_empty();
        let prefix = format!("{}.", p.name);
        empty
            && names
                .iter()
                .any(|n| n.len() > prefix.len() && n.starts_with(&prefix))
    };
    parts.retain(|p| !composite(p));
    parts
}
