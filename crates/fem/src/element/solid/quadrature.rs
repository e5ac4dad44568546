//! Integration rules of the solid elements, as CalculiX 2.20 uses them
//! (`gauss.f`, chosen per element type in `e_c3d.f`), and the polynomial
//! through each rule's points that carries integration-point values to the
//! nodes.
//!
//! | rule | CalculiX name | points (natural coordinates) | weights |
//! | --- | --- | --- | --- |
//! | [`Rule::Hex2`] | `gauss3d2` | `(±1/√3)^3`, x fastest, then y, z | 1 |
//! | [`Rule::Hex3`] | `gauss3d3` | `{-√0.6, 0, √0.6}^3`, x fastest | products of 5/9, 8/9 |
//! | [`Rule::Tet1`] | `gauss3d4` | `(1/4, 1/4, 1/4)` | 1/6 |
//! | [`Rule::Tet4`] | `gauss3d5` | `(a,a,a), (b,a,a), (a,b,a), (a,a,b)`, `a = (5-√5)/20`, `b = (5+3√5)/20` | 1/24 |
//! | [`Rule::Wedge2`] | `gauss3d7` | `(1/3, 1/3, ∓1/√3)` | 1/2 |
//! | [`Rule::Wedge9`] | `gauss3d8` | `(1/6, 1/6), (2/3, 1/6), (1/6, 2/3)` times `zeta` in `{-√0.6, 0, √0.6}`, triangle fastest | 1/6 times 5/9, 8/9 |
//!
//! CalculiX writes its constants with 15 significant digits; the values
//! here are the exact ones rounded to `f64`, which differ by a few units in
//! the 15th digit.

/// `1/√3`, the 2-point Gauss abscissa.
const G2: f64 = 0.577_350_269_189_625_8;
/// `√(3/5)`, the 3-point Gauss abscissa.
const G3: f64 = 0.774_596_669_241_483_4;
/// 4-point tetrahedron rule: `(5 - √5) / 20`.
const TET_A: f64 = 0.138_196_601_125_010_5;
/// 4-point tetrahedron rule: `(5 + 3√5) / 20`.
const TET_B: f64 = 0.585_410_196_624_968_5;

/// An integration rule over a reference element.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Rule {
    /// 2x2x2 Gauss over the cube `[-1, 1]^3`.
    Hex2,
    /// 3x3x3 Gauss over the cube.
    Hex3,
    /// Centroid of the tetrahedron `xi, eta, zeta >= 0, xi + eta + zeta <= 1`.
    Tet1,
    /// 4-point, degree-2 rule over the tetrahedron.
    Tet4,
    /// Triangle centroid times 2-point Gauss in `zeta`, over the wedge
    /// `xi, eta >= 0, xi + eta <= 1, -1 <= zeta <= 1`.
    Wedge2,
    /// 3-point triangle rule (degree 2) times 3-point Gauss in `zeta`.
    Wedge9,
}

const HEX2_POINTS: [[f64; 3]; 8] = tensor_points([-G2, G2]);
const HEX2_WEIGHTS: [f64; 8] = tensor_weights([1.0, 1.0]);
const HEX3_POINTS: [[f64; 3]; 27] = tensor_points([-G3, 0.0, G3]);
const HEX3_WEIGHTS: [f64; 27] = tensor_weights([5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0]);
const TET1_POINTS: [[f64; 3]; 1] = [[0.25, 0.25, 0.25]];
const TET1_WEIGHTS: [f64; 1] = [1.0 / 6.0];
const TET4_POINTS: [[f64; 3]; 4] = [
    [TET_A, TET_A, TET_A],
    [TET_B, TET_A, TET_A],
    [TET_A, TET_B, TET_A],
    [TET_A, TET_A, TET_B],
];
const TET4_WEIGHTS: [f64; 4] = [1.0 / 24.0; 4];
const WEDGE2_POINTS: [[f64; 3]; 2] = [[1.0 / 3.0, 1.0 / 3.0, -G2], [1.0 / 3.0, 1.0 / 3.0, G2]];
const WEDGE2_WEIGHTS: [f64; 2] = [0.5, 0.5];
/// The 3-point triangle rule's points: `t_k = 2/3` at point `k`, `1/6`
/// at the others (`t = (1 - xi - eta, xi, eta)`).
const TRI3: [[f64; 2]; 3] = [
    [1.0 / 6.0, 1.0 / 6.0],
    [2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0],
];
const WEDGE9_POINTS: [[f64; 3]; 9] = wedge_points([-G3, 0.0, G3]);
const WEDGE9_WEIGHTS: [f64; 9] = {
    let w = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let mut out = [0.0; 9];
    let mut p = 0;
    while p < 9 {
        out[p] = w[p / 3] / 6.0;
        p += 1;
    }
    out
};

/// The triangle points of [`TRI3`] at each `zeta` of `z`, the triangle
/// running fastest.
const fn wedge_points(z: [f64; 3]) -> [[f64; 3]; 9] {
    let mut out = [[0.0; 3]; 9];
    let mut p = 0;
    while p < 9 {
        out[p] = [TRI3[p % 3][0], TRI3[p % 3][1], z[p / 3]];
        p += 1;
    }
    out
}

/// Tensor-product points of a 1D rule, x running fastest (CalculiX order).
const fn tensor_points<const N: usize, const M: usize>(x: [f64; N]) -> [[f64; 3]; M] {
    let mut out = [[0.0; 3]; M];
    let mut p = 0;
    while p < M {
        out[p] = [x[p % N], x[(p / N) % N], x[p / (N * N)]];
        p += 1;
    }
    out
}

/// Tensor-product weights of a 1D rule, in the order of [`tensor_points`].
const fn tensor_weights<const N: usize, const M: usize>(w: [f64; N]) -> [f64; M] {
    let mut out = [0.0; M];
    let mut p = 0;
    while p < M {
        out[p] = w[p % N] * w[(p / N) % N] * w[p / (N * N)];
        p += 1;
    }
    out
}

impl Rule {
    /// The integration points in natural coordinates.
    pub(super) fn points(self) -> &'static [[f64; 3]] {
        match self {
            Rule::Hex2 => &HEX2_POINTS,
            Rule::Hex3 => &HEX3_POINTS,
            Rule::Tet1 => &TET1_POINTS,
            Rule::Tet4 => &TET4_POINTS,
            Rule::Wedge2 => &WEDGE2_POINTS,
            Rule::Wedge9 => &WEDGE9_POINTS,
        }
    }

    /// The weights, in the order of [`Rule::points`].
    pub(super) fn weights(self) -> &'static [f64] {
        match self {
            Rule::Hex2 => &HEX2_WEIGHTS,
            Rule::Hex3 => &HEX3_WEIGHTS,
            Rule::Tet1 => &TET1_WEIGHTS,
            Rule::Tet4 => &TET4_WEIGHTS,
            Rule::Wedge2 => &WEDGE2_WEIGHTS,
            Rule::Wedge9 => &WEDGE9_WEIGHTS,
        }
    }

    /// Number of points.
    pub(super) fn len(self) -> usize {
        self.weights().len()
    }

    /// Weights `c_p` of the interpolating polynomial through the rule's
    /// points, evaluated at natural coordinates `xi`: a value sampled at the
    /// points as `f_p` is `sum_p c_p f_p` at `xi`. The polynomial is
    /// trilinear (2x2x2), triquadratic (3x3x3), linear (4-point tetrahedron;
    /// linear in `zeta` for the 2-point wedge; linear in the triangle and
    /// quadratic in `zeta` for the 9-point wedge) or constant (1 point); the
    /// weights sum to one, so a constant is carried exactly.
    ///
    /// `out` must hold at least [`Rule::len`] values.
    pub(super) fn interpolation_weights(self, xi: [f64; 3], out: &mut [f64]) {
        match self {
            Rule::Hex2 => {
                let l = xi.map(|x| {
                    let s = x / G2;
                    [0.5 * (1.0 - s), 0.5 * (1.0 + s)]
                });
                for (p, c) in out.iter_mut().take(8).enumerate() {
                    *c = l[0][p % 2] * l[1][(p / 2) % 2] * l[2][p / 4];
                }
            }
            Rule::Hex3 => {
                let a2 = G3 * G3;
                let l = xi.map(|x| {
                    [
                        x * (x - G3) / (2.0 * a2),
                        (a2 - x * x) / a2,
                        x * (x + G3) / (2.0 * a2),
                    ]
                });
                for (p, c) in out.iter_mut().take(27).enumerate() {
                    *c = l[0][p % 3] * l[1][(p / 3) % 3] * l[2][p / 9];
                }
            }
            Rule::Tet1 => out[0] = 1.0,
            Rule::Tet4 => {
                // Point k has barycentric coordinate b in slot k and a in the
                // others; the linear interpolant is
                // f(l) = sum_k (l_k - a) / (b - a) f_k.
                let bary = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
                for (c, l) in out.iter_mut().zip(bary) {
                    *c = (l - TET_A) / (TET_B - TET_A);
                }
            }
            Rule::Wedge2 => {
                let s = xi[2] / G2;
                out[0] = 0.5 * (1.0 - s);
                out[1] = 0.5 * (1.0 + s);
            }
            Rule::Wedge9 => {
                // In the triangle, point k has t_k = 2/3 and 1/6 in the
                // other slots: f(t) = sum_k (t_k - 1/6) / (1/2) f_k.
                let t = [1.0 - xi[0] - xi[1], xi[0], xi[1]];
                let tri = t.map(|tk| (tk - 1.0 / 6.0) / 0.5);
                let (x, a2) = (xi[2], G3 * G3);
                let z = [
                    x * (x - G3) / (2.0 * a2),
                    (a2 - x * x) / a2,
                    x * (x + G3) / (2.0 * a2),
                ];
                for (p, c) in out.iter_mut().take(9).enumerate() {
                    *c = tri[p % 3] * z[p / 3];
                }
            }
        }
    }
}
