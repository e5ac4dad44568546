//! FE matrices written by other programs: the stiffness K and mass M of a
//! model, with the DOF of each equation, read from CalculiX's
//! `*FREQUENCY, SOLVER=MATRIXSTORAGE` output or from Matrix Market files.
//!
//! Both readers return full symmetric sparse matrices over a [`DofMap`]:
//! equation `i` of K and M is DOF `dof_map.dof(i)`. Entries that are exactly
//! zero in the file are not stored. Units are those of the file (SI for
//! flexbody: N/m, N, N m and kg, kg m, kg m^2).
//!
//! # CalculiX (`read_calculix_matrices`)
//!
//! For a job `dir/job`, CalculiX 2.20 writes three text files:
//!
//! - `job.sti` (K) and `job.mas` (M): one entry per line, `row col value`,
//!   1-based equation numbers. Each off-diagonal entry appears once (CalculiX
//!   writes the upper triangle, column by column) and every diagonal entry
//!   appears, zero or not; values carry 14 significant digits (`%20.13e`).
//! - `job.dof`: one line per equation, `node.direction`, printed as `%d.%d`,
//!   so the part after the dot is an integer: `12.3` is node 12, uz, and
//!   `12.10` would be direction 10, not 1. Directions 1, 2, 3 are ux, uy, uz;
//!   4, 5, 6 are read as rx, ry, rz; 0 (temperature) is refused.
//!
//! The equations are the free DOFs only: DOFs fixed by `*BOUNDARY` are left
//! out by CalculiX.
//!
//! # Matrix Market (`read_matrix_market`)
//!
//! K and M are coordinate files, `%%MatrixMarket matrix coordinate real
//! general` (or `symmetric`, or `integer` values), then `%` comments, the
//! line `rows cols entries` and one `row col value` line per entry, 1-based.
//! A symmetric file gives each off-diagonal entry once, in either triangle; a
//! general one gives both and must be symmetric to 1e-10 of its largest
//! entry (the two are averaged). The DOF list has one line per equation,
//! `node dof`, with `dof` as `ux`..`rz` or `1`..`6`; `#` starts a comment.

use crate::text::excerpt;
use crate::InputError;
use flexbody_fem::{Dof, DofKind, DofMap, NodeId};
use flexbody_linalg::sparse::Triplet;
use flexbody_linalg::{sparse, SparseMat};
use std::collections::HashMap;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// FE matrices read from files, with the DOF of each equation.
#[derive(Clone, Debug)]
pub struct MatrixModel {
    /// DOF of each equation (row and column) of the matrices.
    pub dof_map: DofMap,
    /// Stiffness K, full symmetric.
    pub stiffness: SparseMat,
    /// Mass M, full symmetric.
    pub mass: SparseMat,
}

/// Reads CalculiX `*FREQUENCY, SOLVER=MATRIXSTORAGE` output: `job.sti` (K),
/// `job.mas` (M) and `job.dof` (the DOF of each equation), where `job` is
/// the path without extension, e.g. `dir/job`. Returns full symmetric
/// matrices.
pub fn read_calculix_matrices(job: &Path) -> Result<MatrixModel, InputError> {
    let dof_path = with_suffix(job, "dof");
    let dof_map = parse_calculix_dofs(&dof_path, &read_text(&dof_path)?)?;
    let read = |ext: &str| {
        let path = with_suffix(job, ext);
        let entries = parse_calculix_matrix(&path, &read_text(&path)?, &dof_path, &dof_map)?;
        no_negative_diagonal(&path, &entries, &dof_map)?;
        symmetric_from_triangle(&path, dof_map.len(), &entries)
    };
    Ok(MatrixModel {
        stiffness: read("sti")?,
        mass: read("mas")?,
        dof_map,
    })
}

/// Reads Matrix Market coordinate files (real or integer; symmetric or
/// general) for K and M, and a DOF list with one line `node dof` per
/// equation (`dof` as `ux`..`rz` or `1`..`6`; `#` comments). Returns full
/// symmetric matrices.
pub fn read_matrix_market(
    stiffness: &Path,
    mass: &Path,
    dofs: &Path,
) -> Result<MatrixModel, InputError> {
    let dof_map = parse_dof_list(dofs, &read_text(dofs)?)?;
    let read = |path: &Path| {
        let file = parse_matrix_market(path, &read_text(path)?)?;
        if file.size != dof_map.len() {
            return Err(invalid(
                path,
                Some(file.size_line),
                format!(
                    "the matrix has {} equations, but {} lists {} DOFs",
                    file.size,
                    dofs.display(),
                    dof_map.len()
                ),
            ));
        }
        no_negative_diagonal(path, &file.entries, &dof_map)?;
        match file.symmetry {
            Symmetry::Symmetric => symmetric_from_triangle(path, file.size, &file.entries),
            Symmetry::General => symmetric_from_general(path, file.size, &file.entries),
        }
    };
    Ok(MatrixModel {
        stiffness: read(stiffness)?,
        mass: read(mass)?,
        dof_map,
    })
}

/// One matrix entry as read: 0-based indices and the 1-based line.
#[derive(Copy, Clone, Debug)]
struct Entry {
    row: usize,
    col: usize,
    value: f64,
    line: usize,
}

/// A stiffness or mass matrix is positive semi-definite, so no diagonal
/// entry is negative (`e_i^T A e_i = A_ii`): one that is names its DOF.
fn no_negative_diagonal(path: &Path, entries: &[Entry], dofs: &DofMap) -> Result<(), InputError> {
    match entries.iter().find(|e| e.row == e.col && e.value < 0.0) {
        Some(e) => Err(invalid(
            path,
            Some(e.line),
            format!(
                "diagonal entry {:e} at {} is negative: a stiffness or mass matrix is positive semi-definite",
                e.value,
                dofs.dof(e.row)
            ),
        )),
        None => Ok(()),
    }
}

fn invalid(path: &Path, line: Option<usize>, message: impl Into<String>) -> InputError {
    InputError::Invalid {
        path: path.to_path_buf(),
        line,
        message: message.into(),
    }
}

fn read_text(path: &Path) -> Result<String, InputError> {
    crate::text::read_text(path)
}

/// `job` + `.ext`, keeping any dot already in the job name.
fn with_suffix(job: &Path, ext: &str) -> PathBuf {
    let mut name = OsString::from(job.as_os_str());
    name.push(".");
    name.push(ext);
    PathBuf::from(name)
}

/// Lines with their 1-based numbers, without blank lines.
fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty())
}

/// The DOF map of a CalculiX `.dof` file (`node.direction` per line).
fn parse_calculix_dofs(path: &Path, text: &str) -> Result<DofMap, InputError> {
    let mut dofs = Vec::new();
    let mut seen = HashMap::new();
    for (line, content) in numbered_lines(text) {
        let bad = |what: String| invalid(path, Some(line), what);
        let (node, direction) = content.split_once('.').ok_or_else(|| {
            bad(format!(
                "expected `node.direction` (e.g. `12.3`), found `{}`",
                excerpt(content)
            ))
        })?;
        let node: NodeId = node
            .parse()
            .map_err(|_| bad(format!("node `{}` is not a node number", excerpt(node))))?;
        let direction: u32 = direction.parse().map_err(|_| {
            bad(format!(
                "direction `{}` is not a number",
                excerpt(direction)
            ))
        })?;
        let kind = match direction {
            1..=6 => DofKind::ALL[direction as usize - 1],
            0 => {
                return Err(bad(format!(
                    "node {node} direction 0 (temperature) is not a structural DOF"
                )))
            }
            _ => {
                return Err(bad(format!(
                    "node {node} direction {direction} is not one of 1..6 (ux..rz)"
                )))
            }
        };
        push_dof(path, line, Dof::new(node, kind), &mut dofs, &mut seen)?;
    }
    Ok(DofMap::new(dofs))
}

/// The DOF map of a DOF list (`node dof` per line, `#` comments).
fn parse_dof_list(path: &Path, text: &str) -> Result<DofMap, InputError> {
    let mut dofs = Vec::new();
    let mut seen = HashMap::new();
    for (line, content) in text.lines().enumerate().map(|(i, l)| (i + 1, l)) {
        let content = content.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let bad = |what: String| invalid(path, Some(line), what);
        let fields: Vec<&str> = content.split_whitespace().collect();
        let [node, dof] = fields[..] else {
            return Err(bad(format!(
                "expected `node dof` (e.g. `12 uz`), found {} fields",
                fields.len()
            )));
        };
        let node: NodeId = node
            .parse()
            .map_err(|_| bad(format!("node `{}` is not a node number", excerpt(node))))?;
        let kind = DofKind::parse(dof)
            .or_else(|| match dof.parse::<usize>() {
                Ok(d @ 1..=6) => Some(DofKind::ALL[d - 1]),
                _ => None,
            })
            .ok_or_else(|| {
                bad(format!(
                    "DOF `{}` is not one of ux..rz or 1..6",
                    excerpt(dof)
                ))
            })?;
        push_dof(path, line, Dof::new(node, kind), &mut dofs, &mut seen)?;
    }
    Ok(DofMap::new(dofs))
}

fn push_dof(
    path: &Path,
    line: usize,
    dof: Dof,
    dofs: &mut Vec<Dof>,
    seen: &mut HashMap<Dof, usize>,
) -> Result<(), InputError> {
    if let Some(first) = seen.insert(dof, line) {
        return Err(invalid(
            path,
            Some(line),
            format!("{dof} is listed twice (first on line {first})"),
        ));
    }
    dofs.push(dof);
    Ok(())
}

/// Parses `row col value` (1-based) with both indices in `1..=n`; `size`
/// says where `n` comes from, for the error message.
fn parse_entry(
    path: &Path,
    line: usize,
    content: &str,
    n: usize,
    size: &str,
) -> Result<Entry, InputError> {
    let bad = |what: String| invalid(path, Some(line), what);
    let fields: Vec<&str> = content.split_whitespace().collect();
    let [row, col, value] = fields[..] else {
        return Err(bad(format!(
            "expected `row col value`, found {} fields",
            fields.len()
        )));
    };
    let index = |name: &str, s: &str| -> Result<usize, InputError> {
        let i: usize = s
            .parse()
            .map_err(|_| bad(format!("{name} `{}` is not an equation number", excerpt(s))))?;
        if i == 0 || i > n {
            return Err(bad(format!("{name} {i} is out of range 1..={n} ({size})")));
        }
        Ok(i - 1)
    };
    let row = index("row", row)?;
    let col = index("column", col)?;
    let value: f64 = value
        .parse()
        .map_err(|_| bad(format!("value `{}` is not a number", excerpt(value))))?;
    if !value.is_finite() {
        return Err(bad(format!("value {value} is not finite")));
    }
    let largest = flexbody_linalg::dense_check::LARGEST;
    if value.abs() > largest {
        return Err(bad(format!(
            "value {value:e} is beyond {largest:e} in magnitude"
        )));
    }
    Ok(Entry {
        row,
        col,
        value,
        line,
    })
}

/// The entries of a CalculiX `.sti`/`.mas` file over the equations of
/// `dof_path` (`dofs`); every diagonal entry must be present.
fn parse_calculix_matrix(
    path: &Path,
    text: &str,
    dof_path: &Path,
    dofs: &DofMap,
) -> Result<Vec<Entry>, InputError> {
    let n = dofs.len();
    let mut entries = Vec::new();
    let mut diagonal = vec![false; n];
    let size = format!("{} lists {n} equations", dof_path.display());
    for (line, content) in numbered_lines(text) {
        let entry = parse_entry(path, line, content, n, &size)?;
        if entry.row == entry.col {
            diagonal[entry.row] = true;
        }
        entries.push(entry);
    }
    if let Some(missing) = diagonal.iter().position(|d| !d) {
        let size = entries
            .iter()
            .map(|e| e.row.max(e.col) + 1)
            .max()
            .unwrap_or(0);
        let message = if size < n {
            format!(
                "the matrix has {size} equations, but {} lists {n}",
                dof_path.display()
            )
        } else {
            format!(
                "no diagonal entry for equation {} ({} in {})",
                missing + 1,
                dofs.dof(missing),
                dof_path.display()
            )
        };
        return Err(invalid(path, None, message));
    }
    Ok(entries)
}

/// Whether a Matrix Market file stores one triangle or the whole matrix.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Symmetry {
    Symmetric,
    General,
}

struct MatrixMarketFile {
    size: usize,
    size_line: usize,
    symmetry: Symmetry,
    entries: Vec<Entry>,
}

/// The shortest entry line of a coordinate file: `1 1 1` and its newline.
const MIN_ENTRY_BYTES: usize = 6;

fn parse_matrix_market(path: &Path, text: &str) -> Result<MatrixMarketFile, InputError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let header = lines.next().map_or("", |(_, l)| l);
    let words: Vec<String> = header
        .split_whitespace()
        .map(|w| w.to_ascii_lowercase())
        .collect();
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    let symmetry = match words[..] {
        ["%%matrixmarket", "matrix", "coordinate", "real" | "double" | "integer", symmetry] => {
            match symmetry {
                "symmetric" => Symmetry::Symmetric,
                "general" => Symmetry::General,
                other => {
                    return Err(invalid(
                        path,
                        Some(1),
                        format!(
                            "{} matrices are not supported (symmetric or general)",
                            excerpt(other)
                        ),
                    ))
                }
            }
        }
        _ => {
            return Err(invalid(
                path,
                Some(1),
                format!(
                "expected `%%MatrixMarket matrix coordinate real symmetric|general`, found `{}`",
                excerpt(header)
            ),
            ))
        }
    };
    let mut data = lines.filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    let (size_line, size) = data
        .next()
        .ok_or_else(|| invalid(path, None, "no `rows cols entries` line"))?;
    let fields: Vec<&str> = size.split_whitespace().collect();
    let numbers: Vec<usize> = fields.iter().filter_map(|f| f.parse().ok()).collect();
    let [rows, cols, count] = numbers[..] else {
        return Err(invalid(
            path,
            Some(size_line),
            format!("expected `rows cols entries`, found `{}`", excerpt(size)),
        ));
    };
    if fields.len() != 3 {
        return Err(invalid(
            path,
            Some(size_line),
            format!("expected `rows cols entries`, found `{}`", excerpt(size)),
        ));
    }
    if rows != cols {
        return Err(invalid(
            path,
            Some(size_line),
            format!("the matrix is {rows} x {cols}, not square"),
        ));
    }
    // Each entry is a line of at least `1 1 1` and a newline: a count the
    // file cannot hold is refused before storage is taken for it.
    let room = text.len() / MIN_ENTRY_BYTES + 1;
    if count > room {
        return Err(invalid(
            path,
            Some(size_line),
            format!(
                "{count} entries announced, but the file of {} bytes holds at most {room} \
                 (an entry line takes at least {MIN_ENTRY_BYTES} bytes)",
                text.len()
            ),
        ));
    }
    let size_note = format!("line {size_line} gives {rows} x {cols}");
    let mut entries = Vec::with_capacity(count);
    let mut last_line = size_line;
    for (line, content) in data {
        if entries.len() == count {
            return Err(invalid(
                path,
                Some(line),
                format!("more entries than the {count} announced on line {size_line}"),
            ));
        }
        entries.push(parse_entry(path, line, content, rows, &size_note)?);
        last_line = line;
    }
    if entries.len() != count {
        return Err(invalid(
            path,
            Some(last_line),
            format!(
                "{} entries, but line {size_line} announces {count}",
                entries.len()
            ),
        ));
    }
    Ok(MatrixMarketFile {
        size: rows,
        size_line,
        symmetry,
        entries,
    })
}

/// The full symmetric matrix from entries that give each off-diagonal pair
/// once, in either triangle.
fn symmetric_from_triangle(
    path: &Path,
    n: usize,
    entries: &[Entry],
) -> Result<SparseMat, InputError> {
    let mut first_line = HashMap::with_capacity(entries.len());
    let mut triplets = Vec::with_capacity(2 * entries.len());
    for e in entries {
        let key = (e.row.min(e.col), e.row.max(e.col));
        if let Some(first) = first_line.insert(key, e.line) {
            return Err(invalid(
                path,
                Some(e.line),
                format!(
                    "entry ({}, {}) is given twice (first on line {first}); a symmetric matrix gives each pair once",
                    e.row + 1,
                    e.col + 1
                ),
            ));
        }
        if e.value != 0.0 {
            triplets.push(Triplet::new(e.row, e.col, e.value));
            if e.row != e.col {
                triplets.push(Triplet::new(e.col, e.row, e.value));
            }
        }
    }
    build(path, n, &triplets)
}

/// The symmetric matrix from all entries of a general matrix, which must be
/// symmetric to 1e-10 of its largest entry; mirrored entries are averaged.
fn symmetric_from_general(
    path: &Path,
    n: usize,
    entries: &[Entry],
) -> Result<SparseMat, InputError> {
    let mut by_position: HashMap<(usize, usize), Entry> = HashMap::with_capacity(entries.len());
    for e in entries {
        if let Some(first) = by_position.insert((e.row, e.col), *e) {
            return Err(invalid(
                path,
                Some(e.line),
                format!(
                    "entry ({}, {}) is given twice (first on line {})",
                    e.row + 1,
                    e.col + 1,
                    first.line
                ),
            ));
        }
    }
    let largest = entries.iter().fold(0.0_f64, |m, e| m.max(e.value.abs()));
    let tolerance = 1e-10 * largest;
    let mut triplets = Vec::with_capacity(entries.len());
    for e in entries {
        let mirror = by_position.get(&(e.col, e.row));
        let mirror_value = mirror.map_or(0.0, |m| m.value);
        if (e.value - mirror_value).abs() > tolerance {
            let (line, there) = match mirror {
                Some(m) => (e.line.max(m.line), format!("line {}", e.line.min(m.line))),
                None => (e.line, "absent".to_string()),
            };
            return Err(invalid(
                path,
                Some(line),
                format!(
                    "the matrix is not symmetric: entry ({}, {}) is {:e}, entry ({}, {}) is {:e} ({there})",
                    e.row + 1,
                    e.col + 1,
                    e.value,
                    e.col + 1,
                    e.row + 1,
                    mirror_value
                ),
            ));
        }
        let value = 0.5 * (e.value + mirror_value);
        if value != 0.0 {
            triplets.push(Triplet::new(e.row, e.col, value));
        }
    }
    build(path, n, &triplets)
}

fn build(
    path: &Path,
    n: usize,
    triplets: &[Triplet<usize, usize, f64>],
) -> Result<SparseMat, InputError> {
    sparse::from_triplets(n, n, triplets).map_err(|e| invalid(path, None, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory under the system temp dir, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir()
                .join(format!("flexbody-matrices-{}-{name}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            TempDir(dir)
        }

        fn write(&self, name: &str, text: &str) -> PathBuf {
            let path = self.0.join(name);
            std::fs::write(&path, text).unwrap();
            path
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn dense(a: &SparseMat) -> Vec<Vec<f64>> {
        let d = a.to_dense();
        (0..d.nrows())
            .map(|i| (0..d.ncols()).map(|j| d[(i, j)]).collect())
            .collect()
    }

    /// The file and line of an `Invalid` error, and its message.
    fn where_and_what(e: InputError) -> (PathBuf, Option<usize>, String) {
        match e {
            InputError::Invalid {
                path,
                line,
                message,
            } => (path, line, message),
            other => panic!("expected an Invalid error, got {other}"),
        }
    }

    const DOF: &str = "7.1\n7.3\n12.2\n";
    const STI: &str = "1 1  4.0000000000000e+00\n1 2 -1.0000000000000e+00\n2 2  5.0000000000000e+00\n1 3  0.0000000000000e+00\n2 3  2.5000000000000e+00\n3 3  6.0000000000000e+00\n";
    const MAS: &str = "1 1  2.0000000000000e+00\n1 2  0.0000000000000e+00\n2 2  2.0000000000000e+00\n1 3  0.0000000000000e+00\n2 3  0.0000000000000e+00\n3 3  1.0000000000000e+00\n";

    fn calculix_job(dir: &TempDir, dof: &str, sti: &str, mas: &str) -> PathBuf {
        dir.write("job.dof", dof);
        dir.write("job.sti", sti);
        dir.write("job.mas", mas);
        dir.0.join("job")
    }

    #[test]
    fn calculix_matrices_are_full_symmetric_over_the_dof_file() {
        let dir = TempDir::new("ccx-ok");
        let m = read_calculix_matrices(&calculix_job(&dir, DOF, STI, MAS)).unwrap();
        assert_eq!(
            m.dof_map.dofs(),
            &[
                Dof::new(7, DofKind::Ux),
                Dof::new(7, DofKind::Uz),
                Dof::new(12, DofKind::Uy)
            ]
        );
        assert_eq!(
            dense(&m.stiffness),
            vec![
                vec![4.0, -1.0, 0.0],
                vec![-1.0, 5.0, 2.5],
                vec![0.0, 2.5, 6.0]
            ]
        );
        assert_eq!(
            dense(&m.mass),
            vec![
                vec![2.0, 0.0, 0.0],
                vec![0.0, 2.0, 0.0],
                vec![0.0, 0.0, 1.0]
            ]
        );
        // Explicit zeros of the file are not stored.
        assert_eq!(m.mass.compute_nnz(), 3);
    }

    #[test]
    fn calculix_direction_after_the_dot_is_an_integer() {
        let dir = TempDir::new("ccx-dir");
        let m = read_calculix_matrices(&calculix_job(
            &dir,
            "10.1\n1.10\n",
            "1 1 1.0\n2 2 1.0\n",
            "1 1 1.0\n2 2 1.0\n",
        ));
        let (path, line, message) = where_and_what(m.unwrap_err());
        assert_eq!(path, dir.0.join("job.dof"));
        assert_eq!(line, Some(2));
        assert!(message.contains("direction 10"), "{message}");

        let e = read_calculix_matrices(&calculix_job(&dir, "3.0\n", "1 1 1.0\n", "1 1 1.0\n"));
        let (_, line, message) = where_and_what(e.unwrap_err());
        assert_eq!(line, Some(1));
        assert!(message.contains("temperature"), "{message}");

        let e = read_calculix_matrices(&calculix_job(&dir, "3.1\n3\n", "1 1 1.0\n", "1 1 1.0\n"));
        assert_eq!(where_and_what(e.unwrap_err()).1, Some(2));

        let e = read_calculix_matrices(&calculix_job(
            &dir,
            "3.1\n\n3.1\n",
            "1 1 1.0\n",
            "1 1 1.0\n",
        ));
        let (_, line, message) = where_and_what(e.unwrap_err());
        assert_eq!(line, Some(3));
        assert!(message.contains("twice (first on line 1)"), "{message}");
    }

    #[test]
    fn calculix_bad_rows_name_file_and_line() {
        let dir = TempDir::new("ccx-bad");
        let cases = [
            ("1 1 4.0\n1 2 -1.0 7\n", 2, "found 4 fields"),
            ("1 1 4.0\n1 x -1.0\n", 2, "column `x`"),
            ("1 1 4.0\n\n1 4 -1.0\n", 3, "column 4 is out of range"),
            ("1 1 4.0\n0 1 -1.0\n", 2, "row 0 is out of range"),
            ("1 1 4.0\n1 2 NaN\n", 2, "not finite"),
            ("1 1 4.0\n1 2 abc\n", 2, "value `abc`"),
            (
                "1 1 4.0\n1 2 1.0\n2 1 1.0\n2 2 1.0\n3 3 1.0\n",
                3,
                "twice (first on line 2)",
            ),
            (
                "1 1 4.0\n1 2 1.0\n2 2 -1.0\n3 3 1.0\n",
                3,
                "diagonal entry -1e0 at node 7 uz is negative",
            ),
        ];
        for (sti, line, what) in cases {
            let e = read_calculix_matrices(&calculix_job(&dir, DOF, sti, MAS)).unwrap_err();
            let (path, l, message) = where_and_what(e);
            assert_eq!(path, dir.0.join("job.sti"), "{sti}");
            assert_eq!(l, Some(line), "{sti}: {message}");
            assert!(message.contains(what), "{sti}: {message}");
        }
    }

    #[test]
    fn calculix_size_mismatch_with_the_dof_file() {
        let dir = TempDir::new("ccx-size");
        let short_mass = "1 1 2.0\n1 2 0.0\n2 2 2.0\n";
        let e = read_calculix_matrices(&calculix_job(&dir, DOF, STI, short_mass)).unwrap_err();
        let (path, line, message) = where_and_what(e);
        assert_eq!(path, dir.0.join("job.mas"));
        assert_eq!(line, None);
        assert!(message.contains("has 2 equations"), "{message}");
        assert!(message.contains("lists 3"), "{message}");

        let e = read_calculix_matrices(&calculix_job(&dir, "7.1\n7.3\n", STI, MAS)).unwrap_err();
        let (path, line, message) = where_and_what(e);
        assert_eq!(path, dir.0.join("job.sti"));
        assert_eq!(line, Some(4));
        assert!(message.contains("job.dof lists 2 equations"), "{message}");

        // A diagonal entry missing inside the matrix names its node and DOF.
        let no_diagonal = "1 1 2.0\n1 2 0.0\n1 3 0.0\n3 3 1.0\n";
        let e = read_calculix_matrices(&calculix_job(&dir, DOF, STI, no_diagonal)).unwrap_err();
        let (_, _, message) = where_and_what(e);
        assert!(
            message.contains("no diagonal entry for equation 2 (node 7 uz in ")
                && message.contains("job.dof)"),
            "{message}"
        );

        let e = read_calculix_matrices(&dir.0.join("absent")).unwrap_err();
        assert!(matches!(e, InputError::Read { .. }));
    }

    const DOFS: &str = "# node dof\n7 ux\n7 3   # uz by number\n\n12 UY\n";

    #[test]
    fn matrix_market_symmetric_and_general() {
        let dir = TempDir::new("mm-ok");
        let k = dir.write(
            "k.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n% K\n3 3 5\n1 1 4\n2 1 -1\n2 2 5\n3 2 2.5\n3 3 6\n",
        );
        let m = dir.write(
            "m.mtx",
            "%%MatrixMarket matrix coordinate real general\n3 3 5\n1 1 2\n2 2 2\n3 3 1\n1 3 0.5\n3 1 0.5\n",
        );
        let d = dir.write("dofs.txt", DOFS);
        let model = read_matrix_market(&k, &m, &d).unwrap();
        assert_eq!(
            model.dof_map.dofs(),
            &[
                Dof::new(7, DofKind::Ux),
                Dof::new(7, DofKind::Uz),
                Dof::new(12, DofKind::Uy)
            ]
        );
        assert_eq!(
            dense(&model.stiffness),
            vec![
                vec![4.0, -1.0, 0.0],
                vec![-1.0, 5.0, 2.5],
                vec![0.0, 2.5, 6.0]
            ]
        );
        assert_eq!(
            dense(&model.mass),
            vec![
                vec![2.0, 0.0, 0.5],
                vec![0.0, 2.0, 0.0],
                vec![0.5, 0.0, 1.0]
            ]
        );
    }

    #[test]
    fn matrix_market_errors_name_file_and_line() {
        let dir = TempDir::new("mm-bad");
        let good_k =
            "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 4\n2 2 5\n3 3 6\n";
        let good_m =
            "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 1\n2 2 1\n3 3 1\n";
        let d = dir.write("dofs.txt", DOFS);
        let m = dir.write("m.mtx", good_m);
        let cases = [
            (
                "%%MatrixMarket matrix coordinate real general\n3 3 3\n1 1 4\n1 2 1\n2 2 5\n",
                4,
                "not symmetric",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n3 3 4\n1 1 4\n1 2 1\n2 1 1.5\n2 2 5\n",
                5,
                "not symmetric",
            ),
            (
                "%%MatrixMarket matrix coordinate complex general\n3 3 0\n",
                1,
                "expected `%%MatrixMarket",
            ),
            (
                "%%MatrixMarket matrix coordinate real skew-symmetric\n3 3 0\n",
                1,
                "skew-symmetric",
            ),
            ("%%MatrixMarket matrix coordinate real symmetric\n3 4 0\n", 2, "not square"),
            ("%%MatrixMarket matrix coordinate real symmetric\n2 2 0\n", 2, "lists 3 DOFs"),
            (
                "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 4\n2 2 5\n",
                4,
                "2 entries, but line 2 announces 3",
            ),
            (
                "%%MatrixMarket matrix coordinate real symmetric\n3 3 1\n1 1 4\n2 2 5\n",
                4,
                "more entries than the 1",
            ),
            (
                "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 4\n2 2 5\n3 3 -6\n",
                5,
                "diagonal entry -6e0 at node 12 uy is negative",
            ),
            (
                "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n% c\n1 1 4\n4 2 5\n",
                5,
                "row 4 is out of range",
            ),
            (
                "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 4\n2 2 inf\n",
                4,
                "not finite",
            ),
            (
                "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 4\n2 2\n",
                4,
                "2 fields",
            ),
        ];
        for (text, line, what) in cases {
            let k = dir.write("k.mtx", text);
            let e = read_matrix_market(&k, &m, &d).unwrap_err();
            let (path, l, message) = where_and_what(e);
            assert_eq!(path, k, "{text}");
            assert_eq!(l, Some(line), "{text}: {message}");
            assert!(message.contains(what), "{text}: {message}");
        }

        // Counts the file cannot hold, refused before storage is taken:
        // usize::MAX aborted on "capacity overflow".
        for count in ["18446744073709551615", "1000000000"] {
            let text =
                format!("%%MatrixMarket matrix coordinate real symmetric\n3 3 {count}\n1 1 4\n");
            let k = dir.write("k.mtx", &text);
            let (_, line, message) = where_and_what(read_matrix_market(&k, &m, &d).unwrap_err());
            assert_eq!(line, Some(2));
            let expected = format!(
                "{count} entries announced, but the file of {} bytes holds at most {}",
                text.len(),
                text.len() / 6 + 1
            );
            assert!(message.starts_with(&expected), "{message}");
        }
        // A quoted line is cut to an excerpt.
        let text = format!("%%MatrixMarket matrix {}\n", "y".repeat(5000));
        let k = dir.write("k.mtx", &text);
        let (_, _, message) = where_and_what(read_matrix_market(&k, &m, &d).unwrap_err());
        assert!(
            message.len() < 250 && message.ends_with("... (5022 bytes)`"),
            "{message}"
        );

        let k = dir.write("k.mtx", good_k);
        let bad_dofs = [
            ("1 ux\n2 uq\n", 2, "`uq`"),
            ("1 ux\n2 7\n", 2, "`7`"),
            ("1 ux\nx uy\n", 2, "node `x`"),
            ("1 ux\n1 uy 3\n", 2, "3 fields"),
            ("1 ux\n# c\n1 1\n", 3, "twice (first on line 1)"),
        ];
        for (text, line, what) in bad_dofs {
            let d = dir.write("dofs.txt", text);
            let e = read_matrix_market(&k, &m, &d).unwrap_err();
            let (path, l, message) = where_and_what(e);
            assert_eq!(path, d, "{text}");
            assert_eq!(l, Some(line), "{text}: {message}");
            assert!(message.contains(what), "{text}: {message}");
        }
    }
}
