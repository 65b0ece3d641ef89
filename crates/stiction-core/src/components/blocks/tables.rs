//! Modelica.Blocks.Tables.CombiTable1Ds (a table of an input signal, linear segments) and
//! Modelica.Blocks.Math.Abs: what a speed-dependent conductance is made of (a speed sensor's
//! |w| looked up in a table of `Gc` over speed, fed to a Convection). Neither generates
//! events: MSL's LinearSegments table has kinks at its rows but no events
//! (`getTable1DValueNoDer2`), and Abs's `generateEvent` is false by default.

use crate::components::{Component, Ports};
use crate::error::ModelResult;
use crate::lookup_table::Table1D;
use crate::model::Params;
use crate::signals::{Block, Jet};
use crate::system::{Builder, Out};

use super::sources_math::boxed;
use super::timetable::{output_columns, Y};

#[derive(Clone)]
struct Lookup(Table1D);

impl Block for Lookup {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        self.0.eval(u[0])
    }
}

/// One output `y[k]` per table column in `columns`, each the table of its column over `u`.
struct CombiTable1Ds {
    outputs: Vec<Table1D>,
}

impl Component for CombiTable1Ds {
    fn ports(&self) -> Ports {
        Ports {
            signal_in: vec!["u"],
            signal_out: Y[..self.outputs.len()].to_vec(),
            ..Ports::default()
        }
    }

    fn build(&self, b: &mut Builder) -> ModelResult<()> {
        let u = b.signal_in("u")?;
        b.output("u", Out::Signal(u));
        for (name, table) in Y.iter().zip(&self.outputs) {
            let y = b.signal_out(name)?;
            b.output(name, Out::Signal(y));
            b.add_block(Box::new(Lookup(table.clone())), vec![u], y);
        }
        Ok(())
    }
}

const TABLE: &str = "table [1] Table matrix (grid = first column, strictly increasing; e.g. \
     table = [[0, 0], [1, 1], [2, 4]]); linear between rows, beyond them as `extrapolation` says";

pub fn combi_table_1ds(p: &Params) -> ModelResult<Box<dyn Component>> {
    let width = p.matrix_width("table").unwrap_or(2).max(2);
    let rows = p.matrix(TABLE, width, &[&[0.0, 0.0]])?;
    let columns = output_columns(
        p,
        width,
        "columns [1] Columns of table to be interpolated, 1-based (column 1 is the grid); \
         default all the others",
    )?;
    p.choice(
        "smoothness Smoothness of table interpolation: LinearSegments (the only one stiction \
         has)",
        &["LinearSegments"],
        "LinearSegments",
    )?;
    let extrapolation = p.choice(
        "extrapolation Extrapolation of data outside the definition range: LastTwoPoints \
         (linearly through the first or last two rows) or HoldLastPoint (the first or last \
         row's value)",
        &["LastTwoPoints", "HoldLastPoint"],
        "LastTwoPoints",
    )?;
    let mut outputs = Vec::with_capacity(columns.len());
    for c in columns {
        let table = Table1D::from_rows(p, "table", &rows, c)?;
        outputs.push(if extrapolation == "HoldLastPoint" {
            table.holding()
        } else {
            table
        });
    }
    Ok(Box::new(CombiTable1Ds { outputs }))
}

/// `y = |u|`; its derivative is the input's, signed.
#[derive(Clone)]
struct Abs;

impl Block for Abs {
    fn eval(&self, _t: f64, _horizon: f64, u: &[f64]) -> f64 {
        u[0].abs()
    }
    fn jet(&self, _t: f64, _horizon: f64, u: &[Jet]) -> Option<Jet> {
        let s = if u[0][0] < 0.0 { -1.0 } else { 1.0 };
        Some([u[0][0].abs(), s * u[0][1], s * u[0][2]])
    }
}

pub fn abs(p: &Params) -> ModelResult<Box<dyn Component>> {
    // The output is |u| either way; an event at u = 0 would only restart the integrator at
    // the kink.
    p.boolean(
        "generateEvent true: generate an event at u = 0 (stiction: the output is abs(u) either \
         way, without an event)",
        false,
    )?;
    boxed(&["u"], Abs, vec![])
}
