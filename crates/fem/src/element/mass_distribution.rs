//! Where an element's mass is in space: what integrals of products of two
//! displacement fields over the body need (the floating-frame invariants,
//! `int a b^T dm`), exact for the element's own mass matrix.
//!
//! Two forms cover the elements flexbody has:
//! - **nodal** ([`MassDistribution::Nodal`]): an isoparametric element with
//!   consistent mass, `M_e = S (x) I_3` over its nodes' translations. A
//!   field the shape functions interpolate (a mode shape, and the positions
//!   `x0` themselves) gives `int a b^T dm = sum_pq S_pq a_p b_q^T`;
//! - **points** ([`MassDistribution::Points`]): rigid slices. Each
//!   [`MassPoint`] carries a mass and a rotary inertia and moves as a rigid
//!   body, translation `u` and rotation `theta` linear in the element's
//!   DOFs: a beam's Gauss points along its axis (the beam's own shape
//!   functions), a point mass's node. A material point at `x0 = x_g + r`
//!   moves by `u + theta x r`, so that
//!   `int a b^T dm = sum_g m_g u_a u_b^T + L_a R_g L_b^T` with `L = theta~`
//!   for a mode (`L = I` for `x0`) and `R_g = int r r^T dm`, which follows
//!   from the point's inertia tensor `J_g` as `R_g = tr(J_g)/2 I - J_g`.
//!
//! Summed over the element, `sum_g m_g u_a . u_b + theta_a^T J_g theta_b`
//! is `a_e^T M_e b_e`: the points hold exactly the inertia the mass matrix
//! has (a beam without rotary inertia: its torsion only).

use super::ElementMatrices;
use crate::dof::DofKind;
use crate::model::NodeId;
use crate::FemError;
use faer::Mat;

/// How an element's mass is spread in space (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub enum MassDistribution {
    /// No mass (springs, dashpots, massless elements).
    None,
    /// `M_e = S (x) I_3`: `coupling[(p, q)]` is `S_pq` of `nodes[p]` and
    /// `nodes[q]`.
    Nodal {
        nodes: Vec<NodeId>,
        coupling: Mat<f64>,
    },
    /// Rigid slices, each moving as `u + theta x r`.
    Points(Vec<MassPoint>),
}

/// A rigid slice of an element's mass.
#[derive(Clone, Debug, PartialEq)]
pub struct MassPoint {
    /// Its centre of mass (m).
    pub position: [f64; 3],
    /// Its mass (kg).
    pub mass: f64,
    /// Its inertia tensor about `position`, global axes (kg m^2).
    pub inertia: [[f64; 3]; 3],
    /// `u = translation u_e` (3 x n, `u_e` in the order of the element's
    /// DOFs, global components).
    pub translation: Mat<f64>,
    /// `theta = rotation u_e` (3 x n).
    pub rotation: Mat<f64>,
}

impl MassDistribution {
    /// The nodal form of an element with translational DOFs only whose mass
    /// matrix `em` is `S (x) I_3`; an error naming `element` otherwise
    /// (entries differing by more than 1e-12 of the largest).
    pub fn nodal(element: usize, em: &ElementMatrices) -> Result<Self, FemError> {
        let m = &em.mass;
        let largest = m.norm_max();
        if largest == 0.0 {
            return Ok(Self::None);
        }
        let refuse = |why: &str| FemError::InvalidElement {
            element,
            reason: format!(
                "its mass has no place in space for the floating-frame invariants: {why}"
            ),
        };
        let dofs = &em.dofs;
        if !dofs.len().is_multiple_of(3)
            || dofs.chunks(3).any(|c| {
                c.iter().any(|d| d.node != c[0].node)
                    || c.iter()
                        .map(|d| d.kind)
                        .ne([DofKind::Ux, DofKind::Uy, DofKind::Uz])
            })
        {
            return Err(refuse("its DOFs are not ux, uy, uz node by node"));
        }
        let n = dofs.len() / 3;
        let tolerance = 1e-12 * largest;
        for p in 0..n {
            for q in 0..n {
                let s = m[(3 * p, 3 * q)];
                for a in 0..3 {
                    for b in 0..3 {
                        let want = if a == b { s } else { 0.0 };
                        if (m[(3 * p + a, 3 * q + b)] - want).abs() > tolerance {
                            return Err(refuse("its mass couples directions"));
                        }
                    }
                }
            }
        }
        Ok(Self::Nodal {
            nodes: dofs.chunks(3).map(|c| c[0].node).collect(),
            coupling: Mat::from_fn(n, n, |p, q| m[(3 * p, 3 * q)]),
        })
    }
}

/// Gauss-Legendre points and weights on `[0, 1]` with four points: exact
/// for polynomials to degree 7 (products of two cubic shape functions).
pub(super) const GAUSS_4: [(f64, f64); 4] = {
    const A: f64 = 0.069_431_844_202_973_71;
    const B: f64 = 0.330_009_478_207_571_87;
    const WA: f64 = 0.173_927_422_568_726_93;
    const WB: f64 = 0.326_072_577_431_273_07;
    [(A, WA), (B, WB), (1.0 - B, WB), (1.0 - A, WA)]
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_gauss_points_integrate_degree_seven() {
        for degree in 0..=7 {
            let sum: f64 = GAUSS_4.iter().map(|(x, w)| w * x.powi(degree)).sum();
            let exact = 1.0 / f64::from(degree + 1);
            assert!((sum - exact).abs() < 1e-15, "degree {degree}: {sum}");
        }
    }
}
