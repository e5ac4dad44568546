//! The reduced body in the floating frame of reference formulation (FFRF):
//! elastic coordinates and the mass invariants that a SID file carries,
//! computed as one plain value, [`FloatingFrame`].
//!
//! The reference frame is the model's global frame (origin and axes). A
//! material point at `x0` moves to `x = x0 + Phi q` in that frame, with
//! `Phi` the elastic mode shapes (m x nq) and `q` the elastic coordinates.
//!
//! **Elastic coordinates** ([`elastic_basis`]). If the body's basis `T`
//! spans the rigid-body motions `R` (eq. 12-13; free, free-residual,
//! Craig-Bampton and Guyan bodies of a free model do), the frame carries that
//! motion and the elastic modes must not: `T` is projected onto the
//! M-orthogonal complement of `R` (mean-axis, or Tisserand, conditions
//! `R^T M Phi = 0`), `T_e = T (I - A C)` with `C = R_o^T M T`,
//! `A = M_red^-1 C^T` and `R_o` the M-orthonormal rigid-body modes, which
//! drops `n_rigid` directions of the span. The remaining span is
//! diagonalised, `K_e x = w^2 M_e x`, so that `Phi = T E` has
//! `Phi^T M Phi = I` and `Phi^T K Phi = diag(w^2)`: the elastic eigenmodes
//! of the reduced body, with the same non-zero frequencies. If `T` does not
//! span `R` (a supported model), the frame is fixed and `Phi` is the
//! diagonalised `T` itself.
//!
//! **Invariants** ([`mass_invariants`]; `dm = rho dV`; `a~` is the
//! cross-product matrix of `a`; `<a, b> = a^T M b` with the full, consistent
//! mass matrix `M`):
//!
//! | name | size | zero order (m0) | first order (m1, per `q_k`) |
//! | --- | --- | --- | --- |
//! | mass | 1 | `int dm = <t_d, t_d>` | - |
//! | mdCM | 3 x 1 | `int x0 dm` | `int Phi_k dm` |
//! | J | 3 x 3 | `int x0~^T x0~ dm = <r_a, r_b>` | `-int (x0~ Phi_k~ + Phi_k~ x0~) dm` |
//! | Ct | nq x 3 | `int Phi^T dm = Phi^T M [t_x t_y t_z]` | - |
//! | Cr | nq x 3 | `int (x0 x Phi_k)^T dm = Phi^T M [r_x r_y r_z]` | row k: `int (Phi_l x Phi_k)^T dm` |
//! | Me | nq x nq | `Phi^T M Phi` | - |
//! | Gr | 3 x 3nq | block k: `-2 int x0~ Phi_k~ dm` | - |
//! | Ge | nq x 3nq | block l, row k: `-2 int (Phi_k x Phi_l)^T dm` | - |
//! | Oe | nq x 6 | row k: `[S11 S22 S33 2S12 2S23 2S31]`, `S = sym int Phi_k x0^T dm - I int Phi_k . x0 dm` | the same with `x0 -> Phi_l` |
//! | Ke | nq x nq | `Phi^T K Phi` | - |
//! | De | nq x nq | `Phi^T D Phi` | - |
//!
//! With the mesh ([`mass_invariants`] given the model), every integral
//! runs over the elements
//! ([`MassDistribution`](flexbody_fem::element::MassDistribution)): the
//! whole body's mass, fixed DOFs included, solids through their nodes
//! and beams and point masses as rigid slices moving with the beam's own
//! shape functions (rotations and rotary inertia included);
//! `J = tr(P) I - P` with `P = int x0 x0^T dm`. Exact for every element type. From matrices
//! alone, the mass, `mdCM`, `J`, `Ct` and `Cr` (m0) come from `R^T M R`
//! and `Phi^T M R`, with `t_d` and `r_a` the rigid-body translations and
//! rotations about the frame origin (eq. 12), and the products of two
//! fields from the translational part of `M` node by node,
//! `int a b^T dm = sum_pq a_p (S b)_q^T` with `S_pq` the translational
//! mass coupling of nodes p and q: exact for solids, without rotary terms
//! for beams, and without the mass of DOFs the matrices do not have.
//!
//! **Frame nodes** ([`FloatingFrame::nodes`]): each interface node's
//! position `x0` and its rows of `Phi` (translations `phi`, rotations
//! `psi`, 3 x nq each), from which a SID writes the node's origin
//! `x0 + phi q` and orientation `I + psi~ q`.

mod elastic;
mod frame;
mod invariants;
mod mesh_integrals;
#[cfg(test)]
mod tests;

pub use elastic::{elastic_basis, ElasticBasis};
pub use frame::{node_rows, FloatingFrame, FrameNode};
pub use invariants::{mass_invariants, MassInvariants};

use flexbody_linalg::LinalgError;

/// Why a body has no floating-frame description.
#[derive(Debug, thiserror::Error)]
pub enum FfrfError {
    /// The body was reduced from another model (other DOFs).
    #[error(
        "the body has {body} DOFs and the model {model}, or they differ: reduce this model again"
    )]
    BodyNotOfModel { body: usize, model: usize },
    /// The model has no node coordinates (matrices alone).
    #[error(
        "the model has no node coordinates; the FFRF invariants need them (for matrix input: \
         `--coords NODES.txt`)"
    )]
    NoCoordinates,
    /// `M_red` has no Cholesky factor.
    #[error("the reduced mass matrix is not positive definite")]
    MassNotPositiveDefinite,
    /// Every direction of the basis is rigid-body motion.
    #[error("the body has no elastic coordinates (only rigid-body modes)")]
    NoElasticCoordinates,
    /// A small dense eigenproblem of the elastic span failed.
    #[error("eigen-decomposition failed: {0}")]
    Eigen(LinalgError),
    /// Mode shapes whose rows are not the model's DOFs.
    #[error("mode shapes have {rows} rows for {dofs} DOFs")]
    ShapeRows { rows: usize, dofs: usize },
    /// The mass matrix carries no translational mass.
    #[error("the model has no translational mass")]
    NoTranslationalMass,
    /// An element's mass has no place in space.
    #[error("{0}")]
    Mass(flexbody_fem::FemError),
}
