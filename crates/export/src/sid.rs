//! Standard Input Data (SID, Wallrapp 1994) of a reduced body: the floating
//! frame of reference description that MBS codes read (report ref. \[6\]).
//!
//! The file is text, in the block layout of SID writers:
//!
//! ```text
//! part
//! new modal
//! refmod ... end refmod            (mass, nelastq, ielastq(i))
//! new frame
//! new node ... end node            (one per interface node: rframe,
//!                                   origin, phi, psi, AP)
//! end frame
//! mdCM, J, Ct, Cr, Me, Gr, Ge, Oe, ksigma, Ke, De   (Taylor objects)
//! end modal
//! end part
//! ```
//!
//! Each quantity is a Taylor expansion `A(q) = m0 + sum_k m1_k q_k`, written
//! as `order`, `nrow`, `ncol`, `nq`, `nqn`, `structure` and the entries
//! `m0( i, j) = v` and `m1( i, j, k) = v` (1-based). Field by field, with the
//! formula behind each, in `docs/sid.md`. The invariants come computed, as
//! a [`FloatingFrame`] of `flexbody_reduce::ffrf`, with the recovery rows:
//! [`Sid::new`] lays them out as Taylor objects.
//!
//! The reader ([`read_sid`], [`parse_sid`]) takes this layout and the
//! dialects of two other writers, welib's and PY_SID's ([`Dialect`]),
//! recognised from the text, and brings them to the conventions above
//! (`J` 3 x 3, `m1` per coordinate, every entry stored). It checks every
//! count and names the block and the line of what is wrong.

use crate::float_text::push_exp;
use crate::{write_atomically, ExportError};
use faer::{Mat, MatRef};
use flexbody_reduce::ffrf::FloatingFrame;
use std::io::{self, Write};
use std::path::Path;

mod dialect;
mod read;

pub use dialect::{looks_like_sid, Dialect};
pub use read::{parse_sid, parse_sid_dialect};

/// `structure` code of a Taylor object whose entries are all listed.
pub const FULL: usize = 3;
/// `structure` code of a Taylor object that is zero (no entries listed).
pub const ZERO: usize = 0;

/// A Taylor-expansion object `A(q) = m0 + sum_k m1_k q_k`.
#[derive(Clone, Debug, PartialEq)]
pub struct Taylor {
    /// 0 (constant) or 1 (linear in q).
    pub order: usize,
    pub nrow: usize,
    pub ncol: usize,
    /// Number of elastic coordinates the first order refers to.
    pub nq: usize,
    /// Number of second-order terms (always 0 here).
    pub nqn: usize,
    /// [`FULL`] or [`ZERO`].
    pub structure: usize,
    /// Zero order, nrow x ncol.
    pub m0: Mat<f64>,
    /// First order, one nrow x ncol matrix per coordinate (empty if order 0).
    pub m1: Vec<Mat<f64>>,
}

impl Taylor {
    /// A constant object.
    pub fn constant(m0: Mat<f64>, nq: usize) -> Self {
        Self {
            order: 0,
            nrow: m0.nrows(),
            ncol: m0.ncols(),
            nq,
            nqn: 0,
            structure: FULL,
            m0,
            m1: Vec::new(),
        }
    }

    /// A first-order object.
    pub fn linear(m0: Mat<f64>, m1: Vec<Mat<f64>>) -> Self {
        Self {
            order: 1,
            nrow: m0.nrows(),
            ncol: m0.ncols(),
            nq: m1.len(),
            nqn: 0,
            structure: FULL,
            m0,
            m1,
        }
    }

    /// Value at `q` (first order).
    pub fn at(&self, q: &[f64]) -> Mat<f64> {
        let mut a = self.m0.clone();
        for (m1, qk) in self.m1.iter().zip(q) {
            a += m1 * faer::Scale(*qk);
        }
        a
    }
}

/// `refmod`: the body's mass and the names of its elastic coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Refmod {
    pub mass: f64,
    /// One name per elastic coordinate (`nelastq` of them).
    pub ielastq: Vec<String>,
}

/// A node of the frame (an interface node of the body).
#[derive(Clone, Debug, PartialEq)]
pub struct SidNode {
    /// Node id of the FE model.
    pub id: u64,
    /// Position `m0` (3 x 1) and its change `m1_k = phi_k`.
    pub origin: Taylor,
    /// Translational mode shapes (3 x nq).
    pub phi: Taylor,
    /// Rotational mode shapes (3 x nq).
    pub psi: Taylor,
    /// Orientation of the node frame `(I + psi~ q) R` (3 x 3, first
    /// order; `R = I` unless the interface is along local axes there).
    pub ap: Taylor,
}

/// A SID file's content.
#[derive(Clone, Debug, PartialEq)]
pub struct Sid {
    pub refmod: Refmod,
    pub nodes: Vec<SidNode>,
    pub md_cm: Taylor,
    pub j: Taylor,
    pub ct: Taylor,
    pub cr: Taylor,
    pub me: Taylor,
    pub gr: Taylor,
    pub ge: Taylor,
    pub oe: Taylor,
    /// Modal stresses (6 rows per solid node, Voigt, Pa) or beam section
    /// forces (12 rows per element, N Qy Qz T My Mz at start then end).
    pub ksigma: Taylor,
    pub ke: Taylor,
    pub de: Taylor,
}

fn skew(v: [f64; 3]) -> Mat<f64> {
    let m = [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
    Mat::from_fn(3, 3, |i, j| m[i][j])
}

impl Sid {
    /// The SID of a body in its floating `frame`, with `ksigma` the
    /// recovery rows in the elastic coordinates (nq columns; no rows
    /// without a mesh): the invariants and frame nodes laid out as Taylor
    /// objects, the elastic modes named by their frequencies.
    pub fn new(frame: FloatingFrame, ksigma: Mat<f64>) -> Self {
        let nq = frame.nq();
        let FloatingFrame {
            elastic: basis,
            invariants: inv,
            nodes,
        } = frame;
        let col3 = |v: [f64; 3]| Mat::from_fn(3, 1, |i, _| v[i]);
        let m33 = |a: [[f64; 3]; 3]| Mat::from_fn(3, 3, |i, j| a[i][j]);
        let nodes = nodes
            .into_iter()
            .map(|node| {
                let (id, x, phi, psi) = (node.id, node.position, node.translations, node.rotations);
                // The node frame: the local axes where the interface is
                // along them, else the body frame's.
                let axes = node.axes.map_or_else(|| Mat::identity(3, 3), m33);
                SidNode {
                    id,
                    origin: Taylor::linear(
                        col3(x),
                        (0..nq)
                            .map(|k| Mat::from_fn(3, 1, |i, _| phi[(i, k)]))
                            .collect(),
                    ),
                    ap: Taylor::linear(
                        axes.clone(),
                        (0..nq)
                            .map(|k| skew([psi[(0, k)], psi[(1, k)], psi[(2, k)]]) * &axes)
                            .collect(),
                    ),
                    phi: Taylor::constant(phi, nq),
                    psi: Taylor::constant(psi, nq),
                }
            })
            .collect();
        let frequencies = &basis.frequencies_hz;
        Self {
            refmod: Refmod {
                mass: inv.mass,
                ielastq: frequencies
                    .iter()
                    .enumerate()
                    .map(|(k, f)| format!("Eigen Mode {:4} : {f:.6e} Hz", k + 1))
                    .collect(),
            },
            nodes,
            md_cm: Taylor::linear(col3(inv.md_cm), inv.md_cm1.into_iter().map(col3).collect()),
            j: Taylor::linear(m33(inv.j), inv.j1.into_iter().map(m33).collect()),
            ct: Taylor::constant(inv.ct, nq),
            cr: Taylor::linear(inv.cr, inv.cr1),
            me: Taylor::constant(inv.me, nq),
            gr: Taylor::constant(inv.gr, nq),
            ge: Taylor::constant(inv.ge, nq),
            oe: Taylor::linear(inv.oe, inv.oe1),
            ksigma: Taylor::constant(ksigma, nq),
            ke: Taylor::constant(basis.stiffness, nq),
            de: Taylor::constant(basis.damping.unwrap_or_else(|| Mat::zeros(nq, nq)), nq),
        }
    }

    /// Number of elastic coordinates.
    pub fn nq(&self) -> usize {
        self.refmod.ielastq.len()
    }

    /// Centre of mass of the undeformed body (m).
    pub fn center_of_mass(&self) -> [f64; 3] {
        std::array::from_fn(|i| self.md_cm.m0[(i, 0)] / self.refmod.mass)
    }

    /// Natural frequencies of the elastic modes (Hz), from `Ke` and `Me`.
    pub fn frequencies_hz(&self) -> Result<Vec<f64>, ExportError> {
        flexbody_reduce::natural_frequencies_hz(self.ke.m0.as_ref(), self.me.m0.as_ref())
            .map_err(|e| ExportError::Model(format!("SID modal matrices: {e}")))
    }

    /// The Taylor objects after the frame, in file order, with their names.
    pub fn quantities(&self) -> [(&'static str, &Taylor); 11] {
        [
            ("mdCM", &self.md_cm),
            ("J", &self.j),
            ("Ct", &self.ct),
            ("Cr", &self.cr),
            ("Me", &self.me),
            ("Gr", &self.gr),
            ("Ge", &self.ge),
            ("Oe", &self.oe),
            ("ksigma", &self.ksigma),
            ("Ke", &self.ke),
            ("De", &self.de),
        ]
    }

    /// The SID text.
    pub fn to_text(&self) -> String {
        let mut text = Vec::new();
        self.write_text(&mut text)
            .expect("writing to memory does not fail");
        String::from_utf8(text).expect("the SID text is UTF-8")
    }

    /// Writes the SID text to `out`; the entries of large matrices (the
    /// stress modes `ksigma` of every node) are formatted in parallel.
    pub fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(
            out,
            "# flexbody SID (Wallrapp 1994), SI units: m, kg, s, N, rad"
        )?;
        writeln!(out, "# fields and formulas: docs/sid.md")?;
        out.write_all(b"part\nnew modal\nrefmod\n")?;
        writeln!(out, "  mass = {:e}", self.refmod.mass)?;
        writeln!(out, "  nelastq = {}", self.refmod.ielastq.len())?;
        for (i, name) in self.refmod.ielastq.iter().enumerate() {
            writeln!(out, "  ielastq({}) = '{}'", i + 1, name.replace('\'', " "))?;
        }
        out.write_all(b"end refmod\nnew frame\n")?;
        for node in &self.nodes {
            out.write_all(b"new node\n")?;
            writeln!(out, "  rframe = '{}'", node.id)?;
            for (name, t) in [
                ("origin", &node.origin),
                ("phi", &node.phi),
                ("psi", &node.psi),
                ("AP", &node.ap),
            ] {
                write_taylor(out, name, t, "  ")?;
            }
            out.write_all(b"end node\n")?;
        }
        out.write_all(b"end frame\n")?;
        for (name, t) in self.quantities() {
            write_taylor(out, name, t, "")?;
        }
        out.write_all(b"end modal\nend part\n")
    }
}

fn write_taylor(out: &mut dyn Write, name: &str, t: &Taylor, indent: &str) -> io::Result<()> {
    writeln!(out, "{indent}{name}")?;
    for (key, v) in [
        ("order", t.order),
        ("nrow", t.nrow),
        ("ncol", t.ncol),
        ("nq", t.nq),
        ("nqn", t.nqn),
        ("structure", t.structure),
    ] {
        writeln!(out, "{indent}  {key} = {v}")?;
    }
    if t.structure == FULL {
        write_entries(out, indent, t.m0.as_ref(), None)?;
        for (k, m1) in t.m1.iter().enumerate() {
            write_entries(out, indent, m1.as_ref(), Some(k + 1))?;
        }
    }
    writeln!(out, "{indent}end {name}")
}

/// One line `m0(i, j) = v` (or `m1(i, j, k) = v`) per entry of `m`, row
/// by row; blocks of rows are formatted in parallel and written in order.
fn write_entries(
    out: &mut dyn Write,
    indent: &str,
    m: MatRef<'_, f64>,
    k: Option<usize>,
) -> io::Result<()> {
    use rayon::prelude::*;
    use std::fmt::Write as _;
    const ROWS: usize = 512;
    let starts: Vec<usize> = (0..m.nrows()).step_by(ROWS).collect();
    let block = |&first: &usize| {
        let mut s = String::new();
        for i in first..(first + ROWS).min(m.nrows()) {
            for j in 0..m.ncols() {
                let _ = match k {
                    None => write!(s, "{indent}  m0({}, {}) = ", i + 1, j + 1),
                    Some(k) => write!(s, "{indent}  m1({}, {}, {k}) = ", i + 1, j + 1),
                };
                push_exp(&mut s, m[(i, j)]);
                s.push('\n');
            }
        }
        s
    };
    // A few blocks per thread at a time, so that the text of a large
    // matrix is never in memory whole; the next batch is formatted while
    // this thread writes the last one.
    let batches = starts.chunks(8 * rayon::current_num_threads());
    if batches.len() <= 1 {
        for text in starts.iter().map(block) {
            out.write_all(text.as_bytes())?;
        }
        return Ok(());
    }
    std::thread::scope(|scope| {
        let (send, texts) = std::sync::mpsc::sync_channel::<Vec<String>>(1);
        scope.spawn(move || {
            for batch in batches {
                // The receiver is gone after a write error: stop.
                if send.send(batch.par_iter().map(block).collect()).is_err() {
                    break;
                }
            }
        });
        for batch in texts {
            for text in &batch {
                out.write_all(text.as_bytes())?;
            }
        }
        Ok(())
    })
}

/// Writes `sid` to `path`, atomically; refuses non-finite values.
pub fn write_sid(sid: &Sid, path: &Path) -> Result<(), ExportError> {
    for (name, t) in sid.quantities() {
        crate::writable(t.m0.as_ref(), &format!("{name} (m0)"))?;
        for (k, m) in t.m1.iter().enumerate() {
            crate::writable(m.as_ref(), &format!("{name} (m1 of coordinate {})", k + 1))?;
        }
    }
    write_atomically(path, |out| sid.write_text(out))
}

/// Reads a SID file of any [`Dialect`] (flexbody's own, as [`write_sid`]
/// writes it, welib's or PY_SID's) into flexbody's conventions.
pub fn read_sid(path: &Path) -> Result<Sid, ExportError> {
    read_sid_dialect(path).map(|(sid, _)| sid)
}

/// [`read_sid`], with the dialect the file was written in.
pub fn read_sid_dialect(path: &Path) -> Result<(Sid, Dialect), ExportError> {
    sid_from_text(path, &crate::read_text(path)?)
}

/// The SID in `text` and its dialect, read from `path` (which errors
/// name).
pub(crate) fn sid_from_text(path: &Path, text: &str) -> Result<(Sid, Dialect), ExportError> {
    parse_sid_dialect(text).map_err(|e| ExportError::Format {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// A parse error: line (1-based), the block it is in, and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    pub line: usize,
    pub block: String,
    pub message: String,
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {}, block '{}': {}",
            self.line, self.block, self.message
        )
    }
}
