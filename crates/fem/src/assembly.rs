//! Global assembly of stiffness K, mass M and Rayleigh damping D
//! (report eq. 1) into sparse matrices over the free DOFs.

use crate::model::Model;
use crate::FemError;
use faer::sparse::Triplet;
use flexbody_linalg::{sparse, SparseMat};

/// The assembled matrices of a model, over `model.dof_map()`.
#[derive(Clone, Debug)]
pub struct SystemMatrices {
    pub stiffness: SparseMat,
    pub mass: SparseMat,
    /// Rayleigh damping `alpha M + beta K`, if the model has any.
    pub damping: Option<SparseMat>,
}

/// Assembles all elements of `model`. Entries on fixed DOFs are dropped
/// (homogeneous boundary conditions).
pub fn assemble(model: &Model) -> Result<SystemMatrices, FemError> {
    let map = model.dof_map();
    let n = map.len();
    let mut k = Vec::new();
    let mut m = Vec::new();
    for element in model.elements() {
        let em = element.matrices(model)?;
        let eq: Vec<Option<usize>> = em.dofs.iter().map(|d| map.index_of(*d)).collect();
        for (a, ia) in eq.iter().enumerate() {
            let Some(i) = *ia else { continue };
            for (b, ib) in eq.iter().enumerate() {
                let Some(j) = *ib else { continue };
                let kv = em.stiffness[(a, b)];
                let mv = em.mass[(a, b)];
                if kv != 0.0 {
                    k.push(Triplet::new(i, j, kv));
                }
                if mv != 0.0 {
                    m.push(Triplet::new(i, j, mv));
                }
            }
        }
    }
    let stiffness = sparse::from_triplets(n, n, &k)?;
    let mass = sparse::from_triplets(n, n, &m)?;
    let damping = match model.rayleigh() {
        Some(r) if r.alpha != 0.0 || r.beta != 0.0 => {
            let mut t = sparse::triplets_of(&mass, r.alpha);
            t.extend(sparse::triplets_of(&stiffness, r.beta));
            Some(sparse::from_triplets(n, n, &t)?)
        }
        _ => None,
    };
    Ok(SystemMatrices {
        stiffness,
        mass,
        damping,
    })
}
