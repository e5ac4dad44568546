//! Beams at rest: cantilevers under end and line loads, the sign
//! convention, a simply supported beam.

use crate::beams::*;
use crate::common::{max_abs, static_solution};
use flexbody_fem::{BeamTheory, Dof, DofKind, SectionForces};
use flexbody_recover::section_forces;

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
        let placement = match kind {
            Kind::Planar => ([0.2, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            Kind::Beam(_) => skew(),
        };
        let (a, dir, orientation) = placement;
        let b = combine(&[(1.0, a), (l, dir)]);
        let n = 6;
        let tip = n as u64 + 1;
        let model = cantilever(kind, n, l, placement, |i| i % 2 == 1);
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
        let loads: Vec<(Dof, f64)> = node_loads(tip, force, moment)
            .into_iter()
            .filter(|(d, _)| kind.dof_kinds().contains(&d.kind))
            .collect();
        let u = static_solution(&model, &loads);
        let zero = vec![0.0; u.len()];
        let recovered = section_forces(&model, &u, &zero).unwrap();
        assert_eq!(recovered.len(), n);
        // The clamp's reaction balances the tip loads.
        let point_loads = tip_load_and_reaction(a, b, force, moment);
        let want = expected_statics(&model, &recovered, &point_loads);
        let dev = deviation(&forces_of(&recovered), &want);
        // measured 6e-12: exact up to round-off.
        assert!(dev < 5e-11, "{kind:?}: section forces deviate by {dev:e}");

        // Tip deflection (beam theory; Timoshenko adds the shear term).
        let s = &p.section;
        let g = p.material.shear_modulus;
        let shear = |f: f64, area: f64| shear_deflection(kind, f * l, area);
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
        let model = along_x(kind, n, l, all_dofs(kind, 1));
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
        let shear =
            |q: f64, area: f64, x: f64| shear_deflection(kind, q * (l * x - x * x / 2.0), area);
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
        let model = along_x(kind, n, l, fixed);
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
        let centre_deflection = |f: f64, i: f64, area: f64| {
            f * l.powi(3) / (48.0 * E * i) + shear_deflection(kind, f * l / 4.0, area)
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
