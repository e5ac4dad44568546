//! Beams along a line, their frames, and beam statics and rigid-body
//! acceleration in closed form.

use crate::common::{dense_matrices, mat_vec, max_abs, solve};
use flexbody_fem::mesh::{BeamLine, BeamLineKind};
use flexbody_fem::section::SectionConstants;
use flexbody_fem::{
    BeamProperties, BeamTheory, Dof, DofKind, Element, Material, Model, SectionForces, SectionShape,
};
use flexbody_recover::ElementForces;

pub(crate) const E: f64 = 2.1e11;
pub(crate) const NU: f64 = 0.3;
pub(crate) const RHO: f64 = 7850.0;

/// Solid rectangle 40 mm (local y) by 60 mm (local z): `Iy != Iz`, so the
/// two bending planes cannot be swapped unnoticed.
pub(crate) fn section() -> SectionConstants {
    SectionShape::Rect {
        width: 0.04,
        height: 0.06,
    }
    .constants()
    .unwrap()
}

pub(crate) fn props(theory: BeamTheory) -> BeamProperties {
    BeamProperties::new(Material::new(E, NU, RHO).unwrap(), section(), theory)
}

/// The element kinds under test.
#[derive(Copy, Clone, Debug)]
pub(crate) enum Kind {
    /// Planar beam (uz, ry), Euler-Bernoulli.
    Planar,
    /// 3D beam of the given theory.
    Beam(BeamTheory),
}

pub(crate) const KINDS: [Kind; 3] = [
    Kind::Planar,
    Kind::Beam(BeamTheory::EulerBernoulli),
    Kind::Beam(BeamTheory::Timoshenko),
];

impl Kind {
    pub(crate) fn properties(self) -> BeamProperties {
        match self {
            Kind::Planar => props(BeamTheory::EulerBernoulli),
            Kind::Beam(t) => props(t),
        }
    }

    /// The elements of a [`BeamLine`] of this kind; `orientation` is the
    /// local y of a 3D beam.
    pub(crate) fn line_kind(self, orientation: [f64; 3]) -> BeamLineKind {
        match self {
            Kind::Planar => BeamLineKind::Planar,
            Kind::Beam(_) => BeamLineKind::Spatial { orientation },
        }
    }

    pub(crate) fn dof_kinds(self) -> &'static [DofKind] {
        match self {
            Kind::Planar => &[DofKind::Uz, DofKind::Ry],
            Kind::Beam(_) => &DofKind::ALL,
        }
    }
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    a.map(|v| v / n)
}

/// `sum c_k v_k`.
pub(crate) fn combine(terms: &[(f64, [f64; 3])]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (c, v) in terms {
        for k in 0..3 {
            out[k] += c * v[k];
        }
    }
    out
}

/// Element frame (rows x, y, z) as the element modules document it. 3D
/// beam: x from node 1 to node 2, y the part of the orientation vector
/// normal to x, z = x cross y. Planar beam: x along the element, y = s
/// times global y (s = +1 if node 2 lies at larger x), z = global z.
pub(crate) fn frame(model: &Model, e: &Element) -> [[f64; 3]; 3] {
    let nodes = e.nodes();
    let (a, b) = (model.coords(nodes[0]), model.coords(nodes[1]));
    let ex = unit(sub(b, a));
    match e {
        Element::Beam(beam) => {
            let v = beam.orientation;
            let ey = unit(combine(&[(1.0, v), (-dot(v, ex), ex)]));
            [ex, ey, cross(ex, ey)]
        }
        Element::PlanarBeam(_) => [ex, [0.0, ex[0].signum(), 0.0], [0.0, 0.0, 1.0]],
        _ => unreachable!("not a beam"),
    }
}

/// A straight line of `n` elements of `kind` from `a` to `b`, nodes
/// `1..=n+1` in order along it; element `i` (0-based) runs from its higher
/// node to its lower one if `reversed(i)`.
pub(crate) fn line(
    kind: Kind,
    n: usize,
    a: [f64; 3],
    b: [f64; 3],
    orientation: [f64; 3],
    reversed: impl Fn(usize) -> bool,
    fixed: Vec<Dof>,
) -> Model {
    let line = BeamLine {
        cells: n,
        start: a,
        end: b,
        kind: kind.line_kind(orientation),
        properties: kind.properties(),
    };
    Model::of(line.nodes(), line.elements_reversed(reversed))
        .fixed(fixed)
        .build()
        .unwrap()
}

/// A line of `n` elements of `kind` along global x from the origin to
/// `l`, orientation vector global y, every element forward, `fixed` held.
pub(crate) fn along_x(kind: Kind, n: usize, l: f64, fixed: Vec<Dof>) -> Model {
    line(
        kind,
        n,
        [0.0; 3],
        [l, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        |_| false,
        fixed,
    )
}

/// Where a cantilever lies: its clamped end, its unit direction and the
/// orientation vector of its elements.
pub(crate) type Placement = ([f64; 3], [f64; 3], [f64; 3]);

/// The shear deflection of beam theory, `v / (G A_s)` for a shear term `v`
/// (shear force times length) on the shear area `area`: zero for the
/// kinds that do not deform in shear (Euler-Bernoulli).
pub(crate) fn shear_deflection(kind: Kind, v: f64, area: f64) -> f64 {
    match kind {
        Kind::Beam(BeamTheory::Timoshenko) => v / (kind.properties().material.shear_modulus * area),
        Kind::Planar | Kind::Beam(BeamTheory::EulerBernoulli) => 0.0,
    }
}

/// The skew placement of the 3D cantilevers: no axis of the element frame
/// along a global one.
pub(crate) fn skew() -> Placement {
    ([0.1, -0.2, 0.3], unit([1.0, 2.0, 2.0]), [0.3, 0.0, 1.0])
}

/// A cantilever of `n` elements of `kind` and length `l` placed by
/// `placement`, clamped at node 1; element `i` runs backwards if
/// `reversed(i)`.
pub(crate) fn cantilever(
    kind: Kind,
    n: usize,
    l: f64,
    placement: Placement,
    reversed: impl Fn(usize) -> bool,
) -> Model {
    let (a, dir, orientation) = placement;
    let b = combine(&[(1.0, a), (l, dir)]);
    line(kind, n, a, b, orientation, reversed, all_dofs(kind, 1))
}

/// Loads on every DOF of `node`: `force` on its translations, `moment` on
/// its rotations.
pub(crate) fn node_loads(node: u64, force: [f64; 3], moment: [f64; 3]) -> Vec<(Dof, f64)> {
    DofKind::ALL
        .iter()
        .enumerate()
        .map(|(c, k)| {
            (
                Dof::new(node, *k),
                if c < 3 { force[c] } else { moment[c - 3] },
            )
        })
        .collect()
}

/// A load at the tip `b` of a cantilever and the reaction of its clamp at
/// `a` that balances it.
pub(crate) fn tip_load_and_reaction(
    a: [f64; 3],
    b: [f64; 3],
    force: [f64; 3],
    moment: [f64; 3],
) -> [PointLoad; 2] {
    [
        PointLoad {
            at: b,
            force,
            moment,
        },
        PointLoad {
            at: a,
            force: force.map(|v| -v),
            moment: combine(&[(-1.0, moment), (-1.0, cross(sub(b, a), force))]),
        },
    ]
}

/// All DOFs of `kind` at `node`.
pub(crate) fn all_dofs(kind: Kind, node: u64) -> Vec<Dof> {
    kind.dof_kinds()
        .iter()
        .map(|k| Dof::new(node, *k))
        .collect()
}

/// Global displacement and rotation of a node, `[ux, uy, uz, rx, ry, rz]`
/// (DOFs the model lacks: 0).
pub(crate) fn node_motion(model: &Model, u: &[f64], node: u64) -> [f64; 6] {
    DofKind::ALL.map(|k| {
        let d = Dof::new(node, k);
        if model.dof_map().index_of(d).is_some() {
            model.value(d, u)
        } else {
            0.0
        }
    })
}

/// A concentrated load (support reactions included): point, force (N) and
/// moment (N m), global components.
pub(crate) struct PointLoad {
    pub(crate) at: [f64; 3],
    pub(crate) force: [f64; 3],
    pub(crate) moment: [f64; 3],
}

/// Beam statics: section forces at both ends of an element (frame `f`)
/// from the concentrated loads on the beam. The internal force on the
/// positive cut face (outward normal +x of the element) is what the part
/// beyond the cut in +x exerts on it: the resultant of the loads on that
/// part, `sum F_k` and `sum (M_k + (x_k - p) x F_k)` about the cut `p`.
/// Loads sit at nodes; the part beyond either end of an element is the
/// one beyond its midpoint.
pub(crate) fn statics(
    start: [f64; 3],
    end: [f64; 3],
    f: &[[f64; 3]; 3],
    loads: &[PointLoad],
) -> SectionForces {
    let mid = combine(&[(0.5, start), (0.5, end)]);
    let at = |p: [f64; 3]| {
        let mut force = [0.0; 3];
        let mut moment = [0.0; 3];
        for l in loads.iter().filter(|l| dot(sub(l.at, mid), f[0]) > 0.0) {
            force = combine(&[(1.0, force), (1.0, l.force)]);
            moment = combine(&[
                (1.0, moment),
                (1.0, l.moment),
                (1.0, cross(sub(l.at, p), l.force)),
            ]);
        }
        [
            dot(force, f[0]),
            dot(force, f[1]),
            dot(force, f[2]),
            dot(moment, f[0]),
            dot(moment, f[1]),
            dot(moment, f[2]),
        ]
    };
    SectionForces {
        start: at(start),
        end: at(end),
    }
}

/// Largest deviation of the recovered section forces from the expected
/// ones over all element ends: forces (N, Qy, Qz) relative to the largest
/// expected force, moments (T, My, Mz) to the largest expected moment.
pub(crate) fn deviation(got: &[SectionForces], want: &[SectionForces]) -> f64 {
    assert_eq!(got.len(), want.len());
    let rows = |s: &[SectionForces], r: std::ops::Range<usize>| -> Vec<f64> {
        s.iter()
            .flat_map(|f| {
                f.start[r.clone()]
                    .iter()
                    .chain(&f.end[r.clone()])
                    .copied()
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let mut worst: f64 = 0.0;
    for r in [0..3, 3..6] {
        let (g, w) = (rows(got, r.clone()), rows(want, r));
        let scale = max_abs(w.iter().copied());
        if scale == 0.0 {
            assert!(
                max_abs(g.iter().copied()) == 0.0,
                "expected zero, got {g:?}"
            );
            continue;
        }
        let d = max_abs(g.iter().zip(&w).map(|(a, b)| a - b));
        worst = worst.max(d / scale);
    }
    worst
}

pub(crate) fn forces_of(recovered: &[ElementForces]) -> Vec<SectionForces> {
    recovered.iter().map(|e| e.forces).collect()
}

pub(crate) fn element(model: &Model, id: usize) -> &Element {
    model.elements().iter().find(|e| e.id() == id).unwrap()
}

/// Section forces of a statics problem at every element end.
pub(crate) fn expected_statics(
    model: &Model,
    recovered: &[ElementForces],
    loads: &[PointLoad],
) -> Vec<SectionForces> {
    recovered
        .iter()
        .map(|r| {
            statics(
                r.start,
                r.end,
                &frame(model, element(model, r.element)),
                loads,
            )
        })
        .collect()
}

/// Loads `[Fx, Fy, Fz, Mx]` at the end x = L of a free beam `[0, L]` along
/// global x accelerate it as a rigid body: axial `a = Fx / m`, twist
/// `Mx / (rho (Iy + Iz) L)`, and in each bending plane the translation `F /
/// m` and angular acceleration `beta = F (L/2) / J` with `J = rho A L^3 / 12
/// + rho I L` (the rotary term only if the element has rotary inertia).
pub(crate) struct Accelerated {
    pub(crate) l: f64,
    pub(crate) mu: f64,
    /// Rotary inertia per length about y and z (kg m).
    pub(crate) rot: [f64; 2],
    /// Axial and angular (about x) accelerations.
    pub(crate) axial: f64,
    pub(crate) twist: f64,
    /// Translation at the centre and angular acceleration, per plane (y, z).
    pub(crate) a0: [f64; 2],
    pub(crate) beta: [f64; 2],
    pub(crate) polar: f64,
}

impl Accelerated {
    pub(crate) fn new(p: &BeamProperties, l: f64, loads: [f64; 4]) -> Self {
        let s = &p.section;
        let mu = RHO * s.area;
        let rot = if p.rotary_inertia {
            [RHO * s.iy, RHO * s.iz]
        } else {
            [0.0; 2]
        };
        let polar = RHO * (s.iy + s.iz);
        let m = mu * l;
        let j = |r: f64| mu * l.powi(3) / 12.0 + r * l;
        Self {
            l,
            mu,
            rot,
            axial: loads[0] / m,
            twist: loads[3] / (polar * l),
            a0: [loads[1] / m, loads[2] / m],
            beta: [
                loads[1] * l / 2.0 / j(rot[1]),
                loads[2] * l / 2.0 / j(rot[0]),
            ],
            polar,
        }
    }

    /// Nodal accelerations `[ux, uy, uz, rx, ry, rz]` at x: `v'' = a0 +
    /// beta (x - L/2)` with `rz'' = beta_y`, and `w''` likewise with `ry'' =
    /// -beta_z` (ry = -dw/dx).
    pub(crate) fn acceleration(&self, x: f64) -> [f64; 6] {
        let c = x - self.l / 2.0;
        [
            self.axial,
            self.a0[0] + self.beta[0] * c,
            self.a0[1] + self.beta[1] * c,
            self.twist,
            -self.beta[1],
            self.beta[0],
        ]
    }

    /// d'Alembert on the part `[0, x]`: `Q = mu int_0^x a ds`, `My = mu
    /// int_0^x (x - s) w'' ds - rho Iy beta_z x`, `Mz = -mu int_0^x (x - s)
    /// v'' ds + rho Iz beta_y x`, `N = mu a x`, `T = rho (Iy + Iz) alpha x`.
    pub(crate) fn section_forces(&self, x: f64) -> [f64; 6] {
        let (l, mu) = (self.l, self.mu);
        let shear = |p: usize| mu * (self.a0[p] * x + self.beta[p] * (x * x / 2.0 - l * x / 2.0));
        let moment = |p: usize| {
            mu * (self.a0[p] * x * x / 2.0 + self.beta[p] * (x.powi(3) / 6.0 - l * x * x / 4.0))
        };
        [
            mu * self.axial * x,
            shear(0),
            shear(1),
            self.polar * self.twist * x,
            moment(1) - self.rot[0] * self.beta[1] * x,
            -(moment(0) - self.rot[1] * self.beta[0] * x),
        ]
    }
}

/// Accelerations over the model's equations of the rigid-body motion.
pub(crate) fn acceleration_vector(model: &Model, acc: &Accelerated) -> Vec<f64> {
    let mut a = vec![0.0; model.dof_map().len()];
    for (i, d) in model.dof_map().dofs().iter().enumerate() {
        let x = model.coords(d.node)[0];
        a[i] = acc.acceleration(x)[d.kind.index()];
    }
    a
}

/// The quasi-static state of a free beam under end loads `f`: the rigid
/// acceleration `a` and the deformation `u` with `K u = f - M a`, solved
/// with node 1 held (the right-hand side is balanced, so the reaction
/// `K u - f + M a` there vanishes; the returned figure is its largest
/// value relative to the largest load).
pub(crate) fn accelerated_state(
    model: &Model,
    f: &[f64],
    acc: &Accelerated,
) -> (Vec<f64>, Vec<f64>, f64) {
    let (k, m) = dense_matrices(model);
    let a = acceleration_vector(model, acc);
    let ma = mat_vec(&m, &a);
    let rhs: Vec<f64> = f.iter().zip(&ma).map(|(x, y)| x - y).collect();
    let held: Vec<bool> = model.dof_map().dofs().iter().map(|d| d.node == 1).collect();
    let free: Vec<usize> = (0..f.len()).filter(|i| !held[*i]).collect();
    let kff: Vec<Vec<f64>> = free
        .iter()
        .map(|&i| free.iter().map(|&j| k[i][j]).collect())
        .collect();
    let uf = solve(kff, free.iter().map(|&i| rhs[i]).collect());
    let mut u = vec![0.0; f.len()];
    for (&i, v) in free.iter().zip(uf) {
        u[i] = v;
    }
    let ku = mat_vec(&k, &u);
    let unbalance = max_abs((0..f.len()).filter(|i| held[*i]).map(|i| ku[i] - rhs[i]))
        / max_abs(f.iter().copied());
    (u, a, unbalance)
}
