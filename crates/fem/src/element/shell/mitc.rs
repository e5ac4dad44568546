//! The strains, stiffness, mass and stresses of the shells (see the module
//! docs of [`super`]): a degenerated continuum over the reference surface,
//! its transverse shear strains tied at the edges (MITC4), at interior
//! points (MITC3+, whose rotations carry a cubic bubble), at the edges and
//! inside in Nedelec's space (S6, in the manner of MITC6), or every strain
//! tied as in MITC9 on a nine-node surface (S8).

use super::surface::{self, G2, G3, MAX_NODES, THICKNESS_RULE};
use super::ShellKind;
use crate::element::MassPoint;
use faer::Mat;

/// Largest number of DOFs of a shell element (six per node).
pub(super) const MAX_DOFS: usize = 6 * MAX_NODES;

/// One linear form of the element's DOFs (`ux uy uz rx ry rz` node by node).
type Row = [f64; MAX_DOFS];

const ZERO_ROW: Row = [0.0; MAX_DOFS];

/// The shear correction factor of the transverse shear stiffness (the
/// energy of a parabolic shear distribution through the thickness).
pub(super) const SHEAR_FACTOR: f64 = 5.0 / 6.0;

/// The drilling stiffness per area, as a fraction of `G t`: the penalty on
/// the difference between a node's rotation about the normal and the
/// rotation of the membrane (Hughes and Brezzi), zero under a rigid motion.
pub(super) const DRILLING: f64 = 1e-3;

/// The element's reference surface, relative to its first node, with a
/// unit director at each node (the element's normal there) and its
/// thickness and offset.
pub(super) struct Geometry {
    pub kind: ShellKind,
    pub origin: [f64; 3],
    pub rel: [[f64; 3]; MAX_NODES],
    pub director: [[f64; 3]; MAX_NODES],
    /// Thickness `a` (m).
    pub thickness: f64,
    /// The mid-surface's distance from the nodes along the director, in
    /// thicknesses.
    pub offset: f64,
}

/// Everything at one point `(r, s, t)` of the shell: shape functions, the
/// covariant base vectors `g_r, g_s, g_t`, the distance `h` of the level
/// from the nodes along the directors, `det J` and the local frame.
pub(super) struct Point {
    /// The shape functions of the surface and of the nodes' displacements.
    pub n: [f64; MAX_NODES],
    pub dn: [[f64; 2]; MAX_NODES],
    /// The shape functions of the nodes' rotations: `n`, and for S3 its
    /// bubble at the fourth node.
    pub f: [f64; MAX_NODES],
    pub df: [[f64; 2]; MAX_NODES],
    pub g: [[f64; 3]; 3],
    pub h: f64,
    pub det_j: f64,
    /// `e1` along `g_r`, `e3` normal to `g_r` and `g_s`, `e2 = e3 x e1`.
    pub frame: [[f64; 3]; 3],
    /// `a[alpha][k] = g^alpha . e_k` (contravariant base vectors on the frame).
    pub a: [[f64; 3]; 3],
}

impl Geometry {
    /// The interpolation nodes (S8: with its internal centre).
    fn nodes(&self) -> usize {
        self.kind.interpolation_nodes()
    }

    /// The point at natural coordinates `rs` and thickness coordinate `t`
    /// (`-1` bottom, `1` top).
    pub fn point(&self, rs: [f64; 2], t: f64) -> Point {
        let (mut n, mut dn) = ([0.0; MAX_NODES], [[0.0; 2]; MAX_NODES]);
        surface::evaluate(self.kind, rs, &mut n, &mut dn);
        let h = self.thickness * (self.offset + 0.5 * t);
        let mut g = [[0.0; 3]; 3];
        for i in 0..self.nodes() {
            let (x, v) = (self.rel[i], self.director[i]);
            for c in 0..3 {
                let p = x[c] + h * v[c];
                g[0][c] += dn[i][0] * p;
                g[1][c] += dn[i][1] * p;
                g[2][c] += 0.5 * self.thickness * n[i] * v[c];
            }
        }
        let normal = cross(g[0], g[1]);
        let det_j = dot(normal, g[2]);
        let e3 = unit(normal);
        let e1 = unit(g[0]);
        let frame = [e1, cross(e3, e1), e3];
        let contra = [
            cross(g[1], g[2]).map(|v| v / det_j),
            cross(g[2], g[0]).map(|v| v / det_j),
            normal.map(|v| v / det_j),
        ];
        let a = contra.map(|ga| frame.map(|e| dot(ga, e)));
        let (mut f, mut df) = (n, dn);
        if self.kind == ShellKind::S3 {
            (f[3], df[3]) = surface::rotation_bubble(rs);
        }
        Point {
            n,
            dn,
            f,
            df,
            g,
            h,
            det_j,
            frame,
            a,
        }
    }

    /// The directions, among the DOFs of the interpolation nodes beyond the
    /// element's own, that the element condenses: each of S8's centre
    /// node's six DOFs; S3's bubble rotations about the two in-plane axes
    /// of its frame (the bubble moves no point of the surface and turns no
    /// director about itself). Empty for the other kinds.
    pub fn internal_directions(&self) -> Vec<[f64; 6]> {
        let unit_dof = |k: usize| std::array::from_fn(|i| (i == k) as u8 as f64);
        match self.kind {
            ShellKind::S8 => (0..6).map(unit_dof).collect(),
            ShellKind::S3 => {
                let frame = self.point([1.0 / 3.0, 1.0 / 3.0], 0.0).frame;
                frame[..2]
                    .iter()
                    .map(|e| [0.0, 0.0, 0.0, e[0], e[1], e[2]])
                    .collect()
            }
            ShellKind::S4 | ShellKind::S6 => Vec::new(),
        }
    }

    /// The global position of the reference (node) surface at `rs`.
    pub fn position(&self, rs: [f64; 2]) -> [f64; 3] {
        let (mut n, mut dn) = ([0.0; MAX_NODES], [[0.0; 2]; MAX_NODES]);
        surface::evaluate(self.kind, rs, &mut n, &mut dn);
        let mut x = self.origin;
        for (ni, r) in n.iter().zip(&self.rel).take(self.nodes()) {
            for c in 0..3 {
                x[c] += ni * r[c];
            }
        }
        x
    }

    /// The factors of `u_a` and of `theta_a x V_a` in `dU/dr, dU/ds,
    /// dU/dt` at `p`: `[c, d]` per derivative.
    fn factors(&self, p: &Point, a: usize) -> [[f64; 2]; 3] {
        [
            [p.dn[a][0], p.df[a][0] * p.h],
            [p.dn[a][1], p.df[a][1] * p.h],
            [0.0, 0.5 * self.thickness * p.f[a]],
        ]
    }

    /// The covariant strain `e_ab = (g_a . U,b + g_b . U,a) / 2` at `p` as a
    /// row over the DOFs, for the derivative indices `a`, `b` (0 r, 1 s,
    /// 2 t).
    fn covariant(&self, p: &Point, alpha: usize, beta: usize) -> Row {
        let mut row = ZERO_ROW;
        for i in 0..self.nodes() {
            let f = self.factors(p, i);
            let v = self.director[i];
            let (ga, gb) = (p.g[alpha], p.g[beta]);
            let (va, vb) = (cross(v, ga), cross(v, gb));
            for c in 0..3 {
                row[6 * i + c] = 0.5 * (f[beta][0] * ga[c] + f[alpha][0] * gb[c]);
                row[6 * i + 3 + c] = 0.5 * (f[beta][1] * va[c] + f[alpha][1] * vb[c]);
            }
        }
        row
    }

    /// The points whose covariant strains the tied strains interpolate, as
    /// `(rs, alpha, beta)` for the strain `e_alpha,beta` there, in the order
    /// [`Self::tied_shear`] and [`Self::membrane`] read them from a
    /// [`Level`]. S4: `e_rt` at the edge midpoints `s = 1, -1`, `e_st` at
    /// `r = 1, -1` (MITC4: Dvorkin and Bathe). S3: `e_rt` and `e_st` at
    /// the points A, B, C on the lines from the centroid to the corners,
    /// `e_rt` at D, `e_st` at E and both at F, a distance `d = 1e-4` from
    /// the centroid (MITC3+: Lee, Lee and Bathe, 2014; the authors chose
    /// `d` for the least in-plane twisting stiffness). S6: `e_rt` at the
    /// two Gauss points of the edge `s = 0`, `e_st` at those of `r = 0`,
    /// both at those of the third edge, then both at the three points of
    /// its reduced rule ([`nedelec_weights`]). S8: MITC9's (see
    /// [`mitc9`]), `e_rt`, `e_st`, `e_rr`, `e_ss` at six points each and
    /// `e_rs` at the 2 x 2 Gauss points.
    fn tying_points(&self) -> Vec<([f64; 2], usize, usize)> {
        const THIRD: f64 = 1.0 / 3.0;
        const D: f64 = 1e-4;
        match self.kind {
            ShellKind::S4 => vec![
                ([0.0, 1.0], 0, 2),
                ([0.0, -1.0], 0, 2),
                ([1.0, 0.0], 1, 2),
                ([-1.0, 0.0], 1, 2),
            ],
            ShellKind::S3 => {
                let (a, b, c) = (
                    [1.0 / 6.0, 2.0 / 3.0],
                    [2.0 / 3.0, 1.0 / 6.0],
                    [1.0 / 6.0; 2],
                );
                let (d, e, f) = (
                    [THIRD + D, THIRD - 2.0 * D],
                    [THIRD - 2.0 * D, THIRD + D],
                    [THIRD + D; 2],
                );
                vec![
                    (a, 0, 2),
                    (a, 1, 2),
                    (b, 0, 2),
                    (b, 1, 2),
                    (c, 0, 2),
                    (c, 1, 2),
                    (d, 0, 2),
                    (e, 1, 2),
                    (f, 0, 2),
                    (f, 1, 2),
                ]
            }
            ShellKind::S6 => {
                let (a, b) = (0.5 - 0.5 * G2, 0.5 + 0.5 * G2);
                let mut points = vec![
                    ([a, 0.0], 0, 2),
                    ([b, 0.0], 0, 2),
                    ([0.0, a], 1, 2),
                    ([0.0, b], 1, 2),
                    ([b, a], 0, 2),
                    ([b, a], 1, 2),
                    ([a, b], 0, 2),
                    ([a, b], 1, 2),
                ];
                for (rs, _) in surface::rule(self.kind) {
                    points.extend([(*rs, 0, 2), (*rs, 1, 2)]);
                }
                points
            }
            ShellKind::S8 => {
                let mut points = Vec::with_capacity(28);
                for (turned, alpha, beta) in
                    [(false, 0, 2), (true, 1, 2), (false, 0, 0), (true, 1, 1)]
                {
                    for ri in [-G2, G2] {
                        for sj in [-G3, 0.0, G3] {
                            let rs = if turned { [sj, ri] } else { [ri, sj] };
                            points.push((rs, alpha, beta));
                        }
                    }
                }
                for ri in [-G2, G2] {
                    for sj in [-G2, G2] {
                        points.push(([ri, sj], 0, 1));
                    }
                }
                points
            }
        }
    }

    /// What the strains at level `t` share over the element: the covariant
    /// strains at its tying points ([`Self::tying_points`]) and S8's
    /// membrane correction ([`Self::membrane_correction`]).
    pub fn level(&self, t: f64) -> Level {
        let tied = self
            .tying_points()
            .iter()
            .map(|(rs, alpha, beta)| self.covariant(&self.point(*rs, t), *alpha, *beta))
            .collect();
        let mut level = Level {
            t,
            tied,
            correction: None,
        };
        level.correction = self.membrane_correction(&level);
        level
    }

    /// The transverse shear strains `e_rt`, `e_st` of the element at `rs`
    /// on `level`, interpolated from their values at the tying points.
    fn tied_shear(&self, level: &Level, [r, s]: [f64; 2]) -> [Row; 2] {
        let tied = &level.tied;
        match self.kind {
            ShellKind::S4 => [
                combine(&[(0.5 * (1.0 + s), &tied[0]), (0.5 * (1.0 - s), &tied[1])]),
                combine(&[(0.5 * (1.0 + r), &tied[2]), (0.5 * (1.0 - r), &tied[3])]),
            ],
            ShellKind::S6 => {
                // The tangential strains at the edges' Gauss points (e_qt =
                // e_st - e_rt on the edge from node 2 to node 3) and both
                // components' means over the element (exact for the
                // quadratic strains of a flat element at its three points).
                let qt = |i: usize| combine(&[(1.0, &tied[i + 1]), (-1.0, &tied[i])]);
                let third = 1.0 / 3.0;
                let mean = |c: usize| {
                    combine(&[
                        (third, &tied[8 + c]),
                        (third, &tied[10 + c]),
                        (third, &tied[12 + c]),
                    ])
                };
                let values = [
                    tied[0],
                    tied[1],
                    tied[2],
                    tied[3],
                    qt(4),
                    qt(6),
                    mean(0),
                    mean(1),
                ];
                let [wr, ws] = nedelec_weights([r, s]);
                let pairs =
                    |w: &[f64; 8]| -> Vec<(f64, &Row)> { w.iter().copied().zip(&values).collect() };
                [combine(&pairs(&wr)), combine(&pairs(&ws))]
            }
            ShellKind::S8 => [mitc9(r, s, &tied[0..6]), mitc9(s, r, &tied[6..12])],
            ShellKind::S3 => {
                // e_rt = 2/3 (e_rt^B - e_st^B / 2) + 1/3 (e_rt^C + e_st^C)
                // + c (3 s - 1) / 3, e_st = 2/3 (e_st^A - e_rt^A / 2) + 1/3
                // (e_rt^C + e_st^C) + c (1 - 3 r) / 3, with c = e_rt^F -
                // e_rt^D - e_st^F + e_st^E.
                const THIRD: f64 = 1.0 / 3.0;
                let [rt_a, st_a, rt_b, st_b, rt_c, st_c, rt_d, st_e, rt_f, st_f] =
                    [0, 1, 2, 3, 4, 5, 6, 7, 8, 9].map(|i| &tied[i]);
                let c = combine(&[(1.0, rt_f), (-1.0, rt_d), (-1.0, st_f), (1.0, st_e)]);
                let (cr, cs) = (THIRD * (3.0 * s - 1.0), THIRD * (1.0 - 3.0 * r));
                [
                    combine(&[
                        (2.0 / 3.0, rt_b),
                        (-THIRD, st_b),
                        (THIRD, rt_c),
                        (THIRD, st_c),
                        (cr, &c),
                    ]),
                    combine(&[
                        (2.0 / 3.0, st_a),
                        (-THIRD, rt_a),
                        (THIRD, rt_c),
                        (THIRD, st_c),
                        (cs, &c),
                    ]),
                ]
            }
        }
    }

    /// The in-plane covariant strains `e_rr`, `e_ss`, `e_rs` at `p` (the
    /// point `rs` on `level`): where they are, except for S8, whose strains
    /// are interpolated from tying points as in MITC9 (Bucalem and Bathe,
    /// 1993): `e_rr` from `r = +-1/sqrt(3)` times `s = 0, +-sqrt(3/5)`,
    /// `e_ss` the same turned, `e_rs` bilinear from the 2 x 2 Gauss points.
    /// Each tied component holds the strain a constant physical strain
    /// gives on a straight-edged element, and the tying frees curved
    /// elements of membrane locking; the patch tests need the correction
    /// of [`Self::membrane_correction`] besides.
    fn membrane(&self, p: &Point, level: &Level, [r, s]: [f64; 2]) -> [Row; 3] {
        if self.kind != ShellKind::S8 {
            return [
                self.covariant(p, 0, 0),
                self.covariant(p, 1, 1),
                self.covariant(p, 0, 1),
            ];
        }
        let tied = &level.tied;
        let lin = |x: f64| [0.5 * (1.0 - x / G2), 0.5 * (1.0 + x / G2)];
        let (lr, ls) = (lin(r), lin(s));
        let bilinear = [lr[0] * ls[0], lr[0] * ls[1], lr[1] * ls[0], lr[1] * ls[1]];
        let pairs: Vec<(f64, &Row)> = bilinear.into_iter().zip(&tied[24..28]).collect();
        [
            mitc9(r, s, &tied[12..18]),
            mitc9(s, r, &tied[18..24]),
            combine(&pairs),
        ]
    }

    /// The strains on the local frame at `rs` on `level`, as rows:
    /// `[e11, e22, g12, g13, g23]` (engineering shears), the transverse
    /// shears from the tied covariant strains; S8's membrane strains with
    /// the level's correction ([`Self::membrane_correction`]).
    pub fn local_strains(&self, rs: [f64; 2], level: &Level) -> (Point, [Row; 5]) {
        let p = self.point(rs, level.t);
        let [rt, st] = self.tied_shear(level, rs);
        let [rr, ss, rs_] = self.membrane(&p, level, rs);
        let mut rows = to_local(&p, &[rr, ss, rs_, rt, st]);
        if let Some(c) = &level.correction {
            let turned = turn(&c.rows, &c.frame, &p.frame);
            for (row, add) in rows.iter_mut().zip(&turned) {
                for (r, a) in row.iter_mut().zip(add) {
                    *r += a;
                }
            }
        }
        (p, rows)
    }

    /// S8's correction of its tied membrane strains at level `t` (`None`
    /// for the other kinds): the mean over the element of the compatible
    /// less the tied membrane strains, `[e_xx, e_yy, g_xy]` on the frame at
    /// the element's centre, added to the tied strains at every point. A
    /// constant stress then does the same work on the tied strains as on
    /// the compatible ones, so that the element's nodal forces balance
    /// between elements and it passes the patch tests on distorted meshes
    /// (MITC9's tying alone does not); a displacement the tying holds
    /// exactly (every linear field on a straight-edged element) has no
    /// correction, and the tying's freedom from membrane locking stays.
    fn membrane_correction(&self, level: &Level) -> Option<Correction> {
        if self.kind != ShellKind::S8 {
            return None;
        }
        let t = level.t;
        let frame = self.point([0.0, 0.0], t).frame;
        let mut sum = [ZERO_ROW; 3];
        let mut area = 0.0;
        for (rs, w) in surface::rule(self.kind) {
            let p = self.point(*rs, t);
            let tied = self.membrane(&p, level, *rs);
            let difference: [Row; 3] = std::array::from_fn(|c| {
                let compatible = match c {
                    0 => self.covariant(&p, 0, 0),
                    1 => self.covariant(&p, 1, 1),
                    _ => self.covariant(&p, 0, 1),
                };
                combine(&[(1.0, &compatible), (-1.0, &tied[c])])
            });
            let local = to_local(
                &p,
                &[
                    difference[0],
                    difference[1],
                    difference[2],
                    ZERO_ROW,
                    ZERO_ROW,
                ],
            );
            let turned = turn(&[local[0], local[1], local[2]], &p.frame, &frame);
            let wd = w * p.det_j;
            area += wd;
            for (s, r) in sum.iter_mut().zip(&turned) {
                for (si, ri) in s.iter_mut().zip(r) {
                    *si += wd * ri;
                }
            }
        }
        for s in &mut sum {
            for v in s.iter_mut() {
                *v /= area;
            }
        }
        Some(Correction { frame, rows: sum })
    }

    /// The drilling strain at the mid-surface point `rs`: the rotation
    /// about the normal, interpolated from the nodes, less the membrane's
    /// rotation `(du2/dx1 - du1/dx2) / 2`; zero under a rigid motion.
    fn drilling(&self, rs: [f64; 2]) -> (Point, Row) {
        let p = self.point(rs, 0.0);
        let mut row = ZERO_ROW;
        let [e1, e2, e3] = p.frame;
        for i in 0..self.nodes() {
            let f = self.factors(&p, i);
            let v = self.director[i];
            // dU/dx_k = sum_alpha dU/dalpha a[alpha][k] (alpha = r, s).
            for (fa, aa) in f.iter().zip(&p.a).take(2) {
                let (a1, a2) = (aa[0], aa[1]);
                let (c, d) = (fa[0], fa[1]);
                let (v2, v1) = (cross(v, e2), cross(v, e1));
                for k in 0..3 {
                    row[6 * i + k] -= 0.5 * c * (a1 * e2[k] - a2 * e1[k]);
                    row[6 * i + 3 + k] -= 0.5 * d * (a1 * v2[k] - a2 * v1[k]);
                }
            }
            for k in 0..3 {
                row[6 * i + 3 + k] += p.f[i] * e3[k];
            }
        }
        (p, row)
    }

    /// Stiffness (`6 n` square, symmetric) of the material `(E, nu)`:
    /// membrane, bending and tied transverse shear over the in-plane rule
    /// and two points through the thickness, plus the drilling penalty.
    pub fn stiffness(&self, youngs_modulus: f64, poisson_ratio: f64) -> Mat<f64> {
        let nd = 6 * self.nodes();
        let d = Elasticity::new(youngs_modulus, poisson_ratio);
        let mut k = vec![0.0; nd * nd];
        let levels = THICKNESS_RULE.map(|(t, _)| self.level(t));
        // The strains `which` (of `[e11, e22, g12, g13, g23]`) by `rule`.
        let mut integrate = |rule: &[([f64; 2], f64)], which: std::ops::Range<usize>| {
            for (rs, w) in rule {
                for ((_, wt), level) in THICKNESS_RULE.iter().zip(&levels) {
                    let (p, mut rows) = self.local_strains(*rs, level);
                    for (i, row) in rows.iter_mut().enumerate() {
                        if !which.contains(&i) {
                            *row = ZERO_ROW;
                        }
                    }
                    let stressed = d.apply(&rows, nd);
                    add_products(&mut k, nd, &rows, &stressed, w * wt * p.det_j);
                }
            }
        };
        if self.kind == ShellKind::S6 {
            // Membrane and bending by the reduced rule, the tied shear by
            // the full one.
            integrate(surface::rule(self.kind), 0..3);
            integrate(surface::full_rule(self.kind), 3..5);
        } else {
            integrate(surface::rule(self.kind), 0..5);
        }
        for (rs, w) in surface::full_rule(self.kind) {
            let (p, row) = self.drilling(*rs);
            let area = norm(cross(p.g[0], p.g[1]));
            let penalty = DRILLING * d.shear * self.thickness * w * area;
            add_products(&mut k, nd, &[row], &[row], penalty);
        }
        symmetric(nd, &k)
    }

    /// The mass as rigid slices through the thickness, one per point of
    /// the in-plane rule (see [`super::Shell`]'s mass docs).
    pub fn mass_points(&self, density: f64) -> Vec<MassPoint> {
        let nd = 6 * self.nodes();
        let a = self.thickness;
        surface::full_rule(self.kind)
            .iter()
            .map(|(rs, w)| {
                let p = self.point(*rs, 0.0);
                let mass = density * a * w * norm(cross(p.g[0], p.g[1]));
                let n = p.frame[2];
                let j = mass * a * a / 12.0;
                let inertia = std::array::from_fn(|i| {
                    std::array::from_fn(|k| {
                        let delta = if i == k { 1.0 } else { 0.0 };
                        j * (delta - n[i] * n[k])
                    })
                });
                let mut translation = Mat::<f64>::zeros(3, nd);
                let mut rotation = Mat::<f64>::zeros(3, nd);
                let mut position = self.position(*rs);
                for i in 0..self.nodes() {
                    let (ni, fi, v) = (p.n[i], p.f[i], self.director[i]);
                    for c in 0..3 {
                        position[c] += ni * p.h * v[c];
                        translation[(c, 6 * i + c)] = ni;
                        rotation[(c, 6 * i + 3 + c)] = fi;
                    }
                    // theta x (h V) = -(h V)~ theta.
                    let hv = v.map(|x| p.h * fi * x);
                    let skew = [
                        [0.0, -hv[2], hv[1]],
                        [hv[2], 0.0, -hv[0]],
                        [-hv[1], hv[0], 0.0],
                    ];
                    for (r, row) in skew.iter().enumerate() {
                        for (c, value) in row.iter().enumerate() {
                            translation[(r, 6 * i + 3 + c)] -= value;
                        }
                    }
                }
                MassPoint {
                    position,
                    mass,
                    inertia,
                    translation,
                    rotation,
                }
            })
            .collect()
    }

    /// Stresses (Pa, global Voigt `[sxx, syy, szz, sxy, syz, szx]`) at the
    /// nodes, on the bottom (`t = -1`), middle and top surfaces, of
    /// `columns` displacement fields one after the other in `u_e`: entry
    /// `(3 j + layer) n + a` (`n` the element's nodes; `u_e` over the
    /// interpolation nodes' DOFs, S8's centre included). In-plane stresses
    /// from the strains at the points of [`surface::stress_rule`],
    /// extrapolated to the nodes; transverse shear
    /// parabolic through the thickness, zero on the faces and 3/2 of the
    /// mean on the middle surface.
    pub fn stresses(
        &self,
        youngs_modulus: f64,
        poisson_ratio: f64,
        u_e: &[f64],
        columns: usize,
    ) -> Vec<[f64; 6]> {
        let nn = self.kind.node_count();
        let nd = 6 * self.nodes();
        let d = Elasticity::new(youngs_modulus, poisson_ratio);
        let rule = surface::stress_rule(self.kind);
        let weights = surface::extrapolation(self.kind);
        let layers = [-1.0, 0.0, 1.0];
        // The strain rows and frames at each layer and point.
        let at: Vec<Vec<(Point, [Row; 5])>> = layers
            .iter()
            .map(|&t| {
                let level = self.level(t);
                rule.iter()
                    .map(|(rs, _)| self.local_strains(*rs, &level))
                    .collect()
            })
            .collect();
        let mut out = Vec::with_capacity(3 * nn * columns);
        for u in u_e.chunks_exact(nd).take(columns) {
            let strain = |rows: &[Row; 5]| -> [f64; 5] {
                rows.map(|row| row[..nd].iter().zip(u).map(|(b, x)| b * x).sum())
            };
            // Mean transverse shear stresses at each point.
            let shear: Vec<[f64; 2]> = at[1]
                .iter()
                .map(|(_, rows)| {
                    let e = strain(rows);
                    [d.shear_stiffness * e[3], d.shear_stiffness * e[4]]
                })
                .collect();
            for (layer, points) in at.iter().enumerate() {
                let factor = if layer == 1 { 1.5 } else { 0.0 };
                let global: Vec<[f64; 6]> = points
                    .iter()
                    .zip(&shear)
                    .map(|((p, rows), tau)| {
                        let e = strain(rows);
                        let s11 = d.plane * (e[0] + d.nu * e[1]);
                        let s22 = d.plane * (e[1] + d.nu * e[0]);
                        let s12 = d.shear * e[2];
                        let local = [
                            [s11, s12, factor * tau[0]],
                            [s12, s22, factor * tau[1]],
                            [factor * tau[0], factor * tau[1], 0.0],
                        ];
                        to_global(&local, &p.frame)
                    })
                    .collect();
                out.extend(weights.iter().take(nn).map(|w| {
                    let mut s = [0.0; 6];
                    for (wp, sp) in w.iter().zip(&global) {
                        for (si, v) in s.iter_mut().zip(sp) {
                            *si += wp * v;
                        }
                    }
                    s
                }));
            }
        }
        out
    }
}

/// The covariant strains one level `t` of the thickness shares over the
/// element ([`Geometry::level`]).
pub(super) struct Level {
    t: f64,
    /// The strain rows at the tying points, in the order of
    /// [`Geometry::tying_points`].
    tied: Vec<Row>,
    correction: Option<Correction>,
}

/// S8's membrane correction at one level: rows of `[e_xx, e_yy, g_xy]` on
/// `frame`'s in-plane axes.
pub(super) struct Correction {
    frame: [[f64; 3]; 3],
    rows: [Row; 3],
}

/// The local strains `[e11, e22, g12, g13, g23]` (engineering shears) at
/// `p` of the covariant strains `cov = [e_rr, e_ss, e_rs, e_rt, e_st]`.
fn to_local(p: &Point, cov: &[Row; 5]) -> [Row; 5] {
    let a = &p.a;
    let pairs = [
        (0, 0, 1.0),
        (1, 1, 1.0),
        (0, 1, 2.0),
        (0, 2, 2.0),
        (1, 2, 2.0),
    ];
    pairs.map(|(k, l, factor)| {
        let coefficients = [
            a[0][k] * a[0][l],
            a[1][k] * a[1][l],
            a[0][k] * a[1][l] + a[1][k] * a[0][l],
            a[0][k] * a[2][l] + a[2][k] * a[0][l],
            a[1][k] * a[2][l] + a[2][k] * a[1][l],
        ];
        let terms: Vec<(f64, &Row)> = coefficients
            .iter()
            .zip(cov)
            .map(|(c, row)| (factor * c, row))
            .collect();
        combine(&terms)
    })
}

/// In-plane strains `[e11, e22, g12]` on the first two axes of `from`,
/// turned onto those of `to`: `e'_ij = (b_i . a_k)(b_j . a_l) e_kl`.
fn turn(rows: &[Row; 3], from: &[[f64; 3]; 3], to: &[[f64; 3]; 3]) -> [Row; 3] {
    let c = |i: usize, k: usize| dot(to[i], from[k]);
    // The tensor components e_kl as combinations of the rows.
    let tensor = |k: usize, l: usize| -> [(usize, f64); 1] {
        match (k, l) {
            (0, 0) => [(0, 1.0)],
            (1, 1) => [(1, 1.0)],
            _ => [(2, 0.5)],
        }
    };
    let component = |i: usize, j: usize| -> Row {
        let mut terms = Vec::with_capacity(4);
        for k in 0..2 {
            for l in 0..2 {
                for (row, f) in tensor(k, l) {
                    terms.push((c(i, k) * c(j, l) * f, &rows[row]));
                }
            }
        }
        combine(&terms)
    };
    let e01 = component(0, 1);
    [component(0, 0), component(1, 1), combine(&[(2.0, &e01)])]
}

/// MITC9's interpolation of a covariant strain tied along `r` (`e_rr`,
/// `e_rt`): from its values `rows` at the points `r = +-1/sqrt(3)` times
/// `s = -sqrt(3/5), 0, sqrt(3/5)` (in that order, `r` outer), linear in
/// `r` and quadratic in `s` between them. With the arguments turned (`s`,
/// `r`, and the rows at the turned points), the same for the components
/// tied along `s`.
fn mitc9(r: f64, s: f64, rows: &[Row]) -> Row {
    let lin = [0.5 * (1.0 - r / G2), 0.5 * (1.0 + r / G2)];
    let b2 = G3 * G3;
    let quad = [
        s * (s - G3) / (2.0 * b2),
        1.0 - s * s / b2,
        s * (s + G3) / (2.0 * b2),
    ];
    let weights = lin.iter().flat_map(|l| quad.iter().map(move |q| l * q));
    let pairs: Vec<(f64, &Row)> = weights.zip(rows).collect();
    combine(&pairs)
}

/// S6's assumed transverse shear field (in the manner of MITC6: Lee and
/// Bathe, 2004): the covariant shears `(e_rt, e_st) = (a1 + b1 r + c1 s + s
/// (d r + e s), a2 + b2 r + c2 s - r (d r + e s))`, Nedelec's space of the
/// second order, fixed by its natural degrees of freedom: the tangential
/// strain at the two Gauss points of each edge (its moments against the
/// edge's linear functions) and the mean of each component over the
/// element. The interpolation holds every field of the space exactly, the
/// gradient of each quadratic deflection among them, so that a thin
/// plate's bending without shear stays representable and it does not
/// lock. Returns
/// the weights of the eight values, in the order of [`Geometry::tied_shear`],
/// in `e_rt` and `e_st` at `rs`.
fn nedelec_weights([r, s]: [f64; 2]) -> [[f64; 8]; 2] {
    use std::sync::OnceLock;
    // The basis at a point: its (e_rt, e_st) components.
    fn basis(r: f64, s: f64) -> [[f64; 2]; 8] {
        [
            [1.0, 0.0],
            [r, 0.0],
            [s, 0.0],
            [0.0, 1.0],
            [0.0, r],
            [0.0, s],
            [s * r, -r * r],
            [s * s, -r * s],
        ]
    }
    static INVERSE: OnceLock<[[f64; 8]; 8]> = OnceLock::new();
    let inverse = INVERSE.get_or_init(|| {
        let (a, b) = (0.5 - 0.5 * G2, 0.5 + 0.5 * G2);
        // Basis field k's strain in the direction d = (rt, st) at (r, s),
        // and its mean over the element.
        let at = |[r, s]: [f64; 2], d: [f64; 2], k: usize| {
            let phi = basis(r, s)[k];
            d[0] * phi[0] + d[1] * phi[1]
        };
        let mean = |d: [f64; 2], k: usize| {
            let rule = surface::rule(ShellKind::S6);
            rule.iter().map(|(rs, _)| at(*rs, d, k)).sum::<f64>() / rule.len() as f64
        };
        let (rt, st, qt) = ([1.0, 0.0], [0.0, 1.0], [-1.0, 1.0]);
        let m = faer::Mat::from_fn(8, 8, |i, k| match i {
            0 => at([a, 0.0], rt, k),
            1 => at([b, 0.0], rt, k),
            2 => at([0.0, a], st, k),
            3 => at([0.0, b], st, k),
            4 => at([b, a], qt, k),
            5 => at([a, b], qt, k),
            6 => mean(rt, k),
            _ => mean(st, k),
        });
        let inv = faer::linalg::solvers::DenseSolveCore::inverse(&m.full_piv_lu());
        std::array::from_fn(|k| std::array::from_fn(|i| inv[(k, i)]))
    });
    let phi = basis(r, s);
    std::array::from_fn(|c| {
        std::array::from_fn(|i| (0..8).map(|k| phi[k][c] * inverse[k][i]).sum())
    })
}

/// The plane-stress elasticity of the shell's layers and its transverse
/// shear stiffness.
struct Elasticity {
    /// `E / (1 - nu^2)`.
    plane: f64,
    nu: f64,
    /// `G`.
    shear: f64,
    /// `k G` (k the shear correction factor).
    shear_stiffness: f64,
}

impl Elasticity {
    fn new(e: f64, nu: f64) -> Self {
        let shear = e / (2.0 * (1.0 + nu));
        Self {
            plane: e / (1.0 - nu * nu),
            nu,
            shear,
            shear_stiffness: SHEAR_FACTOR * shear,
        }
    }

    /// `D B` for the strain rows `[e11, e22, g12, g13, g23]`.
    fn apply(&self, rows: &[Row; 5], nd: usize) -> [Row; 5] {
        let mut out = [ZERO_ROW; 5];
        for j in 0..nd {
            let (a, b) = (rows[0][j], rows[1][j]);
            out[0][j] = self.plane * (a + self.nu * b);
            out[1][j] = self.plane * (b + self.nu * a);
            out[2][j] = self.shear * rows[2][j];
            out[3][j] = self.shear_stiffness * rows[3][j];
            out[4][j] = self.shear_stiffness * rows[4][j];
        }
        out
    }
}

/// `sum_k factor_k row_k`.
fn combine(terms: &[(f64, &Row)]) -> Row {
    let mut out = ZERO_ROW;
    for (f, row) in terms {
        for (o, v) in out.iter_mut().zip(row.iter()) {
            *o += f * v;
        }
    }
    out
}

/// Adds `w sum_k left_k^T right_k` to the upper triangle of `k` (row-major,
/// `nd` square).
fn add_products(k: &mut [f64], nd: usize, left: &[Row], right: &[Row], w: f64) {
    for (l, r) in left.iter().zip(right) {
        for i in 0..nd {
            let li = w * l[i];
            if li == 0.0 {
                continue;
            }
            for j in i..nd {
                k[i * nd + j] += li * r[j];
            }
        }
    }
}

/// The symmetric matrix of an upper triangle (row-major).
fn symmetric(nd: usize, upper: &[f64]) -> Mat<f64> {
    Mat::from_fn(nd, nd, |r, c| upper[r.min(c) * nd + r.max(c)])
}

/// `sigma_global = R sigma_local R^T`, `R` the frame's vectors as columns,
/// in Voigt order.
fn to_global(local: &[[f64; 3]; 3], frame: &[[f64; 3]; 3]) -> [f64; 6] {
    let s = |i: usize, j: usize| -> f64 {
        let mut v = 0.0;
        for (k, ek) in frame.iter().enumerate() {
            for (l, el) in frame.iter().enumerate() {
                v += ek[i] * local[k][l] * el[j];
            }
        }
        v
    };
    [s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(2, 0)]
}

pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

pub(super) fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = norm(a);
    a.map(|v| v / l)
}

/// The mass matrix the points hold: `sum_g m_g U^T U + Theta^T J_g Theta`
/// (summed entry by entry on the upper triangle: the matrices are small).
pub(super) fn mass_matrix(points: &[MassPoint], nd: usize) -> Mat<f64> {
    let mut upper = vec![0.0; nd * nd];
    for p in points {
        let (u, theta) = (&p.translation, &p.rotation);
        // J Theta, 3 x nd.
        let j_theta: Vec<[f64; 3]> = (0..nd)
            .map(|c| std::array::from_fn(|r| (0..3).map(|k| p.inertia[r][k] * theta[(k, c)]).sum()))
            .collect();
        for i in 0..nd {
            let (ui, ti) = (
                [u[(0, i)], u[(1, i)], u[(2, i)]],
                [theta[(0, i)], theta[(1, i)], theta[(2, i)]],
            );
            if ui.iter().chain(&ti).all(|v| *v == 0.0) {
                continue;
            }
            for j in i..nd {
                let mut v = 0.0;
                for k in 0..3 {
                    v += p.mass * ui[k] * u[(k, j)] + ti[k] * j_theta[j][k];
                }
                upper[i * nd + j] += v;
            }
        }
    }
    symmetric(nd, &upper)
}
