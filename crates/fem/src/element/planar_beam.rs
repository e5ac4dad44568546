//! Planar Euler-Bernoulli beam along the global x axis, bending in the x-z
//! plane: DOFs per node `uz` (w) and `ry` (= -dw/dx, the right-handed rotation
//! about y, so that the rigid-body modes of eq. 12 apply unchanged). This is
//! the element of the report's side beam.

use super::mass_distribution::GAUSS_4;
use super::{
    axis, bending, mat_vec, node_dofs, ElementBehaviour, ElementMatrices, MassDistribution,
    MassPoint, SectionForces, VtkCell,
};
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::section::BeamProperties;
use crate::FemError;
use faer::Mat;

/// A planar beam element (uz, ry per node).
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarBeam {
    pub id: usize,
    pub nodes: [NodeId; 2],
    /// Uses E, density, area and `iy`; shear-rigid, no rotary inertia unless
    /// `rotary_inertia` is set.
    pub properties: BeamProperties,
}

impl PlanarBeam {
    /// Length and direction sign (+1 if node 2 lies at larger x).
    fn geometry(&self, a: [f64; 3], b: [f64; 3]) -> Result<(f64, f64), FemError> {
        let (l, dir) = axis(a, b);
        if l.is_nan() || l <= 0.0 {
            return Err(FemError::ZeroLength { element: self.id });
        }
        if (dir[0].abs() - 1.0).abs() > 1e-9 {
            return Err(FemError::PlanarBeamNotAlongX { element: self.id });
        }
        Ok((l, dir[0].signum()))
    }

    /// Matrices in local DOFs `(w1, ry1, w2, ry2)` of an element along +x.
    fn local(&self, l: f64, s: f64) -> (Mat<f64>, Mat<f64>) {
        let p = &self.properties;
        let ei = p.material.youngs_modulus * p.section.iy;
        let rho_a = p.material.density * p.section.area;
        let rho_i = if p.rotary_inertia {
            p.material.density * p.section.iy
        } else {
            0.0
        };
        let kb = bending::stiffness(ei, 0.0, l);
        let mb = bending::mass(rho_a, rho_i, 0.0, l);
        // Bending block is in (w, dw/dx); ry = -dw/dx along +x. An element
        // pointing along -x has local ry = -ry (global), so the sign is -s.
        let sign = [1.0, -s, 1.0, -s];
        let k = Mat::from_fn(4, 4, |i, j| sign[i] * sign[j] * kb[i][j]);
        let m = Mat::from_fn(4, 4, |i, j| sign[i] * sign[j] * mb[i][j]);
        (k, m)
    }

    /// Length and direction sign of the element in `model`.
    fn geometry_in(&self, model: &Model) -> Result<(f64, f64), FemError> {
        self.geometry(model.coords(self.nodes[0]), model.coords(self.nodes[1]))
    }
}

impl ElementBehaviour for PlanarBeam {
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
        node_dofs(&self.nodes, &[DofKind::Uz, DofKind::Ry])
    }

    fn validate(&self, model: &Model) -> Result<(), FemError> {
        self.geometry_in(model).map(|_| ())
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        let (l, s) = self.geometry_in(model)?;
        let (stiffness, mass) = self.local(l, s);
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness,
            mass,
            damping: None,
        })
    }

    /// Four Gauss points along the axis moving with the shape functions of
    /// the mass matrix, with the bending rotary inertia `rho Iy` about y if
    /// the beam has rotary inertia: exact for the element's mass matrix.
    fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        let (a, b) = (model.coords(self.nodes[0]), model.coords(self.nodes[1]));
        let (l, s) = self.geometry(a, b)?;
        let p = &self.properties;
        let rho = p.material.density;
        let rho_i = if p.rotary_inertia {
            rho * p.section.iy
        } else {
            0.0
        };
        // The bending block is in (w, dw/dx) along the element's own x
        // ([`Self::local`]); the section turns by ry = -s dw/dx.
        let sign = [1.0, -s, 1.0, -s];
        let points =
            GAUSS_4
                .iter()
                .map(|&(xi, w)| {
                    let (n_v, n_th) = bending::shapes(0.0, l, xi);
                    let mut inertia = [[0.0; 3]; 3];
                    inertia[1][1] = rho_i * l * w;
                    MassPoint {
                        position: std::array::from_fn(|d| a[d] + xi * (b[d] - a[d])),
                        mass: rho * p.section.area * l * w,
                        inertia,
                        translation: Mat::from_fn(3, 4, |d, c| {
                            if d == 2 {
                                sign[c] * n_v[c]
                            } else {
                                0.0
                            }
                        }),
                        rotation: Mat::from_fn(3, 4, |d, c| {
                            if d == 1 {
                                -s * sign[c] * n_th[c]
                            } else {
                                0.0
                            }
                        }),
                    }
                })
                .collect();
        Ok(MassDistribution::Points(points))
    }

    fn has_section_forces(&self) -> bool {
        true
    }

    /// Section forces `Qz` and `My` at both ends (report eq. 25).
    fn section_forces(
        &self,
        model: &Model,
        u: &[f64],
        acc: &[f64],
    ) -> Result<Option<SectionForces>, FemError> {
        let (l, s) = self.geometry_in(model)?;
        let (k, m) = self.local(l, s);
        let ku = mat_vec(&k, u);
        let ma = mat_vec(&m, acc);
        let f: Vec<f64> = ku.iter().zip(&ma).map(|(x, y)| x + y).collect();
        let mut out = SectionForces::default();
        // Qz, My in global DOF sense, turned to the element's local frame (x
        // along the element): local z = global z, local y = s * global y.
        out.start[2] = -f[0];
        out.start[4] = -s * f[1];
        out.end[2] = f[2];
        out.end[4] = s * f[3];
        Ok(Some(out))
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::LINE)
    }
}
