//! Plates and a ring against published frequencies and closed forms.
//!
//! References:
//! - NAFEMS, "Selected Benchmarks for Natural Frequency Analysis" (R0015,
//!   1987) and its Benchmark newsletter: the thin simply supported square
//!   plate (10 x 10 x 0.05 m: 2.377, 5.942, 5.942, 9.507 Hz), the thick
//!   one (test 21, 1 m thick: 45.897, 109.44, 109.44, 167.89 Hz, from
//!   Mindlin's closed form with k = pi^2/12), FV12 (free thin plate:
//!   1.622, 2.360, 2.922, 4.233, 4.233, 7.416 Hz) and FV16 (cantilevered
//!   thin plate: 0.421, 1.029, 2.582, 3.306, 3.753, 6.555 Hz); E = 200 GPa,
//!   nu = 0.3, rho = 8000 kg/m^3.
//! - Kirchhoff's simply supported plate, `omega = pi^2 (m^2 + n^2) / a^2
//!   sqrt(D / (rho h))`, and Mindlin's (Leissa, "Vibration of Plates",
//!   NASA SP-160, 1969).
//! - The thin ring's in-plane bending, `omega_n = sqrt(E I / (rho A R^4))
//!   n (n^2 - 1) / sqrt(n^2 + 1)` (Blevins, "Formulas for Natural Frequency
//!   and Mode Shape", 1979).

use super::*;
use std::f64::consts::PI;

const SIDE: f64 = 10.0;

/// A square plate `SIDE x SIDE` of `n x n` cells of `kind`, `thickness`
/// thick, in the x-y plane, with the supports NAFEMS gives its shell
/// tests: `ux, uy, rz` held at every node (no membrane, no drilling) and
/// `edges` applied to the nodes on the edges.
fn plate(kind: ShellKind, n: usize, thickness: f64, edges: Edges) -> Model {
    let h = SIDE / n as f64;
    plate_on(kind, n, thickness, edges, |i, j| [h * i, h * j, 0.0])
}

/// [`plate`] with its nodes at `position(i, j)` of their grid position.
fn plate_on(
    kind: ShellKind,
    n: usize,
    thickness: f64,
    edges: Edges,
    position: impl Fn(f64, f64) -> [f64; 3],
) -> Model {
    let grid = Grid::new(kind, [n, n], &nafems_steel(), thickness, position);
    let mut fixed = Vec::new();
    for (i, j, node) in grid.each() {
        fixed.extend(at(node, &[DofKind::Ux, DofKind::Uy, DofKind::Rz]));
        let last = n as f64;
        let (x_edge, y_edge) = (i == 0.0 || i == last, j == 0.0 || j == last);
        match edges {
            Edges::Free => {}
            Edges::SimplySupported => {
                if x_edge || y_edge {
                    fixed.push(Dof::new(node, DofKind::Uz));
                }
                if x_edge {
                    fixed.push(Dof::new(node, DofKind::Rx));
                }
                if y_edge {
                    fixed.push(Dof::new(node, DofKind::Ry));
                }
            }
            Edges::ClampedAtXZero => {
                if i == 0.0 {
                    fixed.extend(at(node, &[DofKind::Uz, DofKind::Rx, DofKind::Ry]));
                }
            }
        }
    }
    fixed.sort_unstable_by_key(|d| (d.node, d.kind as u8));
    fixed.dedup();
    grid.model(fixed)
}

#[derive(Clone, Copy)]
enum Edges {
    Free,
    SimplySupported,
    ClampedAtXZero,
}

/// Kirchhoff: the simply supported square plate's `(m, n)` frequency (Hz).
fn kirchhoff(m: f64, n: f64, thickness: f64) -> f64 {
    let (e, nu, rho) = (200e9, 0.3, 8000.0);
    let d = e * thickness.powi(3) / (12.0 * (1.0 - nu * nu));
    PI / 2.0 * (m * m + n * n) / (SIDE * SIDE) * (d / (rho * thickness)).sqrt()
}

/// Mindlin: the simply supported square plate's `(m, n)` flexural
/// frequency (Hz) with shear correction factor `k` (the lower root of
/// `A w^4 - B w^2 + C = 0`).
fn mindlin(m: f64, n: f64, thickness: f64, k: f64) -> f64 {
    let (e, nu, rho) = (200e9, 0.3, 8000.0);
    let g = e / (2.0 * (1.0 + nu));
    let d = e * thickness.powi(3) / (12.0 * (1.0 - nu * nu));
    let i = rho * thickness.powi(3) / 12.0;
    let alpha2 = (m * m + n * n) * PI * PI / (SIDE * SIDE);
    let kgh = k * g * thickness;
    let a = rho * thickness * i;
    let b = i * kgh * alpha2 + rho * thickness * (d * alpha2 + kgh);
    let c = kgh * d * alpha2 * alpha2;
    ((b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a)).sqrt() / (2.0 * PI)
}

const SS_MODES: [(f64, f64); 4] = [(1.0, 1.0), (1.0, 2.0), (2.0, 1.0), (2.0, 2.0)];

#[test]
fn thin_simply_supported_plate_matches_kirchhoff() {
    // NAFEMS' printed values are Kirchhoff's to their four digits.
    let nafems = [2.377, 5.942, 5.942, 9.507];
    let exact: Vec<f64> = SS_MODES
        .iter()
        .map(|&(m, n)| kirchhoff(m, n, 0.05))
        .collect();
    for (e, p) in exact.iter().zip(nafems) {
        assert!((e - p).abs() < 6e-4, "{e} against the printed {p}");
    }
    for kind in ShellKind::ALL {
        let mut errors = Vec::new();
        for n in [8, 16, 32] {
            let f = frequencies(&plate(kind, n, 0.05, Edges::SimplySupported), 4);
            errors.push(worst(&format!("{kind:?} {n}x{n} thin SS"), &f, &exact));
        }
        // Measured at 32 x 32: S4 0.39 %, S3 0.85 % (15 % and 7.2 % at 8 x
        // 8). The quadratic elements reach the difference between their
        // Mindlin plate and Kirchhoff's, which leaves out shear (0.036 %),
        // S8 from 8 x 8 on, S6 from 16 x 16 on (1.7 % at 8 x 8).
        match kind {
            ShellKind::S8 => assert!(errors.iter().all(|e| *e < 1e-3), "{errors:?}"),
            ShellKind::S6 => assert!(errors[0] < 0.02 && errors[1] < 1e-3, "{errors:?}"),
            _ => assert_second_order(kind, &errors),
        }
        let bound = if kind == ShellKind::S4 { 0.005 } else { 0.01 };
        assert!(errors[2] < bound, "{kind:?}: {errors:?}");
    }
}

/// Errors that fall by at least 3 with each halving of the element size
/// (second order, 4 in the limit).
fn assert_second_order(kind: ShellKind, errors: &[f64]) {
    for pair in errors.windows(2) {
        assert!(
            pair[1] < pair[0] / 3.0,
            "{kind:?} converges at second order: {errors:?}"
        );
    }
}

#[test]
fn thick_simply_supported_plate_matches_mindlin() {
    // NAFEMS test 21 (1 m thick): its values are Mindlin's with k =
    // pi^2/12; the element's k = 5/6 moves them by 0.03 to 0.11 %.
    let nafems = [45.897, 109.44, 109.44, 167.89];
    let exact: Vec<f64> = SS_MODES
        .iter()
        .map(|&(m, n)| mindlin(m, n, 1.0, 5.0 / 6.0))
        .collect();
    for (e, p) in exact.iter().zip(nafems) {
        assert!(((e - p) / p).abs() < 2e-3, "{e} against the printed {p}");
    }
    let with_nafems_k: Vec<f64> = SS_MODES
        .iter()
        .map(|&(m, n)| mindlin(m, n, 1.0, PI * PI / 12.0))
        .collect();
    for (e, p) in with_nafems_k.iter().zip(nafems) {
        assert!(((e - p) / p).abs() < 5e-5, "{e} against the printed {p}");
    }
    for kind in ShellKind::ALL {
        let mut errors = Vec::new();
        for n in [8, 16, 32] {
            let f = frequencies(&plate(kind, n, 1.0, Edges::SimplySupported), 4);
            errors.push(worst(&format!("{kind:?} {n}x{n} thick SS"), &f, &exact));
        }
        assert_second_order(kind, &errors);
        // Measured at 32 x 32: S4 0.37 %, S3 0.78 %, S6 0.001 %, S8
        // 0.023 % (0.40 % at 8 x 8).
        assert!(errors[2] < 0.01, "{kind:?}: {errors:?}");
    }
}

#[test]
fn cantilevered_thin_plate_matches_nafems_fv16() {
    let nafems = [0.421, 1.029, 2.582, 3.306, 3.753, 6.555];
    for kind in ShellKind::ALL {
        let mut errors = Vec::new();
        for n in [8, 16, 32] {
            let f = frequencies(&plate(kind, n, 0.05, Edges::ClampedAtXZero), 6);
            errors.push(worst(&format!("{kind:?} {n}x{n} FV16"), &f, &nafems));
        }
        // NAFEMS' values are Barton's (Ritz) parameters, 3.492 for the
        // first mode; the element converges to 3.471 (0.4180 Hz), the
        // value later, more accurate solutions give. Measured at 32 x 32:
        // S4 0.81 %, S3 0.79 %, S6 0.98 %, S8 0.98 % from NAFEMS.
        assert!(errors[2] < 0.01, "{kind:?}: {errors:?}");
        assert_at_nafems_mesh(kind, errors[0], [0.07, 0.04, 0.01, 0.01]);
    }
}

#[test]
fn cantilevered_thin_plate_on_nafems_own_meshes_fv16() {
    // NAFEMS' tests 1 and 2 of FV16: 4 x 4 eight-node elements, regular,
    // and with the nine interior corner nodes moved (test 2; mid-side
    // nodes at the middle of the straight edges). Measured: within 0.69 %
    // on the regular mesh, 1.8 % (sixth mode; 0.98 % in the fifth, the
    // others within 0.78 %) on the distorted one. OptiStruct's
    // verification manual prints its eight-node elements 3 to 11 % below
    // NAFEMS' values on both.
    let nafems = [0.421, 1.029, 2.582, 3.306, 3.753, 6.555];
    let moved = |i: usize, j: usize| -> Option<[f64; 2]> {
        Some(match (i, j) {
            (2, 2) => [4.0, 4.0],
            (1, 1) => [2.25, 2.25],
            (2, 1) => [4.75, 2.5],
            (3, 1) => [7.25, 2.75],
            (3, 2) => [7.5, 4.75],
            (3, 3) => [7.75, 7.25],
            (2, 3) => [5.25, 7.25],
            (1, 3) => [2.25, 7.25],
            (1, 2) => [2.5, 4.75],
            _ => return None,
        })
    };
    for distorted in [false, true] {
        let corner = |i: usize, j: usize| match moved(i, j).filter(|_| distorted) {
            Some(p) => p,
            None => [2.5 * i as f64, 2.5 * j as f64],
        };
        // Corners where the grid position is whole, edge midpoints between.
        let position = |x: f64, y: f64| {
            let (a, b) = (
                corner(x.floor() as usize, y.floor() as usize),
                corner(x.ceil() as usize, y.ceil() as usize),
            );
            [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0]
        };
        let model = plate_on(ShellKind::S8, 4, 0.05, Edges::ClampedAtXZero, position);
        let name = if distorted { "distorted" } else { "regular" };
        let error = worst(
            &format!("S8 4x4 {name} FV16"),
            &frequencies(&model, 6),
            &nafems,
        );
        let bound = if distorted { 0.02 } else { 0.01 };
        assert!(error < bound, "{name}: {error}");
    }
}

#[test]
fn free_thin_plate_matches_nafems_fv12() {
    // Three rigid-body modes (uz, rx, ry) at zero, then NAFEMS' values.
    let nafems = [1.622, 2.360, 2.922, 4.233, 4.233, 7.416];
    for kind in ShellKind::ALL {
        let mut errors = Vec::new();
        for n in [8, 16, 32] {
            let f = frequencies(&plate(kind, n, 0.05, Edges::Free), 9);
            for rigid in &f[..3] {
                assert!(*rigid < 1e-3, "{kind:?}: rigid mode at {rigid} Hz");
            }
            errors.push(worst(&format!("{kind:?} {n}x{n} FV12"), &f[3..], &nafems));
        }
        // The pair at 4.233 Hz converges to 4.19 Hz, Leissa's 34.80 for
        // the frequency parameter (NAFEMS' value is 35.16): measured at
        // 32 x 32, S4 0.91 %, S3 0.94 %, S6 1.09 %, S8 1.10 % from NAFEMS.
        assert!(errors[2] < 0.012, "{kind:?}: {errors:?}");
        assert_at_nafems_mesh(kind, errors[0], [0.07, 0.08, 0.01, 0.011]);
    }
}

/// The worst mode's error on NAFEMS' own mesh, 8 x 8 cells, below the
/// bound of its kind (`bounds` in the order S3, S4, S6, S8). Measured:
/// FV16 S3 6.4 %, S4 3.4 %, S6 0.71 %, S8 0.94 %; FV12 S3 6.4 %, S4
/// 7.5 %, S6 0.93 %, S8 1.01 % (its pair 1.1 % off NAFEMS' value when
/// converged). The linear elements' worst modes are their sixth, with
/// five and more half-waves on eight cells: peers' four-node elements on
/// FV12's 8 x 8 mesh are 5 % off there too (OptiStruct's CQUAD4 5.2 %,
/// CATIA's QD4 5.1 %, in their verification manuals).
fn assert_at_nafems_mesh(kind: ShellKind, error: f64, bounds: [f64; 4]) {
    let i = ShellKind::ALL.iter().position(|k| *k == kind).unwrap();
    assert!(error < bounds[i], "{kind:?} at 8 x 8: {error}");
}

#[test]
fn thin_cantilever_strip_bends_as_beam_theory_without_shear_locking() {
    // L = 1 m, b = 0.1 m, a = 1 mm (L/a = 1000), nu = 0 (so the strip is
    // a beam, E I = E b a^3 / 12), ten elements along, one across: the tip
    // deflection under a tip load within 1 % of P L^3 / (3 E I).
    let (length, width, a): (f64, f64, f64) = (1.0, 0.1, 0.001);
    let material = Material::new(200e9, 0.0, 8000.0).unwrap();
    let ei = 200e9 * width * a.powi(3) / 12.0;
    let want = length.powi(3) / (3.0 * ei);
    for kind in ShellKind::ALL {
        let grid = Grid::new(kind, [10, 1], &material, a, |i, j| {
            [0.1 * i, width * j, 0.0]
        });
        let fixed = grid
            .each()
            .filter(|(i, _, _)| *i == 0.0)
            .flat_map(|(_, _, node)| at(node, &DofKind::ALL))
            .collect();
        let model = grid.model(fixed);
        let k = assemble(&model).unwrap().stiffness.to_dense();
        let n = k.nrows();
        let mut f = faer::Mat::<f64>::zeros(n, 1);
        // A unit load along the tip edge, consistent: a half at each end
        // (linear edge), 1/6, 2/3, 1/6 (quadratic edge).
        for (_, j, node) in grid.each().filter(|(i, _, _)| *i == 10.0) {
            let share = match (kind.is_quadratic(), j) {
                (false, _) => 0.5,
                (true, 0.5) => 2.0 / 3.0,
                (true, _) => 1.0 / 6.0,
            };
            f[(equation(&model, node, DofKind::Uz), 0)] = share;
        }
        let u = k.full_piv_lu().solve(&f);
        let tip = u[(equation(&model, grid.id(10, 0), DofKind::Uz), 0)];
        let error = (tip - want) / want;
        eprintln!(
            "{kind:?} 10x1 strip: tip {tip:.6e} m against {want:.6e} ({:+.3} %)",
            100.0 * error
        );
        assert!(error.abs() < 0.01, "{kind:?}: {:.3} %", 100.0 * error);
    }
}

use faer::linalg::solvers::Solve;

/// A ring of shells: a cylinder band of radius `radius`, `width` along z,
/// `cells` elements round, one across.
fn ring(kind: ShellKind, cells: usize, radius: f64, width: f64, thickness: f64) -> Model {
    let material = Material::new(200e9, 0.0, 8000.0).unwrap();
    let mut grid = Grid::new(kind, [cells, 1], &material, thickness, |i, j| {
        let phi = 2.0 * PI * i / cells as f64;
        [radius * phi.cos(), radius * phi.sin(), width * j]
    });
    grid.close_along_i();
    grid.model(Vec::new())
}

#[test]
fn ring_of_shells_bends_as_a_thin_ring_without_membrane_locking() {
    // R = 1 m, b = 0.1 m, a = 10 mm, nu = 0: in-plane bending n = 2, 3 (a
    // pair each) after the six rigid-body modes.
    let (radius, width, a): (f64, f64, f64) = (1.0, 0.1, 0.01);
    let ei = 200e9 * width * a.powi(3) / 12.0;
    let rho_a = 8000.0 * width * a;
    let ring_hz = |n: f64| {
        (ei / (rho_a * radius.powi(4))).sqrt() * n * (n * n - 1.0)
            / (n * n + 1.0).sqrt()
            / (2.0 * PI)
    };
    let exact = [ring_hz(2.0), ring_hz(2.0), ring_hz(3.0), ring_hz(3.0)];
    for kind in ShellKind::ALL {
        let mut errors = Vec::new();
        for cells in [24, 48, 96, 192] {
            let f = frequencies(&ring(kind, cells, radius, width, a), 10);
            for rigid in &f[..6] {
                assert!(
                    *rigid < 1e-3 * exact[0],
                    "{kind:?}: rigid mode at {rigid} Hz"
                );
            }
            errors.push(worst(&format!("{kind:?} ring of {cells}"), &f[6..], &exact));
        }
        // Measured with 96 elements round: 0.46 % (S4), 0.40 % (S3),
        // 0.040 % (S6; with 24 round, two triangles per cell, S6 is 23 %
        // too stiff: membrane locking on a coarse curved mesh, gone at 48,
        // 0.96 %). S8 is within 0.072 % with 24 round (no membrane
        // locking) and from 48 round at the closed form's own neglect of
        // shear and extension (1.1e-4, ~(a / R)^2).
        if kind == ShellKind::S8 {
            assert!(errors.iter().all(|e| *e < 1e-3), "{kind:?}: {errors:?}");
        } else {
            assert_second_order(kind, &errors);
        }
        assert!(errors[2] < 0.005, "{kind:?}: {errors:?}");
    }
}
