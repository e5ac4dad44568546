//! Scalar spring between two DOFs, or from one DOF to ground.

use super::ElementMatrices;
use crate::dof::Dof;
use faer::Mat;

/// Spring of stiffness `stiffness` (N/m, or N m/rad on rotations).
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    pub id: usize,
    pub first: Dof,
    /// `None`: grounded spring.
    pub second: Option<Dof>,
    pub stiffness: f64,
}

impl Spring {
    pub(crate) fn dofs(&self) -> Vec<Dof> {
        let mut d = vec![self.first];
        d.extend(self.second);
        d
    }

    pub(crate) fn matrices(&self) -> ElementMatrices {
        let c = self.stiffness;
        let dofs = self.dofs();
        let n = dofs.len();
        let stiffness = Mat::from_fn(n, n, |i, j| if i == j { c } else { -c });
        ElementMatrices {
            dofs,
            stiffness,
            mass: Mat::zeros(n, n),
        }
    }
}
