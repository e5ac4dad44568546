//! The mode types of report section 5, one algorithm per file.

pub mod attachment;
pub mod constraint;
pub mod eigen;
pub mod elastic_interface;
pub mod fixed_interface;
pub mod free_interface;
pub mod inertia_relief;
pub mod residual;
pub mod rigid;
pub(crate) mod zero_modes;

pub use attachment::{attachment_modes, unit_loads};
pub use constraint::constraint_modes;
pub use eigen::{eigenmodes, eigenmodes_lent, eigenmodes_owned, EigenModes, Wanted, DENSE_LIMIT};
pub use elastic_interface::elastic_residual_modes;
pub use fixed_interface::craig_bampton_modes;
pub use free_interface::inertia_relief_and_free_modes;
pub use inertia_relief::{
    inertia_relief_attachment_modes, self_equilibrated_loads, statically_determinate_support,
};
pub use residual::residual_modes;
pub use rigid::{rigid_body_modes, rigid_motion_count, RigidModes};
pub use zero_modes::ZERO_GAP;

use faer::Mat;

/// Scatters rows of `part` (for equations `rows`) into an `n`-row matrix of zeros.
pub(crate) fn expand(part: &Mat<f64>, rows: &[usize], n: usize) -> Mat<f64> {
    let mut full = Mat::zeros(n, part.ncols());
    for (k, &i) in rows.iter().enumerate() {
        for j in 0..part.ncols() {
            full[(i, j)] = part[(k, j)];
        }
    }
    full
}

/// Equations of `0..n` not in `taken`.
pub(crate) fn complement(taken: &[usize], n: usize) -> Vec<usize> {
    let mut mask = vec![false; n];
    for &i in taken {
        mask[i] = true;
    }
    (0..n).filter(|&i| !mask[i]).collect()
}
