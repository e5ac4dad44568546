//! flexbody's Python extension, `flexbody._flexbody`: the library's jobs
//! (read a model, its modes, a reduction, a study; write and read bodies)
//! with numpy arrays in and out. The Python package `flexbody` wraps it
//! with scipy.sparse matrices and docstrings; see python/flexbody.
//!
//! Long work releases the GIL and shows a spinner where stderr is a
//! terminal. Every error is a `flexbody.Error` (a `ValueError`) with the
//! command line's message.

use pyo3::prelude::*;

mod arrays;
mod body;
mod errors;
mod model;
mod progress;

/// The command line's allocator (huge pages for large blocks), so that the
/// eigen solve runs as fast from Python as from the command line.
#[global_allocator]
static ALLOCATOR: flexbody::huge_pages::HugePages = flexbody::huge_pages::HugePages;

#[pymodule]
fn _flexbody(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Error", m.py().get_type::<errors::Error>())?;
    m.add_class::<model::Model>()?;
    m.add_class::<body::Body>()?;
    m.add_class::<body::Sid>()?;
    m.add_function(wrap_pyfunction!(model::read, m)?)?;
    m.add_function(wrap_pyfunction!(model::from_matrices, m)?)?;
    m.add_function(wrap_pyfunction!(body::load, m)?)?;
    Ok(())
}
