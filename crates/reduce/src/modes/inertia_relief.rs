//! Inertia-relief attachment modes (report 5.2.2, eq. 18-20).
//!
//! Unit loads on a free body accelerate it; with M-orthonormal rigid-body
//! modes `T_st` the rigid acceleration is `T_st^T P_1` and its inertia forces
//! `-M T_st T_st^T P_1`. Together with the unit loads they form
//! self-equilibrated load groups `P_g = G^T P_1 = (I - M T_st T_st^T) P_1`,
//! which do no work on rigid-body motion (`T_st^T P_g = 0`). Their static
//! response is solved on a statically determinate support (Bild 4a: all DOFs
//! of one node; never a support that constrains the body, Bild 4b), and the
//! rigid part removed: `t = G x`, `G = I - T_st T_st^T M` (eq. 20).

use super::attachment::{attachment_modes, static_factor};
use super::rigid::RigidModes;
use crate::ReduceError;
use faer::{Mat, MatRef};
use flexbody_fem::DofMap;
use flexbody_linalg::ldlt::Factor;
use flexbody_linalg::ordering::Ordering;
use flexbody_linalg::pencil::Pencil;
use flexbody_linalg::progress::{NoProgress, Progress, Stage};
use flexbody_linalg::{sparse, SparseMat};

/// `P_g = (I - M T_st T_st^T) P_1`: loads in equilibrium with the inertia of
/// the rigid-body motion they cause.
pub fn self_equilibrated_loads(mass: &SparseMat, rigid: &RigidModes, loads: &Mat<f64>) -> Mat<f64> {
    equilibrated(|x| sparse::symmetric_mul(mass, x), rigid, loads)
}

/// [`self_equilibrated_loads`] with the products `M X` of `mul_mass`.
fn equilibrated(
    mul_mass: impl Fn(MatRef<'_, f64>) -> Mat<f64>,
    rigid: &RigidModes,
    loads: &Mat<f64>,
) -> Mat<f64> {
    let t = &rigid.vectors;
    let rigid_accel = t.transpose() * loads;
    loads - mul_mass((t * &rigid_accel).as_ref())
}

/// Chooses a statically determinate support: exactly as many DOFs as there
/// are rigid-body modes, with the rigid-mode rows at those DOFs regular (so
/// they fix all rigid motion and constrain nothing else). DOFs of
/// `preferred` (e.g. all DOFs of the first interface node) are taken first,
/// then the DOFs that best complete the set.
pub fn statically_determinate_support(rigid: &RigidModes, preferred: &[usize]) -> Vec<usize> {
    let nr = rigid.count();
    let m = rigid.vectors.nrows();
    let row = |i: usize| -> Vec<f64> { (0..nr).map(|j| rigid.vectors[(i, j)]).collect() };
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut chosen = Vec::new();
    let residual = |basis: &Vec<Vec<f64>>, mut v: Vec<f64>| -> Vec<f64> {
        for _ in 0..2 {
            for q in basis {
                let c: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
                for (x, y) in v.iter_mut().zip(q) {
                    *x -= c * y;
                }
            }
        }
        v
    };
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = (0..m).map(|i| norm(&row(i))).fold(0.0, f64::max);
    let take = |i: usize, basis: &mut Vec<Vec<f64>>, chosen: &mut Vec<usize>| -> bool {
        let r = residual(basis, row(i));
        let n = norm(&r);
        if n > 1e-6 * scale {
            basis.push(r.iter().map(|x| x / n).collect());
            chosen.push(i);
            true
        } else {
            false
        }
    };
    for &i in preferred {
        if chosen.len() == nr {
            break;
        }
        take(i, &mut basis, &mut chosen);
    }
    while chosen.len() < nr {
        let best = (0..m)
            .filter(|i| !chosen.contains(i))
            .map(|i| (norm(&residual(&basis, row(i))), i))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, i)| i);
        match best {
            Some(i) if take(i, &mut basis, &mut chosen) => {}
            _ => break,
        }
    }
    chosen.sort_unstable();
    chosen
}

/// Checks that `support` is statically determinate for `rigid`.
pub fn check_support(
    rigid: &RigidModes,
    support: &[usize],
    dof_map: &DofMap,
) -> Result<(), ReduceError> {
    let nr = rigid.count();
    let dofs = support.iter().map(|&i| dof_map.dof(i)).collect();
    if support.len() != nr {
        return Err(ReduceError::SupportCount {
            given: support.len(),
            needed: nr,
            dofs,
        });
    }
    let auto = statically_determinate_support(rigid, support);
    if auto.len() != nr || auto.iter().any(|i| !support.contains(i)) {
        return Err(ReduceError::SupportNotDeterminate(dofs));
    }
    Ok(())
}

/// Inertia-relief attachment modes `T_stat,a = G S°^-1 G^T P_1` (eq. 20),
/// solved on the statically determinate `support`. One factorisation of the
/// supported stiffness, one block solve for all load cases. Without
/// rigid-body modes (a supported body) these are plain attachment modes.
pub fn inertia_relief_attachment_modes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    rigid: &RigidModes,
    loads: &Mat<f64>,
    support: &[usize],
    dof_map: &DofMap,
) -> Result<Mat<f64>, ReduceError> {
    if rigid.count() == 0 {
        return attachment_modes(stiffness, loads, dof_map);
    }
    check_support(rigid, support, dof_map)?;
    let hook: &dyn Progress = &NoProgress;
    let pencil = Pencil::analyze(stiffness, mass, None, Ordering::Auto, hook)?;
    Ok(inertia_relief_on(&pencil, rigid, loads, support, dof_map, hook)?.0)
}

/// [`inertia_relief_attachment_modes`] on the pencil's factor of `K` held
/// at the `support` equations (a checked support of a body with rigid-body
/// modes), returned with it: the held operator of the Lanczos run
/// afterwards ([`flexbody_linalg::lanczos::Held`]).
pub(crate) fn inertia_relief_on(
    pencil: &Pencil,
    rigid: &RigidModes,
    loads: &Mat<f64>,
    support: &[usize],
    dof_map: &DofMap,
    progress: &dyn Progress,
) -> Result<(Mat<f64>, Factor), ReduceError> {
    let held = static_factor(pencil, support, SUPPORTED, dof_map, progress)?;
    progress.report(&Stage::Solves {
        columns: loads.ncols(),
    });
    let t_a = relieved_modes(
        |x| pencil.mul_mass(x),
        rigid,
        loads,
        |mut p_g| {
            for &i in support {
                for j in 0..p_g.ncols() {
                    p_g[(i, j)] = 0.0;
                }
            }
            held.solve_in_place(p_g.as_mut());
            p_g
        },
    )?;
    Ok((t_a, held))
}

/// What a singular stiffness on the support is called in errors.
const SUPPORTED: &str = "the stiffness matrix on the statically determinate support";

/// Eq. 20 around a solver of the supported body: `solve(P_g)` returns `x`
/// with `K x = P_g` on the free equations and `x = 0` on the support; the
/// result is `G x = x - T_st (T_st^T M x)`. `mul_mass` gives `M X`.
fn relieved_modes(
    mul_mass: impl Fn(MatRef<'_, f64>) -> Mat<f64>,
    rigid: &RigidModes,
    loads: &Mat<f64>,
    solve: impl FnOnce(Mat<f64>) -> Mat<f64>,
) -> Result<Mat<f64>, ReduceError> {
    let p_g = equilibrated(&mul_mass, rigid, loads);
    let x = solve(p_g);
    let t = &rigid.vectors;
    let mx = mul_mass(x.as_ref());
    let c = t.transpose() * &mx;
    Ok(&x - t * &c)
}
