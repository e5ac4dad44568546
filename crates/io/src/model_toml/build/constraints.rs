//! `[[equation]]`, `[[mpc]]` and `[[tie]]`: the file's linear constraints,
//! as [`Equation`]s the model eliminates exactly (the first term's DOF of
//! each, as the deck's `*EQUATION`, `*MPC` and `*TIE`).
//!
//! Each entry is named in errors as the strict-key errors name it
//! (`[[equation]] 'E1'`, `[[mpc]] number 2`, `tie 'JOINT'`), and its name
//! leads to its line when the model refuses a constraint (a DOF no
//! element gives, a DOF eliminated twice). A tie's master faces are solid
//! faces of the deck: an element surface it defines (`master`) and/or the
//! exterior faces of one of its element sets (`master_elements`). With
//! `adjust`, the slave nodes move onto the master surface after every tie
//! is made, from the positions before any moved, as in the deck reader.

use super::Builder;
use crate::model_toml::raw::{RawModel, RawTie};
use crate::spelling::nearest;
use crate::InputError;
use flexbody_fem::element::solid::Solid;
use flexbody_fem::tie::{exterior_faces, solid_face};
use flexbody_fem::{Dof, Element, Equation, Face, NodeId, Tie};
use std::collections::{HashMap, HashSet};
use toml::Spanned;

/// The file's constraint equations, and the entry (byte offset) of each
/// constraint name.
#[derive(Default)]
pub(super) struct FileConstraints {
    pub equations: Vec<Equation>,
    pub entries: HashMap<String, usize>,
}

impl FileConstraints {
    /// Records `name` for the entry at `at`; a name given twice is an error.
    fn claim<T>(
        &mut self,
        src: &crate::TomlSource<'_>,
        name: &str,
        at: &Spanned<T>,
    ) -> Result<(), InputError> {
        if let Some(first) = self.entries.insert(name.to_string(), at.span().start) {
            return Err(src.at(
                at,
                format!(
                    "{name} is defined twice (first on line {})",
                    src.line(first)
                ),
            ));
        }
        Ok(())
    }
}

/// `[[table]] 'name'`, or `[[table]] number k` (from 1) without a name.
fn label(table: &str, name: Option<&str>, index: usize) -> String {
    match name {
        Some(n) => format!("[[{table}]] '{n}'"),
        None => format!("[[{table}]] number {}", index + 1),
    }
}

/// `; did you mean 'x'?` when one of `known` is near `word`.
fn hint<'a>(word: &str, known: impl IntoIterator<Item = &'a str>) -> String {
    nearest(word, known).map_or_else(String::new, |k| format!("; did you mean '{k}'?"))
}

impl Builder<'_> {
    /// Every `[[equation]]`, `[[mpc]]` and `[[tie]]` as equations; the ties'
    /// ADJUST applied to the nodes.
    pub(super) fn constraints(
        &mut self,
        raw: &RawModel,
        known: &HashSet<NodeId>,
    ) -> Result<FileConstraints, InputError> {
        let mut out = FileConstraints::default();
        self.equations(raw, known, &mut out)?;
        self.mpcs(raw, known, &mut out)?;
        let moved = self.ties(raw, known, &mut out)?;
        for (id, x) in moved {
            if let Some(&i) = self.node_index.get(&id) {
                self.nodes[i].coords = x;
            }
        }
        Ok(out)
    }

    /// `[[equation]]`: `terms = [{ node, dof, coefficient }, ..]`.
    fn equations(
        &self,
        raw: &RawModel,
        known: &HashSet<NodeId>,
        out: &mut FileConstraints,
    ) -> Result<(), InputError> {
        for (k, e) in raw.equation.iter().enumerate() {
            let r = e.get_ref();
            let name = label("equation", r.name.as_deref(), k);
            out.claim(&self.src, &name, e)?;
            if r.terms.is_empty() {
                return Err(self.src.at(e, format!("{name} has no terms")));
            }
            let mut terms = Vec::with_capacity(r.terms.len());
            for t in &r.terms {
                let term = t.get_ref();
                self.check_node(known, term.node, t.span().start, &name)?;
                terms.push((Dof::new(term.node, term.dof), term.coefficient));
            }
            out.equations.push(Equation { name, terms });
        }
        Ok(())
    }

    /// `[[mpc]]`: `kind` and `nodes`, the equations of
    /// [`flexbody_fem::MpcKind::equations`] at the nodes' positions.
    fn mpcs(
        &self,
        raw: &RawModel,
        known: &HashSet<NodeId>,
        out: &mut FileConstraints,
    ) -> Result<(), InputError> {
        for (k, m) in raw.mpc.iter().enumerate() {
            let r = m.get_ref();
            let name = label("mpc", r.name.as_deref(), k);
            out.claim(&self.src, &name, m)?;
            let mut x = Vec::with_capacity(r.nodes.len());
            for &n in &r.nodes {
                self.check_node(known, n, m.span().start, &name)?;
                let p = self.position(n).ok_or_else(|| {
                    self.src.at(
                        m,
                        format!("{name} refers to node {n}, which has no position"),
                    )
                })?;
                x.push(p);
            }
            let equations = r
                .kind
                .equations(&name, &r.nodes, &x)
                .map_err(|e| self.src.at(m, e.to_string()))?;
            out.equations.extend(equations);
        }
        Ok(())
    }

    /// `[[tie]]`: its equations (named `tie 'NAME'`, as the deck's) and the
    /// slave nodes' new positions, from the positions before any tie.
    fn ties(
        &self,
        raw: &RawModel,
        known: &HashSet<NodeId>,
        out: &mut FileConstraints,
    ) -> Result<Vec<(NodeId, [f64; 3])>, InputError> {
        let solids: HashMap<usize, &Solid> = self
            .elements
            .iter()
            .filter_map(|e| match e {
                Element::Solid(s) => Some((s.id, s)),
                _ => None,
            })
            .collect();
        let mut moved = Vec::new();
        for t in &raw.tie {
            let r = t.get_ref();
            let name = format!("tie '{}'", r.name);
            if self.deck_equations.iter().any(|e| e.name == name) {
                return Err(self
                    .src
                    .at(t, format!("{name}: the deck has a *TIE of that name")));
            }
            out.claim(&self.src, &name, t)?;
            let slaves = self.tie_slaves(t, known, &name)?;
            let mut master = Vec::new();
            if let Some(surface) = &r.master {
                master.extend(self.surface_faces(t, &name, surface, &solids)?);
            }
            if let Some(set) = &r.master_elements {
                let members = self.deck_set_solids(t, &name, set, &solids)?;
                master.extend(exterior_faces(members));
            }
            if r.master.is_none() && r.master_elements.is_none() {
                return Err(self.src.at(
                    t,
                    format!(
                        "{name}: give its master faces: `master` (an element surface of the \
                         deck) and/or `master_elements` (an element set of the deck)"
                    ),
                ));
            }
            let tie = Tie {
                name: r.name.clone(),
                slaves,
                master,
                tolerance: r.tolerance,
                adjust: r.adjust,
            };
            let made = tie
                .equations(&|n| self.position(n))
                .map_err(|e| self.src.at(t, e.to_string()))?;
            out.equations.extend(made.equations);
            moved.extend(made.moved);
        }
        Ok(moved)
    }

    /// The slave nodes of a tie: its node set (`set`) or `nodes`.
    fn tie_slaves(
        &self,
        t: &Spanned<RawTie>,
        known: &HashSet<NodeId>,
        what: &str,
    ) -> Result<Vec<NodeId>, InputError> {
        let r = t.get_ref();
        let slaves = match (&r.set, &r.nodes) {
            (Some(set), None) => {
                let key = self.sets.keys().find(|k| k.eq_ignore_ascii_case(set));
                match key {
                    Some(k) => self.sets[k].clone(),
                    None => {
                        let hint = hint(set, self.sets.keys().map(String::as_str));
                        return Err(self
                            .src
                            .at(t, format!("{what}: node set '{set}' does not exist{hint}")));
                    }
                }
            }
            (None, Some(list)) => {
                for n in list {
                    self.check_node(known, *n, t.span().start, what)?;
                }
                list.clone()
            }
            _ => {
                return Err(self.src.at(
                    t,
                    format!("{what}: give its slave nodes as either `set` or `nodes`"),
                ))
            }
        };
        if slaves.is_empty() {
            return Err(self.src.at(t, format!("{what}: it has no slave nodes")));
        }
        Ok(slaves)
    }

    /// The faces of the deck's element surface `surface`.
    fn surface_faces(
        &self,
        t: &Spanned<RawTie>,
        what: &str,
        surface: &str,
        solids: &HashMap<usize, &Solid>,
    ) -> Result<Vec<Face>, InputError> {
        let key = surface.trim().to_uppercase();
        let Some(lines) = self.deck_surfaces.get(&key) else {
            let hint = hint(&key, self.deck_surfaces.keys().map(String::as_str));
            return Err(self.src.at(
                t,
                format!(
                    "{what}: master surface '{surface}' is not an element surface of the deck \
                     (*SURFACE, TYPE=ELEMENT){hint}"
                ),
            ));
        };
        let mut faces = Vec::new();
        for line in lines {
            let members = match line.elements.parse::<usize>() {
                Ok(id) => vec![self.solid(t, what, id, solids)?],
                Err(_) => self.deck_set_solids(t, what, &line.elements, solids)?,
            };
            for solid in members {
                let local = solid_face(solid.kind, line.face).ok_or_else(|| {
                    self.src.at(
                        t,
                        format!(
                            "{what}: surface '{key}': a {} element ({}) has no face S{}",
                            solid.kind.name(),
                            solid.id,
                            line.face
                        ),
                    )
                })?;
                faces.push(Face {
                    nodes: local.iter().map(|&i| solid.nodes[i]).collect(),
                });
            }
        }
        Ok(faces)
    }

    /// The solids of the deck's element set `set`.
    fn deck_set_solids<'s>(
        &self,
        t: &Spanned<RawTie>,
        what: &str,
        set: &str,
        solids: &HashMap<usize, &'s Solid>,
    ) -> Result<Vec<&'s Solid>, InputError> {
        let key = set.trim().to_uppercase();
        let Some(ids) = self.deck_element_sets.get(&key) else {
            let hint = hint(&key, self.deck_element_sets.keys().map(String::as_str));
            return Err(self.src.at(
                t,
                format!("{what}: element set '{set}' is not an element set of the deck{hint}"),
            ));
        };
        ids.iter()
            .map(|&id| self.solid(t, what, id, solids))
            .collect()
    }

    /// Solid element `id`, or an error: ties join solid faces.
    fn solid<'s>(
        &self,
        t: &Spanned<RawTie>,
        what: &str,
        id: usize,
        solids: &HashMap<usize, &'s Solid>,
    ) -> Result<&'s Solid, InputError> {
        solids.get(&id).copied().ok_or_else(|| {
            let is = if self.elements.iter().any(|e| e.id() == id) {
                "is not a solid element (ties join solid faces)"
            } else {
                "does not exist"
            };
            self.src.at(t, format!("{what}: master element {id} {is}"))
        })
    }
}
