//! Mesh tying (`*TIE`): each slave node follows the point of the master
//! surface it lies on, `u_s = sum_i N_i(xi) u_i` over the master face's
//! nodes (translations), with `xi` the slave node's projection onto the face.
//! The equations are eliminated exactly like every [`Equation`]: the slave
//! translations leave the DOF map.
//!
//! Master faces are solid element faces in Abaqus/CalculiX numbering
//! ([`solid_face`]): 3-node and 6-node triangles, 4-node and 8-node
//! quadrilaterals, interpolated with their own shape functions. A slave node
//! that is also a node of a master face is already joined and is left
//! alone. With `adjust`, slave nodes are moved onto the master surface
//! before the model is built (CalculiX's ADJUST=YES).

use crate::constraint::Equation;
use crate::dof::{Dof, DofKind};
use crate::element::solid::Solid;
use crate::element::SolidKind;
use crate::model::NodeId;
use crate::FemError;
use std::collections::{HashMap, HashSet};

/// Local node indices (0-based) of face `face` (1-based, S1..) of a solid,
/// corners first in the face's order, then its mid-side nodes.
pub fn solid_face(kind: SolidKind, face: usize) -> Option<&'static [usize]> {
    const HEX: [&[usize]; 6] = [
        &[0, 1, 2, 3],
        &[4, 7, 6, 5],
        &[0, 4, 5, 1],
        &[1, 5, 6, 2],
        &[2, 6, 7, 3],
        &[3, 7, 4, 0],
    ];
    const HEX20: [&[usize]; 6] = [
        &[0, 1, 2, 3, 8, 9, 10, 11],
        &[4, 7, 6, 5, 15, 14, 13, 12],
        &[0, 4, 5, 1, 16, 12, 17, 8],
        &[1, 5, 6, 2, 17, 13, 18, 9],
        &[2, 6, 7, 3, 18, 14, 19, 10],
        &[3, 7, 4, 0, 19, 15, 16, 11],
    ];
    const TET: [&[usize]; 4] = [&[0, 1, 2], &[0, 3, 1], &[1, 3, 2], &[2, 3, 0]];
    const TET10: [&[usize]; 4] = [
        &[0, 1, 2, 4, 5, 6],
        &[0, 3, 1, 7, 8, 4],
        &[1, 3, 2, 8, 9, 5],
        &[2, 3, 0, 9, 7, 6],
    ];
    const WEDGE: [&[usize]; 5] = [
        &[0, 1, 2],
        &[3, 5, 4],
        &[0, 3, 4, 1],
        &[1, 4, 5, 2],
        &[2, 5, 3, 0],
    ];
    const WEDGE15: [&[usize]; 5] = [
        &[0, 1, 2, 6, 7, 8],
        &[3, 5, 4, 11, 10, 9],
        &[0, 3, 4, 1, 12, 9, 13, 6],
        &[1, 4, 5, 2, 13, 10, 14, 7],
        &[2, 5, 3, 0, 14, 11, 12, 8],
    ];
    let table: &[&'static [usize]] = match kind {
        SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => &HEX,
        SolidKind::C3D20 | SolidKind::C3D20R => &HEX20,
        SolidKind::C3D4 => &TET,
        SolidKind::C3D10 => &TET10,
        SolidKind::C3D6 => &WEDGE,
        SolidKind::C3D15 => &WEDGE15,
    };
    face.checked_sub(1).and_then(|f| table.get(f).copied())
}

/// The exterior faces of a set of solids: every face ([`solid_face`]) that
/// no other solid of the set shares (the same nodes in any order), in the
/// order of the solids and their faces. Faces shared with elements outside
/// the set are exterior to it. Cost: linear in the faces.
pub fn exterior_faces<'a>(solids: impl IntoIterator<Item = &'a Solid>) -> Vec<Face> {
    let mut faces: Vec<Face> = Vec::new();
    let mut count: HashMap<Vec<NodeId>, usize> = HashMap::new();
    for solid in solids {
        for face in (1..).map_while(|f| solid_face(solid.kind, f)) {
            let nodes: Vec<NodeId> = face.iter().map(|&i| solid.nodes[i]).collect();
            let mut key = nodes.clone();
            key.sort_unstable();
            *count.entry(key).or_default() += 1;
            faces.push(Face { nodes });
        }
    }
    faces.retain(|f| {
        let mut key = f.nodes.clone();
        key.sort_unstable();
        count[&key] == 1
    });
    faces
}

/// A master face: its nodes in [`solid_face`] order (3, 4, 6 or 8).
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    pub nodes: Vec<NodeId>,
}

/// A `*TIE` of slave nodes to master faces.
#[derive(Clone, Debug, PartialEq)]
pub struct Tie {
    pub name: String,
    pub slaves: Vec<NodeId>,
    pub master: Vec<Face>,
    /// Largest distance (m) of a slave node from the master surface; `None`:
    /// 2.5 % of the master faces' mean size.
    pub tolerance: Option<f64>,
    /// Move slave nodes onto the master surface.
    pub adjust: bool,
}

/// What a tie makes: its equations and, with `adjust`, the slave nodes'
/// new positions.
#[derive(Clone, Debug, Default)]
pub struct TieEquations {
    pub equations: Vec<Equation>,
    pub moved: Vec<(NodeId, [f64; 3])>,
}

impl Tie {
    /// The equations of the tie from the node positions `coords`. An error
    /// names the slave nodes that find no master face within the tolerance,
    /// or a master face with an undefined node.
    pub fn equations(
        &self,
        coords: &dyn Fn(NodeId) -> Option<[f64; 3]>,
    ) -> Result<TieEquations, FemError> {
        let bad = |reason: String| FemError::InvalidConstraint {
            name: format!("tie '{}'", self.name),
            reason,
        };
        if self.master.is_empty() {
            return Err(bad("its master surface has no faces".into()));
        }
        let mut faces = Vec::with_capacity(self.master.len());
        for f in &self.master {
            let mut x = Vec::with_capacity(f.nodes.len());
            for n in &f.nodes {
                x.push(coords(*n).ok_or_else(|| bad(format!("master node {n} does not exist")))?);
            }
            let shape = FaceShape::of(x.len())
                .ok_or_else(|| bad(format!("a master face of {} nodes", x.len())))?;
            faces.push((shape, x));
        }
        let size = faces.iter().map(|(_, x)| face_size(x)).sum::<f64>() / faces.len() as f64;
        let tolerance = self.tolerance.unwrap_or(0.025 * size);
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(bad(format!("position tolerance {tolerance}")));
        }
        let grid = Grid::new(&faces, size.max(f64::MIN_POSITIVE), tolerance);
        let on_master: HashSet<NodeId> = self
            .master
            .iter()
            .flat_map(|f| f.nodes.iter().copied())
            .collect();
        let mut out = TieEquations::default();
        let mut lost = Vec::new();
        let mut seen = HashSet::new();
        for &s in &self.slaves {
            if on_master.contains(&s) || !seen.insert(s) {
                continue;
            }
            let p = coords(s).ok_or_else(|| bad(format!("slave node {s} does not exist")))?;
            // The nearest projection; among equally near ones, the face
            // that holds it inside.
            let mut best: Option<(f64, f64, usize, [f64; 2])> = None;
            for fi in grid.candidates(p) {
                let (shape, x) = &faces[fi];
                let (xi, point) = shape.project(x, p);
                let distance = norm(sub(point, p));
                let outside = shape.outside(xi);
                let better = match best {
                    None => true,
                    Some((d, o, _, _)) => {
                        distance < d - 1e-12 * size || (distance <= d + 1e-12 * size && outside < o)
                    }
                };
                if better {
                    best = Some((distance, outside, fi, xi));
                }
            }
            match best {
                Some((distance, outside, fi, xi)) if distance <= tolerance && outside <= 1e-6 => {
                    let (shape, x) = &faces[fi];
                    let n = shape.functions(xi);
                    for k in [DofKind::Ux, DofKind::Uy, DofKind::Uz] {
                        let mut terms = vec![(Dof::new(s, k), 1.0)];
                        for (node, ni) in self.master[fi].nodes.iter().zip(&n) {
                            if *ni != 0.0 {
                                terms.push((Dof::new(*node, k), -ni));
                            }
                        }
                        out.equations.push(Equation {
                            name: format!("tie '{}'", self.name),
                            terms,
                        });
                    }
                    if self.adjust && distance > 0.0 {
                        out.moved.push((s, shape.point(x, xi)));
                    }
                }
                _ => lost.push(s),
            }
        }
        if !lost.is_empty() {
            let shown: Vec<String> = lost.iter().take(10).map(|n| n.to_string()).collect();
            return Err(bad(format!(
                "{} slave node(s) find no master face within the position tolerance {tolerance:e} m: \
                 node(s) {}{}",
                lost.len(),
                shown.join(", "),
                if lost.len() > 10 { ", ..." } else { "" }
            )));
        }
        Ok(out)
    }
}

/// The shape of a master face.
#[derive(Copy, Clone, Debug)]
enum FaceShape {
    Tri3,
    Tri6,
    Quad4,
    Quad8,
}

impl FaceShape {
    fn of(nodes: usize) -> Option<Self> {
        match nodes {
            3 => Some(Self::Tri3),
            6 => Some(Self::Tri6),
            4 => Some(Self::Quad4),
            8 => Some(Self::Quad8),
            _ => None,
        }
    }

    fn triangle(self) -> bool {
        matches!(self, Self::Tri3 | Self::Tri6)
    }

    /// Shape functions at `xi` (triangles: area coordinates `xi, eta`,
    /// quadrilaterals: `[-1, 1]^2`).
    fn functions(self, [r, s]: [f64; 2]) -> Vec<f64> {
        match self {
            Self::Tri3 => vec![1.0 - r - s, r, s],
            Self::Tri6 => {
                let t = 1.0 - r - s;
                vec![
                    t * (2.0 * t - 1.0),
                    r * (2.0 * r - 1.0),
                    s * (2.0 * s - 1.0),
                    4.0 * t * r,
                    4.0 * r * s,
                    4.0 * s * t,
                ]
            }
            Self::Quad4 => [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .iter()
                .map(|(a, b)| 0.25 * (1.0 + a * r) * (1.0 + b * s))
                .collect(),
            Self::Quad8 => {
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
                let mut n: Vec<f64> = corners
                    .iter()
                    .map(|(a, b)| 0.25 * (1.0 + a * r) * (1.0 + b * s) * (a * r + b * s - 1.0))
                    .collect();
                n.push(0.5 * (1.0 - r * r) * (1.0 - s));
                n.push(0.5 * (1.0 + r) * (1.0 - s * s));
                n.push(0.5 * (1.0 - r * r) * (1.0 + s));
                n.push(0.5 * (1.0 - r) * (1.0 - s * s));
                n
            }
        }
    }

    /// The point of the face at `xi`.
    fn point(self, x: &[[f64; 3]], xi: [f64; 2]) -> [f64; 3] {
        let n = self.functions(xi);
        let mut p = [0.0; 3];
        for (ni, xi) in n.iter().zip(x) {
            for k in 0..3 {
                p[k] += ni * xi[k];
            }
        }
        p
    }

    /// How far `xi` lies outside the parameter domain (0 inside).
    fn outside(self, [r, s]: [f64; 2]) -> f64 {
        if self.triangle() {
            (-r).max(-s).max(r + s - 1.0).max(0.0)
        } else {
            (r.abs() - 1.0).max(s.abs() - 1.0).max(0.0)
        }
    }

    /// The nearest point of the face's surface (extended beyond its edges)
    /// to `p`, by Gauss-Newton from the face's centre; falls back to the
    /// domain's nearest point when the iteration leaves it far behind.
    fn project(self, x: &[[f64; 3]], p: [f64; 3]) -> ([f64; 2], [f64; 3]) {
        let mut xi = if self.triangle() {
            [1.0 / 3.0; 2]
        } else {
            [0.0; 2]
        };
        let h = 1e-7;
        for _ in 0..30 {
            let q = self.point(x, xi);
            let r = sub(p, q);
            // Tangents by central differences of the face map (exact for
            // the bilinear and quadratic maps up to round-off of h^2).
            let d = |k: usize| {
                let (mut a, mut b) = (xi, xi);
                a[k] += h;
                b[k] -= h;
                let (pa, pb) = (self.point(x, a), self.point(x, b));
                [
                    (pa[0] - pb[0]) / (2.0 * h),
                    (pa[1] - pb[1]) / (2.0 * h),
                    (pa[2] - pb[2]) / (2.0 * h),
                ]
            };
            let (t1, t2) = (d(0), d(1));
            let (a11, a12, a22) = (dot(t1, t1), dot(t1, t2), dot(t2, t2));
            let (b1, b2) = (dot(t1, r), dot(t2, r));
            let det = a11 * a22 - a12 * a12;
            if det.abs() <= 1e-300 {
                break;
            }
            let step = [(a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det];
            xi = [xi[0] + step[0], xi[1] + step[1]];
            // Keep the iteration near the face.
            xi = [xi[0].clamp(-3.0, 3.0), xi[1].clamp(-3.0, 3.0)];
            if step[0].abs() + step[1].abs() < 1e-13 {
                break;
            }
        }
        // Slightly outside: the nearest point of the domain instead.
        if self.outside(xi) > 0.0 {
            xi = if self.triangle() {
                clamp_triangle(xi)
            } else {
                [xi[0].clamp(-1.0, 1.0), xi[1].clamp(-1.0, 1.0)]
            };
        }
        (xi, self.point(x, xi))
    }
}

/// The nearest point of the unit triangle in parameter space.
fn clamp_triangle([r, s]: [f64; 2]) -> [f64; 2] {
    let (r, s) = (r.max(0.0), s.max(0.0));
    let excess = r + s - 1.0;
    if excess > 0.0 {
        let (r, s) = (r - excess / 2.0, s - excess / 2.0);
        [r.clamp(0.0, 1.0), s.clamp(0.0, 1.0)]
    } else {
        [r, s]
    }
}

/// The diameter of a face's bounding box.
fn face_size(x: &[[f64; 3]]) -> f64 {
    let (lo, hi) = bounds(x);
    norm(sub(hi, lo))
}

fn bounds(x: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in x {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Faces by the cells of a uniform grid their bounding boxes (grown by the
/// tolerance) touch: a slave node meets only the faces of its cell.
struct Grid {
    cell: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl Grid {
    fn new(faces: &[(FaceShape, Vec<[f64; 3]>)], size: f64, tolerance: f64) -> Self {
        let cell = size;
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        let index = |v: f64| (v / cell).floor() as i64;
        for (fi, (_, x)) in faces.iter().enumerate() {
            let (lo, hi) = bounds(x);
            let (lo, hi) = (lo.map(|v| v - tolerance), hi.map(|v| v + tolerance));
            let (a, b) = (lo.map(index), hi.map(index));
            // A face much larger than a cell (a mesh of very unequal faces)
            // spans many cells; bounded by the faces' own extent.
            for i in a[0]..=b[0] {
                for j in a[1]..=b[1] {
                    for k in a[2]..=b[2] {
                        cells.entry([i, j, k]).or_default().push(fi);
                    }
                }
            }
        }
        Self { cell, cells }
    }

    fn candidates(&self, p: [f64; 3]) -> impl Iterator<Item = usize> + '_ {
        let key = p.map(|v| (v / self.cell).floor() as i64);
        self.cells.get(&key).into_iter().flatten().copied()
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_interpolate_nodes() {
        let nodes: [(FaceShape, Vec<[f64; 2]>); 4] = [
            (FaceShape::Tri3, vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
            (
                FaceShape::Tri6,
                vec![
                    [0.0, 0.0],
                    [1.0, 0.0],
                    [0.0, 1.0],
                    [0.5, 0.0],
                    [0.5, 0.5],
                    [0.0, 0.5],
                ],
            ),
            (
                FaceShape::Quad4,
                vec![[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]],
            ),
            (
                FaceShape::Quad8,
                vec![
                    [-1.0, -1.0],
                    [1.0, -1.0],
                    [1.0, 1.0],
                    [-1.0, 1.0],
                    [0.0, -1.0],
                    [1.0, 0.0],
                    [0.0, 1.0],
                    [-1.0, 0.0],
                ],
            ),
        ];
        for (shape, at) in nodes {
            for (i, xi) in at.iter().enumerate() {
                let n = shape.functions(*xi);
                for (j, v) in n.iter().enumerate() {
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < 1e-15, "{shape:?} node {i}: N_{j} = {v}");
                }
            }
            let n = shape.functions([0.2, 0.3]);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
    }

    /// A slave node on a curved (quadratic) face projects onto it, and one
    /// off every face within the tolerance is named.
    #[test]
    fn slave_nodes_project_onto_master_faces() {
        // Quad8 face on z = 0.1 (x^2 - 1) bulge, x, y in [-1, 1].
        let z = |x: f64| 0.1 * (x * x - 1.0);
        let pts = [
            [-1.0, -1.0],
            [1.0, -1.0],
            [1.0, 1.0],
            [-1.0, 1.0],
            [0.0, -1.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [-1.0, 0.0],
        ];
        let mut coords: HashMap<NodeId, [f64; 3]> = pts
            .iter()
            .enumerate()
            .map(|(i, p)| (i as NodeId + 1, [p[0], p[1], z(p[0])]))
            .collect();
        coords.insert(100, [0.5, 0.25, z(0.5)]);
        coords.insert(101, [0.5, 0.25, z(0.5) + 0.5]);
        let tie = |slaves: Vec<NodeId>| Tie {
            name: "t".into(),
            slaves,
            master: vec![Face {
                nodes: (1..=8).collect(),
            }],
            tolerance: Some(1e-6),
            adjust: false,
        };
        let lookup = |n: NodeId| coords.get(&n).copied();
        let eqs = tie(vec![100]).equations(&lookup).unwrap().equations;
        assert_eq!(eqs.len(), 3);
        // The interpolation reproduces the slave's position: sum N_i x_i.
        let n: Vec<f64> = eqs[0].terms[1..].iter().map(|(_, c)| -c).collect();
        let mut x = [0.0; 3];
        for (ni, (dof, _)) in n.iter().zip(&eqs[0].terms[1..]) {
            let p = coords[&dof.node];
            for k in 0..3 {
                x[k] += ni * p[k];
            }
        }
        let want = coords[&100];
        assert!(norm(sub(x, want)) < 1e-12, "{x:?} vs {want:?}");
        let err = tie(vec![100, 101])
            .equations(&lookup)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("tie 't'") && err.contains("node(s) 101"),
            "{err}"
        );
    }

    /// Two bricks side by side have 10 exterior faces (the shared one is
    /// inside); a brick alone has its 6, a tetrahedron its 4.
    #[test]
    fn exterior_faces_leave_out_the_shared_ones() {
        use crate::element::solid::Solid;
        use crate::mesh::BrickBlock;
        use crate::{Element, Material};
        let material = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let block = BrickBlock {
            cells: [2, 1, 1],
            origin: [0.0; 3],
            size: [2.0, 1.0, 1.0],
        };
        let elements = block.elements(&material);
        let solids: Vec<&Solid> = elements
            .iter()
            .filter_map(|e| match e {
                Element::Solid(s) => Some(s),
                _ => None,
            })
            .collect();
        let both = exterior_faces(solids.iter().copied());
        assert_eq!(both.len(), 10);
        // The face x = 1 is shared: none of the exterior faces has all its
        // nodes there.
        let mid: Vec<NodeId> = (0..2)
            .flat_map(|j| (0..2).map(move |k| (j, k)))
            .map(|(j, k)| block.node([1, j, k]))
            .collect();
        assert!(both
            .iter()
            .all(|f| !f.nodes.iter().all(|n| mid.contains(n))));
        assert_eq!(exterior_faces(solids[..1].iter().copied()).len(), 6);
        let tet = Solid {
            id: 1,
            kind: SolidKind::C3D4,
            nodes: vec![1, 2, 3, 4],
            material,
        };
        assert_eq!(exterior_faces([&tet]).len(), 4);
    }
}
