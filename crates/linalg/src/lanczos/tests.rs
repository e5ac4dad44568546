//! The Lanczos solver against the dense one, on 3D spring lattices built in
//! code (free bodies with 6 rigid-body modes; cubes have repeated
//! eigenvalues).

use super::block_qr::{dot, orthonormalize_block};
use super::run::Rng;
use super::sturm::shift_above;
use super::*;
use crate::eigen::generalized_symmetric;
use crate::progress::NoProgress;
use crate::sparse::from_triplets;
use faer::sparse::Triplet;
use faer::Mat;

/// A free truss lattice of `nx * ny * nz` nodes with unit spacing: springs
/// along every edge, face diagonal and body diagonal of each cell (stiffness
/// `1 / length`), 3 DOFs per node, lumped masses (1, or varied when `skew`).
/// With `hinge`, the lattice is cut into two halves along x that share only
/// one node: a mechanism with 3 extra zero modes.
fn lattice(nx: usize, ny: usize, nz: usize, skew: bool, hinge: bool) -> (SparseMat, SparseMat) {
    let id = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
    let coords = |v: usize| {
        let (i, j, k) = (v % nx, (v / nx) % ny, v / (nx * ny));
        [i as f64, j as f64, k as f64]
    };
    let nn = nx * ny * nz;
    let mut t = Vec::new();
    let mid = nx / 2;
    for k in 0..nz.saturating_sub(1) {
        for j in 0..ny.saturating_sub(1) {
            for i in 0..nx - 1 {
                let corners: Vec<usize> = (0..8)
                    .map(|c| id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)))
                    .collect();
                if hinge && i == mid {
                    continue;
                }
                for a in 0..8 {
                    for b in a + 1..8 {
                        let (p, q) = (corners[a], corners[b]);
                        let (x, y) = (coords(p), coords(q));
                        let d = [y[0] - x[0], y[1] - x[1], y[2] - x[2]];
                        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                        let s = 1.0 / len;
                        for r in 0..3 {
                            for c in 0..3 {
                                let v = s * d[r] * d[c] / (len * len);
                                t.push(Triplet::new(3 * p + r, 3 * p + c, v));
                                t.push(Triplet::new(3 * q + r, 3 * q + c, v));
                                t.push(Triplet::new(3 * p + r, 3 * q + c, -v));
                                t.push(Triplet::new(3 * q + r, 3 * p + c, -v));
                            }
                        }
                    }
                }
            }
        }
    }
    if hinge {
        // Join the two halves at one node: a spherical hinge.
        let (a, b) = (id(mid, 0, 0), id(mid + 1, 0, 0));
        for r in 0..3 {
            let s = 10.0;
            t.push(Triplet::new(3 * a + r, 3 * a + r, s));
            t.push(Triplet::new(3 * b + r, 3 * b + r, s));
            t.push(Triplet::new(3 * a + r, 3 * b + r, -s));
            t.push(Triplet::new(3 * b + r, 3 * a + r, -s));
        }
    }
    let mass: Vec<Triplet<usize, usize, f64>> = (0..3 * nn)
        .map(|i| {
            let v = if skew {
                1.0 + 0.37 * ((i / 3 * 7) % 5) as f64
            } else {
                1.0
            };
            Triplet::new(i, i, v)
        })
        .collect();
    let n = 3 * nn;
    (
        from_triplets(n, n, &t).unwrap(),
        from_triplets(n, n, &mass).unwrap(),
    )
}

fn dense(k: &SparseMat, m: &SparseMat) -> Vec<f64> {
    generalized_symmetric(k.to_dense().as_ref(), m.to_dense().as_ref())
        .unwrap()
        .values
}

/// Values agree to `tol` relative, zero (rigid) ones to `tol` of the first
/// elastic one.
fn assert_same(got: &[f64], want: &[f64], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
    let elastic = want.iter().copied().find(|l| *l > 1e-8).unwrap_or(1.0);
    for (g, w) in got.iter().zip(want) {
        let scale = if w.abs() < 1e-8 * elastic {
            elastic
        } else {
            w.abs()
        };
        assert!((g - w).abs() <= tol * scale, "{g} vs {w} ({got:?})");
    }
}

fn solve(k: &SparseMat, m: &SparseMat, wanted: Wanted, params: &LanczosParams) -> EigenSolution {
    lanczos(k, m, wanted, params, &NoProgress).unwrap()
}

#[test]
fn free_lattice_equals_the_dense_solver() {
    let (k, m) = lattice(9, 4, 3, true, false);
    let want = dense(&k, &m);
    for ordering in [Ordering::Amd, Ordering::NestedDissection] {
        let params = LanczosParams {
            ordering,
            ..Default::default()
        };
        let got = solve(&k, &m, Wanted::Lowest(20), &params);
        assert_same(&got.pairs.values, &want[..20], 1e-10);
        for (j, r) in got.residuals.iter().enumerate() {
            assert!(*r < 1e-7, "mode {j}: residual {r}");
        }
        // M-orthonormal.
        let x = &got.pairs.vectors;
        let g = x.transpose() * &m * x;
        for i in 0..20 {
            for j in 0..20 {
                let d = if i == j { 1.0 } else { 0.0 };
                assert!((g[(i, j)] - d).abs() < 1e-10);
            }
        }
        let s = got.sturm.unwrap();
        assert_eq!(s.count, 20);
        assert_eq!(s.found, 20);
    }
}

#[test]
fn medium_lattice_with_restarts_equals_the_dense_solver() {
    // 576 DOFs, 30 modes with a small block: several thick restarts.
    let (k, m) = lattice(12, 4, 4, true, false);
    let want = dense(&k, &m);
    let params = LanczosParams {
        block_size: 4,
        basis_size: 40,
        ..Default::default()
    };
    let got = solve(&k, &m, Wanted::Lowest(30), &params);
    assert!(got.stats.restarts > 0, "{:?}", got.stats);
    assert_same(&got.pairs.values, &want[..30], 1e-10);
}

#[test]
fn cube_multiplicities_are_complete() {
    // A cubic lattice: eigenvalues in 2- and 3-fold clusters.
    let (k, m) = lattice(6, 6, 6, false, false);
    let want = dense(&k, &m);
    // A count that ends a cluster.
    let count = (20..40)
        .find(|&c| want[c] > want[c - 1] * (1.0 + 1e-6))
        .unwrap();
    let repeated = (7..count)
        .filter(|&i| (want[i] - want[i - 1]).abs() < 1e-8 * want[i])
        .count();
    assert!(repeated >= 4, "the cube should have repeated eigenvalues");
    let got = solve(&k, &m, Wanted::Lowest(count), &LanczosParams::default());
    assert_same(&got.pairs.values, &want[..count], 1e-10);
}

#[test]
fn sturm_check_makes_a_single_vector_find_a_fourfold_eigenvalue() {
    // A diagonal pencil: a Krylov space of one start vector holds one
    // vector of each eigenspace, round-off never adds a second. The Sturm
    // count above the 4-fold eigenvalue must make the solver continue.
    let n = 400;
    let lambda = |i: usize| if i < 4 { 2.0 } else { 1.0 + i as f64 };
    let k = from_triplets(
        n,
        n,
        &(0..n)
            .map(|i| Triplet::new(i, i, lambda(i)))
            .collect::<Vec<_>>(),
    )
    .unwrap();
    let m = from_triplets(
        n,
        n,
        &(0..n).map(|i| Triplet::new(i, i, 1.0)).collect::<Vec<_>>(),
    )
    .unwrap();
    let params = LanczosParams {
        block_size: 1,
        ..Default::default()
    };
    let got = solve(&k, &m, Wanted::Lowest(6), &params);
    let s = got.sturm.unwrap();
    assert!(s.found_first < s.count, "{s:?}");
    assert_eq!(s.found, s.count);
    assert_same(&got.pairs.values, &[2.0, 2.0, 2.0, 2.0, 5.0, 6.0], 1e-12);
}

#[test]
fn modes_below_a_bound_match_the_dense_count() {
    let (k, m) = lattice(8, 3, 3, true, false);
    let want = dense(&k, &m);
    let bound = 0.5 * (want[17] + want[18]);
    let got = solve(&k, &m, Wanted::Below(bound), &LanczosParams::default());
    assert_eq!(got.sturm.unwrap().count, 18);
    assert_same(&got.pairs.values, &want[..18], 1e-10);
}

#[test]
fn a_hinge_shows_nine_zero_modes() {
    // Two lattices joined at one node: 6 rigid-body modes plus 3 rotations
    // about the hinge, all at zero frequency.
    let (k, m) = lattice(8, 3, 3, false, true);
    let got = solve(&k, &m, Wanted::Lowest(12), &LanczosParams::default());
    let v = &got.pairs.values;
    let zero = v.iter().filter(|l| l.abs() < 1e-10 * v[11]).count();
    assert_eq!(zero, 9, "{v:?}");
    assert_same(v, &dense(&k, &m)[..12], 1e-10);
}

/// `Q^T M Q = I` and `Q B = W` for the block orthonormalisation, on a
/// well-conditioned block (Cholesky QR) and on one with a repeated column
/// (the Gram-Schmidt fallback, which keeps its coefficients on the earlier
/// columns in `B` and continues with a fresh direction, diagonal 0).
#[test]
fn block_orthonormalisation_in_the_m_inner_product() {
    let (k, m) = lattice(4, 3, 3, true, false);
    let pencil =
        Pencil::analyze(&k, &m, None, Ordering::Amd, &crate::progress::NoProgress).unwrap();
    let n = m.nrows();
    let mut rng = Rng(7);
    let good = Mat::from_fn(n, 4, |_, _| rng.next());
    let mut repeated = good.clone();
    let first = good.col(0).to_owned();
    repeated.col_mut(2).copy_from(&first);
    for (w0, dependent) in [(good, false), (repeated, true)] {
        let mut w = w0.clone();
        let mut mw = symmetric_mul(&m, w.as_ref());
        let before: Vec<f64> = (0..4).map(|j| dot(w.col(j), mw.col(j)).sqrt()).collect();
        let none = Mat::<f64>::zeros(n, 0);
        let b = orthonormalize_block(
            &mut w,
            &mut mw,
            &before,
            &[none.as_ref()],
            &pencil,
            &mut rng,
        );
        let g = w.transpose() * symmetric_mul(&m, w.as_ref());
        assert!(
            (&g - Mat::<f64>::identity(4, 4)).norm_max() < 1e-12,
            "{dependent}"
        );
        assert!(
            (&w * &b - &w0).norm_max() < 1e-12 * w0.norm_max(),
            "{dependent}"
        );
        let mw_exact = symmetric_mul(&m, w.as_ref());
        assert!((&mw - &mw_exact).norm_max() < 1e-12 * mw_exact.norm_max());
        assert_eq!(b[(2, 2)] == 0.0, dependent);
    }
}

#[test]
fn the_shift_above_a_stalled_band_lies_in_the_gap_to_the_next_value() {
    // Halfway to the next value; at most 5 % of the span above the top
    // (nothing above, or a wide gap); at least 1e-4 of it (a close pair).
    let span = 10.0;
    assert_eq!(shift_above(&[1.0, 2.0, 2.2, 3.0], 2.0, span), 2.1);
    assert_eq!(shift_above(&[1.0, 2.0], 2.0, span), 2.5);
    assert_eq!(shift_above(&[2.0, 4.0], 2.0, span), 2.5);
    assert_eq!(shift_above(&[2.0, 2.0000001], 2.0, span), 2.001);
}

/// A diagonal pencil (`M = I`) with the eigenvalues `lambda`.
fn diagonal(lambda: &[f64]) -> (SparseMat, SparseMat) {
    let n = lambda.len();
    let diag = |v: &dyn Fn(usize) -> f64| {
        let t: Vec<_> = (0..n).map(|i| Triplet::new(i, i, v(i))).collect();
        from_triplets(n, n, &t).unwrap()
    };
    (diag(&|i| lambda[i]), diag(&|_| 1.0))
}

/// The first number after `prefix` in `message`, and the text after it.
fn number_after<'a>(message: &'a str, prefix: &str) -> (f64, &'a str) {
    let at = message
        .find(prefix)
        .unwrap_or_else(|| panic!("no '{prefix}' in: {message}"))
        + prefix.len();
    let rest = &message[at..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || "+-.e".contains(c)))
        .unwrap_or(rest.len());
    let value = rest[..end]
        .parse()
        .unwrap_or_else(|_| panic!("no number after '{prefix}' in: {message}"));
    (value, &rest[end..])
}

#[test]
fn a_sturm_count_the_allowed_runs_do_not_reach_is_an_error_naming_both_counts() {
    // One start vector finds one vector of the 4-fold eigenvalue 2 (see
    // the test above); with no run allowed after the first, the count
    // above the band is not reached: an error, not 6 modes with some of
    // the eigenvalue 2 missing.
    let lambda: Vec<f64> = (0..400)
        .map(|i| if i < 4 { 2.0 } else { 1.0 + i as f64 })
        .collect();
    let (k, m) = diagonal(&lambda);
    let params = LanczosParams {
        block_size: 1,
        sturm_runs: 0,
        ..Default::default()
    };
    let e = lanczos(&k, &m, Wanted::Lowest(6), &params, &NoProgress).unwrap_err();
    let LinalgError::SturmMissing { .. } = &e else {
        panic!("expected the Sturm mismatch, got {e}");
    };
    let message = &e.to_string();
    let (found, rest) = number_after(message, "the Lanczos runs found ");
    let (count, rest) = number_after(rest, " of the ");
    let (bound, rest) = number_after(rest, " eigenvalues below ");
    assert!(
        rest.starts_with(" (Sturm count) in 0 runs after the first"),
        "{message}"
    );
    // The bound lies above the 6 wanted eigenvalues (the highest is 6);
    // the count is the eigenvalues below it, the found ones fewer.
    assert!(bound > 6.0, "{message}");
    let below = lambda.iter().filter(|&&l| l < bound).count();
    assert_eq!(count, below as f64, "{message}");
    assert!(found < count, "{message}");
    // The runs allowed by default find them all.
    let params = LanczosParams {
        block_size: 1,
        ..Default::default()
    };
    let got = solve(&k, &m, Wanted::Lowest(6), &params);
    assert_same(&got.pairs.values, &[2.0, 2.0, 2.0, 2.0, 5.0, 6.0], 1e-12);
}

#[test]
fn more_eigenvalues_than_the_sturm_count_are_an_error_not_modes() {
    // A tolerance of 0.9 accepts Ritz pairs far from convergence: the
    // first run's vectors are poor, the run above the band finds again
    // what they left out, and the two together hold more eigenvalues
    // below the Sturm bound than there are.
    let (k, m) = lattice(9, 4, 3, true, false);
    let params = LanczosParams {
        tolerance: 0.9,
        ..Default::default()
    };
    let e = lanczos(&k, &m, Wanted::Lowest(20), &params, &NoProgress).unwrap_err();
    let LinalgError::SturmSpurious { .. } = &e else {
        panic!("expected the Sturm mismatch, got {e}");
    };
    let message = &e.to_string();
    let (found, rest) = number_after(message, "the Lanczos runs found ");
    let (bound, rest) = number_after(rest, " eigenvalues below ");
    let (count, rest) = number_after(rest, " where the Sturm count has ");
    assert_eq!(rest, ": spurious eigenpairs", "{message}");
    // The count is the dense solver's eigenvalues below the bound.
    let below = dense(&k, &m).iter().filter(|&&l| l < bound).count();
    assert!(below >= 20, "{message}");
    assert_eq!(count, below as f64, "{message}");
    assert!(found > count, "{message}");
}
