//! MSL `LossyGear` (spec §5.5): an ideal gear `phi_a = ratio·phi_b` whose torque balance carries
//! a loss torque `tauLoss` referred to flange_a — mesh efficiency and bearing friction from
//! `lossTable`, by quadrant (direction of motion × driving side) — and which can stick.
//!
//! In the linear system the gear torque `τa = flange_a.tau` is the multiplier of the gear row.
//! The loss torque acts through `ℓ = [flange_b: ratio, support: −ratio]`: while rolling it is
//! `c1·τa + c0` (the quadrant's line), so `τa`'s column becomes `row + c1·ℓ`; while stuck it is
//! the unknown `sa` of the extra row `a_a = 0`.

use super::super::{heat_port, with_support, Component, Entry, Ports};
use crate::components::decl::{USE_HEAT_PORT, USE_SUPPORT};
use crate::components::gears::gear_ratio;
use crate::error::ModelResult;
use crate::lookup_table::Table1D;
use crate::model::Params;
use crate::switching::lossy_gear::{tbf_a, LossyGearElem};
use crate::system::outputs::SwitchVar as GearVar;
use crate::system::{Builder, Out, Rel};

// Ports alike in shape to IdealGear and Brake (see gears.rs).
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
        let k = b.add_switching(Box::new(LossyGearElem {
            name: b.name().to_string(),
            ratio: r,
            ideal: self.ideal,
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
        }));
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
            ("tauLossMax_p", GearVar::Tau0Max),
            ("tauLossMin_m", GearVar::Tau0),
            ("lossPower", GearVar::LossPower),
            ("mode", GearVar::Mode),
            ("locked", GearVar::Locked),
            ("startForward", GearVar::StartForward),
            ("startBackward", GearVar::StartBackward),
            ("tau_etaPos", GearVar::TauEtaPos),
            ("tau_aPos", GearVar::TauEtaPos),
        ] {
            b.output(name, Out::Switch(k, var));
        }
        b.output("ideal", Out::Const(if self.ideal { 1.0 } else { 0.0 }));
        b.flange("flange_a", na, Some(Out::Switch(k, GearVar::Tau)))?;
        b.flange("flange_b", nb, Some(Out::Switch(k, GearVar::TauB)))?;
        if self.use_support {
            b.flange("support", ns, Some(Out::Switch(k, GearVar::TauSupport)))?;
        }
        if let Some(node) = heat_node {
            b.output("heatPort.T", Out::HeatT(node));
            b.output(
                "heatPort.Q_flow",
                Out::Scaled(Box::new(Out::Switch(k, GearVar::LossPower)), -1.0),
            );
        }
        Ok(())
    }
}

/// MSL's `lossTable` parameter, checked: speeds increasing, efficiencies in (0, 1].
pub(crate) fn loss_table(p: &Params) -> ModelResult<Vec<Vec<f64>>> {
    let table = p.matrix(
        "lossTable [rad/s, 1, 1, N.m, N.m] Rows [abs(w_a), eta_mf1, eta_mf2, tau_bf1, tau_bf2], \
         linear between rows and beyond them linearly through the first or last two rows \
         (MSL's CombiTable1D, LastTwoPoints): give rows up to the speeds the run reaches",
        5,
        &[&[0.0, 1.0, 1.0, 0.0, 0.0]],
    )?;
    p.range("lossTable", "eta_mf1, eta_mf2 in (0, 1]");
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
    Ok(table)
}

/// A LossyGear of a checked `ratio` and `table` (a Gearbox's part, or the component itself).
pub(crate) fn part(
    ratio: f64,
    table: Vec<Vec<f64>>,
    use_support: bool,
    use_heat_port: bool,
) -> Box<dyn Component> {
    let ideal = table.len() == 1
        && table[0]
            .iter()
            .zip([0.0, 1.0, 1.0, 0.0, 0.0])
            .all(|(v, ideal)| (v - ideal).abs() <= 1e-15);
    Box::new(LossyGear {
        ratio,
        table,
        ideal,
        use_support,
        use_heat_port,
    })
}

fn lossy_gear(p: &Params) -> ModelResult<Box<dyn Component>> {
    let ratio = gear_ratio(p)?;
    let table = loss_table(p)?;
    Ok(part(
        ratio,
        table,
        p.boolean(USE_SUPPORT, false)?,
        p.boolean(USE_HEAT_PORT, false)?,
    ))
}

pub const REGISTRY: &[Entry] = &[Entry::new(
    "LossyGear",
    "Modelica.Mechanics.Rotational.Components.LossyGear",
    "Gear with mesh efficiency and bearing friction (stuck/rolling possible)",
    lossy_gear,
)];
