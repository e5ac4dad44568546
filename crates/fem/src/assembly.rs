//! Global assembly of stiffness K, mass M and damping D (report eq. 1)
//! into sparse matrices over the free DOFs. D is the model's global
//! Rayleigh damping `alpha M + beta K` plus the elements' damping matrices
//! (dashpots, and `alpha_e M_e + beta_e K_e` of materials with Rayleigh
//! damping), assembled as K and M are.
//!
//! The pattern is built before the values: the node graph of the elements
//! gives every column's rows once, sorted. Elements are then coloured so that
//! no two elements of a colour share a node, and each colour is scattered in
//! parallel (rayon); threads write disjoint entries without locks. Memory is
//! the pattern plus the values of K and M (and of D when an element has
//! damping), never a triplet list.

use crate::element::{Element, ElementMatrices};
use crate::model::Model;
use crate::FemError;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::Mat;
use flexbody_linalg::SparseMat;
use rayon::prelude::*;

/// The assembled matrices of a model, over `model.dof_map()`.
#[derive(Clone, Debug)]
pub struct SystemMatrices {
    pub stiffness: SparseMat,
    pub mass: SparseMat,
    /// Damping D: the model's Rayleigh `alpha M + beta K` plus the
    /// elements' damping matrices; `None` if the model has neither.
    pub damping: Option<SparseMat>,
}

/// Assembles all elements of `model`. Entries on fixed DOFs are dropped
/// (homogeneous boundary conditions).
pub fn assemble(model: &Model) -> Result<SystemMatrices, FemError> {
    let map = model.dof_map();
    let n = map.len();
    // Equations of each element's DOFs (fixed: none; coupled: several).
    let equations: Vec<Vec<Terms>> = model
        .elements()
        .par_iter()
        .map(|e| element_equations(model, e))
        .collect();
    let touched: Vec<Vec<usize>> = equations.par_iter().map(|t| equations_of(t)).collect();
    let (col_ptr, row_idx) = pattern(n, &touched);
    let nnz = row_idx.len();
    let mut k = vec![0.0; nnz];
    let mut m = vec![0.0; nnz];
    let element_damping = model.elements().par_iter().any(Element::has_damping);
    let mut d = if element_damping {
        vec![0.0; nnz]
    } else {
        Vec::new()
    };
    let batches = batches(n, &touched);
    drop(touched);
    let out = Outputs {
        k: SharedSlice(k.as_mut_ptr()),
        m: SharedSlice(m.as_mut_ptr()),
        d: element_damping.then_some(SharedSlice(d.as_mut_ptr())),
    };
    for color in batches {
        color
            .par_iter()
            .try_for_each_init(Vec::new, |sorted, batch| -> Result<(), FemError> {
                for &e in batch {
                    let em = model.elements()[e].matrices(model)?;
                    let terms = &equations[e];
                    // Safety: the batches of one colour share no equation, and
                    // a batch's elements are added one after another.
                    if terms.iter().all(|t| !matches!(t, Terms::Combination(_))) {
                        unsafe { scatter_direct(&em, terms, &col_ptr, &row_idx, out, sorted) };
                    } else {
                        unsafe { scatter(&em, terms, &col_ptr, &row_idx, out) };
                    }
                }
                Ok(())
            })?;
    }
    // The mass matrix gets its own copy of the pattern, written by all
    // threads: the first touch of fresh memory costs as much as the copy
    // (190 MB at 3e5 DOFs of a C3D8 mesh).
    let mass_pattern = {
        let (cols, rows) = (col_ptr.clone(), par_copy(&row_idx));
        // SAFETY: a copy of the pattern that `new_checked` checks below.
        unsafe { SymbolicSparseColMat::new_unchecked(n, n, cols, None, rows) }
    };
    let rayleigh = model.rayleigh().filter(|r| r.alpha != 0.0 || r.beta != 0.0);
    // D on the same pattern: the elements' damping plus alpha M + beta K.
    let damping_pattern = (element_damping || rayleigh.is_some()).then(|| {
        let (cols, rows) = (col_ptr.clone(), par_copy(&row_idx));
        // SAFETY: a copy of the pattern that `new_checked` checks below.
        unsafe { SymbolicSparseColMat::new_unchecked(n, n, cols, None, rows) }
    });
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let damping = damping_pattern.map(|pattern| {
        if !element_damping {
            d = vec![0.0; nnz];
        }
        if let Some(r) = rayleigh {
            d.par_iter_mut()
                .zip(k.par_iter().zip(&m))
                .for_each(|(d, (k, m))| *d += r.alpha * m + r.beta * k);
        }
        SparseColMat::new(pattern, d)
    });
    let stiffness = SparseColMat::new(symbolic, k);
    let mass = SparseColMat::new(mass_pattern, m);
    Ok(SystemMatrices {
        stiffness,
        mass,
        damping,
    })
}

/// A copy of `a`, in parallel chunks.
fn par_copy(a: &[usize]) -> Vec<usize> {
    let mut b = vec![0; a.len()];
    b.par_chunks_mut(1 << 16)
        .zip(a.par_chunks(1 << 16))
        .for_each(|(b, a)| b.copy_from_slice(a));
    b
}

/// Where an element DOF goes: nowhere (fixed), to one equation, or to a
/// combination of equations (a DOF eliminated by a coupling).
#[derive(Clone, Debug)]
enum Terms {
    Fixed,
    Direct(usize),
    Combination(Vec<(usize, f64)>),
}

impl Terms {
    fn of(model: &Model, dof: crate::Dof) -> Terms {
        match model.dof_map().index_of(dof) {
            Some(i) => Terms::Direct(i),
            None if model.has_constraints() => {
                let t = model.terms(dof);
                if t.is_empty() {
                    Terms::Fixed
                } else {
                    Terms::Combination(t)
                }
            }
            None => Terms::Fixed,
        }
    }

    /// Calls `f(equation, coefficient)` for each term.
    fn each(&self, mut f: impl FnMut(usize, f64)) {
        match self {
            Terms::Fixed => {}
            Terms::Direct(i) => f(*i, 1.0),
            Terms::Combination(t) => t.iter().for_each(|&(i, c)| f(i, c)),
        }
    }
}

/// The sorted, distinct equations an element touches.
fn equations_of(terms: &[Terms]) -> Vec<usize> {
    let mut v = Vec::with_capacity(terms.len());
    for t in terms {
        t.each(|i, _| v.push(i));
    }
    v.sort_unstable();
    v.dedup();
    v
}

/// Equation terms of an element's DOFs, in [`Element::dofs`] order: a DOF
/// the model does not have (of an element that creates none, a point mass
/// or a dashpot) is held, as a fixed one.
fn element_equations(model: &Model, e: &Element) -> Vec<Terms> {
    e.dofs().into_iter().map(|d| Terms::of(model, d)).collect()
}

/// Column pointers and sorted row indices of the union of all element blocks.
fn pattern(n: usize, equations: &[Vec<usize>]) -> (Vec<usize>, Vec<usize>) {
    // Elements per equation, then each column's rows as the sorted union of
    // the equations of those elements.
    let mut count = vec![0usize; n + 1];
    for eq in equations {
        for &i in eq {
            count[i + 1] += 1;
        }
    }
    for i in 0..n {
        count[i + 1] += count[i];
    }
    let mut fill = count.clone();
    let mut elements_of = vec![0usize; count[n]];
    for (e, eq) in equations.iter().enumerate() {
        for i in eq {
            elements_of[fill[*i]] = e;
            fill[*i] += 1;
        }
    }
    // Consecutive columns with the same elements (the DOFs of one node) share
    // their rows: each group's rows are found once.
    let mut groups = Vec::new();
    let mut j = 0;
    while j < n {
        let elements = &elements_of[count[j]..count[j + 1]];
        let mut end = j + 1;
        while end < n && &elements_of[count[end]..count[end + 1]] == elements {
            end += 1;
        }
        groups.push(j..end);
        j = end;
    }
    let rows_of: Vec<Vec<usize>> = groups
        .par_iter()
        .map(|g| {
            let mut rows: Vec<usize> = elements_of[count[g.start]..count[g.start + 1]]
                .iter()
                .flat_map(|&e| equations[e].iter().copied())
                .collect();
            rows.sort_unstable();
            rows.dedup();
            rows
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    for (g, rows) in groups.iter().zip(&rows_of) {
        for _ in g.clone() {
            col_ptr.push(col_ptr.last().copied().unwrap_or(0) + rows.len());
        }
    }
    let mut row_idx = Vec::with_capacity(col_ptr[n]);
    for (g, rows) in groups.iter().zip(&rows_of) {
        for _ in g.clone() {
            row_idx.extend_from_slice(rows);
        }
    }
    (col_ptr, row_idx)
}

/// Elements in an order for parallel scatter: colours, run one after
/// another; each colour's batches of elements share no equation and run in
/// parallel; a batch runs in order.
///
/// Batches are runs of [`BATCH`] consecutive elements, so that a thread adds
/// neighbouring elements into the same columns while they are in cache (mesh
/// generators number elements in space). Where that needs more than
/// [`MAX_BATCH_COLORS`] colours (elements in no spatial order), each element
/// is a batch of its own.
fn batches(n: usize, equations: &[Vec<usize>]) -> Vec<Vec<Vec<usize>>> {
    let runs: Vec<Vec<usize>> = (0..equations.len())
        .collect::<Vec<_>>()
        .chunks(BATCH)
        .map(<[usize]>::to_vec)
        .collect();
    color(n, runs, equations, MAX_BATCH_COLORS).unwrap_or_else(|| {
        let singles = (0..equations.len()).map(|e| vec![e]).collect();
        color(n, singles, equations, usize::MAX).unwrap_or_default()
    })
}

/// Consecutive elements per batch.
const BATCH: usize = 256;

/// Most colours of batches before elements are coloured one by one.
const MAX_BATCH_COLORS: usize = 8;

/// Greedy colouring of `batches`: batches of one colour share no equation.
/// `None` if more than `max_colors` colours are needed.
fn color(
    n: usize,
    batches: Vec<Vec<usize>>,
    equations: &[Vec<usize>],
    max_colors: usize,
) -> Option<Vec<Vec<Vec<usize>>>> {
    let mut colors: Vec<Vec<Vec<usize>>> = Vec::new();
    // Equations each colour touches.
    let mut used: Vec<Vec<bool>> = Vec::new();
    for batch in batches {
        let touches = || batch.iter().flat_map(|&e| equations[e].iter().copied());
        let c = match used.iter().position(|u| touches().all(|i| !u[i])) {
            Some(c) => c,
            None if colors.len() < max_colors => {
                used.push(vec![false; n]);
                colors.push(Vec::new());
                colors.len() - 1
            }
            None => return None,
        };
        for i in touches() {
            used[c][i] = true;
        }
        colors[c].push(batch);
    }
    Some(colors)
}

/// A raw pointer that may be shared between threads writing disjoint entries.
#[derive(Copy, Clone)]
struct SharedSlice(*mut f64);
unsafe impl Send for SharedSlice {}
unsafe impl Sync for SharedSlice {}

/// The value arrays of K, M and (if some element has damping) D over the
/// pattern.
#[derive(Copy, Clone)]
struct Outputs {
    k: SharedSlice,
    m: SharedSlice,
    d: Option<SharedSlice>,
}

/// Adds the K, M and D of an element without coupled DOFs into the value
/// arrays. The element's equations are sorted once; each of its columns then
/// finds all of them in one forward walk over the column's sorted rows.
///
/// # Safety
/// As [`scatter`]; `terms` has no [`Terms::Combination`].
unsafe fn scatter_direct(
    em: &ElementMatrices,
    terms: &[Terms],
    col_ptr: &[usize],
    row_idx: &[usize],
    out: Outputs,
    sorted: &mut Vec<(usize, usize)>,
) {
    sorted.clear();
    sorted.extend(terms.iter().enumerate().filter_map(|(a, t)| match t {
        Terms::Direct(i) => Some((*i, a)),
        _ => None,
    }));
    sorted.sort_unstable();
    let damping = em.damping.as_ref().zip(out.d);
    for &(j, b) in sorted.iter() {
        let (kb, mb) = (column(&em.stiffness, b), column(&em.mass, b));
        let db = damping.map(|(d, to)| (column(d, b), to));
        let start = col_ptr[j];
        let rows = &row_idx[start..col_ptr[j + 1]];
        let mut p = 0;
        for &(i, a) in sorted.iter() {
            // The pattern holds every (i, j) of every element, in order.
            match rows[p..].iter().position(|&r| r == i) {
                Some(q) => p += q,
                None => continue,
            }
            let at = start + p;
            unsafe {
                *out.k.0.add(at) += kb[a];
                *out.m.0.add(at) += mb[a];
                if let Some((db, d)) = db {
                    *d.0.add(at) += db[a];
                }
            }
        }
    }
}

/// Column `b` of a small dense (column-major) matrix.
fn column(m: &Mat<f64>, b: usize) -> &[f64] {
    match m.col(b).try_as_col_major() {
        Some(c) => c.as_slice(),
        None => unreachable!("element matrices are column-major"),
    }
}

/// Adds an element's K, M and D into the value arrays, through the terms
/// of its DOFs: `K_ij += sum_ab c_ai c_bj K_e,ab`.
///
/// # Safety
/// The arrays of `out` hold `row_idx.len()` values each, and no other
/// thread writes the entries of the element's equations at the same time.
unsafe fn scatter(
    em: &ElementMatrices,
    eq: &[Terms],
    col_ptr: &[usize],
    row_idx: &[usize],
    out: Outputs,
) {
    let damping = em.damping.as_ref().zip(out.d);
    for (b, tb) in eq.iter().enumerate() {
        tb.each(|j, cj| {
            let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            for (a, ta) in eq.iter().enumerate() {
                let (kv, mv) = (em.stiffness[(a, b)], em.mass[(a, b)]);
                let dv = damping.map_or(0.0, |(d, _)| d[(a, b)]);
                if kv == 0.0 && mv == 0.0 && dv == 0.0 {
                    continue;
                }
                ta.each(|i, ci| {
                    // The pattern holds every (i, j) of every element.
                    if let Ok(p) = rows.binary_search(&i) {
                        let at = col_ptr[j] + p;
                        let c = ci * cj;
                        unsafe {
                            *out.k.0.add(at) += c * kv;
                            *out.m.0.add(at) += c * mv;
                            if let Some((_, d)) = damping {
                                *d.0.add(at) += c * dv;
                            }
                        }
                    }
                });
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{AxialSpring, Beam, PointMass, Spring};
    use crate::mesh::BrickBlock;
    use crate::{BeamProperties, BeamTheory, Dof, DofKind, Material, Node, SectionShape};
    use faer::Mat;

    /// Dense reference: every element block added at its equations.
    fn dense(model: &Model) -> (Mat<f64>, Mat<f64>) {
        let n = model.dof_map().len();
        let (mut k, mut m) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
        for e in model.elements() {
            let em = e.matrices(model).unwrap();
            let eq: Vec<Option<usize>> = em
                .dofs
                .iter()
                .map(|d| model.dof_map().index_of(*d))
                .collect();
            for (a, ia) in eq.iter().enumerate() {
                for (b, ib) in eq.iter().enumerate() {
                    if let (Some(i), Some(j)) = (ia, ib) {
                        k[(*i, *j)] += em.stiffness[(a, b)];
                        m[(*i, *j)] += em.mass[(a, b)];
                    }
                }
            }
        }
        (k, m)
    }

    /// Dense reference of D: `alpha M + beta K` of the model's Rayleigh
    /// damping plus every element's damping block at its equations.
    fn dense_damping(model: &Model) -> Mat<f64> {
        let n = model.dof_map().len();
        let (k, m) = dense(model);
        let r = model.rayleigh().unwrap_or_default();
        let mut d = Mat::from_fn(n, n, |i, j| r.alpha * m[(i, j)] + r.beta * k[(i, j)]);
        for e in model.elements() {
            let em = e.matrices(model).unwrap();
            let Some(de) = em.damping else { continue };
            let eq: Vec<Option<usize>> = em
                .dofs
                .iter()
                .map(|d| model.dof_map().index_of(*d))
                .collect();
            for (a, ia) in eq.iter().enumerate() {
                for (b, ib) in eq.iter().enumerate() {
                    if let (Some(i), Some(j)) = (ia, ib) {
                        d[(*i, *j)] += de[(a, b)];
                    }
                }
            }
        }
        d
    }

    /// A C3D8 brick of `nx * ny * nz` unit-ish elements (a [`BrickBlock`] of
    /// cells 1 x 0.9 x 1.1 m, sheared by z += 0.05 x), free, its elements
    /// listed in the order `order(e)` of the mesh order `e`.
    fn brick(nx: usize, ny: usize, nz: usize, order: impl Fn(usize) -> usize) -> Model {
        let block = BrickBlock {
            cells: [nx, ny, nz],
            origin: [0.0; 3],
            size: [nx as f64, 0.9 * ny as f64, 1.1 * nz as f64],
        };
        let mut nodes = block.nodes();
        for node in &mut nodes {
            node.coords[2] += 0.05 * node.coords[0];
        }
        let cells = block.elements(&Material::new(2.1e11, 0.3, 7850.0).unwrap());
        let elements = (0..cells.len()).map(|e| cells[order(e)].clone()).collect();
        Model::of(nodes, elements).build().unwrap()
    }

    #[test]
    fn batched_assembly_of_a_solid_mesh_equals_dense_assembly_in_any_element_order() {
        // 360 elements: two batches, which share nodes in either order.
        let (nx, ny, nz) = (12, 6, 5);
        let count = nx * ny * nz;
        for shuffled in [false, true] {
            let model = brick(nx, ny, nz, |e| if shuffled { (e * 97) % 360 } else { e });
            assert_eq!(model.elements().len(), count);
            let s = assemble(&model).unwrap();
            let (k, m) = dense(&model);
            let scale = flexbody_linalg::sparse::max_abs(k.as_ref());
            let dk = s.stiffness.to_dense() - &k;
            assert!(flexbody_linalg::sparse::max_abs(dk.as_ref()) <= 1e-15 * scale);
            let dm = s.mass.to_dense() - &m;
            let m_scale = flexbody_linalg::sparse::max_abs(m.as_ref());
            assert!(flexbody_linalg::sparse::max_abs(dm.as_ref()) <= 1e-15 * m_scale);
        }
    }

    #[test]
    fn batches_of_one_colour_share_no_equation_and_cover_every_element_once() {
        // 2880 elements, 12 batches: in mesh order a batch touches only its
        // neighbours; shuffled, all of them, and elements are coloured singly.
        let (nx, ny, nz) = (24, 12, 10);
        for shuffled in [false, true] {
            let model = brick(nx, ny, nz, |e| if shuffled { (e * 97) % 2880 } else { e });
            let equations: Vec<Vec<usize>> = model
                .elements()
                .iter()
                .map(|e| equations_of(&element_equations(&model, e)))
                .collect();
            let n = model.dof_map().len();
            let colors = batches(n, &equations);
            let batch_len = colors.iter().flatten().map(Vec::len).max().unwrap();
            assert_eq!(batch_len, if shuffled { 1 } else { BATCH });
            let mut seen = vec![0; equations.len()];
            for color in &colors {
                let mut owner = vec![usize::MAX; n];
                for (b, batch) in color.iter().enumerate() {
                    for &e in batch {
                        seen[e] += 1;
                        for &i in &equations[e] {
                            assert!(owner[i] == usize::MAX || owner[i] == b);
                            owner[i] = b;
                        }
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1));
        }
    }

    #[test]
    fn parallel_pattern_assembly_equals_dense_assembly() {
        let props = BeamProperties::new(
            Material::new(2.1e11, 0.3, 7850.0).unwrap(),
            SectionShape::Circ { radius: 0.02 }.constants().unwrap(),
            BeamTheory::Timoshenko,
        );
        // A branched frame: nodes 1..=6, beams 1-2-3-4, 2-5, 3-6 (shared nodes).
        let coords = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [2.0, 0.0, 1.0],
        ];
        let nodes = coords
            .iter()
            .enumerate()
            .map(|(i, c)| Node {
                id: i as u64 + 1,
                coords: *c,
            })
            .collect();
        let mut elements: Vec<Element> = [(1, 2), (2, 3), (3, 4), (2, 5), (3, 6)]
            .iter()
            .enumerate()
            .map(|(i, &(a, b))| {
                Element::Beam(Beam {
                    id: i + 1,
                    nodes: [a, b],
                    properties: props.clone(),
                    orientation: [0.3, 0.2, 1.0],
                })
            })
            .collect();
        elements.push(Element::PointMass(PointMass {
            id: 10,
            node: 4,
            mass: 3.0,
            inertia: [0.1, 0.2, 0.3, 0.01, 0.0, 0.02],
        }));
        elements.push(Element::Spring(Spring {
            id: 11,
            first: Dof::new(5, DofKind::Uy),
            second: Some(Dof::new(6, DofKind::Rz)),
            stiffness: 1e5,
        }));
        elements.push(Element::AxialSpring(AxialSpring {
            id: 12,
            nodes: [4, 5],
            stiffness: 2e6,
        }));
        let fixed = vec![
            Dof::new(1, DofKind::Ux),
            Dof::new(1, DofKind::Uy),
            Dof::new(1, DofKind::Rz),
        ];
        let model = Model::of(nodes, elements).fixed(fixed).build().unwrap();
        let s = assemble(&model).unwrap();
        let (k, m) = dense(&model);
        let scale = flexbody_linalg::sparse::max_abs(k.as_ref());
        assert!(
            flexbody_linalg::sparse::max_abs((s.stiffness.to_dense() - &k).as_ref())
                <= 1e-15 * scale
        );
        assert!(
            flexbody_linalg::sparse::max_abs((s.mass.to_dense() - &m).as_ref())
                <= 1e-15 * flexbody_linalg::sparse::max_abs(m.as_ref())
        );
        assert_eq!(model.dof_map().len(), 6 * 6 - 3);
    }

    /// Beams of two materials (one with Rayleigh damping), dashpots along
    /// a line, to ground and between DOFs, and the model's Rayleigh
    /// damping: D is their sum, entry by entry; without any, no D.
    #[test]
    fn damping_is_the_models_rayleigh_plus_every_elements_damping() {
        use crate::element::{AxialDashpot, Dashpot};
        use crate::Rayleigh;
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let damped = steel
            .clone()
            .with_damping(Rayleigh {
                alpha: 3.0,
                beta: 2e-5,
            })
            .unwrap();
        let section = SectionShape::Circ { radius: 0.02 }.constants().unwrap();
        let coords = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.5, 0.0],
            [3.0, 0.5, 1.0],
        ];
        let nodes: Vec<Node> = coords
            .iter()
            .enumerate()
            .map(|(i, c)| Node {
                id: i as u64 + 1,
                coords: *c,
            })
            .collect();
        let beams = |damped_middle: bool| -> Vec<Element> {
            (1..4)
                .map(|i| {
                    let material = if i == 2 && damped_middle {
                        damped.clone()
                    } else {
                        steel.clone()
                    };
                    Element::Beam(Beam {
                        id: i,
                        nodes: [i as u64, i as u64 + 1],
                        properties: BeamProperties::new(
                            material,
                            section.clone(),
                            BeamTheory::Timoshenko,
                        ),
                        orientation: [0.0, 0.0, 1.0],
                    })
                })
                .collect()
        };
        let mut elements = beams(true);
        let plain = Model::of(nodes.clone(), beams(false))
            .fixed(vec![Dof::new(1, DofKind::Ux)])
            .build()
            .unwrap();
        elements.push(Element::AxialDashpot(AxialDashpot {
            id: 10,
            nodes: [1, 4],
            coefficient: 7.0e3,
        }));
        elements.push(Element::Dashpot(Dashpot {
            id: 11,
            first: Dof::new(3, DofKind::Ry),
            second: None,
            coefficient: 50.0,
        }));
        elements.push(Element::Dashpot(Dashpot {
            id: 12,
            first: Dof::new(2, DofKind::Uy),
            second: Some(Dof::new(4, DofKind::Uz)),
            coefficient: 900.0,
        }));
        for rayleigh in [None, Some((0.5, 1e-4))] {
            let mut parts =
                Model::of(nodes.clone(), elements.clone()).fixed(vec![Dof::new(1, DofKind::Ux)]);
            if let Some((alpha, beta)) = rayleigh {
                parts = parts.rayleigh(Rayleigh { alpha, beta });
            }
            let model = parts.build().unwrap();
            assert_eq!(model.dof_map().len(), plain.dof_map().len(), "no new DOFs");
            let d = assemble(&model).unwrap().damping.unwrap().to_dense();
            let want = dense_damping(&model);
            let scale = flexbody_linalg::sparse::max_abs(want.as_ref());
            let diff = flexbody_linalg::sparse::max_abs((&d - &want).as_ref());
            assert!(diff <= 1e-14 * scale, "{diff:e} of {scale:e}");
            // The dashpot along 1-4 on its own: c e e^T at node 4 (node 1's
            // ux is fixed).
            let l = (9.0_f64 + 0.25 + 1.0).sqrt();
            let e = [3.0 / l, 0.5 / l, 1.0 / l];
            let ux4 = model.dof_map().index_of(Dof::new(4, DofKind::Ux)).unwrap();
            let uz4 = model.dof_map().index_of(Dof::new(4, DofKind::Uz)).unwrap();
            let beams = dense_damping(
                &Model::of(nodes.clone(), elements[..3].to_vec())
                    .fixed(vec![Dof::new(1, DofKind::Ux)])
                    .rayleigh(Rayleigh {
                        alpha: rayleigh.map_or(0.0, |r| r.0),
                        beta: rayleigh.map_or(0.0, |r| r.1),
                    })
                    .build()
                    .unwrap(),
            );
            let got = d[(ux4, uz4)] - beams[(ux4, uz4)];
            assert!((got - 7.0e3 * e[0] * e[2]).abs() < 1e-9 * 7.0e3, "{got}");
        }
        assert!(assemble(&plain).unwrap().damping.is_none());
    }
}
