//! Linear multi-point constraints: homogeneous equations
//! `sum_k c_k u_k = 0` among DOFs (Abaqus/CalculiX `*EQUATION`, the
//! linearised `*MPC`s, ties), eliminated exactly like the couplings' own
//! constraints: the first term's DOF is dependent,
//! `u_d = -sum_{k>0} (c_k / c_0) u_k`, and leaves the DOF map.
//!
//! `resolve` turns the constraints of all sources (couplings, equations)
//! into combinations of independent DOFs only: a term that is itself
//! dependent is substituted (chains of any length), a fixed term drops out
//! (it is zero). A cycle, a DOF made dependent twice, or a dependent DOF
//! that is also fixed is an error naming the DOFs and the constraints.

use crate::coupling::Constraints;
use crate::dof::{Dof, DofKind};
use crate::model::NodeId;
use crate::FemError;
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// A homogeneous linear constraint `sum_k c_k u_k = 0`; the first term's
/// DOF is the dependent one (eliminated), as in `*EQUATION`.
#[derive(Clone, Debug, PartialEq)]
pub struct Equation {
    /// Names the constraint in errors (`*EQUATION (line 12)`, `tie 'T1'`).
    pub name: String,
    /// `(DOF, coefficient)`; the first term's coefficient is not zero. A DOF
    /// listed twice has its coefficients added.
    pub terms: Vec<(Dof, f64)>,
}

impl Equation {
    /// `u_d` as a combination of the other DOFs, the dependent DOF `d` being
    /// the first term's; an error names a bad coefficient or a dependent
    /// DOF whose coefficients add up to zero.
    pub fn solved(&self) -> Result<(Dof, Vec<(Dof, f64)>), FemError> {
        let bad = |reason: String| FemError::InvalidConstraint {
            name: self.name.clone(),
            reason,
        };
        let Some(&(dependent, _)) = self.terms.first() else {
            return Err(bad("it has no terms".into()));
        };
        let mut sum: BTreeMap<Dof, f64> = BTreeMap::new();
        for &(dof, c) in &self.terms {
            if !c.is_finite() {
                return Err(bad(format!("the coefficient of {dof} is {c}")));
            }
            *sum.entry(dof).or_default() += c;
        }
        let c0 = sum.remove(&dependent).unwrap_or(0.0);
        if c0 == 0.0 {
            return Err(bad(format!(
                "the coefficient of its dependent (first) DOF {dependent} is zero"
            )));
        }
        let terms = sum
            .into_iter()
            .filter(|(_, c)| *c != 0.0)
            .map(|(d, c)| (d, -c / c0))
            .collect();
        Ok((dependent, terms))
    }
}

/// The linearised CalculiX `*MPC`s: nodes held on a geometric figure that
/// other nodes define, for small displacements. The node order and the
/// dependent DOFs are CalculiX's. In a model file: `"beam"`, `"plane"`,
/// `"straight"`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MpcKind {
    /// Two nodes keep their distance: `(x_a - x_b) . (u_a - u_b) = 0`; the
    /// dependent DOF is node a's along the largest component of `x_a - x_b`.
    Beam,
    /// The first three nodes define a plane; every further node stays in
    /// it, dependent along the largest component of the plane's normal.
    Plane,
    /// The first two nodes define a straight line; every further node stays
    /// on it, dependent in the two directions other than the line's largest
    /// component.
    Straight,
}

impl MpcKind {
    /// The kind of an `*MPC` card's first field (upper case).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "BEAM" => Some(Self::Beam),
            "PLANE" => Some(Self::Plane),
            "STRAIGHT" => Some(Self::Straight),
            _ => None,
        }
    }

    /// The nodes that define the figure; the nodes after them are held.
    pub fn defining_nodes(self) -> usize {
        match self {
            Self::Beam => 1,
            Self::Plane => 3,
            Self::Straight => 2,
        }
    }

    /// The equations of the MPC on `nodes` at positions `x`. An error names
    /// a wrong node count or a degenerate figure (coincident nodes, a plane
    /// of collinear nodes).
    pub fn equations(
        self,
        name: &str,
        nodes: &[NodeId],
        x: &[[f64; 3]],
    ) -> Result<Vec<Equation>, FemError> {
        let bad = |reason: String| FemError::InvalidConstraint {
            name: name.to_string(),
            reason,
        };
        let defining = self.defining_nodes();
        let count_ok = match self {
            Self::Beam => nodes.len() == 2,
            _ => nodes.len() > defining,
        };
        if !count_ok || x.len() != nodes.len() {
            let wanted = match self {
                Self::Beam => "2 nodes".to_string(),
                _ => format!("at least {} nodes", defining + 1),
            };
            return Err(bad(format!("it takes {wanted}, got {}", nodes.len())));
        }
        let largest = |v: [f64; 3]| {
            (0..3)
                .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
                .unwrap_or(0)
        };
        let scale = x
            .iter()
            .flat_map(|p| x.iter().map(move |q| norm(sub(*p, *q))))
            .fold(0.0, f64::max);
        // One equation `sum_n g_n . u_n = 0` over the held node (first in
        // `ids`) and the defining nodes, its dependent DOF the held node's
        // component `dep`.
        let equation = |dep: usize, g: &[[f64; 3]], ids: &[NodeId]| {
            let mut terms = vec![(Dof::new(ids[0], DofKind::ALL[dep]), g[0][dep])];
            for (n, gn) in ids.iter().zip(g) {
                for (k, c) in gn.iter().enumerate() {
                    if (*n, k) != (ids[0], dep) && *c != 0.0 {
                        terms.push((Dof::new(*n, DofKind::ALL[k]), *c));
                    }
                }
            }
            Equation {
                name: name.to_string(),
                terms,
            }
        };
        let degenerate = |what: &str| bad(format!("its nodes {nodes:?} {what}"));
        match self {
            Self::Beam => {
                let e = sub(x[0], x[1]);
                if norm(e) <= 1e-12 * scale.max(f64::MIN_POSITIVE) || norm(e) == 0.0 {
                    return Err(degenerate("are coincident"));
                }
                Ok(vec![equation(largest(e), &[e, neg(e)], nodes)])
            }
            Self::Plane => {
                // r . ((a - c) x (b - c)) = 0 with r = x_p - x_c, differentiated.
                let (a, b, c) = (x[0], x[1], x[2]);
                let (ea, eb) = (sub(a, c), sub(b, c));
                let n = cross(ea, eb);
                if norm(n) <= 1e-9 * scale * scale {
                    return Err(degenerate(
                        "do not define a plane (the first three are collinear)",
                    ));
                }
                let dep = largest(n);
                let mut out = Vec::new();
                for (&id, &p) in nodes.iter().zip(x).skip(3) {
                    let r = sub(p, c);
                    // d(r . (ea x eb)) = dr . n + dea . (eb x r) + deb . (r x ea).
                    let ga = cross(eb, r);
                    let gb = cross(r, ea);
                    let gc = neg(add(add(n, ga), gb));
                    out.push(equation(
                        dep,
                        &[n, ga, gb, gc],
                        &[id, nodes[0], nodes[1], nodes[2]],
                    ));
                }
                Ok(out)
            }
            Self::Straight => {
                // (x_p - x_a) x (x_b - x_a) = 0: the components in the planes
                // of the line's largest direction and each other direction.
                let (a, b) = (x[0], x[1]);
                let t = sub(b, a);
                if norm(t) <= 1e-12 * scale || norm(t) == 0.0 {
                    return Err(degenerate("do not define a line (the first two coincide)"));
                }
                let along = largest(t);
                let mut out = Vec::new();
                for (&id, &p) in nodes.iter().zip(x).skip(2) {
                    let r = sub(p, a);
                    for dep in (0..3).filter(|j| *j != along) {
                        // Component i (the third axis) of r x t.
                        let i = 3 - dep - along;
                        let gp = cross_row(i, t, false);
                        let gb = cross_row(i, r, true);
                        let ga = neg(add(gp, gb));
                        out.push(equation(dep, &[gp, ga, gb], &[id, nodes[0], nodes[1]]));
                    }
                }
                Ok(out)
            }
        }
    }
}

/// The coefficient vector of `du` in component `i` of `du x v` (or, with
/// `left`, of `v x du`).
fn cross_row(i: usize, v: [f64; 3], left: bool) -> [f64; 3] {
    let mut g = [0.0; 3];
    for (k, gk) in g.iter_mut().enumerate() {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        *gk = if left { cross(v, e)[i] } else { cross(e, v)[i] };
    }
    g
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn neg(a: [f64; 3]) -> [f64; 3] {
    [-a[0], -a[1], -a[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Every dependent DOF of `direct` as a combination of independent DOFs:
/// dependent terms substituted, fixed terms dropped, equal DOFs merged.
/// `owner` names the constraint of each dependent DOF for errors. Cost:
/// linear in the terms of the resolved constraints.
pub(crate) fn resolve(
    direct: Constraints,
    owner: &HashMap<Dof, String>,
    fixed: &BTreeSet<Dof>,
) -> Result<Constraints, FemError> {
    let name = |d: &Dof| owner.get(d).cloned().unwrap_or_default();
    // Post-order of the dependency graph (dependents a constraint refers
    // to come first), by an explicit stack: chains may be long.
    #[derive(Copy, Clone, PartialEq)]
    enum State {
        Open,
        Done,
    }
    let mut state: HashMap<Dof, State> = HashMap::with_capacity(direct.len());
    let mut order: Vec<Dof> = Vec::with_capacity(direct.len());
    for &root in direct.keys() {
        if state.contains_key(&root) {
            continue;
        }
        state.insert(root, State::Open);
        let mut stack: Vec<(Dof, usize)> = vec![(root, 0)];
        while let Some((dof, next)) = stack.last_mut() {
            let terms = &direct[dof];
            if let Some(&(t, _)) = terms.get(*next) {
                *next += 1;
                if !direct.contains_key(&t) {
                    continue;
                }
                match state.get(&t) {
                    Some(State::Done) => {}
                    Some(State::Open) => {
                        let start = stack.iter().position(|(d, _)| *d == t).unwrap_or(0);
                        let cycle: Vec<String> =
                            stack[start..].iter().map(|(d, _)| d.to_string()).collect();
                        return Err(FemError::InvalidConstraint {
                            name: name(&t),
                            reason: format!(
                                "its constraints form a cycle: {} depends on itself through {} \
                                 (a DOF can be eliminated once; remove one of the equations)",
                                t,
                                cycle.join(" -> ")
                            ),
                        });
                    }
                    None => {
                        state.insert(t, State::Open);
                        stack.push((t, 0));
                    }
                }
            } else {
                let done = *dof;
                state.insert(done, State::Done);
                order.push(done);
                stack.pop();
            }
        }
    }
    let mut resolved = Constraints::new();
    for dof in order {
        if fixed.contains(&dof) {
            return Err(FemError::InvalidConstraint {
                name: name(&dof),
                reason: format!("{dof} is fixed by a boundary condition and also eliminated by it"),
            });
        }
        let mut sum: BTreeMap<Dof, f64> = BTreeMap::new();
        for &(t, c) in &direct[&dof] {
            if let Some(sub) = resolved.get(&t) {
                for &(s, cs) in sub {
                    *sum.entry(s).or_default() += c * cs;
                }
            } else if !fixed.contains(&t) {
                *sum.entry(t).or_default() += c;
            }
        }
        resolved.insert(dof, sum.into_iter().filter(|(_, c)| *c != 0.0).collect());
    }
    Ok(resolved)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(node: NodeId, k: usize) -> Dof {
        Dof::new(node, DofKind::ALL[k])
    }

    #[test]
    fn an_equation_solves_for_its_first_dof() {
        let e = Equation {
            name: "e".into(),
            terms: vec![
                (d(1, 0), 2.0),
                (d(2, 0), -1.0),
                (d(3, 1), 4.0),
                (d(2, 0), -1.0),
            ],
        };
        let (dep, terms) = e.solved().unwrap();
        assert_eq!(dep, d(1, 0));
        assert_eq!(terms, vec![(d(2, 0), 1.0), (d(3, 1), -2.0)]);
        let zero = Equation {
            name: "z".into(),
            terms: vec![(d(1, 0), 1.0), (d(1, 0), -1.0), (d(2, 0), 1.0)],
        };
        let err = zero.solved().unwrap_err().to_string();
        assert!(
            err.contains("constraint z") && err.contains("zero"),
            "{err}"
        );
    }

    #[test]
    fn chains_are_substituted_and_fixed_terms_dropped() {
        // u1 = u2 + u3, u2 = 2 u4, u3 fixed: u1 = 2 u4.
        let mut direct = Constraints::new();
        direct.insert(d(1, 0), vec![(d(2, 0), 1.0), (d(3, 0), 1.0)]);
        direct.insert(d(2, 0), vec![(d(4, 0), 2.0)]);
        let fixed: BTreeSet<Dof> = [d(3, 0)].into();
        let r = resolve(direct, &HashMap::new(), &fixed).unwrap();
        assert_eq!(r[&d(1, 0)], vec![(d(4, 0), 2.0)]);
        assert_eq!(r[&d(2, 0)], vec![(d(4, 0), 2.0)]);
    }

    #[test]
    fn a_long_chain_resolves_without_deep_recursion() {
        let n = 200_000;
        let mut direct = Constraints::new();
        for i in 1..n {
            direct.insert(d(i, 2), vec![(d(i + 1, 2), 1.0)]);
        }
        let r = resolve(direct, &HashMap::new(), &BTreeSet::new()).unwrap();
        assert_eq!(r[&d(1, 2)], vec![(d(n, 2), 1.0)]);
    }

    #[test]
    fn a_cycle_is_named() {
        let mut direct = Constraints::new();
        direct.insert(d(1, 0), vec![(d(2, 0), 1.0)]);
        direct.insert(d(2, 0), vec![(d(3, 0), 1.0)]);
        direct.insert(d(3, 0), vec![(d(1, 0), 1.0)]);
        let owner: HashMap<Dof, String> = direct.keys().map(|k| (*k, "eq".to_string())).collect();
        let err = resolve(direct, &owner, &BTreeSet::new())
            .unwrap_err()
            .to_string();
        assert!(err.contains("cycle") && err.contains("node 1"), "{err}");
    }

    /// The linearised MPCs keep their figure to first order: a rigid
    /// motion of all nodes satisfies them, and the dependent DOFs are
    /// CalculiX's.
    #[test]
    fn mpc_equations_are_the_linearised_figures() {
        let residual = |eq: &Equation,
                        ids: &[NodeId],
                        x: &[[f64; 3]],
                        u: &dyn Fn([f64; 3]) -> [f64; 3]|
         -> f64 {
            eq.terms
                .iter()
                .map(|(dof, c)| {
                    let i = ids.iter().position(|n| *n == dof.node).unwrap();
                    c * u(x[i])[dof.kind.index()]
                })
                .sum()
        };
        let spin = |p: [f64; 3]| add([1e-3, -2e-3, 5e-4], cross([1e-3, 2e-3, -3e-3], p));
        // The plane z = 0 through nodes 1..3 holds nodes 4 and 5 (in z).
        let ids = [1, 2, 3, 4, 5];
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.3, 0.4, 0.0],
            [0.7, 0.1, 0.0],
        ];
        let eqs = MpcKind::Plane.equations("p", &ids, &x).unwrap();
        assert_eq!(
            eqs.iter().map(|e| e.terms[0].0).collect::<Vec<_>>(),
            vec![d(4, 2), d(5, 2)]
        );
        for e in &eqs {
            assert!(residual(e, &ids, &x, &spin).abs() < 1e-15);
            // Moving the held node out of the plane violates it.
            let lift = |p: [f64; 3]| {
                if p == x[3] || p == x[4] {
                    [0.0, 0.0, 1e-3]
                } else {
                    [0.0; 3]
                }
            };
            assert!(residual(e, &ids, &x, &lift).abs() > 1e-4);
        }
        // The line along x through nodes 1 and 2 holds node 3 (in y and z).
        let ids = [1, 2, 3];
        let xs = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 0.0]];
        let eqs = MpcKind::Straight.equations("s", &ids, &xs).unwrap();
        assert_eq!(
            eqs.iter().map(|e| e.terms[0].0).collect::<Vec<_>>(),
            vec![d(3, 1), d(3, 2)]
        );
        for e in &eqs {
            assert!(residual(e, &ids, &xs, &spin).abs() < 1e-15);
        }
        // Beam: the distance; coincident nodes are refused.
        let eqs = MpcKind::Beam
            .equations("b", &[1, 2], &[[0.0, 0.0, 2.0], [0.0, 0.0, 0.0]])
            .unwrap();
        assert_eq!(eqs[0].terms, vec![(d(1, 2), 2.0), (d(2, 2), -2.0)]);
        let err = MpcKind::Beam
            .equations("b", &[1, 2], &[[0.0; 3], [0.0; 3]])
            .unwrap_err()
            .to_string();
        assert!(err.contains("coincident"), "{err}");
        let err = MpcKind::Plane
            .equations(
                "p",
                &[1, 2, 3, 4],
                &[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            )
            .unwrap_err()
            .to_string();
        assert!(err.contains("collinear"), "{err}");
    }

    /// Chained constraints (an MPC's dependent DOF among another's terms,
    /// an equation on a coupled DOF's neighbour) eliminated in the model
    /// give the eigenvalues of the constrained problem solved independently:
    /// K and M projected on the null space of the constraint rows.
    #[test]
    fn chained_constraints_equal_the_null_space_solve() {
        use crate::mesh::BrickBlock;
        use crate::{assemble, Material, Model};
        use faer::Mat;
        use flexbody_linalg::eigen::{generalized_symmetric, symmetric_eigen};
        let bar = BrickBlock {
            cells: [3, 1, 1],
            origin: [0.0; 3],
            size: [0.3, 0.1, 0.12],
        };
        let material = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let plain = Model::of(bar.nodes(), bar.elements(&material))
            .build()
            .unwrap();
        let id = |i, j, k| bar.node([i, j, k]);
        let x = |n: NodeId| plain.coords(n);
        let mut equations = Vec::new();
        // A BEAM whose dependent DOF (node a's ux) is a term of a PLANE.
        let (a, b) = (id(3, 0, 1), id(1, 1, 0));
        equations.extend(
            MpcKind::Beam
                .equations("beam", &[a, b], &[x(a), x(b)])
                .unwrap(),
        );
        let plane = [id(3, 0, 0), id(3, 1, 0), a, id(3, 1, 1)];
        let px: Vec<[f64; 3]> = plane.iter().map(|n| x(*n)).collect();
        equations.extend(MpcKind::Plane.equations("plane", &plane, &px).unwrap());
        // An equation whose term is the PLANE's dependent DOF.
        equations.push(Equation {
            name: "eq".into(),
            terms: vec![(d(id(0, 0, 0), 2), 1.0), (d(id(3, 1, 1), 0), -0.5)],
        });
        let constrained = Model::of(bar.nodes(), bar.elements(&material))
            .equations(equations.clone())
            .build()
            .unwrap();
        assert_eq!(constrained.dof_map().len(), plain.dof_map().len() - 3);

        // The constraint rows over the plain model's DOFs, their null space Z.
        let map = plain.dof_map();
        let n = map.len();
        let c = Mat::from_fn(equations.len(), n, |r, i| {
            equations[r]
                .terms
                .iter()
                .filter(|(dof, _)| map.index_of(*dof) == Some(i))
                .map(|(_, c)| c)
                .sum::<f64>()
        });
        let (s, v) = symmetric_eigen((c.transpose() * &c).as_ref()).unwrap();
        let null: Vec<usize> = (0..n).filter(|&k| s[k] < 1e-12 * s[n - 1]).collect();
        assert_eq!(null.len(), n - 3);
        let z = Mat::from_fn(n, null.len(), |i, j| v[(i, null[j])]);
        let full = assemble(&plain).unwrap();
        let project = |a: &flexbody_linalg::SparseMat| z.transpose() * (a.to_dense() * &z);
        let want = generalized_symmetric(
            project(&full.stiffness).as_ref(),
            project(&full.mass).as_ref(),
        )
        .unwrap();
        let s = assemble(&constrained).unwrap();
        let got =
            generalized_symmetric(s.stiffness.to_dense().as_ref(), s.mass.to_dense().as_ref())
                .unwrap();
        let top = want.values[want.values.len() - 1];
        for (k, (g, w)) in got.values.iter().zip(&want.values).enumerate() {
            assert!(
                (g - w).abs() <= 1e-9 * w.abs() + 1e-12 * top,
                "eigenvalue {k}: eliminated {g}, null space {w}"
            );
        }
    }
}
