//! Three-node 3D beam (B32): a quadratic isoparametric Timoshenko beam, 6
//! DOFs per node, straight or curved.
//!
//! Nodes in Abaqus/CalculiX order: end, middle, end (`xi = -1, 0, 1`). The
//! axis `x(xi) = sum_a N_a(xi) x_a` and the displacements `u` and section
//! rotations `theta` (global components) share the quadratic shape
//! functions `N = [xi (xi - 1) / 2, 1 - xi^2, xi (xi + 1) / 2]`.
//!
//! Local frame at each point of the axis: x the unit tangent `t = x' / |x'|`,
//! y the part of the orientation vector normal to it, z = x cross y (as for
//! B31, so a curved element's frame turns with its axis). Strains of the
//! linearised Reissner beam, `gamma = R (u' + t x theta)` and
//! `kappa = R theta'` (`'` the derivative along the arc, `R` the frame):
//! axial strain `t . u'`, shear `e_y . u' - e_z . theta` and
//! `e_z . u' + e_y . theta`, twist and curvatures `R theta'`; section
//! stiffness `diag(E A, G A_sy, G A_sz, G J, E I_y, E I_z)` as B31's
//! (`I_y` resists bending in the local x-z plane, `ry = -dw/dx`).
//!
//! Stiffness: two Gauss points along the axis (reduced). On a straight
//! element that integrates axial, torsion and bending exactly and the
//! shear at the points where it is exact, so the element neither locks in
//! shear nor has spurious zero-energy modes (six strains at two points
//! span the twelve deformation modes). Mass: consistent, three Gauss
//! points (exact on a straight element), translation `rho A` and rotary
//! inertia `rho (I_y + I_z)` about the axis, `rho I_y`, `rho I_z` about the
//! section's axes.
//!
//! Section forces (report eq. 25): the element's end forces `K u + M a`
//! at its first and last node, in the local frame there.

use super::beam::local_frame;
use super::{
    mat_vec, node_dofs, ElementBehaviour, ElementMatrices, ElementType, MassDistribution,
    MassPoint, SectionForces, SectionKind, SectionValues, VtkCell,
};
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::section::{BeamProperties, BeamTheory};
use crate::FemError;
use faer::Mat;

/// The deck's three-node beam.
pub(super) const ELEMENT_TYPES: &[ElementType] = &[ElementType {
    name: "B32",
    nodes: 3,
    section: SectionKind::Beam,
    reference_nodes: &[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]],
    build: |id, nodes, section| match (section, nodes) {
        (
            SectionValues::Beam {
                material,
                constants,
                orientation,
            },
            &[a, b, c],
        ) if material.anisotropy.is_none() => Ok(QuadraticBeam {
            id,
            nodes: [a, b, c],
            properties: BeamProperties::new(
                material.clone(),
                constants.clone(),
                BeamTheory::Timoshenko,
            ),
            orientation: *orientation,
        }
        .into()),
        (SectionValues::Beam { .. }, &[_, _, _]) => Err(FemError::InvalidElement {
            element: id,
            reason: "B32 beams take isotropic materials only (an anisotropic *ELASTIC \
                     has no meaning for the beam's section constants)"
                .into(),
        }),
        _ => Err(super::registry::wrong_section("B32", id, section)),
    },
}];

/// Number of DOFs: 6 at each of the 3 nodes.
const NDOF: usize = 18;

/// Two-point Gauss rule on `[-1, 1]` (stiffness).
const GAUSS_2: [(f64, f64); 2] = [
    (-0.577_350_269_189_625_8, 1.0),
    (0.577_350_269_189_625_8, 1.0),
];

/// Three-point Gauss rule on `[-1, 1]` (mass).
const GAUSS_3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// A three-node 3D beam element (B32).
#[derive(Clone, Debug, PartialEq)]
pub struct QuadraticBeam {
    pub id: usize,
    /// End, middle, end.
    pub nodes: [NodeId; 3],
    /// Timoshenko, with rotary inertia.
    pub properties: BeamProperties,
    /// Approximate direction of the local y axis (global components).
    pub orientation: [f64; 3],
}

/// The element at one point of its axis.
struct Station {
    /// Shape functions.
    n: [f64; 3],
    /// Their derivatives along the arc, `dN/ds`.
    dn: [f64; 3],
    /// `ds/dxi`.
    jac: f64,
    /// Local axes (rows: x = tangent, y, z).
    frame: [[f64; 3]; 3],
    /// Position on the axis.
    position: [f64; 3],
}

impl QuadraticBeam {
    fn coords(&self, model: &Model) -> [[f64; 3]; 3] {
        self.nodes.map(|n| model.coords(n))
    }

    /// Refuses an element that has no length, folds back on itself (its
    /// middle node outside the middle half of the chord, where `ds/dxi`
    /// changes sign), or whose orientation vector is parallel to its axis
    /// somewhere.
    fn check(&self, x: &[[f64; 3]; 3]) -> Result<(), FemError> {
        if x.iter().flatten().any(|c| !c.is_finite()) {
            return Err(self.invalid("node coordinates must be finite".into()));
        }
        let chord: [f64; 3] = std::array::from_fn(|i| x[2][i] - x[0][i]);
        let length = dot(&chord, &chord).sqrt();
        let size = x
            .iter()
            .flat_map(|a| x.iter().map(move |b| dist(a, b)))
            .fold(0.0_f64, f64::max);
        if length <= 1e-12 * size || size == 0.0 {
            return Err(FemError::ZeroLength { element: self.id });
        }
        // x'(xi) is linear in xi: along the chord at both ends means along
        // it everywhere.
        for xi in [-1.0, 1.0] {
            let (_, dn) = shape(xi);
            let tangent: [f64; 3] = std::array::from_fn(|i| (0..3).map(|a| dn[a] * x[a][i]).sum());
            if dot(&tangent, &chord) <= 1e-8 * length * length {
                return Err(self.invalid(format!(
                    "its middle node {} is not within the middle half of the element: the \
                     element folds back on itself",
                    self.nodes[1]
                )));
            }
        }
        for xi in [-1.0, 1.0]
            .into_iter()
            .chain(GAUSS_2.iter().chain(&GAUSS_3).map(|p| p.0))
        {
            self.station(x, xi)?;
        }
        Ok(())
    }

    /// The element at `xi`.
    fn station(&self, x: &[[f64; 3]; 3], xi: f64) -> Result<Station, FemError> {
        let (n, dn_dxi) = shape(xi);
        let tangent: [f64; 3] = std::array::from_fn(|i| (0..3).map(|a| dn_dxi[a] * x[a][i]).sum());
        let jac = dot(&tangent, &tangent).sqrt();
        if jac.is_nan() || jac <= 0.0 {
            return Err(FemError::ZeroLength { element: self.id });
        }
        let t = tangent.map(|v| v / jac);
        let frame = local_frame(t, self.orientation).ok_or(FemError::OrientationParallel {
            element: self.id,
            orientation: self.orientation,
        })?;
        Ok(Station {
            n,
            dn: dn_dxi.map(|d| d / jac),
            jac,
            frame,
            position: std::array::from_fn(|i| (0..3).map(|a| n[a] * x[a][i]).sum()),
        })
    }

    /// The strains `[eps, gamma_y, gamma_z, kappa_x, kappa_y, kappa_z]` of
    /// the element's DOFs at a station (6 x 18).
    fn strain_matrix(s: &Station) -> Mat<f64> {
        let [t, ey, ez] = s.frame;
        let mut b = Mat::<f64>::zeros(6, NDOF);
        for a in 0..3 {
            let (u, r) = (6 * a, 6 * a + 3);
            for i in 0..3 {
                b[(0, u + i)] = t[i] * s.dn[a];
                b[(1, u + i)] = ey[i] * s.dn[a];
                b[(1, r + i)] = -ez[i] * s.n[a];
                b[(2, u + i)] = ez[i] * s.dn[a];
                b[(2, r + i)] = ey[i] * s.n[a];
                b[(3, r + i)] = t[i] * s.dn[a];
                b[(4, r + i)] = ey[i] * s.dn[a];
                b[(5, r + i)] = ez[i] * s.dn[a];
            }
        }
        b
    }

    /// The section stiffness `diag(E A, G A_sy, G A_sz, G J, E I_y, E I_z)`.
    fn section_stiffness(&self) -> [f64; 6] {
        let p = &self.properties;
        let (e, g, s) = (
            p.material.youngs_modulus,
            p.material.shear_modulus,
            &p.section,
        );
        [
            e * s.area,
            g * s.shear_area_y,
            g * s.shear_area_z,
            g * s.torsion,
            e * s.iy,
            e * s.iz,
        ]
    }

    /// Rotary inertia per length about the local x, y, z axes.
    fn rotary_inertia(&self) -> [f64; 3] {
        let p = &self.properties;
        let (rho, s) = (p.material.density, &p.section);
        let rot = if p.rotary_inertia { 1.0 } else { 0.0 };
        [rho * (s.iy + s.iz), rot * rho * s.iy, rot * rho * s.iz]
    }

    /// `u = translation u_e` and `theta = rotation u_e` at a station (3 x 18
    /// each, global components).
    fn interpolation(s: &Station) -> (Mat<f64>, Mat<f64>) {
        let mut u = Mat::<f64>::zeros(3, NDOF);
        let mut th = Mat::<f64>::zeros(3, NDOF);
        for a in 0..3 {
            for i in 0..3 {
                u[(i, 6 * a + i)] = s.n[a];
                th[(i, 6 * a + 3 + i)] = s.n[a];
            }
        }
        (u, th)
    }

    /// The mass points of the three-point rule: mass `rho A ds`, inertia
    /// `R^T diag(rotary inertia) R ds` about the axis point.
    fn mass_points(&self, x: &[[f64; 3]; 3]) -> Result<Vec<MassPoint>, FemError> {
        let p = &self.properties;
        let rho_a = p.material.density * p.section.area;
        let j_local = self.rotary_inertia();
        GAUSS_3
            .iter()
            .map(|&(xi, w)| {
                let s = self.station(x, xi)?;
                let ds = s.jac * w;
                let r = s.frame;
                let (translation, rotation) = Self::interpolation(&s);
                Ok(MassPoint {
                    position: s.position,
                    mass: rho_a * ds,
                    inertia: std::array::from_fn(|i| {
                        std::array::from_fn(|j| {
                            (0..3).map(|c| r[c][i] * j_local[c] * r[c][j]).sum::<f64>() * ds
                        })
                    }),
                    translation,
                    rotation,
                })
            })
            .collect()
    }

    /// Stiffness and consistent mass in global components (18 x 18).
    fn global_matrices(&self, x: &[[f64; 3]; 3]) -> Result<(Mat<f64>, Mat<f64>), FemError> {
        self.check(x)?;
        let d = self.section_stiffness();
        let mut k = Mat::<f64>::zeros(NDOF, NDOF);
        for &(xi, w) in &GAUSS_2 {
            let s = self.station(x, xi)?;
            let b = Self::strain_matrix(&s);
            let db = Mat::from_fn(6, NDOF, |i, j| d[i] * s.jac * w * b[(i, j)]);
            k += b.transpose() * db;
        }
        let mut m = Mat::<f64>::zeros(NDOF, NDOF);
        for point in self.mass_points(x)? {
            let j = Mat::from_fn(3, 3, |a, b| point.inertia[a][b]);
            m += point.mass * point.translation.transpose() * &point.translation;
            m += point.rotation.transpose() * &j * &point.rotation;
        }
        Ok((symmetric(k), symmetric(m)))
    }

    fn invalid(&self, reason: String) -> FemError {
        FemError::InvalidElement {
            element: self.id,
            reason,
        }
    }
}

impl ElementBehaviour for QuadraticBeam {
    fn id(&self) -> usize {
        self.id
    }

    fn material_damping(&self) -> Option<crate::model::Rayleigh> {
        self.properties.material.damping
    }

    fn nodes(&self) -> Vec<NodeId> {
        self.nodes.to_vec()
    }

    fn dofs(&self) -> Vec<Dof> {
        node_dofs(&self.nodes, &DofKind::ALL)
    }

    fn validate(&self, model: &Model) -> Result<(), FemError> {
        self.check(&self.coords(model))
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        let (stiffness, mass) = self.global_matrices(&self.coords(model))?;
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness,
            mass,
            damping: None,
        })
    }

    /// The three Gauss points of the mass matrix, each a rigid slice moving
    /// with the interpolated translation and rotation: exact for the
    /// element's mass matrix.
    fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        let x = self.coords(model);
        self.check(&x)?;
        Ok(MassDistribution::Points(self.mass_points(&x)?))
    }

    fn has_section_forces(&self) -> bool {
        true
    }

    /// All six section forces at both ends (the first and the last node),
    /// each in the local frame at that end.
    fn section_forces(
        &self,
        model: &Model,
        u: &[f64],
        acc: &[f64],
    ) -> Result<Option<SectionForces>, FemError> {
        let x = self.coords(model);
        let (k, m) = self.global_matrices(&x)?;
        let ku = mat_vec(&k, u);
        let ma = mat_vec(&m, acc);
        let f: Vec<f64> = ku.iter().zip(&ma).map(|(a, b)| a + b).collect();
        let local = |xi: f64, at: usize| -> Result<[f64; 6], FemError> {
            let r = self.station(&x, xi)?.frame;
            Ok(std::array::from_fn(|c| {
                let (block, axis) = (c / 3, c % 3);
                (0..3).map(|i| r[axis][i] * f[at + 3 * block + i]).sum()
            }))
        };
        let start = local(-1.0, 0)?;
        Ok(Some(SectionForces {
            start: start.map(|v| -v),
            end: local(1.0, 12)?,
        }))
    }

    /// VTK's quadratic edge (ends first, then the middle node).
    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell {
            cell_type: 21,
            order: &[0, 2, 1],
        })
    }
}

/// Quadratic shape functions and their `xi` derivatives (end, middle, end).
fn shape(xi: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)],
        [xi - 0.5, -2.0 * xi, xi + 0.5],
    )
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|i| a[i] - b[i]);
    dot(&d, &d).sqrt()
}

/// `(a + a^T) / 2`: exactly symmetric, as the other elements' matrices are.
fn symmetric(a: Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

#[cfg(test)]
mod tests;
