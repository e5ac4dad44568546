//! Node numbering of the solid elements, in Abaqus/CalculiX order (VTK's
//! order for the same cells): where the corners of a hexahedron sit, and
//! which corners each mid-edge node of a quadratic element joins.

/// The corners of the 8- and 20-node hexahedron in Abaqus order, each as
/// the bit pattern of its position in the unit cell (x: bit 0, y: bit 1,
/// z: bit 2): nodes 1-4 go round the bottom face, 5-8 the top face.
pub const HEX_CORNERS: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];

/// Mid-edge nodes 9-20 of the 20-node hexahedron: the corners (0-based)
/// each joins (bottom face, top face, then the vertical edges).
pub const HEX20_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Mid-edge nodes 5-10 of the 10-node tetrahedron: the corners (0-based)
/// each joins.
pub const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// Mid-edge nodes 7-15 of the 15-node wedge: the corners (0-based) each
/// joins (bottom triangle, top triangle, then the vertical edges).
pub const WEDGE15_EDGES: [(usize, usize); 9] = [
    (0, 1),
    (1, 2),
    (2, 0),
    (3, 4),
    (4, 5),
    (5, 3),
    (0, 3),
    (1, 4),
    (2, 5),
];

/// The 8 corner nodes, in Abaqus order, of the cell `(i, j, k)` of a
/// structured grid whose point `[i, j, k]` is node `node([i, j, k])`.
pub fn hex_cell<N>(i: usize, j: usize, k: usize, node: impl Fn([usize; 3]) -> N) -> Vec<N> {
    HEX_CORNERS
        .iter()
        .map(|&b| node([i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1)]))
        .collect()
}
