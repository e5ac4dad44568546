//! Shell elements with six DOFs per node (`ux uy uz rx ry rz`): the MITC
//! shells of Dvorkin and Bathe (S4, four nodes) and of Lee, Lee and Bathe
//! (S3, three nodes: MITC3+), the quadratic (curved) triangle S6 and the
//! quadratic quadrilateral S8 (MITC9 of Bucalem and Bathe on a nine-node
//! surface, its centre node condensed), in the node numbering of
//! Abaqus/CalculiX.
//!
//! **Kinematics.** A degenerated continuum over the reference surface
//! through the nodes: the point at natural coordinates `(r, s)` and
//! thickness coordinate `t` in `[-1, 1]` is
//! `X = sum_a N_a (x_a + h(t) V_a)` with `h(t) = a (t / 2 - o)` (`a` the
//! thickness, `o` Abaqus' offset: where the nodes lie from the
//! mid-surface, in thicknesses), and moves by
//! `U = sum_a N_a (u_a + h(t) theta_a x V_a)`.
//! The director `V_a` is the element's unit normal at node `a`, so warped
//! elements need no correction: a rigid motion (`u_a = c + w x x_a`,
//! `theta_a = w`) moves every point rigidly and strains nothing. S3's
//! rotations carry besides a cubic bubble `27 r s (1 - r - s)` times an
//! internal rotation `theta_b` about in-plane axes (MITC3+), which enriches
//! its bending and is zero under a rigid motion.
//!
//! **Strains.** The covariant strains `e_ij = (g_i . U,j + g_j . U,i) / 2`
//! on the base vectors `g_i = dX/di`; the transverse shear strains `e_rt`,
//! `e_st` are not taken where they are evaluated but interpolated from
//! their values at tying points, which removes shear locking (MITC4: `e_rt`
//! from the edge midpoints `s = +-1`, `e_st` from `r = +-1`; MITC3+: a
//! constant part from three points on the lines from the centroid to the
//! corners and a linear part from three points next to the centroid, Lee,
//! Lee and Bathe, 2014; S6: Nedelec's second-order space from the
//! tangential strains at the two Gauss points of each edge and the
//! element's mean strains, in the manner of MITC6) and S6 takes its
//! membrane and bending strains at the three interior points of its
//! (reduced) rule, against membrane locking; S8 ties all five components as
//! MITC9 and corrects the membrane ones by their mean difference from the
//! compatible ones, so that it passes the patch tests on distorted meshes
//! (`membrane_correction` in `mitc.rs`). They are turned onto a local
//! Cartesian frame (`e1` along `g_r`, `e3` normal to the surface) and meet
//! a plane-stress material (`sigma_33 = 0`) with transverse shear stiffness
//! `k G`, `k = 5/6`. Stiffness `K = int B^T D B dV`: 2 x 2 Gauss points in
//! the plane (S4), six (S3), three (S6; six for its shear) or 3 x 3 (S8),
//! two through the thickness (exact for a flat shell). S8's centre node and
//! S3's bubble are condensed statically in the element: `K = K_bb - K_bc
//! K_cc^-1 K_cb`, their mass and stresses through the same map `u_c =
//! -K_cc^-1 K_cb u_b`.
//!
//! **Drilling.** The rotation about the normal has no stiffness in the
//! continuum; a penalty `gamma (theta_n - w)^2 / 2` per area ties it to the
//! membrane's rotation `w = (du2/dx1 - du1/dx2) / 2` at the points of the
//! mass rule (Hughes and Brezzi), with `gamma = 1e-3 G a`: zero for a rigid
//! motion, so it adds no energy to rigid-body modes, and it stiffens every
//! drilling rotation, so that an element has no zero-energy mode besides
//! the six rigid-body modes.
//!
//! **Mass.** Consistent, with rotary inertia (2 x 2 points for S4, 6 for
//! S3 and S6, 3 x 3 for S8): at each point a
//! rigid slice through the thickness of mass `rho a dA` at the mid-surface
//! and rotary inertia `rho a^3 / 12 dA` about the in-plane axes, moving
//! with the interpolated displacement and rotation of that point (its
//! translation includes `theta x h V` of an offset mid-surface); the mass
//! matrix is the sum over the slices, `sum m U^T U + Theta^T J Theta`, and
//! the floating-frame invariants take the same slices.
//!
//! **Stresses.** Plane stress from the strains at the in-plane points on
//! the bottom (`t = -1`), middle and top (`t = 1`, the side the element's
//! normal points to, which is Abaqus' SPOS) surfaces, extrapolated to the
//! nodes, in global axes (Voigt `[sxx, syy, szz, sxy, syz, szx]`); the
//! transverse shear stresses are the parabolic distribution of the
//! element's shear forces: zero on the faces, 3/2 of the mean on the
//! middle surface.

mod mitc;
mod surface;

use super::{
    condense, element_coords, mat_vec, node_dofs, ElementBehaviour, ElementMatrices, VtkCell,
};
use super::{Element, ElementType, MassDistribution, SectionKind, SectionValues, StressLayer};
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::section::Material;
use crate::FemError;
use mitc::{cross, dot, norm, unit, Geometry};
use surface::MAX_NODES;

/// An element whose area is below this fraction of the square of its size
/// (bounding-box diagonal) counts as having zero area.
const ZERO_AREA: f64 = 1e-12;

/// The largest warping of a quadrilateral flexbody accepts: the angle
/// between the normals of the two triangles either diagonal splits it
/// into, in degrees.
pub const WARP_LIMIT_DEGREES: f64 = 30.0;

/// Shell element types (Abaqus/CalculiX names).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum ShellKind {
    /// 3-node triangle, MITC3+ (its rotations' bubble condensed).
    S3,
    /// 4-node quadrilateral, MITC4.
    S4,
    /// 6-node triangle, quadratic (curved): its shear tied in Nedelec's
    /// space, its membrane and bending strains at three points.
    S6,
    /// 8-node quadrilateral, quadratic (curved): MITC9 with its centre node
    /// condensed.
    S8,
}

impl ShellKind {
    /// All kinds.
    pub const ALL: [ShellKind; 4] = [ShellKind::S3, ShellKind::S4, ShellKind::S6, ShellKind::S8];

    /// Number of nodes.
    pub const fn node_count(self) -> usize {
        match self {
            ShellKind::S3 => 3,
            ShellKind::S4 => 4,
            ShellKind::S6 => 6,
            ShellKind::S8 => 8,
        }
    }

    /// Number of nodes the element is interpolated on: its own, and for S8
    /// an internal centre node, for S3 the bubble of its rotations, whose
    /// DOFs the element condenses.
    pub const fn interpolation_nodes(self) -> usize {
        match self {
            ShellKind::S8 => 9,
            ShellKind::S3 => 4,
            kind => kind.node_count(),
        }
    }

    /// Abaqus/CalculiX name.
    pub const fn name(self) -> &'static str {
        match self {
            ShellKind::S3 => "S3",
            ShellKind::S4 => "S4",
            ShellKind::S6 => "S6",
            ShellKind::S8 => "S8",
        }
    }

    /// True for the quadratic (curved) kinds.
    pub const fn is_quadratic(self) -> bool {
        matches!(self, ShellKind::S6 | ShellKind::S8)
    }

    /// The VTK cell: triangle (5), quadrilateral (9), quadratic triangle
    /// (22), quadratic quadrilateral (23), in the element's node order
    /// (VTK's for all four).
    pub const fn vtk_cell(self) -> VtkCell {
        match self {
            ShellKind::S3 => VtkCell::in_order(5, 3),
            ShellKind::S4 => VtkCell::in_order(9, 4),
            ShellKind::S6 => VtkCell::in_order(22, 6),
            ShellKind::S8 => VtkCell::in_order(23, 8),
        }
    }

    /// The deck type of this kind: a shell section; the reference element
    /// is the natural one in the x-y plane.
    const fn element_type(self, build: BuildFn) -> ElementType {
        ElementType {
            name: self.name(),
            nodes: self.node_count(),
            section: SectionKind::Shell,
            reference_nodes: match self {
                ShellKind::S3 => &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                ShellKind::S4 => &[
                    [-1.0, -1.0, 0.0],
                    [1.0, -1.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [-1.0, 1.0, 0.0],
                ],
                ShellKind::S6 => &[
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.5, 0.0, 0.0],
                    [0.5, 0.5, 0.0],
                    [0.0, 0.5, 0.0],
                ],
                ShellKind::S8 => &[
                    [-1.0, -1.0, 0.0],
                    [1.0, -1.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [-1.0, 1.0, 0.0],
                    [0.0, -1.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [-1.0, 0.0, 0.0],
                ],
            },
            build,
        }
    }

    /// Element `id` of this kind on `nodes` with a shell section's values.
    fn build(
        self,
        id: usize,
        nodes: &[NodeId],
        section: &SectionValues,
    ) -> Result<Element, FemError> {
        match section {
            SectionValues::Shell {
                material,
                thickness,
                offset,
            } => Ok(Shell {
                id,
                kind: self,
                nodes: nodes.to_vec(),
                material: material.clone(),
                thickness: *thickness,
                offset: *offset,
            }
            .into()),
            _ => Err(super::registry::wrong_section(self.name(), id, section)),
        }
    }
}

/// The signature of [`ElementType::build`].
type BuildFn = fn(usize, &[NodeId], &SectionValues) -> Result<Element, FemError>;

/// The deck's shell types, in the order of [`ShellKind::ALL`].
pub(super) const ELEMENT_TYPES: &[ElementType] = &[
    ShellKind::S3.element_type(|id, nodes, s| ShellKind::S3.build(id, nodes, s)),
    ShellKind::S4.element_type(|id, nodes, s| ShellKind::S4.build(id, nodes, s)),
    ShellKind::S6.element_type(|id, nodes, s| ShellKind::S6.build(id, nodes, s)),
    ShellKind::S8.element_type(|id, nodes, s| ShellKind::S8.build(id, nodes, s)),
];

/// A shell element.
#[derive(Clone, Debug, PartialEq)]
pub struct Shell {
    /// Element number (user id).
    pub id: usize,
    pub kind: ShellKind,
    /// Node ids in Abaqus/CalculiX order; the element's normal follows
    /// them by the right-hand rule.
    pub nodes: Vec<NodeId>,
    /// Linear isotropic material.
    pub material: Material,
    /// Thickness (m).
    pub thickness: f64,
    /// Where the nodes (the reference surface) lie from the mid-surface
    /// along the normal, in thicknesses, as Abaqus' `OFFSET=`: 0.5 (SPOS)
    /// puts them on the top face, the mid-surface half a thickness below.
    pub offset: f64,
}

impl ElementBehaviour for Shell {
    fn id(&self) -> usize {
        self.id
    }

    fn nodes(&self) -> Vec<NodeId> {
        self.nodes.clone()
    }

    fn dofs(&self) -> Vec<Dof> {
        node_dofs(&self.nodes, &DofKind::ALL)
    }

    fn material_damping(&self) -> Option<crate::model::Rayleigh> {
        self.material.damping
    }

    fn validate(&self, model: &Model) -> Result<(), FemError> {
        self.geometry(&element_coords(model, &self.nodes))
            .map(|_| ())
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        Shell::matrices(self, &element_coords(model, &self.nodes))
    }

    fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        let geometry = self.geometry(&element_coords(model, &self.nodes))?;
        Ok(match self.material.density {
            0.0 => MassDistribution::None,
            _ => {
                let condensation = self.condensation(&geometry)?;
                MassDistribution::Points(self.mass_points(&geometry, &condensation))
            }
        })
    }

    fn has_stresses(&self) -> bool {
        true
    }

    fn stress_layers(&self) -> &'static [StressLayer] {
        &[StressLayer::Bottom, StressLayer::Middle, StressLayer::Top]
    }

    /// [`Shell::surface_stresses`] at the element's coordinates.
    fn stresses(
        &self,
        model: &Model,
        u_e: &[f64],
        columns: usize,
    ) -> Result<Option<Vec<[f64; 6]>>, FemError> {
        let coords = element_coords(model, &self.nodes);
        self.surface_stresses(&coords, u_e, columns).map(Some)
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(self.kind.vtk_cell())
    }
}

impl Shell {
    /// Stiffness and consistent mass (with rotary inertia) in the DOFs of
    /// [`ElementBehaviour::dofs`], symmetric.
    pub fn matrices(&self, coords: &[[f64; 3]]) -> Result<ElementMatrices, FemError> {
        let geometry = self.geometry(coords)?;
        let nd = 6 * self.kind.node_count();
        let (stiffness, condensation) = self.condensed_stiffness(&geometry)?;
        let mass = mitc::mass_matrix(&self.mass_points(&geometry, &condensation), nd);
        Ok(ElementMatrices {
            dofs: ElementBehaviour::dofs(self),
            stiffness,
            mass,
            damping: None,
        })
    }

    /// Stresses at the nodes on the bottom, middle and top surfaces (Pa,
    /// global Voigt order, see the module docs) of `columns` displacement
    /// fields one after the other in `u_e` (each `6 n` values in the order
    /// of the element's DOFs): entry `(3 j + layer) n + a` is node `a`'s
    /// stress on layer `layer` (0 bottom, 1 middle, 2 top) in field `j`.
    pub fn surface_stresses(
        &self,
        coords: &[[f64; 3]],
        u_e: &[f64],
        columns: usize,
    ) -> Result<Vec<[f64; 6]>, FemError> {
        let geometry = self.geometry(coords)?;
        let nd = 6 * self.kind.node_count();
        if u_e.len() != nd * columns {
            return Err(self.invalid(format!(
                "{} needs {nd} displacement values per field, got {} for {columns}",
                self.kind.name(),
                u_e.len()
            )));
        }
        let m = &self.material;
        match self.condensation(&geometry)? {
            None => Ok(geometry.stresses(m.youngs_modulus, m.poisson_ratio, u_e, columns)),
            Some(t) => {
                let full: Vec<f64> = u_e.chunks_exact(nd).flat_map(|u| mat_vec(&t, u)).collect();
                Ok(geometry.stresses(m.youngs_modulus, m.poisson_ratio, &full, columns))
            }
        }
    }

    /// The stiffness over the element's DOFs and, for S8 and S3, the map
    /// `T` from them to the interpolation DOFs. The internal DOFs `u_c`
    /// (S8's centre node's six; S3's bubble, two rotations about in-plane
    /// axes, `E` their directions among the bubble node's six) follow by
    /// static condensation, `u_c = -K_cc^-1 K_cb u_b` with `K_cc = E^T K_ii
    /// E`, `K_cb = E^T K_ib`, so that `T = [I; -E K_cc^-1 K_cb]` and `K =
    /// T^T K_full T = K_bb - K_bc K_cc^-1 K_cb`.
    fn condensed_stiffness(
        &self,
        geometry: &Geometry,
    ) -> Result<(faer::Mat<f64>, Option<faer::Mat<f64>>), FemError> {
        let m = &self.material;
        let full = geometry.stiffness(m.youngs_modulus, m.poisson_ratio);
        let nb = 6 * self.kind.node_count();
        if full.nrows() == nb {
            return Ok((full, None));
        }
        let directions = geometry.internal_directions();
        let (ni, m) = (full.nrows() - nb, directions.len());
        let e = faer::Mat::from_fn(ni, m, |r, c| directions[c][r]);
        // [K_bb, K_bi E; E^T K_ib, E^T K_ii E].
        let k_bi_e = full.as_ref().submatrix(0, nb, nb, ni) * &e;
        let k_ee = e.transpose() * (full.as_ref().submatrix(nb, nb, ni, ni) * &e);
        let reduced = faer::Mat::from_fn(nb + m, nb + m, |r, c| match (r < nb, c < nb) {
            (true, true) => full[(r, c)],
            (true, false) => k_bi_e[(r, c - nb)],
            (false, true) => k_bi_e[(c, r - nb)],
            (false, false) => k_ee[(r - nb, c - nb)],
        });
        let (k, x) = condense(&reduced, nb).ok_or_else(|| {
            let what = match self.kind {
                ShellKind::S3 => "its rotation bubble",
                _ => "its centre node",
            };
            self.invalid(format!("{what} has a singular stiffness"))
        })?;
        let ex = &e * &x;
        let t = faer::Mat::from_fn(nb + ni, nb, |r, c| {
            if r < nb {
                (r == c) as u8 as f64
            } else {
                ex[(r - nb, c)]
            }
        });
        Ok((k, Some(t)))
    }

    /// S8's and S3's map `T` from the element's DOFs to the interpolation
    /// DOFs ([`Self::condensed_stiffness`]); `None` for the other kinds,
    /// whose nodes are their interpolation nodes.
    fn condensation(&self, geometry: &Geometry) -> Result<Option<faer::Mat<f64>>, FemError> {
        if self.kind.interpolation_nodes() == self.kind.node_count() {
            return Ok(None);
        }
        self.condensed_stiffness(geometry).map(|(_, t)| t)
    }

    /// The mass slices ([`Geometry::mass_points`]) moving with the
    /// element's DOFs (through `condensation`, S8's and S3's `T = [I;
    /// T_i]`: `U T = U_b + U_i T_i`).
    fn mass_points(
        &self,
        geometry: &Geometry,
        condensation: &Option<faer::Mat<f64>>,
    ) -> Vec<super::MassPoint> {
        let mut points = geometry.mass_points(self.material.density);
        if let Some(t) = condensation {
            let (nb, n) = (t.ncols(), t.nrows());
            let map = |u: &faer::Mat<f64>| {
                faer::Mat::from_fn(3, nb, |r, c| {
                    u[(r, c)] + (nb..n).map(|k| u[(r, k)] * t[(k, c)]).sum::<f64>()
                })
            };
            for p in &mut points {
                p.translation = map(&p.translation);
                p.rotation = map(&p.rotation);
            }
        }
        points
    }

    fn invalid(&self, reason: String) -> FemError {
        FemError::InvalidElement {
            element: self.id,
            reason,
        }
    }

    /// Checks the section, the material and the geometry, and gives the
    /// element's surface with its directors: the thickness must be positive
    /// and finite, the material isotropic; the element must have an area,
    /// a normal at every node on the side of the element's mean normal
    /// (else it is inverted or degenerate there), a warping within
    /// [`WARP_LIMIT_DEGREES`] and a positive Jacobian at every integration
    /// point.
    fn geometry(&self, coords: &[[f64; 3]]) -> Result<Geometry, FemError> {
        let kind = self.kind;
        let nn = kind.node_count();
        if coords.len() != nn {
            return Err(self.invalid(format!(
                "{} needs {nn} nodes, got {}",
                kind.name(),
                coords.len()
            )));
        }
        self.check_section()?;
        if coords.iter().flatten().any(|c| !c.is_finite()) {
            return Err(self.invalid("node coordinates must be finite".into()));
        }
        let mut rel = [[0.0; 3]; MAX_NODES];
        for (r, x) in rel.iter_mut().zip(coords) {
            *r = std::array::from_fn(|i| x[i] - coords[0][i]);
        }
        let size = bounding_diagonal(coords);
        // The mean normal: of the diagonals (S4) or the two edges (S3).
        let mean = match kind {
            ShellKind::S4 | ShellKind::S8 => cross(sub(rel[2], rel[0]), sub(rel[3], rel[1])),
            ShellKind::S3 | ShellKind::S6 => cross(rel[1], rel[2]),
        };
        if kind == ShellKind::S3 {
            // The bubble at the centroid (it moves no point of the surface).
            rel[3] = std::array::from_fn(|i| (rel[1][i] + rel[2][i]) / 3.0);
        }
        if kind == ShellKind::S8 {
            // The centre on the serendipity surface through the eight
            // nodes: the nine-node surface is then the eight-node one.
            rel[8] = std::array::from_fn(|i| {
                -0.25 * (0..4).map(|a| rel[a][i]).sum::<f64>()
                    + 0.5 * (4..8).map(|a| rel[a][i]).sum::<f64>()
            });
        }
        let area = norm(mean);
        if area.is_nan() || area <= ZERO_AREA * size * size {
            return Err(self.invalid(format!(
                "zero area (its nodes lie on a line or coincide; size {size:.3e} m)"
            )));
        }
        let mut director = [[0.0; 3]; MAX_NODES];
        let mut geometry = Geometry {
            kind,
            origin: coords[0],
            rel,
            director,
            thickness: self.thickness,
            offset: -self.offset,
        };
        for (a, xi) in surface::node_coordinates(kind).iter().enumerate() {
            // The normal of the reference surface at the node.
            let flat = Geometry {
                thickness: 0.0,
                ..geometry
            };
            let p = flat.point(*xi, 0.0);
            let normal = cross(p.g[0], p.g[1]);
            let along = dot(normal, unit(mean));
            if along.is_nan() || along <= ZERO_AREA * size * size {
                let at = match self.nodes.get(a) {
                    Some(node) => format!("its node {node}"),
                    None => "its centre".into(),
                };
                return Err(self.invalid(format!(
                    "inverted or degenerate at {at} (zero or negative Jacobian; a collapsed \
                     quadrilateral is an S3)"
                )));
            }
            director[a] = unit(normal);
        }
        geometry.director = director;
        if kind == ShellKind::S4 {
            let warp = warping_degrees(&rel);
            if warp > WARP_LIMIT_DEGREES {
                return Err(self.invalid(format!(
                    "warped by {warp:.1} degrees (the angle between the normals of the \
                     triangles a diagonal splits it into; the limit is {WARP_LIMIT_DEGREES})"
                )));
            }
        }
        let points = surface::rule(kind).iter().chain(surface::full_rule(kind));
        for (p, (rs, _)) in points.enumerate() {
            for (t, _) in surface::THICKNESS_RULE {
                let det = geometry.point(*rs, t).det_j;
                if det.is_nan() || det <= 0.0 {
                    return Err(self.invalid(format!(
                        "zero or negative Jacobian at integration point {} (det J = {det:.3e}; \
                         is the thickness {} m larger than the radius of curvature?)",
                        p + 1,
                        self.thickness
                    )));
                }
            }
        }
        Ok(geometry)
    }

    fn check_section(&self) -> Result<(), FemError> {
        let m = &self.material;
        let problem = if !(self.thickness.is_finite() && self.thickness > 0.0) {
            Some(format!(
                "shell thickness must be positive and finite, got {}",
                self.thickness
            ))
        } else if !self.offset.is_finite() {
            Some(format!("shell offset must be finite, got {}", self.offset))
        } else if m.anisotropy.is_some() {
            Some("shells take isotropic materials only (an anisotropic *ELASTIC is refused)".into())
        } else {
            m.problem().map(|p| format!("material: {p}"))
        };
        match problem {
            Some(p) => Err(self.invalid(p)),
            None => Ok(()),
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn bounding_diagonal(coords: &[[f64; 3]]) -> f64 {
    (0..3)
        .map(|i| {
            let lo = coords.iter().map(|x| x[i]).fold(f64::INFINITY, f64::min);
            let hi = coords
                .iter()
                .map(|x| x[i])
                .fold(f64::NEG_INFINITY, f64::max);
            (hi - lo).powi(2)
        })
        .sum::<f64>()
        .sqrt()
}

/// The larger, over both diagonals, of the angle between the normals of
/// the two triangles the diagonal splits a quadrilateral into (degrees;
/// 0 for a flat element).
fn warping_degrees(x: &[[f64; 3]; MAX_NODES]) -> f64 {
    let normal = |a: usize, b: usize, c: usize| cross(sub(x[b], x[a]), sub(x[c], x[a]));
    let angle = |n1: [f64; 3], n2: [f64; 3]| {
        let c = dot(n1, n2) / (norm(n1) * norm(n2));
        c.clamp(-1.0, 1.0).acos().to_degrees()
    };
    let first = angle(normal(0, 1, 2), normal(0, 2, 3));
    let second = angle(normal(0, 1, 3), normal(1, 2, 3));
    first.max(second)
}

#[cfg(test)]
mod tests;
