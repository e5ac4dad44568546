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
//! [`Sid::new`] lays them out as Taylor objects. The reader checks every
//! count and names the block and the line of what is wrong.

use crate::float_text::push_exp;
use crate::{write_atomically, ExportError};
use faer::{Mat, MatRef};
use flexbody_io::text::{excerpt, finite_number};
use flexbody_linalg::memory::Budget;
use flexbody_reduce::ffrf::FloatingFrame;
use std::io::{self, Write};
use std::path::Path;

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
    /// Orientation `I + psi~ q` (3 x 3, first order).
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
                SidNode {
                    id,
                    origin: Taylor::linear(
                        col3(x),
                        (0..nq)
                            .map(|k| Mat::from_fn(3, 1, |i, _| phi[(i, k)]))
                            .collect(),
                    ),
                    ap: Taylor::linear(
                        Mat::identity(3, 3),
                        (0..nq)
                            .map(|k| skew([psi[(0, k)], psi[(1, k)], psi[(2, k)]]))
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

/// Reads a SID file written by [`write_sid`].
pub fn read_sid(path: &Path) -> Result<Sid, ExportError> {
    sid_from_text(path, &crate::read_text(path)?)
}

/// The SID in `text`, read from `path` (which errors name).
pub(crate) fn sid_from_text(path: &Path, text: &str) -> Result<Sid, ExportError> {
    parse_sid(text).map_err(|e| ExportError::Format {
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

/// Line cursor over the significant lines of a SID text.
struct Lines<'a> {
    text: &'a str,
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            text,
            lines: text.lines().enumerate(),
        }
    }

    fn next(&mut self, block: &str, opened: usize) -> Result<(usize, &'a str), ParseError> {
        for (i, l) in self.lines.by_ref() {
            let l = l.trim();
            if !l.is_empty() && !l.starts_with('#') && !l.starts_with('!') {
                return Ok((i + 1, l));
            }
        }
        Err(ParseError {
            line: self.text.lines().count(),
            block: block.to_string(),
            message: format!("the file ends inside block '{block}' (opened at line {opened})"),
        })
    }

    fn expect(&mut self, keyword: &str, block: &str, opened: usize) -> Result<usize, ParseError> {
        let (n, l) = self.next(block, opened)?;
        if l.eq_ignore_ascii_case(keyword) {
            Ok(n)
        } else {
            Err(ParseError {
                line: n,
                block: block.to_string(),
                message: format!("expected '{keyword}', found '{l}'", l = excerpt(l)),
            })
        }
    }
}

fn key_value(l: &str) -> Option<(&str, &str)> {
    let (k, v) = l.split_once('=')?;
    Some((k.trim(), v.trim()))
}

/// `name(1, 2, 3)` -> ("name", [1, 2, 3]): a name and one to three
/// indices.
fn indexed(key: &str) -> Option<(&str, Indices)> {
    let (name, rest) = key.split_once('(')?;
    let inner = rest.strip_suffix(')')?;
    let mut idx = Indices::default();
    for s in inner.split(',') {
        *idx.values.get_mut(idx.len)? = s.trim().parse().ok()?;
        idx.len += 1;
    }
    Some((name.trim(), idx))
}

/// The indices of an entry `name(i, j, k)`, without a heap allocation
/// (a SID holds millions of entries).
#[derive(Default)]
struct Indices {
    values: [usize; 3],
    len: usize,
}

impl Indices {
    fn as_slice(&self) -> &[usize] {
        &self.values[..self.len]
    }
}

/// One block `name` (a Taylor expansion) of `nq` coordinates that must be
/// `shape` (rows, columns; `usize::MAX` rows: any). Its shape and its
/// count of entries are checked before storage is taken for it, and the
/// storage against the memory left ([`Budget::MACHINE`]).
fn parse_taylor(
    lines: &mut Lines<'_>,
    name: &str,
    opened: usize,
    nq: usize,
    shape: (usize, usize),
) -> Result<Taylor, ParseError> {
    let err = |line: usize, message: String| ParseError {
        line,
        block: name.to_string(),
        message,
    };
    let mut header = [None::<usize>; 6];
    const KEYS: [&str; 6] = ["order", "nrow", "ncol", "nq", "nqn", "structure"];
    let mut m0: Vec<(usize, usize, usize, f64)> = Vec::new();
    let mut m1: Vec<(usize, usize, usize, usize, f64)> = Vec::new();
    let end = format!("end {name}");
    let end_line = loop {
        let (n, l) = lines.next(name, opened)?;
        if l.eq_ignore_ascii_case(&end) {
            break n;
        }
        if l.starts_with("end ") || l.starts_with("new ") {
            return Err(err(
                n,
                format!(
                    "'{l}' before 'end {name}' (block opened at line {opened})",
                    l = excerpt(l)
                ),
            ));
        }
        let (k, v) = key_value(l).ok_or_else(|| {
            err(
                n,
                format!("expected 'key = value', found '{l}'", l = excerpt(l)),
            )
        })?;
        if let Some(slot) = KEYS.iter().position(|key| k.eq_ignore_ascii_case(key)) {
            if header[slot].is_some() {
                return Err(err(n, format!("'{}' is given twice", KEYS[slot])));
            }
            header[slot] = Some(
                v.parse()
                    .map_err(|_| err(n, format!("{k} = '{v}' is not a count", v = excerpt(v))))?,
            );
            continue;
        }
        let (kind, idx) =
            indexed(k).ok_or_else(|| err(n, format!("unknown entry '{k}'", k = excerpt(k))))?;
        let value = finite_number(v).map_err(|m| err(n, m))?;
        match (kind, idx.as_slice()) {
            ("m0", [i, j]) => m0.push((n, *i, *j, value)),
            ("m1", [i, j, k]) => m1.push((n, *i, *j, *k, value)),
            _ => return Err(err(n, format!("unknown entry '{k}'", k = excerpt(k)))),
        }
    };
    let mut h = [0usize; 6];
    for (slot, key) in KEYS.iter().enumerate() {
        h[slot] = header[slot].ok_or_else(|| err(end_line, format!("'{key}' is missing")))?;
    }
    let [order, nrow, ncol, tq, nqn, structure] = h;
    if order > 1 {
        return Err(err(
            end_line,
            format!("order {order} is not supported (0 or 1)"),
        ));
    }
    if tq != nq {
        return Err(err(
            end_line,
            format!("nq = {tq}, but refmod has nelastq = {nq}"),
        ));
    }
    if structure != FULL && structure != ZERO {
        return Err(err(
            end_line,
            format!("structure {structure} is not supported (0 or 3)"),
        ));
    }
    let (rows, cols) = shape;
    if (rows != usize::MAX && nrow != rows) || ncol != cols {
        let rows = if rows == usize::MAX { nrow } else { rows };
        return Err(err(
            opened,
            format!("is {nrow} x {ncol}, expected {rows} x {cols}"),
        ));
    }
    let matrices = if order == 1 { nq + 1 } else { 1 };
    let entries = nrow.checked_mul(ncol);
    let bytes = entries
        .and_then(|e| e.checked_mul(matrices))
        .and_then(|e| e.checked_mul(std::mem::size_of::<f64>()));
    let what = format!("{matrices} matrices of {nrow} x {ncol}");
    Budget::MACHINE
        .ensure(bytes.map_or(u64::MAX, |b| b as u64), &what)
        .map_err(|e| err(opened, e.to_string()))?;
    let entries = entries.unwrap_or(usize::MAX);
    let expect = |count: usize, want: usize, what: &str| {
        if count == want {
            Ok(())
        } else {
            Err(err(end_line, format!("{count} {what} entries, expected {want} (nrow = {nrow}, ncol = {ncol}, nq = {nq}, structure = {structure})")))
        }
    };
    let full = structure == FULL;
    expect(m0.len(), if full { entries } else { 0 }, "m0")?;
    expect(
        m1.len(),
        if full && order == 1 {
            entries.saturating_mul(nq)
        } else {
            0
        },
        "m1",
    )?;
    // Every entry once: the counts matched, so a repeated entry hides a
    // missing one. An entry not yet given is NaN (values read are finite),
    // so a repeat is seen without a second table.
    let unset = if full { f64::NAN } else { 0.0 };
    let mut a0 = Mat::from_fn(nrow, ncol, |_, _| unset);
    let mut a1 = vec![a0.clone(); if order == 1 { nq } else { 0 }];
    for &(n, i, j, v) in &m0 {
        if i == 0 || j == 0 || i > nrow || j > ncol {
            return Err(err(n, format!("m0({i}, {j}) is outside {nrow} x {ncol}")));
        }
        if !a0[(i - 1, j - 1)].is_nan() {
            let first = m0.iter().find(|e| (e.1, e.2) == (i, j)).map_or(0, |e| e.0);
            return Err(err(
                n,
                format!("m0({i}, {j}) is given twice (first at line {first})"),
            ));
        }
        a0[(i - 1, j - 1)] = v;
    }
    for &(n, i, j, k, v) in &m1 {
        if i == 0 || j == 0 || k == 0 || i > nrow || j > ncol || k > nq {
            return Err(err(
                n,
                format!("m1({i}, {j}, {k}) is outside {nrow} x {ncol} x {nq}"),
            ));
        }
        if !a1[k - 1][(i - 1, j - 1)].is_nan() {
            let first = m1
                .iter()
                .find(|e| (e.1, e.2, e.3) == (i, j, k))
                .map_or(0, |e| e.0);
            return Err(err(
                n,
                format!("m1({i}, {j}, {k}) is given twice (first at line {first})"),
            ));
        }
        a1[k - 1][(i - 1, j - 1)] = v;
    }
    Ok(Taylor {
        order,
        nrow,
        ncol,
        nq,
        nqn,
        structure,
        m0: a0,
        m1: a1,
    })
}

/// The inertia tensor `J` and the modal mass, stiffness and damping
/// `Me`, `Ke`, `De` are symmetric (each order); `J`, `Me` and `De` are
/// positive semi-definite (their constant part), and `Ke` with `Me` has
/// no negative eigenvalue (checked by the caller): a file where they are
/// not describes no body.
fn check_symmetric_semi_definite(t: &Taylor, name: &str, line: usize) -> Result<(), ParseError> {
    use flexbody_linalg::dense_check::{semi_definite, symmetric};
    let err = |message: String| ParseError {
        line,
        block: name.to_string(),
        message,
    };
    symmetric(t.m0.as_ref()).map_err(|e| err(format!("m0 {e}")))?;
    for (k, m1) in t.m1.iter().enumerate() {
        symmetric(m1.as_ref()).map_err(|e| err(format!("m1(:, :, {}) {e}", k + 1)))?;
    }
    if name == "Ke" {
        return Ok(());
    }
    semi_definite(t.m0.as_ref()).map_err(|e| err(format!("m0 {e}")))
}

/// Parses SID text (see the module docs).
pub fn parse_sid(text: &str) -> Result<Sid, ParseError> {
    let mut lines = Lines::new(text);
    let part = lines.expect("part", "part", 1)?;
    let modal = lines.expect("new modal", "part", part)?;
    let refmod_line = lines.expect("refmod", "modal", modal)?;
    let mut mass = None;
    let mut nelastq = None;
    let mut names: Vec<(usize, usize, String)> = Vec::new();
    let bad = |line, message: String| ParseError {
        line,
        block: "refmod".into(),
        message,
    };
    let refmod_end = loop {
        let (n, l) = lines.next("refmod", refmod_line)?;
        if l.eq_ignore_ascii_case("end refmod") {
            break n;
        }
        let (k, v) = key_value(l).ok_or_else(|| {
            bad(
                n,
                format!("expected 'key = value', found '{l}'", l = excerpt(l)),
            )
        })?;
        if k.eq_ignore_ascii_case("mass") {
            let m = finite_number(v).map_err(|m| bad(n, format!("mass: {m}")))?;
            if m <= 0.0 || mass.is_some() {
                let why = if m <= 0.0 {
                    "is not positive"
                } else {
                    "is given twice"
                };
                return Err(bad(n, format!("mass {v} {why}", v = excerpt(v))));
            }
            mass = Some(m);
        } else if k.eq_ignore_ascii_case("nelastq") {
            if nelastq.is_some() {
                return Err(bad(n, "nelastq is given twice".into()));
            }
            nelastq =
                Some(v.parse::<usize>().map_err(|_| {
                    bad(n, format!("nelastq '{v}' is not a count", v = excerpt(v)))
                })?);
        } else if let Some(("ielastq", idx)) = indexed(k) {
            let [i] = idx.as_slice() else {
                return Err(bad(n, format!("'{k}' needs one index", k = excerpt(k))));
            };
            names.push((n, *i, v.trim_matches('\'').trim().to_string()));
        } else {
            return Err(bad(n, format!("unknown entry '{k}'", k = excerpt(k))));
        }
    };
    let mass = mass.ok_or_else(|| bad(refmod_end, "'mass' is missing".into()))?;
    let nq = nelastq.ok_or_else(|| bad(refmod_end, "'nelastq' is missing".into()))?;
    if names.len() != nq {
        return Err(bad(
            refmod_end,
            format!("{} ielastq names, nelastq = {nq}", names.len()),
        ));
    }
    let mut ielastq = vec![None; nq];
    for (n, i, name) in names {
        if i == 0 || i > nq {
            return Err(bad(n, format!("ielastq({i}) is outside 1..{nq}")));
        }
        if ielastq[i - 1].replace(name).is_some() {
            return Err(bad(n, format!("ielastq({i}) is given twice")));
        }
    }
    let ielastq = ielastq.into_iter().map(Option::unwrap_or_default).collect();
    let frame = lines.expect("new frame", "modal", modal)?;
    let mut nodes = Vec::new();
    let mut node_lines: Vec<(u64, usize)> = Vec::new();
    loop {
        let (n, l) = lines.next("frame", frame)?;
        if l.eq_ignore_ascii_case("end frame") {
            break;
        }
        if !l.eq_ignore_ascii_case("new node") {
            return Err(ParseError {
                line: n,
                block: "frame".into(),
                message: format!(
                    "expected 'new node' or 'end frame', found '{l}'",
                    l = excerpt(l)
                ),
            });
        }
        let (rn, rl) = lines.next("node", n)?;
        let id = key_value(rl)
            .filter(|(k, _)| k.eq_ignore_ascii_case("rframe"))
            .and_then(|(_, v)| v.trim_matches('\'').trim().parse::<u64>().ok())
            .ok_or_else(|| ParseError {
                line: rn,
                block: "node".into(),
                message: format!(
                    "expected \"rframe = '<node id>'\", found '{rl}'",
                    rl = excerpt(rl)
                ),
            })?;
        let mut parts = Vec::new();
        for name in ["origin", "phi", "psi", "AP"] {
            let opened = lines.expect(name, "node", n)?;
            let shape = match name {
                "origin" => (3, 1),
                "AP" => (3, 3),
                _ => (3, nq),
            };
            parts.push(parse_taylor(&mut lines, name, opened, nq, shape)?);
        }
        lines.expect("end node", "node", n)?;
        node_lines.push((id, rn));
        let mut parts = parts.into_iter();
        let mut take = || parts.next().expect("four parts");
        nodes.push(SidNode {
            id,
            origin: take(),
            phi: take(),
            psi: take(),
            ap: take(),
        });
    }
    // Each node once; a repeat is named at its second line.
    node_lines.sort_unstable();
    if let Some(w) = node_lines.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(ParseError {
            line: w[1].1,
            block: "node".into(),
            message: format!("node {} is given twice (first at line {})", w[0].0, w[0].1),
        });
    }
    let expected: [(&str, usize, usize); 11] = [
        ("mdCM", 3, 1),
        ("J", 3, 3),
        ("Ct", nq, 3),
        ("Cr", nq, 3),
        ("Me", nq, nq),
        ("Gr", 3, 3 * nq),
        ("Ge", nq, 3 * nq),
        ("Oe", nq, 6),
        ("ksigma", usize::MAX, nq),
        ("Ke", nq, nq),
        ("De", nq, nq),
    ];
    let mut q: Vec<Taylor> = Vec::with_capacity(11);
    for (name, rows, cols) in expected {
        let opened = lines.expect(name, "modal", modal)?;
        let t = parse_taylor(&mut lines, name, opened, nq, (rows, cols))?;
        if ["J", "Me", "Ke", "De"].contains(&name) {
            check_symmetric_semi_definite(&t, name, opened)?;
        }
        if name == "Ke" {
            // q[4] is Me: the elastic modes are stable.
            flexbody_linalg::dense_check::stable_pencil(t.m0.as_ref(), q[4].m0.as_ref()).map_err(
                |e| ParseError {
                    line: opened,
                    block: name.into(),
                    message: format!("m0 {e}"),
                },
            )?;
        }
        q.push(t);
    }
    lines.expect("end modal", "modal", modal)?;
    lines.expect("end part", "part", part)?;
    let mut q = q.into_iter();
    let mut take = || q.next().expect("eleven quantities");
    Ok(Sid {
        refmod: Refmod { mass, ielastq },
        nodes,
        md_cm: take(),
        j: take(),
        ct: take(),
        cr: take(),
        me: take(),
        gr: take(),
        ge: take(),
        oe: take(),
        ksigma: take(),
        ke: take(),
        de: take(),
    })
}
