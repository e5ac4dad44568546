//! Nodal stresses of solid elements (`nodal_stresses`, `ModalStress`) from
//! the solution of the full FE model, compared with closed forms of linear
//! elasticity: the patch test (a linear displacement field on a distorted
//! mesh gives `sigma = lambda tr(eps) I + 2 mu eps` at every node), a bar
//! in uniaxial tension (`sigma_xx = F / A`, the other components zero, `u =
//! F L / (E A)`) and a bar in pure bending (`sigma_xx = M z / I`, exact for
//! the quadratic elements, whose space holds the bending solution).

mod common;

use common::{dense_matrices, load_vector, mat_vec, max_abs, solve, static_solution};
use faer::Mat;
use flexbody_fem::element::SolidKind;
use flexbody_fem::mesh::{SolidBlock, SolidMesh};
use flexbody_fem::{Dof, DofKind, Material, Model};
use flexbody_recover::{nodal_stresses, ModalStress};
use flexbody_reduce::{Method, ModeKind, ReducedBody};

const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;

/// Lame constants of the material.
fn lame() -> (f64, f64) {
    (
        E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU)),
        E / (2.0 * (1.0 + NU)),
    )
}

/// Hooke's law for a displacement gradient `g[i][j] = du_i / dx_j`, Voigt
/// order `[sxx, syy, szz, sxy, syz, szx]`.
fn hooke(g: &[[f64; 3]; 3]) -> [f64; 6] {
    let (lambda, mu) = lame();
    let tr = g[0][0] + g[1][1] + g[2][2];
    [
        lambda * tr + 2.0 * mu * g[0][0],
        lambda * tr + 2.0 * mu * g[1][1],
        lambda * tr + 2.0 * mu * g[2][2],
        mu * (g[0][1] + g[1][0]),
        mu * (g[1][2] + g[2][1]),
        mu * (g[2][0] + g[0][2]),
    ]
}

/// A structured mesh of the box `origin + [0, size]` in `cells` hexahedral
/// cells (a [`SolidBlock`]), each one element (C3D8, C3D20) or six
/// tetrahedra (C3D10).
struct Mesh {
    solid: SolidMesh,
}

impl Mesh {
    /// The mesh; interior grid points move at random by up to `distortion`
    /// times the cell size and interior mid-edge nodes of C3D20 by a fifth
    /// of that off their edge (curved edges). Boundary nodes stay on the box.
    fn new(
        kind: SolidKind,
        cells: [usize; 3],
        size: [f64; 3],
        origin: [f64; 3],
        distortion: f64,
    ) -> Self {
        assert!(KINDS.contains(&kind), "kind not meshed here");
        let solid = SolidBlock {
            kind,
            cells,
            origin,
            size,
            corner_distortion: distortion,
            // Straight edges for C3D10: the 4-point rule of C3D10 integrates
            // its stiffness exactly only for affine elements, so curved ones
            // miss the patch test (as CalculiX's C3D10).
            edge_distortion: if kind == SolidKind::C3D10 {
                0.0
            } else {
                distortion * 0.2
            },
            seed: 1,
        }
        .mesh();
        Self { solid }
    }

    /// Reference position relative to the box origin, in units of the box
    /// size along `axis`: 0 or 1 on its faces.
    fn relative(&self, node: usize, axis: usize) -> f64 {
        self.solid.reference[node][axis]
    }

    fn model(&self, fixed: Vec<Dof>) -> Model {
        let elements = self.solid.elements(&Material::new(E, NU, RHO).unwrap());
        Model::of(self.solid.nodes(), elements)
            .fixed(fixed)
            .build()
            .unwrap()
    }

    /// Consistent nodal forces along x of the traction `t(y, z)` (Pa) on the
    /// face x = max: `f_a = int N_a t dA` with the face's own shape
    /// functions (bilinear or 8-node serendipity quadrilaterals, 3 x 3
    /// Gauss points, exact for a traction linear in y and z), or for the
    /// 6-node triangles of C3D10 the rule for a uniform traction (corners
    /// 0, mid-edge nodes 1/3 of the area: Zienkiewicz and Taylor, The
    /// Finite Element Method, vol. 1). Returns `(node, force)` pairs.
    fn end_face_loads(&self, traction: impl Fn(f64, f64) -> f64) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        let on_face = |n: usize| (self.relative(n, 0) - 1.0).abs() < 1e-12;
        match self.solid.kind {
            SolidKind::C3D8 | SolidKind::C3D20 => {
                for e in &self.solid.elements {
                    // Face corners: the cell's corners at x = max (Abaqus
                    // order 2, 3, 7, 6 in 1-based numbering), counter-
                    // clockwise in (y, z).
                    let corners = [e[1], e[2], e[6], e[5]];
                    if !corners.iter().all(|&n| on_face(n)) {
                        continue;
                    }
                    let yz = |n: usize| [self.solid.coords[n][1], self.solid.coords[n][2]];
                    let (lo, hi) = (yz(corners[0]), yz(corners[2]));
                    let jac = (hi[0] - lo[0]) * (hi[1] - lo[1]) / 4.0;
                    // Nodes with their (s, t) in the face's parameter square.
                    let mut nodes: Vec<(usize, [f64; 2])> = vec![
                        (corners[0], [-1.0, -1.0]),
                        (corners[1], [1.0, -1.0]),
                        (corners[2], [1.0, 1.0]),
                        (corners[3], [-1.0, 1.0]),
                    ];
                    if self.solid.kind == SolidKind::C3D20 {
                        for (a, b) in [(0, 1), (1, 2), (2, 3), (3, 0)] {
                            let m = self.solid.mid
                                [&(corners[a].min(corners[b]), corners[a].max(corners[b]))];
                            let st = [0, 1].map(|c| 0.5 * (nodes[a].1[c] + nodes[b].1[c]));
                            nodes.push((m, st));
                        }
                    }
                    let g = (0.6f64).sqrt();
                    let gauss = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
                    for (s, ws) in gauss {
                        for (t, wt) in gauss {
                            let y = lo[0] + (s + 1.0) / 2.0 * (hi[0] - lo[0]);
                            let z = lo[1] + (t + 1.0) / 2.0 * (hi[1] - lo[1]);
                            let w = ws * wt * jac * traction(y, z);
                            for &(n, [si, ti]) in &nodes {
                                let shape = if self.solid.kind == SolidKind::C3D8 {
                                    (1.0 + s * si) * (1.0 + t * ti) / 4.0
                                } else if si == 0.0 {
                                    (1.0 - s * s) * (1.0 + t * ti) / 2.0
                                } else if ti == 0.0 {
                                    (1.0 + s * si) * (1.0 - t * t) / 2.0
                                } else {
                                    (1.0 + s * si) * (1.0 + t * ti) * (s * si + t * ti - 1.0) / 4.0
                                };
                                out.push((n, w * shape));
                            }
                        }
                    }
                }
            }
            SolidKind::C3D10 => {
                for e in &self.solid.elements {
                    for face in [[0, 1, 2], [0, 1, 3], [1, 2, 3], [0, 2, 3]] {
                        let c = face.map(|a| e[a]);
                        if !c.iter().all(|&n| on_face(n)) {
                            continue;
                        }
                        let p = c.map(|n| [self.solid.coords[n][1], self.solid.coords[n][2]]);
                        let area = 0.5
                            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
                                .abs();
                        let centre = [0, 1].map(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
                        let t = traction(centre[0], centre[1]);
                        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                            let m = self.solid.mid[&(c[a].min(c[b]), c[a].max(c[b]))];
                            out.push((m, t * area / 3.0));
                        }
                    }
                }
            }
            _ => unreachable!("kind not meshed here"),
        }
        out
    }
}

const KINDS: [SolidKind; 3] = [SolidKind::C3D8, SolidKind::C3D20, SolidKind::C3D10];

/// A general displacement gradient (stretch, shear, rotation) and offset.
const GRADIENT: [[f64; 3]; 3] = [
    [1.0e-3, -4.0e-4, 2.5e-4],
    [3.0e-4, -6.0e-4, 5.0e-4],
    [-2.0e-4, 7.0e-4, 8.0e-4],
];
const OFFSET: [f64; 3] = [1.0e-4, -2.0e-4, 3.0e-4];

/// The patch test: the boundary nodes of a distorted mesh (interior nodes
/// moved, quadratic elements with curved interior edges) get the linear
/// field `u = G x + c`; the interior nodes, solved from `K_ii u_i = -K_ib
/// u_b`, must follow it, and every node's averaged stress is Hooke's law of
/// `G`. Returns the model, the solved `u`, and the largest deviations of
/// the displacements and of the stresses, relative to their largest values.
fn patch(kind: SolidKind, gradient: &[[f64; 3]; 3]) -> (Model, Vec<f64>, f64, f64) {
    let mesh = Mesh::new(kind, [3, 3, 3], [1.0, 0.8, 0.6], [0.3, -0.2, 1.1], 0.25);
    let model = mesh.model(vec![]);
    let (k, _) = dense_matrices(&model);
    let dofs = model.dof_map().dofs().to_vec();
    let exact = |d: &Dof| {
        let x = model.coords(d.node);
        let i = d.kind.index();
        OFFSET[i] + (0..3).map(|j| gradient[i][j] * x[j]).sum::<f64>()
    };
    let boundary: Vec<bool> = dofs
        .iter()
        .map(|d| mesh.solid.on_boundary(d.node as usize - 1))
        .collect();
    let mut u: Vec<f64> = dofs
        .iter()
        .zip(&boundary)
        .map(|(d, on)| if *on { exact(d) } else { 0.0 })
        .collect();
    let inner: Vec<usize> = (0..dofs.len()).filter(|i| !boundary[*i]).collect();
    assert!(!inner.is_empty());
    let ku = mat_vec(&k, &u);
    let kii: Vec<Vec<f64>> = inner
        .iter()
        .map(|&i| inner.iter().map(|&j| k[i][j]).collect())
        .collect();
    let ui = solve(kii, inner.iter().map(|&i| -ku[i]).collect());
    for (&i, v) in inner.iter().zip(ui) {
        u[i] = v;
    }
    let scale_u = max_abs(dofs.iter().map(exact));
    let du = max_abs(dofs.iter().zip(&u).map(|(d, v)| v - exact(d))) / scale_u;
    let want = hooke(gradient);
    let s = nodal_stresses(&model, &u).unwrap();
    assert_eq!(s.nodes.len(), model.nodes().len());
    let scale = max_abs(want);
    let ds = max_abs(
        s.stress
            .iter()
            .flat_map(|st| (0..6).map(move |c| st[c] - want[c])),
    ) / scale;
    (model, u, du, ds)
}

#[test]
fn patch_test_on_a_distorted_mesh_gives_the_exact_stress_at_every_node() {
    for kind in KINDS {
        let (_, _, du, ds) = patch(kind, &GRADIENT);
        // measured: displacements 5e-15, stresses 6e-14 (C3D8, C3D20, C3D10).
        assert!(du < 1e-13, "{kind:?}: displacements deviate by {du:e}");
        assert!(ds < 1e-12, "{kind:?}: stresses deviate by {ds:e}");
    }
}

/// Modal stress matrices of a basis of two patch-test fields: `T_sigma q`
/// must be Hooke's law of `q_1 G_1 + q_2 G_2` at every node.
#[test]
fn modal_stress_of_linear_fields_is_hookes_law_of_the_combination() {
    let g2 = [
        [-5.0e-4, 2.0e-4, 0.0],
        [1.0e-4, 9.0e-4, -3.0e-4],
        [6.0e-4, 0.0, -2.0e-4],
    ];
    for kind in [SolidKind::C3D8, SolidKind::C3D20] {
        let (model, u1, _, _) = patch(kind, &GRADIENT);
        let (_, u2, _, _) = patch(kind, &g2);
        let m = u1.len();
        let body = ReducedBody {
            method: Method::Free,
            dof_map: model.dof_map().clone(),
            basis: Mat::from_fn(m, 2, |i, j| if j == 0 { u1[i] } else { u2[i] }),
            mass: Mat::identity(2, 2),
            stiffness: Mat::identity(2, 2),
            damping: None,
            modes: vec![ModeKind::Eigen { frequency_hz: 0.0 }; 2],
            interface: vec![],
            local_axes: Default::default(),
        };
        let q = [0.7, -1.3];
        let combined: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| q[0] * GRADIENT[i][j] + q[1] * g2[i][j])
        });
        let want = hooke(&combined);
        let modal = ModalStress::new(&model, &body).unwrap();
        let s = modal.stresses(&q);
        assert_eq!(s.nodes.len(), model.nodes().len());
        let dev = max_abs(
            s.stress
                .iter()
                .flat_map(|st| (0..6).map(move |c| st[c] - want[c])),
        ) / max_abs(want);
        // measured 5e-14.
        assert!(dev < 1e-12, "{kind:?}: modal stresses deviate by {dev:e}");
    }
}

/// A bar in tension: quarter model of a prism (symmetry planes x = 0, y =
/// 0, z = 0 held normal to themselves) under a uniform traction on its end
/// face, applied as consistent nodal loads: `sigma_xx = F / A`, the other
/// components zero, `von Mises = F / A`, end displacement `F L / (E A)` and
/// lateral contraction `-nu F b / (E A)`.
#[test]
fn bar_in_tension_gives_f_over_a() {
    let (l, b, h) = (1.2, 0.1, 0.15);
    let force = 3.0e5;
    let sigma = force / (b * h);
    for kind in KINDS {
        let mesh = Mesh::new(kind, [6, 2, 2], [l, b, h], [0.0; 3], 0.2);
        let mut fixed = Vec::new();
        for n in 0..mesh.solid.coords.len() {
            for (axis, dof) in [DofKind::Ux, DofKind::Uy, DofKind::Uz]
                .into_iter()
                .enumerate()
            {
                if mesh.relative(n, axis).abs() < 1e-12 {
                    fixed.push(Dof::new(n as u64 + 1, dof));
                }
            }
        }
        let model = mesh.model(fixed);
        let loads: Vec<(Dof, f64)> = mesh
            .end_face_loads(|_, _| sigma)
            .into_iter()
            .map(|(n, f)| (Dof::new(n as u64 + 1, DofKind::Ux), f))
            .collect();
        let total: f64 = loads.iter().map(|(_, f)| f).sum();
        assert!(
            (total - force).abs() < 1e-13 * force,
            "{kind:?}: load {total} vs {force}"
        );
        let u = static_solution(&model, &loads);
        let s = nodal_stresses(&model, &u).unwrap();
        let want = [sigma, 0.0, 0.0, 0.0, 0.0, 0.0];
        let dev = max_abs(
            s.stress
                .iter()
                .flat_map(|st| (0..6).map(move |c| st[c] - want[c])),
        ) / sigma;
        // measured 3e-13 (C3D8, C3D20, C3D10).
        assert!(dev < 3e-12, "{kind:?}: stresses deviate by {dev:e}");
        let vm = max_abs(s.von_mises().into_iter().map(|v| v - sigma)) / sigma;
        assert!(vm < 3e-12, "{kind:?}: von Mises deviates by {vm:e}");
        // End and lateral displacements of the uniaxial stress state.
        let eps = sigma / E;
        // The uniaxial field is linear in the (distorted) coordinates.
        for node in model.nodes() {
            let ux = model.value(Dof::new(node.id, DofKind::Ux), &u);
            let uy = model.value(Dof::new(node.id, DofKind::Uy), &u);
            let (want_ux, want_uy) = (eps * node.coords[0], -NU * eps * node.coords[1]);
            // measured 2e-13 relative to eps L.
            assert!(
                (ux - want_ux).abs() < 2e-12 * eps * l && (uy - want_uy).abs() < 2e-12 * eps * l,
                "{kind:?}: node {}: ({ux}, {uy}) vs ({want_ux}, {want_uy})",
                node.id
            );
        }
    }
}

/// A bar in pure bending: half model (symmetry plane y = 0; x = 0 held
/// plane, uz held at the origin) of a prism `z in [-h/2, h/2]` with the
/// linear traction `sigma_0 2 z / h` on its end face (consistent loads):
/// the Saint-Venant solution `sigma_xx = M z / I`, the other stresses
/// zero, `ux = kappa x z` with `kappa = M / (E I)`. Its displacements are
/// quadratic, so C3D20 reproduces it exactly; C3D8 (trilinear, shear
/// locking in bending) only approximately, checked away from the ends.
#[test]
fn bar_in_pure_bending_gives_m_z_over_i() {
    let (l, b, h): (f64, f64, f64) = (1.0, 0.08, 0.2);
    let sigma0 = 1.0e8;
    // M = int sigma z dA = sigma_0 (2 / h) I over the half section.
    let i_half = b * h.powi(3) / 12.0;
    let moment = sigma0 * 2.0 / h * i_half;
    for (kind, cells) in [(SolidKind::C3D20, [4, 1, 2]), (SolidKind::C3D8, [20, 2, 8])] {
        let mesh = Mesh::new(kind, cells, [l, b, h], [0.0, 0.0, -h / 2.0], 0.0);
        let mut fixed = Vec::new();
        for n in 0..mesh.solid.coords.len() {
            let id = n as u64 + 1;
            if mesh.relative(n, 0).abs() < 1e-12 {
                fixed.push(Dof::new(id, DofKind::Ux));
                if mesh.relative(n, 1).abs() < 1e-12 && (mesh.relative(n, 2) - 0.5).abs() < 1e-12 {
                    fixed.push(Dof::new(id, DofKind::Uz));
                }
            }
            if mesh.relative(n, 1).abs() < 1e-12 {
                fixed.push(Dof::new(id, DofKind::Uy));
            }
        }
        assert!(fixed.iter().any(|d| d.kind == DofKind::Uz));
        let model = mesh.model(fixed);
        let loads: Vec<(Dof, f64)> = mesh
            .end_face_loads(|_, z| sigma0 * 2.0 * z / h)
            .into_iter()
            .map(|(n, f)| (Dof::new(n as u64 + 1, DofKind::Ux), f))
            .collect();
        let f = load_vector(&model, &loads);
        let applied: f64 = loads.iter().map(|(d, f)| f * model.coords(d.node)[2]).sum();
        assert!(
            (applied - moment).abs() < 1e-13 * moment,
            "moment {applied} vs {moment}"
        );
        assert!(max_abs(f.iter().copied()) > 0.0);
        let u = static_solution(&model, &loads);
        let s = nodal_stresses(&model, &u).unwrap();
        let kappa = moment / (E * i_half);
        let mut dev: f64 = 0.0;
        let mut dev_u: f64 = 0.0;
        for (node, st) in s.nodes.iter().zip(&s.stress) {
            let x = model.coords(*node);
            if kind == SolidKind::C3D8 && (x[0] < 0.25 * l || x[0] > 0.75 * l) {
                continue;
            }
            let want = [moment * x[2] / i_half, 0.0, 0.0, 0.0, 0.0, 0.0];
            dev = dev.max(max_abs((0..6).map(|c| st[c] - want[c])) / sigma0);
            let ux = model.value(Dof::new(*node, DofKind::Ux), &u);
            dev_u = dev_u.max((ux - kappa * x[0] * x[2]).abs() / (kappa * l * h / 2.0));
        }
        let (tol, tol_u) = match kind {
            // measured 4e-12 and 1.4e-12: exact up to round-off.
            SolidKind::C3D20 => (4e-11, 2e-11),
            // measured: C3D8 stresses 5.0e-2 of sigma_0, displacements 2.0e-2 of the
            // extreme fibre's (locking); loose for that reason.
            _ => (0.1, 0.05),
        };
        assert!(
            dev < tol,
            "{kind:?}: stresses deviate by {dev:e} of sigma_0"
        );
        assert!(dev_u < tol_u, "{kind:?}: ux deviates by {dev_u:e}");
    }
}
