//! The registry of signal block components (Modelica.Blocks sources, math, time tables).

use super::{blocks, timetable, Constructor};

/// All signal component types.
pub const REGISTRY: &[(&str, Constructor)] = &[
    ("Constant", blocks::constant),
    ("Step", blocks::step),
    ("Ramp", blocks::ramp),
    ("Sine", blocks::sine),
    ("Pulse", blocks::pulse),
    ("Product", blocks::product),
    ("Feedback", blocks::feedback),
    ("Add", blocks::add),
    ("Gain", blocks::gain),
    ("TimeTable", timetable::time_table),
];
