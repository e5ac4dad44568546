//! Residual static modes (report 5.4, eq. 23-24).
//!
//! A static mode contains a part of the kept eigenmodes `Phi`; removing it,
//! `t_res = t - Phi (Phi^T M t)` (Phi M-orthonormal), leaves a combination of
//! the neglected eigenmodes only. Residual modes are therefore M- and
//! K-orthogonal to the kept eigenmodes (of the same K and M), and the two
//! groups decouple in the reduced equations.

use faer::{Mat, MatRef};
use flexbody_linalg::{sparse, SparseMat};

/// `T_res = T_stat - Phi Phi^T M T_stat` for M-orthonormal `phi`.
pub fn residual_modes(static_modes: &Mat<f64>, phi: &Mat<f64>, mass: &SparseMat) -> Mat<f64> {
    residual_modes_by(static_modes, phi, |t| sparse::symmetric_mul(mass, t))
}

/// [`residual_modes`] with the product `M T_stat` from `mul_mass`.
pub(crate) fn residual_modes_by(
    static_modes: &Mat<f64>,
    phi: &Mat<f64>,
    mul_mass: impl FnOnce(MatRef<'_, f64>) -> Mat<f64>,
) -> Mat<f64> {
    if phi.ncols() == 0 {
        return static_modes.clone();
    }
    let mt = mul_mass(static_modes.as_ref());
    let c = phi.transpose() * &mt;
    static_modes - phi * &c
}
