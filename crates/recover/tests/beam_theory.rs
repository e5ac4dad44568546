//! Section forces of beam elements (report eq. 25: `section_forces`,
//! `harmonic_section_forces`, `ModalRecovery`) from the solution of the full
//! FE model, compared with closed forms of beam theory: cantilevers under
//! end loads (statics of the part beyond the cut; tip deflection
//! `P L^3 / (3 E I) + P L / (G A_s)`) and under uniform line loads, a simply
//! supported beam under a central load (`M = P x / 2`, `P L^3 / (48 E I)`),
//! a free beam accelerated as a rigid body by end loads (d'Alembert), and a
//! cantilever in harmonic motion (the Euler-Bernoulli solution with
//! `cosh, sinh, cos, sin` of `k x`, `k^4 = rho A Omega^2 / (E I)`). The sign
//! convention of `SectionForces` (internal force on the positive cut face,
//! rows `N Qy Qz T My Mz` in the element frame) is checked on its own.

mod common;

use common::{dense_matrices, load_vector, mat_vec, max_abs, solve, static_solution};
use flexbody_fem::element::{Beam, PlanarBeam};
use flexbody_fem::section::SectionConstants;
use flexbody_fem::{
    BeamProperties, BeamTheory, Dof, DofKind, Element, Material, Model, Node, SectionForces,
    SectionShape, Substructure,
};
use flexbody_recover::{harmonic_section_forces, section_forces, ElementForces, ModalRecovery};
use flexbody_reduce::{reduce, Method, ModeKind, Reduction};
use std::collections::BTreeMap;

const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;

/// Solid rectangle 40 mm (local y) by 60 mm (local z): `Iy != Iz`, so the
/// two bending planes cannot be swapped unnoticed.
fn section() -> SectionConstants {
    SectionShape::Rect {
        width: 0.04,
        height: 0.06,
    }
    .constants()
    .unwrap()
}

fn props(theory: BeamTheory) -> BeamProperties {
    BeamProperties::new(Material::new(E, NU, RHO).unwrap(), section(), theory)
}

/// The element kinds under test.
#[derive(Copy, Clone, Debug)]
enum Kind {
    /// Planar beam (uz, ry), Euler-Bernoulli.
    Planar,
    /// 3D beam of the given theory.
    Beam(BeamTheory),
}

const KINDS: [Kind; 3] = [
    Kind::Planar,
    Kind::Beam(BeamTheory::EulerBernoulli),
    Kind::Beam(BeamTheory::Timoshenko),
];

impl Kind {
    fn properties(self) -> BeamProperties {
        match self {
            Kind::Planar => props(BeamTheory::EulerBernoulli),
            Kind::Beam(t) => props(t),
        }
    }

    fn dof_kinds(self) -> &'static [DofKind] {
        match self {
            Kind::Planar => &[DofKind::Uz, DofKind::Ry],
            Kind::Beam(_) => &DofKind::ALL,
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
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

fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    a.map(|v| v / n)
}

/// `sum c_k v_k`.
fn combine(terms: &[(f64, [f64; 3])]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (c, v) in terms {
        for k in 0..3 {
            out[k] += c * v[k];
        }
    }
    out
}

/// Element frame (rows x, y, z) as the element modules document it. 3D
/// beam: x from node 1 to node 2, y the part of the orientation vector
/// normal to x, z = x cross y. Planar beam: x along the element, y = s
/// times global y (s = +1 if node 2 lies at larger x), z = global z.
fn frame(model: &Model, e: &Element) -> [[f64; 3]; 3] {
    let nodes = e.nodes();
    let (a, b) = (model.coords(nodes[0]), model.coords(nodes[1]));
    let ex = unit(sub(b, a));
    match e {
        Element::Beam(beam) => {
            let v = beam.orientation;
            let ey = unit(combine(&[(1.0, v), (-dot(v, ex), ex)]));
            [ex, ey, cross(ex, ey)]
        }
        Element::PlanarBeam(_) => [ex, [0.0, ex[0].signum(), 0.0], [0.0, 0.0, 1.0]],
        _ => unreachable!("not a beam"),
    }
}

/// A straight line of `n` elements of `kind` from `a` to `b`, nodes
/// `1..=n+1` in order along it; element `i` (0-based) runs from its higher
/// node to its lower one if `reversed(i)`.
fn line(
    kind: Kind,
    n: usize,
    a: [f64; 3],
    b: [f64; 3],
    orientation: [f64; 3],
    reversed: impl Fn(usize) -> bool,
    fixed: Vec<Dof>,
) -> Model {
    let nodes = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            Node {
                id: i as u64 + 1,
                coords: [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k])),
            }
        })
        .collect();
    let elements = (0..n)
        .map(|i| {
            let mut nodes = [i as u64 + 1, i as u64 + 2];
            if reversed(i) {
                nodes.reverse();
            }
            match kind {
                Kind::Planar => Element::PlanarBeam(PlanarBeam {
                    id: i + 1,
                    nodes,
                    properties: kind.properties(),
                }),
                Kind::Beam(_) => Element::Beam(Beam {
                    id: i + 1,
                    nodes,
                    properties: kind.properties(),
                    orientation,
                }),
            }
        })
        .collect();
    Model::new(nodes, elements, BTreeMap::new(), fixed, None).unwrap()
}

/// All DOFs of `kind` at `node`.
fn all_dofs(kind: Kind, node: u64) -> Vec<Dof> {
    kind.dof_kinds()
        .iter()
        .map(|k| Dof::new(node, *k))
        .collect()
}

/// Global displacement and rotation of a node, `[ux, uy, uz, rx, ry, rz]`
/// (DOFs the model lacks: 0).
fn node_motion(model: &Model, u: &[f64], node: u64) -> [f64; 6] {
    DofKind::ALL.map(|k| {
        let d = Dof::new(node, k);
        if model.dof_map().index_of(d).is_some() {
            model.value(d, u)
        } else {
            0.0
        }
    })
}

/// A concentrated load (support reactions included): point, force (N) and
/// moment (N m), global components.
struct PointLoad {
    at: [f64; 3],
    force: [f64; 3],
    moment: [f64; 3],
}

/// Beam statics: section forces at both ends of an element (frame `f`)
/// from the concentrated loads on the beam. The internal force on the
/// positive cut face (outward normal +x of the element) is what the part
/// beyond the cut in +x exerts on it: the resultant of the loads on that
/// part, `sum F_k` and `sum (M_k + (x_k - p) x F_k)` about the cut `p`.
/// Loads sit at nodes; the part beyond either end of an element is the
/// one beyond its midpoint.
fn statics(
    start: [f64; 3],
    end: [f64; 3],
    f: &[[f64; 3]; 3],
    loads: &[PointLoad],
) -> SectionForces {
    let mid = combine(&[(0.5, start), (0.5, end)]);
    let at = |p: [f64; 3]| {
        let mut force = [0.0; 3];
        let mut moment = [0.0; 3];
        for l in loads.iter().filter(|l| dot(sub(l.at, mid), f[0]) > 0.0) {
            force = combine(&[(1.0, force), (1.0, l.force)]);
            moment = combine(&[
                (1.0, moment),
                (1.0, l.moment),
                (1.0, cross(sub(l.at, p), l.force)),
            ]);
        }
        [
            dot(force, f[0]),
            dot(force, f[1]),
            dot(force, f[2]),
            dot(moment, f[0]),
            dot(moment, f[1]),
            dot(moment, f[2]),
        ]
    };
    SectionForces {
        start: at(start),
        end: at(end),
    }
}

/// Largest deviation of the recovered section forces from the expected
/// ones over all element ends: forces (N, Qy, Qz) relative to the largest
/// expected force, moments (T, My, Mz) to the largest expected moment.
fn deviation(got: &[SectionForces], want: &[SectionForces]) -> f64 {
    assert_eq!(got.len(), want.len());
    let rows = |s: &[SectionForces], r: std::ops::Range<usize>| -> Vec<f64> {
        s.iter()
            .flat_map(|f| {
                f.start[r.clone()]
                    .iter()
                    .chain(&f.end[r.clone()])
                    .copied()
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let mut worst: f64 = 0.0;
    for r in [0..3, 3..6] {
        let (g, w) = (rows(got, r.clone()), rows(want, r));
        let scale = max_abs(w.iter().copied());
        if scale == 0.0 {
            assert!(
                max_abs(g.iter().copied()) == 0.0,
                "expected zero, got {g:?}"
            );
            continue;
        }
        let d = max_abs(g.iter().zip(&w).map(|(a, b)| a - b));
        worst = worst.max(d / scale);
    }
    worst
}

fn forces_of(recovered: &[ElementForces]) -> Vec<SectionForces> {
    recovered.iter().map(|e| e.forces).collect()
}

fn element(model: &Model, id: usize) -> &Element {
    model.elements().iter().find(|e| e.id() == id).unwrap()
}

/// Section forces of a statics problem at every element end.
fn expected_statics(
    model: &Model,
    recovered: &[ElementForces],
    loads: &[PointLoad],
) -> Vec<SectionForces> {
    recovered
        .iter()
        .map(|r| {
            statics(
                r.start,
                r.end,
                &frame(model, element(model, r.element)),
                loads,
            )
        })
        .collect()
}

/// (a) Cantilever with loads at its tip: forces from statics at every
/// element end, in the frame of each element (every other element runs
/// backwards), and the tip deflection of beam theory, with the shear term
/// `P L / (G A_s)` for Timoshenko. The 3D beam lies skew in space and
/// carries all six tip loads; the planar one carries Fz and My.
#[test]
fn cantilever_with_tip_loads_matches_statics_and_tip_deflection() {
    let l = 1.5;
    for kind in KINDS {
        let p = kind.properties();
        let (a, dir, orientation) = match kind {
            Kind::Planar => ([0.2, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            Kind::Beam(_) => ([0.1, -0.2, 0.3], unit([1.0, 2.0, 2.0]), [0.3, 0.0, 1.0]),
        };
        let b = combine(&[(1.0, a), (l, dir)]);
        let n = 6;
        let tip = n as u64 + 1;
        let model = line(
            kind,
            n,
            a,
            b,
            orientation,
            |i| i % 2 == 1,
            all_dofs(kind, 1),
        );
        // Tip loads in the frame of the beam's forward direction.
        let ex = dir;
        let ey = unit(combine(&[(1.0, orientation), (-dot(orientation, ex), ex)]));
        let ez = cross(ex, ey);
        let local: [f64; 6] = match kind {
            Kind::Planar => [0.0, 0.0, 1.5e3, 0.0, 300.0, 0.0],
            Kind::Beam(_) => [3.0e3, -2.0e3, 1.5e3, 400.0, 300.0, -250.0],
        };
        let force = combine(&[(local[0], ex), (local[1], ey), (local[2], ez)]);
        let moment = combine(&[(local[3], ex), (local[4], ey), (local[5], ez)]);
        let loads: Vec<(Dof, f64)> = DofKind::ALL
            .iter()
            .enumerate()
            .map(|(c, k)| {
                (
                    Dof::new(tip, *k),
                    if c < 3 { force[c] } else { moment[c - 3] },
                )
            })
            .filter(|(d, _)| kind.dof_kinds().contains(&d.kind))
            .collect();
        let u = static_solution(&model, &loads);
        let zero = vec![0.0; u.len()];
        let recovered = section_forces(&model, &u, &zero).unwrap();
        assert_eq!(recovered.len(), n);
        // The clamp's reaction balances the tip loads.
        let point_loads = [
            PointLoad {
                at: b,
                force,
                moment,
            },
            PointLoad {
                at: a,
                force: force.map(|v| -v),
                moment: combine(&[(-1.0, moment), (-1.0, cross(sub(b, a), force))]),
            },
        ];
        let want = expected_statics(&model, &recovered, &point_loads);
        let dev = deviation(&forces_of(&recovered), &want);
        // measured 6e-12: exact up to round-off.
        assert!(dev < 5e-11, "{kind:?}: section forces deviate by {dev:e}");

        // Tip deflection (beam theory; Timoshenko adds the shear term).
        let s = &p.section;
        let g = p.material.shear_modulus;
        let timoshenko = matches!(kind, Kind::Beam(BeamTheory::Timoshenko));
        let shear = |f: f64, area: f64| if timoshenko { f * l / (g * area) } else { 0.0 };
        let [fx, fy, fz, mx, my, mz] = local;
        let want_tip = [
            fx * l / (E * s.area),
            fy * l.powi(3) / (3.0 * E * s.iz)
                + mz * l * l / (2.0 * E * s.iz)
                + shear(fy, s.shear_area_y),
            fz * l.powi(3) / (3.0 * E * s.iy) - my * l * l / (2.0 * E * s.iy)
                + shear(fz, s.shear_area_z),
            mx * l / (g * s.torsion),
            -fz * l * l / (2.0 * E * s.iy) + my * l / (E * s.iy),
            fy * l * l / (2.0 * E * s.iz) + mz * l / (E * s.iz),
        ];
        let m = node_motion(&model, &u, tip);
        let (ut, rt) = ([m[0], m[1], m[2]], [m[3], m[4], m[5]]);
        let got_tip = [
            dot(ut, ex),
            dot(ut, ey),
            dot(ut, ez),
            dot(rt, ex),
            dot(rt, ey),
            dot(rt, ez),
        ];
        for c in 0..6 {
            let scale = max_abs(want_tip[..3].iter().copied()).max(1e-300);
            let rscale = max_abs(want_tip[3..].iter().copied()).max(1e-300);
            let err = (got_tip[c] - want_tip[c]).abs() / if c < 3 { scale } else { rscale };
            // measured 4e-12: the two-node beams are exact for end loads.
            assert!(
                err < 5e-11,
                "{kind:?}: tip motion {c}: {} vs {}",
                got_tip[c],
                want_tip[c]
            );
        }
    }
}

/// The sign convention of `SectionForces`, spelt out on one clamped
/// element with tip loads `Fx = N0` (tension), `Fy = Fz = P`, `Mx = T0`:
/// on the positive cut face N > 0 in tension, `Qy = Qz = P`, `T = T0`,
/// and at the clamp `My = -P L`, `Mz = +P L` (the moment of P about the
/// cut: `L e_x x P e_z = -P L e_y`). An element running backwards (node 1
/// at the tip) has the frame `(-x, y, -z)` (3D) or `(-x, -y, z)` (planar).
#[test]
fn sign_convention_is_the_internal_force_on_the_positive_cut_face() {
    let (l, n0, p, t0) = (2.0, 5.0e3, 1.0e3, 200.0);
    for kind in [Kind::Beam(BeamTheory::EulerBernoulli), Kind::Planar] {
        for reversed in [false, true] {
            let model = line(
                kind,
                1,
                [0.0; 3],
                [l, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                |_| reversed,
                all_dofs(kind, 1),
            );
            let loads: Vec<(Dof, f64)> = [
                (DofKind::Ux, n0),
                (DofKind::Uy, p),
                (DofKind::Uz, p),
                (DofKind::Rx, t0),
            ]
            .into_iter()
            .filter(|(k, _)| kind.dof_kinds().contains(k))
            .map(|(k, v)| (Dof::new(2, k), v))
            .collect();
            let u = static_solution(&model, &loads);
            let f = section_forces(&model, &u, &vec![0.0; u.len()]).unwrap()[0].forces;
            // (at the clamp, at the tip) in element order.
            let (clamp, tip) = if reversed {
                (f.end, f.start)
            } else {
                (f.start, f.end)
            };
            let want_clamp: [f64; 6];
            let want_tip: [f64; 6];
            match (kind, reversed) {
                (Kind::Beam(_), false) => {
                    want_clamp = [n0, p, p, t0, -p * l, p * l];
                    want_tip = [n0, p, p, t0, 0.0, 0.0];
                }
                // Frame (-x, y, -z): the face and the frame turn; N, Qz, T
                // and Mz keep their sign, Qy and My change it.
                (Kind::Beam(_), true) => {
                    want_clamp = [n0, -p, p, t0, p * l, p * l];
                    want_tip = [n0, -p, p, t0, 0.0, 0.0];
                }
                (Kind::Planar, false) => {
                    want_clamp = [0.0, 0.0, p, 0.0, -p * l, 0.0];
                    want_tip = [0.0, 0.0, p, 0.0, 0.0, 0.0];
                }
                // Frame (-x, -y, z): Qz changes sign, My keeps it.
                (Kind::Planar, true) => {
                    want_clamp = [0.0, 0.0, -p, 0.0, -p * l, 0.0];
                    want_tip = [0.0, 0.0, -p, 0.0, 0.0, 0.0];
                }
            }
            for c in 0..6 {
                let scale = if c < 3 { n0 } else { p * l };
                // measured 2e-16 relative.
                assert!(
                    (clamp[c] - want_clamp[c]).abs() < 1e-13 * scale
                        && (tip[c] - want_tip[c]).abs() < 1e-13 * scale,
                    "{kind:?} reversed={reversed} {}: clamp {} vs {}, tip {} vs {}",
                    SectionForces::NAMES[c],
                    clamp[c],
                    want_clamp[c],
                    tip[c],
                    want_tip[c]
                );
            }
        }
    }
}

/// (b) Cantilever along x under uniform line loads (qz, qy, axial p,
/// torque m per length), applied as the consistent nodal loads of each
/// element (`q l/2` and `+-q l^2/12`). The nodal displacements are exact
/// (`q x^2 (6L^2 - 4Lx + x^2) / (24 E I)`, plus `q (L x - x^2/2) / (G A_s)`
/// for Timoshenko). Eq. 25 gives `K_e u_e`, the end forces of the element
/// as loaded through its nodes; a load on its own span is not in them, so
/// the recovered forces are the closed form `N = p (L - x)`, `Qz = q (L -
/// x)`, `My = -q (L - x)^2 / 2`, ... minus the element's consistent loads at
/// its start and plus them at its end (exactly so at the nodes).
#[test]
fn cantilever_under_line_loads_matches_beam_theory_at_the_nodes() {
    let (l, n) = (2.0, 8);
    let (px, qy, qz, mx) = (1.0e3, -1.5e3, 2.0e3, 300.0);
    for kind in KINDS {
        let p = kind.properties();
        let model = line(
            kind,
            n,
            [0.0; 3],
            [l, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            |_| false,
            all_dofs(kind, 1),
        );
        let le = l / n as f64;
        // Consistent loads of one element, [start, end] x [ux uy uz rx ry rz]
        // (ry = -dw/dx, rz = dv/dx).
        let eq_start = [
            px * le / 2.0,
            qy * le / 2.0,
            qz * le / 2.0,
            mx * le / 2.0,
            -qz * le * le / 12.0,
            qy * le * le / 12.0,
        ];
        let eq_end = [
            px * le / 2.0,
            qy * le / 2.0,
            qz * le / 2.0,
            mx * le / 2.0,
            qz * le * le / 12.0,
            -qy * le * le / 12.0,
        ];
        let mut loads = Vec::new();
        for i in 0..n as u64 {
            for (c, k) in DofKind::ALL.into_iter().enumerate() {
                if kind.dof_kinds().contains(&k) {
                    loads.push((Dof::new(i + 1, k), eq_start[c]));
                    loads.push((Dof::new(i + 2, k), eq_end[c]));
                }
            }
        }
        let loads: Vec<(Dof, f64)> = loads.into_iter().filter(|(d, _)| d.node != 1).collect();
        let u = static_solution(&model, &loads);
        let planar = matches!(kind, Kind::Planar);
        let on = |c: usize| !planar || c == 2 || c == 4;
        let internal = |x: f64| {
            let r = l - x;
            [
                px * r,
                qy * r,
                qz * r,
                mx * r,
                -qz * r * r / 2.0,
                qy * r * r / 2.0,
            ]
        };
        let recovered = section_forces(&model, &u, &vec![0.0; u.len()]).unwrap();
        let want: Vec<SectionForces> = recovered
            .iter()
            .map(|r| {
                let (s, e) = (internal(r.start[0]), internal(r.end[0]));
                SectionForces {
                    start: std::array::from_fn(|c| if on(c) { s[c] - eq_start[c] } else { 0.0 }),
                    end: std::array::from_fn(|c| if on(c) { e[c] + eq_end[c] } else { 0.0 }),
                }
            })
            .collect();
        let dev = deviation(&forces_of(&recovered), &want);
        // measured 1.5e-13.
        assert!(dev < 2e-12, "{kind:?}: section forces deviate by {dev:e}");

        // Nodal displacements and rotations against beam theory.
        let s = &p.section;
        let g = p.material.shear_modulus;
        let timoshenko = matches!(kind, Kind::Beam(BeamTheory::Timoshenko));
        let shear = |q: f64, area: f64, x: f64| {
            if timoshenko {
                q * (l * x - x * x / 2.0) / (g * area)
            } else {
                0.0
            }
        };
        let deflection = |q: f64, i: f64, x: f64| {
            q * x * x * (6.0 * l * l - 4.0 * l * x + x * x) / (24.0 * E * i)
        };
        let slope =
            |q: f64, i: f64, x: f64| q * x * (3.0 * l * l - 3.0 * l * x + x * x) / (6.0 * E * i);
        let mut worst: f64 = 0.0;
        for node in model.nodes() {
            let x = node.coords[0];
            let want = [
                px * (l * x - x * x / 2.0) / (E * s.area),
                deflection(qy, s.iz, x) + shear(qy, s.shear_area_y, x),
                deflection(qz, s.iy, x) + shear(qz, s.shear_area_z, x),
                mx * (l * x - x * x / 2.0) / (g * s.torsion),
                -slope(qz, s.iy, x),
                slope(qy, s.iz, x),
            ];
            let got = node_motion(&model, &u, node.id);
            for c in (0..6).filter(|c| on(*c)) {
                let scale = if c < 3 {
                    deflection(qz.abs(), s.iy, l)
                } else {
                    slope(qz.abs(), s.iy, l)
                };
                worst = worst.max((got[c] - want[c]).abs() / scale);
            }
        }
        // measured 4e-13: nodally exact.
        assert!(
            worst < 5e-12,
            "{kind:?}: nodal motion deviates by {worst:e}"
        );
    }
}

/// (c) Simply supported beam, central load P (in z, and for the 3D beam
/// also in y): `Qz = +-P/2`, `My = P x / 2` left of the load and `P (L - x)
/// / 2` right of it, `Qy = +-P/2`, `Mz = -P x / 2`; centre deflection
/// `P L^3 / (48 E I)` plus `P L / (4 G A_s)` for Timoshenko.
#[test]
fn simply_supported_beam_with_a_central_load() {
    let (l, n) = (2.0, 8);
    let (pz, py) = (2.0e3, -1.2e3);
    for kind in KINDS {
        let p = kind.properties();
        let last = n as u64 + 1;
        let fixed = match kind {
            Kind::Planar => vec![Dof::new(1, DofKind::Uz), Dof::new(last, DofKind::Uz)],
            Kind::Beam(_) => [
                Dof::new(1, DofKind::Ux),
                Dof::new(1, DofKind::Uy),
                Dof::new(1, DofKind::Uz),
                Dof::new(1, DofKind::Rx),
                Dof::new(last, DofKind::Uy),
                Dof::new(last, DofKind::Uz),
            ]
            .to_vec(),
        };
        let model = line(
            kind,
            n,
            [0.0; 3],
            [l, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            |_| false,
            fixed,
        );
        let planar = matches!(kind, Kind::Planar);
        let py = if planar { 0.0 } else { py };
        let centre = n as u64 / 2 + 1;
        let mut loads = vec![(Dof::new(centre, DofKind::Uz), pz)];
        if !planar {
            loads.push((Dof::new(centre, DofKind::Uy), py));
        }
        let u = static_solution(&model, &loads);
        let recovered = section_forces(&model, &u, &vec![0.0; u.len()]).unwrap();
        let closed = |x: f64, left: bool| -> [f64; 6] {
            let (q, m) = if left {
                (0.5, x / 2.0)
            } else {
                (-0.5, (l - x) / 2.0)
            };
            [0.0, q * py, q * pz, 0.0, m * pz, -m * py]
        };
        let want: Vec<SectionForces> = recovered
            .iter()
            .map(|r| {
                let left = (r.start[0] + r.end[0]) / 2.0 < l / 2.0;
                SectionForces {
                    start: closed(r.start[0], left),
                    end: closed(r.end[0], left),
                }
            })
            .collect();
        let dev = deviation(&forces_of(&recovered), &want);
        // measured 1e-13.
        assert!(dev < 2e-12, "{kind:?}: section forces deviate by {dev:e}");
        let s = &p.section;
        let g = p.material.shear_modulus;
        let timoshenko = matches!(kind, Kind::Beam(BeamTheory::Timoshenko));
        let centre_deflection = |f: f64, i: f64, area: f64| {
            f * l.powi(3) / (48.0 * E * i)
                + if timoshenko {
                    f * l / (4.0 * g * area)
                } else {
                    0.0
                }
        };
        let m = node_motion(&model, &u, centre);
        let wz = centre_deflection(pz, s.iy, s.shear_area_z);
        let wy = centre_deflection(py, s.iz, s.shear_area_y);
        // measured 3e-14 relative.
        assert!(
            (m[2] - wz).abs() < 1e-12 * wz.abs(),
            "{kind:?}: w {} vs {wz}",
            m[2]
        );
        assert!(
            (m[1] - wy).abs() < 1e-12 * wz.abs(),
            "{kind:?}: v {} vs {wy}",
            m[1]
        );
    }
}

/// Loads `[Fx, Fy, Fz, Mx]` at the end x = L of a free beam `[0, L]` along
/// global x accelerate it as a rigid body: axial `a = Fx / m`, twist
/// `Mx / (rho (Iy + Iz) L)`, and in each bending plane the translation `F /
/// m` and angular acceleration `beta = F (L/2) / J` with `J = rho A L^3 / 12
/// + rho I L` (the rotary term only if the element has rotary inertia).
struct Accelerated {
    l: f64,
    mu: f64,
    /// Rotary inertia per length about y and z (kg m).
    rot: [f64; 2],
    /// Axial and angular (about x) accelerations.
    axial: f64,
    twist: f64,
    /// Translation at the centre and angular acceleration, per plane (y, z).
    a0: [f64; 2],
    beta: [f64; 2],
    polar: f64,
}

impl Accelerated {
    fn new(p: &BeamProperties, l: f64, loads: [f64; 4]) -> Self {
        let s = &p.section;
        let mu = RHO * s.area;
        let rot = if p.rotary_inertia {
            [RHO * s.iy, RHO * s.iz]
        } else {
            [0.0; 2]
        };
        let polar = RHO * (s.iy + s.iz);
        let m = mu * l;
        let j = |r: f64| mu * l.powi(3) / 12.0 + r * l;
        Self {
            l,
            mu,
            rot,
            axial: loads[0] / m,
            twist: loads[3] / (polar * l),
            a0: [loads[1] / m, loads[2] / m],
            beta: [
                loads[1] * l / 2.0 / j(rot[1]),
                loads[2] * l / 2.0 / j(rot[0]),
            ],
            polar,
        }
    }

    /// Nodal accelerations `[ux, uy, uz, rx, ry, rz]` at x: `v'' = a0 +
    /// beta (x - L/2)` with `rz'' = beta_y`, and `w''` likewise with `ry'' =
    /// -beta_z` (ry = -dw/dx).
    fn acceleration(&self, x: f64) -> [f64; 6] {
        let c = x - self.l / 2.0;
        [
            self.axial,
            self.a0[0] + self.beta[0] * c,
            self.a0[1] + self.beta[1] * c,
            self.twist,
            -self.beta[1],
            self.beta[0],
        ]
    }

    /// d'Alembert on the part `[0, x]`: `Q = mu int_0^x a ds`, `My = mu
    /// int_0^x (x - s) w'' ds - rho Iy beta_z x`, `Mz = -mu int_0^x (x - s)
    /// v'' ds + rho Iz beta_y x`, `N = mu a x`, `T = rho (Iy + Iz) alpha x`.
    fn section_forces(&self, x: f64) -> [f64; 6] {
        let (l, mu) = (self.l, self.mu);
        let shear = |p: usize| mu * (self.a0[p] * x + self.beta[p] * (x * x / 2.0 - l * x / 2.0));
        let moment = |p: usize| {
            mu * (self.a0[p] * x * x / 2.0 + self.beta[p] * (x.powi(3) / 6.0 - l * x * x / 4.0))
        };
        [
            mu * self.axial * x,
            shear(0),
            shear(1),
            self.polar * self.twist * x,
            moment(1) - self.rot[0] * self.beta[1] * x,
            -(moment(0) - self.rot[1] * self.beta[0] * x),
        ]
    }
}

/// Accelerations over the model's equations of the rigid-body motion.
fn acceleration_vector(model: &Model, acc: &Accelerated) -> Vec<f64> {
    let mut a = vec![0.0; model.dof_map().len()];
    for (i, d) in model.dof_map().dofs().iter().enumerate() {
        let x = model.coords(d.node)[0];
        a[i] = acc.acceleration(x)[d.kind.index()];
    }
    a
}

/// The quasi-static state of a free beam under end loads `f`: the rigid
/// acceleration `a` and the deformation `u` with `K u = f - M a`, solved
/// with node 1 held (the right-hand side is balanced, so the reaction
/// `K u - f + M a` there vanishes; the returned figure is its largest
/// value relative to the largest load).
fn accelerated_state(model: &Model, f: &[f64], acc: &Accelerated) -> (Vec<f64>, Vec<f64>, f64) {
    let (k, m) = dense_matrices(model);
    let a = acceleration_vector(model, acc);
    let ma = mat_vec(&m, &a);
    let rhs: Vec<f64> = f.iter().zip(&ma).map(|(x, y)| x - y).collect();
    let held: Vec<bool> = model.dof_map().dofs().iter().map(|d| d.node == 1).collect();
    let free: Vec<usize> = (0..f.len()).filter(|i| !held[*i]).collect();
    let kff: Vec<Vec<f64>> = free
        .iter()
        .map(|&i| free.iter().map(|&j| k[i][j]).collect())
        .collect();
    let uf = solve(kff, free.iter().map(|&i| rhs[i]).collect());
    let mut u = vec![0.0; f.len()];
    for (&i, v) in free.iter().zip(uf) {
        u[i] = v;
    }
    let ku = mat_vec(&k, &u);
    let unbalance = max_abs((0..f.len()).filter(|i| held[*i]).map(|i| ku[i] - rhs[i]))
        / max_abs(f.iter().copied());
    (u, a, unbalance)
}

/// (d) A free beam accelerated by loads at its end, in both bending planes,
/// axially and in torsion: the recovered forces `K_e u_e + M_e a_e` must
/// be the d'Alembert forces of the rigid-body motion (cubic beams with
/// consistent mass are exact at the nodes for this linear acceleration
/// field, rotary inertia included).
#[test]
fn free_beam_accelerated_by_end_loads_matches_dalembert() {
    let (l, n) = (2.0, 8);
    let loads = [3.0e3, -2.0e3, 1.5e3, 400.0];
    let mut with_rotary = props(BeamTheory::EulerBernoulli);
    with_rotary.rotary_inertia = true;
    let cases: Vec<(Kind, Option<BeamProperties>)> = vec![
        (Kind::Planar, None),
        (Kind::Beam(BeamTheory::EulerBernoulli), None),
        (Kind::Beam(BeamTheory::EulerBernoulli), Some(with_rotary)),
        (Kind::Beam(BeamTheory::Timoshenko), None),
    ];
    for (kind, properties) in cases {
        let mut model = line(
            kind,
            n,
            [0.0; 3],
            [l, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            |_| false,
            vec![],
        );
        let has_own = properties.is_some();
        let p = properties.unwrap_or_else(|| kind.properties());
        if has_own {
            let elements = model
                .elements()
                .iter()
                .map(|e| match e {
                    Element::Beam(b) => Element::Beam(Beam {
                        properties: p.clone(),
                        ..b.clone()
                    }),
                    e => e.clone(),
                })
                .collect();
            model = Model::new(
                model.nodes().to_vec(),
                elements,
                BTreeMap::new(),
                vec![],
                None,
            )
            .unwrap();
        }
        let planar = matches!(kind, Kind::Planar);
        let loads = if planar {
            [0.0, 0.0, loads[2], 0.0]
        } else {
            loads
        };
        let acc = Accelerated::new(&p, l, loads);
        let tip = n as u64 + 1;
        let f = load_vector(
            &model,
            &[DofKind::Ux, DofKind::Uy, DofKind::Uz, DofKind::Rx]
                .iter()
                .zip(loads)
                .filter(|(k, _)| kind.dof_kinds().contains(k))
                .map(|(k, v)| (Dof::new(tip, *k), v))
                .collect::<Vec<_>>(),
        );
        let (u, a, unbalance) = accelerated_state(&model, &f, &acc);
        // measured 3e-14: the consistent mass carries the exact rigid-body
        // mass and inertia, so the end loads balance the inertia exactly.
        assert!(unbalance < 1e-12, "{kind:?}: unbalanced by {unbalance:e}");
        let recovered = section_forces(&model, &u, &a).unwrap();
        let want: Vec<SectionForces> = recovered
            .iter()
            .map(|r| SectionForces {
                start: acc.section_forces(r.start[0]),
                end: acc.section_forces(r.end[0]),
            })
            .collect();
        let dev = deviation(&forces_of(&recovered), &want);
        // measured 1.6e-13.
        assert!(
            dev < 2e-12,
            "{kind:?} rotary={}: section forces deviate by {dev:e}",
            p.rotary_inertia
        );
    }
}

/// Euler-Bernoulli cantilever `[0, L]` clamped at 0 with a harmonic end
/// force F at `Omega`: `w = A (cosh kx - cos kx) + B (sinh kx - sin kx)`,
/// `k^4 = mu Omega^2 / (E I)`, with `w''(L) = 0` and `-E I w'''(L) = F`.
/// Returns `(E I w'', -E I w''')` at x, i.e. the bending moment in the
/// x-y plane (`Mz = E Iz v''`) and the shear force (Q = -E I w''').
fn harmonic_cantilever(ei: f64, mu: f64, l: f64, omega: f64, force: f64, x: f64) -> (f64, f64) {
    let k = (mu * omega * omega / ei).powf(0.25);
    let (ch, sh, c, s) = ((k * l).cosh(), (k * l).sinh(), (k * l).cos(), (k * l).sin());
    let d = 2.0 + 2.0 * ch * c;
    let g = force / (ei * k.powi(3) * d);
    let (a, b) = ((sh + s) * g, -(ch + c) * g);
    let (chx, shx, cx, sx) = ((k * x).cosh(), (k * x).sinh(), (k * x).cos(), (k * x).sin());
    let w2 = k * k * (a * (chx + cx) + b * (shx + sx));
    let w3 = k.powi(3) * (a * (shx - sx) + b * (chx + cx));
    (ei * w2, -ei * w3)
}

/// (d, harmonic) A cantilever driven at its tip by `Fy`, `Fz` at `Omega`
/// below and between the first two bending frequencies: the forces from
/// `harmonic_section_forces` (`a = -Omega^2 u`) against the dynamic beam
/// solution, which the FE state approaches as the mesh is refined (the
/// tolerance is the discretisation error of 40 elements).
#[test]
fn harmonic_cantilever_matches_the_dynamic_beam_solution() {
    let (l, n): (f64, usize) = (2.0, 40);
    let (fy, fz) = (-1.2e3, 2.0e3);
    let s = section();
    let mu = RHO * s.area;
    // First bending frequency (x-y plane, the weaker one): (1.8751)^2
    // sqrt(E Iz / (mu L^4)) (Euler-Bernoulli cantilever).
    let omega1 = 1.875_104_068_7_f64.powi(2) * (E * s.iz / (mu * l.powi(4))).sqrt();
    for kind in [Kind::Planar, Kind::Beam(BeamTheory::EulerBernoulli)] {
        for ratio in [0.6, 2.5] {
            let omega = ratio * omega1;
            let model = line(
                kind,
                n,
                [0.0; 3],
                [l, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                |_| false,
                all_dofs(kind, 1),
            );
            let planar = matches!(kind, Kind::Planar);
            let fy = if planar { 0.0 } else { fy };
            let tip = n as u64 + 1;
            let mut loads = vec![(Dof::new(tip, DofKind::Uz), fz)];
            if !planar {
                loads.push((Dof::new(tip, DofKind::Uy), fy));
            }
            let (k, m) = dense_matrices(&model);
            let dyn_k: Vec<Vec<f64>> = k
                .iter()
                .zip(&m)
                .map(|(kr, mr)| {
                    kr.iter()
                        .zip(mr)
                        .map(|(a, b)| a - omega * omega * b)
                        .collect()
                })
                .collect();
            let u = solve(dyn_k, load_vector(&model, &loads));
            let recovered = harmonic_section_forces(&model, &u, omega).unwrap();
            let closed = |x: f64| {
                let (mz, qy) = harmonic_cantilever(E * s.iz, mu, l, omega, fy, x);
                let (ey_w2, qz) = harmonic_cantilever(E * s.iy, mu, l, omega, fz, x);
                // My = -E Iy w''.
                [0.0, qy, qz, 0.0, -ey_w2, mz]
            };
            let want: Vec<SectionForces> = recovered
                .iter()
                .map(|r| SectionForces {
                    start: closed(r.start[0]),
                    end: closed(r.end[0]),
                })
                .collect();
            let dev = deviation(&forces_of(&recovered), &want);
            // measured 1.2e-9 (0.6 omega_1) and 2.3e-8 (2.5 omega_1): the
            // discretisation error of 40 elements, loose for that reason.
            assert!(dev < 1e-7, "{kind:?} at {ratio} omega_1: deviation {dev:e}");
        }
    }
}

/// Modal section-force matrices of a Craig-Bampton body (interface: the
/// six tip DOFs, so the constraint modes hold the static response to tip
/// loads): `S_K q` with `K_red q = T^T f` must give the statics of the
/// cantilever at every element.
#[test]
fn modal_recovery_of_a_craig_bampton_cantilever_matches_statics() {
    let l = 1.5;
    let kind = Kind::Beam(BeamTheory::Timoshenko);
    let (a, dir, orientation) = ([0.1, -0.2, 0.3], unit([1.0, 2.0, 2.0]), [0.3, 0.0, 1.0]);
    let b = combine(&[(1.0, a), (l, dir)]);
    let n = 6;
    let tip = n as u64 + 1;
    let model = line(
        kind,
        n,
        a,
        b,
        orientation,
        |i| i % 3 == 2,
        all_dofs(kind, 1),
    );
    let substructure = Substructure::from_model(&model).unwrap();
    let interface = all_dofs(kind, tip);
    let body = reduce(
        &substructure,
        &Reduction::new(Method::CraigBampton, 3, interface),
    )
    .unwrap();
    let force = [1.2e3, -2.5e3, 0.8e3];
    let moment = [150.0, -90.0, 220.0];
    let loads: Vec<(Dof, f64)> = DofKind::ALL
        .iter()
        .enumerate()
        .map(|(c, k)| {
            (
                Dof::new(tip, *k),
                if c < 3 { force[c] } else { moment[c - 3] },
            )
        })
        .collect();
    let f = load_vector(&model, &loads);
    let r = body.r();
    let t = |i: usize, j: usize| body.basis[(i, j)];
    let f_red: Vec<f64> = (0..r)
        .map(|j| (0..f.len()).map(|i| t(i, j) * f[i]).sum())
        .collect();
    let k_red: Vec<Vec<f64>> = (0..r)
        .map(|i| (0..r).map(|j| body.stiffness[(i, j)]).collect())
        .collect();
    let q = solve(k_red, f_red);
    let recovery = ModalRecovery::new(&model, &body).unwrap();
    assert_eq!(recovery.elements.len(), n);
    let point_loads = [
        PointLoad {
            at: b,
            force,
            moment,
        },
        PointLoad {
            at: a,
            force: force.map(|v| -v),
            moment: combine(&[(-1.0, moment), (-1.0, cross(sub(b, a), force))]),
        },
    ];
    let zero = vec![0.0; r];
    let mut got = Vec::new();
    let mut want = Vec::new();
    for (k, &id) in recovery.elements.iter().enumerate() {
        let e = element(&model, id);
        let nodes = e.nodes();
        got.push(recovery.forces(k, &q, &zero));
        want.push(statics(
            model.coords(nodes[0]),
            model.coords(nodes[1]),
            &frame(&model, e),
            &point_loads,
        ));
    }
    let dev = deviation(&got, &want);
    // measured 3.6e-12.
    assert!(dev < 3e-11, "deviation {dev:e}");
}

/// Modal section-force matrices of a free-residual body (rigid-body modes
/// plus inertia-relief attachment modes of the tip DOFs): the quasi-static
/// reduced state under tip loads — rigid accelerations `q''_R` and elastic
/// coordinates `q_E` from `M_red q'' + K_red q = T^T f` — must give the
/// d'Alembert forces of the accelerated beam through `S_K q + S_M q''`.
#[test]
fn modal_recovery_of_a_free_residual_body_matches_dalembert() {
    let (l, n) = (2.0, 8);
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let kind = Kind::Beam(theory);
        let model = line(
            kind,
            n,
            [0.0; 3],
            [l, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            |_| false,
            vec![],
        );
        let tip = n as u64 + 1;
        let sub = Substructure::from_model(&model).unwrap();
        let body = reduce(
            &sub,
            &Reduction::new(Method::FreeResidual, 3, all_dofs(kind, tip)),
        )
        .unwrap();
        let loads = [3.0e3, -2.0e3, 1.5e3, 400.0];
        let f = load_vector(
            &model,
            &[DofKind::Ux, DofKind::Uy, DofKind::Uz, DofKind::Rx]
                .iter()
                .zip(loads)
                .map(|(k, v)| (Dof::new(tip, *k), v))
                .collect::<Vec<_>>(),
        );
        let r = body.r();
        let rigid: Vec<bool> = body
            .modes
            .iter()
            .map(|m| matches!(m, ModeKind::Rigid { .. }))
            .collect();
        assert_eq!(rigid.iter().filter(|r| **r).count(), 6);
        // Unknowns: q''_j of the rigid columns, q_j of the others.
        let a_mat: Vec<Vec<f64>> = (0..r)
            .map(|i| {
                (0..r)
                    .map(|j| {
                        if rigid[j] {
                            body.mass[(i, j)]
                        } else {
                            body.stiffness[(i, j)]
                        }
                    })
                    .collect()
            })
            .collect();
        let f_red: Vec<f64> = (0..r)
            .map(|j| (0..f.len()).map(|i| body.basis[(i, j)] * f[i]).sum())
            .collect();
        let x = solve(a_mat, f_red);
        let q: Vec<f64> = (0..r).map(|j| if rigid[j] { 0.0 } else { x[j] }).collect();
        let q_dd: Vec<f64> = (0..r).map(|j| if rigid[j] { x[j] } else { 0.0 }).collect();
        let acc = Accelerated::new(&kind.properties(), l, loads);
        let recovery = ModalRecovery::new(&model, &body).unwrap();
        let mut got = Vec::new();
        let mut want = Vec::new();
        for (k, &id) in recovery.elements.iter().enumerate() {
            let nodes = element(&model, id).nodes();
            got.push(recovery.forces(k, &q, &q_dd));
            want.push(SectionForces {
                start: acc.section_forces(model.coords(nodes[0])[0]),
                end: acc.section_forces(model.coords(nodes[1])[0]),
            });
        }
        let dev = deviation(&got, &want);
        // measured 2.4e-14.
        assert!(dev < 1e-12, "{theory:?}: deviation {dev:e}");
    }
}
