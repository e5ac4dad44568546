//! Anisotropic linear elasticity of solids: a 6x6 elasticity matrix `C` in
//! material axes and the orientation that turns those axes into global
//! ones (CalculiX `*ELASTIC, TYPE=ORTHO | ENGINEERING CONSTANTS | ANISO`
//! and `*ORIENTATION`).
//!
//! Voigt order `[11, 22, 33, 12, 23, 31]` with engineering shear strains
//! (`gamma_12 = 2 eps_12`), the order of the solid elements: then every
//! entry of `C` is the tensor component it stands for (`C[3][3] = D1212`,
//! `C[0][3] = D1112`), because `sigma_11 = C_1112 eps_12 + C_1121 eps_21 =
//! C_1112 gamma_12`.
//!
//! Rotation: with `R` the matrix whose columns are the local axes in global
//! components (CalculiX `transformatrix`), the global tensor is
//! `C'_ijkl = R_ia R_jb R_kc R_ld C_abcd`, evaluated by four one-index
//! contractions of the full tensor.

// Tensor index loops read as the equations they implement.
#![allow(clippy::needless_range_loop)]

use crate::FemError;
use serde::{Deserialize, Serialize};

/// A 6x6 elasticity matrix in Voigt order `[11, 22, 33, 12, 23, 31]`,
/// engineering shear strains (Pa).
pub type Voigt = [[f64; 6]; 6];

/// The local axes of an orientation (CalculiX `*ORIENTATION`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Orientation {
    /// Local 1 along `a`, local 2 in the plane of `a` and `b` (towards `b`),
    /// local 3 = 1 x 2; the same at every point.
    Rectangular { a: [f64; 3], b: [f64; 3] },
    /// The axis runs from point `a` to point `b`: local 3 along it, local 1
    /// radial (from the axis to the point), local 2 = 3 x 1 (tangential).
    Cylindrical { a: [f64; 3], b: [f64; 3] },
}

impl Orientation {
    /// A rectangular system, checked: `a` non-zero, `b` not parallel to `a`.
    pub fn rectangular(a: [f64; 3], b: [f64; 3]) -> Result<Self, FemError> {
        let o = Orientation::Rectangular { a, b };
        o.axes_at([0.0; 3])?;
        Ok(o)
    }

    /// A cylindrical system, checked: `a` and `b` distinct.
    pub fn cylindrical(a: [f64; 3], b: [f64; 3]) -> Result<Self, FemError> {
        if norm(sub(b, a)) == 0.0 || !norm(sub(b, a)).is_finite() {
            return Err(invalid("cylindrical orientation: points a and b coincide"));
        }
        Ok(Orientation::Cylindrical { a, b })
    }

    /// The rectangular system turned by `angle` (rad) about its local axis
    /// `axis` (0, 1 or 2), as CalculiX's optional second `*ORIENTATION`
    /// line does (right-hand rule). Cylindrical systems do not take it.
    pub fn rotated(&self, axis: usize, angle: f64) -> Result<Self, FemError> {
        let Orientation::Rectangular { .. } = self else {
            return Err(invalid(
                "an additional rotation is only allowed for rectangular orientations",
            ));
        };
        if axis > 2 {
            return Err(invalid("the rotation axis must be 1, 2 or 3"));
        }
        let r = self.axes_at([0.0; 3])?;
        let p = [r[0][axis], r[1][axis], r[2][axis]];
        let (s, c) = angle.sin_cos();
        let rot = [
            [
                c + (1.0 - c) * p[0] * p[0],
                -s * p[2] + (1.0 - c) * p[0] * p[1],
                s * p[1] + (1.0 - c) * p[0] * p[2],
            ],
            [
                s * p[2] + (1.0 - c) * p[1] * p[0],
                c + (1.0 - c) * p[1] * p[1],
                -s * p[0] + (1.0 - c) * p[1] * p[2],
            ],
            [
                -s * p[1] + (1.0 - c) * p[2] * p[0],
                s * p[0] + (1.0 - c) * p[2] * p[1],
                c + (1.0 - c) * p[2] * p[2],
            ],
        ];
        let turn = |col: usize| -> [f64; 3] {
            std::array::from_fn(|i| (0..3).map(|j| rot[i][j] * r[j][col]).sum())
        };
        Orientation::rectangular(turn(0), turn(1))
    }

    /// `R` at global point `x`: column `k` is local axis `k` in global
    /// components (CalculiX `transformatrix`). Fails where the axes are not
    /// defined: a zero or parallel `a`, `b`; a point on a cylinder's axis.
    pub fn axes_at(&self, x: [f64; 3]) -> Result<[[f64; 3]; 3], FemError> {
        let (e1, e2, e3) = match *self {
            Orientation::Rectangular { a, b } => {
                let e1 = unit(a).ok_or_else(|| invalid("orientation: point a is at the origin"))?;
                let e2 = sub(b, scale(e1, dot(e1, b)));
                if norm(e2).is_nan() || norm(e2) <= 1e-10 * norm(b) {
                    return Err(invalid("orientation: points a and b are parallel"));
                }
                let e2 = scale(e2, 1.0 / norm(e2));
                (e1, e2, cross(e1, e2))
            }
            Orientation::Cylindrical { a, b } => {
                let e3 = unit(sub(b, a))
                    .ok_or_else(|| invalid("cylindrical orientation: points a and b coincide"))?;
                let r = sub(x, a);
                let radial = sub(r, scale(e3, dot(r, e3)));
                if norm(radial) < 1e-10 {
                    return Err(invalid(format!(
                        "cylindrical orientation: point {x:?} lies on the axis \
                         (the radial direction is not defined)"
                    )));
                }
                let e1 = scale(radial, 1.0 / norm(radial));
                (e1, cross(e3, e1), e3)
            }
        };
        Ok([
            [e1[0], e2[0], e3[0]],
            [e1[1], e2[1], e3[1]],
            [e1[2], e2[2], e3[2]],
        ])
    }

    /// True if the axes are the same at every point.
    pub fn is_uniform(&self) -> bool {
        matches!(self, Orientation::Rectangular { .. })
    }
}

/// Anisotropic elasticity of a solid: `C` in material axes and the
/// orientation of those axes (global axes if none).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Anisotropy {
    /// `C` in material axes (Pa), symmetric and positive definite.
    pub stiffness: Voigt,
    /// The material axes; `None`: the global axes.
    pub orientation: Option<Orientation>,
}

/// The symmetry class of an elasticity matrix, for summaries.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum SymmetryClass {
    /// No coupling between normal and shear terms or between shears.
    Orthotropic,
    /// Anything else.
    Anisotropic,
}

impl Anisotropy {
    /// `C` in material axes, checked: finite, symmetric (to `1e-12` of its
    /// largest entry) and positive definite (Cholesky).
    pub fn new(stiffness: Voigt, orientation: Option<Orientation>) -> Result<Self, FemError> {
        let max = stiffness
            .iter()
            .flatten()
            .fold(0.0_f64, |m, c| m.max(c.abs()));
        if !max.is_finite() || stiffness.iter().flatten().any(|c| !c.is_finite()) {
            return Err(invalid("elasticity matrix: entries must be finite"));
        }
        for i in 0..6 {
            for j in 0..i {
                if (stiffness[i][j] - stiffness[j][i]).abs() > 1e-12 * max {
                    return Err(invalid("elasticity matrix is not symmetric"));
                }
            }
        }
        if let Some(k) = cholesky_failure(&stiffness) {
            return Err(invalid(format!(
                "elasticity matrix is not positive definite (pivot {} of 6 is not positive): \
                 the material would be unstable",
                k + 1
            )));
        }
        Ok(Self {
            stiffness,
            orientation,
        })
    }

    /// Orthotropic `C` from the engineering constants `E1, E2, E3` (Pa),
    /// `nu12, nu13, nu23` (`nu_ij = -eps_j / eps_i` under stress along `i`)
    /// and `G12, G13, G23` (Pa): the inverse of the compliance with
    /// `S_ij = -nu_ij / E_i`.
    pub fn engineering(
        e: [f64; 3],
        nu12: f64,
        nu13: f64,
        nu23: f64,
        g12: f64,
        g13: f64,
        g23: f64,
    ) -> Result<Voigt, FemError> {
        for (what, v) in [
            ("E1", e[0]),
            ("E2", e[1]),
            ("E3", e[2]),
            ("G12", g12),
            ("G13", g13),
            ("G23", g23),
        ] {
            crate::require_positive(what, v)?;
        }
        let s = [
            [1.0 / e[0], -nu12 / e[0], -nu13 / e[0]],
            [-nu12 / e[0], 1.0 / e[1], -nu23 / e[1]],
            [-nu13 / e[0], -nu23 / e[1], 1.0 / e[2]],
        ];
        let det = s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1])
            - s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0])
            + s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0]);
        if det.is_nan() || det <= 0.0 {
            return Err(invalid(
                "engineering constants: the Poisson's ratios make the compliance \
                 not positive definite (the material would be unstable)",
            ));
        }
        let cof = |i: usize, j: usize| {
            let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
            let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
            s[r0][c0] * s[r1][c1] - s[r0][c1] * s[r1][c0]
        };
        let mut c = [[0.0; 6]; 6];
        for (i, row) in c.iter_mut().enumerate().take(3) {
            for (j, cij) in row.iter_mut().enumerate().take(3) {
                *cij = cof(j, i) / det;
            }
        }
        c[3][3] = g12;
        c[4][4] = g23;
        c[5][5] = g13;
        Ok(c)
    }

    /// `C` in global axes at global point `x`.
    pub fn global_at(&self, x: [f64; 3]) -> Result<Voigt, FemError> {
        match &self.orientation {
            None => Ok(self.stiffness),
            Some(o) => Ok(rotate(&self.stiffness, &o.axes_at(x)?)),
        }
    }

    /// Orthotropic if the normal-shear and shear-shear couplings are zero.
    pub fn symmetry_class(&self) -> SymmetryClass {
        let c = &self.stiffness;
        let coupled = (0..6)
            .flat_map(|i| (0..6).map(move |j| (i, j)))
            .any(|(i, j)| i != j && (i >= 3 || j >= 3) && c[i][j] != 0.0);
        if coupled {
            SymmetryClass::Anisotropic
        } else {
            SymmetryClass::Orthotropic
        }
    }
}

/// The Voigt index of tensor index pair `(i, j)` in `[11, 22, 33, 12, 23, 31]`.
const fn voigt_index(i: usize, j: usize) -> usize {
    match (i, j) {
        (0, 0) => 0,
        (1, 1) => 1,
        (2, 2) => 2,
        (0, 1) | (1, 0) => 3,
        (1, 2) | (2, 1) => 4,
        _ => 5,
    }
}

/// `C` rotated into the axes of `r` (columns: local axes in global
/// components): `C'_ijkl = R_ia R_jb R_kc R_ld C_abcd` (module docs).
pub fn rotate(c: &Voigt, r: &[[f64; 3]; 3]) -> Voigt {
    let mut t = [0.0; 81];
    let at = |i: usize, j: usize, k: usize, l: usize| ((i * 3 + j) * 3 + k) * 3 + l;
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    t[at(i, j, k, l)] = c[voigt_index(i, j)][voigt_index(k, l)];
                }
            }
        }
    }
    // Contract one index at a time: position `p` of the four.
    for p in 0..4 {
        let mut u = [0.0; 81];
        for (idx, ui) in u.iter_mut().enumerate() {
            let mut digits = [idx / 27, (idx / 9) % 3, (idx / 3) % 3, idx % 3];
            let target = digits[p];
            let mut sum = 0.0;
            for a in 0..3 {
                digits[p] = a;
                sum += r[target][a] * t[at(digits[0], digits[1], digits[2], digits[3])];
            }
            *ui = sum;
        }
        t = u;
    }
    const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
    std::array::from_fn(|m| {
        std::array::from_fn(|n| {
            let ((i, j), (k, l)) = (PAIRS[m], PAIRS[n]);
            t[at(i, j, k, l)]
        })
    })
}

/// The first pivot at which the Cholesky factorisation of `c` fails.
fn cholesky_failure(c: &Voigt) -> Option<usize> {
    let mut l = [[0.0; 6]; 6];
    for j in 0..6 {
        let d = c[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return Some(j);
        }
        l[j][j] = d.sqrt();
        for i in j + 1..6 {
            l[i][j] = (c[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    None
}

fn invalid(reason: impl Into<String>) -> FemError {
    FemError::InvalidMaterial(reason.into())
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    a.map(|v| v * s)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`, or `None` for a (numerically) zero vector.
fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 1e-300 && n.is_finite()).then(|| scale(a, 1.0 / n))
}

#[cfg(test)]
pub(crate) mod tests;
