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

/// The error and its causes, `outer: inner: ...`, each cause once (a
/// wrapper that already prints its cause is not followed by it again), as
/// the command line prints them.
pub fn message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut out = String::new();
    let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(c) = cause {
        let text = c.to_string();
        if !out.ends_with(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&flexbody::io::text::shortened(&text));
        }
        cause = c.source();
    }
    out
}

/// A library error as a `flexbody.Error`.
pub fn to_py<E: std::error::Error + 'static>(e: E) -> PyErr {
    Error::new_err(message(&e))
}

/// An `anyhow` error as a `flexbody.Error`.
pub fn any_to_py(e: anyhow::Error) -> PyErr {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.ends_with(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&flexbody::io::text::shortened(&text));
    }
    Error::new_err(out)
}

/// A `flexbody.Error` with `text`.
pub fn invalid(text: impl Into<String>) -> PyErr {
    Error::new_err(text.into())
}
