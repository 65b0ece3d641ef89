//! MSL `LossyGear` (spec §5.5): an ideal gear `phi_a = ratio·phi_b` whose torque balance carries
//! a loss torque `tauLoss` referred to flange_a — mesh efficiency and bearing friction from
//! `lossTable`, by quadrant (direction of motion × driving side) — and which can stick.
//!
//! In the linear system the gear torque `τa = flange_a.tau` is the multiplier of the gear row.
//! The loss torque acts through `ℓ = [flange_b: ratio, support: −ratio]`: while rolling it is
//! `c1·τa + c0` (the quadrant's line), so `τa`'s column becomes `row + c1·ℓ`; while stuck it is
//! the unknown `sa` of the extra row `a_a = 0`.

use super::super::{heat_port, with_support, Component, Constructor, Ports};
use super::logic::{Discrete, BACKWARD, FORWARD, FREE, STUCK};
use crate::error::ModelResult;
use crate::events::relation;
use crate::model::Params;
use crate::system::outputs::GearVar;
use crate::system::{Builder, Out, Rel};
use crate::table::Table1D;

/// One LossyGear as the engine sees it.
pub struct LossyGearElem {
    pub name: String,
    pub ratio: f64,
    /// `lossTable = [0, 1, 1, 0, 0]` exactly: an ideal gear (mode 2 for ever).
    pub ideal: bool,
    /// Columns 2..5 of lossTable against |w_a|: eta_mf1, eta_mf2, tau_bf1, tau_bf2.
    table: [Table1D; 4],
    /// Whether the losses depend on the speed (more than one table row).
    pub speed_dependent: bool,
    eta1_0: f64,
    eta2_0: f64,
    tbf1_0: f64,
    tbf2_0: f64,
    tbf_a_0: f64,
    /// `phi_a − ratio·phi_b − (1 − ratio)·phi_support`.
    pub row: Rel,
    /// `a_a = flange_a − support`: locked when stuck.
    pub lock_row: Rel,
    /// Where the loss torque acts: `[flange_b: ratio, support: −ratio]`.
    pub loss_col: Rel,
    pub heat_node: Option<usize>,
}

/// Discrete state between events: `pre()` of mode and start flags, `locked`, and the frozen
/// relation `tau_etaPos = tau_eta ≥ 0` that picks the driving side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GearState {
    pub pre: Discrete,
    pub locked: bool,
    /// The values of its relations (they change only at events).
    pub rel: GearRelations,
}

/// The relations of the LossyGear's Boolean equations, each `g > 0` with hysteresis (see
/// `events::relation`): `sa > tauLossMax_p`, `sa < tauLossMin_m`, `w_a > 0`, `w_a < 0` and
/// `tau_eta ≥ 0` (`tau_etaPos`, the driving side).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GearRelations(pub [bool; 5]);

impl GearRelations {
    pub const SA_ABOVE_MAX_P: usize = 0;
    pub const SA_BELOW_MIN_M: usize = 1;
    pub const W_POS: usize = 2;
    pub const W_NEG: usize = 3;
    pub const TAU_ETA_POS: usize = 4;

    /// `tau_etaPos(start = true)`; the others start false.
    pub const INITIAL: GearRelations = GearRelations([false, false, false, false, true]);

    /// The relations at the gear's current values, from their previous values (literal at
    /// initialization).
    pub fn update(
        self,
        sa: f64,
        max_p: f64,
        min_m: f64,
        w_a: f64,
        tau_eta: f64,
        initial: bool,
    ) -> Self {
        let g = [sa - max_p, min_m - sa, w_a, -w_a, tau_eta];
        let mut next = relation::update(self.0, g, initial);
        // `tau_eta >= 0` holds at 0 itself
        if initial {
            next[Self::TAU_ETA_POS] = tau_eta >= 0.0;
        }
        GearRelations(next)
    }

    pub fn get(&self, i: usize) -> bool {
        self.0[i]
    }
}

impl GearState {
    /// `tau_etaPos`: flange_a drives.
    pub fn tau_eta_pos(&self) -> bool {
        self.rel.get(GearRelations::TAU_ETA_POS)
    }
}

impl GearState {
    /// `mode(start = 2, fixed = true)`, `tau_etaPos(start = true)`.
    pub const INITIAL: GearState = GearState {
        pre: Discrete {
            mode: FREE,
            start_forward: false,
            start_backward: false,
        },
        locked: false,
        rel: GearRelations::INITIAL,
    };
}

/// Efficiencies and bearing friction at one speed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Losses {
    pub eta1: f64,
    pub eta2: f64,
    pub tbf1: f64,
    pub tbf2: f64,
    pub tbf_a: f64,
}

/// How the gear enters the linear system in one mode: locked, or rolling with `τa`'s column
/// `row + c1·ℓ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearMode {
    pub locked: bool,
    pub c1: f64,
}

fn tbf_a(eta1: f64, eta2: f64, tbf1: f64, tbf2: f64) -> f64 {
    if (eta1 - 1.0).abs() <= 1e-15 && (eta2 - 1.0).abs() <= 1e-15 {
        tbf1 / 2.0
    } else {
        (tbf1 - tbf2) / (eta1 - 1.0 / eta2)
    }
}

impl LossyGearElem {
    pub fn losses(&self, w_a: f64) -> Losses {
        if self.ideal {
            return Losses {
                eta1: 1.0,
                eta2: 1.0,
                ..Losses::default()
            };
        }
        let u = w_a.abs();
        let (eta1, eta2) = (self.table[0].eval(u), self.table[1].eval(u));
        let (tbf1, tbf2) = (self.table[2].eval(u).abs(), self.table[3].eval(u).abs());
        Losses {
            eta1,
            eta2,
            tbf1,
            tbf2,
            tbf_a: tbf_a(eta1, eta2, tbf1, tbf2),
        }
    }

    /// The loss torque while rolling, `c1·τa + c0`, by quadrant: forward motion uses
    /// `tauLossMax`, backward `tauLossMin`; `tau_etaPos` says which flange drives.
    pub fn rolling_line(&self, st: &GearState, l: &Losses) -> (f64, f64) {
        let forward = st.pre.start_forward || (!st.pre.start_backward && st.pre.mode == FORWARD);
        match (forward, st.tau_eta_pos()) {
            (true, true) => (1.0 - l.eta1, l.tbf1),         // quadrant 1
            (true, false) => (1.0 - 1.0 / l.eta2, l.tbf2),  // quadrant 2
            (false, true) => (1.0 - 1.0 / l.eta2, -l.tbf2), // quadrant 4
            (false, false) => (1.0 - l.eta1, -l.tbf1),      // quadrant 3
        }
    }

    pub fn mode_in(&self, st: &GearState, l: &Losses) -> GearMode {
        if self.ideal {
            GearMode {
                locked: false,
                c1: 0.0,
            }
        } else if st.locked {
            GearMode {
                locked: true,
                c1: 0.0,
            }
        } else {
            GearMode {
                locked: false,
                c1: self.rolling_line(st, l).0,
            }
        }
    }

    /// The losses at zero speed: the key of the factored mode (exact for a one-row table).
    pub fn losses_at_rest(&self) -> Losses {
        self.losses(0.0)
    }

    /// `tau_eta`: flange_a torque less the bearing friction share, deciding the driving side.
    pub fn tau_eta(&self, st: &GearState, tau_a: f64, tbf_a: f64) -> f64 {
        if self.ideal || st.locked {
            tau_a
        } else if st.pre.start_forward || st.pre.mode == FORWARD {
            tau_a - tbf_a
        } else {
            tau_a + tbf_a
        }
    }

    /// `(tauLossMax_p, tauLossMin_m)`: the loss limits just off rest, for the breakaway test.
    pub fn rest_limits(&self, tau_a: f64) -> (f64, f64) {
        let max_p = if tau_a - self.tbf_a_0 > 0.0 {
            (1.0 - self.eta1_0) * tau_a + self.tbf1_0
        } else {
            (1.0 - 1.0 / self.eta2_0) * tau_a + self.tbf2_0
        };
        let min_m = if tau_a + self.tbf_a_0 > 0.0 {
            (1.0 - 1.0 / self.eta2_0) * tau_a - self.tbf2_0
        } else {
            (1.0 - self.eta1_0) * tau_a - self.tbf1_0
        };
        (max_p, min_m)
    }

    pub fn start_flags(&self, pre: Discrete, r: GearRelations, initial: bool) -> (bool, bool) {
        use GearRelations as R;
        (
            (pre.mode == STUCK && r.get(R::SA_ABOVE_MAX_P)) || (initial && r.get(R::W_POS)),
            (pre.mode == STUCK && r.get(R::SA_BELOW_MIN_M)) || (initial && r.get(R::W_NEG)),
        )
    }

    pub fn locked(&self, pre: Discrete, sf: bool, sb: bool) -> bool {
        !(self.ideal || pre.mode == FORWARD || sf || pre.mode == BACKWARD || sb)
    }

    pub fn mode(&self, pre: Discrete, sf: bool, sb: bool, r: GearRelations) -> i8 {
        if self.ideal {
            FREE
        } else if (pre.mode == FORWARD || sf) && r.get(GearRelations::W_POS) {
            FORWARD
        } else if (pre.mode == BACKWARD || sb) && r.get(GearRelations::W_NEG) {
            BACKWARD
        } else {
            STUCK
        }
    }
}

struct LossyGear {
    ratio: f64,
    table: Vec<Vec<f64>>,
    ideal: bool,
    use_support: bool,
    use_heat_port: bool,
}

impl Component for LossyGear {
    fn ports(&self) -> Ports {
        Ports {
            mech: with_support(&["flange_a", "flange_b"], self.use_support),
            heat: heat_port(self.use_heat_port),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let (na, nb, ns) = (b.node("flange_a")?, b.node("flange_b")?, b.node("support")?);
        let r = self.ratio;
        let row = Rel::of(&[(na, 1.0), (nb, -r), (ns, r - 1.0)]);
        if row.is_zero() {
            return Err(b.error(
                "its flanges are rigidly connected to each other or to ground on both sides",
            ));
        }
        let column = |k: usize| -> Table1D {
            let rows: Vec<Vec<f64>> = self.table.iter().map(|row| vec![row[0], row[k]]).collect();
            Table1D::from_points(&rows)
        };
        let table = [column(1), column(2), column(3), column(4)];
        let at_rest = |t: &Table1D| t.eval(0.0);
        let (eta1_0, eta2_0) = (at_rest(&table[0]), at_rest(&table[1]));
        let (tbf1_0, tbf2_0) = (at_rest(&table[2]).abs(), at_rest(&table[3]).abs());
        let heat_node = if self.use_heat_port {
            Some(b.heat_node("heatPort")?)
        } else {
            None
        };
        let k = b.add_lossy_gear(LossyGearElem {
            name: b.name().to_string(),
            ratio: r,
            ideal: self.ideal,
            speed_dependent: self.table.len() > 1,
            table,
            eta1_0,
            eta2_0,
            tbf1_0,
            tbf2_0,
            tbf_a_0: tbf_a(eta1_0, eta2_0, tbf1_0, tbf2_0),
            row: row.clone(),
            lock_row: Rel::of(&[(na, 1.0), (ns, -1.0)]),
            loss_col: Rel::of(&[(nb, r), (ns, -r)]),
            heat_node,
        });
        b.init_constraint(row);
        b.output("phi_a", Out::Angle(Rel::of(&[(na, 1.0), (ns, -1.0)])));
        b.output("phi_b", Out::Angle(Rel::of(&[(nb, 1.0), (ns, -1.0)])));
        for (name, var) in [
            ("w_a", GearVar::W),
            ("a_a", GearVar::A),
            ("sa", GearVar::Sa),
            ("tauLoss", GearVar::TauLoss),
            ("tau_eta", GearVar::TauEta),
            ("eta_mf1", GearVar::Eta1),
            ("eta_mf2", GearVar::Eta2),
            ("tau_bf1", GearVar::Tbf1),
            ("tau_bf2", GearVar::Tbf2),
            ("tau_bf_a", GearVar::TbfA),
            ("tauLossMax_p", GearVar::LossMaxP),
            ("tauLossMin_m", GearVar::LossMinM),
            ("lossPower", GearVar::LossPower),
            ("mode", GearVar::Mode),
            ("locked", GearVar::Locked),
            ("startForward", GearVar::StartForward),
            ("startBackward", GearVar::StartBackward),
            ("tau_etaPos", GearVar::TauEtaPos),
            ("tau_aPos", GearVar::TauEtaPos),
            ("ideal", GearVar::Ideal),
        ] {
            b.output(name, Out::Gear(k, var));
        }
        b.flange("flange_a", na, Some(Out::Gear(k, GearVar::TauA)))?;
        b.flange("flange_b", nb, Some(Out::Gear(k, GearVar::TauB)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::Gear(k, GearVar::TauSupport)))?;
        }
        if let Some(node) = heat_node {
            b.output("heatPort.T", Out::HeatT(node));
            b.output(
                "heatPort.Q_flow",
                Out::Scaled(Box::new(Out::Gear(k, GearVar::LossPower)), -1.0),
            );
        }
        Ok(())
    }
}

fn lossy_gear(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = p.real("ratio", 1.0)?;
    if ratio == 0.0 {
        return Err(p.error("ratio", "must not be 0"));
    }
    let table = p.matrix("lossTable", 5, &[&[0.0, 1.0, 1.0, 0.0, 0.0]])?;
    Table1D::check_increasing(p, "lossTable", &table)?;
    for row in &table {
        for (col, name) in [(1, "eta_mf1"), (2, "eta_mf2")] {
            if !(row[col] > 0.0 && row[col] <= 1.0) {
                return Err(p.error(
                    "lossTable",
                    format!(
                        "efficiency {name} must be in (0, 1], got {} at |w_a| = {}",
                        row[col], row[0]
                    ),
                ));
            }
        }
    }
    let ideal = table.len() == 1
        && table[0]
            .iter()
            .zip([0.0, 1.0, 1.0, 0.0, 0.0])
            .all(|(v, ideal)| (v - ideal).abs() <= 1e-15);
    Ok(Box::new(LossyGear {
        ratio,
        table,
        ideal,
        use_support: p.boolean("useSupport", false)?,
        use_heat_port: p.boolean("useHeatPort", false)?,
    }))
}

pub const REGISTRY: &[(&str, Constructor)] = &[("LossyGear", lossy_gear)];
