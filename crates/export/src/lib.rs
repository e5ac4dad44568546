//! Formats reduced bodies as files (JSON, SID, Matrix Market, VTK), and reads them.
//!
//! A [`ReducedBody`] becomes
//!
//! - a self-describing JSON document (units, DOF map, method, modes,
//!   frequencies, matrices), this module;
//! - a Standard Input Data file (SID, Wallrapp 1994) in the floating frame
//!   of reference formulation, [`sid`], from the invariants computed in
//!   `flexbody_reduce::ffrf` and the recovery rows;
//! - a folder of Matrix Market files with a JSON index, [`mtx`], for large
//!   bodies;
//! - MBDyn's modal FEM file for its `modal` joint, [`mbdyn`], from the same
//!   floating frame, the mesh's nodes and their lumped masses;
//! - columns of numbers (time histories, transfer functions) as CSV,
//!   [`columns`], refusing any value that is not finite;
//! - a VTK unstructured grid with the mode shapes and modal stresses for
//!   ParaView, [`vtk`], from the modes and stresses computed for it, as
//!   zlib-compressed binary or ASCII XML ([`vtu`]).
//!
//! The writers only format values they are given: what a format adds to the
//! body (SID content, MBDyn content, accuracy figures) comes in a
//! [`BodyOutput`].
//! [`write()`] and [`read_any`] pick the format; [`summary`] describes a body
//! in a few lines. Readers check every count and name the block and line of
//! what is wrong. Writers go through [`write_atomically`]: a temporary file
//! beside the target, renamed on success, so a failed write never leaves a
//! half-written file; a folder of files goes through a [`FileSet`], renamed
//! only when every file is written, so it never mixes two bodies. Only
//! regular files are replaced, never a device, a FIFO or a symbolic link.

pub mod columns;
mod float_text;
pub mod format;
mod json_layout;
pub mod mbdyn;
pub mod mtx;
pub mod sid;
pub mod vtk;
pub mod vtu;
mod zlib_blocks;

pub use format::{convert, read_any, summary, write, AnyBody, BodyOutput, Format};
pub use mbdyn::{write_mbdyn, ModalFem};
pub use sid::{read_sid, write_sid, Dialect, Sid};

use faer::Mat;
use flexbody_fem::{Dof, DofMap, NodeId};
use flexbody_reduce::{Method, ModeKind, ReducedBody};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Errors writing or reading reduced-body files; each names the path.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("{}: cannot write: {cause}", .path.display())]
    Write {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("{}: cannot read: {cause}", .path.display())]
    Read {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("{}: {}", .path.display(), flexbody_io::text::shortened(.message))]
    Format { path: PathBuf, message: String },
    #[error("refusing to write a non-finite value in {0}")]
    NonFinite(&'static str),
    /// A matrix entry that is not finite, or beyond the
    /// [`LARGEST`](flexbody_linalg::dense_check::LARGEST) magnitude no
    /// reader takes back: the matrix and the entry.
    #[error("refusing to write {0}")]
    NonFiniteIn(String),
    /// A format's content that the [`BodyOutput`] does not hold.
    #[error("nothing to write: {0} was not computed")]
    Missing(&'static str),
    /// The model and the body do not fit together, or the body cannot be
    /// expressed in the requested format.
    #[error("{0}")]
    Model(String),
}

/// The text of the body file at `path`, read with a bound on its line
/// length ([`flexbody_io::text::read_text`]).
pub(crate) fn read_text(path: &Path) -> Result<String, ExportError> {
    flexbody_io::text::read_text(path).map_err(from_input_error)
}

/// The text of a JSON body file: read whole, as another program may write
/// JSON on one line, but only from a regular file
/// ([`flexbody_io::text::regular_file`]).
pub(crate) fn read_json_text(path: &Path) -> Result<String, ExportError> {
    flexbody_io::text::regular_file(path).map_err(from_input_error)?;
    std::fs::read_to_string(path).map_err(|source| ExportError::Read {
        path: path.to_path_buf(),
        cause: source,
    })
}

/// A reader's error as the body readers give it.
fn from_input_error(e: flexbody_io::InputError) -> ExportError {
    match e {
        flexbody_io::InputError::Read { path, cause } => ExportError::Read { path, cause },
        flexbody_io::InputError::Invalid {
            path,
            line,
            message,
        } => ExportError::Format {
            path,
            message: match line {
                Some(line) => format!("line {line}: {message}"),
                None => message,
            },
        },
    }
}

/// The temporary file beside `path` that [`write_atomically`] writes and
/// renames.
fn temporary(path: &Path) -> Result<PathBuf, ExportError> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().ok_or_else(|| ExportError::Write {
        path: path.to_path_buf(),
        cause: std::io::Error::other("not a file path"),
    })?;
    Ok(dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    )))
}

/// Checks, before a long computation, that [`write_atomically`] will be
/// able to write `path`: no folder is in its place, and its folder exists
/// and takes a new file (created and removed again).
pub fn check_writable(path: &Path) -> Result<(), ExportError> {
    let err = |cause| ExportError::Write {
        path: path.to_path_buf(),
        cause,
    };
    if path.is_dir() {
        return Err(err(std::io::Error::other("it is a folder")));
    }
    check_replaceable(path)?;
    let tmp = temporary(path)?;
    std::fs::File::create(&tmp).map_err(err)?;
    let _ = std::fs::remove_file(&tmp);
    Ok(())
}

/// Checks, before a long computation, that a folder of files can be
/// written at `dir`: an existing folder takes `first` (the first file to be
/// written, which an error names), or a new folder can be made beside its
/// siblings.
pub fn check_folder_writable(dir: &Path, first: &str) -> Result<(), ExportError> {
    if dir.is_dir() {
        return check_writable(&dir.join(first));
    }
    if dir.exists() {
        return Err(ExportError::Write {
            path: dir.to_path_buf(),
            cause: std::io::Error::other("a file is in the folder's place"),
        });
    }
    check_writable(dir)
}

/// Refuses to replace what is not a regular file: a device, a FIFO, a
/// socket or a symbolic link at `path` (writing through them would not
/// give a file, or would write elsewhere). A missing path is fine.
fn check_replaceable(path: &Path) -> Result<(), ExportError> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if !meta.file_type().is_file() && !meta.is_dir() => Err(ExportError::Write {
            path: path.to_path_buf(),
            cause: std::io::Error::other(
                "it is not a regular file (a symbolic link, device, FIFO or socket); \
                 flexbody only writes regular files (--follow-symlinks writes through a link)",
            ),
        }),
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` through a temporary file and a rename.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), ExportError> {
    let mut set = FileSet::default();
    set.stage(path, write)?;
    set.commit()
}

/// Files written whole or not at all, as one: each goes to a temporary
/// file beside its target; only when all are written are they renamed into
/// place, in the order staged (an index last). A failed write, or a set
/// dropped before [`FileSet::commit`], removes the temporary files and
/// leaves the targets as they were.
#[derive(Default)]
pub struct FileSet {
    /// (temporary file, target), in the order staged.
    staged: Vec<(PathBuf, PathBuf)>,
}

impl FileSet {
    /// Writes the content of `path` to its temporary file.
    pub fn stage(
        &mut self,
        path: &Path,
        write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<(), ExportError> {
        check_replaceable(path)?;
        if path.is_dir() {
            return Err(ExportError::Write {
                path: path.to_path_buf(),
                cause: std::io::Error::other("it is a folder"),
            });
        }
        let tmp = temporary(path)?;
        let result = (|| {
            let file = std::fs::File::create(&tmp)?;
            let mut out = std::io::BufWriter::new(file);
            write(&mut out)?;
            out.flush()?;
            out.get_ref().sync_all()
        })();
        self.staged.push((tmp, path.to_path_buf()));
        result.map_err(|cause| ExportError::Write {
            path: path.to_path_buf(),
            cause,
        })
    }

    /// Renames every staged file into place.
    pub fn commit(mut self) -> Result<(), ExportError> {
        let staged = std::mem::take(&mut self.staged);
        for (i, (tmp, path)) in staged.iter().enumerate() {
            if let Err(cause) = std::fs::rename(tmp, path) {
                for (tmp, _) in &staged[i..] {
                    let _ = std::fs::remove_file(tmp);
                }
                return Err(ExportError::Write {
                    path: path.clone(),
                    cause,
                });
            }
        }
        Ok(())
    }
}

impl Drop for FileSet {
    fn drop(&mut self) {
        for (tmp, _) in &self.staged {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// A node of the body's mesh in a body file (the JSON document's and the
/// Matrix Market index's `nodes`): its id, its coordinates (m) where known,
/// and, where the body was reduced from a mesh, its HRZ lumped masses
/// `ux uy uz` (kg) and `rx ry rz` (kg m^2) ([`flexbody_fem::lumped`]). With
/// a mesh every node is listed, fixed ones too, so that each direction's
/// masses sum to the whole body's mass.
/// An interface node whose interface DOFs are along local axes (a
/// `*TRANSFORM`), as a body file lists it: the node and the axes, one
/// column per local axis in global components ([`ReducedBody::local_axes`]).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LocalAxesEntry {
    pub node: u64,
    pub axes: [[f64; 3]; 3],
}

/// The entries of a body's local axes, by node.
pub fn local_axes_entries(body: &ReducedBody) -> Vec<LocalAxesEntry> {
    body.local_axes
        .iter()
        .map(|(node, axes)| LocalAxesEntry {
            node: *node,
            axes: *axes,
        })
        .collect()
}

/// The local axes of a body file's entries; a node listed twice is refused.
pub(crate) fn local_axes_of(
    entries: Vec<LocalAxesEntry>,
) -> Result<std::collections::BTreeMap<u64, flexbody_fem::Axes>, String> {
    let mut out = std::collections::BTreeMap::new();
    for e in entries {
        if out.insert(e.node, e.axes).is_some() {
            return Err(format!("node {} is listed twice", e.node));
        }
    }
    Ok(out)
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BodyNode {
    pub id: NodeId,
    /// Coordinates (m), if known.
    pub coords: Option<[f64; 3]>,
    /// Lumped masses, if the body was reduced from a mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<[f64; 6]>,
}

/// The first problem of `nodes` read from a body file: an id listed twice,
/// a coordinate that is not finite or beyond
/// [`LARGEST`](flexbody_linalg::dense_check::LARGEST), a lumped mass that
/// is not finite, negative or beyond it.
pub(crate) fn check_nodes(nodes: &[BodyNode]) -> Result<(), String> {
    use flexbody_linalg::dense_check::LARGEST;
    let mut ids: Vec<NodeId> = nodes.iter().map(|n| n.id).collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!("node {} is listed twice", w[0]));
    }
    for n in nodes {
        if let Some(x) = n
            .coords
            .iter()
            .flatten()
            .find(|x| !(-LARGEST..=LARGEST).contains(*x))
        {
            return Err(format!(
                "node {}: coordinate {x:e} is not a finite number of at most {LARGEST:e}",
                n.id
            ));
        }
        if let Some(m) = n
            .mass
            .iter()
            .flatten()
            .find(|m| !(0.0..=LARGEST).contains(*m))
        {
            return Err(format!(
                "node {}: lumped mass {m:e} is not a number in [0, {LARGEST:e}]",
                n.id
            ));
        }
    }
    Ok(())
}

/// The JSON document of a reduced body. Matrices are row-major arrays of
/// rows. Units: SI (basis rows in m or rad per unit q; mass in kg-consistent
/// units of q; stiffness in N/m-consistent units of q).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BodyFile {
    pub format: String,
    pub units: String,
    pub method: Method,
    pub r: usize,
    pub dofs: Vec<Dof>,
    pub interface: Vec<Dof>,
    /// The interface nodes whose DOFs in `interface` are along local axes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub local_axes: Vec<LocalAxesEntry>,
    pub modes: Vec<ModeKind>,
    /// Natural frequencies of the free reduced body (Hz).
    pub frequencies_hz: Vec<f64>,
    pub mass: Vec<Vec<f64>>,
    pub stiffness: Vec<Vec<f64>>,
    pub damping: Option<Vec<Vec<f64>>>,
    /// The nodes of the mesh with their coordinates and lumped masses
    /// (none in files written without them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub nodes: Vec<BodyNode>,
    /// The Ritz basis T, one row per DOF of `dofs`.
    #[serde(serialize_with = "json_layout::rows_in_parallel")]
    pub basis: Vec<Vec<f64>>,
}

/// Format tag written into every file.
pub const FORMAT: &str = "flexbody-reduced-body/1";

/// Refuses to write `m` (named `what`) if an entry is not finite or
/// beyond [`LARGEST`](flexbody_linalg::dense_check::LARGEST) in magnitude
/// (the readers would refuse the file), naming the first such entry.
pub(crate) fn writable(m: faer::MatRef<'_, f64>, what: &str) -> Result<(), ExportError> {
    use flexbody_linalg::dense_check::{out_of_range, LARGEST};
    out_of_range(m, LARGEST).map_err(|e| ExportError::NonFiniteIn(format!("{what}: {e}")))
}

fn rows(m: &Mat<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

impl BodyFile {
    /// The document of `body` and its mesh's `nodes`; fails on NaN or
    /// infinite entries.
    pub fn new(body: &ReducedBody, nodes: &[BodyNode]) -> Result<Self, ExportError> {
        writable(body.basis.as_ref(), "the basis")?;
        writable(body.mass.as_ref(), "the mass matrix")?;
        writable(body.stiffness.as_ref(), "the stiffness matrix")?;
        if let Some(d) = &body.damping {
            writable(d.as_ref(), "the damping matrix")?;
        }
        let frequencies_hz = body.frequencies_hz().map_err(|_| {
            ExportError::NonFinite("the frequencies (reduced mass matrix not positive definite)")
        })?;
        Ok(Self {
            format: FORMAT.into(),
            units: "SI: m, kg, s, N, rad; frequencies in Hz".into(),
            method: body.method,
            r: body.r(),
            dofs: body.dof_map.dofs().to_vec(),
            interface: body.interface.clone(),
            local_axes: local_axes_entries(body),
            modes: body.modes.clone(),
            frequencies_hz,
            mass: rows(&body.mass),
            stiffness: rows(&body.stiffness),
            damping: body.damping.as_ref().map(rows),
            nodes: nodes.to_vec(),
            basis: rows(&body.basis),
        })
    }

    /// Back to a [`ReducedBody`], checking every count; errors name the
    /// block (the JSON key) that is wrong.
    pub fn into_body(self, path: &Path) -> Result<ReducedBody, ExportError> {
        self.checked()
            .map(|(body, _)| body)
            .map_err(|(block, message)| ExportError::Format {
                path: path.to_path_buf(),
                message: format!("block '{block}': {message}"),
            })
    }

    /// The body and its nodes, or the block and message of the first
    /// inconsistency.
    fn checked(self) -> Result<(ReducedBody, Vec<BodyNode>), (&'static str, String)> {
        if self.format != FORMAT {
            return Err((
                "format",
                format!("format '{}' is not {FORMAT}", self.format),
            ));
        }
        let r = self.r;
        let square =
            |m: &Vec<Vec<f64>>, what: &'static str| -> Result<Mat<f64>, (&'static str, String)> {
                if m.len() != r {
                    return Err((what, format!("{what} has {} rows, r = {r}", m.len())));
                }
                if let Some((i, row)) = m.iter().enumerate().find(|(_, row)| row.len() != r) {
                    return Err((
                        what,
                        format!("{what} row {i} has {} entries, r = {r}", row.len()),
                    ));
                }
                Ok(Mat::from_fn(r, r, |i, j| m[i][j]))
            };
        let mass = square(&self.mass, "mass")?;
        let stiffness = square(&self.stiffness, "stiffness")?;
        let damping = self
            .damping
            .as_ref()
            .map(|d| square(d, "damping"))
            .transpose()?;
        if self.basis.len() != self.dofs.len() {
            return Err((
                "basis",
                format!(
                    "basis has {} rows for {} DOFs",
                    self.basis.len(),
                    self.dofs.len()
                ),
            ));
        }
        if let Some((i, row)) = self
            .basis
            .iter()
            .enumerate()
            .find(|(_, row)| row.len() != r)
        {
            return Err((
                "basis",
                format!(
                    "basis row {i} ({}) has {} entries, r = {r}",
                    self.dofs[i],
                    row.len()
                ),
            ));
        }
        if self.modes.len() != r {
            return Err((
                "modes",
                format!("{} mode descriptions for r = {r}", self.modes.len()),
            ));
        }
        let basis = Mat::from_fn(self.dofs.len(), r, |i, j| self.basis[i][j]);
        let dof_map = DofMap::new(self.dofs);
        if let Some(d) = self
            .interface
            .iter()
            .find(|d| dof_map.index_of(**d).is_none())
        {
            return Err((
                "interface",
                format!("interface DOF {d} is not among the body's DOFs"),
            ));
        }
        let body = ReducedBody {
            method: self.method,
            dof_map,
            basis,
            mass,
            stiffness,
            damping,
            modes: self.modes,
            interface: self.interface,
            local_axes: local_axes_of(self.local_axes).map_err(|m| ("local_axes", m))?,
        };
        body.check().map_err(|d| (d.block, d.message))?;
        check_nodes(&self.nodes).map_err(|message| ("nodes", message))?;
        Ok((body, self.nodes))
    }
}

/// Line (1-based) of the top-level key `key` in a pretty-printed JSON text.
pub(crate) fn json_key_line(text: &str, key: &str) -> Option<usize> {
    let pattern = format!("\"{key}\":");
    text.lines()
        .position(|l| l.starts_with("  \"") && l.trim_start().starts_with(&pattern))
        .map(|i| i + 1)
}

/// The top-level key of a pretty-printed JSON text that `line` is in.
pub(crate) fn json_block_at(text: &str, line: usize) -> String {
    text.lines()
        .take(line)
        .filter(|l| l.starts_with("  \"") && !l.starts_with("   "))
        .filter_map(|l| l.trim_start().strip_prefix('"')?.split('"').next())
        .last()
        .map_or("document".into(), |key| {
            flexbody_io::text::excerpt(key).into_owned()
        })
}

/// Writes `body` and its mesh's `nodes` (none if unknown) as JSON to
/// `path` (atomically).
pub fn write_json(body: &ReducedBody, nodes: &[BodyNode], path: &Path) -> Result<(), ExportError> {
    let doc = BodyFile::new(body, nodes)?;
    write_atomically(path, |out| {
        json_layout::to_writer(&mut *out, &doc).map_err(std::io::Error::other)?;
        out.write_all(b"\n")
    })
}

/// Reads a JSON reduced body written by [`write_json`].
pub fn read_json(path: &Path) -> Result<ReducedBody, ExportError> {
    read_json_with_nodes(path).map(|(body, _)| body)
}

/// Reads a JSON reduced body and its mesh's nodes (empty if the file has
/// none).
pub fn read_json_with_nodes(path: &Path) -> Result<(ReducedBody, Vec<BodyNode>), ExportError> {
    json_from_text(path, &read_json_text(path)?)
}

/// The JSON body and its nodes in `text`, read from `path` (which errors
/// name).
pub(crate) fn json_from_text(
    path: &Path,
    text: &str,
) -> Result<(ReducedBody, Vec<BodyNode>), ExportError> {
    let doc: BodyFile = serde_json::from_str(text).map_err(|e| ExportError::Format {
        path: path.to_path_buf(),
        message: format!(
            "line {}, block '{}': {e}",
            e.line(),
            json_block_at(text, e.line())
        ),
    })?;
    doc.checked()
        .map_err(|(block, message)| ExportError::Format {
            path: path.to_path_buf(),
            message: match json_key_line(text, block) {
                Some(line) => format!("line {line}, block '{block}': {message}"),
                None => format!("block '{block}': {message}"),
            },
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexbody_fem::DofKind;

    /// The names in `dir`, sorted.
    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    /// A free body of three DOFs and two coordinates: unit masses, one
    /// rigid-body mode and one of 1 rad/s.
    fn small_body() -> ReducedBody {
        ReducedBody {
            method: Method::Free,
            dof_map: DofMap::new(vec![
                Dof::new(1, DofKind::Uz),
                Dof::new(2, DofKind::Uz),
                Dof::new(3, DofKind::Uz),
            ]),
            basis: Mat::from_fn(3, 2, |i, j| if j == 0 { 1.0 } else { i as f64 - 1.0 }),
            mass: Mat::from_fn(2, 2, |i, j| f64::from(i == j)),
            stiffness: Mat::from_fn(2, 2, |i, j| f64::from(i == 1 && j == 1)),
            damping: None,
            modes: vec![
                ModeKind::Rigid {
                    motion: "uz".into(),
                },
                ModeKind::Eigen {
                    frequency_hz: 1.0 / (2.0 * std::f64::consts::PI),
                },
            ],
            interface: vec![],
            local_axes: Default::default(),
        }
    }

    #[test]
    fn a_writer_that_fails_after_writing_removes_its_temporary_and_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("body.json");
        std::fs::write(&path, "the previous body\n").unwrap();
        let tmp = temporary(&path).unwrap();
        // More than the writer's buffer: the bytes reach the temporary file
        // before the failure.
        let e = write_atomically(&path, |out| {
            out.write_all(&[b'x'; 1 << 16])?;
            assert!(tmp.is_file(), "the temporary exists while writing");
            assert!(std::fs::metadata(&tmp).unwrap().len() > 0);
            Err(std::io::Error::other("the disk is full"))
        })
        .unwrap_err();
        match &e {
            ExportError::Write { path: p, cause } => {
                assert_eq!(p, &path);
                assert_eq!(cause.to_string(), "the disk is full");
            }
            other => panic!("expected a Write error, got {other}"),
        }
        assert!(e.to_string().contains("body.json: cannot write"), "{e}");
        assert!(!tmp.exists());
        assert_eq!(names(dir.path()), ["body.json"]);
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "the previous body\n"
        );
    }

    #[test]
    fn a_rename_onto_a_folder_fails_and_removes_the_complete_temporary() {
        // The whole document is written and synced; only the rename onto
        // a folder that holds a file fails.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("body.json");
        std::fs::create_dir(&path).unwrap();
        std::fs::write(path.join("keep.txt"), "kept").unwrap();
        let e = write_json(&small_body(), &[], &path).unwrap_err();
        match &e {
            ExportError::Write { path: p, .. } => assert_eq!(p, &path),
            other => panic!("expected a Write error, got {other}"),
        }
        assert_eq!(names(dir.path()), ["body.json"]);
        assert!(path.is_dir());
        assert_eq!(names(&path), ["keep.txt"]);
        assert_eq!(
            std::fs::read_to_string(path.join("keep.txt")).unwrap(),
            "kept"
        );
    }

    #[test]
    fn a_matrix_market_folder_that_fails_midway_has_no_index() {
        // `index.json` comes last: a folder whose stiffness cannot be
        // written has no index, and no temporary of any file.
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("body");
        std::fs::create_dir_all(folder.join("stiffness.mtx")).unwrap();
        std::fs::write(folder.join("stiffness.mtx/keep.txt"), "kept").unwrap();
        let e = mtx::write_mtx(&small_body(), &[], &Default::default(), &folder).unwrap_err();
        match &e {
            ExportError::Write { path, .. } => assert_eq!(path, &folder.join("stiffness.mtx")),
            other => panic!("expected a Write error, got {other}"),
        }
        let left = names(&folder);
        assert!(!left.contains(&"index.json".to_string()), "{left:?}");
        assert!(left.iter().all(|n| !n.ends_with(".tmp")), "{left:?}");
        // Written without the obstacle, the folder is complete and reads back.
        std::fs::remove_dir_all(folder.join("stiffness.mtx")).unwrap();
        mtx::write_mtx(&small_body(), &[], &Default::default(), &folder).unwrap();
        assert_eq!(
            names(&folder),
            ["basis.mtx", "index.json", "mass.mtx", "stiffness.mtx"]
        );
        let back = mtx::read_mtx(&folder).unwrap();
        assert_eq!(back.basis, small_body().basis);
    }

    #[test]
    fn a_body_writer_names_the_entry_it_refuses_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let mut body = small_body();
        body.basis[(2, 1)] = f64::NAN;
        let json = dir.path().join("body.json");
        let e = write_json(&body, &[], &json).unwrap_err().to_string();
        assert_eq!(e, "refusing to write the basis: entry (3, 2) is NaN");
        assert!(!json.exists());
        // Beyond 1e100 no reader would take it back.
        let mut body = small_body();
        body.damping = Some(Mat::from_fn(2, 2, |i, j| if i == j { 1e200 } else { 0.0 }));
        let folder = dir.path().join("body");
        let e = mtx::write_mtx(&body, &[], &Default::default(), &folder)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("the damping matrix: entry (1, 1) is 1e200, beyond 1e100"),
            "{e}"
        );
        assert!(!folder.exists());
    }
}
