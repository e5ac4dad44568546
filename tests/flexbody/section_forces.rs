//! Section forces on the side beam (section 6): from Ritz coordinates and
//! from displacements, in balance with the springs, and in equilibrium with
//! the springs and the inertia.

use super::study::{ELEMENT, HEAVE, RHO_A, STATIC};
use super::support::unit_translation;
use flexbody::fem::{Dof, DofKind, Substructure};
use flexbody::mbs::FlexibleBody;
use flexbody::recover::{harmonic_section_forces, ModalRecovery};
use flexbody::reduce::Method;
use flexbody::scenario::read_model_file;
use flexbody::study::respond;

#[test]
fn section_forces_from_ritz_coordinates_equal_those_from_displacements() {
    // Eq. 25 with modal section-force matrices S_K = K_e T_e, S_M = M_e T_e.
    let (file, _, body) = super::side_beam_body(Method::FreeResidual, 1);
    let recovery = ModalRecovery::new(&file.model, &body).unwrap();
    let system = file.system(FlexibleBody::Reduced(&body));
    let r = flexbody::mbs::harmonic_response(&system, HEAVE).unwrap();
    let q = &r.flexible_coords[0].0;
    let q_dd: Vec<f64> = q.iter().map(|v| -HEAVE * HEAVE * v).collect();
    let direct = harmonic_section_forces(&file.model, &r.flexible[0].0, HEAVE).unwrap();
    assert_eq!(recovery.elements.len(), 20);
    let scale = direct
        .iter()
        .map(|e| e.forces.end[2].abs())
        .fold(0.0, f64::max);
    for (k, e) in direct.iter().enumerate() {
        let modal = recovery.forces(k, q, &q_dd);
        for c in 0..6 {
            assert!((modal.start[c] - e.forces.start[c]).abs() < 1e-9 * scale);
            assert!((modal.end[c] - e.forces.end[c]).abs() < 1e-9 * scale);
        }
    }
}

#[test]
fn section_forces_balance_the_spring_forces() {
    // Equilibrium at the spring seats: the jump of Q across a seat equals
    // the spring's tension T (the force on the beam is -T, the elongation
    // being the node's displacement against the other end), and the free
    // ends carry it: Q(0) = T_1, Q(2.5 m) = -T_21. Over the whole beam the
    // spring forces balance the inertia, sum T = Omega^2 (1^T M u) over the
    // uz DOFs (M from the assembly, not from the element recovery).
    let file = read_model_file(&super::side_beam_path()).unwrap();
    let sub = Substructure::from_model(&file.model).unwrap();
    let ones = unit_translation(&sub, DofKind::Uz);
    for omega in [STATIC, HEAVE] {
        let full = FlexibleBody::Full {
            dof_map: &sub.dof_map,
            matrices: &sub.matrices,
        };
        let resp = respond(&file, full, omega).unwrap();
        let tension: Vec<f64> = resp.forces.iter().map(|f| f.0).collect();
        let scale = tension.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
        // Q at element ends: resp.q.re[2 (e - 1)] starts element e, [2 e - 1]
        // ends it; element e spans nodes e and e + 1.
        let q = &resp.q.re;
        let jumps = [
            ("primary_front", q[0], tension[0]),
            ("primary_rear", -q[39], tension[1]),
            (
                "secondary_front, node 7",
                q[2 * 6] - q[2 * 5 + 1],
                tension[2],
            ),
            (
                "secondary_rear, node 15",
                q[2 * 14] - q[2 * 13 + 1],
                tension[3],
            ),
        ];
        for (seat, jump, t) in jumps {
            // measured up to 8.5e-11 of the largest force
            assert!(
                (jump - t).abs() < 5e-10 * scale,
                "{omega}: {seat}: jump {jump} vs tension {t}"
            );
        }
        // No jump at the nodes without a spring.
        for node in (2..21).filter(|n| *n != 7 && *n != 15) {
            let jump = q[2 * (node - 1)] - q[2 * (node - 1) - 1];
            assert!(jump.abs() < 1e-9 * scale, "{omega}: node {node}: {jump}");
        }
        let (_, (u, _)) = full_solution(&file, &sub, omega);
        let m = &sub.matrices.mass;
        let mu = m * faer::Mat::from_fn(u.len(), 1, |i, _| u[i]);
        let inertia: f64 = omega * omega * (0..u.len()).map(|i| ones[i] * mu[(i, 0)]).sum::<f64>();
        let total: f64 = tension.iter().sum();
        // measured 2.0e-10 (static) and 1.8e-10 (122 rad/s, where the
        // inertia is 2.5 times the largest spring force)
        assert!(
            (total - inertia).abs() < 1e-9 * scale,
            "{omega}: sum of tensions {total} vs inertia {inertia}"
        );
    }
}

/// The full model in the example's MBS at `omega`: the response and the
/// FE displacements (re, im).
fn full_solution(
    file: &flexbody::scenario::ModelFile,
    sub: &Substructure,
    omega: f64,
) -> (flexbody::mbs::HarmonicResponse, (Vec<f64>, Vec<f64>)) {
    let system = file.system(FlexibleBody::Full {
        dof_map: &sub.dof_map,
        matrices: &sub.matrices,
    });
    let r = flexbody::mbs::harmonic_response(&system, omega).unwrap();
    let u = r.flexible[0].clone();
    (r, u)
}

/// `(Qz, My)` at the start and the end of each of the side beam's 20
/// elements from equilibrium alone, without the element matrices. From
/// the free end at x = 0 (Q = -F_1, M = 0), each element of length L
/// carries the d'Alembert load `-rho A a(x)`, `a` the cubic (Hermite)
/// interpolation of the nodal accelerations `-omega^2 (w, dw/dx)`,
///   `Q_end = Q_start + rho A int_0^L a dx`,
///   `M_end = M_start + L Q_end - rho A int_0^L x a dx`
/// (My about +y: a force F_z at x has the moment -x F_z), with
/// `int N dx = (L/2, L^2/12, L/2, -L^2/12)` and
/// `int x N dx = (3 L^2/20, L^3/30, 7 L^2/20, -L^3/20)`; at node j the
/// external force F_j makes Q jump by -F_j. Returns per element
/// `[Q_start, M_start, Q_end, M_end]`, and the Q and M left beyond the
/// last node (zero in equilibrium).
fn equilibrium_section_forces(
    w: &[f64],
    slope: &[f64],
    nodal_force: &[f64],
    omega: f64,
) -> (Vec<[f64; 4]>, [f64; 2]) {
    let l = ELEMENT;
    let a = |v: f64| -omega * omega * v;
    let (mut q, mut m) = (-nodal_force[0], 0.0);
    let mut out = Vec::new();
    for e in 0..w.len() - 1 {
        let n = [a(w[e]), a(slope[e]), a(w[e + 1]), a(slope[e + 1])];
        let int_a = l / 2.0 * n[0] + l * l / 12.0 * n[1] + l / 2.0 * n[2] - l * l / 12.0 * n[3];
        let int_xa =
            3.0 * l * l / 20.0 * n[0] + l.powi(3) / 30.0 * n[1] + 7.0 * l * l / 20.0 * n[2]
                - l.powi(3) / 20.0 * n[3];
        let (q0, m0) = (q, m);
        q += RHO_A * int_a;
        m += l * q - RHO_A * int_xa;
        out.push([q0, m0, q, m]);
        q -= nodal_force[e + 1];
    }
    (out, [q, m])
}

#[test]
fn section_forces_are_in_equilibrium_with_the_springs_and_the_inertia() {
    // The recovered Qz and My of the full model, and those of the
    // free-residual body from its Ritz coordinates (eq. 25), against the
    // beam's equilibrium written out above from the full model's nodal
    // displacements and spring forces k (w_j - z_j) computed here from the
    // file's stiffnesses and track (no element matrix, no MBS force).
    let (file, sub, body) = super::side_beam_body(Method::FreeResidual, 1);
    let recovery = ModalRecovery::new(&file.model, &body).unwrap();
    let a = file.track.unwrap().amplitude;
    // (node, stiffness, other end's displacement): primaries on the track
    // (a cos(2 pi x / L_w) = a at x = 0 and x = L_w = 2.5 m), secondaries
    // on the car body at rest.
    let seats = [
        (1, 1.0e6, a),
        (21, 1.0e6, a),
        (7, 0.25e6, 0.0),
        (15, 0.25e6, 0.0),
    ];
    for omega in [STATIC, HEAVE] {
        let (r, (u, u_im)) = full_solution(&file, &sub, omega);
        // Undamped: only the track's phase at x = 2.5 m (sin 2 pi) is not real.
        let re = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(u_im.iter().all(|v| v.abs() < 1e-12 * re), "undamped");
        let value = |n: u64, kind| file.model.value(Dof::new(n, kind), &u);
        let w: Vec<f64> = (1..=21).map(|n| value(n, DofKind::Uz)).collect();
        let slope: Vec<f64> = (1..=21).map(|n| -value(n, DofKind::Ry)).collect();
        let mut nodal_force = vec![0.0; 21];
        for (k, &(node, c, z)) in seats.iter().enumerate() {
            let f = -c * (w[node as usize - 1] - z);
            nodal_force[node as usize - 1] = f;
            // The MBS's tension is minus the force on the node.
            assert!(
                (r.forces[k].0 + f).abs() < 1e-12 * f.abs(),
                "{omega}: seat {node}: {} vs {f}",
                r.forces[k].0
            );
        }
        let (reference, rest) = equilibrium_section_forces(&w, &slope, &nodal_force, omega);
        let q_scale = reference
            .iter()
            .fold(0.0_f64, |s, v| s.max(v[0].abs()).max(v[2].abs()));
        let m_scale = reference
            .iter()
            .fold(0.0_f64, |s, v| s.max(v[1].abs()).max(v[3].abs()));
        // The full solution is in equilibrium: nothing is left beyond the
        // far end (measured 2.0e-10 of the largest Q, 3.5e-10 of the largest M).
        assert!(
            rest[0].abs() < 1e-9 * q_scale && rest[1].abs() < 1e-9 * m_scale,
            "{omega}: {rest:?}"
        );
        let direct = harmonic_section_forces(&file.model, &u, omega).unwrap();
        let worst = |get: &dyn Fn(usize) -> [f64; 4]| {
            let mut err = [0.0_f64; 2];
            for (e, want) in reference.iter().enumerate() {
                let got = get(e);
                err[0] = err[0]
                    .max((got[0] - want[0]).abs())
                    .max((got[2] - want[2]).abs());
                err[1] = err[1]
                    .max((got[1] - want[1]).abs())
                    .max((got[3] - want[3]).abs());
            }
            [err[0] / q_scale, err[1] / m_scale]
        };
        let full_err = worst(&|e| {
            let f = &direct[e].forces;
            [f.start[2], f.start[4], f.end[2], f.end[4]]
        });
        // measured [Q, M]: [2.1e-10, 2.1e-10] static, [1.9e-10, 3.5e-10] at
        // 122 rad/s
        assert!(
            full_err[0] < 2e-9 && full_err[1] < 2e-9,
            "{omega}: full model {full_err:?}"
        );
        // The reduced body in the same MBS, recovered from q alone.
        let system = file.system(FlexibleBody::Reduced(&body));
        let red = flexbody::mbs::harmonic_response(&system, omega).unwrap();
        let q = &red.flexible_coords[0].0;
        let q_dd: Vec<f64> = q.iter().map(|v| -omega * omega * v).collect();
        let reduced_err = worst(&|e| {
            let f = recovery.forces(e, q, &q_dd);
            [f.start[2], f.start[4], f.end[2], f.end[4]]
        });
        // measured [Q, M]: [1.4e-10, 2.1e-10] statically, [6.7e-5, 1.4e-5] at
        // 122 rad/s (the study's errors: the modes the basis leaves out)
        let bound = if omega == STATIC {
            [1e-9, 1e-9]
        } else {
            [2e-4, 5e-5]
        };
        assert!(
            reduced_err[0] < bound[0] && reduced_err[1] < bound[1],
            "{omega}: reduced {reduced_err:?}"
        );
    }
}
