//! `flexbody.Model`: a component read from any input flexbody reads (a
//! model file, a deck, CalculiX or Matrix Market matrices) or built from
//! matrices, with its modes, reductions and study, each one library call
//! as the command line makes it.

use crate::arrays::{self, CscParts};
use crate::body::Body;
use crate::errors::{any_to_py, invalid, to_py};
use crate::progress::Spinner;
use flexbody::fem::{Dof, Substructure, SystemMatrices};
use flexbody::file_kind::Takes;
use flexbody::input::{self, Component, MatrixFiles};
use flexbody::io::deck::DeckOptions;
use flexbody::linalg::memory::Budget;
use flexbody::reduce::modes::{eigenmodes_lent, rigid::rigid_motion_count, Wanted};
use flexbody::reduce::{reduce_reporting, Method, Reduction};
use flexbody::report::diagnose_mechanism;
use numpy::{PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// A component ready for modes and reductions: its K, M (and D), DOF map,
/// node coordinates and, where it came from a mesh, the mesh with its sets
/// and couplings.
#[pyclass(module = "flexbody._flexbody", frozen)]
pub struct Model {
    pub(crate) c: Arc<Component>,
}

/// Reads the component at `path` as `flexbody modes`, `reduce` and `info`
/// do: a model file (.toml), a deck (.inp), CalculiX matrices (job.sti
/// with job.mas and job.dof beside it) or a Matrix Market stiffness (.mtx,
/// with `mass` and `dofs`; `coords` gives node coordinates to matrices).
#[pyfunction]
#[pyo3(signature = (path, mass=None, dofs=None, coords=None, allow_unknown=false))]
pub fn read(
    py: Python<'_>,
    path: PathBuf,
    mass: Option<PathBuf>,
    dofs: Option<PathBuf>,
    coords: Option<PathBuf>,
    allow_unknown: bool,
) -> PyResult<Model> {
    Takes::INFO.check(&path).map_err(to_py)?;
    let files = MatrixFiles { mass, dofs, coords };
    let options = DeckOptions {
        allow_unknown,
        ..DeckOptions::default()
    };
    let c = py
        .detach(|| input::load_with(&path, &files, &options))
        .map_err(to_py)?;
    Ok(Model { c: Arc::new(c) })
}

/// A sparse matrix coming in as CSC arrays `(indptr, indices, data)`.
type CscIn<'py> = (
    PyReadonlyArray1<'py, i64>,
    PyReadonlyArray1<'py, i64>,
    PyReadonlyArray1<'py, f64>,
);

/// A component of the matrices K, M (and D) given as CSC arrays over the
/// DOFs `dofs` (flattened `(n, 2)`: node id, DOF 1..6), with the node
/// coordinates `coords` (flattened `(k, 3)`) of the nodes `node_ids`.
#[pyfunction]
#[pyo3(signature = (n, k, m, dofs, node_ids=None, coords=None, d=None))]
#[allow(clippy::too_many_arguments)]
pub fn from_matrices(
    py: Python<'_>,
    n: usize,
    k: CscIn<'_>,
    m: CscIn<'_>,
    dofs: PyReadonlyArray1<'_, i64>,
    node_ids: Option<PyReadonlyArray1<'_, i64>>,
    coords: Option<PyReadonlyArray1<'_, f64>>,
    d: Option<CscIn<'_>>,
) -> PyResult<Model> {
    let dof_map = arrays::dof_map(dofs.as_slice()?)?;
    if dof_map.len() != n {
        return Err(invalid(format!(
            "K and M have {n} equations but dofs lists {}; one DOF per equation",
            dof_map.len()
        )));
    }
    let matrix = |name: &str, (p, i, v): &CscIn<'_>| -> PyResult<_> {
        let (p, i, v) = (p.as_slice()?, i.as_slice()?, v.as_slice()?);
        py.detach(|| arrays::symmetric_from_csc(name, (n, n), p, i, v))
    };
    let stiffness = matrix("K", &k)?;
    let mass = matrix("M", &m)?;
    let damping = d.as_ref().map(|d| matrix("D", d)).transpose()?;
    let coordinates = match (node_ids, coords) {
        (None, None) => HashMap::new(),
        (Some(ids), Some(xyz)) => coordinate_map(ids.as_slice()?, xyz.as_slice()?, &dof_map)?,
        _ => return Err(invalid("give node ids and coordinates together")),
    };
    let matrices = SystemMatrices {
        stiffness,
        mass,
        damping,
    };
    let sub = Substructure::from_matrices(dof_map, matrices, coordinates);
    let c = Component::of_matrices(PathBuf::from("matrices"), sub, 0.0);
    Ok(Model { c: Arc::new(c) })
}

/// The coordinates of nodes `ids` (`xyz` flattened `(k, 3)`): every node of
/// the DOFs needs one, each finite, each node given once.
fn coordinate_map(
    ids: &[i64],
    xyz: &[f64],
    dofs: &flexbody::fem::DofMap,
) -> PyResult<HashMap<u64, [f64; 3]>> {
    if xyz.len() != 3 * ids.len() {
        return Err(invalid(format!(
            "coords must be ({}, 3) for {} node ids; got {} values",
            ids.len(),
            ids.len(),
            xyz.len()
        )));
    }
    let mut map = HashMap::with_capacity(ids.len());
    for (row, (&id, p)) in ids.iter().zip(xyz.chunks_exact(3)).enumerate() {
        if id < 0 {
            return Err(invalid(format!("coords row {row}: node {id} is negative")));
        }
        if p.iter().any(|v| !v.is_finite()) {
            return Err(invalid(format!(
                "coords row {row}: node {id} has a coordinate that is not finite"
            )));
        }
        if map.insert(id as u64, [p[0], p[1], p[2]]).is_some() {
            return Err(invalid(format!(
                "coords row {row}: node {id} is given twice"
            )));
        }
    }
    if let Some(d) = dofs.dofs().iter().find(|d| !map.contains_key(&d.node)) {
        return Err(invalid(format!(
            "node {} has DOFs but no coordinates; give every node of the DOFs its coordinates",
            d.node
        )));
    }
    Ok(map)
}

/// The modes `modes` computes: `count` (default 10), every one below
/// `fmax` Hz, or the lowest `count` below `fmax`, as `flexbody modes`
/// takes them.
fn wanted(count: Option<usize>, fmax: Option<f64>, dofs: usize) -> PyResult<Wanted> {
    if count == Some(0) {
        return Err(invalid("count must be at least 1"));
    }
    if let Some(f) = fmax {
        if !(f.is_finite() && f > 0.0) {
            return Err(invalid(format!(
                "fmax must be a positive frequency in Hz; got {f}"
            )));
        }
    }
    let band = match (count, fmax) {
        (None, Some(f)) => Wanted::below_hz(f),
        (Some(count), Some(f)) => Wanted::lowest_below_hz(count, f),
        (count, None) => Wanted::Lowest(count.unwrap_or(10)),
    };
    Ok(band.map_count(|c| c.min(dofs)))
}

/// What `modes` returns: eigenvalues (rad^2/s^2), frequencies (Hz), the
/// M-orthonormal shapes (n x k), residuals, and a warning on a mechanism.
type ModesTuple<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Option<String>,
);

#[pymethods]
impl Model {
    /// The lowest modes (`count`, default 10), every mode below `fmax` Hz,
    /// or the lowest `count` below `fmax`: the eigen solve of `flexbody
    /// modes`, on the model's own K and M (lent to the solver, not copied).
    #[pyo3(signature = (count=None, fmax=None))]
    fn modes<'py>(
        &self,
        py: Python<'py>,
        count: Option<usize>,
        fmax: Option<f64>,
    ) -> PyResult<ModesTuple<'py>> {
        let sub = &self.c.sub;
        let band = wanted(count, fmax, sub.len())?;
        let rigid = match sub.support {
            flexbody::fem::Support::Free => rigid_motion_count(sub),
            _ => 0,
        };
        let (modes, residuals) = py
            .detach(|| {
                let spinner = Spinner::new("modes");
                let (k, m) = (&sub.matrices.stiffness, &sub.matrices.mass);
                eigenmodes_lent(k, m, band, Budget::MACHINE, &spinner)
            })
            .map_err(to_py)?;
        let mechanism = diagnose_mechanism(&modes.values, sub.support, rigid)
            .map(|m| format!("{}: {m}", self.c.path.display()));
        Ok((
            PyArray1::from_vec(py, modes.values.clone()),
            PyArray1::from_vec(py, modes.frequencies_hz()),
            arrays::dense(py, modes.vectors.as_ref())?,
            PyArray1::from_vec(py, residuals),
            mechanism,
        ))
    }

    /// A reduced body by `method` (free, craig-bampton, elastic-residual,
    /// free-residual, guyan) with `modes` eigenmodes or every one below
    /// `fmax` Hz, on `interface` (comma-separated node sets and node
    /// numbers, all DOFs of each) or `interface_dofs` (flattened `(k, 2)`),
    /// else the model's default interface: the reduction `flexbody reduce`
    /// makes.
    #[pyo3(signature = (method, interface=None, interface_dofs=None, modes=None, fmax=None, orthonormalize=false))]
    #[allow(clippy::too_many_arguments)]
    fn reduce(
        &self,
        py: Python<'_>,
        method: &str,
        interface: Option<String>,
        interface_dofs: Option<PyReadonlyArray1<'_, i64>>,
        modes: Option<usize>,
        fmax: Option<f64>,
        orthonormalize: bool,
    ) -> PyResult<Body> {
        let c = &self.c;
        let method = Method::parse(method).ok_or_else(|| {
            let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
            invalid(format!(
                "unknown method '{method}'; expected one of: {}",
                names.join(", ")
            ))
        })?;
        if let Some(f) = fmax {
            if !(f.is_finite() && f > 0.0) {
                return Err(invalid(format!(
                    "fmax must be a positive frequency in Hz; got {f}"
                )));
            }
        }
        let count = match (modes, fmax) {
            (Some(m), _) => m,
            (None, Some(_)) => 0,
            (None, None) if method == Method::Guyan => 0,
            (None, None) => {
                return Err(invalid(format!(
                    "the {method} method needs modes=N (its eigenmodes e; for free the total r, \
                     rigid-body modes included) or fmax=F (every eigenmode below F Hz)"
                )))
            }
        };
        let (dofs, source) = interface_of(c, interface.as_deref(), interface_dofs, method)?;
        let mut spec = match &c.file {
            Some(file) => input::file_reduction(file, method, count, dofs),
            None => Reduction::new(method, count, dofs),
        };
        if let Some(model) = &c.model {
            spec.local_axes = model.local_axes().clone();
        }
        spec.max_frequency_hz = fmax;
        spec.orthonormalize = orthonormalize;
        let body = py
            .detach(|| {
                let spinner = Spinner::new("reducing");
                reduce_reporting(&c.sub, &spec, &spinner)
            })
            .map_err(to_py)?;
        Ok(Body::reduced(body, Some(c.clone()), source))
    }

    /// The study of a model file's `[study]` table, as `flexbody study
    /// --json` prints it: `{"cases": [...], "failed": [...]}` (JSON text).
    fn study_json(&self, py: Python<'_>) -> PyResult<String> {
        let file = self.c.file.as_ref().ok_or_else(|| {
            invalid(format!(
                "{}: a study needs a model file (TOML) with a [study] table",
                self.c.path.display()
            ))
        })?;
        let result = py
            .detach(|| {
                let spinner = Spinner::new("study");
                flexbody::study::run_study(file, Budget::MACHINE, &spinner)
            })
            .map_err(to_py)?;
        let doc = serde_json::json!({ "cases": result.rows(), "failed": result.failures });
        serde_json::to_string(&doc).map_err(|e| any_to_py(e.into()))
    }

    /// The path the model was read from ("matrices" for matrices from
    /// Python).
    #[getter]
    fn path(&self) -> String {
        self.c.path.display().to_string()
    }

    /// Number of equations (free DOFs).
    #[getter]
    fn dof_count(&self) -> usize {
        self.c.sub.len()
    }

    /// K as CSC arrays `(indptr, indices, data, n)`.
    fn stiffness_csc<'py>(&self, py: Python<'py>) -> CscParts<'py> {
        arrays::csc(py, &self.c.sub.matrices.stiffness)
    }

    /// M as CSC arrays `(indptr, indices, data, n)`.
    fn mass_csc<'py>(&self, py: Python<'py>) -> CscParts<'py> {
        arrays::csc(py, &self.c.sub.matrices.mass)
    }

    /// D as CSC arrays, or `None` where the model has no damping.
    fn damping_csc<'py>(&self, py: Python<'py>) -> Option<CscParts<'py>> {
        self.c
            .sub
            .matrices
            .damping
            .as_ref()
            .map(|d| arrays::csc(py, d))
    }

    /// The DOF of each equation, `(n, 2)`: node id, 1..6 for ux..rz.
    #[getter]
    fn dofs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        arrays::dof_rows(py, self.c.sub.dof_map.dofs())
    }

    /// Node ids and coordinates `(ids (k,), xyz (k, 3))`: every node of
    /// the mesh, or the nodes matrices were given coordinates for.
    fn nodes<'py>(&self, py: Python<'py>) -> PyResult<arrays::NodeArrays<'py>> {
        arrays::node_arrays(py, arrays::component_nodes(&self.c))
    }

    /// Node sets by name (node ids).
    fn node_sets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        if let Some(m) = &self.c.model {
            for (name, nodes) in m.node_sets() {
                let ids: Vec<i64> = nodes.iter().map(|&n| n as i64).collect();
                out.set_item(name, PyArray1::from_vec(py, ids))?;
            }
        }
        Ok(out)
    }

    /// Element sets by name (element ids).
    fn element_sets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        for (name, elements) in &self.c.element_sets {
            let ids: Vec<i64> = elements.iter().map(|&e| e as i64).collect();
            out.set_item(name, PyArray1::from_vec(py, ids))?;
        }
        Ok(out)
    }

    /// The couplings: one dict each with `name`, `kind`, `point` (the
    /// reference node) and `nodes`.
    fn couplings<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let Some(m) = &self.c.model else {
            return Ok(vec![]);
        };
        m.couplings()
            .iter()
            .map(|c| {
                let d = PyDict::new(py);
                d.set_item("name", &c.name)?;
                d.set_item("kind", format!("{:?}", c.kind).to_lowercase())?;
                d.set_item("point", c.point)?;
                d.set_item("nodes", c.nodes.clone())?;
                Ok(d)
            })
            .collect()
    }

    /// The DOFs held by boundary conditions (not equations of K and M),
    /// `(k, 2)` as `dofs`.
    fn fixed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let fixed: Vec<Dof> = match &self.c.model {
            Some(m) => m.fixed_dofs().copied().collect(),
            None => vec![],
        };
        arrays::dof_rows(py, &fixed)
    }

    /// The deck's notes and warnings, each naming its deck, as the command
    /// line prints them.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        let c = &self.c;
        let mut out: Vec<String> = c.notes.iter().map(|n| format!("note: {n}")).collect();
        out.extend(c.warnings.iter().map(|w| format!("warning: {w}")));
        if let Some(summary) = c.unknown_keywords.summary() {
            out.push(format!("warning: {summary}"));
        }
        out
    }

    /// The interface a reduction takes when none is given and where it
    /// comes from, or `None`.
    fn default_interface<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Option<(Bound<'py, PyArray2<i64>>, String)>> {
        self.c
            .default_interface()
            .map(|d| Ok((arrays::dof_rows(py, &d.dofs)?, d.source)))
            .transpose()
    }

    fn __repr__(&self) -> String {
        let c = &self.c;
        match &c.model {
            Some(m) => format!(
                "<flexbody.Model {}: {} DOFs, {} nodes, {} elements>",
                c.path.display(),
                c.sub.len(),
                m.nodes().len(),
                m.elements().len()
            ),
            None => format!(
                "<flexbody.Model {}: {} DOFs (matrices)>",
                c.path.display(),
                c.sub.len()
            ),
        }
    }
}

/// The interface DOFs of a reduction and where they come from: those
/// given (by name or as DOFs), else the model's default, else none (an
/// error for every method but free).
fn interface_of(
    c: &Component,
    names: Option<&str>,
    dofs: Option<PyReadonlyArray1<'_, i64>>,
    method: Method,
) -> PyResult<(Vec<Dof>, Option<String>)> {
    match (names, dofs) {
        (Some(_), Some(_)) => Err(invalid(
            "give the interface by name (interface=) or as DOFs (interface_dofs=), not both",
        )),
        (Some(names), None) => Ok((c.interface(Some(names)).map_err(to_py)?, None)),
        (None, Some(dofs)) => {
            let map = arrays::dof_map(dofs.as_slice()?)?;
            if let Some(d) = map
                .dofs()
                .iter()
                .find(|d| c.sub.dof_map.index_of(**d).is_none())
            {
                return Err(invalid(format!(
                    "interface {d} is not a DOF of the model (fixed, or not there)"
                )));
            }
            Ok((map.dofs().to_vec(), None))
        }
        (None, None) => match c.default_interface() {
            Some(d) => Ok((d.dofs, Some(d.source))),
            None if method != Method::Free => Err(invalid(format!(
                "{}: the {method} method needs interface DOFs and none are given: name them with \
                 interface='SETS_OR_NODES' (comma-separated; {}) or interface_dofs=, or give \
                 the model file an [interface] table or connections, or the deck a *COUPLING",
                c.path.display(),
                c.node_set_list()
            ))),
            None => Ok((vec![], None)),
        },
    }
}
