//! MBDyn's modal FEM file (`.fem`): the flexible body that MBDyn's `modal`
//! joint reads, as ASCII "record groups" (MBDyn input manual, "FEM File
//! Format" of the modal element; the reader is `ReadModal` in MBDyn's
//! `struct/modal.cc`).
//!
//! ```text
//! ** comments                          (any line before a record group)
//! ** RECORD GROUP 1, HEADER
//! ** one comment line, which MBDyn skips
//! REV0 <nodes> <normal modes> 0 0 0
//! ** RECORD GROUP 2, FINITE ELEMENT NODE LIST     (labels, no blanks)
//! ** RECORD GROUP 3, INITIAL MODAL DISPLACEMENTS  (optional)
//! ** RECORD GROUP 4, INITIAL MODAL VELOCITIES     (optional)
//! ** RECORD GROUP 5/6/7, NODAL X/Y/Z COORDINATES
//! ** RECORD GROUP 8, MODE SHAPES   (per mode: a "**" line, then per node
//!                                   ux uy uz rx ry rz)
//! ** RECORD GROUP 9, MODAL MASS MATRIX
//! ** RECORD GROUP 10, MODAL STIFFNESS MATRIX
//! ** RECORD GROUP 11, DIAGONAL OF LUMPED MASS MATRIX  (optional; per node
//!                                   mx my mz Jx Jy Jz)
//! ** RECORD GROUP 12, RIGID BODY INERTIA MATRIX (optional; mass, centre of
//!                                   mass, inertia about the centre of mass)
//! ** RECORD GROUP 13, MODAL DAMPING MATRIX      (optional)
//! ** END OF FILE
//! ```
//!
//! MBDyn reads the numbers of a group as whitespace-separated tokens, so
//! line breaks inside a group are free; lines it reads whole (the comment
//! after group 1's title and the "**" line before each mode) must be there.
//! The content comes computed, as a [`ModalFem`] (the elastic modes of a
//! [`FloatingFrame`], the nodes, their lumped masses); field by field, with
//! the flexbody quantity behind each, in `docs/mbdyn.md`.

use crate::float_text::push_exp;
use crate::{write_atomically, ExportError};
use faer::Mat;
use flexbody_fem::{Dof, DofKind, DofMap, Model, NodeId, ValueTerms};
use flexbody_reduce::ffrf::{FloatingFrame, MassInvariants};
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

/// Numbers per line in the groups of vectors and matrices (MBDyn reads
/// tokens; short lines stay readable and under its line buffer).
const PER_LINE: usize = 6;

/// Node labels per line in group 2.
const LABELS_PER_LINE: usize = 10;

/// A node of the file.
#[derive(Clone, Debug, PartialEq)]
pub struct FemNode {
    /// Label: the FE model's node id.
    pub label: NodeId,
    /// Position in the FE model's frame (m).
    pub position: [f64; 3],
    /// How `ux, uy, uz, rx, ry, rz` follow from the rows of
    /// [`ModalFem::shapes`]: a row, a constraint's combination of rows (a
    /// DOF a coupling or tie eliminated), or zero (fixed, or absent).
    pub rows: [ValueTerms; 6],
}

impl FemNode {
    /// Node `label` at `position`, its DOFs the rows of `dofs` (the body's
    /// DOF map); zero where `dofs` has no such DOF.
    pub fn of_dofs(label: NodeId, position: [f64; 3], dofs: &DofMap) -> Self {
        Self {
            label,
            position,
            rows: DofKind::ALL.map(|kind| {
                dofs.index_of(Dof::new(label, kind))
                    .map_or(ValueTerms::Fixed, ValueTerms::Equation)
            }),
        }
    }

    /// Node `id` of the mesh `model` (whose equations are the body's
    /// DOFs): every DOF as [`Model::value_terms`] gives it, so that a node
    /// a coupling or tie made dependent moves with its constraint.
    pub fn of_model(model: &Model, id: NodeId) -> Self {
        Self {
            label: id,
            position: model.coords(id),
            rows: DofKind::ALL.map(|kind| model.value_terms(Dof::new(id, kind))),
        }
    }
}

/// Group 12: the body's rigid inertia as MBDyn reads it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RigidInertia {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass in the FE model's frame (m).
    pub center_of_mass: [f64; 3],
    /// Inertia tensor about the centre of mass, FE axes (kg m^2).
    pub inertia: [[f64; 3]; 3],
}

impl RigidInertia {
    /// From the floating frame's invariants: `c = mdCM / m` and
    /// `J_c = J_o - m (|c|^2 I - c c^T)` (parallel axes from the frame
    /// origin, about which [`MassInvariants::j`] is, to the centre of mass),
    /// symmetrised.
    pub fn from_invariants(inv: &MassInvariants) -> Self {
        let m = inv.mass;
        let c: [f64; 3] = std::array::from_fn(|i| inv.md_cm[i] / m);
        let c2 = c.iter().map(|x| x * x).sum::<f64>();
        let inertia = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let delta = if i == j { c2 } else { 0.0 };
                0.5 * (inv.j[i][j] + inv.j[j][i]) - m * (delta - c[i] * c[j])
            })
        });
        Self {
            mass: m,
            center_of_mass: c,
            inertia,
        }
    }
}

/// The content of an MBDyn modal FEM file (see the module docs).
#[derive(Clone, Debug)]
pub struct ModalFem {
    /// The nodes, in file order.
    pub nodes: Vec<FemNode>,
    /// `Phi` (m x nq): the elastic mode shapes over the body's DOFs.
    pub shapes: Mat<f64>,
    /// `Me = Phi^T M Phi` (nq x nq).
    pub mass: Mat<f64>,
    /// `Ke = Phi^T K Phi`.
    pub stiffness: Mat<f64>,
    /// `De = Phi^T D Phi`, if the body has damping (group 13).
    pub damping: Option<Mat<f64>>,
    /// Natural frequencies of the elastic modes (Hz), named in group 8.
    pub frequencies_hz: Vec<f64>,
    /// Lumped masses `mx my mz Jx Jy Jz` per node (group 11), if the body
    /// has a mesh to lump.
    pub lumped: Option<Vec<[f64; 6]>>,
    /// Group 12.
    pub inertia: RigidInertia,
}

impl ModalFem {
    /// The file of a body in its floating `frame`, at `nodes` (in file
    /// order, their rows over the body's DOFs), with their `lumped` masses
    /// (one per node) if known.
    pub fn new(frame: FloatingFrame, nodes: Vec<FemNode>, lumped: Option<Vec<[f64; 6]>>) -> Self {
        let FloatingFrame {
            elastic,
            invariants,
            ..
        } = frame;
        Self {
            nodes,
            shapes: elastic.shapes,
            mass: elastic.mass,
            stiffness: elastic.stiffness,
            damping: elastic.damping,
            frequencies_hz: elastic.frequencies_hz,
            lumped,
            inertia: RigidInertia::from_invariants(&invariants),
        }
    }

    /// Number of elastic modes.
    pub fn nq(&self) -> usize {
        self.mass.nrows()
    }

    /// Mode `k`'s six values at `node`: `ux uy uz rx ry rz` (zero where
    /// the node has no DOF).
    pub fn shape_at(&self, node: &FemNode, k: usize) -> [f64; 6] {
        std::array::from_fn(|d| match &node.rows[d] {
            ValueTerms::Equation(i) => self.shapes[(*i, k)],
            ValueTerms::Combination(terms) => {
                terms.iter().map(|(i, c)| c * self.shapes[(*i, k)]).sum()
            }
            ValueTerms::Fixed => 0.0,
        })
    }

    /// Writes the file's text to `out`; the mode shapes of a few modes at
    /// a time are formatted in parallel.
    pub fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        let (n, nq) = (self.nodes.len(), self.nq());
        let mut s = String::new();
        s.push_str("** MBDyn modal FEM file written by flexbody\n");
        let _ = writeln!(
            s,
            "** {n} nodes, {nq} elastic modes of the floating frame (mean axes); \
             the modal node carries the rigid-body motion"
        );
        s.push_str("** SI units: m, kg, s, N, rad; record groups: docs/mbdyn.md\n");
        if self.lumped.is_none() {
            s.push_str(
                "** no lumped masses (record group 11): the body has no mesh to lump; \
                 MBDyn builds no inertia invariants and takes the rigid inertia of \
                 group 12 alone\n",
            );
        }
        if self.damping.is_none() {
            s.push_str("** no modal damping (record group 13): the body has no damping\n");
        }
        s.push_str("**\n** RECORD GROUP 1, HEADER\n");
        s.push_str("**   REVISION, NODES, NORMAL, ATTACHMENT, CONSTRAINT, REJECTED MODES\n");
        let _ = writeln!(s, "REV0 {n} {nq} 0 0 0");
        s.push_str("**\n** RECORD GROUP 2, FINITE ELEMENT NODE LIST\n");
        for chunk in self.nodes.chunks(LABELS_PER_LINE) {
            let labels: Vec<String> = chunk.iter().map(|p| p.label.to_string()).collect();
            let _ = writeln!(s, "{}", labels.join(" "));
        }
        let zeros = vec![0.0; nq];
        for (group, name) in [(3, "DISPLACEMENTS"), (4, "VELOCITIES")] {
            let _ = writeln!(s, "**\n** RECORD GROUP {group}, INITIAL MODAL {name}");
            push_rows(&mut s, &zeros);
        }
        for (d, axis) in ["X", "Y", "Z"].into_iter().enumerate() {
            let _ = writeln!(s, "**\n** RECORD GROUP {}, NODAL {axis} COORDINATES", 5 + d);
            for p in &self.nodes {
                push_line(&mut s, &[p.position[d]]);
            }
        }
        s.push_str("**\n** RECORD GROUP 8, MODE SHAPES\n");
        out.write_all(s.as_bytes())?;
        self.write_shapes(out)?;
        let mut s = String::new();
        s.push_str("**\n** RECORD GROUP 9, MODAL MASS MATRIX\n");
        push_matrix(&mut s, &self.mass);
        s.push_str("**\n** RECORD GROUP 10, MODAL STIFFNESS MATRIX\n");
        push_matrix(&mut s, &self.stiffness);
        if let Some(lumped) = &self.lumped {
            s.push_str("**\n** RECORD GROUP 11, DIAGONAL OF LUMPED MASS MATRIX\n");
            for m in lumped {
                push_line(&mut s, m);
            }
        }
        let g = &self.inertia;
        s.push_str("**\n** RECORD GROUP 12, RIGID BODY INERTIA MATRIX\n");
        push_line(&mut s, &[g.mass]);
        push_line(&mut s, &g.center_of_mass);
        for row in &g.inertia {
            push_line(&mut s, row);
        }
        if let Some(d) = &self.damping {
            s.push_str("**\n** RECORD GROUP 13, MODAL DAMPING MATRIX\n");
            push_matrix(&mut s, d);
        }
        s.push_str("**\n** END OF FILE\n");
        out.write_all(s.as_bytes())
    }

    /// Group 8 after its title: per mode a comment line and one line per
    /// node.
    fn write_shapes(&self, out: &mut dyn Write) -> io::Result<()> {
        use rayon::prelude::*;
        let mode = |k: usize| {
            let mut s = String::with_capacity(self.nodes.len() * 6 * 24);
            let f = self.frequencies_hz.get(k).copied().unwrap_or(f64::NAN);
            let _ = writeln!(s, "**    NORMAL MODE SHAPE # {}, {f:.6e} Hz", k + 1);
            for p in &self.nodes {
                push_line(&mut s, &self.shape_at(p, k));
            }
            s
        };
        let modes: Vec<usize> = (0..self.nq()).collect();
        for batch in modes.chunks(rayon::current_num_threads().max(1)) {
            let texts: Vec<String> = batch.par_iter().map(|&k| mode(k)).collect();
            for text in texts {
                out.write_all(text.as_bytes())?;
            }
        }
        Ok(())
    }
}

/// `values` on one line, separated by blanks.
fn push_line(s: &mut String, values: &[f64]) {
    for (i, v) in values.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        push_exp(s, *v);
    }
    s.push('\n');
}

/// `values`, [`PER_LINE`] to a line.
fn push_rows(s: &mut String, values: &[f64]) {
    for chunk in values.chunks(PER_LINE) {
        push_line(s, chunk);
    }
}

/// `m` row by row, each row starting a line.
fn push_matrix(s: &mut String, m: &Mat<f64>) {
    for i in 0..m.nrows() {
        let row: Vec<f64> = (0..m.ncols()).map(|j| m[(i, j)]).collect();
        push_rows(s, &row);
    }
}

/// Writes `fem` to `path`, atomically; refuses non-finite values (and
/// values beyond what a reader takes back), naming the quantity.
pub fn write_mbdyn(fem: &ModalFem, path: &Path) -> Result<(), ExportError> {
    let positions = Mat::from_fn(fem.nodes.len(), 3, |p, d| fem.nodes[p].position[d]);
    crate::writable(positions.as_ref(), "the node coordinates")?;
    crate::writable(fem.shapes.as_ref(), "the mode shapes")?;
    crate::writable(fem.mass.as_ref(), "the modal mass matrix")?;
    crate::writable(fem.stiffness.as_ref(), "the modal stiffness matrix")?;
    if let Some(d) = &fem.damping {
        crate::writable(d.as_ref(), "the modal damping matrix")?;
    }
    if let Some(lumped) = &fem.lumped {
        if lumped.len() != fem.nodes.len() {
            return Err(ExportError::Model(format!(
                "{} lumped masses for {} nodes",
                lumped.len(),
                fem.nodes.len()
            )));
        }
        let l = Mat::from_fn(lumped.len(), 6, |p, d| lumped[p][d]);
        crate::writable(l.as_ref(), "the lumped masses")?;
    }
    let g = &fem.inertia;
    let inertia = Mat::from_fn(5, 3, |i, j| match i {
        0 => g.mass,
        1 => g.center_of_mass[j],
        _ => g.inertia[i - 2][j],
    });
    crate::writable(inertia.as_ref(), "the rigid-body inertia")?;
    write_atomically(path, |out| fem.write_text(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fem(lumped: bool) -> ModalFem {
        use ValueTerms::{Combination, Equation, Fixed};
        let nodes = vec![
            FemNode {
                label: 7,
                position: [0.0, 0.5, -1.0],
                rows: [Equation(0), Equation(1), Equation(2), Fixed, Fixed, Fixed],
            },
            FemNode {
                label: 12,
                position: [1.0, 0.0, 0.25],
                rows: [
                    Equation(3),
                    Combination(vec![(0, 0.5), (1, 0.5)]),
                    Fixed,
                    Fixed,
                    Fixed,
                    Equation(4),
                ],
            },
        ];
        ModalFem {
            nodes,
            shapes: Mat::from_fn(5, 2, |i, k| {
                (i + 1) as f64 * if k == 0 { 1.0 } else { -0.5 }
            }),
            mass: Mat::identity(2, 2),
            stiffness: Mat::from_fn(2, 2, |i, j| if i == j { 1e4 * (i + 1) as f64 } else { 0.0 }),
            damping: None,
            frequencies_hz: vec![15.9, 22.5],
            lumped: lumped.then(|| {
                vec![
                    [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
                    [2.0, 2.0, 2.0, 0.1, 0.1, 0.1],
                ]
            }),
            inertia: RigidInertia {
                mass: 3.0,
                center_of_mass: [0.5, 0.1, 0.0],
                inertia: [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]],
            },
        }
    }

    fn text(f: &ModalFem) -> String {
        let mut out = Vec::new();
        f.write_text(&mut out).unwrap();
        String::from_utf8(out).unwrap()
    }

    /// The lines MBDyn reads whole are where it reads them: a comment after
    /// group 1's title, a "**" line before each mode.
    #[test]
    fn the_header_and_the_mode_lines_are_where_mbdyn_reads_them() {
        let t = text(&fem(true));
        let lines: Vec<&str> = t.lines().collect();
        let at = |title: &str| lines.iter().position(|l| *l == title).unwrap();
        let g1 = at("** RECORD GROUP 1, HEADER");
        assert!(lines[g1 + 1].starts_with("**"));
        assert_eq!(lines[g1 + 2], "REV0 2 2 0 0 0");
        let g8 = at("** RECORD GROUP 8, MODE SHAPES");
        assert!(lines[g8 + 1].starts_with("**    NORMAL MODE SHAPE # 1"));
        assert_eq!(lines[g8 + 2], "1e0 2e0 3e0 0e0 0e0 0e0");
        // Node 12's uy is the mean of rows 0 and 1 (a constraint's).
        assert_eq!(lines[g8 + 3], "4e0 1.5e0 0e0 0e0 0e0 5e0");
        assert!(lines[g8 + 4].starts_with("**    NORMAL MODE SHAPE # 2"));
        assert_eq!(lines[g8 + 6], "-2e0 -7.5e-1 0e0 0e0 0e0 -2.5e0");
        assert_eq!(
            lines[at("** RECORD GROUP 2, FINITE ELEMENT NODE LIST") + 1],
            "7 12"
        );
        assert!(t.contains("** RECORD GROUP 11, DIAGONAL OF LUMPED MASS MATRIX\n1e0 1e0 1e0"));
        assert!(!t.contains("RECORD GROUP 13"));
        assert!(t.ends_with("** END OF FILE\n"));
        // No comment line may look like a record group's title.
        let titles = lines
            .iter()
            .filter(|l| l.starts_with("** RECORD GROUP "))
            .count();
        assert_eq!(titles, 12);
    }

    /// Without lumped masses group 11 is left out, and the file says so.
    #[test]
    fn without_lumped_masses_the_file_says_what_is_missing() {
        let t = text(&fem(false));
        assert!(!t.contains("RECORD GROUP 11"));
        assert!(t.contains("no lumped masses (record group 11)"));
    }

    /// Non-finite values are refused, naming the quantity; nothing is
    /// written.
    #[test]
    fn a_non_finite_value_is_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("b.fem");
        let mut f = fem(true);
        f.inertia.inertia[1][2] = f64::NAN;
        let e = write_mbdyn(&f, &path).unwrap_err().to_string();
        assert!(e.contains("the rigid-body inertia"), "{e}");
        assert!(!path.exists());
        let mut f = fem(true);
        f.shapes[(2, 1)] = f64::INFINITY;
        let e = write_mbdyn(&f, &path).unwrap_err().to_string();
        assert!(e.contains("the mode shapes"), "{e}");
        write_mbdyn(&fem(true), &path).unwrap();
        assert!(path.exists());
    }

    /// Group 12 is about the centre of mass: a point mass off the origin
    /// has no inertia about its own centre.
    #[test]
    fn the_rigid_inertia_is_moved_to_the_centre_of_mass() {
        let (m, c) = (2.0, [0.3, -0.4, 1.2]);
        let c2: f64 = c.iter().map(|x| x * x).sum();
        let j = std::array::from_fn(|i| {
            std::array::from_fn(|k| m * (if i == k { c2 } else { 0.0 } - c[i] * c[k]))
        });
        let inv = MassInvariants {
            mass: m,
            md_cm: c.map(|x| m * x),
            md_cm1: vec![],
            j,
            j1: vec![],
            ct: Mat::zeros(0, 3),
            cr: Mat::zeros(0, 3),
            cr1: vec![],
            me: Mat::zeros(0, 0),
            gr: Mat::zeros(3, 0),
            ge: Mat::zeros(0, 0),
            oe: Mat::zeros(0, 6),
            oe1: vec![],
        };
        let g = RigidInertia::from_invariants(&inv);
        assert_eq!(g.center_of_mass, c);
        for row in g.inertia {
            for v in row {
                assert!(v.abs() < 1e-15, "{:?}", g.inertia);
            }
        }
    }
}
