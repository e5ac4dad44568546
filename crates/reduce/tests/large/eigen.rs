//! The sparse eigen path: equal to the dense solver, repeated frequencies,
//! mechanisms, stalls, bands, massless DOFs, indefinite stiffness.

use crate::models::*;
use faer::Mat;
use flexbody_fem::{Dof, DofKind, Substructure};
use flexbody_linalg::eigen::Wanted;
use flexbody_linalg::lanczos::{lanczos, EigenSolution, LanczosParams};
use flexbody_linalg::memory::Budget;
use flexbody_linalg::progress::NoProgress;
use flexbody_linalg::sparse;
use flexbody_linalg::SparseMat;
use flexbody_reduce::modes::eigen::{eigenmodes_with, Solver, SPARSE_FROM};
use flexbody_reduce::{reduce, Method, ReduceError, Reduction};

/// The `count` lowest modes of `s` by [`lanczos`] with `params`, and the
/// dense solver's eigenvalues.
fn lowest_both_ways(
    s: &Substructure,
    count: usize,
    params: &LanczosParams,
) -> (EigenSolution, Vec<f64>) {
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, Wanted::Lowest(count), Solver::Dense).unwrap();
    (lowest_by_lanczos(s, count, params), dense.values)
}

/// The `count` lowest modes of `s` by [`lanczos`] with `params`.
fn lowest_by_lanczos(s: &Substructure, count: usize, params: &LanczosParams) -> EigenSolution {
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    lanczos(k, m, Wanted::Lowest(count), params, &NoProgress).unwrap()
}

/// The slender bar: 40 x 2 x 2 cells over 2 x 0.05 x 0.05 m.
fn slender_bar() -> Substructure {
    block(40, 2, 2, [2.0, 0.05, 0.05], false)
}

/// Lanczos parameters with a basis of `size` vectors, the rest default.
fn basis_of(size: usize) -> LanczosParams {
    LanczosParams {
        basis_size: size,
        ..Default::default()
    }
}

/// `max |X^T M X - I|`: how far the columns of `x` are from M-orthonormal.
fn m_orthonormality_error(x: &Mat<f64>, m: &SparseMat) -> f64 {
    let g: Mat<f64> = x.transpose() * m * x;
    (&g - Mat::<f64>::identity(x.ncols(), x.ncols())).norm_max()
}

#[test]
fn sparse_path_equals_dense_on_a_solid_bar() {
    // 10 x 3 x 3 C3D8: 528 DOFs, free; 20 modes (6 rigid).
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, Wanted::Lowest(20), Solver::Dense).unwrap();
    let sparse = eigenmodes_with(k, m, Wanted::Lowest(20), Solver::Sparse).unwrap();
    assert_close(&sparse.values, &dense.values, 1e-10);
    // The same modes: |phi_s^T M phi_d| = 1 on the simple elastic ones.
    let overlap = sparse.vectors.transpose() * m * &dense.vectors;
    for j in 6..19 {
        let v = &dense.values;
        let simple = (v[j] - v[j - 1]).abs() > 1e-6 * v[j] && (v[j + 1] - v[j]).abs() > 1e-6 * v[j];
        if simple {
            assert!((overlap[(j, j)].abs() - 1.0).abs() < 1e-8, "mode {j}");
        }
    }
}

/// `eigenmodes_owned` (the solver takes K and M and drops them once it
/// holds its compact copy) gives the dense solver's modes and residuals at
/// round-off, for a count and for a band.
#[test]
fn owned_matrices_give_the_same_modes_and_their_residuals() {
    use flexbody_reduce::modes::eigen::{eigenmodes_owned, Wanted};
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, Wanted::Lowest(20), Solver::Dense).unwrap();
    let (modes, residuals) = eigenmodes_owned(
        k.clone(),
        m.clone(),
        Wanted::Lowest(20),
        Budget::MACHINE,
        &NoProgress,
    )
    .unwrap();
    assert_close(&modes.values, &dense.values, 1e-10);
    assert_eq!(residuals.len(), 20);
    assert!(residuals.iter().all(|r| *r < 1e-8), "{residuals:?}");
    // The band up to midway between modes 12 and 13: exactly 12 modes.
    let v = &dense.values;
    let hz = 0.5 * (v[11].sqrt() + v[12].sqrt()) / (2.0 * std::f64::consts::PI);
    let (band, _) = eigenmodes_owned(
        k.clone(),
        m.clone(),
        Wanted::below_hz(hz),
        Budget::MACHINE,
        &NoProgress,
    )
    .unwrap();
    assert_close(&band.values, &dense.values[..12], 1e-10);
}

#[test]
fn a_cube_has_its_repeated_frequencies_with_full_multiplicity() {
    // A 6 x 6 x 6 C3D8 cube (1029 DOFs): by symmetry, 2- and 3-fold
    // frequencies. The sparse path (Auto at this size) must give each of
    // them as often as the dense solver and the Sturm count.
    let s = block(6, 6, 6, [0.3, 0.3, 0.3], false);
    assert!(s.len() >= SPARSE_FROM);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, Wanted::Lowest(40), Solver::Dense)
        .unwrap()
        .values;
    let count = (24..40)
        .find(|&c| dense[c] > dense[c - 1] * (1.0 + 1e-6))
        .unwrap();
    let repeated = (7..count)
        .filter(|&i| (dense[i] - dense[i - 1]).abs() < 1e-8 * dense[i])
        .count();
    assert!(repeated >= 6, "{dense:?}");
    let found = lowest_by_lanczos(&s, count, &LanczosParams::default());
    let sturm = found.sturm.unwrap();
    assert_eq!(sturm.count, count, "{sturm:?}");
    assert_eq!(sturm.found, count);
    assert_close(&found.pairs.values, &dense[..count], 1e-10);
    // Auto takes the sparse path here and agrees.
    let auto = flexbody_reduce::modes::eigenmodes(k, m, Wanted::Lowest(count)).unwrap();
    assert_close(&auto.values, &dense[..count], 1e-10);
    let dev = m_orthonormality_error(&auto.vectors, m);
    assert!(dev < 1e-10, "{dev:e}");
}

#[test]
fn a_mechanism_is_reported_with_its_zero_mode_count() {
    // A bar with one element hanging on a single node: 9 zero-frequency
    // modes (6 rigid + 3 rotations of the element about that node).
    let s = block(12, 4, 4, [1.2, 0.2, 0.2], true);
    assert!(s.len() >= SPARSE_FROM, "{} DOFs", s.len());
    let found = lowest_by_lanczos(&s, 12, &LanczosParams::default());
    let v = &found.pairs.values;
    let zero = v.iter().filter(|l| l.abs() < 1e-6 * v[11]).count();
    assert_eq!(zero, 9, "{v:?}");
    // Every free method names the count, on the sparse path (1053 DOFs)
    // and the dense one (69 DOFs), K and M lent or handed over: `free`
    // with no more modes than rigid ones (once reduced silently), with one
    // more (once "7 zero-frequency modes", all it had computed), and
    // free-residual (once only "K on the support is singular at a DOF").
    let small = block(3, 1, 1, [0.3, 0.1, 0.1], true);
    assert!(small.len() < SPARSE_FROM);
    let interface: Vec<Dof> = [DofKind::Ux, DofKind::Uy, DofKind::Uz]
        .map(|k| Dof::new(1, k))
        .to_vec();
    for model in [&s, &small] {
        // A band of 1 mHz holds the rigid-body modes alone (0 modes asked).
        for (method, modes) in [
            (Method::Free, 12),
            (Method::Free, 6),
            (Method::Free, 7),
            (Method::Free, 0),
            (Method::FreeResidual, 4),
            (Method::FreeResidual, 0),
        ] {
            let mut spec = Reduction::new(method, modes, interface.clone());
            if modes == 0 {
                spec.max_frequency_hz = Some(1e-3);
            }
            let lent = reduce(model, &spec);
            let given = flexbody_reduce::reduce_keeping(
                &mut model.clone(),
                &spec,
                flexbody_reduce::Keep::Neither,
                &NoProgress,
            );
            for result in [lent, given] {
                match result {
                    Err(ReduceError::FreeMechanism { zero, rigid }) => {
                        assert_eq!((zero, rigid), (9, 6), "{method} {modes}");
                    }
                    other => panic!("{method} {modes}: got {:?}", other.map(|b| b.r())),
                }
            }
        }
        // Clamped at its end x = 0, the bar is held, the element is not:
        // K_NN is singular at a DOF of the element, which Craig-Bampton
        // names as the body's own mechanism (once "use the free-residual
        // method", which refuses it as above).
        let face: Vec<Dof> = model
            .dof_map
            .dofs()
            .iter()
            .filter(|d| model.coordinates[&d.node][0] == 0.0)
            .copied()
            .collect();
        let spec = Reduction::new(Method::CraigBampton, 4, face.clone());
        match reduce(model, &spec) {
            Err(ReduceError::BodyMechanism {
                interface,
                dof,
                rigid,
            }) => {
                assert_eq!((interface, rigid), (face, 6));
                assert!(dof.node >= 1_000_000, "{dof}");
            }
            other => panic!("Craig-Bampton: got {:?}", other.map(|b| b.r())),
        }
        // Matrices without node positions: the rigid-body modes come from
        // K's null space, which holds 9 zeros where 6 at most are rigid.
        let bare = Substructure::from_matrices(
            model.dof_map.clone(),
            model.matrices.clone(),
            Default::default(),
        );
        match flexbody_reduce::method::free_body_rigid_modes(&bare) {
            Err(ReduceError::FreeMechanism { zero, rigid }) => assert_eq!((zero, rigid), (9, 6)),
            other => panic!("matrices alone: got {:?}", other.map(|r| r.count())),
        }
    }
}

/// Times both paths (run with `--release -- --ignored --nocapture`).
#[test]
#[ignore]
fn time_dense_against_sparse() {
    for (nx, ny, nz) in [
        (4, 2, 2),
        (6, 3, 3),
        (10, 3, 3),
        (10, 4, 4),
        (14, 5, 4),
        (20, 5, 5),
    ] {
        let s = block(nx, ny, nz, [1.0, 0.2, 0.2], false);
        let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
        let t = std::time::Instant::now();
        let d = eigenmodes_with(k, m, Wanted::Lowest(20), Solver::Dense).unwrap();
        let td = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let sp = eigenmodes_with(k, m, Wanted::Lowest(20), Solver::Sparse).unwrap();
        let ts = t.elapsed().as_secs_f64();
        let err = d
            .values
            .iter()
            .zip(&sp.values)
            .skip(6)
            .map(|(a, b)| ((a - b) / a).abs())
            .fold(0.0, f64::max);
        println!(
            "{} DOFs: dense {td:.3} s, sparse {ts:.3} s, max rel diff {err:e}",
            s.len()
        );
    }
}

/// A slender bar (1107 DOFs) and 150 modes on a basis of only 24 vectors
/// more than that (a basis held small to save memory): each restart keeps
/// little room to grow, and the first run stops converging new pairs
/// before it has them all. It hands the rest over to the Sturm check's
/// shift above the band (and, stalling again, to shifts below it): every
/// mode, counted by the inertia, with residuals below 1e-7, M-orthonormal,
/// and the dense solver's frequencies; the same for a band, which counts
/// first.
#[test]
fn a_stalled_run_finishes_on_shifts_above_the_band() {
    let s = slender_bar();
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let count = 150;
    let params = basis_of(count + 24);
    let (found, dense) = lowest_both_ways(&s, count, &params);
    let sturm = found.sturm.unwrap();
    assert!(sturm.found_first < count, "{sturm:?}");
    assert!(
        sturm.count >= count && sturm.found == sturm.count,
        "{sturm:?}"
    );
    assert_eq!(found.pairs.values.len(), count);
    let worst = found.residuals.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-7, "{:?}", found.residuals);
    let dev = m_orthonormality_error(&found.pairs.vectors, m);
    assert!(dev < 1e-12, "{dev:e}");
    assert_close(&found.pairs.values, &dense, 1e-9);
    // The band up to midway between modes 140 and 141: counted first, then
    // the stalled run finishes on a factor at the band's bound.
    let v = &dense;
    let bound = 0.5 * (v[139] + v[140]);
    let band = lanczos(k, m, Wanted::Below(bound), &params, &NoProgress).unwrap();
    let sturm = band.sturm.unwrap();
    assert_eq!(sturm.count, 140, "{sturm:?}");
    assert!(sturm.found_first < 140, "{sturm:?}");
    assert_eq!(band.pairs.values.len(), 140);
    assert!(
        band.residuals.iter().all(|r| *r < 1e-7),
        "{:?}",
        band.residuals
    );
    assert_close(&band.pairs.values, &v[..140], 1e-9);
}

/// 250 modes of the slender bar on a basis of only 16 vectors more: 187
/// restarts, two runs. However slowly a run converges, a mode is accepted
/// at the round-off floor of its operator and no higher: every residual
/// below 1e-7 (a rule that raised the floor where estimates stopped
/// falling accepted the top ones at up to 9.6e-5 here).
#[test]
fn a_slow_run_on_a_small_basis_accepts_no_mode_above_its_floor() {
    let s = slender_bar();
    let count = 250;
    let params = basis_of(count + 16);
    let (found, dense) = lowest_both_ways(&s, count, &params);
    let sturm = found.sturm.unwrap();
    assert!(
        sturm.found == sturm.count && sturm.count >= count,
        "{sturm:?}"
    );
    let worst = found.residuals.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-7, "{:?}", found.residuals);
    assert_close(&found.pairs.values, &dense, 1e-9);
}

/// The 20 lowest modes of the 6 x 6 x 6 cube with the default basis: the
/// 6 rigid-body modes converge in 3 sweeps, the elastic ones, a decade per
/// sweep, after the first restart. Sweeps while the basis still grows are
/// no stall (they once counted as one and handed this run over to the
/// Sturm check's factor with only the rigid-body modes found: 27 sweeps
/// instead of 18).
#[test]
fn sweeps_before_the_first_restart_are_no_stall() {
    let s = block(6, 6, 6, [0.3, 0.3, 0.3], false);
    let (found, dense) = lowest_both_ways(&s, 20, &LanczosParams::default());
    let sturm = found.sturm.unwrap();
    assert!(found.stats.restarts > 0, "{:?}", found.stats);
    assert_eq!(found.stats.runs, 1, "{sturm:?}");
    assert_eq!(sturm.found_first, sturm.count, "{sturm:?}");
    assert_close(&found.pairs.values, &dense, 1e-10);
}

/// More modes than a Lanczos basis holds: for 600 of the 6 x 6 x 6 cube's
/// 1029 the basis would span the model, and a Krylov space that exhausts
/// it is round-off in its last blocks (900 of them once came with
/// residuals of 0.7, and with hundreds more eigenvalues below the Sturm
/// bound than it has). Such a count, or a band that holds one, goes to
/// the dense solver, ascending and accurate; half the modes and fewer
/// stay with Lanczos.
#[test]
fn a_count_whose_basis_would_span_the_model_is_solved_densely() {
    let s = block(6, 6, 6, [0.3, 0.3, 0.3], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let n = k.nrows();
    let dense = eigenmodes_with(k, m, Wanted::Lowest(n), Solver::Dense)
        .unwrap()
        .values;
    let params = LanczosParams::default();
    let ascending = |v: &[f64]| v.windows(2).all(|w| w[0] <= w[1]);
    // The first count from 600 on that ends a cluster of equal frequencies.
    let count = (600..n)
        .find(|&c| dense[c] > dense[c - 1] * (1.0 + 1e-6))
        .unwrap();
    let found = lanczos(k, m, Wanted::Lowest(count), &params, &NoProgress).unwrap();
    assert!(
        found.stats.dense && found.stats.runs == 0,
        "{:?}",
        found.stats
    );
    assert_close(&found.pairs.values, &dense[..count], 1e-10);
    let worst = |r: &[f64]| r.iter().copied().fold(0.0, f64::max);
    assert!(
        worst(&found.residuals) < 1e-10,
        "{:e}",
        worst(&found.residuals)
    );
    // A band with that many modes: counted, then solved densely.
    let bound = 0.5 * (dense[count - 1] + dense[count]);
    let band = lanczos(k, m, Wanted::Below(bound), &params, &NoProgress).unwrap();
    assert!(band.stats.dense);
    assert_eq!(band.sturm.unwrap().count, count);
    assert_close(&band.pairs.values, &dense[..count], 1e-10);
    // Every mode (a bound above the highest, 84.6 kHz).
    let all = lanczos(k, m, Wanted::Below(1e20), &params, &NoProgress).unwrap();
    assert_eq!(all.sturm.unwrap().count, n);
    assert_close(&all.pairs.values, &dense, 1e-10);
    assert!(ascending(&all.pairs.values));
    assert!(worst(&all.residuals) < 1e-10, "{:e}", worst(&all.residuals));
    // Lanczos keeps 490 modes: its basis of 1012 leaves room.
    let lanczos_490 = lanczos(k, m, Wanted::Lowest(490), &params, &NoProgress).unwrap();
    assert!(!lanczos_490.stats.dense && lanczos_490.stats.runs >= 1);
    assert!(ascending(&lanczos_490.pairs.values));
    assert!(worst(&lanczos_490.residuals) < 1e-7);
    assert_close(&lanczos_490.pairs.values, &dense[..490], 1e-9);
}

/// A band whose bound is an eigenvalue to round-off: the Sturm count and
/// the modes found may place that one on either side of it, and neither
/// is an error; the modes returned are the lowest ones.
#[test]
fn a_band_bounded_on_an_eigenvalue_is_no_error() {
    let s = slender_bar();
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, Wanted::Lowest(40), Solver::Dense)
        .unwrap()
        .values;
    let params = LanczosParams::default();
    for i in 8..36 {
        let band = lanczos(k, m, Wanted::Below(dense[i]), &params, &NoProgress).unwrap();
        let len = band.pairs.values.len();
        assert!(len + 2 >= i && len <= i + 2, "{i}: {len}");
        assert_close(&band.pairs.values, &dense[..len], 1e-10);
    }
}

/// DOFs that carry no mass (the last element of a bar of density 0) have
/// no finite eigenvalue. A band gives the finite ones below it: those of
/// K condensed on the DOFs with mass (exact for them, eq. 15), and a count
/// beyond them says how many there are. A model without any mass is
/// refused by name on both paths.
#[test]
fn massless_dofs_have_no_eigenvalue_and_a_band_gives_the_finite_ones() {
    use faer::linalg::solvers::Solve;
    use flexbody_reduce::modes::{eigenmodes, Wanted};
    let s = bar_of_densities(2, |e| if e == 0 { 7850.0 } else { 0.0 });
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let n = s.len();
    // Equations of the 4 nodes at x = 0.2 m, which only the massless
    // element holds, and the others.
    let light: Vec<usize> = (0..n)
        .filter(|&i| s.node_coordinates(s.dof_map.dof(i).node).unwrap()[0] > 0.15)
        .collect();
    let heavy: Vec<usize> = (0..n).filter(|i| !light.contains(i)).collect();
    assert_eq!((light.len(), heavy.len()), (12, 24));
    let (kd, md) = (sparse::to_dense(k), sparse::to_dense(m));
    let block = |a: &Mat<f64>, r: &[usize], c: &[usize]| {
        Mat::from_fn(r.len(), c.len(), |i, j| a[(r[i], c[j])])
    };
    let k_ss = block(&kd, &light, &light);
    let k_sm = block(&kd, &light, &heavy);
    let x = k_ss.llt(faer::Side::Lower).unwrap().solve(&k_sm);
    let mut condensed = block(&kd, &heavy, &heavy) - k_sm.transpose() * &x;
    sparse::symmetrize(&mut condensed);
    let want = flexbody_linalg::eigen::generalized_symmetric(
        condensed.as_ref(),
        block(&md, &heavy, &heavy).as_ref(),
    )
    .unwrap()
    .values;
    let got = eigenmodes(k, m, Wanted::below_hz(1e9)).unwrap().values;
    assert_eq!(got.len(), 24);
    let top = want[23];
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (g - w).abs() < 1e-10 * w.abs().max(1e-6 * top),
            "{g} vs {w}"
        );
    }
    match eigenmodes(k, m, Wanted::Lowest(30)) {
        Err(ReduceError::NotEnoughModes {
            requested: 30,
            available: 24,
        }) => {}
        other => panic!("got {:?}", other.map(|p| p.values.len())),
    }
    // No mass at all: 36 DOFs (dense) and 372 (Lanczos).
    for nx in [2, 30] {
        let s = bar_of_densities(nx, |_| 0.0);
        let err =
            eigenmodes(&s.matrices.stiffness, &s.matrices.mass, Wanted::Lowest(6)).unwrap_err();
        assert!(err.to_string().contains("the mass matrix is zero"), "{err}");
    }
}

/// A stiffness with a negative eigenvalue (a chain of unit masses on
/// springs of 1e4 N/m, one of them -3e4 N/m: -5.1e4 1/s^2) is refused on
/// the dense path (40 DOFs; it once showed that mode as 0 Hz) and on the
/// Lanczos path (400 DOFs; once "dimension mismatch"), naming the count.
#[test]
fn an_indefinite_stiffness_is_refused_on_both_paths() {
    use faer::sparse::Triplet;
    use flexbody_linalg::LinalgError;
    use flexbody_reduce::modes::{eigenmodes, Wanted};
    for n in [40, 400] {
        let spring = |i: usize| if i == n / 2 { -3e4 } else { 1e4 };
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, spring(i) + spring(i + 1)));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -spring(i + 1)));
                t.push(Triplet::new(i + 1, i, -spring(i + 1)));
            }
        }
        let k = sparse::from_triplets(n, n, &t).unwrap();
        let ones: Vec<_> = (0..n).map(|i| Triplet::new(i, i, 1.0)).collect();
        let m = sparse::from_triplets(n, n, &ones).unwrap();
        for result in [
            eigenmodes(&k, &m, Wanted::Lowest(5)),
            eigenmodes(&k, &m, Wanted::below_hz(1.0)),
        ] {
            match result {
                Err(ReduceError::Linalg(LinalgError::NotSemiDefinite { count: 1, .. })) => {}
                other => panic!("{n} DOFs: got {:?}", other.map(|p| p.values)),
            }
        }
    }
}
