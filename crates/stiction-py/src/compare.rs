//! The MSL tube comparison for Python (`stiction`'s `compare` and `tube`): the core's, the one
//! implementation, over NumPy float64 arrays.

use std::borrow::Cow;

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use stiction_core::CompareError;

/// The values of a 1-D array (borrowed when contiguous).
fn slice_of<'a>(a: &'a PyReadonlyArray1<'_, f64>) -> Cow<'a, [f64]> {
    match a.as_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(a.as_array().to_vec()),
    }
}

fn value_err(e: CompareError) -> PyErr {
    match e {
        // it names the reference already (as the Python `tube` said it)
        CompareError::Trajectory(_, m) if m.starts_with("the reference") => {
            PyValueError::new_err(m)
        }
        e => PyValueError::new_err(e.to_string()),
    }
}

/// The tube around the reference at `time`: `(lower, upper, x, y)`, its edges and its
/// half-sizes in time and value (`y >= floor`). ValueError if the reference has no rows or
/// its arrays differ in length.
#[pyfunction]
#[pyo3(signature = (ref_time, ref_values, time, tolerance, floor))]
#[allow(clippy::type_complexity)]
fn tube<'py>(
    py: Python<'py>,
    ref_time: PyReadonlyArray1<'py, f64>,
    ref_values: PyReadonlyArray1<'py, f64>,
    time: PyReadonlyArray1<'py, f64>,
    tolerance: f64,
    floor: f64,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    f64,
    f64,
)> {
    let (t_ref, y_ref, t) = (slice_of(&ref_time), slice_of(&ref_values), slice_of(&time));
    let tube = py
        .detach(|| stiction_core::tube((&t_ref, &y_ref), &t, tolerance, floor))
        .map_err(value_err)?;
    let (lower, upper) = (tube.lower, tube.upper);
    let (lower, upper) = (PyArray1::from_vec(py, lower), PyArray1::from_vec(py, upper));
    Ok((lower, upper, tube.x_half, tube.y_half))
}

/// One signal against the tube around its reference: `(max_excess, worst_time,
/// points_outside, x, y)` — the largest distance of a point outside, in tube half-heights
/// (0.0 when all are inside, inf for a NaN), when that point is (None when all are inside),
/// how many are outside, and the tube's half-sizes. ValueError if the reference has no rows or
/// a side's arrays differ in length.
#[pyfunction]
#[pyo3(signature = (ref_time, ref_values, time, values, tolerance, floor))]
fn check_signal(
    py: Python<'_>,
    ref_time: PyReadonlyArray1<'_, f64>,
    ref_values: PyReadonlyArray1<'_, f64>,
    time: PyReadonlyArray1<'_, f64>,
    values: PyReadonlyArray1<'_, f64>,
    tolerance: f64,
    floor: f64,
) -> PyResult<(f64, Option<f64>, usize, f64, f64)> {
    let (t_ref, y_ref) = (slice_of(&ref_time), slice_of(&ref_values));
    let (t, y) = (slice_of(&time), slice_of(&values));
    let c = py
        .detach(|| stiction_core::check_signal((&t_ref, &y_ref), (&t, &y), tolerance, floor))
        .map_err(value_err)?;
    Ok((
        c.max_excess,
        c.worst_time,
        c.points_outside,
        c.x_half,
        c.y_half,
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(tube, m)?)?;
    m.add_function(wrap_pyfunction!(check_signal, m)?)?;
    Ok(())
}
