//! Tests of the solid elements: shape functions and rules here, and the
//! builders the other files share. Nodal stresses in `tests/stresses.rs`;
//! rigid-body motions, symmetry, the spectrum of K, mass and volume in
//! `tests/matrices.rs`; geometry checks in `tests/checks.rs`; patch tests in
//! `tests/patch.rs`, comparison with CalculiX in `tests/calculix.rs`, a
//! cantilever against beam theory in `tests/cantilever.rs`.

use super::quadrature::Rule;
use super::shape::{self, MAX_NODES};
use super::{Solid, SolidKind};
use crate::section::Material;
use faer::Mat;

mod anisotropic;
mod calculix;
mod cantilever;
mod checks;
mod matrices;
mod patch;
mod stresses;

pub(super) const E: f64 = 2.1e11;

pub(super) const NU: f64 = 0.3;

pub(super) const RHO: f64 = 7850.0;

pub(super) fn steel() -> Material {
    Material::new(E, NU, RHO).unwrap()
}

pub(super) fn solid(kind: SolidKind) -> Solid {
    Solid {
        id: 7,
        kind,
        nodes: (1..=kind.node_count() as u64).collect(),
        material: steel(),
    }
}

pub(super) use crate::mesh::Xorshift as Random;

/// `A x + b`: a general (sheared, stretched, rotated) affine map.
const AFFINE: [[f64; 3]; 3] = [[0.9, 0.2, -0.1], [0.15, 0.7, 0.12], [-0.05, 0.1, 0.6]];

const SHIFT: [f64; 3] = [0.3, -0.2, 1.1];

fn affine(x: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| SHIFT[i] + (0..3).map(|j| AFFINE[i][j] * x[j]).sum::<f64>())
}

/// A single distorted element: the reference element through [`affine`],
/// every node moved by up to `amplitude` (corners) and mid-edge nodes by up
/// to `amplitude / 2` off the midpoint of their (moved) corners, so
/// quadratic elements get curved edges. `amplitude = 0` gives an affine
/// image of the reference element.
pub(super) fn distorted(kind: SolidKind, seed: u64, amplitude: f64) -> Vec<[f64; 3]> {
    let mut rng = Random::new(seed);
    let reference = shape::node_coordinates(kind);
    let corners = match kind {
        SolidKind::C3D20 | SolidKind::C3D20R => 8,
        SolidKind::C3D10 => 4,
        SolidKind::C3D15 => 6,
        _ => kind.node_count(),
    };
    let mut x: Vec<[f64; 3]> = reference[..corners]
        .iter()
        .map(|r| {
            let d = rng.vec3();
            affine([0, 1, 2].map(|i| r[i] + amplitude * d[i]))
        })
        .collect();
    for r in &reference[corners..] {
        // The two corners this mid-edge node sits between.
        let ends: Vec<(usize, usize)> = (0..corners)
            .flat_map(|a| (a + 1..corners).map(move |b| (a, b)))
            .filter(|&(a, b)| (0..3).all(|i| 0.5 * (reference[a][i] + reference[b][i]) == r[i]))
            .collect();
        assert_eq!(ends.len(), 1, "{kind:?} mid-edge node {r:?}");
        let (a, b) = ends[0];
        let d = rng.vec3();
        let m = [0, 1, 2].map(|i| 0.5 * (x[a][i] + x[b][i]));
        x.push([0, 1, 2].map(|i| m[i] + 0.5 * amplitude * d[i]));
    }
    x
}

fn max_abs(a: &Mat<f64>) -> f64 {
    let mut m = 0.0_f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            m = m.max(a[(i, j)].abs());
        }
    }
    m
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `u = a + B x` at each point, 3 values per point.
fn linear_field(a: [f64; 3], b: [[f64; 3]; 3], coords: &[[f64; 3]]) -> Vec<f64> {
    coords
        .iter()
        .flat_map(|x| [0, 1, 2].map(|i| a[i] + (0..3).map(|j| b[i][j] * x[j]).sum::<f64>()))
        .collect()
}

/// Exact stress of the linear field `u = a + B x` (Voigt order).
fn exact_stress(b: [[f64; 3]; 3]) -> [f64; 6] {
    let lambda = E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let mu = E / (2.0 * (1.0 + NU));
    let tr = b[0][0] + b[1][1] + b[2][2];
    [
        lambda * tr + 2.0 * mu * b[0][0],
        lambda * tr + 2.0 * mu * b[1][1],
        lambda * tr + 2.0 * mu * b[2][2],
        mu * (b[0][1] + b[1][0]),
        mu * (b[1][2] + b[2][1]),
        mu * (b[2][0] + b[0][2]),
    ]
}

/// Asserts that every component of the stress `s` is the exact `sigma` to
/// 1e-10 of the largest component of `sigma`; `what` names the place.
fn assert_exact_stress(s: &[f64; 6], sigma: &[f64; 6], what: std::fmt::Arguments) {
    let s_max = sigma.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    for c in 0..6 {
        assert!(
            (s[c] - sigma[c]).abs() <= 1e-10 * s_max,
            "{what} component {c}: {} vs {}",
            s[c],
            sigma[c]
        );
    }
}

const GRADIENT: [[f64; 3]; 3] = [
    [1.2e-3, -0.4e-3, 0.7e-3],
    [0.3e-3, -0.9e-3, 0.25e-3],
    [-0.6e-3, 0.5e-3, 0.8e-3],
];

const OFFSET: [f64; 3] = [1e-3, -2e-3, 0.5e-3];

// ---------------------------------------------------------------------------
// Shape functions and rules

#[test]
fn shape_functions_interpolate_nodes_and_sum_to_one() {
    for kind in SolidKind::ALL {
        let nn = kind.node_count();
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        for (b, xb) in shape::node_coordinates(kind).iter().enumerate() {
            shape::evaluate(kind, *xb, &mut n, &mut dn);
            for (a, na) in n[..nn].iter().enumerate() {
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((na - expected).abs() < 1e-15, "{kind:?} N{a} at node {b}");
            }
        }
        let mut rng = Random::new(3);
        for _ in 0..5 {
            let xi = interior_point(kind, &mut rng);
            shape::evaluate(kind, xi, &mut n, &mut dn);
            assert!(
                (n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-14,
                "{kind:?}"
            );
            for j in 0..3 {
                let s: f64 = dn[..nn].iter().map(|d| d[j]).sum();
                assert!(s.abs() < 1e-14, "{kind:?} sum of dN/dxi_{j} = {s}");
            }
        }
    }
}

#[test]
fn shape_derivatives_match_finite_differences() {
    let h = 1e-6;
    for kind in SolidKind::ALL {
        let nn = kind.node_count();
        let mut rng = Random::new(11);
        let xi = interior_point(kind, &mut rng);
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        shape::evaluate(kind, xi, &mut n, &mut dn);
        for j in 0..3 {
            let (mut np, mut nm) = ([0.0; MAX_NODES], [0.0; MAX_NODES]);
            let mut scratch = [[0.0; 3]; MAX_NODES];
            let mut xp = xi;
            xp[j] += h;
            shape::evaluate(kind, xp, &mut np, &mut scratch);
            let mut xm = xi;
            xm[j] -= h;
            shape::evaluate(kind, xm, &mut nm, &mut scratch);
            for a in 0..nn {
                let fd = (np[a] - nm[a]) / (2.0 * h);
                assert!(
                    (fd - dn[a][j]).abs() < 1e-8,
                    "{kind:?} dN{a}/dxi{j}: {} vs {fd}",
                    dn[a][j]
                );
            }
        }
    }
}

fn interior_point(kind: SolidKind, rng: &mut Random) -> [f64; 3] {
    let r = rng.vec3();
    match kind {
        SolidKind::C3D10 | SolidKind::C3D4 => r.map(|v| 0.15 + 0.1 * v),
        SolidKind::C3D6 | SolidKind::C3D15 => [0.3 + 0.1 * r[0], 0.2 + 0.1 * r[1], 0.8 * r[2]],
        _ => r.map(|v| 0.9 * v),
    }
}

#[test]
fn rules_integrate_monomials_of_their_degree() {
    // Integral over the reference element of a monomial x^p y^q z^r.
    fn cube(p: i32) -> f64 {
        if p % 2 == 1 {
            0.0
        } else {
            2.0 / (p as f64 + 1.0)
        }
    }
    fn fact(n: i32) -> f64 {
        (1..=n).map(f64::from).product()
    }
    let exact = |rule: Rule, e: [i32; 3]| match rule {
        Rule::Hex2 | Rule::Hex3 => cube(e[0]) * cube(e[1]) * cube(e[2]),
        Rule::Tet1 | Rule::Tet4 => {
            fact(e[0]) * fact(e[1]) * fact(e[2]) / fact(e[0] + e[1] + e[2] + 3)
        }
        Rule::Wedge2 | Rule::Wedge9 => fact(e[0]) * fact(e[1]) / fact(e[0] + e[1] + 2) * cube(e[2]),
    };
    // (rule, degree per variable for the cube / total degree otherwise).
    let cases = [
        (Rule::Hex2, 3),
        (Rule::Hex3, 5),
        (Rule::Tet1, 1),
        (Rule::Tet4, 2),
        (Rule::Wedge2, 1),
        (Rule::Wedge9, 2),
    ];
    for (rule, degree) in cases {
        for p in 0..=5 {
            for q in 0..=5 {
                for r in 0..=5 {
                    let ok = match rule {
                        Rule::Hex2 | Rule::Hex3 => p <= degree && q <= degree && r <= degree,
                        Rule::Wedge2 => p + q <= degree && r <= 3,
                        Rule::Wedge9 => p + q <= degree && r <= 5,
                        _ => p + q + r <= degree,
                    };
                    if !ok {
                        continue;
                    }
                    let sum: f64 = rule
                        .points()
                        .iter()
                        .zip(rule.weights())
                        .map(|(x, w)| w * x[0].powi(p) * x[1].powi(q) * x[2].powi(r))
                        .sum();
                    let e = exact(rule, [p, q, r]);
                    assert!(
                        (sum - e).abs() < 1e-14,
                        "{rule:?} x^{p} y^{q} z^{r}: {sum} vs {e}"
                    );
                }
            }
        }
    }
}

#[test]
fn interpolation_through_the_points_reproduces_its_polynomials() {
    // The interpolant of a function of the rule's polynomial space is the
    // function itself: check at the nodes with values sampled at the points.
    let f = |rule: Rule, x: [f64; 3]| match rule {
        Rule::Hex2 => 1.0 + 2.0 * x[0] - x[1] + 0.5 * x[2] + 0.3 * x[0] * x[1] * x[2],
        Rule::Hex3 => 1.0 + x[0] * x[0] * x[1] - 0.7 * x[2] * x[2] * x[0] * x[1] * x[1],
        Rule::Tet1 => 2.5,
        Rule::Tet4 => 1.0 + 2.0 * x[0] - 3.0 * x[1] + 0.5 * x[2],
        Rule::Wedge2 => 1.0 - 0.4 * x[2],
        Rule::Wedge9 => (1.0 + 2.0 * x[0] - 0.5 * x[1]) * (1.0 - 0.4 * x[2] + 0.3 * x[2] * x[2]),
    };
    for kind in SolidKind::ALL {
        let rule = kind.stiffness_rule();
        let values: Vec<f64> = rule.points().iter().map(|x| f(rule, *x)).collect();
        let mut c = [0.0; 27];
        for xi in shape::node_coordinates(kind) {
            rule.interpolation_weights(*xi, &mut c);
            let got: f64 = c.iter().zip(&values).map(|(c, v)| c * v).sum();
            assert!((got - f(rule, *xi)).abs() < 1e-13, "{kind:?} at {xi:?}");
        }
    }
}

#[test]
fn mass_rule_is_the_stiffness_rule_as_in_calculix() {
    for kind in SolidKind::ALL {
        assert_eq!(kind.mass_rule(), kind.stiffness_rule(), "{kind:?}");
    }
    assert_eq!(SolidKind::C3D20R.stiffness_rule(), Rule::Hex2);
    assert_eq!(SolidKind::C3D4.stiffness_rule(), Rule::Tet1);
}

// ---------------------------------------------------------------------------
// Meshes

pub(super) use super::topology::HEX20_EDGES as HEX_EDGES;
