//! Shape functions and their derivatives with respect to the natural
//! coordinates, in the Abaqus/CalculiX node numbering (as CalculiX's
//! `shape8h.f`, `shape20h.f`, `shape4tet.f`, `shape10tet.f`, `shape6w.f`).
//!
//! Reference elements:
//! - hexahedra: the cube `-1 <= xi, eta, zeta <= 1`; corners 1-4 on
//!   `zeta = -1` counter-clockwise from `(-1,-1)`, 5-8 above them; 20-node
//!   mid-edge nodes 9-12 on edges 1-2, 2-3, 3-4, 4-1, 13-16 on 5-6, 6-7,
//!   7-8, 8-5, 17-20 on 1-5, 2-6, 3-7, 4-8;
//! - tetrahedra: `xi, eta, zeta >= 0, xi + eta + zeta <= 1`; corner 1 at the
//!   origin, 2 on `xi`, 3 on `eta`, 4 on `zeta`; 10-node mid-edge nodes 5-10
//!   on edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4;
//! - wedge: triangle `xi, eta >= 0, xi + eta <= 1` times `-1 <= zeta <= 1`;
//!   nodes 1-3 (origin, `xi`, `eta`) on `zeta = -1`, 4-6 above them;
//!   15-node mid-edge nodes 7-9 on edges 1-2, 2-3, 3-1, 10-12 on 4-5, 5-6,
//!   6-4, 13-15 on 1-4, 2-5, 3-6 (`shape15w.f`).

use super::SolidKind;

/// Largest node count of a solid element.
pub(super) const MAX_NODES: usize = 20;

/// Natural coordinates of the 20-node hexahedron's nodes (the first 8 are
/// the 8-node hexahedron's).
const HEX20_NODES: [[f64; 3]; 20] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// Natural coordinates of the 10-node tetrahedron's nodes (the first 4 are
/// the 4-node tetrahedron's).
const TET10_NODES: [[f64; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];

/// Natural coordinates of the 6-node wedge's nodes.
const WEDGE6_NODES: [[f64; 3]; 6] = [
    [0.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
];

/// Natural coordinates of the 15-node wedge's nodes (the first 6 are the
/// 6-node wedge's).
const WEDGE15_NODES: [[f64; 3]; 15] = [
    [0.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [0.5, 0.0, -1.0],
    [0.5, 0.5, -1.0],
    [0.0, 0.5, -1.0],
    [0.5, 0.0, 1.0],
    [0.5, 0.5, 1.0],
    [0.0, 0.5, 1.0],
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// Natural coordinates of the element's nodes, in node order.
pub(super) const fn node_coordinates(kind: SolidKind) -> &'static [[f64; 3]] {
    let hex: &'static [[f64; 3]] = &HEX20_NODES;
    let tet: &'static [[f64; 3]] = &TET10_NODES;
    match kind {
        SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => hex.split_at(8).0,
        SolidKind::C3D20 | SolidKind::C3D20R => hex,
        SolidKind::C3D10 => tet,
        SolidKind::C3D4 => tet.split_at(4).0,
        SolidKind::C3D6 => &WEDGE6_NODES,
        SolidKind::C3D15 => &WEDGE15_NODES,
    }
}

/// Shape functions `n[a]` and their natural derivatives `dn[a][j] =
/// dN_a / dxi_j` at natural coordinates `xi`, for the first
/// `kind.node_count()` entries.
pub(super) fn evaluate(
    kind: SolidKind,
    xi: [f64; 3],
    n: &mut [f64; MAX_NODES],
    dn: &mut [[f64; 3]; MAX_NODES],
) {
    match kind {
        SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => hex8(xi, n, dn),
        SolidKind::C3D20 | SolidKind::C3D20R => hex20(xi, n, dn),
        SolidKind::C3D10 => tet10(xi, n, dn),
        SolidKind::C3D4 => tet4(xi, n, dn),
        SolidKind::C3D6 => wedge6(xi, n, dn),
        SolidKind::C3D15 => wedge15(xi, n, dn),
    }
}

/// Trilinear hexahedron: `N = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a) / 8`.
fn hex8(xi: [f64; 3], n: &mut [f64; MAX_NODES], dn: &mut [[f64; 3]; MAX_NODES]) {
    for (a, c) in HEX20_NODES[..8].iter().enumerate() {
        let f = [0, 1, 2].map(|j| 1.0 + xi[j] * c[j]);
        n[a] = 0.125 * f[0] * f[1] * f[2];
        dn[a] = [
            0.125 * c[0] * f[1] * f[2],
            0.125 * f[0] * c[1] * f[2],
            0.125 * f[0] * f[1] * c[2],
        ];
    }
}

/// 20-node serendipity hexahedron. Corners:
/// `N = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a)(xi xi_a + eta eta_a + zeta zeta_a - 2) / 8`;
/// mid-edge nodes with `xi_a = 0`: `N = (1 - xi^2)(1 + eta eta_a)(1 + zeta zeta_a) / 4`
/// (and permutations).
fn hex20(xi: [f64; 3], n: &mut [f64; MAX_NODES], dn: &mut [[f64; 3]; MAX_NODES]) {
    for (a, c) in HEX20_NODES[..8].iter().enumerate() {
        let f = [0, 1, 2].map(|j| 1.0 + xi[j] * c[j]);
        let s = xi[0] * c[0] + xi[1] * c[1] + xi[2] * c[2] - 2.0;
        n[a] = 0.125 * f[0] * f[1] * f[2] * s;
        // d/dxi_j: c_j (prod of the other two f) (s + f_j).
        dn[a] = [
            0.125 * c[0] * f[1] * f[2] * (s + f[0]),
            0.125 * c[1] * f[0] * f[2] * (s + f[1]),
            0.125 * c[2] * f[0] * f[1] * (s + f[2]),
        ];
    }
    for (a, c) in HEX20_NODES.iter().enumerate().skip(8) {
        // The direction along the edge (natural coordinate 0 at the node).
        let along = if c[0] == 0.0 {
            0
        } else if c[1] == 0.0 {
            1
        } else {
            2
        };
        let (p, q) = ((along + 1) % 3, (along + 2) % 3);
        let g = 1.0 - xi[along] * xi[along];
        let fp = 1.0 + xi[p] * c[p];
        let fq = 1.0 + xi[q] * c[q];
        n[a] = 0.25 * g * fp * fq;
        let mut d = [0.0; 3];
        d[along] = -0.5 * xi[along] * fp * fq;
        d[p] = 0.25 * g * c[p] * fq;
        d[q] = 0.25 * g * fp * c[q];
        dn[a] = d;
    }
}

/// Linear tetrahedron: `N = (1 - xi - eta - zeta, xi, eta, zeta)`.
fn tet4(xi: [f64; 3], n: &mut [f64; MAX_NODES], dn: &mut [[f64; 3]; MAX_NODES]) {
    n[0] = 1.0 - xi[0] - xi[1] - xi[2];
    n[1] = xi[0];
    n[2] = xi[1];
    n[3] = xi[2];
    dn[0] = [-1.0, -1.0, -1.0];
    dn[1] = [1.0, 0.0, 0.0];
    dn[2] = [0.0, 1.0, 0.0];
    dn[3] = [0.0, 0.0, 1.0];
}

/// Quadratic tetrahedron in barycentric coordinates `l = (1 - xi - eta -
/// zeta, xi, eta, zeta)`: corners `l_i (2 l_i - 1)`, mid-edge nodes
/// `4 l_i l_j`.
fn tet10(xi: [f64; 3], n: &mut [f64; MAX_NODES], dn: &mut [[f64; 3]; MAX_NODES]) {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    // dl_i / dxi_j.
    const DL: [[f64; 3]; 4] = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        let s = 4.0 * l[i] - 1.0;
        dn[i] = DL[i].map(|d| s * d);
    }
    for (k, &(i, j)) in super::topology::TET10_EDGES.iter().enumerate() {
        n[4 + k] = 4.0 * l[i] * l[j];
        dn[4 + k] = [0, 1, 2].map(|m| 4.0 * (DL[i][m] * l[j] + l[i] * DL[j][m]));
    }
}

/// Linear wedge: triangle coordinates `(1 - xi - eta, xi, eta)` times
/// `(1 -+ zeta) / 2`.
fn wedge6(xi: [f64; 3], n: &mut [f64; MAX_NODES], dn: &mut [[f64; 3]; MAX_NODES]) {
    let t = [1.0 - xi[0] - xi[1], xi[0], xi[1]];
    const DT: [[f64; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    for (layer, sign) in [(0, -1.0), (1, 1.0)] {
        let h = 0.5 * (1.0 + sign * xi[2]);
        for i in 0..3 {
            let a = 3 * layer + i;
            n[a] = t[i] * h;
            dn[a] = [DT[i][0] * h, DT[i][1] * h, 0.5 * sign * t[i]];
        }
    }
}

/// 15-node serendipity wedge, with the triangle coordinates
/// `t = (1 - xi - eta, xi, eta)` and `zeta`. Corner `i` of the layer
/// `zeta_a = -1, 1`: `N = t_i (2 t_i - 1)(1 + zeta zeta_a) / 2 - t_i (1 -
/// zeta^2) / 2`; mid-edge node between corners `i`, `j` of a layer:
/// `N = 2 t_i t_j (1 + zeta zeta_a)`; mid-height node of corner `i`:
/// `N = t_i (1 - zeta^2)`.
fn wedge15(xi: [f64; 3], n: &mut [f64; MAX_NODES], dn: &mut [[f64; 3]; MAX_NODES]) {
    let t = [1.0 - xi[0] - xi[1], xi[0], xi[1]];
    // d t_i / d (xi, eta)
    const DT: [[f64; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let z = xi[2];
    let bubble = 1.0 - z * z;
    let d_of = |dt: [f64; 2], f: f64, dz: f64| [dt[0] * f, dt[1] * f, dz];
    for (layer, sign) in [(0, -1.0), (1, 1.0)] {
        let h = 1.0 + sign * z;
        for i in 0..3 {
            let a = 3 * layer + i;
            let ti = t[i];
            n[a] = 0.5 * ti * (2.0 * ti - 1.0) * h - 0.5 * ti * bubble;
            // d/dt_i of the corner function, then the chain rule.
            let d_dt = 0.5 * (4.0 * ti - 1.0) * h - 0.5 * bubble;
            let d_dz = 0.5 * ti * (2.0 * ti - 1.0) * sign + ti * z;
            dn[a] = d_of(DT[i], d_dt, d_dz);
        }
        for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
            let a = 6 + 3 * layer + k;
            n[a] = 2.0 * t[i] * t[j] * h;
            let d = [0, 1].map(|c| 2.0 * (DT[i][c] * t[j] + t[i] * DT[j][c]) * h);
            dn[a] = [d[0], d[1], 2.0 * t[i] * t[j] * sign];
        }
    }
    for i in 0..3 {
        let a = 12 + i;
        n[a] = t[i] * bubble;
        dn[a] = d_of(DT[i], bubble, -2.0 * t[i] * z);
    }
}
