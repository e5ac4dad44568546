//! The invariants against their closed forms (point masses) and against
//! products with the full mass matrix (a solid).

use super::*;
use crate::modes::rigid::rigid_body_transformation;
use crate::{Method, ModeKind, ReducedBody};
use faer::sparse::Triplet;
use faer::Mat;
use flexbody_fem::{Dof, DofKind, DofMap, Model, Substructure, SystemMatrices};

/// Point masses (lumped mass): every invariant has a closed form,
/// `int f dm = sum_i m_i f(x_i)`.
const POINTS: [([f64; 3], f64); 5] = [
    ([0.1, 0.2, -0.3], 2.0),
    ([1.0, -0.5, 0.4], 1.5),
    ([-0.7, 0.3, 0.9], 3.0),
    ([0.4, 1.1, 0.2], 0.5),
    ([-0.2, -0.8, -0.6], 1.0),
];

fn skew3(v: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

fn mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn point_model() -> (Substructure, ReducedBody) {
    let n = POINTS.len();
    let dofs: Vec<Dof> = (0..n as u64)
        .flat_map(|p| DofKind::ALL[..3].iter().map(move |k| Dof::new(p + 1, *k)))
        .collect();
    let m = 3 * n;
    let diag = |f: &dyn Fn(usize) -> f64| {
        let t: Vec<Triplet<usize, usize, f64>> = (0..m).map(|i| Triplet::new(i, i, f(i))).collect();
        flexbody_linalg::sparse::from_triplets(m, m, &t).unwrap()
    };
    let mass = diag(&|i| POINTS[i / 3].1);
    let stiffness = diag(&|i| 1.0 + i as f64);
    let coordinates = (0..n).map(|p| (p as u64 + 1, POINTS[p].0)).collect();
    let sub = Substructure::from_matrices(
        DofMap::new(dofs.clone()),
        SystemMatrices {
            stiffness,
            mass,
            damping: None,
        },
        coordinates,
    );
    // The six rigid-body motions plus three arbitrary fields.
    let rigid = rigid_body_transformation(&sub, [0.0; 3]);
    let basis = Mat::from_fn(m, 9, |i, j| {
        if j < 6 {
            rigid[(i, j)]
        } else {
            ((i * 7 + j * 3) % 11) as f64 / 11.0 - 0.4
        }
    });
    let reduced = |a: &flexbody_linalg::SparseMat| basis.transpose() * (a * &basis);
    let body = ReducedBody {
        method: Method::Free,
        dof_map: DofMap::new(dofs),
        mass: reduced(&sub.matrices.mass),
        stiffness: reduced(&sub.matrices.stiffness),
        damping: None,
        modes: vec![ModeKind::Eigen { frequency_hz: 0.0 }; 9],
        interface: vec![],
        local_axes: Default::default(),
        basis,
    };
    (sub, body)
}

/// The elastic basis of a body reduced from `sub`, which must float
/// (its basis holds the rigid-body motions), and its mass invariants.
fn floating_invariants(
    (sub, body): (Substructure, ReducedBody),
) -> (Substructure, ElasticBasis, MassInvariants) {
    let basis = elastic_basis(&sub, &body).unwrap();
    assert!(basis.floating);
    let inv = mass_invariants(&sub, None, &basis).unwrap();
    (sub, basis, inv)
}

#[test]
fn invariants_of_point_masses_have_their_closed_forms() {
    let (_, basis, inv) = floating_invariants(point_model());
    let nq = basis.shapes.ncols();
    assert_eq!(nq, 3);
    let total: f64 = POINTS.iter().map(|p| p.1).sum();
    assert!((inv.mass - total).abs() < 1e-13 * total);
    for a in 0..3 {
        let s: f64 = POINTS.iter().map(|(x, m)| m * x[a]).sum();
        assert!((inv.md_cm[a] - s).abs() < 1e-13 * total, "mdCM {a}");
        for b in 0..3 {
            let s: f64 = POINTS
                .iter()
                .map(|(x, m)| {
                    let r2: f64 = x.iter().map(|v| v * v).sum();
                    m * (if a == b { r2 } else { 0.0 } - x[a] * x[b])
                })
                .sum();
            assert!((inv.j[a][b] - s).abs() < 1e-13 * total, "J {a} {b}");
        }
    }
    // Mean axes: no rigid-body part in the elastic modes.
    assert!(inv.ct.norm_max() < 1e-12 && inv.cr.norm_max() < 1e-12);
    let phi =
        |p: usize, k: usize| -> [f64; 3] { std::array::from_fn(|d| basis.shapes[(3 * p + d, k)]) };
    for k in 0..nq {
        // Gr_k = -2 sum m x~ phi_k~; J1_k = -sum m (x~ phi~ + phi~ x~).
        let mut gr = [[0.0; 3]; 3];
        let mut j1 = [[0.0; 3]; 3];
        for (p, (x, m)) in POINTS.iter().enumerate() {
            let (xs, ps) = (skew3(*x), skew3(phi(p, k)));
            let (a, b) = (mul(xs, ps), mul(ps, xs));
            for i in 0..3 {
                for j in 0..3 {
                    gr[i][j] -= 2.0 * m * a[i][j];
                    j1[i][j] -= m * (a[i][j] + b[i][j]);
                }
            }
        }
        for i in 0..3 {
            for j in 0..3 {
                assert!((inv.gr[(i, 3 * k + j)] - gr[i][j]).abs() < 1e-12, "Gr");
                assert!((inv.j1[k][i][j] - j1[i][j]).abs() < 1e-12, "J1");
            }
        }
        for l in 0..nq {
            // Ge block l, row k = -2 sum m (phi_k x phi_l); Cr1 block l,
            // row k = sum m (phi_l x phi_k).
            let mut c = [0.0; 3];
            for (p, (_, m)) in POINTS.iter().enumerate() {
                let (a, b) = (phi(p, k), phi(p, l));
                c[0] += m * (a[1] * b[2] - a[2] * b[1]);
                c[1] += m * (a[2] * b[0] - a[0] * b[2]);
                c[2] += m * (a[0] * b[1] - a[1] * b[0]);
            }
            for (a, ca) in c.iter().enumerate() {
                assert!((inv.ge[(k, 3 * l + a)] + 2.0 * ca).abs() < 1e-12, "Ge");
                assert!((inv.cr1[l][(k, a)] + ca).abs() < 1e-12, "Cr1");
            }
        }
        // Oe: phi_k . (w x (w x x)) summed, for a test w.
        let w = [0.3, -1.2, 0.7];
        let wq = [
            w[0] * w[0],
            w[1] * w[1],
            w[2] * w[2],
            w[0] * w[1],
            w[1] * w[2],
            w[2] * w[0],
        ];
        let mut want = 0.0;
        for (p, (x, m)) in POINTS.iter().enumerate() {
            let ws = skew3(w);
            let wwx: [f64; 3] = std::array::from_fn(|i| {
                (0..3)
                    .map(|j| (0..3).map(|l| ws[i][l] * ws[l][j]).sum::<f64>() * x[j])
                    .sum()
            });
            let f = phi(p, k);
            want += m * (0..3).map(|i| f[i] * wwx[i]).sum::<f64>();
        }
        let got: f64 = (0..6).map(|c| inv.oe[(k, c)] * wq[c]).sum();
        assert!((got - want).abs() < 1e-12, "Oe: {got} against {want}");
    }
    // Unit modal mass, diagonal stiffness.
    for i in 0..nq {
        for j in 0..nq {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((basis.mass[(i, j)] - want).abs() < 1e-12);
            if i != j {
                assert!(basis.stiffness[(i, j)].abs() < 1e-9);
            }
        }
    }
}

/// The block of [`solid_block`]: 1.2 x 0.5 x 0.4 m, origin (-0.3, 0.1, 0).
const BLOCK: ([f64; 3], [f64; 3]) = ([-0.3, 0.1, 0.0], [1.2, 0.5, 0.4]);
const STEEL_DENSITY: f64 = 7850.0;

/// A steel C3D8 block of 3 x 2 x 2 elements ([`BLOCK`]), its face at the
/// smallest x clamped if `clamped`, and its model.
fn block_model(clamped: bool) -> (Model, Substructure) {
    use flexbody_fem::mesh::BrickBlock;
    use flexbody_fem::Material;
    let grid = BrickBlock {
        cells: [3, 2, 2],
        origin: BLOCK.0,
        size: BLOCK.1,
    };
    let nodes = grid.nodes();
    let fixed = if clamped {
        nodes
            .iter()
            .filter(|n| n.coords[0] == BLOCK.0[0])
            .flat_map(|n| DofKind::ALL[..3].iter().map(move |k| Dof::new(n.id, *k)))
            .collect()
    } else {
        vec![]
    };
    let elements = grid.elements(&Material::new(2.1e11, 0.3, STEEL_DENSITY).unwrap());
    let model = Model::of(nodes, elements).fixed(fixed).build().unwrap();
    let sub = Substructure::from_model(&model).unwrap();
    (model, sub)
}

/// The free block of [`block_model`] and its free reduction with 6
/// elastic modes.
fn solid_block() -> (Substructure, ReducedBody) {
    let (_, sub) = block_model(false);
    let spec = crate::Reduction::new(Method::Free, 12, vec![]);
    let body = crate::reduce(&sub, &spec).unwrap();
    (sub, body)
}

/// Every invariant of `a` against `b`, relative to the largest entry of
/// each (at least 1); the worst.
fn largest_difference(a: &MassInvariants, b: &MassInvariants) -> (f64, &'static str) {
    let mats = |i: &MassInvariants| -> Vec<(&'static str, Mat<f64>)> {
        let small = |m: &[[f64; 3]; 3]| Mat::from_fn(3, 3, |r, c| m[r][c]);
        let mut v = vec![
            ("mass", Mat::from_fn(1, 1, |_, _| i.mass)),
            ("mdCM", Mat::from_fn(3, 1, |r, _| i.md_cm[r])),
            ("J", small(&i.j)),
            ("Ct", i.ct.clone()),
            ("Cr", i.cr.clone()),
            ("Me", i.me.clone()),
            ("Gr", i.gr.clone()),
            ("Ge", i.ge.clone()),
            ("Oe", i.oe.clone()),
        ];
        for (k, j1) in i.j1.iter().enumerate() {
            v.push(("J m1", small(j1)));
            v.push(("mdCM m1", Mat::from_fn(3, 1, |r, _| i.md_cm1[k][r])));
            v.push(("Cr m1", i.cr1[k].clone()));
            v.push(("Oe m1", i.oe1[k].clone()));
        }
        v
    };
    let mut worst = (0.0, "");
    for ((name, x), (_, y)) in mats(a).into_iter().zip(mats(b)) {
        // Mean axes make Ct and mdCM m1 vanish: round-off against 1 (their
        // scale is sqrt(mass), 43 kg^0.5).
        let scale = x.norm_max().max(y.norm_max()).max(1.0);
        let d = (&x - &y).norm_max() / scale;
        if d > worst.0 {
            worst = (d, name);
        }
    }
    worst
}

#[test]
fn a_solid_mesh_and_its_mass_matrix_give_the_same_invariants() {
    // Free: both routes integrate the whole body exactly (isoparametric
    // elements, consistent mass), the mesh one element by element.
    let (model, sub) = block_model(false);
    let body = crate::reduce(&sub, &crate::Reduction::new(Method::Free, 12, vec![])).unwrap();
    let basis = elastic_basis(&sub, &body).unwrap();
    let from_mesh = mass_invariants(&sub, Some(&model), &basis).unwrap();
    let from_matrix = mass_invariants(&sub, None, &basis).unwrap();
    let (d, name) = largest_difference(&from_mesh, &from_matrix);
    assert!(d < 1e-12, "{name}: {d:e}");
}

#[test]
fn a_clamped_body_keeps_the_mass_of_its_fixed_nodes() {
    // The mass matrix of the free DOFs lost the clamped face's share; the
    // mesh has it all: the block's rho V, its first moment rho V c and its
    // inertia tensor about the origin, in closed form.
    let (model, sub) = block_model(true);
    let body = crate::reduce(&sub, &crate::Reduction::new(Method::Free, 6, vec![])).unwrap();
    let basis = elastic_basis(&sub, &body).unwrap();
    assert!(!basis.floating);
    let inv = mass_invariants(&sub, Some(&model), &basis).unwrap();
    let (lo, size) = BLOCK;
    let volume: f64 = size.iter().product();
    let mass = STEEL_DENSITY * volume;
    assert!(
        (inv.mass - mass).abs() < 1e-12 * mass,
        "{} against {mass}",
        inv.mass
    );
    let centre: [f64; 3] = std::array::from_fn(|a| lo[a] + size[a] / 2.0);
    // int x_a x_b dV over the box: V (c_a c_b + delta_ab s_a^2 / 12).
    let second = |a: usize, b: usize| {
        mass * (centre[a] * centre[b]
            + if a == b {
                size[a] * size[a] / 12.0
            } else {
                0.0
            })
    };
    for (a, c) in centre.iter().enumerate() {
        assert!((inv.md_cm[a] - mass * c).abs() < 1e-12 * mass);
        for b in 0..3 {
            let trace: f64 = (0..3).map(|c| second(c, c)).sum();
            let want = if a == b { trace } else { 0.0 } - second(a, b);
            assert!((inv.j[a][b] - want).abs() < 1e-12 * trace, "J {a} {b}");
        }
    }
    // The matrix alone has less: the fixed nodes' own mass is gone.
    let partial = mass_invariants(&sub, None, &basis).unwrap();
    assert!(partial.mass < 0.95 * mass, "{}", partial.mass);
    // The elastic part is the same: Me from the same modes.
    assert!((&inv.me - &partial.me).norm_max() < 1e-12);
}

#[test]
fn invariants_of_a_solid_equal_their_products_with_the_full_mass_matrix() {
    // The products of two fields go node by node through the scalar
    // couplings S_pq (`NodeMass`). For a solid, M couples the same
    // direction of two nodes only, and equally in x, y and z, so
    // int a_i b_j dm is a^T M g with g carrying b's j-components in the
    // i-slots: every invariant of the module docs from M itself.
    let (sub, basis, inv) = floating_invariants(solid_block());
    let nq = basis.shapes.ncols();
    assert_eq!(nq, 6);
    let map = &sub.dof_map;
    let n = map.len();
    let slot = |i: usize| map.dof(i).kind.index();
    let position: Vec<f64> = (0..n)
        .map(|i| sub.node_coordinates(map.dof(i).node).unwrap()[slot(i)])
        .collect();
    let mode = |k: usize| -> Vec<f64> { (0..n).map(|i| basis.shapes[(i, k)]).collect() };
    // P(a, b)[i][j] = int a_i b_j dm.
    let m = &sub.matrices.mass;
    let p = |a: &[f64], b: &[f64]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let g = Mat::from_fn(n, 1, |r, _| {
                    if slot(r) != i {
                        return 0.0;
                    }
                    let d = map.dof(r);
                    let from = map
                        .index_of(Dof::new(d.node, DofKind::ALL[j]))
                        .expect("solid nodes carry ux, uy, uz");
                    b[from]
                });
                let mg = flexbody_linalg::sparse::symmetric_mul(m, g.as_ref());
                (0..n).map(|r| a[r] * mg[(r, 0)]).sum()
            })
        })
    };
    let tr = |q: &[[f64; 3]; 3]| q[0][0] + q[1][1] + q[2][2];
    let cross = |q: &[[f64; 3]; 3], a: usize| {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        q[b][c] - q[c][b]
    };
    let oe_of = |q: &[[f64; 3]; 3]| {
        let s = |i: usize, j: usize| 0.5 * (q[i][j] + q[j][i]) - if i == j { tr(q) } else { 0.0 };
        [
            s(0, 0),
            s(1, 1),
            s(2, 2),
            2.0 * s(0, 1),
            2.0 * s(1, 2),
            2.0 * s(2, 0),
        ]
    };
    // Each invariant against its own largest entry.
    let mut worst = [0.0_f64; 6];
    let mut scale = [0.0_f64; 6];
    let mut check = |which: usize, got: f64, want: f64| {
        worst[which] = worst[which].max((got - want).abs());
        scale[which] = scale[which].max(want.abs());
    };
    let x0 = position.clone();
    for k in 0..nq {
        let fk = mode(k);
        let (xk, kx) = (p(&x0, &fk), p(&fk, &x0));
        for a in 0..3 {
            for b in 0..3 {
                let delta = if a == b { 2.0 * tr(&xk) } else { 0.0 };
                // J1_k = -int (x0~ phi_k~ + phi_k~ x0~) dm.
                check(0, inv.j1[k][a][b], delta - kx[a][b] - xk[a][b]);
                // Gr block k = -2 int x0~ phi_k~ dm.
                check(1, inv.gr[(a, 3 * k + b)], -2.0 * kx[a][b] + delta);
            }
        }
        // Oe row k from int phi_k x0^T dm.
        for (c, want) in oe_of(&kx).iter().enumerate() {
            check(2, inv.oe[(k, c)], *want);
        }
        for l in 0..nq {
            let fl = mode(l);
            let (kl, lk) = (p(&fk, &fl), p(&fl, &fk));
            for a in 0..3 {
                // Ge block l, row k = -2 int phi_k x phi_l dm; Cr1 for
                // q_l, row k = int phi_l x phi_k dm.
                check(3, inv.ge[(k, 3 * l + a)], -2.0 * cross(&kl, a));
                check(4, inv.cr1[l][(k, a)], cross(&lk, a));
            }
            for (c, want) in oe_of(&kl).iter().enumerate() {
                check(5, inv.oe1[l][(k, c)], *want);
            }
        }
    }
    for (name, (w, s)) in ["J1", "Gr", "Oe", "Ge", "Cr1", "Oe1"]
        .iter()
        .zip(worst.iter().zip(&scale))
    {
        assert!(*s > 0.0, "{name} vanishes: no test");
        assert!(w / s < 1e-12, "{name}: {w:e} of {s:e}");
    }
}
