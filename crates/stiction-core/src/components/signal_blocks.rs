//! The registry of signal block components (Modelica.Blocks sources, math, time tables).

use super::{blocks, timetable, Entry};

/// All signal component types.
pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Constant",
        "Modelica.Blocks.Sources.Constant",
        "Generate a constant signal",
        blocks::constant,
    ),
    Entry::new(
        "Step",
        "Modelica.Blocks.Sources.Step",
        "Generate a step signal",
        blocks::step,
    ),
    Entry::new(
        "Ramp",
        "Modelica.Blocks.Sources.Ramp",
        "Generate a ramp signal",
        blocks::ramp,
    ),
    Entry::new(
        "Sine",
        "Modelica.Blocks.Sources.Sine",
        "Generate a sine signal",
        blocks::sine,
    ),
    Entry::new(
        "Pulse",
        "Modelica.Blocks.Sources.Pulse",
        "Generate a pulse signal; every edge is a time event",
        blocks::pulse,
    ),
    Entry::new(
        "Product",
        "Modelica.Blocks.Math.Product",
        "Output product of the two inputs",
        blocks::product,
    ),
    Entry::new(
        "Feedback",
        "Modelica.Blocks.Math.Feedback",
        "Output difference between the two inputs, u1 - u2",
        blocks::feedback,
    ),
    Entry::new(
        "Add",
        "Modelica.Blocks.Math.Add",
        "Output the weighted sum k1*u1 + k2*u2",
        blocks::add,
    ),
    Entry::new(
        "Gain",
        "Modelica.Blocks.Math.Gain",
        "Output the product of a gain value with the input signal",
        blocks::gain,
    ),
    Entry::new(
        "TimeTable",
        "Modelica.Blocks.Sources.TimeTable",
        "Generate a piecewise linear signal from a table or CSV file",
        timetable::time_table,
    ),
];
