//! Result files: CSV (`csv`) and Dymola's MATLAB v4 format (`mat`), written from a table of
//! values as the bindings hand it over.

mod csv;
mod mat;

pub use csv::write_csv;
pub use mat::{write_mat, Parameter};
