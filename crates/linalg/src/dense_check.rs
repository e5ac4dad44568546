//! Checks of small dense matrices read from files: finite entries,
//! symmetry, semi-definiteness. Each returns what is wrong as a sentence
//! naming the entry (1-based row and column), for the reader to prefix
//! with the file and the quantity.

use faer::{MatRef, Side};

/// The largest magnitude a number read from a file may have. No quantity
/// of a structural model comes near it in SI units, and the squares and
/// products the computation forms of larger ones overflow to infinity.
pub const LARGEST: f64 = 1e100;

/// Relative asymmetry `|a_ij - a_ji|` above which a matrix that should be
/// symmetric is refused: `T^T A T` computed in floating point is symmetric
/// to a few ulps of its largest entry.
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Relative size `-lambda_min / lambda_max` of a negative eigenvalue above
/// which a matrix that should be positive semi-definite is refused
/// (round-off of a semi-definite matrix stays orders of magnitude below).
pub const DEFINITENESS_TOLERANCE: f64 = 1e-9;

/// The first entry (column by column) that is not finite or is larger in
/// magnitude than `largest`.
pub fn out_of_range(a: MatRef<'_, f64>, largest: f64) -> Result<(), String> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let v = a[(i, j)];
            if !v.is_finite() {
                return Err(format!("entry ({}, {}) is {v}", i + 1, j + 1));
            }
            if v.abs() > largest {
                return Err(format!(
                    "entry ({}, {}) is {v:e}, beyond {largest:e} in magnitude",
                    i + 1,
                    j + 1
                ));
            }
        }
    }
    Ok(())
}

/// The entry pair furthest from symmetry, if beyond
/// [`SYMMETRY_TOLERANCE`] of the largest entry. `a` must be square and
/// finite.
pub fn symmetric(a: MatRef<'_, f64>) -> Result<(), String> {
    let n = a.nrows();
    let scale = a.norm_max();
    let mut worst = (0.0, 0, 0);
    for j in 0..n {
        for i in j + 1..n {
            let d = (a[(i, j)] - a[(j, i)]).abs();
            if d > worst.0 {
                worst = (d, i, j);
            }
        }
    }
    let (d, i, j) = worst;
    if d > SYMMETRY_TOLERANCE * scale {
        return Err(format!(
            "is not symmetric: entry ({}, {}) is {:e}, entry ({}, {}) is {:e}",
            i + 1,
            j + 1,
            a[(i, j)],
            j + 1,
            i + 1,
            a[(j, i)]
        ));
    }
    Ok(())
}

/// Whether the symmetric matrix `a` is positive semi-definite: no
/// eigenvalue below `-DEFINITENESS_TOLERANCE` times the largest in
/// magnitude. `a` must be square, finite and symmetric.
pub fn semi_definite(a: MatRef<'_, f64>) -> Result<(), String> {
    if a.nrows() == 0 {
        return Ok(());
    }
    let values = a
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|e| format!("has no eigenvalues ({e:?})"))?;
    let largest = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let lowest = values.iter().copied().fold(f64::INFINITY, f64::min);
    if lowest < -DEFINITENESS_TOLERANCE * largest {
        return Err(format!(
            "is not positive semi-definite: its lowest eigenvalue is {lowest:.3e} (largest {largest:.3e})"
        ));
    }
    Ok(())
}

/// Frequency (Hz) below which a negative eigenvalue of `K x = w^2 M x`
/// is taken as the round-off zero of a rigid-body mode: a body whose
/// modes are all rigid has nothing else to measure round-off against.
pub const ROUND_OFF_HZ: f64 = 0.01;

/// The lowest eigenvalue `w^2` among `values` that is still the round-off
/// zero of a rigid-body mode: `-1e-8` times the largest magnitude, or
/// `-floor` where that is lower. The dense eigen solver refuses a pencil
/// with an eigenvalue below it (`floor` 0), as does [`stable_pencil`].
pub fn round_off_zero(values: &[f64], floor: f64) -> f64 {
    let top = values.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    -(1e-8 * top).max(floor)
}

/// Whether the pencil of the symmetric `k` and the positive semi-definite
/// `m` is stable: no eigenvalue `w^2` below `-1e-8` times the largest and
/// below `-(2 pi ROUND_OFF_HZ)^2`. A pencil the dense solver cannot split
/// (no mass) is left to its user.
pub fn stable_pencil(k: MatRef<'_, f64>, m: MatRef<'_, f64>) -> Result<(), String> {
    let Ok(pairs) = crate::eigen::generalized_symmetric(k, m) else {
        return Ok(());
    };
    let top = pairs.values.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let floor = (std::f64::consts::TAU * ROUND_OFF_HZ).powi(2);
    let bound = round_off_zero(&pairs.values, floor);
    match pairs.values.iter().copied().find(|&l| l < bound) {
        None => Ok(()),
        Some(l) => Err(format!(
            "with the mass matrix has the negative eigenvalue {l:.3e} 1/s^2 (largest {top:.3e}): \
             the body would be unstable, growing at {:.3e} Hz",
            (-l).sqrt() / std::f64::consts::TAU
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    #[test]
    fn each_check_names_the_first_entry_that_fails() {
        let mut a = Mat::from_fn(3, 3, |i, j| if i == j { 2.0 } else { 0.5 });
        assert!(out_of_range(a.as_ref(), 1e100).is_ok());
        assert!(symmetric(a.as_ref()).is_ok());
        assert!(semi_definite(a.as_ref()).is_ok());
        a[(2, 1)] = f64::NAN;
        assert_eq!(
            out_of_range(a.as_ref(), 1e100).unwrap_err(),
            "entry (3, 2) is NaN"
        );
        a[(2, 1)] = 1e200;
        assert!(out_of_range(a.as_ref(), 1e100)
            .unwrap_err()
            .contains("entry (3, 2) is 1e200, beyond 1e100"));
        a[(2, 1)] = 0.6;
        let e = symmetric(a.as_ref()).unwrap_err();
        assert!(
            e.contains("entry (3, 2) is 6e-1, entry (2, 3) is 5e-1"),
            "{e}"
        );
        // A rank-one matrix is semi-definite; minus it is not.
        let v = [1.0, -2.0, 3.0];
        let p = Mat::from_fn(3, 3, |i, j| v[i] * v[j]);
        assert!(semi_definite(p.as_ref()).is_ok());
        let e = semi_definite((-&p).as_ref()).unwrap_err();
        assert!(e.contains("lowest eigenvalue is -1.400e1"), "{e}");
        // A stiffness of round-off size on rigid-body modes is stable; one
        // that pushes a mode away at 1 Hz is not.
        let m = Mat::<f64>::identity(2, 2);
        let tiny = Mat::from_fn(2, 2, |i, j| if i == j { -1e-7 } else { 0.0 });
        assert!(stable_pencil(tiny.as_ref(), m.as_ref()).is_ok());
        let w = std::f64::consts::TAU;
        let unstable = Mat::from_fn(2, 2, |i, j| match (i, j) {
            (0, 0) => 4.0e4,
            (1, 1) => -w * w,
            _ => 0.0,
        });
        let e = stable_pencil(unstable.as_ref(), m.as_ref()).unwrap_err();
        assert!(e.contains("growing at 1.000e0 Hz"), "{e}");
    }
}
