//! A saved simulation state as Python sees it (`stiction._core.State`): its time, and its
//! bytes, the core's (`SimState::to_bytes`), so it pickles with the bytes the FMU's serialized
//! states carry too.

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use stiction_core::SimState;

use crate::sim_err;

/// A saved simulation state (opaque; restore it with `Simulation.set_state`). It pickles as
/// its bytes (`to_bytes`), the format the FMU's serialized states carry too.
#[pyclass(frozen, module = "stiction._core", name = "State")]
pub(crate) struct PyState(pub(crate) SimState);

#[pymethods]
impl PyState {
    #[getter]
    fn time(&self) -> f64 {
        self.0.cursor.now
    }

    /// The state as bytes (`SimState::to_bytes`): versioned, f64 bit patterns, a checksum.
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.0.to_bytes())
    }

    /// The state in bytes from `to_bytes`; a UsageError says what is wrong with them.
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<Self> {
        SimState::from_bytes(data).map(PyState).map_err(sim_err)
    }

    /// Pickling: `State.from_bytes(bytes)`.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let from_bytes = py.get_type::<PyState>().getattr("from_bytes")?;
        Ok((from_bytes, (self.to_bytes(py),)))
    }
}
