//! Isoparametric solid elements with consistent mass and linear isotropic
//! elasticity, in the node numbering and with the integration rules of
//! Abaqus/CalculiX, so that assembled matrices agree with CalculiX's
//! (`*FREQUENCY, SOLVER=MATRIXSTORAGE` output of CalculiX 2.20):
//!
//! | kind | nodes | stiffness rule | mass rule | stresses from |
//! | --- | --- | --- | --- | --- |
//! | C3D8 | 8 | 2x2x2 Gauss | 2x2x2 Gauss | 2x2x2 points, trilinear extrapolation |
//! | C3D8I | 8 | 2x2x2 Gauss, 9 incompatible modes condensed | 2x2x2 Gauss (trilinear) | 2x2x2 points, with the incompatible modes |
//! | C3D8R | 8 | uniform strain (1 point) plus hourglass stiffness | 1 point | the element's uniform strain (constant) |
//! | C3D20 | 20 | 3x3x3 Gauss | 3x3x3 Gauss | 3x3x3 points, triquadratic extrapolation |
//! | C3D20R | 20 | 2x2x2 Gauss | 2x2x2 Gauss | 2x2x2 points, trilinear extrapolation |
//! | C3D10 | 10 | 4-point | 4-point | 4 points, linear extrapolation |
//! | C3D4 | 4 | 1-point | 1-point | the centroid (constant) |
//! | C3D6 | 6 | 2-point | 2-point | 2 points, linear in `zeta` |
//! | C3D15 | 15 | 9-point | 9-point | 9 points, linear in the triangle, quadratic in `zeta` |
//!
//! CalculiX (`e_c3d.f`) integrates stiffness and mass in the same loop over
//! the same points (`mint3d`): the mass rule is the stiffness rule for every
//! kind, also for C3D20R (2x2x2, reduced) and C3D4 (the centroid, which
//! makes its consistent mass `rho V / 16` in every entry of each direction).
//! Only with `intscheme = 1` (initial accelerations of dynamic steps) does
//! CalculiX use the full rule for C3D20R; frequency steps use
//! `intscheme = 0`. CalculiX's C3D8 is the plain fully integrated trilinear
//! hexahedron (`shape8h.f`; incompatible modes are the separate C3D8I).
//! The rules are listed in `quadrature.rs`.
//!
//! C3D8I adds the incompatible modes of Wilson, Taylor, Beresford:
//! displacements `u = sum_a N_a u_a + sum_k (1 - xi_k^2) alpha_k` with three
//! vectors `alpha_k` per element, their gradients taken through the
//! Jacobian at the element's centre `J_0` and scaled by `det J_0 / det J`,
//! so that they integrate to zero over the element and any element passes
//! the constant-strain patch test; 2x2x2 points. flexbody condenses the
//! nine `alpha` DOFs statically in the element, `K = K_uu - K_ua K_aa^-1
//! K_au`, and keeps the trilinear consistent mass of C3D8 (the modes are
//! massless).
//!
//! CalculiX 2.20 (`e_c3d.f`) builds the same modes without the scaling
//! (measured against its matrices: 1e-15 of the largest entry), keeps the
//! nine DOFs as three extra nodes per element and gives them a consistent
//! mass. On a parallelepiped (`det J` constant) the stiffness is the same:
//! flexbody's element K is the Schur complement of CalculiX's to
//! round-off. On a distorted element CalculiX's modes no longer integrate
//! to zero, its element fails the patch test, and its K differs from
//! flexbody's (0.5 % of the largest entry on an element distorted by 15 %);
//! and the mass it gives the modes moves frequencies (3 % for the first
//! bending mode of a free beam six elements long).
//!
//! C3D8R is Flanagan and Belytschko's uniform-strain hexahedron with
//! hourglass control, as CalculiX 2.20 builds it (`shape8hr.f`,
//! `hgstiffness.f`): the mean gradients `b_a = (1/V) int grad N_a dV`
//! (exact, from 2x2x2 points) give one constant strain, `K = V B^T C B`;
//! the four hourglass modes of each direction get the stiffness
//! `c 0.0005 sum_b |V b_b|^2 / V gamma^k gamma^k^T` (`c` = E, or `C_xxxx`
//! in global axes for an anisotropic material, as in CalculiX) with
//! Flanagan and Belytschko's vectors `gamma^k = h^k - sum_j b^j (x_j . h^k)`
//! (`h^k` the base vectors `eta zeta`, `zeta xi`, `xi eta`, `xi eta zeta`
//! at the corners, `x_j` the nodes' coordinate `j`). Its mass is
//! CalculiX's one-point mass, `rho V / 64` in every entry of each
//! direction (singular: rank 1 per direction and element).
//!
//! CalculiX's `shape8hr.f` resets `gamma^k` in its loop over `j`, so that
//! only the `j = z` term of the projection survives. The two agree where
//! `x` and `y` are linear in the natural coordinates (parallelepipeds,
//! regular meshes, elements distorted along z only: tested entry by entry);
//! on a general distorted element CalculiX's vectors are not orthogonal to
//! linear displacement fields, its hourglass stiffness resists a constant
//! strain and the element fails the patch test; flexbody's passes it. The
//! stiffness then differs by the hourglass term (1.1e-3 of the largest
//! entry on an element distorted by 15 %).
//!
//! Stiffness: `K_ab = sum_p w_p det J_p [lambda g_a g_b^T + mu (g_b g_a^T +
//! (g_a . g_b) I)]` with `g_a = grad N_a` at point `p`, the Lame constants
//! from E and nu (`lambda = E nu / ((1 + nu)(1 - 2 nu))`, `mu = E / (2 (1 +
//! nu))`, as CalculiX; [`Material::shear_modulus`] is not used). Mass:
//! `M_ab = rho sum_p w_p det J_p N_a N_b I`.
//!
//! Anisotropic materials ([`Material::anisotropy`]) take the general form
//! `K_ab = sum_p w_p det J_p B_a^T C_p B_b` with the strain-displacement
//! block `B_a` of engineering strains and `C_p` the elasticity in global
//! axes at point `p`: rotated from the material axes by the orientation
//! evaluated at the point's global position (for a cylindrical system it
//! changes from point to point, as in CalculiX, which evaluates it at each
//! integration point). Stresses use the same `C_p`.
//!
//! Nodal stresses are evaluated at the integration points of the stiffness
//! rule and carried to the nodes by the polynomial through those points
//! (the standard extrapolation; at the mid-edge nodes of a C3D20R the
//! trilinear one gives the mean of the two corners). That is exact for a
//! constant stress field, smoother than evaluating the strains at the nodes
//! themselves, and leaves out the hourglass modes of C3D20R (they strain
//! nothing at the points, as in the stiffness).
//!
//! DOFs: `ux, uy, uz` per node, in element node order. Stresses in Voigt
//! order `[sxx, syy, szz, sxy, syz, szx]` (Pa), from engineering shear
//! strains.

mod quadrature;
mod shape;
pub mod topology;
mod uniform_strain;

use super::{
    condense, element_coords, node_dofs, ElementBehaviour, ElementMatrices, VtkCell, TRANSLATIONS,
};
use super::{Element, ElementType, SectionKind, SectionValues};
use crate::anisotropy::Voigt;
use crate::dof::Dof;
use crate::model::{Model, NodeId};
use crate::section::Material;
use crate::FemError;
use faer::Mat;
use quadrature::Rule;
use shape::MAX_NODES;

/// Largest number of integration points of a rule.
const MAX_POINTS: usize = 27;

/// An element whose volume is below this fraction of the cube of its size
/// (bounding-box diagonal) counts as having zero volume.
const ZERO_VOLUME: f64 = 1e-12;

/// Solid element types (Abaqus/CalculiX names).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum SolidKind {
    /// 8-node trilinear hexahedron, full (2x2x2) integration.
    C3D8,
    /// 8-node hexahedron with incompatible (bubble) modes, condensed.
    C3D8I,
    /// 8-node hexahedron, uniform (mean) strain with hourglass control.
    C3D8R,
    /// 20-node serendipity hexahedron, full (3x3x3) integration.
    C3D20,
    /// 20-node serendipity hexahedron, reduced (2x2x2) integration.
    C3D20R,
    /// 10-node quadratic tetrahedron, 4-point integration.
    C3D10,
    /// 4-node linear tetrahedron, 1-point integration.
    C3D4,
    /// 6-node linear wedge (pentahedron), 2-point integration.
    C3D6,
    /// 15-node serendipity wedge, 9-point integration.
    C3D15,
}

impl SolidKind {
    /// All kinds.
    pub const ALL: [SolidKind; 9] = [
        SolidKind::C3D8,
        SolidKind::C3D8I,
        SolidKind::C3D8R,
        SolidKind::C3D20,
        SolidKind::C3D20R,
        SolidKind::C3D10,
        SolidKind::C3D4,
        SolidKind::C3D6,
        SolidKind::C3D15,
    ];

    /// Number of nodes.
    pub const fn node_count(self) -> usize {
        match self {
            SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => 8,
            SolidKind::C3D20 | SolidKind::C3D20R => 20,
            SolidKind::C3D10 => 10,
            SolidKind::C3D4 => 4,
            SolidKind::C3D6 => 6,
            SolidKind::C3D15 => 15,
        }
    }

    /// Abaqus/CalculiX name (`"C3D20R"`).
    pub const fn name(self) -> &'static str {
        match self {
            SolidKind::C3D8 => "C3D8",
            SolidKind::C3D8I => "C3D8I",
            SolidKind::C3D8R => "C3D8R",
            SolidKind::C3D20 => "C3D20",
            SolidKind::C3D20R => "C3D20R",
            SolidKind::C3D10 => "C3D10",
            SolidKind::C3D4 => "C3D4",
            SolidKind::C3D6 => "C3D6",
            SolidKind::C3D15 => "C3D15",
        }
    }

    /// Parses a name, case-insensitive.
    pub fn parse(s: &str) -> Option<Self> {
        SolidKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
    }

    /// The VTK cell: hexahedron (12), quadratic hexahedron (25),
    /// tetrahedron (10), quadratic tetrahedron (24) in the Abaqus node
    /// order, which is VTK's; the wedge (13) and the quadratic wedge (26)
    /// with their triangles turned the other way round, as VTK orders them.
    pub const fn vtk_cell(self) -> VtkCell {
        match self {
            SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => VtkCell::in_order(12, 8),
            SolidKind::C3D20 | SolidKind::C3D20R => VtkCell::in_order(25, 20),
            SolidKind::C3D4 => VtkCell::in_order(10, 4),
            SolidKind::C3D10 => VtkCell::in_order(24, 10),
            SolidKind::C3D6 => VtkCell {
                cell_type: 13,
                order: &[0, 2, 1, 3, 5, 4],
            },
            SolidKind::C3D15 => VtkCell {
                cell_type: 26,
                order: &[0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13],
            },
        }
    }

    /// The deck type of this kind: its name, node count, a solid section
    /// and a reference element in natural coordinates.
    const fn element_type(self, build: BuildFn) -> ElementType {
        ElementType {
            name: self.name(),
            nodes: self.node_count(),
            section: SectionKind::Solid,
            reference_nodes: shape::node_coordinates(self),
            build,
        }
    }

    /// Element `id` of this kind on `nodes`, with the material of a solid
    /// section.
    fn build(
        self,
        id: usize,
        nodes: &[NodeId],
        section: &SectionValues,
    ) -> Result<Element, FemError> {
        match section {
            SectionValues::Solid { material } => Ok(Solid {
                id,
                kind: self,
                nodes: nodes.to_vec(),
                material: material.clone(),
            }
            .into()),
            _ => Err(super::registry::wrong_section(self.name(), id, section)),
        }
    }

    /// The stiffness rule (CalculiX `mint3d` with `intscheme = 0`); for
    /// C3D8R the rule that integrates its mean gradients exactly (its
    /// stiffness and mass take one point, see the module docs).
    fn stiffness_rule(self) -> Rule {
        match self {
            SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R | SolidKind::C3D20R => Rule::Hex2,
            SolidKind::C3D20 => Rule::Hex3,
            SolidKind::C3D10 => Rule::Tet4,
            SolidKind::C3D4 => Rule::Tet1,
            SolidKind::C3D6 => Rule::Wedge2,
            SolidKind::C3D15 => Rule::Wedge9,
        }
    }

    /// The mass rule: CalculiX's mass loop is its stiffness loop.
    fn mass_rule(self) -> Rule {
        self.stiffness_rule()
    }

    /// Number of incompatible modes, each a vector of three DOFs internal
    /// to the element (C3D8I: 3).
    const fn incompatible_modes(self) -> usize {
        match self {
            SolidKind::C3D8I => 3,
            _ => 0,
        }
    }

    /// A rule that integrates `det J` exactly (for [`Solid::volume`]).
    fn volume_rule(self) -> Rule {
        match self {
            SolidKind::C3D20R => Rule::Hex3,
            kind => kind.stiffness_rule(),
        }
    }
}

/// The signature of [`ElementType::build`].
type BuildFn = fn(usize, &[NodeId], &SectionValues) -> Result<Element, FemError>;

/// The deck's solid types, one per [`SolidKind`] in the order of
/// [`SolidKind::ALL`].
pub(super) const ELEMENT_TYPES: &[ElementType] = &[
    SolidKind::C3D8.element_type(|id, nodes, s| SolidKind::C3D8.build(id, nodes, s)),
    SolidKind::C3D8I.element_type(|id, nodes, s| SolidKind::C3D8I.build(id, nodes, s)),
    SolidKind::C3D8R.element_type(|id, nodes, s| SolidKind::C3D8R.build(id, nodes, s)),
    SolidKind::C3D20.element_type(|id, nodes, s| SolidKind::C3D20.build(id, nodes, s)),
    SolidKind::C3D20R.element_type(|id, nodes, s| SolidKind::C3D20R.build(id, nodes, s)),
    SolidKind::C3D10.element_type(|id, nodes, s| SolidKind::C3D10.build(id, nodes, s)),
    SolidKind::C3D4.element_type(|id, nodes, s| SolidKind::C3D4.build(id, nodes, s)),
    SolidKind::C3D6.element_type(|id, nodes, s| SolidKind::C3D6.build(id, nodes, s)),
    SolidKind::C3D15.element_type(|id, nodes, s| SolidKind::C3D15.build(id, nodes, s)),
];

/// A solid element.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// Element number (user id).
    pub id: usize,
    /// Element type.
    pub kind: SolidKind,
    /// Node ids in Abaqus/CalculiX order (`kind.node_count()` of them).
    pub nodes: Vec<NodeId>,
    /// Linear elastic material (isotropic, or anisotropic with its
    /// orientation).
    pub material: Material,
}

impl ElementBehaviour for Solid {
    fn id(&self) -> usize {
        self.id
    }

    fn material_damping(&self) -> Option<crate::model::Rayleigh> {
        self.material.damping
    }

    fn nodes(&self) -> Vec<NodeId> {
        self.nodes.clone()
    }

    fn dofs(&self) -> Vec<Dof> {
        node_dofs(&self.nodes, &TRANSLATIONS)
    }

    fn validate(&self, model: &Model) -> Result<(), FemError> {
        Solid::validate(self, &element_coords(model, &self.nodes))
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        Solid::matrices(self, &element_coords(model, &self.nodes))
    }

    fn has_stresses(&self) -> bool {
        true
    }

    /// [`Solid::nodal_stress_columns`] at the element's coordinates.
    fn stresses(
        &self,
        model: &Model,
        u_e: &[f64],
        columns: usize,
    ) -> Result<Option<Vec<[f64; 6]>>, FemError> {
        let coords = element_coords(model, &self.nodes);
        self.nodal_stress_columns(&coords, u_e, columns).map(Some)
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(self.kind.vtk_cell())
    }
}

impl Solid {
    /// Checks node count, material and geometry: the element must have a
    /// volume above `1e-12` times the cube of its size (bounding-box
    /// diagonal) and a positive Jacobian determinant at every integration
    /// point of its stiffness and mass rules.
    pub fn validate(&self, coords: &[[f64; 3]]) -> Result<(), FemError> {
        self.checked_geometry(coords).map(|_| ())
    }

    /// [`Solid::validate`], returning the geometry it checked.
    fn checked_geometry(&self, coords: &[[f64; 3]]) -> Result<Geometry, FemError> {
        let geometry = self.geometry(coords)?;
        self.check_material()?;
        let mut det = [0.0; MAX_POINTS];
        let rules = [self.kind.stiffness_rule(), self.kind.mass_rule()];
        for (r, &rule) in rules.iter().enumerate() {
            if r > 0 && rule == rules[0] {
                continue;
            }
            let mut volume = 0.0;
            for (p, (xi, w)) in rule.points().iter().zip(rule.weights()).enumerate() {
                det[p] = geometry.det_j(*xi);
                volume += w * det[p];
            }
            let size3 = geometry.size.powi(3);
            if volume.is_nan() || volume.abs() <= ZERO_VOLUME * size3 {
                return Err(self.invalid(format!(
                    "zero volume ({volume:.3e} m^3 for a size of {:.3e} m)",
                    geometry.size
                )));
            }
            if let Some(p) = det[..rule.len()]
                .iter()
                .position(|d| d.is_nan() || *d <= 0.0)
            {
                let what = if det[p] < 0.0 { "negative" } else { "zero" };
                return Err(self.invalid(format!(
                    "inverted: {what} Jacobian at integration point {} (det J = {:.3e})",
                    p + 1,
                    det[p]
                )));
            }
        }
        Ok(geometry)
    }

    /// Element volume (m^3): the integral of `det J`, with a rule that is
    /// exact for the element's geometry (3x3x3 points for C3D20R, whose
    /// stiffness rule is not exact for curved edges).
    pub fn volume(&self, coords: &[[f64; 3]]) -> Result<f64, FemError> {
        let geometry = self.checked_geometry(coords)?;
        let rule = self.kind.volume_rule();
        Ok(rule
            .points()
            .iter()
            .zip(rule.weights())
            .map(|(xi, w)| w * geometry.det_j(*xi))
            .sum())
    }

    /// Stiffness and consistent mass in the DOFs of [`Solid::dofs`],
    /// symmetric to the last bit.
    pub(crate) fn matrices(&self, coords: &[[f64; 3]]) -> Result<ElementMatrices, FemError> {
        let geometry = self.checked_geometry(coords)?;
        let nn = self.kind.node_count();
        let nd = 3 * nn;
        let (k, m) = self.integrate(&geometry, true)?;
        let stiffness = match self.kind.incompatible_modes() {
            0 => k,
            _ => {
                condense(&k, nd)
                    .ok_or_else(|| {
                        self.invalid("its incompatible modes have a singular stiffness".into())
                    })?
                    .0
            }
        };
        let mass = Mat::from_fn(nd, nd, |r, c| {
            if r % 3 != c % 3 {
                0.0
            } else {
                let (a, b) = (r / 3, c / 3);
                m[a.min(b) * nn + a.max(b)]
            }
        });
        Ok(ElementMatrices {
            dofs: ElementBehaviour::dofs(self),
            stiffness,
            mass,
            damping: None,
        })
    }

    /// The stiffness over the nodes' DOFs and then the incompatible modes'
    /// (C3D8I), symmetric, `3 (n + modes)` square; with `mass`, the mass
    /// per node pair (the same for each direction), upper triangle,
    /// row-major, `n` square (else empty).
    fn integrate(&self, geometry: &Geometry, mass: bool) -> Result<(Mat<f64>, Vec<f64>), FemError> {
        if self.kind == SolidKind::C3D8R {
            return self.integrate_uniform_strain(geometry, mass);
        }
        let nn = self.kind.node_count();
        let nk = nn + self.kind.incompatible_modes();
        let ndk = 3 * nk;
        let (lambda, mu) = self.lame();
        let anisotropy = self.material.anisotropy.as_deref();
        let rho = self.material.density;
        // Upper triangles, row-major.
        let mut k = vec![0.0; ndk * ndk];
        let mut m = vec![0.0; if mass { nn * nn } else { 0 }];
        let stiffness_rule = self.kind.stiffness_rule();
        let mass_rule = self.kind.mass_rule();
        for (xi, w) in stiffness_rule.points().iter().zip(stiffness_rule.weights()) {
            let point = self.point_with_incompatible_modes(geometry, *xi);
            let wd = w * point.det_j;
            match anisotropy {
                None => add_stiffness(&mut k, nk, &point.grad, lambda * wd, mu * wd),
                Some(a) => {
                    let c = a
                        .global_at(geometry.global(&point))
                        .map_err(|e| self.invalid(e.to_string()))?;
                    add_stiffness_general(&mut k, nk, &point.grad, &c, wd);
                }
            }
            if mass && mass_rule == stiffness_rule {
                add_mass(&mut m, nn, &point.n, rho * wd);
            }
        }
        if mass && mass_rule != stiffness_rule {
            for (xi, w) in mass_rule.points().iter().zip(mass_rule.weights()) {
                let point = geometry.point(*xi);
                add_mass(&mut m, nn, &point.n, rho * w * point.det_j);
            }
        }
        let k = Mat::from_fn(ndk, ndk, |r, c| {
            if r <= c {
                k[r * ndk + c]
            } else {
                k[c * ndk + r]
            }
        });
        Ok((k, m))
    }

    /// [`Geometry::point`], with the gradients of the incompatible modes
    /// `1 - xi_k^2` after the nodes' (C3D8I): through the Jacobian at the
    /// element's centre, scaled by `det J_0 / det J` (Taylor, Beresford and
    /// Wilson), so that they integrate to zero over any element and a
    /// constant strain excites none of them.
    fn point_with_incompatible_modes(&self, geometry: &Geometry, xi: [f64; 3]) -> PointValues {
        let mut point = geometry.point(xi);
        let modes = self.kind.incompatible_modes();
        if modes > 0 {
            let (inv0, det0) = geometry.inverse_jacobian([0.0; 3]);
            let scale = det0 / point.det_j;
            let nn = self.kind.node_count();
            for k in 0..modes {
                // d(1 - xi_k^2)/dxi_l = -2 xi_k delta_kl.
                let d = -2.0 * xi[k] * scale;
                point.grad[nn + k] = inv0[k].map(|v| d * v);
            }
        }
        point
    }

    /// The map from the nodes' displacements to the incompatible modes'
    /// amplitudes that minimise the energy, `alpha = -K_aa^-1 K_au u`
    /// (`3 modes x 3 n`), or `None` for an element without them.
    fn incompatible_amplitudes(&self, geometry: &Geometry) -> Result<Option<Mat<f64>>, FemError> {
        if self.kind.incompatible_modes() == 0 {
            return Ok(None);
        }
        let (k, _) = self.integrate(geometry, false)?;
        let (_, x) = condense(&k, 3 * self.kind.node_count()).ok_or_else(|| {
            self.invalid("its incompatible modes have a singular stiffness".into())
        })?;
        Ok(Some(x))
    }

    /// Stresses at the element's nodes (Pa, Voigt order) from the element
    /// displacements `u_e` (`ux, uy, uz` per node, in node order): evaluated
    /// at the stiffness rule's integration points and extrapolated to the
    /// nodes (see the module docs). Exact for a constant stress field.
    pub fn nodal_stresses(
        &self,
        coords: &[[f64; 3]],
        u_e: &[f64],
    ) -> Result<Vec<[f64; 6]>, FemError> {
        self.nodal_stress_columns(coords, u_e, 1)
    }

    /// [`Self::nodal_stresses`] of `columns` displacement fields at once,
    /// `u_e` holding them one after the other (`3 n` values each, `n`
    /// nodes): the geometry is evaluated once for all (the modal stresses
    /// of a reduced body take every basis column). Entry `j n + a` is node
    /// `a`'s stress in field `j`, each as [`Self::nodal_stresses`] gives it.
    pub fn nodal_stress_columns(
        &self,
        coords: &[[f64; 3]],
        u_e: &[f64],
        columns: usize,
    ) -> Result<Vec<[f64; 6]>, FemError> {
        let geometry = self.checked_geometry(coords)?;
        let nn = self.kind.node_count();
        if u_e.len() != 3 * nn * columns {
            let fields = match columns {
                1 => String::new(),
                _ => format!(" per field ({columns} fields)"),
            };
            return Err(self.invalid(format!(
                "{} needs {} displacement values{fields}, got {}",
                self.kind.name(),
                3 * nn,
                u_e.len()
            )));
        }
        if self.kind == SolidKind::C3D8R {
            return self.uniform_strain_stresses(&geometry, u_e);
        }
        let (lambda, mu) = self.lame();
        let rule = self.kind.stiffness_rule();
        let points: Vec<_> = rule
            .points()
            .iter()
            .map(|xi| self.point_with_incompatible_modes(&geometry, *xi))
            .collect();
        let amplitudes = self.incompatible_amplitudes(&geometry)?;
        let nk = nn + self.kind.incompatible_modes();
        let mut extended = vec![0.0; 3 * nk];
        let elasticity: Vec<Option<Voigt>> = match self.material.anisotropy.as_deref() {
            None => vec![None; points.len()],
            Some(a) => points
                .iter()
                .map(|p| a.global_at(geometry.global(p)).map(Some))
                .collect::<Result<_, _>>()
                .map_err(|e| self.invalid(e.to_string()))?,
        };
        // The extrapolation weights of each node from the points.
        let mut c = [0.0; MAX_POINTS];
        let weights: Vec<[f64; MAX_POINTS]> = shape::node_coordinates(self.kind)
            .iter()
            .map(|xi| {
                rule.interpolation_weights(*xi, &mut c);
                c
            })
            .collect();
        let mut out = Vec::with_capacity(nn * columns);
        let mut at_points = [[0.0; 6]; MAX_POINTS];
        for u in u_e.chunks_exact(3 * nn) {
            // The nodes' displacements, then the incompatible modes'
            // amplitudes they imply.
            extended[..3 * nn].copy_from_slice(u);
            if let Some(r) = &amplitudes {
                for (i, e) in extended[3 * nn..].iter_mut().enumerate() {
                    *e = (0..3 * nn).map(|j| r[(i, j)] * u[j]).sum();
                }
            }
            for ((s, point), c) in at_points.iter_mut().zip(&points).zip(&elasticity) {
                let e = strain(&point.grad[..nk], &extended);
                *s = match c {
                    None => stress(&e, lambda, mu),
                    Some(c) => std::array::from_fn(|i| (0..6).map(|j| c[i][j] * e[j]).sum()),
                };
            }
            out.extend(weights.iter().map(|c| {
                let mut s = [0.0; 6];
                for (cp, sp) in c.iter().zip(&at_points[..rule.len()]) {
                    for (si, spi) in s.iter_mut().zip(sp) {
                        *si += cp * spi;
                    }
                }
                s
            }));
        }
        Ok(out)
    }

    fn invalid(&self, reason: String) -> FemError {
        FemError::InvalidElement {
            element: self.id,
            reason,
        }
    }

    /// Node coordinates relative to the first node (so that the Jacobian
    /// does not lose digits far from the origin) and the element's size.
    fn geometry(&self, coords: &[[f64; 3]]) -> Result<Geometry, FemError> {
        let nn = self.kind.node_count();
        if coords.len() != nn {
            return Err(self.invalid(format!(
                "{} needs {} nodes, got {}",
                self.kind.name(),
                nn,
                coords.len()
            )));
        }
        if coords.iter().flatten().any(|c| !c.is_finite()) {
            return Err(self.invalid("node coordinates must be finite".into()));
        }
        let mut rel = [[0.0; 3]; MAX_NODES];
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (r, x) in rel.iter_mut().zip(coords) {
            for i in 0..3 {
                r[i] = x[i] - coords[0][i];
                lo[i] = lo[i].min(x[i]);
                hi[i] = hi[i].max(x[i]);
            }
        }
        let size = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
        Ok(Geometry {
            kind: self.kind,
            origin: coords[0],
            rel,
            size,
        })
    }

    fn check_material(&self) -> Result<(), FemError> {
        match self.material.problem() {
            Some(p) => Err(self.invalid(format!("material: {p}"))),
            None => Ok(()),
        }
    }

    /// Lame constants `(lambda, mu)` from E and nu.
    fn lame(&self) -> (f64, f64) {
        let e = self.material.youngs_modulus;
        let nu = self.material.poisson_ratio;
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }
}

/// Node coordinates relative to the first node, and the element size.
struct Geometry {
    kind: SolidKind,
    /// Global coordinates of the first node.
    origin: [f64; 3],
    rel: [[f64; 3]; MAX_NODES],
    size: f64,
}

/// Shape functions, their global gradients and `det J` at one point.
struct PointValues {
    n: [f64; MAX_NODES],
    grad: [[f64; 3]; MAX_NODES],
    det_j: f64,
}

impl Geometry {
    /// Shape functions, natural derivatives and the Jacobian
    /// `J_ij = dx_i / dxi_j` at `xi`.
    fn jacobian(&self, xi: [f64; 3]) -> ([f64; MAX_NODES], [[f64; 3]; MAX_NODES], [[f64; 3]; 3]) {
        let mut n = [0.0; MAX_NODES];
        let mut dn = [[0.0; 3]; MAX_NODES];
        shape::evaluate(self.kind, xi, &mut n, &mut dn);
        let mut j = [[0.0; 3]; 3];
        for (x, d) in self.rel.iter().zip(&dn).take(self.kind.node_count()) {
            for (ji, xc) in j.iter_mut().zip(x) {
                for (jij, dj) in ji.iter_mut().zip(d) {
                    *jij += xc * dj;
                }
            }
        }
        (n, dn, j)
    }

    /// The global position of a point: `origin + sum_a N_a rel_a`.
    fn global(&self, point: &PointValues) -> [f64; 3] {
        let mut x = self.origin;
        for (n, r) in point.n.iter().zip(&self.rel).take(self.kind.node_count()) {
            for (xi, ri) in x.iter_mut().zip(r) {
                *xi += n * ri;
            }
        }
        x
    }

    fn det_j(&self, xi: [f64; 3]) -> f64 {
        det3(&self.jacobian(xi).2)
    }

    /// The inverse Jacobian at `xi`, `inv[l][m] = dxi_l / dx_m`, and
    /// `det J` there.
    fn inverse_jacobian(&self, xi: [f64; 3]) -> ([[f64; 3]; 3], f64) {
        let j = self.jacobian(xi).2;
        (inverse(&j), det3(&j))
    }

    /// Everything at `xi`; the element must have been validated (`det J > 0`).
    fn point(&self, xi: [f64; 3]) -> PointValues {
        let (n, dn, j) = self.jacobian(xi);
        let det_j = det3(&j);
        let inv = inverse(&j);
        let mut grad = [[0.0; 3]; MAX_NODES];
        for (g, d) in grad.iter_mut().zip(&dn).take(self.kind.node_count()) {
            for (m, gm) in g.iter_mut().enumerate() {
                *gm = d[0] * inv[0][m] + d[1] * inv[1][m] + d[2] * inv[2][m];
            }
        }
        PointValues { n, grad, det_j }
    }
}

/// The inverse of `j` from its cofactors.
fn inverse(j: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let det_j = det3(j);
    [
        [
            (j[1][1] * j[2][2] - j[2][1] * j[1][2]) / det_j,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det_j,
            (j[0][1] * j[1][2] - j[1][1] * j[0][2]) / det_j,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det_j,
            (j[0][0] * j[2][2] - j[2][0] * j[0][2]) / det_j,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det_j,
        ],
        [
            (j[1][0] * j[2][1] - j[2][0] * j[1][1]) / det_j,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det_j,
            (j[0][0] * j[1][1] - j[1][0] * j[0][1]) / det_j,
        ],
    ]
}

fn det3(j: &[[f64; 3]; 3]) -> f64 {
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// Adds one point's stiffness to the upper triangle of `k` (row-major,
/// `3 nn` square): block `(a, b)`, `a <= b`, gets
/// `lw g_a g_b^T + mw (g_b g_a^T + (g_a . g_b) I)` with `lw = lambda w det J`,
/// `mw = mu w det J`.
fn add_stiffness(k: &mut [f64], nn: usize, grad: &[[f64; 3]; MAX_NODES], lw: f64, mw: f64) {
    let nd = 3 * nn;
    for a in 0..nn {
        let gl = grad[a].map(|g| lw * g);
        let gm = grad[a].map(|g| mw * g);
        for (b, gb) in grad.iter().enumerate().take(nn).skip(a) {
            let dot = gm[0] * gb[0] + gm[1] * gb[1] + gm[2] * gb[2];
            for i in 0..3 {
                let row = &mut k[(3 * a + i) * nd + 3 * b..][..3];
                for (j, kij) in row.iter_mut().enumerate() {
                    *kij += gl[i] * gb[j] + gm[j] * gb[i] + if i == j { dot } else { 0.0 };
                }
            }
        }
    }
}

/// Adds one point's stiffness `wd B_a^T C B_b` (`wd = w det J`) to the
/// upper triangle of `k` (row-major, `3 nn` square), for a general
/// elasticity `C` in Voigt order `[xx, yy, zz, xy, yz, zx]` (engineering
/// shears): `B_a` maps `u_a` to those strains.
fn add_stiffness_general(
    k: &mut [f64],
    nn: usize,
    grad: &[[f64; 3]; MAX_NODES],
    c: &Voigt,
    wd: f64,
) {
    let nd = 3 * nn;
    let b = |g: &[f64; 3]| -> [[f64; 3]; 6] {
        [
            [g[0], 0.0, 0.0],
            [0.0, g[1], 0.0],
            [0.0, 0.0, g[2]],
            [g[1], g[0], 0.0],
            [0.0, g[2], g[1]],
            [g[2], 0.0, g[0]],
        ]
    };
    for a in 0..nn {
        let ba = b(&grad[a]);
        // (B_a^T C) w det J: 3 x 6.
        let btc: [[f64; 6]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|m| wd * (0..6).map(|l| ba[l][i] * c[l][m]).sum::<f64>())
        });
        for (bi, gb) in grad.iter().enumerate().take(nn).skip(a) {
            let bb = b(gb);
            for (i, btc_i) in btc.iter().enumerate() {
                let row = &mut k[(3 * a + i) * nd + 3 * bi..][..3];
                for (j, kij) in row.iter_mut().enumerate() {
                    *kij += (0..6).map(|m| btc_i[m] * bb[m][j]).sum::<f64>();
                }
            }
        }
    }
}

/// Adds one point's scalar mass `rw N_a N_b` to the upper triangle of `m`
/// (row-major, `nn` square).
fn add_mass(m: &mut [f64], nn: usize, n: &[f64; MAX_NODES], rw: f64) {
    for a in 0..nn {
        let na = rw * n[a];
        for b in a..nn {
            m[a * nn + b] += na * n[b];
        }
    }
}

/// Engineering strains `[exx, eyy, ezz, gxy, gyz, gzx]` from nodal
/// displacements `u` (3 per node) and the shape-function gradients.
fn strain(grad: &[[f64; 3]], u: &[f64]) -> [f64; 6] {
    // h[i][j] = du_i / dx_j.
    let mut h = [[0.0; 3]; 3];
    for (g, ua) in grad.iter().zip(u.chunks_exact(3)) {
        for (hi, ui) in h.iter_mut().zip(ua) {
            for (hij, gj) in hi.iter_mut().zip(g) {
                *hij += ui * gj;
            }
        }
    }
    [
        h[0][0],
        h[1][1],
        h[2][2],
        h[0][1] + h[1][0],
        h[1][2] + h[2][1],
        h[2][0] + h[0][2],
    ]
}

/// Isotropic Hooke's law in Voigt notation.
fn stress(e: &[f64; 6], lambda: f64, mu: f64) -> [f64; 6] {
    let tr = e[0] + e[1] + e[2];
    [
        lambda * tr + 2.0 * mu * e[0],
        lambda * tr + 2.0 * mu * e[1],
        lambda * tr + 2.0 * mu * e[2],
        mu * e[3],
        mu * e[4],
        mu * e[5],
    ]
}

/// Von Mises equivalent stress of a Voigt stress `[sxx, syy, szz, sxy, syz, szx]`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, zx] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + zx * zx))
        .sqrt()
}

#[cfg(test)]
mod tests;
