//! Choosing a reduced-body format: [`write()`] by [`Format`], [`read_any`] by
//! what the path holds, [`summary`] for `flexbody inspect` and [`convert`]
//! for `flexbody convert`.

use crate::mbdyn::{write_mbdyn, ModalFem};
use crate::sid::{self, write_sid, Sid};
use crate::{mtx, write_json, BodyNode, ExportError};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use flexbody_fem::DofKind;
use flexbody_reduce::ReducedBody;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

/// A reduced-body file format.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Format {
    /// One JSON document (`flexbody-reduced-body/1`), for small bodies.
    Json,
    /// Standard Input Data (FFRF invariants), for MBS codes.
    Sid,
    /// A folder of Matrix Market files and `index.json`, for large bodies.
    Mtx,
    /// MBDyn's modal FEM file (`.fem`), for its `modal` joint.
    Mbdyn,
}

impl Format {
    /// All formats, by name.
    pub const ALL: [Format; 4] = [Format::Json, Format::Sid, Format::Mtx, Format::Mbdyn];

    /// The CLI name: `json`, `sid`, `mtx`, `mbdyn`.
    pub fn name(self) -> &'static str {
        match self {
            Format::Json => "json",
            Format::Sid => "sid",
            Format::Mtx => "mtx",
            Format::Mbdyn => "mbdyn",
        }
    }

    /// Parses a CLI name (case-insensitive).
    pub fn parse(name: &str) -> Option<Format> {
        Format::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(name))
    }
}

impl std::str::FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Format::parse(s).ok_or_else(|| format!("unknown format '{s}' (json, sid, mtx or mbdyn)"))
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What [`write()`] formats: a reduced body and the values its formats
/// add to it, each computed before (none of the writers computes).
#[derive(Clone, Debug)]
pub struct BodyOutput<'a> {
    /// The body: all of JSON and Matrix Market.
    pub body: &'a ReducedBody,
    /// The nodes of the mesh the body was reduced from, with their
    /// coordinates and lumped masses, for JSON and the Matrix Market index
    /// (none without them).
    pub nodes: Vec<BodyNode>,
    /// The SID content (floating-frame invariants and recovery rows), which
    /// [`Format::Sid`] needs.
    pub sid: Option<Sid>,
    /// The MBDyn content (elastic modes, nodes, lumped masses), which
    /// [`Format::Mbdyn`] needs.
    pub mbdyn: Option<ModalFem>,
    /// The accuracy figures of the Matrix Market index.
    pub metadata: mtx::Metadata,
}

impl<'a> BodyOutput<'a> {
    /// The body alone: no SID or MBDyn content, nodes or accuracy figures.
    pub fn new(body: &'a ReducedBody) -> Self {
        Self {
            body,
            nodes: Vec::new(),
            sid: None,
            mbdyn: None,
            metadata: mtx::Metadata::default(),
        }
    }
}

/// Writes `output` to `path` in `format`: a file for JSON, SID and MBDyn, a
/// folder for MTX. JSON formats the body and the nodes; SID the SID
/// content and MBDyn the MBDyn content (an error without it); MTX the body
/// with the nodes and accuracy figures in its index.
pub fn write(output: &BodyOutput<'_>, format: Format, path: &Path) -> Result<(), ExportError> {
    match format {
        Format::Json => write_json(output.body, &output.nodes, path),
        Format::Sid => match &output.sid {
            Some(sid) => write_sid(sid, path),
            None => Err(ExportError::Missing("the SID content")),
        },
        Format::Mtx => mtx::write_mtx(output.body, &output.nodes, &output.metadata, path),
        Format::Mbdyn => match &output.mbdyn {
            Some(fem) => write_mbdyn(fem, path),
            None => Err(ExportError::Missing("the MBDyn content")),
        },
    }
}

/// A body read by [`read_any`].
#[derive(Clone, Debug)]
pub enum AnyBody {
    /// From JSON or a Matrix Market folder: the full reduced body and the
    /// nodes of its mesh (empty if the file lists none).
    Reduced(Box<ReducedBody>, Vec<BodyNode>),
    /// From a SID file: the FFRF description (no full basis), and the
    /// dialect the file was written in.
    Sid(Box<Sid>, sid::Dialect),
}

impl AnyBody {
    /// The summary `flexbody inspect` prints.
    pub fn summary(&self) -> String {
        match self {
            AnyBody::Reduced(b, nodes) => summary(b) + &nodes_summary(nodes),
            AnyBody::Sid(s, dialect) => sid_summary(s, *dialect),
        }
    }

    /// The same summary as a JSON document (`flexbody inspect --json`):
    /// `format` ("reduced-body" or "sid"), `r`, `mass_kg` (null where the
    /// basis holds no rigid translation), `interface_nodes`,
    /// `frequencies_hz` (null where they cannot be computed, with
    /// `frequency_error`); a reduced body adds `method`, `dofs` and
    /// `interface_dofs`, a SID `dialect` and `center_of_mass_m`.
    pub fn summary_json(&self) -> serde_json::Value {
        let (frequencies, error) = match self {
            AnyBody::Reduced(b, _) => split(b.frequencies_hz()),
            AnyBody::Sid(s, _) => split(s.frequencies_hz()),
        };
        let mut doc = match self {
            AnyBody::Reduced(body, mesh) => {
                let nodes: BTreeSet<u64> = body.interface.iter().map(|d| d.node).collect();
                serde_json::json!({
                    "format": "reduced-body",
                    "method": body.method.name(),
                    "r": body.r(),
                    "dofs": body.dof_map.len(),
                    "mass_kg": body_mass(body),
                    "interface_nodes": nodes,
                    "interface_dofs": body.interface.iter().map(|d| d.to_string()).collect::<Vec<_>>(),
                    "local_axes_nodes": body.local_axes.keys().collect::<Vec<_>>(),
                    "nodes": mesh.len(),
                    "lumped_mass_kg": lumped_mass(mesh),
                })
            }
            AnyBody::Sid(sid, dialect) => serde_json::json!({
                "format": "sid",
                "dialect": dialect.name(),
                "r": sid.nq(),
                "mass_kg": sid.refmod.mass,
                "center_of_mass_m": sid.center_of_mass(),
                "interface_nodes": sid.nodes.iter().map(|n| n.id).collect::<Vec<_>>(),
            }),
        };
        doc["frequencies_hz"] = serde_json::json!(frequencies);
        if let Some(e) = error {
            doc["frequency_error"] = serde_json::json!(e);
        }
        doc
    }
}

/// The frequencies, or `None` and why not.
fn split<E: std::fmt::Display>(f: Result<Vec<f64>, E>) -> (Option<Vec<f64>>, Option<String>) {
    match f {
        Ok(f) => (Some(f), None),
        Err(e) => (None, Some(e.to_string())),
    }
}

/// The body's mass along the rigid translations its basis holds (the
/// largest of them), if it holds any.
fn body_mass(body: &ReducedBody) -> Option<f64> {
    [DofKind::Ux, DofKind::Uy, DofKind::Uz]
        .into_iter()
        .filter_map(|k| translation_mass(body, k))
        .reduce(f64::max)
}

/// The sum of the lumped translational masses of `nodes` along x, y, z
/// (kg), if every node has them.
pub fn lumped_mass(nodes: &[BodyNode]) -> Option<[f64; 3]> {
    if nodes.is_empty() {
        return None;
    }
    nodes.iter().try_fold([0.0; 3], |mut sum, n| {
        let m = n.mass?;
        for (s, v) in sum.iter_mut().zip(m) {
            *s += v;
        }
        Some(sum)
    })
}

/// The summary's line on the mesh's nodes a body file lists: how many, with
/// coordinates, and the sum of their lumped masses.
fn nodes_summary(nodes: &[BodyNode]) -> String {
    if nodes.is_empty() {
        return String::new();
    }
    let located = nodes.iter().filter(|n| n.coords.is_some()).count();
    let mass = match lumped_mass(nodes) {
        Some([x, y, z]) => {
            format!("; lumped masses sum to {x:.6e}, {y:.6e}, {z:.6e} kg along x, y, z")
        }
        None => "; no lumped masses".into(),
    };
    format!(
        "mesh: {}, {located} with coordinates{mass}\n",
        counted(nodes.len(), "node")
    )
}

/// `n` and `noun`, plural unless `n` is 1: "1 node", "3 nodes".
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Reads a reduced body from `path`, recognising the format: a folder (or
/// its `index.json`) is a Matrix Market body, a file whose first significant
/// line is `part` or a PY_SID counts line ([`sid::looks_like_sid`]), or
/// named `.sid` or `.SID_FEM` and not a JSON document, is a SID of any
/// [`sid::Dialect`], any other file is read as JSON. The file is read
/// once, whole (as [`crate::read_json`] reads it).
pub fn read_any(path: &Path) -> Result<AnyBody, ExportError> {
    if path.is_dir() {
        return mtx::read_mtx_with_nodes(path).map(|(b, n)| AnyBody::Reduced(Box::new(b), n));
    }
    let text = crate::read_json_text(path)?;
    let sid_name = path.extension().is_some_and(|e| {
        let e = e.to_string_lossy();
        e.eq_ignore_ascii_case("sid") || e.eq_ignore_ascii_case("sid_fem")
    });
    if sid::looks_like_sid(&text) || (sid_name && !text.trim_start().starts_with('{')) {
        return sid::sid_from_text(path, &text).map(|(s, d)| AnyBody::Sid(Box::new(s), d));
    }
    if text.contains(mtx::INDEX_FORMAT) {
        let dir = path.parent().unwrap_or(Path::new("."));
        return mtx::read_mtx_with_nodes(dir).map(|(b, n)| AnyBody::Reduced(Box::new(b), n));
    }
    crate::json_from_text(path, &text).map(|(b, n)| AnyBody::Reduced(Box::new(b), n))
}

/// Converts the reduced-body file (or Matrix Market folder) `input` to
/// `format` at `out`, through the writers (atomic), and returns what was
/// read. Supported: a SID of any dialect to flexbody's SID; a JSON body
/// or a Matrix Market folder to JSON or Matrix Market, with the nodes it
/// lists (the index then without accuracy figures, which a body does not
/// hold). Refused, saying why and what to do instead: a SID to JSON or
/// Matrix Market (a SID has no full basis), and a JSON or Matrix Market
/// body to SID or MBDyn (the invariants and lumped masses need the
/// model).
pub fn convert(input: &Path, format: Format, out: &Path) -> Result<AnyBody, ExportError> {
    let body = read_any(input)?;
    match (&body, format) {
        (AnyBody::Sid(sid, _), Format::Sid) => write_sid(sid, out)?,
        (AnyBody::Sid(..), _) => {
            return Err(ExportError::Model(format!(
                "{}: a SID cannot be converted to the {format} format: it holds the floating-frame invariants, not the full basis T and the reduced matrices that format holds; reduce the model again with `flexbody reduce MODEL ... --format {format}`, or convert to `--format sid`",
                input.display()
            )))
        }
        (AnyBody::Reduced(..), Format::Sid | Format::Mbdyn) => {
            return Err(ExportError::Model(format!(
                "{}: a reduced body cannot be converted to the {format} format: its invariants (mass, inertia, Ct, Cr, Gr, ...) and lumped masses need the model's mass matrix and node coordinates, which the body does not hold; write it from the model with `flexbody reduce MODEL ... --format {format}`",
                input.display()
            )))
        }
        (AnyBody::Reduced(b, nodes), Format::Json) => write_json(b, nodes, out)?,
        (AnyBody::Reduced(b, nodes), Format::Mtx) => {
            mtx::write_mtx(b, nodes, &mtx::Metadata::default(), out)?
        }
    }
    Ok(body)
}

/// The mass of the rigid translation along `kind` that the basis spans,
/// `a^T M_red a` with `T a` the translation (least squares), if it does.
fn translation_mass(body: &ReducedBody, kind: DofKind) -> Option<f64> {
    let m = body.basis.nrows();
    let target: Vec<f64> = (0..m)
        .map(|i| f64::from(u8::from(body.dof_map.dof(i).kind == kind)))
        .collect();
    let count: f64 = target.iter().sum();
    if count == 0.0 || body.r() == 0 {
        return None;
    }
    let t = &body.basis;
    let rhs = Mat::from_fn(body.r(), 1, |j, _| {
        (0..m).map(|i| t[(i, j)] * target[i]).sum()
    });
    let gram = t.transpose() * t;
    let a = gram.llt(Side::Lower).ok()?.solve(&rhs);
    let ta = t * &a;
    let residual: f64 = (0..m).map(|i| (ta[(i, 0)] - target[i]).powi(2)).sum();
    if residual > 1e-12 * count {
        return None;
    }
    Some((a.transpose() * &body.mass * &a)[(0, 0)])
}

fn list_nodes(nodes: impl IntoIterator<Item = u64>) -> String {
    let v: Vec<String> = nodes.into_iter().map(|n| n.to_string()).collect();
    if v.len() > 20 {
        format!(
            "{} ... {} ({} nodes)",
            v[..10].join(" "),
            v[v.len() - 5..].join(" "),
            v.len()
        )
    } else {
        v.join(" ")
    }
}

fn list_frequencies(f: &[f64]) -> String {
    f.iter()
        .map(|x| format!("{x:.4}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A few lines on `body`: method, r, DOFs, mass (if the basis holds a rigid
/// translation), interface nodes, damping and frequencies (Hz).
pub fn summary(body: &ReducedBody) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "method: {}", body.method);
    let _ = writeln!(s, "r: {}", body.r());
    let _ = writeln!(s, "DOFs of the full model: {}", body.dof_map.len());
    match body_mass(body) {
        Some(m) => {
            let _ = writeln!(s, "mass: {m:.6e} kg");
        }
        None => {
            let _ = writeln!(s, "mass: not in the basis (no rigid translation)");
        }
    }
    let nodes: BTreeSet<u64> = body.interface.iter().map(|d| d.node).collect();
    let _ = writeln!(
        s,
        "interface: {} at {}: {}",
        counted(body.interface.len(), "DOF"),
        counted(nodes.len(), "node"),
        list_nodes(nodes.iter().copied())
    );
    if !body.local_axes.is_empty() {
        let _ = writeln!(
            s,
            "interface DOFs along local axes (*TRANSFORM) at {}: {}",
            counted(body.local_axes.len(), "node"),
            list_nodes(body.local_axes.keys().copied())
        );
    }
    let damping = match &body.damping {
        Some(_) => "D_red = T^T D T (eq. 5-7)",
        None => "none",
    };
    let _ = writeln!(s, "damping: {damping}");
    match body.frequencies_hz() {
        Ok(f) => {
            let _ = writeln!(s, "frequencies (Hz): {}", list_frequencies(&f));
        }
        Err(e) => {
            let _ = writeln!(s, "frequencies: not available ({e})");
        }
    }
    s
}

fn sid_summary(sid: &Sid, dialect: sid::Dialect) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "format: SID (floating frame of reference)");
    let _ = writeln!(s, "dialect: {dialect}");
    let _ = writeln!(s, "r: {} elastic coordinates", sid.nq());
    let _ = writeln!(s, "mass: {:.6e} kg", sid.refmod.mass);
    let c = sid.center_of_mass();
    let _ = writeln!(
        s,
        "centre of mass: [{:.6e}, {:.6e}, {:.6e}] m",
        c[0], c[1], c[2]
    );
    let _ = writeln!(
        s,
        "interface: {}: {}",
        counted(sid.nodes.len(), "node"),
        list_nodes(sid.nodes.iter().map(|n| n.id))
    );
    match sid.frequencies_hz() {
        Ok(f) => {
            let _ = writeln!(s, "frequencies (Hz): {}", list_frequencies(&f));
        }
        Err(e) => {
            let _ = writeln!(s, "frequencies: not available ({e})");
        }
    }
    s
}
