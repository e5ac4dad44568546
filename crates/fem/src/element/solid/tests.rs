//! Tests of the solid elements: shape functions and rules, nodal stresses,
//! rigid-body motions, mass and volume, the spectrum of K, geometry checks.
//! Patch tests in `tests/patch.rs`, comparison with CalculiX in
//! `tests/calculix.rs`, a cantilever against beam theory in
//! `tests/cantilever.rs`.

mod calculix;
mod cantilever;
mod patch;

use super::quadrature::Rule;
use super::shape::{self, MAX_NODES};
use super::{Solid, SolidKind};
use crate::element::mat_vec;
use crate::section::Material;
use crate::FemError;
use faer::{Mat, Side};

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

/// Deterministic pseudo-random numbers in `[-1, 1)` (xorshift).
pub(super) struct Random(u64);

impl Random {
    pub(super) fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub(super) fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn vec3(&mut self) -> [f64; 3] {
        [self.next(), self.next(), self.next()]
    }
}

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
        SolidKind::C3D6 => [0.3 + 0.1 * r[0], 0.2 + 0.1 * r[1], 0.8 * r[2]],
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
        Rule::Wedge2 => fact(e[0]) * fact(e[1]) / fact(e[0] + e[1] + 2) * cube(e[2]),
    };
    // (rule, degree per variable for the cube / total degree otherwise).
    let cases = [
        (Rule::Hex2, 3),
        (Rule::Hex3, 5),
        (Rule::Tet1, 1),
        (Rule::Tet4, 2),
        (Rule::Wedge2, 1),
    ];
    for (rule, degree) in cases {
        for p in 0..=5 {
            for q in 0..=5 {
                for r in 0..=5 {
                    let ok = match rule {
                        Rule::Hex2 | Rule::Hex3 => p <= degree && q <= degree && r <= degree,
                        Rule::Wedge2 => p + q <= degree && r <= 3,
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

/// Hexahedron corners in Abaqus order as bit offsets `x + 2 y + 4 z`.
const HEX_CORNERS: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];
/// Mid-edge nodes of the 20-node hexahedron: the corners (0-based) they join.
const HEX_EDGES: [(usize, usize); 12] = [
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

// ---------------------------------------------------------------------------
// Nodal stresses

#[test]
fn nodal_stresses_of_a_linear_field_are_exact_on_distorted_elements() {
    let sigma = exact_stress(GRADIENT);
    let s_max = sigma.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    for kind in SolidKind::ALL {
        let x = distorted(kind, 17, 0.15);
        let u = linear_field(OFFSET, GRADIENT, &x);
        let stresses = solid(kind).nodal_stresses(&x, &u).unwrap();
        assert_eq!(stresses.len(), kind.node_count());
        for (a, s) in stresses.iter().enumerate() {
            for c in 0..6 {
                assert!(
                    (s[c] - sigma[c]).abs() <= 1e-10 * s_max,
                    "{kind:?} node {a} component {c}: {} vs {}",
                    s[c],
                    sigma[c]
                );
            }
        }
    }
}

#[test]
fn nodal_stresses_extrapolate_a_linear_stress_field_in_a_c3d8() {
    // u = (c x y, 0, 0) on the reference cube: sxx = (lambda + 2 mu) c y and
    // sxy = mu c x, linear, which the trilinear extrapolation from the Gauss
    // points reproduces at the nodes.
    let c = 1e-3;
    let x: Vec<[f64; 3]> = shape::node_coordinates(SolidKind::C3D8).to_vec();
    let u: Vec<f64> = x.iter().flat_map(|p| [c * p[0] * p[1], 0.0, 0.0]).collect();
    let s = solid(SolidKind::C3D8).nodal_stresses(&x, &u).unwrap();
    let lambda = E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let mu = E / (2.0 * (1.0 + NU));
    for (p, sp) in x.iter().zip(&s) {
        let sxx = (lambda + 2.0 * mu) * c * p[1];
        let sxy = mu * c * p[0];
        assert!(
            (sp[0] - sxx).abs() < 1e-9 * sxx.abs(),
            "{p:?}: {} vs {sxx}",
            sp[0]
        );
        assert!(
            (sp[3] - sxy).abs() < 1e-9 * sxy.abs(),
            "{p:?}: {} vs {sxy}",
            sp[3]
        );
    }
}

#[test]
fn nodal_stresses_reject_a_wrong_displacement_length() {
    let x = distorted(SolidKind::C3D8, 1, 0.1);
    let e = solid(SolidKind::C3D8)
        .nodal_stresses(&x, &[0.0; 23])
        .unwrap_err();
    assert!(e.to_string().contains("24 displacement values"), "{e}");
}

// ---------------------------------------------------------------------------
// Rigid-body motions, symmetry, spectrum

/// The six rigid-body motions (translations, small rotations about the
/// origin) at the given points.
pub(super) fn rigid_modes(coords: &[[f64; 3]]) -> Vec<Vec<f64>> {
    let mut modes = Vec::new();
    for d in 0..3 {
        let mut t = [0.0; 3];
        t[d] = 1.0;
        modes.push(coords.iter().flat_map(|_| t).collect());
    }
    for d in 0..3 {
        let mut w = [0.0; 3];
        w[d] = 1.0;
        modes.push(
            coords
                .iter()
                .flat_map(|x| {
                    [
                        w[1] * x[2] - w[2] * x[1],
                        w[2] * x[0] - w[0] * x[2],
                        w[0] * x[1] - w[1] * x[0],
                    ]
                })
                .collect(),
        );
    }
    modes
}

#[test]
fn rigid_body_motions_have_no_strain_energy() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 23, 0.15);
        let em = solid(kind).matrices(&x).unwrap();
        let k_max = max_abs(&em.stiffness);
        for (r, u) in rigid_modes(&x).iter().enumerate() {
            let u_max = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let f = mat_vec(&em.stiffness, u);
            let f_max = f.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(
                f_max <= 1e-12 * k_max * u_max,
                "{kind:?} rigid mode {r}: |K u| = {f_max:e}"
            );
            let energy = dot(u, &f);
            assert!(
                energy.abs() <= 1e-12 * k_max * dot(u, u),
                "{kind:?} rigid mode {r}: u^T K u = {energy:e}"
            );
        }
    }
}

#[test]
fn matrices_are_exactly_symmetric() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 29, 0.15);
        let em = solid(kind).matrices(&x).unwrap();
        let nd = 3 * kind.node_count();
        assert_eq!(em.dofs.len(), nd);
        assert_eq!((em.stiffness.nrows(), em.stiffness.ncols()), (nd, nd));
        assert_eq!((em.mass.nrows(), em.mass.ncols()), (nd, nd));
        for i in 0..nd {
            for j in 0..nd {
                assert_eq!(em.stiffness[(i, j)], em.stiffness[(j, i)], "{kind:?} K");
                assert_eq!(em.mass[(i, j)], em.mass[(j, i)], "{kind:?} M");
            }
        }
    }
}

/// Eigenvalues of a dense symmetric matrix, ascending.
fn eigenvalues(a: &Mat<f64>) -> Vec<f64> {
    a.self_adjoint_eigenvalues(Side::Lower).unwrap()
}

#[test]
fn stiffness_is_positive_semidefinite_with_six_rigid_modes() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 31, 0.15);
        let em = solid(kind).matrices(&x).unwrap();
        let lam = eigenvalues(&em.stiffness);
        let top = *lam.last().unwrap();
        let tol = 1e-10 * top;
        assert!(lam[0] > -tol, "{kind:?}: negative eigenvalue {:e}", lam[0]);
        let zeros = lam.iter().filter(|l| l.abs() <= tol).count();
        // C3D20R: 8 points x 6 strains bound the rank by 48 of 60, so a
        // single element has 6 hourglass modes besides the 6 rigid ones.
        // C3D6: both points lie on the line through the triangles'
        // centroids, where twisting the end triangles against each other
        // about that line strains nothing: one spurious mode (CalculiX's
        // C3D6 has it too; its K is the same, see calculix.rs).
        let expected = match kind {
            SolidKind::C3D20R => 12,
            SolidKind::C3D6 => 7,
            _ => 6,
        };
        assert_eq!(zeros, expected, "{kind:?}: eigenvalues {lam:?}");
    }
}

#[test]
fn mass_is_positive_semidefinite() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 37, 0.15);
        let em = solid(kind).matrices(&x).unwrap();
        let lam = eigenvalues(&em.mass);
        let top = *lam.last().unwrap();
        assert!(
            lam[0] > -1e-12 * top,
            "{kind:?}: negative eigenvalue {:e}",
            lam[0]
        );
    }
}

// ---------------------------------------------------------------------------
// Mass and volume

#[test]
fn translation_carries_the_element_mass() {
    for kind in SolidKind::ALL {
        // C3D20R integrates the mass with 2x2x2 points, exact for straight
        // edges (trilinear geometry) but not for curved ones.
        let x = if kind == SolidKind::C3D20R {
            let mut x = distorted(SolidKind::C3D8, 41, 0.15);
            for (a, b) in HEX_EDGES {
                x.push([0, 1, 2].map(|c| 0.5 * (x[a][c] + x[b][c])));
            }
            x
        } else {
            distorted(kind, 41, 0.15)
        };
        let s = solid(kind);
        let em = s.matrices(&x).unwrap();
        let mass = RHO * s.volume(&x).unwrap();
        for t in &rigid_modes(&x)[..3] {
            let mt = dot(t, &mat_vec(&em.mass, t));
            assert!(
                (mt - mass).abs() <= 1e-12 * mass,
                "{kind:?}: {mt} vs {mass}"
            );
        }
    }
}

#[test]
fn volume_is_exact_for_boxes_tets_and_wedges() {
    let (a, b, c) = (0.3, 0.2, 0.7);
    let scale = |r: &[f64; 3]| [0.3 + a * r[0], -1.0 + b * r[1], 2.0 + c * r[2]];
    for kind in [SolidKind::C3D8, SolidKind::C3D20, SolidKind::C3D20R] {
        let x: Vec<[f64; 3]> = shape::node_coordinates(kind)
            .iter()
            .map(|r| scale(&r.map(|v| 0.5 * (v + 1.0))))
            .collect();
        let v = solid(kind).volume(&x).unwrap();
        assert!((v - a * b * c).abs() < 1e-15, "{kind:?}: {v}");
    }
    for kind in [SolidKind::C3D4, SolidKind::C3D10] {
        let x: Vec<[f64; 3]> = shape::node_coordinates(kind).iter().map(scale).collect();
        let v = solid(kind).volume(&x).unwrap();
        assert!((v - a * b * c / 6.0).abs() < 1e-15, "{kind:?}: {v}");
    }
    let x: Vec<[f64; 3]> = shape::node_coordinates(SolidKind::C3D6)
        .iter()
        .map(|r| scale(&[r[0], r[1], 0.5 * (r[2] + 1.0)]))
        .collect();
    let v = solid(SolidKind::C3D6).volume(&x).unwrap();
    assert!((v - a * b * c / 2.0).abs() < 1e-15, "C3D6: {v}");
}

#[test]
fn volume_of_a_distorted_element_agrees_across_kinds() {
    // Straight-edged 20-node element = the 8-node one; the volume of a
    // sheared parallelepiped is |det A|.
    let x8 = distorted(SolidKind::C3D8, 43, 0.2);
    let mut x20 = x8.clone();
    for (a, b) in HEX_EDGES {
        x20.push([0, 1, 2].map(|c| 0.5 * (x8[a][c] + x8[b][c])));
    }
    let v8 = solid(SolidKind::C3D8).volume(&x8).unwrap();
    let v20 = solid(SolidKind::C3D20).volume(&x20).unwrap();
    let v20r = solid(SolidKind::C3D20R).volume(&x20).unwrap();
    assert!(
        (v8 - v20).abs() < 1e-14 * v8 && (v8 - v20r).abs() < 1e-14 * v8,
        "{v8} {v20} {v20r}"
    );
    let det_a = AFFINE[0][0] * (AFFINE[1][1] * AFFINE[2][2] - AFFINE[1][2] * AFFINE[2][1])
        - AFFINE[0][1] * (AFFINE[1][0] * AFFINE[2][2] - AFFINE[1][2] * AFFINE[2][0])
        + AFFINE[0][2] * (AFFINE[1][0] * AFFINE[2][1] - AFFINE[1][1] * AFFINE[2][0]);
    let p = distorted(SolidKind::C3D20, 1, 0.0);
    let v = solid(SolidKind::C3D20).volume(&p).unwrap();
    assert!((v - 8.0 * det_a).abs() < 1e-14, "{v} vs {}", 8.0 * det_a);
}

#[test]
fn unit_cube_c3d8_matches_the_closed_form_mass_matrix() {
    // Consistent mass of a trilinear brick: rho V / 216 * (2^3, 2^2, 2, 1)
    // for nodes sharing 3, 2, 1, 0 coordinates.
    let x: Vec<[f64; 3]> = shape::node_coordinates(SolidKind::C3D8)
        .iter()
        .map(|r| r.map(|v| 0.5 * (v + 1.0)))
        .collect();
    let em = solid(SolidKind::C3D8).matrices(&x).unwrap();
    for a in 0..8 {
        for b in 0..8 {
            let shared = (0..3).filter(|&c| x[a][c] == x[b][c]).count() as i32;
            let exact = RHO / 216.0 * 2f64.powi(shared);
            assert!((em.mass[(3 * a, 3 * b)] - exact).abs() < 1e-12 * exact);
            assert_eq!(em.mass[(3 * a, 3 * b + 1)], 0.0);
        }
    }
}

// ---------------------------------------------------------------------------
// Geometry and input checks

fn reason(e: FemError) -> String {
    match e {
        FemError::InvalidElement { element, reason } => {
            assert_eq!(element, 7);
            reason
        }
        other => panic!("unexpected error {other}"),
    }
}

/// A node order that turns the element inside out: swaps the two ends of
/// the element (hexahedra, wedge) or two corners (tetrahedra), with the
/// mid-edge nodes that go with them.
fn reversed(kind: SolidKind) -> Vec<usize> {
    match kind {
        SolidKind::C3D8 => vec![4, 5, 6, 7, 0, 1, 2, 3],
        SolidKind::C3D20 | SolidKind::C3D20R => vec![
            4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19,
        ],
        SolidKind::C3D4 => vec![0, 2, 1, 3],
        // Corners 2 <-> 3; edges 1-2 <-> 3-1, 2-4 <-> 3-4.
        SolidKind::C3D10 => vec![0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
        SolidKind::C3D6 => vec![3, 4, 5, 0, 1, 2],
    }
}

#[test]
fn inverted_elements_are_rejected() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 47, 0.1);
        solid(kind).validate(&x).unwrap();
        let swapped: Vec<[f64; 3]> = reversed(kind).iter().map(|&i| x[i]).collect();
        let r = reason(solid(kind).validate(&swapped).unwrap_err());
        assert!(
            r.starts_with("inverted: negative Jacobian at integration point 1"),
            "{kind:?}: {r}"
        );
        let mirrored: Vec<[f64; 3]> = x.iter().map(|p| [-p[0], p[1], p[2]]).collect();
        let r = reason(solid(kind).matrices(&mirrored).unwrap_err());
        assert!(r.starts_with("inverted"), "{kind:?}: {r}");
    }
    // Two corner nodes of a hexahedron swapped: a twisted element, inverted
    // at some integration points only.
    let mut x = distorted(SolidKind::C3D8, 47, 0.0);
    x.swap(0, 1);
    let r = reason(solid(SolidKind::C3D8).validate(&x).unwrap_err());
    assert!(r.starts_with("inverted"), "{r}");
}

#[test]
fn flat_elements_are_rejected() {
    for kind in SolidKind::ALL {
        let x: Vec<[f64; 3]> = distorted(kind, 53, 0.1)
            .iter()
            .map(|p| [p[0], p[1], 0.25])
            .collect();
        let r = reason(solid(kind).validate(&x).unwrap_err());
        assert!(r.starts_with("zero volume"), "{kind:?}: {r}");
        assert!(solid(kind).volume(&x).is_err());
        assert!(solid(kind).matrices(&x).is_err());
    }
}

#[test]
fn wrong_node_count_is_rejected() {
    let x = distorted(SolidKind::C3D8, 1, 0.1);
    let r = reason(solid(SolidKind::C3D20).validate(&x).unwrap_err());
    assert_eq!(r, "C3D20 needs 20 nodes, got 8");
    let r = reason(solid(SolidKind::C3D8).validate(&x[..7]).unwrap_err());
    assert_eq!(r, "C3D8 needs 8 nodes, got 7");
}

#[test]
fn bad_material_and_coordinates_are_rejected() {
    let x = distorted(SolidKind::C3D4, 1, 0.1);
    let mut s = solid(SolidKind::C3D4);
    s.material.poisson_ratio = 0.5;
    assert!(reason(s.validate(&x).unwrap_err()).contains("Poisson"));
    let mut s = solid(SolidKind::C3D4);
    s.material.youngs_modulus = 0.0;
    assert!(reason(s.validate(&x).unwrap_err()).contains("Young"));
    let mut bad = x.clone();
    bad[2][1] = f64::NAN;
    assert!(reason(solid(SolidKind::C3D4).validate(&bad).unwrap_err()).contains("finite"));
}

#[test]
fn elements_far_from_the_origin_are_accepted() {
    // A 1 mm element 10 km away: the Jacobian is built from coordinates
    // relative to the first node.
    let x: Vec<[f64; 3]> = distorted(SolidKind::C3D10, 59, 0.1)
        .iter()
        .map(|p| [1e4 + 1e-3 * p[0], -1e4 + 1e-3 * p[1], 5e3 + 1e-3 * p[2]])
        .collect();
    let v = solid(SolidKind::C3D10).volume(&x).unwrap();
    let v0 = solid(SolidKind::C3D10)
        .volume(&distorted(SolidKind::C3D10, 59, 0.1))
        .unwrap();
    // Rounding the coordinates to f64 moves the nodes by 2e-12 m, 2e-9 of
    // the element size.
    assert!((v - 1e-9 * v0).abs() < 1e-7 * v, "{v} vs {}", 1e-9 * v0);
}
