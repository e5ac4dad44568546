//! Lumped nodal masses by HRZ lumping (Hinton, Rock and Zienkiewicz 1976):
//! a diagonal mass per node, three translations and three rotations, for
//! formats that carry one (MBDyn's modal `.fem` file).
//!
//! Element by element, with `M_e` the element's own mass matrix in global
//! components ([`Element::matrices`](crate::Element::matrices)) and `S_k`
//! the element's DOFs of one kind `k` (`ux` .. `rz`):
//!
//! - the element's mass in `k` is `m_k = sum_{i, j in S_k} (M_e)_ij`, the
//!   kinetic energy (times two) of a unit motion of every DOF of kind `k`
//!   with the others held. For a translation this is a rigid translation,
//!   so `m_k` is the element's mass. For a rotation it is a uniform unit
//!   rotation of the nodes with their translations held: the element's
//!   rotary inertia (a beam's torsion `rho I_p L` exactly; its bending the
//!   sections' rotary inertia plus the inertia of the Hermite field of equal
//!   end slopes, `m L^2 / 210` for an Euler-Bernoulli beam without rotary
//!   inertia; a point mass's `J_kk`);
//! - each diagonal entry of `S_k` is scaled so that they sum to `m_k`:
//!   `l_i = (M_e)_ii m_k / sum_{j in S_k} (M_e)_jj`.
//!
//! The diagonal of a mass matrix is non-negative, and so is `m_k` (M_e is
//! positive semi-definite), so every lumped mass is non-negative, unlike
//! row-sum lumping, which gives the corners of a C3D20 negative masses.
//! Each direction's sum over the nodes is the mesh's mass; the element's
//! off-diagonal inertia (a point mass's products of inertia) is dropped.
//! Fixed DOFs keep their mass: the elements' matrices are taken before any
//! DOF is fixed, so the lumped masses hold the whole body's mass.

use crate::dof::DofKind;
use crate::element::ElementMatrices;
use crate::model::{Model, NodeId};
use crate::FemError;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// A node's lumped masses: `ux, uy, uz` (kg) and `rx, ry, rz` (kg m^2).
pub type NodeMass = [f64; 6];

/// Elements whose matrices are held at a time (in parallel) before their
/// diagonals are added in element order.
const BATCH: usize = 4096;

/// The HRZ diagonal of one element's mass matrix: one lumped mass per entry
/// of `em.dofs`, in that order (see the module docs). Kinds without mass
/// (a zero diagonal) lump to zero.
pub fn hrz_diagonal(em: &ElementMatrices) -> Vec<f64> {
    let m = &em.mass;
    let mut lumped = vec![0.0; em.dofs.len()];
    for kind in DofKind::ALL {
        let of_kind: Vec<usize> = (0..em.dofs.len())
            .filter(|&i| em.dofs[i].kind == kind)
            .collect();
        let total: f64 = of_kind
            .iter()
            .map(|&i| of_kind.iter().map(|&j| m[(i, j)]).sum::<f64>())
            .sum();
        let diagonal: f64 = of_kind.iter().map(|&i| m[(i, i)]).sum();
        if diagonal <= 0.0 || total <= 0.0 {
            continue;
        }
        let scale = total / diagonal;
        for &i in &of_kind {
            lumped[i] = m[(i, i)] * scale;
        }
    }
    lumped
}

/// The lumped masses of every node of `model` (zero where no element has
/// mass), summed over the elements' [`hrz_diagonal`]s in element order.
pub fn lumped_masses(model: &Model) -> Result<BTreeMap<NodeId, NodeMass>, FemError> {
    let mut masses: BTreeMap<NodeId, NodeMass> =
        model.nodes().iter().map(|n| (n.id, [0.0; 6])).collect();
    for batch in model.elements().chunks(BATCH) {
        let diagonals = batch
            .par_iter()
            .map(|e| {
                let em = e.matrices(model)?;
                let diagonal = hrz_diagonal(&em);
                Ok(em.dofs.into_iter().zip(diagonal).collect::<Vec<_>>())
            })
            .collect::<Result<Vec<_>, FemError>>()?;
        for (dof, value) in diagonals.into_iter().flatten() {
            masses.entry(dof.node).or_insert([0.0; 6])[dof.kind.index()] += value;
        }
    }
    Ok(masses)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{Element, PointMass, SolidKind};
    use crate::mesh::{BeamLine, BeamLineKind, SolidBlock};
    use crate::section::{BeamProperties, BeamTheory, Material, SectionShape};
    use crate::Dof;

    fn steel() -> Material {
        Material::new(2.1e11, 0.3, 7850.0).unwrap()
    }

    /// The sum of `lumped` over each kind of `dofs`.
    fn sums(dofs: &[Dof], lumped: &[f64]) -> [f64; 6] {
        let mut s = [0.0; 6];
        for (d, v) in dofs.iter().zip(lumped) {
            s[d.kind.index()] += v;
        }
        s
    }

    /// One C3D20 of 0.2 x 0.1 x 0.3 m: the consistent mass matrix's row
    /// sums are negative at the corners, HRZ's diagonal is positive
    /// everywhere and sums to the element's mass in each direction.
    #[test]
    fn hrz_of_a_c3d20_is_positive_where_row_sums_are_negative() {
        let size = [0.2, 0.1, 0.3];
        let block = SolidBlock {
            kind: SolidKind::C3D20,
            cells: [1, 1, 1],
            origin: [0.0; 3],
            size,
            corner_distortion: 0.0,
            edge_distortion: 0.0,
            seed: 1,
        };
        let mesh = block.mesh();
        let model = Model::of(mesh.nodes(), mesh.elements(&steel()))
            .build()
            .unwrap();
        let em = model.elements()[0].matrices(&model).unwrap();
        let mass = 7850.0 * size.iter().product::<f64>();
        // Row-sum lumping: negative corner masses.
        let row_sum = |i: usize| (0..em.dofs.len()).map(|j| em.mass[(i, j)]).sum::<f64>();
        assert!((0..em.dofs.len()).any(|i| row_sum(i) < 0.0));
        let lumped = hrz_diagonal(&em);
        assert!(lumped.iter().all(|&v| v > 0.0), "{lumped:?}");
        for s in &sums(&em.dofs, &lumped)[..3] {
            assert!((s - mass).abs() <= 1e-12 * mass, "{s} against {mass}");
        }
        // The same through the model, node by node.
        let nodal = lumped_masses(&model).unwrap();
        assert_eq!(nodal.len(), 20);
        for d in 0..3 {
            let s: f64 = nodal.values().map(|m| m[d]).sum();
            assert!((s - mass).abs() <= 1e-12 * mass);
        }
        // Corners take less than mid-edge nodes.
        let corner = nodal[&1][0];
        let edge = nodal.values().map(|m| m[0]).fold(0.0, f64::max);
        assert!(corner < edge, "{corner} against {edge}");
    }

    /// A free 3D beam of 8 Euler-Bernoulli elements with a point mass,
    /// one end clamped: every mass is non-negative, each translation sums
    /// to the beam's and the point's mass (the clamped node's included),
    /// each rotation to the elements' rotary inertias and the point's.
    #[test]
    fn hrz_of_a_beam_keeps_the_mass_of_every_direction_and_of_fixed_nodes() {
        let section = SectionShape::Rect {
            width: 0.04,
            height: 0.06,
        }
        .constants()
        .unwrap();
        let properties = BeamProperties::new(steel(), section.clone(), BeamTheory::EulerBernoulli);
        let (l, n) = (1.6, 8);
        let clamped: Vec<Dof> = DofKind::ALL.iter().map(|&k| Dof::new(1, k)).collect();
        let line = BeamLine {
            cells: n,
            start: [0.1, 0.2, 0.3],
            end: [0.1 + l, 0.2, 0.3],
            kind: BeamLineKind::Spatial {
                orientation: [0.0, 1.0, 0.0],
            },
            properties,
        }
        .model(clamped)
        .unwrap();
        let point = PointMass {
            id: 100,
            node: 5,
            mass: 3.0,
            inertia: [0.1, 0.2, 0.3, 0.01, 0.0, 0.0],
        };
        let mut elements = line.elements().to_vec();
        elements.push(Element::PointMass(point));
        let model = Model::of(line.nodes().to_vec(), elements)
            .fixed(line.fixed_dofs().copied().collect())
            .build()
            .unwrap();
        let beam_mass = 7850.0 * section.area * l;
        let mass = beam_mass + 3.0;
        let nodal = lumped_masses(&model).unwrap();
        assert!(nodal.values().flatten().all(|&v| v >= 0.0));
        let total = |d: usize| nodal.values().map(|m| m[d]).sum::<f64>();
        for d in 0..3 {
            assert!((total(d) - mass).abs() <= 1e-12 * mass, "{}", total(d));
        }
        // The clamped node keeps half an element's mass.
        let half = beam_mass / n as f64 / 2.0;
        assert!((nodal[&1][0] - half).abs() <= 1e-12 * half);
        // Rotations: torsion rho I_p L exactly (the section's polar
        // moment), bending m L_e^2 / 210 per element, plus the point's
        // diagonal inertia.
        let le = l / n as f64;
        let torsion = 7850.0 * (section.iy + section.iz) * l;
        let bending = beam_mass * le * le / 210.0;
        for (d, want) in [(3, torsion + 0.1), (4, bending + 0.2), (5, bending + 0.3)] {
            assert!(
                (total(d) - want).abs() <= 1e-12 * want,
                "rotation {d}: {} against {want}",
                total(d)
            );
        }
        // Element by element: each kind's sum is the element's own.
        for e in model.elements() {
            let em = e.matrices(&model).unwrap();
            let s = sums(&em.dofs, &hrz_diagonal(&em));
            for k in DofKind::ALL {
                let of_kind: Vec<usize> = (0..em.dofs.len())
                    .filter(|&i| em.dofs[i].kind == k)
                    .collect();
                let want: f64 = of_kind
                    .iter()
                    .flat_map(|&i| of_kind.iter().map(move |&j| (i, j)))
                    .map(|(i, j)| em.mass[(i, j)])
                    .sum();
                let got = s[k.index()];
                assert!((got - want).abs() <= 1e-12 * want.abs().max(1e-30));
            }
        }
    }
}
