//! `flexbody.Body` (a reduced body: basis, reduced matrices, interface,
//! and, where it knows the model it came from, its floating-frame
//! invariants and recovery rows) and `flexbody.Sid` (a SID file's
//! floating-frame description), with `load` for every body file flexbody
//! reads.

use crate::arrays;
use crate::errors::{invalid, to_py};
use flexbody::export::{self, AnyBody, BodyNode, BodyOutput, Format, Sid as SidContent};
use flexbody::input::Component;
use flexbody::reduce::ffrf::FloatingFrame;
use flexbody::reduce::{ModeKind, ReducedBody};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;

/// A reduced flexible body `u = T q`.
#[pyclass(module = "flexbody._flexbody", frozen)]
pub struct Body {
    body: ReducedBody,
    /// The component it was reduced from (not for a body read from a file).
    source: Option<Arc<Component>>,
    /// The nodes a body file lists (for one read from a file).
    nodes: Vec<BodyNode>,
    /// Where the interface came from when the model's default was taken.
    interface_source: Option<String>,
}

impl Body {
    /// A body reduced from `source`.
    pub fn reduced(
        body: ReducedBody,
        source: Option<Arc<Component>>,
        interface_source: Option<String>,
    ) -> Self {
        Self {
            body,
            source,
            nodes: vec![],
            interface_source,
        }
    }

    /// The component the body was reduced from, or an error saying what
    /// `what` needs.
    fn source(&self, what: &str) -> PyResult<&Component> {
        self.source.as_deref().ok_or_else(|| {
            invalid(format!(
                "{what} needs the model the body was reduced from (its mass matrix, \
                 coordinates or mesh); a body read from a file has only its basis: \
                 reduce the model in Python instead"
            ))
        })
    }
}

/// A mode kind as text: "rigid ux", "constraint node 3 uz",
/// "eigen 12.5 Hz", ...
fn kind_text(kind: &ModeKind) -> String {
    match kind {
        ModeKind::Rigid { motion } => format!("rigid {motion}"),
        ModeKind::Constraint { dof } => format!("constraint {dof}"),
        ModeKind::ResidualConstraint { dof } => format!("residual constraint {dof}"),
        ModeKind::ResidualInertiaRelief { dof } => format!("residual inertia relief {dof}"),
        ModeKind::ResidualForceGroup { name } => format!("residual force group {name}"),
        ModeKind::Eigen { frequency_hz } => format!("eigen {frequency_hz} Hz"),
        ModeKind::Orthonormal { frequency_hz } => format!("orthonormal {frequency_hz} Hz"),
    }
}

#[pymethods]
impl Body {
    /// The reduction method's name.
    #[getter]
    fn method(&self) -> &'static str {
        self.body.method.name()
    }

    /// Number of Ritz coordinates r.
    #[getter]
    fn r(&self) -> usize {
        self.body.r()
    }

    /// The DOF of each row of the basis, `(n, 2)`: node id, 1..6.
    #[getter]
    fn dofs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        arrays::dof_rows(py, self.body.dof_map.dofs())
    }

    /// The basis T (n x r): the full DOFs are `T q`.
    #[getter]
    fn basis<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        arrays::dense(py, self.body.basis.as_ref())
    }

    /// `M_red = T^T M T` (r x r).
    #[getter]
    fn mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        arrays::dense(py, self.body.mass.as_ref())
    }

    /// `K_red = T^T K T` (r x r).
    #[getter]
    fn stiffness<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        arrays::dense(py, self.body.stiffness.as_ref())
    }

    /// `D_red = T^T D T` (r x r), or `None` without damping.
    #[getter]
    fn damping<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        self.body
            .damping
            .as_ref()
            .map(|d| arrays::dense(py, d.as_ref()))
            .transpose()
    }

    /// What each column of the basis is ("rigid ux", "eigen 12.5 Hz", ...).
    #[getter]
    fn mode_kinds(&self) -> Vec<String> {
        self.body.modes.iter().map(kind_text).collect()
    }

    /// The interface DOFs, `(k, 2)`: node id, 1..6 (along a node's local
    /// axes where it has them).
    #[getter]
    fn interface<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        arrays::dof_rows(py, &self.body.interface)
    }

    /// Where the interface came from when the model's default was taken
    /// (e.g. "the reference nodes of the couplings (node 9001), all their
    /// DOFs"), else `None`.
    #[getter]
    fn interface_source(&self) -> Option<String> {
        self.interface_source.clone()
    }

    /// The interface rows of the basis (k x r), in the order of
    /// `interface`: the interface DOFs are `rows @ q`.
    #[getter]
    fn interface_rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        arrays::dense(py, self.body.interface_rows().as_ref())
    }

    /// Natural frequencies of `K_red`, `M_red` (Hz), lowest first.
    fn frequencies_hz<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let hz = py.detach(|| self.body.frequencies_hz()).map_err(to_py)?;
        Ok(PyArray1::from_vec(py, hz))
    }

    /// Node ids and coordinates `(ids (k,), xyz (k, 3))`: the mesh's nodes
    /// (or those matrices were given coordinates for) for a body reduced in
    /// Python; the nodes a body file lists for one read from a file (NaN
    /// where the file gives no coordinates).
    fn nodes<'py>(&self, py: Python<'py>) -> PyResult<arrays::NodeArrays<'py>> {
        let nodes = match &self.source {
            Some(c) => arrays::component_nodes(c),
            None => self
                .nodes
                .iter()
                .map(|n| (n.id, n.coords.unwrap_or([f64::NAN; 3])))
                .collect(),
        };
        arrays::node_arrays(py, nodes)
    }

    /// The floating-frame description (the SID's content, docs/sid.md):
    /// a dict of `mass`, `md_cm` (3), `md_cm1` (nq x 3), `j` (3 x 3), `j1`
    /// (nq x 3 x 3), `ct`, `cr` (nq x 3), `cr1` (nq x nq x 3), `me`, `ke`
    /// (nq x nq), `de` or None, `gr` (3 x 3nq), `ge` (nq x 3nq), `oe`
    /// (nq x 6), `oe1` (nq x nq x 6), `elastic_hz` (nq), `transform` E
    /// (r x nq: `q_body = E q`), `elastic_shapes` (n x nq), `floating`
    /// and `nodes` (per interface node: `id`, `position`, `translations` and
    /// `rotations` (3 x nq)).
    fn invariants<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.source("the floating-frame invariants")?;
        let frame = py
            .detach(|| FloatingFrame::new(&c.sub, c.model.as_ref(), &self.body))
            .map_err(to_py)?;
        let inv = &frame.invariants;
        let e = &frame.elastic;
        let nq = e.transform.ncols();
        let d = PyDict::new(py);
        d.set_item("mass", inv.mass)?;
        d.set_item("md_cm", PyArray1::from_vec(py, inv.md_cm.to_vec()))?;
        let flat3 = |v: &[[f64; 3]]| v.iter().flatten().copied().collect::<Vec<f64>>();
        d.set_item("md_cm1", arrays::rows(py, flat3(&inv.md_cm1), 3)?)?;
        d.set_item("j", arrays::rows(py, flat3(&inv.j), 3)?)?;
        let j1: Vec<f64> = inv.j1.iter().flat_map(|m| flat3(m)).collect();
        d.set_item("j1", PyArray1::from_vec(py, j1).reshape([nq, 3, 3])?)?;
        d.set_item("ct", arrays::dense(py, inv.ct.as_ref())?)?;
        d.set_item("cr", arrays::dense(py, inv.cr.as_ref())?)?;
        d.set_item("cr1", stacked(py, &inv.cr1, nq, 3)?)?;
        d.set_item("me", arrays::dense(py, inv.me.as_ref())?)?;
        d.set_item("ke", arrays::dense(py, e.stiffness.as_ref())?)?;
        let de = e
            .damping
            .as_ref()
            .map(|m| arrays::dense(py, m.as_ref()))
            .transpose()?;
        d.set_item("de", de)?;
        d.set_item("gr", arrays::dense(py, inv.gr.as_ref())?)?;
        d.set_item("ge", arrays::dense(py, inv.ge.as_ref())?)?;
        d.set_item("oe", arrays::dense(py, inv.oe.as_ref())?)?;
        d.set_item("oe1", stacked(py, &inv.oe1, nq, 6)?)?;
        d.set_item(
            "elastic_hz",
            PyArray1::from_vec(py, e.frequencies_hz.clone()),
        )?;
        d.set_item("transform", arrays::dense(py, e.transform.as_ref())?)?;
        d.set_item("elastic_shapes", arrays::dense(py, e.shapes.as_ref())?)?;
        d.set_item("floating", e.floating)?;
        let nodes: Vec<Bound<'py, PyDict>> = frame
            .nodes
            .iter()
            .map(|n| {
                let nd = PyDict::new(py);
                nd.set_item("id", n.id)?;
                nd.set_item("position", PyArray1::from_vec(py, n.position.to_vec()))?;
                nd.set_item("translations", arrays::dense(py, n.translations.as_ref())?)?;
                nd.set_item("rotations", arrays::dense(py, n.rotations.as_ref())?)?;
                let axes = n
                    .axes
                    .as_ref()
                    .map(|a| a.iter().flatten().copied().collect::<Vec<f64>>());
                match axes {
                    Some(r) => nd.set_item("axes", arrays::rows(py, r, 3)?)?,
                    None => nd.set_item("axes", py.None())?,
                }
                Ok(nd)
            })
            .collect::<PyResult<_>>()?;
        d.set_item("nodes", nodes)?;
        Ok(d)
    }

    /// The recovery rows over q (rows x r): for solids and shells 6
    /// stresses (Pa, Voigt xx, yy, zz, xy, yz, zx) per node (a shell's per
    /// node and surface: bottom, middle, top), for beams 12 section forces
    /// per element (N, Qy, Qz, T, My, Mz at start, then end); the mesh is
    /// needed.
    fn recovery<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let c = self.source("the recovery rows")?;
        let model = c
            .model
            .as_ref()
            .ok_or_else(|| invalid("the recovery rows need a mesh; matrices alone have none"))?;
        let rows = py
            .detach(|| flexbody::recover::recovery_matrix(model, &self.body))
            .map_err(to_py)?;
        arrays::dense(py, rows.as_ref())
    }

    /// Writes the body to `path` in `format` (json, sid, mtx (a folder),
    /// mbdyn), as `flexbody reduce --format` does; atomically (a
    /// temporary, then renamed). SID and MBDyn need the model the body
    /// was reduced from.
    #[pyo3(signature = (path, format="json"))]
    fn write(&self, py: Python<'_>, path: PathBuf, format: &str) -> PyResult<()> {
        let format = Format::parse(format).ok_or_else(|| {
            invalid(format!(
                "unknown format '{format}'; expected one of: json, sid, mtx, mbdyn"
            ))
        })?;
        match format {
            Format::Mtx => export::check_folder_writable(&path, "index.json"),
            _ => export::check_writable(&path),
        }
        .map_err(to_py)?;
        let body = &self.body;
        py.detach(|| -> PyResult<()> {
            let output = match &self.source {
                Some(c) => flexbody::output::body_output(
                    &c.sub,
                    c.model.as_ref(),
                    body,
                    format,
                    Default::default(),
                )
                .map_err(to_py)?,
                None => match format {
                    Format::Json | Format::Mtx => BodyOutput {
                        body,
                        nodes: self.nodes.clone(),
                        sid: None,
                        mbdyn: None,
                        metadata: Default::default(),
                    },
                    Format::Sid | Format::Mbdyn => {
                        self.source(&format!("writing {format}"))?;
                        unreachable!("a body without its model is refused above")
                    }
                },
            };
            export::write(&output, format, &path).map_err(to_py)
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<flexbody.Body {}: r = {}, {} DOFs, {} interface DOFs>",
            self.body.method.name(),
            self.body.r(),
            self.body.dof_map.len(),
            self.body.interface.len()
        )
    }
}

/// One `rows x cols` matrix per coordinate as an `(nq, rows, cols)` array.
fn stacked<'py>(
    py: Python<'py>,
    mats: &[faer::Mat<f64>],
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
    let mut data = Vec::with_capacity(mats.len() * rows * cols);
    for m in mats {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                data.push(m[(i, j)]);
            }
        }
    }
    PyArray1::from_vec(py, data).reshape([mats.len(), rows, cols])
}

/// A SID file's floating-frame description.
#[pyclass(module = "flexbody._flexbody", frozen)]
pub struct Sid {
    sid: SidContent,
    dialect: String,
}

#[pymethods]
impl Sid {
    /// The writer's layout (flexbody, welib, PY_SID).
    #[getter]
    fn dialect(&self) -> String {
        self.dialect.clone()
    }

    /// Total mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.sid.refmod.mass
    }

    /// The names of the elastic coordinates.
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.sid.refmod.ielastq.clone()
    }

    /// A Taylor term (`mdcm`, `j`, `ct`, `cr`, `me`, `gr`, `ge`, `oe`,
    /// `ksigma`, `ke`, `de`) as `(m0, m1)`: the constant matrix and the
    /// list of first-order matrices (one per coordinate; empty for order 0).
    #[allow(clippy::type_complexity)]
    fn term<'py>(
        &self,
        py: Python<'py>,
        name: &str,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<Bound<'py, PyArray2<f64>>>)> {
        let s = &self.sid;
        let t = match name.to_ascii_lowercase().as_str() {
            "mdcm" => &s.md_cm,
            "j" => &s.j,
            "ct" => &s.ct,
            "cr" => &s.cr,
            "me" => &s.me,
            "gr" => &s.gr,
            "ge" => &s.ge,
            "oe" => &s.oe,
            "ksigma" => &s.ksigma,
            "ke" => &s.ke,
            "de" => &s.de,
            _ => {
                return Err(invalid(format!(
                    "unknown SID term '{name}'; expected one of: mdcm, j, ct, cr, me, gr, ge, \
                     oe, ksigma, ke, de"
                )))
            }
        };
        let first =
            t.m1.iter()
                .map(|m| arrays::dense(py, m.as_ref()))
                .collect::<PyResult<_>>()?;
        Ok((arrays::dense(py, t.m0.as_ref())?, first))
    }

    /// The frame nodes: one dict each with `id`, `position` (3),
    /// `translations` and `rotations` (3 x nq) and `orientation` (3 x 3).
    fn nodes<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.sid
            .nodes
            .iter()
            .map(|n| {
                let d = PyDict::new(py);
                d.set_item("id", n.id)?;
                let p: Vec<f64> = (0..3).map(|i| n.origin.m0[(i, 0)]).collect();
                d.set_item("position", PyArray1::from_vec(py, p))?;
                d.set_item("translations", arrays::dense(py, n.phi.m0.as_ref())?)?;
                d.set_item("rotations", arrays::dense(py, n.psi.m0.as_ref())?)?;
                d.set_item("orientation", arrays::dense(py, n.ap.m0.as_ref())?)?;
                Ok(d)
            })
            .collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "<flexbody.Sid ({}): {} elastic coordinates, {} nodes, mass {:.6e} kg>",
            self.dialect,
            self.sid.refmod.ielastq.len(),
            self.sid.nodes.len(),
            self.sid.refmod.mass
        )
    }
}

/// Reads a body file as `flexbody inspect` does: a JSON body or a Matrix
/// Market folder (or its index.json) gives a `Body`, a SID file (any
/// dialect) a `Sid`.
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf) -> PyResult<Py<PyAny>> {
    flexbody::file_kind::Takes::INSPECT
        .check(&path)
        .map_err(to_py)?;
    let read = py.detach(|| export::read_any(&path)).map_err(to_py)?;
    Ok(match read {
        AnyBody::Reduced(body, nodes) => Body {
            body: *body,
            source: None,
            nodes,
            interface_source: None,
        }
        .into_pyobject(py)?
        .into_any()
        .unbind(),
        AnyBody::Sid(sid, dialect) => Sid {
            sid: *sid,
            dialect: dialect.to_string(),
        }
        .into_pyobject(py)?
        .into_any()
        .unbind(),
    })
}
