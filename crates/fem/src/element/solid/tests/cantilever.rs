//! A clamped steel bar of C3D20 elements against beam theory: tip
//! deflection under a tip shear load (Euler-Bernoulli plus the shear term)
//! and the first bending frequency (Euler-Bernoulli), both within 1 %; and
//! a coarse bar of C3D8I, whose incompatible modes bend without the shear
//! locking of C3D8; C3D8R (uniform strain, hourglass control) converging
//! from the flexible side.
//!
//! Bar: L = 2 m, square 0.1 m x 0.1 m section (L/h = 20), clamped (all
//! three translations) over the whole end face x = 0.

use super::{steel, E, NU, RHO};
use crate::dof::{Dof, DofKind};
use crate::element::SolidKind;
use crate::mesh::SolidBlock;
use crate::model::{Model, NodeId};
use crate::{assemble, SystemMatrices};
use faer::Mat;
use flexbody_linalg::eigen::generalized_symmetric;
use flexbody_linalg::ldlt::Factor;
use flexbody_linalg::SparseMat;
use std::collections::HashMap;

const LENGTH: f64 = 2.0;
const SIDE: f64 = 0.1;

/// A structured bar of `n[0] x n[1] x n[2]` C3D20 elements over
/// `[0, L] x [0, h] x [0, h]` (a [`SolidBlock`]), clamped at x = 0; returns
/// the model and the node id at each point of the half-step grid (corners
/// and mid-edge points) it uses.
fn bar(n: [usize; 3]) -> (Model, HashMap<[usize; 3], NodeId>) {
    bar_of(SolidKind::C3D20, n)
}

/// [`bar`] of `kind` elements.
fn bar_of(kind: SolidKind, n: [usize; 3]) -> (Model, HashMap<[usize; 3], NodeId>) {
    let mesh = SolidBlock {
        kind,
        cells: n,
        origin: [0.0; 3],
        size: [LENGTH, SIDE, SIDE],
        corner_distortion: 0.0,
        edge_distortion: 0.0,
        seed: 1,
    }
    .mesh();
    let ids: HashMap<[usize; 3], NodeId> = mesh
        .reference
        .iter()
        .enumerate()
        .map(|(node, r)| {
            let g = [0, 1, 2].map(|c| (r[c] * (2 * n[c]) as f64).round() as usize);
            (g, node as NodeId + 1)
        })
        .collect();
    let fixed = ids
        .iter()
        .filter(|(g, _)| g[0] == 0)
        .flat_map(|(_, &id)| [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|d| Dof::new(id, d)))
        .collect();
    let elements = mesh.elements(&steel());
    let model = Model::of(mesh.nodes(), elements)
        .fixed(fixed)
        .build()
        .unwrap();
    (model, ids)
}

/// Consistent nodal forces of a uniform shear traction `p` (N in total,
/// along z) on the tip face x = L: per 8-node face, -1/12 of its share at
/// each corner and 1/3 at each mid-edge node.
fn tip_load(model: &Model, ids: &HashMap<[usize; 3], NodeId>, n: [usize; 3], p: f64) -> Vec<f64> {
    let mut f = vec![0.0; model.dof_map().len()];
    let face = p / (n[1] * n[2]) as f64;
    let i = 2 * n[0];
    for k in 0..n[2] {
        for j in 0..n[1] {
            for dj in 0..=2 {
                for dk in 0..=2 {
                    let share = match (dj % 2, dk % 2) {
                        (0, 0) => -1.0 / 12.0,
                        (1, 1) => continue,
                        _ => 1.0 / 3.0,
                    };
                    let node = ids[&[i, 2 * j + dj, 2 * k + dk]];
                    let eq = model
                        .dof_map()
                        .index_of(Dof::new(node, DofKind::Uz))
                        .unwrap();
                    f[eq] += share * face;
                }
            }
        }
    }
    f
}

/// [`tip_load`] for 4-node faces (C3D8, C3D8I): a quarter of each face's
/// share at each of its corners.
fn tip_load_linear(
    model: &Model,
    ids: &HashMap<[usize; 3], NodeId>,
    n: [usize; 3],
    p: f64,
) -> Vec<f64> {
    let mut f = vec![0.0; model.dof_map().len()];
    let face = p / (n[1] * n[2]) as f64;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for (dj, dk) in [(0, 0), (2, 0), (0, 2), (2, 2)] {
                let node = ids[&[2 * n[0], 2 * j + dj, 2 * k + dk]];
                let eq = model
                    .dof_map()
                    .index_of(Dof::new(node, DofKind::Uz))
                    .unwrap();
                f[eq] += 0.25 * face;
            }
        }
    }
    f
}

/// Work-conjugate tip deflection `f^T u / P` of a bar under the tip load
/// `f` of `p` N in all.
fn tip_deflection(model: &Model, f: &[f64], p: f64) -> f64 {
    let SystemMatrices { stiffness, .. } = assemble(model).unwrap();
    let u = Factor::of(&stiffness).unwrap().solve(column(f).as_ref());
    let u: Vec<f64> = (0..u.nrows()).map(|i| u[(i, 0)]).collect();
    dot(f, &u) / p
}

/// Euler-Bernoulli plus the shear term (shear coefficient 5/6): the tip
/// deflection of the bar under a tip load `p`.
fn beam_tip_deflection(p: f64) -> f64 {
    let g = E / (2.0 * (1.0 + NU));
    p * LENGTH.powi(3) / (3.0 * E * second_moment()) + p * LENGTH / (5.0 / 6.0 * g * SIDE * SIDE)
}

#[test]
fn c3d8i_bends_without_locking_on_a_coarse_mesh() {
    // Ten elements along, two through the section. The reference is the
    // same clamped bar of 20 x 4 x 4 C3D20 (0.7 % from beam theory, which
    // knows neither the clamp's restraint of the cross-section nor the
    // load's spread): C3D8I within 2 % of it, while C3D8 locks in shear and
    // bends far too little.
    let p = 1000.0;
    let fine = [20, 4, 4];
    let (model, ids) = bar(fine);
    let reference = tip_deflection(&model, &tip_load(&model, &ids, fine, p), p);
    let beam = beam_tip_deflection(p);
    eprintln!(
        "C3D20 20x4x4 tip deflection: {:+.3} % from beam theory",
        100.0 * (reference - beam) / beam
    );
    let n = [10, 2, 2];
    let mut errors = Vec::new();
    for kind in [SolidKind::C3D8I, SolidKind::C3D8] {
        let (model, ids) = bar_of(kind, n);
        let f = tip_load_linear(&model, &ids, n, p);
        let err = (tip_deflection(&model, &f, p) - reference) / reference;
        eprintln!(
            "{kind:?} 10x2x2 tip deflection: {:+.3} % from the C3D20 bar",
            100.0 * err
        );
        errors.push(err);
    }
    assert!(
        errors[0].abs() < 0.02,
        "C3D8I off by {:.3} %",
        100.0 * errors[0]
    );
    assert!(
        errors[1] < -0.5,
        "C3D8 should lock: {:.3} %",
        100.0 * errors[1]
    );
}

/// `A x` for a sparse matrix holding both triangles.
fn mul(a: &SparseMat, x: &[f64]) -> Vec<f64> {
    let (col_ptr, row_idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let mut y = vec![0.0; a.nrows()];
    for (j, xj) in x.iter().enumerate() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            y[row_idx[p]] += val[p] * xj;
        }
    }
    y
}

fn column(v: &[f64]) -> Mat<f64> {
    Mat::from_fn(v.len(), 1, |i, _| v[i])
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn second_moment() -> f64 {
    SIDE.powi(4) / 12.0
}

/// `omega_1 = (beta_1 L)^2 sqrt(E I / (rho A L^4))`, `beta_1 L = 1.8751`.
fn euler_bernoulli_omega() -> f64 {
    1.875_104_07_f64.powi(2) * (E * second_moment() / (RHO * SIDE * SIDE * LENGTH.powi(4))).sqrt()
}

#[test]
fn c3d20_cantilever_20x4x4_tip_deflection_and_first_frequency() {
    let n = [20, 4, 4];
    let (model, ids) = bar(n);
    let SystemMatrices {
        stiffness, mass, ..
    } = assemble(&model).unwrap();
    let ldlt = Factor::of(&stiffness).unwrap();

    // Static: work-conjugate tip deflection f^T u / P.
    let p = 1000.0;
    let f = tip_load(&model, &ids, n, p);
    let u = ldlt.solve(column(&f).as_ref());
    let u: Vec<f64> = (0..u.nrows()).map(|i| u[(i, 0)]).collect();
    let deflection = dot(&f, &u) / p;
    let g = E / (2.0 * (1.0 + NU));
    let bending = p * LENGTH.powi(3) / (3.0 * E * second_moment());
    let shear = p * LENGTH / (5.0 / 6.0 * g * SIDE * SIDE);
    let beam = bending + shear;
    let err = (deflection - beam) / beam;
    eprintln!(
        "tip deflection {deflection:.6e} m, beam theory {beam:.6e} m (shear {shear:.2e}): {:+.3} %",
        100.0 * err
    );
    assert!(
        err.abs() < 0.01,
        "tip deflection off by {:.3} %",
        100.0 * err
    );

    // First bending mode by inverse iteration from the static shape (the
    // two bending modes of the square bar have one frequency and the static
    // shape lies in their span; the next bending mode is ~40x higher in
    // omega^2, so each step gains more than a digit).
    let mut x = u;
    let mut omega = 0.0;
    for _ in 0..4 {
        let y = ldlt.solve(column(&mul(&mass, &x)).as_ref());
        let norm = (0..y.nrows()).map(|i| y[(i, 0)].abs()).fold(0.0, f64::max);
        x = (0..y.nrows()).map(|i| y[(i, 0)] / norm).collect();
        omega = (dot(&x, &mul(&stiffness, &x)) / dot(&x, &mul(&mass, &x))).sqrt();
    }
    let beam = euler_bernoulli_omega();
    let err = (omega - beam) / beam;
    eprintln!(
        "first bending frequency {:.4} Hz, Euler-Bernoulli {:.4} Hz: {:+.3} %",
        omega / (2.0 * std::f64::consts::PI),
        beam / (2.0 * std::f64::consts::PI),
        100.0 * err
    );
    assert!(
        err.abs() < 0.01,
        "first frequency off by {:.3} %",
        100.0 * err
    );
}

#[test]
fn c3d20_cantilever_16x1x1_dense_eigenproblem() {
    // The dense path (flexbody_linalg::eigen) on a coarser bar, 16 elements
    // along and one through the section (576 DOFs): both bending modes at
    // the Euler-Bernoulli frequency.
    let (model, _) = bar([16, 1, 1]);
    let sys = assemble(&model).unwrap();
    let pairs = generalized_symmetric(
        sys.stiffness.to_dense().as_ref(),
        sys.mass.to_dense().as_ref(),
    )
    .unwrap();
    let beam = euler_bernoulli_omega();
    for (mode, lambda) in pairs.values[..2].iter().enumerate() {
        let err = (lambda.sqrt() - beam) / beam;
        eprintln!(
            "16x1x1 mode {}: {:+.3} % from Euler-Bernoulli",
            mode + 1,
            100.0 * err
        );
        assert!(
            err.abs() < 0.01,
            "mode {} off by {:.3} %",
            mode + 1,
            100.0 * err
        );
    }
    // The third mode (torsion or second bending) is well above.
    assert!(pairs.values[2].sqrt() > 3.0 * beam);
}

#[test]
fn c3d8r_bends_without_locking_and_converges() {
    // The uniform-strain hexahedron with CalculiX's hourglass stiffness on
    // the clamped bar: no shear locking (unlike C3D8); with one point per
    // element it is too flexible on a coarse mesh, and the error falls
    // with the square of the element size.
    let p = 1000.0;
    let fine = [20, 4, 4];
    let (model, ids) = bar(fine);
    let reference = tip_deflection(&model, &tip_load(&model, &ids, fine, p), p);
    let mut errors = Vec::new();
    for n in [[10, 2, 2], [20, 4, 4], [40, 8, 8]] {
        let (model, ids) = bar_of(SolidKind::C3D8R, n);
        let f = tip_load_linear(&model, &ids, n, p);
        let err = (tip_deflection(&model, &f, p) - reference) / reference;
        eprintln!(
            "C3D8R {}x{}x{} tip deflection: {:+.3} % from the C3D20 bar",
            n[0],
            n[1],
            n[2],
            100.0 * err
        );
        errors.push(err);
    }
    // Measured: +17.6 %, +4.1 %, +1.2 %.
    assert!(errors.iter().all(|e| *e > 0.0), "too stiff: {errors:?}");
    assert!(
        errors[1] < errors[0] / 3.0 && errors[2] < errors[1] / 2.5,
        "no second-order convergence: {errors:?}"
    );
    assert!(errors[2] < 0.02, "40x8x8 off by {:.2} %", 100.0 * errors[2]);
}
