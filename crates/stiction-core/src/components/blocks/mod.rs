//! The Modelica.Blocks components: sources and math (`sources_math`), the time table
//! (`timetable`), the table of a signal and Abs (`tables`), and their registry here.

use super::Entry;

mod sources_math;
mod tables;
mod timetable;

/// All signal component types.
pub const REGISTRY: &[Entry] = &[
    Entry::new(
        "Constant",
        "Modelica.Blocks.Sources.Constant",
        "Generate a constant signal",
        sources_math::constant,
    ),
    Entry::new(
        "Step",
        "Modelica.Blocks.Sources.Step",
        "Generate a step signal",
        sources_math::step,
    ),
    Entry::new(
        "Ramp",
        "Modelica.Blocks.Sources.Ramp",
        "Generate a ramp signal",
        sources_math::ramp,
    ),
    Entry::new(
        "Sine",
        "Modelica.Blocks.Sources.Sine",
        "Generate a sine signal",
        sources_math::sine,
    ),
    Entry::new(
        "Pulse",
        "Modelica.Blocks.Sources.Pulse",
        "Generate a pulse signal; every edge is a time event",
        sources_math::pulse,
    ),
    Entry::new(
        "Product",
        "Modelica.Blocks.Math.Product",
        "Output product of the two inputs",
        sources_math::product,
    ),
    Entry::new(
        "Feedback",
        "Modelica.Blocks.Math.Feedback",
        "Output difference between the two inputs, u1 - u2",
        sources_math::feedback,
    ),
    Entry::new(
        "Add",
        "Modelica.Blocks.Math.Add",
        "Output the weighted sum k1*u1 + k2*u2",
        sources_math::add,
    ),
    Entry::new(
        "Gain",
        "Modelica.Blocks.Math.Gain",
        "Output the product of a gain value with the input signal",
        sources_math::gain,
    ),
    Entry::new(
        "TimeTable",
        "Modelica.Blocks.Sources.TimeTable",
        "Generate a piecewise linear signal from a table or CSV file",
        timetable::time_table,
    ),
    Entry::new(
        "CombiTable1Ds",
        "Modelica.Blocks.Tables.CombiTable1Ds",
        "Table look-up in one dimension (matrix) with one input and n outputs",
        tables::combi_table_1ds,
    ),
    Entry::new(
        "Abs",
        "Modelica.Blocks.Math.Abs",
        "Output the absolute value of the input",
        tables::abs,
    ),
];
