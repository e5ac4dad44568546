//! Two-node 3D beam, 6 DOFs per node, Euler-Bernoulli or Timoshenko.
//!
//! Local frame: x along the beam (node 1 to node 2), y from the orientation
//! vector (its part normal to x), z = x cross y. `Iy` resists bending in the
//! local x-z plane (displacement w, rotation ry = -dw/dx), `Iz` in the x-y
//! plane (v, rz = dv/dx). Local DOF order per node: ux uy uz rx ry rz.

use super::mass_distribution::GAUSS_4;
use super::{
    axis, bending, congruence, mat_vec, node_dofs, ElementBehaviour, ElementMatrices, ElementType,
    MassDistribution, MassPoint, SectionForces, SectionKind, SectionValues, VtkCell,
};
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::section::{BeamProperties, BeamTheory};
use crate::FemError;
use faer::Mat;

/// The deck's beam: B31 is a two-node Timoshenko beam with rotary inertia.
pub(super) const ELEMENT_TYPES: &[ElementType] = &[ElementType {
    name: "B31",
    nodes: 2,
    section: SectionKind::Beam,
    reference_nodes: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
    build: |id, nodes, section| match (section, nodes) {
        (
            SectionValues::Beam {
                material,
                constants,
                orientation,
            },
            &[a, b],
        ) if material.anisotropy.is_none() => Ok(Beam {
            id,
            nodes: [a, b],
            properties: BeamProperties::new(
                material.clone(),
                constants.clone(),
                BeamTheory::Timoshenko,
            ),
            orientation: *orientation,
        }
        .into()),
        (SectionValues::Beam { .. }, &[_, _]) => Err(FemError::InvalidElement {
            element: id,
            reason: "B31 beams take isotropic materials only (an anisotropic *ELASTIC \
                     has no meaning for the beam's section constants)"
                .into(),
        }),
        _ => Err(super::registry::wrong_section("B31", id, section)),
    },
}];

/// A 3D beam element.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    pub id: usize,
    pub nodes: [NodeId; 2],
    pub properties: BeamProperties,
    /// Approximate direction of the local y axis (global components).
    pub orientation: [f64; 3],
}

impl Beam {
    /// Rotation from global to local components (rows: local x, y, z).
    fn rotation(&self, a: [f64; 3], b: [f64; 3]) -> Result<(f64, [[f64; 3]; 3]), FemError> {
        let (l, ex) = axis(a, b);
        if l.is_nan() || l <= 0.0 {
            return Err(FemError::ZeroLength { element: self.id });
        }
        let frame = local_frame(ex, self.orientation).ok_or(FemError::OrientationParallel {
            element: self.id,
            orientation: self.orientation,
        })?;
        Ok((l, frame))
    }

    /// 12x12 transformation `u_local = T u_global`.
    fn transformation(r: &[[f64; 3]; 3]) -> Mat<f64> {
        Mat::from_fn(
            12,
            12,
            |i, j| {
                if i / 3 == j / 3 {
                    r[i % 3][j % 3]
                } else {
                    0.0
                }
            },
        )
    }

    /// The shear parameters `12 E I / (G A_s l^2)` of bending in the x-y
    /// and the x-z plane (zero for Euler-Bernoulli).
    fn shear_parameters(&self, l: f64) -> (f64, f64) {
        let p = &self.properties;
        let (e, g, s) = (
            p.material.youngs_modulus,
            p.material.shear_modulus,
            &p.section,
        );
        match p.theory {
            BeamTheory::EulerBernoulli => (0.0, 0.0),
            BeamTheory::Timoshenko => (
                12.0 * e * s.iz / (g * s.shear_area_y * l * l),
                12.0 * e * s.iy / (g * s.shear_area_z * l * l),
            ),
        }
    }

    /// Local stiffness and mass (12x12).
    fn local_matrices(&self, l: f64) -> (Mat<f64>, Mat<f64>) {
        let p = &self.properties;
        let (e, g, rho) = (
            p.material.youngs_modulus,
            p.material.shear_modulus,
            p.material.density,
        );
        let s = &p.section;
        let (phi_y, phi_z) = self.shear_parameters(l);
        let rot = if p.rotary_inertia { 1.0 } else { 0.0 };
        let mut k = Mat::<f64>::zeros(12, 12);
        let mut m = Mat::<f64>::zeros(12, 12);
        // Axial: ux1, ux2.
        let ka = e * s.area / l;
        let ma = rho * s.area * l / 6.0;
        let ax = [0, 6];
        for (a, &i) in ax.iter().enumerate() {
            for (b, &j) in ax.iter().enumerate() {
                k[(i, j)] += if a == b { ka } else { -ka };
                m[(i, j)] += if a == b { 2.0 * ma } else { ma };
            }
        }
        // Torsion: rx1, rx2 (polar inertia Iy + Iz for the mass).
        let kt = g * s.torsion / l;
        let mt = rho * (s.iy + s.iz) * l / 6.0;
        let tx = [3, 9];
        for (a, &i) in tx.iter().enumerate() {
            for (b, &j) in tx.iter().enumerate() {
                k[(i, j)] += if a == b { kt } else { -kt };
                m[(i, j)] += if a == b { 2.0 * mt } else { mt };
            }
        }
        // Bending in x-y: (uy, rz), rz = dv/dx: signs +1.
        let kb = bending::stiffness(e * s.iz, phi_y, l);
        let mb = bending::mass(rho * s.area, rot * rho * s.iz, phi_y, l);
        scatter(
            &mut k,
            &mut m,
            &kb,
            &mb,
            [1, 5, 7, 11],
            [1.0, 1.0, 1.0, 1.0],
        );
        // Bending in x-z: (uz, ry), ry = -dw/dx: rotation signs -1.
        let kb = bending::stiffness(e * s.iy, phi_z, l);
        let mb = bending::mass(rho * s.area, rot * rho * s.iy, phi_z, l);
        scatter(
            &mut k,
            &mut m,
            &kb,
            &mb,
            [2, 4, 8, 10],
            [1.0, -1.0, 1.0, -1.0],
        );
        (k, m)
    }

    /// The coordinates of the two nodes.
    fn ends(&self, model: &Model) -> ([f64; 3], [f64; 3]) {
        (model.coords(self.nodes[0]), model.coords(self.nodes[1]))
    }
}

impl ElementBehaviour for Beam {
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
        let (a, b) = self.ends(model);
        self.rotation(a, b).map(|_| ())
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        let (a, b) = self.ends(model);
        let (l, r) = self.rotation(a, b)?;
        let t = Self::transformation(&r);
        let (k, m) = self.local_matrices(l);
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness: congruence(&k, &t),
            mass: congruence(&m, &t),
            damping: None,
        })
    }

    /// Four Gauss points along the axis, moving with the shape functions
    /// of the mass matrix (Przemieniecki's; axial displacement and
    /// twist linear), with the section's rotary inertia: the polar
    /// `rho (Iy + Iz)` always, bending `rho Iy`, `rho Iz` with rotary
    /// inertia. Exact for the element's mass matrix.
    fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        let (a, b) = self.ends(model);
        let (l, r) = self.rotation(a, b)?;
        let t = Self::transformation(&r);
        let p = &self.properties;
        let (rho, s) = (p.material.density, &p.section);
        let (phi_y, phi_z) = self.shear_parameters(l);
        let rot = if p.rotary_inertia { 1.0 } else { 0.0 };
        // Rotary inertia per length about the local x, y, z axes.
        let j_local = [rho * (s.iy + s.iz), rot * rho * s.iy, rot * rho * s.iz];
        let to_global = Mat::from_fn(3, 3, |i, j| r[j][i]);
        let points = GAUSS_4
            .iter()
            .map(|&(xi, w)| {
                let mut u = Mat::<f64>::zeros(3, 12);
                let mut th = Mat::<f64>::zeros(3, 12);
                u[(0, 0)] = 1.0 - xi;
                u[(0, 6)] = xi;
                th[(0, 3)] = 1.0 - xi;
                th[(0, 9)] = xi;
                // x-y plane (uy, rz), rz = dv/dx: signs +1.
                let (n_v, n_th) = bending::shapes(phi_y, l, xi);
                for (c, i) in [1, 5, 7, 11].into_iter().enumerate() {
                    u[(1, i)] = n_v[c];
                    th[(2, i)] = n_th[c];
                }
                // x-z plane (uz, ry), ry = -dw/dx: the block's rotation is
                // -ry, and the section turns by ry.
                let (n_v, n_th) = bending::shapes(phi_z, l, xi);
                for (c, i) in [2, 4, 8, 10].into_iter().enumerate() {
                    let sign = if c % 2 == 0 { 1.0 } else { -1.0 };
                    u[(2, i)] = sign * n_v[c];
                    th[(1, i)] = -sign * n_th[c];
                }
                MassPoint {
                    position: std::array::from_fn(|d| a[d] + xi * (b[d] - a[d])),
                    mass: rho * s.area * l * w,
                    inertia: std::array::from_fn(|i| {
                        std::array::from_fn(|j| {
                            (0..3).map(|c| r[c][i] * j_local[c] * r[c][j]).sum::<f64>() * l * w
                        })
                    }),
                    translation: &to_global * &u * &t,
                    rotation: &to_global * &th * &t,
                }
            })
            .collect();
        Ok(MassDistribution::Points(points))
    }

    fn has_section_forces(&self) -> bool {
        true
    }

    /// All six section forces at both ends, in the local frame.
    fn section_forces(
        &self,
        model: &Model,
        u: &[f64],
        acc: &[f64],
    ) -> Result<Option<SectionForces>, FemError> {
        let (a, b) = self.ends(model);
        let (l, r) = self.rotation(a, b)?;
        let t = Self::transformation(&r);
        let (k, m) = self.local_matrices(l);
        let ul = mat_vec(&t, u);
        let al = mat_vec(&t, acc);
        let ku = mat_vec(&k, &ul);
        let ma = mat_vec(&m, &al);
        let f: Vec<f64> = ku.iter().zip(&ma).map(|(x, y)| x + y).collect();
        let mut out = SectionForces::default();
        for c in 0..6 {
            out.start[c] = -f[c];
            out.end[c] = f[6 + c];
        }
        Ok(Some(out))
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::LINE)
    }
}

/// The beam's local axes (rows: x, y, z) at a point where its axis has the
/// unit tangent `ex`: y is the part of the orientation vector `v` normal to
/// `ex`, z = x cross y. `None` if `v` is (within 1e-8) parallel to `ex`.
pub(super) fn local_frame(ex: [f64; 3], v: [f64; 3]) -> Option<[[f64; 3]; 3]> {
    let vx = v[0] * ex[0] + v[1] * ex[1] + v[2] * ex[2];
    let y = [v[0] - vx * ex[0], v[1] - vx * ex[1], v[2] - vx * ex[2]];
    let ny = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
    let nv = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if ny.is_nan() || ny <= 1e-8 * nv {
        return None;
    }
    let ey = [y[0] / ny, y[1] / ny, y[2] / ny];
    let ez = [
        ex[1] * ey[2] - ex[2] * ey[1],
        ex[2] * ey[0] - ex[0] * ey[2],
        ex[0] * ey[1] - ex[1] * ey[0],
    ];
    Some([ex, ey, ez])
}

/// Adds a 4x4 bending block into 12x12 matrices at `idx`, with DOF signs.
fn scatter(
    k: &mut Mat<f64>,
    m: &mut Mat<f64>,
    kb: &[[f64; 4]; 4],
    mb: &[[f64; 4]; 4],
    idx: [usize; 4],
    sign: [f64; 4],
) {
    for a in 0..4 {
        for b in 0..4 {
            k[(idx[a], idx[b])] += sign[a] * sign[b] * kb[a][b];
            m[(idx[a], idx[b])] += sign[a] * sign[b] * mb[a][b];
        }
    }
}
