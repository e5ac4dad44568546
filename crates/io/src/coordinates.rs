//! Node coordinates for matrix input (`--coords FILE`): one `node x y z`
//! line per node (m), fields separated by blanks or commas, `#` starts a
//! comment. Matrices alone have no geometry; with coordinates, their
//! rigid-body modes come from geometry (eq. 12) and their body can be
//! written as a SID.

use crate::text::{excerpt, finite_number, read_text};
use crate::InputError;
use flexbody_fem::{DofMap, NodeId};
use std::collections::HashMap;
use std::path::Path;

/// The coordinates in the file at `path`, which must give every node of
/// `dofs` (the matrices' DOF map); nodes without DOFs may be listed too
/// (a whole mesh's list for condensed matrices). Errors name the file,
/// the line and the node: a line that is not `node x y z`, a value that is
/// not a finite number, a node listed twice, a node of the matrices
/// missing.
pub fn read_node_coordinates(
    path: &Path,
    dofs: &DofMap,
) -> Result<HashMap<NodeId, [f64; 3]>, InputError> {
    let text = read_text(path)?;
    let invalid = |line: Option<usize>, message: String| InputError::Invalid {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut coordinates = HashMap::new();
    let mut lines: HashMap<NodeId, usize> = HashMap::new();
    for (line, content) in text.lines().enumerate().map(|(i, l)| (i + 1, l)) {
        let content = content.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let bad = |what: String| invalid(Some(line), what);
        let fields: Vec<&str> = content
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let [node, x, y, z] = fields[..] else {
            return Err(bad(format!(
                "expected `node x y z` (e.g. `12 0.5 0 0.1`), found {} fields",
                fields.len()
            )));
        };
        let node: NodeId = node
            .parse()
            .map_err(|_| bad(format!("node `{}` is not a node number", excerpt(node))))?;
        let mut xyz = [0.0; 3];
        for (slot, value) in xyz.iter_mut().zip([x, y, z]) {
            *slot = finite_number(value).map_err(|m| bad(format!("node {node}: {m}")))?;
        }
        if let Some(first) = lines.insert(node, line) {
            return Err(bad(format!(
                "node {node} is listed twice (first on line {first})"
            )));
        }
        coordinates.insert(node, xyz);
    }
    let mut missing: Vec<NodeId> = dofs
        .dofs()
        .iter()
        .map(|d| d.node)
        .filter(|n| !coordinates.contains_key(n))
        .collect();
    missing.sort_unstable();
    missing.dedup();
    if let Some(first) = missing.first() {
        return Err(invalid(
            None,
            format!(
                "no coordinates for node {first}, which has DOFs in the matrices \
                 ({} such nodes missing); give one `node x y z` line per node",
                missing.len()
            ),
        ));
    }
    Ok(coordinates)
}
