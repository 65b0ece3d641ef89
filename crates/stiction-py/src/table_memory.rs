//! The table of every variable as a NumPy array over the engine's own memory, handed back to
//! the engine once NumPy is done with it (`stiction_core::recycle_table`): the next
//! large table then skips the kernel's clearing of fresh pages.

use numpy::ndarray::Array2;
use numpy::PyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use stiction_core::recycle_table;

/// Owns a table's values while NumPy arrays over them live (it is their base object).
#[pyclass(frozen, module = "stiction._core")]
struct TableMemory(Array2<f64>);

impl Drop for TableMemory {
    fn drop(&mut self) {
        let (values, _) = std::mem::take(&mut self.0).into_raw_vec_and_offset();
        recycle_table(values);
    }
}

/// `values` (row-major, `shape`) as a NumPy array, without a copy.
pub fn table_array(
    py: Python<'_>,
    values: Vec<f64>,
    shape: [usize; 2],
) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let values =
        Array2::from_shape_vec(shape, values).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let owner = Bound::new(py, TableMemory(values))?;
    // SAFETY: the values stay where they are while `owner` lives (it is frozen: nothing but its
    // drop takes them), and NumPy keeps `owner` alive as the base of the array and its views.
    Ok(unsafe { PyArray2::borrow_from_array(&owner.get().0, owner.clone().into_any()) })
}
