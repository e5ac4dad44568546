//! [`Wanted::LowestBelow`] by both solvers, against the whole spectrum of
//! the dense solver and against the two requests it combines: the lowest
//! `count` of the pairs below a bound.

use super::*;
use crate::progress::NoProgress;
use crate::sparse::from_triplets;
use faer::sparse::Triplet;

/// Stiffness triplets of a spring `s` between equations `a` and `b`
/// (`b = None`: to the ground).
fn spring(t: &mut Vec<Triplet<usize, usize, f64>>, a: usize, b: Option<usize>, s: f64) {
    t.push(Triplet::new(a, a, s));
    if let Some(b) = b {
        t.push(Triplet::new(b, b, s));
        t.push(Triplet::new(a, b, -s));
        t.push(Triplet::new(b, a, -s));
    }
}

/// Lumped masses, varied so that no eigenvalue repeats.
fn masses(n: usize) -> SparseMat {
    let m: Vec<_> = (0..n)
        .map(|i| Triplet::new(i, i, 1.0 + 0.37 * ((7 * i) % 5) as f64))
        .collect();
    from_triplets(n, n, &m).unwrap()
}

/// A held membrane of `nx * ny` nodes (one DOF each): unit springs to the
/// four neighbours, to the ground where the rim has none.
fn membrane(nx: usize, ny: usize) -> (SparseMat, SparseMat) {
    let n = nx * ny;
    let mut t = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let a = i + nx * j;
            for (di, dj) in [(1, 0), (0, 1)] {
                let (p, q) = (i + di, j + dj);
                spring(&mut t, a, (p < nx && q < ny).then_some(p + nx * q), 1.0);
            }
            for rim in [i == 0, j == 0] {
                if rim {
                    spring(&mut t, a, None, 1.0);
                }
            }
        }
    }
    (from_triplets(n, n, &t).unwrap(), masses(n))
}

/// A free chain of `n` masses on springs of varied stiffness: one
/// rigid-body mode at zero.
fn free_chain(n: usize) -> (SparseMat, SparseMat) {
    let mut t = Vec::new();
    for i in 0..n - 1 {
        spring(&mut t, i, Some(i + 1), 1.0 + 0.5 * ((3 * i) % 7) as f64);
    }
    (from_triplets(n, n, &t).unwrap(), masses(n))
}

fn values(k: &SparseMat, m: &SparseMat, wanted: Wanted, solver: Solver) -> EigenSolution {
    eigen(k, m, wanted, solver, Budget::MACHINE, &NoProgress).unwrap()
}

/// Equal to `1e-9` of the largest value (rigid-body zeros at round-off).
fn assert_same(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?} vs {want:?}");
    let scale = want.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= 1e-9 * scale, "{what}: {g} vs {w}");
    }
}

/// For both solvers, the lowest `count` below a bound between the
/// `below`-th and the next eigenvalue of the whole spectrum: those of the
/// spectrum, of `Below` cut to `count` and of `Lowest` without those above
/// the bound. The sparse solver's Sturm check proves them: at the bound
/// when the count does not cut the band, else just above the `count`-th
/// eigenvalue, no run having looked for the band's pairs above it.
fn lowest_below(k: &SparseMat, m: &SparseMat, count: usize, below: usize) {
    let all = generalized_symmetric(k.to_dense().as_ref(), m.to_dense().as_ref())
        .unwrap()
        .values;
    let bound = 0.5 * (all[below.saturating_sub(1)] + all[below]);
    let bound = if below == 0 { 0.5 * all[0] } else { bound };
    assert_eq!(all.iter().filter(|&&l| l < bound).count(), below);
    let keep = count.min(below);
    let wanted = Wanted::LowestBelow { count, bound };
    for solver in [Solver::Dense, Solver::Sparse] {
        let what = format!("{solver:?}, {count} below the {below}-th");
        let got = values(k, m, wanted, solver);
        assert_same(&got.pairs.values, &all[..keep], &what);
        let band = values(k, m, Wanted::Below(bound), solver).pairs.values;
        assert_same(&got.pairs.values, &band[..count.min(band.len())], &what);
        let lowest = values(k, m, Wanted::Lowest(count), solver).pairs.values;
        let filtered: Vec<f64> = lowest.into_iter().filter(|&l| l < bound).collect();
        assert_same(&got.pairs.values, &filtered, &what);
        assert_eq!(got.pairs.vectors.ncols(), keep, "{what}");
        for (j, r) in got.residuals.iter().enumerate() {
            assert!(*r < 1e-8, "{what}: mode {j}: residual {r}");
        }
        match solver {
            Solver::Dense => assert!(got.stats.dense && got.sturm.is_none(), "{what}"),
            _ if keep == 0 => assert!(got.pairs.values.is_empty()),
            _ => {
                let sturm = got.sturm.expect("a Sturm check");
                assert_eq!(sturm.found, sturm.count, "{what}: {sturm:?}");
                if below <= count {
                    assert_eq!((sturm.bound, sturm.count), (bound, below), "{what}");
                } else {
                    assert_eq!(sturm.count, count, "{what}: {sturm:?}");
                    assert!(sturm.bound < all[count], "{what}: {sturm:?}");
                }
            }
        }
    }
}

#[test]
fn lowest_below_a_bound_with_fewer_below_than_the_count() {
    let (k, m) = membrane(23, 14);
    lowest_below(&k, &m, 20, 8);
    let (k, m) = free_chain(330);
    lowest_below(&k, &m, 20, 8);
}

#[test]
fn lowest_below_a_bound_with_more_below_than_the_count() {
    let (k, m) = membrane(23, 14);
    lowest_below(&k, &m, 6, 25);
    let (k, m) = free_chain(330);
    lowest_below(&k, &m, 6, 25);
}

#[test]
fn lowest_below_a_bound_with_as_many_or_none_below() {
    let (k, m) = membrane(23, 14);
    lowest_below(&k, &m, 12, 12);
    lowest_below(&k, &m, 5, 0);
}

#[test]
fn a_count_caps_a_band_in_the_choice_of_the_solver() {
    let band = Wanted::LowestBelow {
        count: 400,
        bound: 1.0,
    };
    assert!(Solver::Auto.is_dense(1000, band));
    assert!(!Solver::Auto.is_dense(1000, Wanted::Below(1.0)));
    assert!(!Solver::Auto.is_dense(1000, band.map_count(|_| 20)));
}
