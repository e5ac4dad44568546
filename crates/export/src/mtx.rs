//! A reduced body as a folder of Matrix Market files plus a JSON index, for
//! bodies too large for one JSON document:
//!
//! | file | content |
//! | --- | --- |
//! | `mass.mtx` | `M_red = T^T M T` (r x r) |
//! | `stiffness.mtx` | `K_red = T^T K T` (r x r, free body) |
//! | `damping.mtx` | `D_red = T^T D T` (r x r), only if the body has damping |
//! | `basis.mtx` | the Ritz basis `T` (m x r), rows in the order of `dofs` |
//! | `index.json` | format tag, units, method, r, modes, frequencies, DOF map, interface, node ids and coordinates, accuracy figures, file names |
//!
//! Matrices are written dense (`%%MatrixMarket matrix array real general`,
//! column by column) with round-trip precision; the reader also takes
//! `coordinate` files (`general` or `symmetric`). The files are written
//! as one [`FileSet`]: all to temporary files first, then renamed into
//! place, `index.json` last; a write that fails (a full disk) leaves the
//! folder's previous body whole, never a mix of two.

use crate::float_text::push_exp;
use crate::{BodyNode, ExportError, FileSet};
use faer::Mat;
use flexbody_fem::{Dof, DofMap, NodeId};
use flexbody_io::text::{excerpt, finite_number};
use flexbody_linalg::memory::Budget;
use flexbody_reduce::{Method, ModeKind, ReducedBody};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Format tag of `index.json`.
pub const INDEX_FORMAT: &str = "flexbody-reduced-body-mtx/1";

/// Optional figures a caller adds to the index.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Metadata {
    /// Accuracy figures by name (e.g. `"err_w at 122 rad/s"`), relative.
    #[serde(default)]
    pub accuracy: BTreeMap<String, f64>,
    /// Natural frequencies of the full model (Hz), if computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub full_frequencies_hz: Option<Vec<f64>>,
}

/// `index.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Index {
    pub format: String,
    pub units: String,
    pub method: Method,
    pub r: usize,
    /// Number of rows of the basis (DOFs of the full model).
    pub m: usize,
    pub modes: Vec<ModeKind>,
    /// Natural frequencies of the free reduced body (Hz).
    pub frequencies_hz: Vec<f64>,
    pub dofs: Vec<Dof>,
    pub interface: Vec<Dof>,
    /// The interface nodes whose DOFs in `interface` are along local axes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub local_axes: Vec<crate::LocalAxesEntry>,
    /// The nodes of the mesh (coordinates, lumped masses), or those of
    /// `dofs` without them.
    pub nodes: Vec<BodyNode>,
    #[serde(default)]
    pub metadata: Metadata,
    /// File names in the folder.
    pub files: BTreeMap<String, String>,
}

/// The Matrix Market text of `m`, its columns formatted in parallel.
fn matrix_text(m: &Mat<f64>, what: &str) -> String {
    use rayon::prelude::*;
    let columns: Vec<String> = (0..m.ncols())
        .into_par_iter()
        .map(|j| {
            let mut s = String::with_capacity(24 * m.nrows());
            for i in 0..m.nrows() {
                push_exp(&mut s, m[(i, j)]);
                s.push('\n');
            }
            s
        })
        .collect();
    let mut s = String::with_capacity(columns.iter().map(String::len).sum::<usize>() + 100);
    s.push_str("%%MatrixMarket matrix array real general\n");
    s.push_str(&format!("% flexbody reduced body: {what}\n"));
    s.push_str(&format!("{} {}\n", m.nrows(), m.ncols()));
    for column in &columns {
        s.push_str(column);
    }
    s
}

/// Writes `body` to the folder `dir` (created if missing). `nodes` (the
/// mesh's, with coordinates and lumped masses) go to the index; without
/// them the index lists the nodes of the body's DOFs alone. `metadata` adds
/// accuracy figures.
pub fn write_mtx(
    body: &ReducedBody,
    nodes: &[BodyNode],
    metadata: &Metadata,
    dir: &Path,
) -> Result<(), ExportError> {
    for (m, what) in [
        (&body.basis, "the basis"),
        (&body.mass, "the mass matrix"),
        (&body.stiffness, "the stiffness matrix"),
    ] {
        crate::writable(m.as_ref(), what)?;
    }
    if let Some(d) = &body.damping {
        crate::writable(d.as_ref(), "the damping matrix")?;
    }
    let frequencies_hz = body.frequencies_hz().map_err(|_| {
        ExportError::NonFinite("the frequencies (reduced mass matrix not positive definite)")
    })?;
    std::fs::create_dir_all(dir).map_err(|source| ExportError::Write {
        path: dir.to_path_buf(),
        cause: source,
    })?;
    let mut files = BTreeMap::new();
    let mut matrices = vec![
        ("mass", &body.mass),
        ("stiffness", &body.stiffness),
        ("basis", &body.basis),
    ];
    if let Some(d) = &body.damping {
        matrices.push(("damping", d));
    }
    // Every file staged before any is renamed: a failed write leaves the
    // folder's old body whole.
    let mut set = FileSet::default();
    for (name, m) in matrices {
        let file = format!("{name}.mtx");
        let text = matrix_text(m, name);
        set.stage(&dir.join(&file), |out| out.write_all(text.as_bytes()))?;
        files.insert(name.to_string(), file);
    }
    let nodes = if nodes.is_empty() {
        let ids: BTreeSet<NodeId> = body.dof_map.dofs().iter().map(|d| d.node).collect();
        ids.into_iter()
            .map(|id| BodyNode {
                id,
                coords: None,
                mass: None,
            })
            .collect()
    } else {
        nodes.to_vec()
    };
    let index = Index {
        format: INDEX_FORMAT.into(),
        units: "SI: m, kg, s, N, rad; frequencies in Hz".into(),
        method: body.method,
        r: body.r(),
        m: body.basis.nrows(),
        modes: body.modes.clone(),
        frequencies_hz,
        dofs: body.dof_map.dofs().to_vec(),
        interface: body.interface.clone(),
        local_axes: crate::local_axes_entries(body),
        nodes,
        metadata: metadata.clone(),
        files,
    };
    set.stage(&dir.join("index.json"), |out| {
        serde_json::to_writer_pretty(&mut *out, &index).map_err(std::io::Error::other)?;
        out.write_all(b"\n")
    })?;
    set.commit()
}

/// Reads a Matrix Market matrix (array or coordinate; real; general or
/// symmetric), naming the file and line of what is wrong.
///
/// Sizes are checked before storage is taken: the entries a size line
/// announces must fit in the file (a value line takes at least 2 bytes,
/// an entry line 6), and the dense matrix (8 bytes per entry) in the
/// memory left ([`Budget::MACHINE`]).
pub fn read_matrix(path: &Path) -> Result<Mat<f64>, ExportError> {
    read_matrix_of(path, None)
}

/// [`read_matrix`] of a matrix that must be `shape` (rows, columns): a
/// size line that says otherwise is an error before storage is taken.
fn read_matrix_of(path: &Path, shape: Option<(usize, usize)>) -> Result<Mat<f64>, ExportError> {
    let text = crate::read_text(path)?;
    parse_matrix(&text, shape).map_err(|(line, message)| ExportError::Format {
        path: path.to_path_buf(),
        message: format!("line {line}: {message}"),
    })
}

/// The shortest value line of an array file (`0` and a newline) and entry
/// line of a coordinate file (`1 1 0` and a newline).
const MIN_VALUE_BYTES: usize = 2;
const MIN_ENTRY_BYTES: usize = 6;

fn parse_matrix(text: &str, shape: Option<(usize, usize)>) -> Result<Mat<f64>, (usize, String)> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let (_, header) = lines.next().ok_or((1, "empty file".to_string()))?;
    let h: Vec<String> = header
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .collect();
    if h.len() < 5 || h[0] != "%%matrixmarket" || h[1] != "matrix" || h[3] != "real" {
        return Err((
            1,
            format!(
                "'{header}' is not a real Matrix Market matrix header",
                header = excerpt(header)
            ),
        ));
    }
    let array = match h[2].as_str() {
        "array" => true,
        "coordinate" => false,
        other => {
            return Err((
                1,
                format!(
                    "storage '{other}' (array or coordinate)",
                    other = excerpt(other)
                ),
            ))
        }
    };
    let symmetric = match h[4].as_str() {
        "general" => false,
        "symmetric" => true,
        other => {
            return Err((
                1,
                format!(
                    "symmetry '{other}' (general or symmetric)",
                    other = excerpt(other)
                ),
            ))
        }
    };
    let mut body = lines.filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    let (size_line, size) = body
        .next()
        .ok_or((1, "the size line is missing".to_string()))?;
    let dims: Vec<usize> = size
        .split_whitespace()
        .map(|t| {
            t.parse()
                .map_err(|_| (size_line, format!("'{t}' is not a count", t = excerpt(t))))
        })
        .collect::<Result<_, _>>()?;
    let (nrows, ncols) = match dims.as_slice() {
        [r, c] if array => (*r, *c),
        [r, c, _] if !array => (*r, *c),
        _ => {
            return Err((
                size_line,
                format!(
                    "size line '{size}' has the wrong number of counts",
                    size = excerpt(size)
                ),
            ))
        }
    };
    if let Some((rows, cols)) = shape.filter(|s| *s != (nrows, ncols)) {
        return Err((
            size_line,
            format!("the matrix is {nrows} x {ncols}, the index says {rows} x {cols}"),
        ));
    }
    let values = nrows.checked_mul(ncols);
    let announced = if array {
        if symmetric {
            nrows.checked_mul(nrows.saturating_add(1)).map(|n| n / 2)
        } else {
            values
        }
    } else {
        Some(dims[2])
    };
    let min_bytes = if array {
        MIN_VALUE_BYTES
    } else {
        MIN_ENTRY_BYTES
    };
    let room = text.len() / min_bytes + 1;
    match announced {
        Some(n) if n <= room => {}
        _ => {
            return Err((
                size_line,
                format!(
                    "the size line announces {} entries, but the file of {} bytes holds at \
                     most {room} (a line takes at least {min_bytes} bytes)",
                    announced.map_or_else(|| "more than 2^64".into(), |n| n.to_string()),
                    text.len()
                ),
            ))
        }
    }
    let bytes = values.and_then(|v| v.checked_mul(std::mem::size_of::<f64>()));
    let what = format!("a {nrows} x {ncols} dense matrix");
    match bytes {
        Some(b) => Budget::MACHINE
            .ensure(b as u64, &what)
            .map_err(|e| (size_line, e.to_string()))?,
        None => {
            return Err((
                size_line,
                format!("{what} has more entries than memory can hold"),
            ))
        }
    }
    let mut m = Mat::zeros(nrows, ncols);
    let mut last = size_line;
    if array {
        let want = announced.unwrap_or_default();
        let mut count = 0;
        for (n, l) in body {
            last = n;
            let v = finite_number(l).map_err(|message| (n, message))?;
            if count >= want {
                return Err((
                    n,
                    format!("more than the {want} entries of {nrows} x {ncols}"),
                ));
            }
            // Column-major; symmetric arrays list the lower triangle.
            let (i, j) = if symmetric {
                let mut j = 0;
                let mut left = count;
                while left >= nrows - j {
                    left -= nrows - j;
                    j += 1;
                }
                (j + left, j)
            } else {
                (count % nrows, count / nrows)
            };
            m[(i, j)] = v;
            if symmetric {
                m[(j, i)] = v;
            }
            count += 1;
        }
        if count != want {
            return Err((
                last,
                format!("{count} entries, expected {want} for {nrows} x {ncols} (file truncated?)"),
            ));
        }
    } else {
        let want = dims[2];
        let mut count = 0;
        for (n, l) in body {
            last = n;
            let t: Vec<&str> = l.split_whitespace().collect();
            let [i, j, v] = t.as_slice() else {
                return Err((n, format!("'{l}' is not 'row col value'", l = excerpt(l))));
            };
            let (i, j): (usize, usize) = match (i.parse(), j.parse()) {
                (Ok(i), Ok(j)) if i >= 1 && j >= 1 && i <= nrows && j <= ncols => (i, j),
                _ => return Err((n, format!("entry ({i}, {j}) is outside {nrows} x {ncols}"))),
            };
            let v = finite_number(v).map_err(|message| (n, message))?;
            m[(i - 1, j - 1)] += v;
            if !m[(i - 1, j - 1)].is_finite() {
                return Err((n, format!("entry ({i}, {j}) is not finite: its values add up beyond the range of a float")));
            }
            if symmetric && i != j {
                m[(j - 1, i - 1)] += v;
            }
            count += 1;
        }
        if count != want {
            return Err((
                last,
                format!("{count} entries, the size line says {want} (file truncated?)"),
            ));
        }
    }
    Ok(m)
}

/// Reads a body written by [`write_mtx`] from its folder (or the path of its
/// `index.json`).
pub fn read_mtx(dir: &Path) -> Result<ReducedBody, ExportError> {
    read_mtx_with_nodes(dir).map(|(body, _)| body)
}

/// [`read_mtx`], with the index's nodes.
pub fn read_mtx_with_nodes(dir: &Path) -> Result<(ReducedBody, Vec<BodyNode>), ExportError> {
    let (dir, index_path): (PathBuf, PathBuf) = if dir.is_dir() {
        (dir.to_path_buf(), dir.join("index.json"))
    } else {
        (
            dir.parent().unwrap_or(Path::new(".")).to_path_buf(),
            dir.to_path_buf(),
        )
    };
    let text = crate::read_text(&index_path)?;
    let bad = |message: String| ExportError::Format {
        path: index_path.clone(),
        message,
    };
    let index: Index = serde_json::from_str(&text).map_err(|e| {
        bad(format!(
            "line {}, block '{}': {e}",
            e.line(),
            crate::json_block_at(&text, e.line())
        ))
    })?;
    if index.format != INDEX_FORMAT {
        return Err(bad(format!(
            "format '{}' is not {INDEX_FORMAT}",
            index.format
        )));
    }
    let r = index.r;
    let load = |name: &str, rows: usize| -> Result<Option<Mat<f64>>, ExportError> {
        let Some(file) = index.files.get(name) else {
            return Ok(None);
        };
        let path = dir.join(file);
        read_matrix_of(&path, Some((rows, r))).map(Some)
    };
    let need = |name: &str, rows: usize| {
        load(name, rows)?.ok_or_else(|| bad(format!("block 'files': no '{name}' file")))
    };
    if index.dofs.len() != index.m {
        return Err(bad(format!(
            "block 'dofs': {} DOFs, m = {}",
            index.dofs.len(),
            index.m
        )));
    }
    if index.modes.len() != r {
        return Err(bad(format!(
            "block 'modes': {} mode descriptions for r = {r}",
            index.modes.len()
        )));
    }
    let mass = need("mass", r)?;
    let stiffness = need("stiffness", r)?;
    let basis = need("basis", index.m)?;
    let damping = load("damping", r)?;
    let dof_map = DofMap::new(index.dofs);
    if let Some(d) = index
        .interface
        .iter()
        .find(|d| dof_map.index_of(**d).is_none())
    {
        return Err(bad(format!(
            "block 'interface': DOF {d} is not among the body's DOFs"
        )));
    }
    let body = ReducedBody {
        method: index.method,
        dof_map,
        basis,
        mass,
        stiffness,
        damping,
        modes: index.modes,
        interface: index.interface,
        local_axes: crate::local_axes_of(index.local_axes)
            .map_err(|m| bad(format!("block 'local_axes': {m}")))?,
    };
    body.check().map_err(|d| {
        // The matrix's own file, or the index for the mode descriptions.
        match index.files.get(d.block) {
            Some(file) => ExportError::Format {
                path: dir.join(file),
                message: format!("{}: {}", d.block, d.message),
            },
            None => bad(format!("block '{}': {}", d.block, d.message)),
        }
    })?;
    crate::check_nodes(&index.nodes).map_err(|message| bad(format!("block 'nodes': {message}")))?;
    Ok((body, index.nodes))
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_matrix_entry_that_is_not_finite_is_refused_at_its_line() {
        let array = "%%MatrixMarket matrix array real general\n1 2\n1.0\n";
        for bad in ["1e510", "inf", "-inf", "nan"] {
            let (line, message) =
                super::parse_matrix(&format!("{array}{bad}\n"), None).unwrap_err();
            assert_eq!(line, 4, "{bad}: {message}");
            assert!(message.contains("not a finite number"), "{message}");
        }
        let coordinate =
            "%%MatrixMarket matrix coordinate real general\n1 1 2\n1 1 1e100\n1 1 1e308\n";
        let (line, message) = super::parse_matrix(coordinate, None).unwrap_err();
        assert_eq!(line, 4, "{message}");
        assert!(message.contains("1e308 is beyond 1e100"), "{message}");
        let fine = "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 -0\n";
        assert!(super::parse_matrix(fine, None).is_ok());
    }

    use super::*;

    #[test]
    fn array_and_coordinate_files_parse() {
        let a = parse_matrix(
            "%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n4\n",
            None,
        )
        .unwrap();
        assert_eq!((a[(1, 0)], a[(0, 1)]), (2.0, 3.0));
        let s = parse_matrix(
            "%%MatrixMarket matrix array real symmetric\n2 2\n1\n2\n4\n",
            None,
        )
        .unwrap();
        assert_eq!((s[(0, 1)], s[(1, 0)], s[(1, 1)]), (2.0, 2.0, 4.0));
        let c = parse_matrix(
            "%%MatrixMarket matrix coordinate real symmetric\n% c\n2 2 2\n1 1 5\n2 1 7\n",
            None,
        )
        .unwrap();
        assert_eq!((c[(0, 1)], c[(1, 0)], c[(0, 0)]), (7.0, 7.0, 5.0));
    }

    #[test]
    fn sizes_are_checked_before_storage_is_taken() {
        let array = "%%MatrixMarket matrix array real general\n";
        let coordinate = "%%MatrixMarket matrix coordinate real general\n";
        // More values than the file can hold, or than 2^64.
        let e = parse_matrix(&format!("{array}1000 1000\n1\n"), None).unwrap_err();
        assert_eq!(e.0, 2);
        assert!(
            e.1.contains("announces 1000000 entries, but the file of"),
            "{}",
            e.1
        );
        let huge = format!("{array}18446744073709551615 18446744073709551615\n");
        let e = parse_matrix(&huge, None).unwrap_err();
        assert!(e.1.contains("announces more than 2^64 entries"), "{}", e.1);
        let e = parse_matrix(&format!("{coordinate}2 2 1000000\n1 1 1\n"), None).unwrap_err();
        assert!(e.1.contains("announces 1000000 entries"), "{}", e.1);
        // A coordinate file of no entries whose dense matrix (8 TB) no
        // machine holds.
        let e = parse_matrix(&format!("{coordinate}1000000 1000000 0\n"), None).unwrap_err();
        assert!(
            e.1.starts_with("a 1000000 x 1000000 dense matrix needs 7450.58 GiB")
                && e.1.contains("more memory"),
            "{}",
            e.1
        );
        // A shape other than the expected one, before anything else.
        let e = parse_matrix(&format!("{coordinate}1000000 1000000 0\n"), Some((3, 2)));
        assert!(e.unwrap_err().1.contains("the index says 3 x 2"));
        // A long header is quoted as an excerpt.
        let long = format!("%%MatrixMarket {}\n", "x".repeat(10_000));
        let e = parse_matrix(&long, None).unwrap_err();
        assert!(
            e.1.len() < 200 && e.1.contains("... (10015 bytes)"),
            "{}",
            e.1
        );
    }

    #[test]
    fn truncated_files_name_the_line() {
        let e = parse_matrix(
            "%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n",
            None,
        )
        .unwrap_err();
        assert_eq!(e.0, 5);
        assert!(e.1.contains("3 entries, expected 4"), "{}", e.1);
    }
}
