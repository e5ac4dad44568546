//! Whether a reduced body read from a file can be one: the checks a reader
//! runs before the body is used, so that a damaged or hand-edited file is
//! refused with the block and entry at fault instead of giving NaN in a
//! simulation or a wrong mass in a summary.

use crate::body::{ModeKind, ReducedBody};
use flexbody_linalg::dense_check::{
    out_of_range, semi_definite, stable_pencil, symmetric, LARGEST,
};

/// What is wrong with a body: the block of its file (`mass`, `stiffness`,
/// `damping`, `basis`, `modes`) and a sentence.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyDefect {
    pub block: &'static str,
    pub message: String,
}

impl ReducedBody {
    /// Checks what every body satisfies (eq. 5-7 with a symmetric, positive
    /// semi-definite M and K): every number finite and at most
    /// [`LARGEST`] in magnitude; `M_red`, `K_red` and `D_red` symmetric;
    /// `M_red` positive semi-definite and not zero; no negative eigenvalue
    /// of `K_red x = w^2 M_red x` beyond round-off
    /// ([`stable_pencil`]); the frequency
    /// of every mode description finite and not negative. Sizes are the
    /// reader's to check (they come with the format).
    pub fn check(&self) -> Result<(), BodyDefect> {
        let defect = |block: &'static str, message: String| BodyDefect { block, message };
        let matrices = [
            ("mass", Some(&self.mass)),
            ("stiffness", Some(&self.stiffness)),
            ("damping", self.damping.as_ref()),
        ];
        for (block, m) in matrices {
            let Some(m) = m else { continue };
            out_of_range(m.as_ref(), LARGEST).map_err(|e| defect(block, e))?;
            symmetric(m.as_ref()).map_err(|e| defect(block, format!("the matrix {e}")))?;
        }
        semi_definite(self.mass.as_ref()).map_err(|e| defect("mass", format!("the matrix {e}")))?;
        if self.r() > 0 && self.mass.norm_max() == 0.0 {
            return Err(defect("mass", "the reduced mass matrix is zero".into()));
        }
        stable_pencil(self.stiffness.as_ref(), self.mass.as_ref())
            .map_err(|e| defect("stiffness", format!("the matrix {e}")))?;
        out_of_range(self.basis.as_ref(), LARGEST).map_err(|e| {
            defect(
                "basis",
                format!("{e} (rows are the DOFs in the order of `dofs`)"),
            )
        })?;
        for (k, mode) in self.modes.iter().enumerate() {
            if let ModeKind::Eigen { frequency_hz } | ModeKind::Orthonormal { frequency_hz } = mode
            {
                if !(frequency_hz.is_finite() && *frequency_hz >= 0.0) {
                    return Err(defect(
                        "modes",
                        format!("mode {} has frequency {frequency_hz} Hz", k + 1),
                    ));
                }
            }
        }
        for (node, r) in &self.local_axes {
            flexbody_fem::local_axes::check_axes(*node, r)
                .map_err(|e| defect("local_axes", e.to_string()))?;
            if !self.interface.iter().any(|d| d.node == *node) {
                return Err(defect(
                    "local_axes",
                    format!("node {node} has local axes but no interface DOF"),
                ));
            }
            if let Some(d) = self
                .interface
                .iter()
                .find(|d| d.node == *node && self.interface_row(**d).is_none())
            {
                return Err(defect(
                    "local_axes",
                    format!(
                        "interface DOF {d} is along local axes, but the body lacks one of \
                         the node's three {}",
                        if d.kind.is_rotation() {
                            "rotations"
                        } else {
                            "translations"
                        }
                    ),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Method;
    use faer::Mat;
    use flexbody_fem::{Dof, DofKind, DofMap};

    /// Two unit masses on a spring, as a free body in the nodal basis.
    fn body() -> ReducedBody {
        ReducedBody {
            method: Method::Free,
            dof_map: DofMap::new(vec![Dof::new(1, DofKind::Ux), Dof::new(2, DofKind::Ux)]),
            basis: Mat::identity(2, 2),
            mass: Mat::identity(2, 2),
            stiffness: Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { -1.0 }),
            damping: None,
            modes: vec![
                ModeKind::Eigen { frequency_hz: 0.0 },
                ModeKind::Eigen {
                    frequency_hz: 2f64.sqrt() / std::f64::consts::TAU,
                },
            ],
            interface: vec![],
            local_axes: Default::default(),
        }
    }

    #[test]
    fn a_body_whose_matrices_cannot_be_a_bodys_is_refused_naming_the_block() {
        assert_eq!(body().check(), Ok(()));
        let refused = |edit: &dyn Fn(&mut ReducedBody)| {
            let mut b = body();
            edit(&mut b);
            b.check().unwrap_err()
        };
        let e = refused(&|b| b.mass[(0, 1)] = 0.5);
        assert_eq!(e.block, "mass");
        assert!(e.message.contains("not symmetric"), "{}", e.message);
        let e = refused(&|b| b.mass[(0, 0)] = -1.0);
        assert_eq!(e.block, "mass");
        assert!(
            e.message.contains("not positive semi-definite"),
            "{}",
            e.message
        );
        let e = refused(&|b| b.stiffness[(1, 1)] = 0.5);
        assert_eq!(e.block, "stiffness");
        assert!(e.message.contains("negative eigenvalue"), "{}", e.message);
        let e = refused(&|b| b.mass = Mat::zeros(2, 2));
        assert_eq!(e.block, "mass");
        let e = refused(&|b| b.basis[(1, 0)] = 1e308);
        assert_eq!(e.block, "basis");
        assert!(e.message.contains("entry (2, 1) is 1e308"), "{}", e.message);
        let e = refused(&|b| b.damping = Some(Mat::from_fn(2, 2, |_, _| f64::NAN)));
        assert_eq!(e.block, "damping");
        let e = refused(&|b| {
            b.modes[1] = ModeKind::Eigen {
                frequency_hz: f64::NAN,
            }
        });
        assert_eq!(e.block, "modes");
    }
}
