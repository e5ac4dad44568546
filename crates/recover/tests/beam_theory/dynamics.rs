//! Beams in motion: a free beam accelerated by end loads (d'Alembert) and a
//! cantilever in harmonic motion.

use crate::beams::*;
use crate::common::{dense_matrices, load_vector, solve};
use flexbody_fem::mesh::BeamLine;
use flexbody_fem::{BeamProperties, BeamTheory, Dof, DofKind, SectionForces};
use flexbody_recover::{harmonic_section_forces, section_forces};

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
        let p = properties.unwrap_or_else(|| kind.properties());
        let model = BeamLine {
            cells: n,
            start: [0.0; 3],
            end: [l, 0.0, 0.0],
            kind: kind.line_kind([0.0, 1.0, 0.0]),
            properties: p.clone(),
        }
        .model(vec![])
        .unwrap();
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
            let model = along_x(kind, n, l, all_dofs(kind, 1));
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
