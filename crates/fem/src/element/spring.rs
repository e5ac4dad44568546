//! Scalar spring between two DOFs, or from one DOF to ground.

use super::{axis, ElementMatrices};
use crate::dof::{Dof, DofKind};
use crate::model::NodeId;
use crate::FemError;
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

/// Spring along the line between two nodes: `k d d^T` on their translations
/// (CalculiX SPRINGA, linear).
#[derive(Clone, Debug, PartialEq)]
pub struct AxialSpring {
    pub id: usize,
    pub nodes: [NodeId; 2],
    /// Stiffness (N/m).
    pub stiffness: f64,
}

impl AxialSpring {
    pub(crate) fn dofs(&self) -> Vec<Dof> {
        self.nodes
            .iter()
            .flat_map(|&n| [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| Dof::new(n, k)))
            .collect()
    }

    pub(crate) fn validate(&self, a: [f64; 3], b: [f64; 3]) -> Result<(), FemError> {
        let (l, _) = axis(a, b);
        if l.is_nan() || l <= 0.0 {
            return Err(FemError::ZeroLength { element: self.id });
        }
        Ok(())
    }

    pub(crate) fn matrices(&self, a: [f64; 3], b: [f64; 3]) -> Result<ElementMatrices, FemError> {
        self.validate(a, b)?;
        let (_, d) = axis(a, b);
        let k = self.stiffness;
        let stiffness = Mat::from_fn(6, 6, |i, j| {
            let sign = if (i < 3) == (j < 3) { 1.0 } else { -1.0 };
            sign * k * d[i % 3] * d[j % 3]
        });
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness,
            mass: Mat::zeros(6, 6),
        })
    }
}
