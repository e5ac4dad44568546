//! flexbody's errors as Python exceptions: every one is a
//! `flexbody.Error`, a subclass of `ValueError`, carrying the message the
//! command line prints (the file, line, node, DOF or set it is about).

use pyo3::exceptions::PyValueError;
use pyo3::PyErr;

pyo3::create_exception!(
    flexbody,
    Error,
    PyValueError,
    "An input or request flexbody cannot use; the message names the file, line, node, DOF or \
     set. A subclass of ValueError."
);

/// A library error as a `flexbody.Error`, with the command line's
/// message ([`flexbody::io::text::error_chain`]).
pub fn to_py<E: std::error::Error + 'static>(e: E) -> PyErr {
    Error::new_err(flexbody::io::text::error_chain(&e))
}

/// An `anyhow` error as a `flexbody.Error`.
pub fn any_to_py(e: anyhow::Error) -> PyErr {
    Error::new_err(flexbody::io::text::error_chain(e.as_ref()))
}

/// A `flexbody.Error` with `text`.
pub fn invalid(text: impl Into<String>) -> PyErr {
    Error::new_err(text.into())
}
