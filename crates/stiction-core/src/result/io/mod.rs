//! Result files: CSV (`csv`) and Dymola's MATLAB v4 format (`mat`), written from a table of
//! values as the bindings hand it over.

mod csv;
mod mat;

pub use csv::write_csv;
pub use mat::{write_mat, Parameter};

/// A table of `values` for `names` columns, with one more item (a flag, a description) per
/// column: an error unless the shapes match.
fn check_shape(names: usize, per_column: usize, values: usize) -> std::io::Result<()> {
    if names == 0 || per_column != names || !values.is_multiple_of(names) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "table shape does not match the names",
        ));
    }
    Ok(())
}
