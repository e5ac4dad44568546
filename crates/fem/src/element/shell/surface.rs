//! The shell's reference surface in natural coordinates: shape functions,
//! the in-plane integration rules (of stiffness, of mass, of the drilling
//! penalty), and the extrapolation from the stiffness rule's points to the
//! nodes.

use super::ShellKind;

/// Largest number of interpolation nodes of a shell element (S8: its eight
/// and an internal centre node; S3: its three and the rotation bubble).
pub(super) const MAX_NODES: usize = 9;

/// Largest number of points of a stress rule ([`stress_rule`]).
pub(super) const MAX_POINTS: usize = 4;

/// `1 / sqrt(3)`: the two-point Gauss abscissa.
pub(super) const G2: f64 = 0.577_350_269_189_625_8;

/// `sqrt(3 / 5)`: the outer three-point Gauss abscissa.
pub(super) const G3: f64 = 0.774_596_669_241_483_4;

/// Shape functions `n` and their derivatives `dn[a] = [dN_a/dr, dN_a/ds]`
/// at `(r, s)`, in the Abaqus node order. S4: the bilinear quadrilateral on
/// `[-1, 1]^2`, corners `(-1, -1), (1, -1), (1, 1), (-1, 1)`; S3: the linear
/// triangle, corners `(0, 0), (1, 0), (0, 1)`; S6: the quadratic triangle,
/// those corners and then the mid-side nodes `(1/2, 0), (1/2, 1/2), (0,
/// 1/2)`; S8: the nine-node Lagrangian quadrilateral, its corners as S4's,
/// then the mid-side nodes `(0, -1), (1, 0), (0, 1), (-1, 0)` and the
/// internal centre `(0, 0)`. S3's bubble (its fourth interpolation node)
/// moves no point of the surface: its `n` and `dn` are zero (its rotations
/// enter through [`rotation_bubble`]).
pub(super) fn evaluate(
    kind: ShellKind,
    [r, s]: [f64; 2],
    n: &mut [f64; MAX_NODES],
    dn: &mut [[f64; 2]; MAX_NODES],
) {
    match kind {
        ShellKind::S4 => {
            for (a, [ra, sa]) in QUAD_NODES.iter().enumerate() {
                n[a] = 0.25 * (1.0 + ra * r) * (1.0 + sa * s);
                dn[a] = [0.25 * ra * (1.0 + sa * s), 0.25 * sa * (1.0 + ra * r)];
            }
        }
        ShellKind::S3 => {
            n[..3].copy_from_slice(&[1.0 - r - s, r, s]);
            dn[..3].copy_from_slice(&[[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
        }
        ShellKind::S6 => {
            let l = 1.0 - r - s;
            n[..6].copy_from_slice(&[
                l * (2.0 * l - 1.0),
                r * (2.0 * r - 1.0),
                s * (2.0 * s - 1.0),
                4.0 * l * r,
                4.0 * r * s,
                4.0 * s * l,
            ]);
            dn[..6].copy_from_slice(&[
                [1.0 - 4.0 * l, 1.0 - 4.0 * l],
                [4.0 * r - 1.0, 0.0],
                [0.0, 4.0 * s - 1.0],
                [4.0 * (l - r), -4.0 * r],
                [4.0 * s, 4.0 * r],
                [-4.0 * s, 4.0 * (l - s)],
            ]);
        }
        ShellKind::S8 => {
            // One-dimensional quadratics through -1, 0, 1 and derivatives.
            let q = |x: f64| [0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)];
            let dq = |x: f64| [x - 0.5, -2.0 * x, x + 0.5];
            let (qr, qs, dqr, dqs) = (q(r), q(s), dq(r), dq(s));
            for (a, [ra, sa]) in QUAD9_NODES.iter().enumerate() {
                let (i, j) = ((ra + 1.0) as usize, (sa + 1.0) as usize);
                n[a] = qr[i] * qs[j];
                dn[a] = [dqr[i] * qs[j], qr[i] * dqs[j]];
            }
        }
    }
}

/// The nine interpolation nodes of S8: its corners, its mid-side nodes and
/// the internal centre.
const QUAD9_NODES: [[f64; 2]; 9] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
    [0.0, 0.0],
];

const QUAD_NODES: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
/// S3's corners and its rotation bubble, at the centroid.
const TRIANGLE_NODES_AND_BUBBLE: [[f64; 2]; 4] =
    [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0 / 3.0, 1.0 / 3.0]];

/// The cubic bubble `27 r s (1 - r - s)` of S3's rotations (MITC3+: Lee,
/// Lee and Bathe, 2014) and its derivatives `[d/dr, d/ds]` at `(r, s)`:
/// zero on the edges, one at the centroid.
pub(super) fn rotation_bubble([r, s]: [f64; 2]) -> (f64, [f64; 2]) {
    let l = 1.0 - r - s;
    (27.0 * r * s * l, [27.0 * s * (l - r), 27.0 * r * (l - s)])
}

const TRIANGLE_NODES: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [0.5, 0.5],
    [0.0, 0.5],
];

/// The interpolation nodes' natural coordinates (S8: with its centre; S3:
/// with its bubble).
pub(super) fn node_coordinates(kind: ShellKind) -> &'static [[f64; 2]] {
    match kind {
        ShellKind::S4 => &QUAD_NODES,
        ShellKind::S8 => &QUAD9_NODES,
        ShellKind::S3 => &TRIANGLE_NODES_AND_BUBBLE,
        ShellKind::S6 => &TRIANGLE_NODES,
    }
}

const GAUSS_2X2: [([f64; 2], f64); 4] = [
    ([-G2, -G2], 1.0),
    ([G2, -G2], 1.0),
    ([G2, G2], 1.0),
    ([-G2, G2], 1.0),
];

const GAUSS_3X3: [([f64; 2], f64); 9] = {
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    const X: [f64; 3] = [-G3, 0.0, G3];
    let mut out = [([0.0; 2], 0.0); 9];
    let mut k = 0;
    while k < 9 {
        out[k] = ([X[k % 3], X[k / 3]], W[k % 3] * W[k / 3]);
        k += 1;
    }
    out
};

/// The interior three-point triangle rule (exact for quadratics).
const TRIANGLE_3: [([f64; 2], f64); 3] = [
    ([1.0 / 6.0, 1.0 / 6.0], 1.0 / 6.0),
    ([2.0 / 3.0, 1.0 / 6.0], 1.0 / 6.0),
    ([1.0 / 6.0, 2.0 / 3.0], 1.0 / 6.0),
];

/// The six-point triangle rule of Strang and Fix (exact for quartics).
const TRIANGLE_6: [([f64; 2], f64); 6] = {
    const A: f64 = 0.445_948_490_915_965;
    const B: f64 = 0.091_576_213_509_771;
    const WA: f64 = 0.223_381_589_678_011 / 2.0;
    const WB: f64 = 0.109_951_743_655_322 / 2.0;
    [
        ([A, A], WA),
        ([1.0 - 2.0 * A, A], WA),
        ([A, 1.0 - 2.0 * A], WA),
        ([B, B], WB),
        ([1.0 - 2.0 * B, B], WB),
        ([B, 1.0 - 2.0 * B], WB),
    ]
};

/// The in-plane rule of the stiffness: 2 x 2 Gauss points for S4, 3 x 3
/// for S8, the six-point rule for S3 (its bubble's bending strains are
/// quadratic), the three-point interior rule for S6 (reduced); weights
/// sum to the area of the natural element (4 and 1/2).
pub(super) fn rule(kind: ShellKind) -> &'static [([f64; 2], f64)] {
    match kind {
        ShellKind::S4 => &GAUSS_2X2,
        ShellKind::S8 => &GAUSS_3X3,
        ShellKind::S3 => &TRIANGLE_6,
        ShellKind::S6 => &TRIANGLE_3,
    }
}

/// The in-plane points the stresses are evaluated at and extrapolated
/// from: S4's and S6's stiffness rule, S8's 2 x 2 Gauss points (in the
/// order of the corners they are nearest), S3's three interior points.
pub(super) fn stress_rule(kind: ShellKind) -> &'static [([f64; 2], f64)] {
    match kind {
        ShellKind::S8 => &GAUSS_2X2,
        ShellKind::S3 => &TRIANGLE_3,
        _ => rule(kind),
    }
}

/// The in-plane rule of the mass, of the drilling penalty and of S6's
/// tied shear: exact for
/// products of two shape functions on an undistorted element (S4: 2 x 2,
/// S6: 6 points; S3: 6 points, exact for the products of its corners'
/// functions with each other and with its bubble, not for the bubble's
/// square, of degree six), and with at least
/// as many points as nodes, so that the penalty holds every node's
/// rotation about the normal (S8: 3 x 3).
pub(super) fn full_rule(kind: ShellKind) -> &'static [([f64; 2], f64)] {
    match kind {
        ShellKind::S4 => &GAUSS_2X2,
        ShellKind::S8 => &GAUSS_3X3,
        ShellKind::S3 | ShellKind::S6 => &TRIANGLE_6,
    }
}

/// Two-point Gauss rule through the thickness, `t` in `[-1, 1]`: exact for
/// the quadratic variation of a flat shell's strain energy.
pub(super) const THICKNESS_RULE: [(f64, f64); 2] = [(-G2, 1.0), (G2, 1.0)];

/// The weights that carry values at the points of [`stress_rule`] to the
/// nodes: `value(node a) = sum_p weights[a][p] value(point p)`, by the
/// bilinear (S4, S8) or linear (S3, S6) polynomial through the points.
/// Exact for values that polynomial holds (a constant, a linear field).
pub(super) fn extrapolation(kind: ShellKind) -> [[f64; MAX_POINTS]; MAX_NODES] {
    let basis = |[r, s]: [f64; 2]| -> [f64; MAX_POINTS] {
        match kind {
            ShellKind::S4 | ShellKind::S8 => [1.0, r, s, r * s],
            ShellKind::S3 | ShellKind::S6 => [1.0, r, s, 0.0],
        }
    };
    let points = stress_rule(kind);
    let np = points.len();
    // P[p][q] = basis_q(point p); weights[a] = basis(node a) P^-1.
    let mut p = [[0.0; MAX_POINTS]; MAX_POINTS];
    for (row, (xi, _)) in p.iter_mut().zip(points) {
        *row = basis(*xi);
    }
    let inverse = invert(&p, np);
    let mut out = [[0.0; MAX_POINTS]; MAX_NODES];
    for (w, xi) in out.iter_mut().zip(node_coordinates(kind)) {
        let b = basis(*xi);
        for (q, wq) in w.iter_mut().enumerate().take(np) {
            *wq = (0..np).map(|k| b[k] * inverse[k][q]).sum();
        }
    }
    out
}

/// The inverse of the leading `n x n` block of `a` by Gauss-Jordan
/// elimination with partial pivoting (the small, well-conditioned
/// matrices of [`extrapolation`]).
fn invert(a: &[[f64; MAX_POINTS]; MAX_POINTS], n: usize) -> [[f64; MAX_POINTS]; MAX_POINTS] {
    let mut m = *a;
    let mut inv = [[0.0; MAX_POINTS]; MAX_POINTS];
    for (i, row) in inv.iter_mut().enumerate().take(n) {
        row[i] = 1.0;
    }
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))
            .unwrap_or(col);
        m.swap(col, pivot);
        inv.swap(col, pivot);
        let d = m[col][col];
        for k in 0..n {
            m[col][k] /= d;
            inv[col][k] /= d;
        }
        for row in 0..n {
            if row != col {
                let f = m[row][col];
                for k in 0..n {
                    m[row][k] -= f * m[col][k];
                    inv[row][k] -= f * inv[col][k];
                }
            }
        }
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_interpolate_the_nodes() {
        for kind in ShellKind::ALL {
            let (mut n, mut dn) = ([0.0; MAX_NODES], [[0.0; 2]; MAX_NODES]);
            // S3's bubble node carries rotations only: no shape function
            // of the surface belongs to it.
            let surface_nodes = match kind {
                ShellKind::S3 => 3,
                _ => kind.interpolation_nodes(),
            };
            for (a, xi) in node_coordinates(kind)[..surface_nodes].iter().enumerate() {
                evaluate(kind, *xi, &mut n, &mut dn);
                for (b, nb) in n.iter().enumerate().take(kind.interpolation_nodes()) {
                    let want = if a == b { 1.0 } else { 0.0 };
                    assert!((nb - want).abs() < 1e-15, "{kind:?} N{b} at node {a}");
                }
            }
            evaluate(kind, [0.2, 0.3], &mut n, &mut dn);
            let nn = kind.interpolation_nodes();
            assert!((n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-15);
            for d in 0..2 {
                assert!(dn[..nn].iter().map(|g| g[d]).sum::<f64>().abs() < 1e-15);
            }
        }
    }

    #[test]
    fn the_rotation_bubble_vanishes_on_the_edges_and_its_derivatives_hold() {
        for rs in [[0.5, 0.0], [0.5, 0.5], [0.0, 0.5], [0.3, 0.0], [0.0, 0.0]] {
            assert!(rotation_bubble(rs).0.abs() < 1e-15, "{rs:?}");
        }
        let (centre, slope) = rotation_bubble([1.0 / 3.0, 1.0 / 3.0]);
        assert!((centre - 1.0).abs() < 1e-15 && slope.iter().all(|d| d.abs() < 1e-14));
        let (x, h) = ([0.2, 0.3], 1e-6);
        let (_, d) = rotation_bubble(x);
        for k in 0..2 {
            let mut plus = x;
            let mut minus = x;
            plus[k] += h;
            minus[k] -= h;
            let fd = (rotation_bubble(plus).0 - rotation_bubble(minus).0) / (2.0 * h);
            assert!((fd - d[k]).abs() < 1e-8, "d/d{k}: {fd} against {}", d[k]);
        }
    }

    #[test]
    fn rules_integrate_what_they_promise() {
        // Area, and the product of two shape functions' highest terms: r^2
        // s^2 (S4) and degree 4 on the triangle (S6).
        let quad = |f: &dyn Fn(f64, f64) -> f64, rule: &[([f64; 2], f64)]| -> f64 {
            rule.iter().map(|([r, s], w)| w * f(*r, *s)).sum()
        };
        assert!((quad(&|r, s| r * r * s * s, &GAUSS_2X2) - 4.0 / 9.0).abs() < 1e-14);
        // int_T r^a s^b = a! b! / (a + b + 2)!.
        assert!((quad(&|_, _| 1.0, &TRIANGLE_6) - 0.5).abs() < 1e-14);
        assert!((quad(&|r, s| r * r * s * s, &TRIANGLE_6) - 4.0 / 720.0).abs() < 1e-14);
        assert!((quad(&|r, _| r.powi(4), &TRIANGLE_6) - 24.0 / 720.0).abs() < 1e-14);
        assert!((quad(&|r, s| r * s, &TRIANGLE_3) - 1.0 / 24.0).abs() < 1e-15);
    }

    #[test]
    fn extrapolation_reproduces_a_linear_field_at_the_nodes() {
        for kind in ShellKind::ALL {
            let field = |[r, s]: [f64; 2]| 3.0 - 2.0 * r + 0.5 * s;
            let w = extrapolation(kind);
            for (a, xi) in node_coordinates(kind).iter().enumerate() {
                let at: f64 = stress_rule(kind)
                    .iter()
                    .enumerate()
                    .map(|(p, (x, _))| w[a][p] * field(*x))
                    .sum();
                assert!((at - field(*xi)).abs() < 1e-13, "{kind:?} node {a}: {at}");
            }
        }
    }
}
