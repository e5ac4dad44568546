//! Elastic coordinates of a reduced body in the floating frame: the basis
//! projected onto the M-orthogonal complement of the rigid-body motions
//! (mean-axis conditions `R^T M Phi = 0`) and diagonalised, `Phi = T E`
//! (see the [module docs](super)).

use super::FfrfError;
use crate::modes::rigid::rigid_body_transformation;
use crate::ReducedBody;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use flexbody_fem::Substructure;
use flexbody_linalg::orthonormal::m_orthonormalize;

/// Below this M-norm (squared, relative) a rigid-body mode counts as
/// contained in the span of the basis.
const SPAN_TOLERANCE: f64 = 1e-6;

/// Directions of the projected span with a mass below this fraction of the
/// largest are dropped (they were rigid-body motion).
const RANK_TOLERANCE: f64 = 1e-10;

/// Elastic coordinates of a reduced body in the FFRF.
#[derive(Clone, Debug)]
pub struct ElasticBasis {
    /// `E` (r x nq): `Phi = T E`, `q_body = E q`.
    pub transform: Mat<f64>,
    /// `Phi` (m x nq), rows in the body's DOF order.
    pub shapes: Mat<f64>,
    /// `Phi^T M Phi` (the identity to round-off).
    pub mass: Mat<f64>,
    /// `Phi^T K Phi` (diagonal to round-off).
    pub stiffness: Mat<f64>,
    /// `Phi^T D Phi` if the body has damping.
    pub damping: Option<Mat<f64>>,
    /// Natural frequencies of the elastic modes (Hz), ascending.
    pub frequencies_hz: Vec<f64>,
    /// Whether rigid-body motion was removed (free frame) or not (fixed).
    pub floating: bool,
}

impl ElasticBasis {
    /// `R E`: `rows` over the body's coordinates (one column per basis
    /// vector of `T`, as recovery matrices have) as rows over the elastic
    /// coordinates, since `q_body = E q`.
    pub fn elastic_rows(&self, rows: Mat<f64>) -> Mat<f64> {
        rows * &self.transform
    }
}

/// Symmetric eigen-decomposition (ascending) of a small dense matrix.
fn sym_eigen(a: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>), FfrfError> {
    let n = a.nrows();
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let mut s = a.clone();
    flexbody_linalg::sparse::symmetrize(&mut s);
    flexbody_linalg::eigen::symmetric_eigen(s.as_ref()).map_err(FfrfError::Eigen)
}

/// Checks that the body belongs to the substructure.
fn check_match(sub: &Substructure, body: &ReducedBody) -> Result<(), FfrfError> {
    if sub.dof_map.dofs() != body.dof_map.dofs() {
        return Err(FfrfError::BodyNotOfModel {
            body: body.dof_map.len(),
            model: sub.dof_map.len(),
        });
    }
    if !sub.has_geometry() {
        return Err(FfrfError::NoCoordinates);
    }
    Ok(())
}

/// The elastic coordinates of `body`, reduced from `sub` (which gives the
/// full mass matrix and the node coordinates of the rigid-body motions):
/// `Phi = T E` with `Phi^T M Phi = I`, `Phi^T K Phi = diag(w^2)`, ascending,
/// free of rigid-body motion if `T` spans it (see the [module
/// docs](super)).
pub fn elastic_basis(sub: &Substructure, body: &ReducedBody) -> Result<ElasticBasis, FfrfError> {
    check_match(sub, body)?;
    let mass_matrix = &sub.matrices.mass;
    let r = body.r();
    let t = &body.basis;
    let rigid = rigid_body_transformation(sub, [0.0; 3]);
    let rigid_o = m_orthonormalize(rigid.as_ref(), mass_matrix, 1e-8).vectors;
    let identity = Mat::<f64>::identity(r, r);
    let mut e0 = identity.clone();
    let mut floating = false;
    if rigid_o.ncols() > 0 {
        let mt = flexbody_linalg::sparse::symmetric_mul(mass_matrix, t.as_ref());
        let c = rigid_o.transpose() * &mt; // n_r x r
        let llt = body
            .mass
            .llt(Side::Lower)
            .map_err(|_| FfrfError::MassNotPositiveDefinite)?;
        let a = llt.solve(c.transpose()); // r x n_r
        let ca = &c * &a;
        let outside = (0..ca.nrows())
            .map(|i| (1.0 - ca[(i, i)]).abs())
            .fold(0.0, f64::max);
        if outside < SPAN_TOLERANCE {
            e0 = &identity - &a * &c;
            floating = true;
        }
    }
    // Columns that were rigid-body motion vanish; scale the others to unit
    // modal mass so that static modes (small in m/N) and eigenmodes (unit
    // modal mass) weigh the same in the rank decision.
    let mp = e0.transpose() * &body.mass * &e0;
    let kept_cols: Vec<usize> = (0..r)
        .filter(|&j| mp[(j, j)] > SPAN_TOLERANCE * SPAN_TOLERANCE * body.mass[(j, j)].abs())
        .filter(|&j| mp[(j, j)] > 0.0)
        .collect();
    if kept_cols.is_empty() {
        return Err(FfrfError::NoElasticCoordinates);
    }
    let e0 = Mat::from_fn(r, kept_cols.len(), |i, j| {
        e0[(i, kept_cols[j])] / mp[(kept_cols[j], kept_cols[j])].sqrt()
    });
    let mp = e0.transpose() * &body.mass * &e0;
    let (s, u) = sym_eigen(&mp)?;
    let s_max = s.iter().copied().fold(0.0, f64::max);
    let keep: Vec<usize> = (0..s.len())
        .filter(|&i| s[i] > RANK_TOLERANCE * s_max)
        .collect();
    let w = Mat::from_fn(e0.ncols(), keep.len(), |i, j| {
        u[(i, keep[j])] / s[keep[j]].sqrt()
    });
    let ew = &e0 * &w;
    let kw = ew.transpose() * &body.stiffness * &ew;
    let (lambda, v) = sym_eigen(&kw)?;
    let transform = &ew * &v;
    let project = |m: &Mat<f64>| {
        let mut p = transform.transpose() * m * &transform;
        flexbody_linalg::sparse::symmetrize(&mut p);
        p
    };
    Ok(ElasticBasis {
        shapes: t * &transform,
        mass: project(&body.mass),
        stiffness: project(&body.stiffness),
        damping: body.damping.as_ref().map(project),
        frequencies_hz: lambda
            .iter()
            .map(|l| flexbody_linalg::eigen::frequency_hz(*l))
            .collect(),
        transform,
        floating,
    })
}
