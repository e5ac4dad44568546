//! `[[beam_line]]`: equally spaced points along a straight line and the
//! beams between them. Lines that meet share the node they meet at: a point
//! of a line at an existing node (within [`RELATIVE_TOLERANCE`] of the
//! model's size) is that node, and `start_node` / `end_node` name the
//! existing node a line starts or ends at. Point `i` is otherwise a new
//! node `first_node + i`; that id on another position is an error naming
//! both definitions.

use super::Builder;
use crate::model_toml::raw::{BeamKind, RawBeamLine, RawModel};
use crate::InputError;
use flexbody_fem::element::{Beam, PlanarBeam};
use flexbody_fem::{BeamTheory, Element};
use flexbody_linalg::memory::Budget;
use toml::Spanned;

/// The memory one beam element takes at least, from its line to the
/// assembled model: the element and its node, and its share of the
/// columns of K and M. A line of more elements than the memory left holds
/// at this size is refused before any is made.
pub(crate) const BEAM_ELEMENT_BYTES: u64 = 4096;

/// Two points closer than this times the diagonal of the bounding box of
/// the explicit nodes and the lines' end points are the same point.
pub(crate) const RELATIVE_TOLERANCE: f64 = 1e-6;

impl Builder<'_> {
    /// Every `[[beam_line]]` in order: its nodes (shared or new), its
    /// elements and its node set.
    pub(super) fn beam_lines(&mut self, raw: &RawModel, memory: &Budget) -> Result<(), InputError> {
        let mut total: u64 = 0;
        for line in &raw.beam_line {
            total = total.saturating_add(line.get_ref().elements as u64);
            memory
                .ensure(
                    total.saturating_mul(BEAM_ELEMENT_BYTES),
                    &format!(
                        "beam_line: {total} beam elements (at least {BEAM_ELEMENT_BYTES} bytes each)"
                    ),
                )
                .map_err(|e| self.src.at(line, e.to_string()))?;
        }
        let ends = raw
            .beam_line
            .iter()
            .map(|line| self.line_ends(line, f64::INFINITY))
            .collect::<Result<Vec<_>, _>>()?;
        let tolerance = RELATIVE_TOLERANCE * self.extent(ends.iter().flatten().flatten());
        let mut next_element = 1;
        for line in &raw.beam_line {
            let b = line.get_ref();
            let offset = line.span().start;
            if b.elements == 0 {
                return Err(self.src.at(line, "beam_line needs at least one element"));
            }
            let p = self.properties(&b.material, &b.section, b.theory, b.rotary_inertia)?;
            if b.element == BeamKind::PlanarBeam && b.theory != BeamTheory::EulerBernoulli {
                return Err(self.src.at(line, "planar-beam elements are Euler-Bernoulli; use element = \"beam\" for Timoshenko"));
            }
            for (key, node) in [("start_node", b.start_node), ("end_node", b.end_node)] {
                if let Some(id) = node.filter(|id| self.position(*id).is_none()) {
                    return Err(self.src.at(
                        line,
                        format!("beam_line: {key} = {id} does not exist (name a node of `nodes` or of an earlier beam_line)"),
                    ));
                }
            }
            let [from, to] = self
                .line_ends(line, tolerance)?
                .map(|end| end.unwrap_or_default());
            let length = (0..3)
                .map(|k| (to[k] - from[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            if length <= tolerance {
                return Err(self.src.at(line, "beam_line has zero length"));
            }
            let mut ids = Vec::with_capacity(b.elements + 1);
            for i in 0..=b.elements {
                let t = i as f64 / b.elements as f64;
                let c = [0, 1, 2].map(|k| from[k] + t * (to[k] - from[k]));
                let named = match i {
                    0 => b.start_node,
                    i if i == b.elements => b.end_node,
                    _ => None,
                };
                let id = match named {
                    Some(id) => id,
                    None => self.line_point(line, i, c, tolerance)?,
                };
                ids.push(id);
            }
            let first = b.first_element.unwrap_or(next_element);
            for i in 0..b.elements {
                let id = first + i;
                let nodes = [ids[i], ids[i + 1]];
                let e = match b.element {
                    BeamKind::PlanarBeam => Element::PlanarBeam(PlanarBeam {
                        id,
                        nodes,
                        properties: p.clone(),
                    }),
                    BeamKind::Beam => Element::Beam(Beam {
                        id,
                        nodes,
                        properties: p.clone(),
                        orientation: b.orientation.ok_or_else(|| {
                            self.src.at(
                                line,
                                "beam_line of 3D beams needs an orientation (local y direction)",
                            )
                        })?,
                    }),
                };
                self.add_element(e, offset)?;
            }
            next_element = first + b.elements;
            if let Some(set) = &b.set {
                self.sets.entry(set.clone()).or_default().extend(ids);
            }
        }
        Ok(())
    }

    /// The start and end point of a line: given, or the position of the
    /// named node (`None` while that node is not defined yet). A given
    /// point must be within `tolerance` of the named node.
    fn line_ends(
        &self,
        line: &Spanned<RawBeamLine>,
        tolerance: f64,
    ) -> Result<[Option<[f64; 3]>; 2], InputError> {
        let b = line.get_ref();
        let end = |point: Option<[f64; 3]>, node: Option<u64>, key: &str, node_key: &str| {
            let at = node.and_then(|id| self.position(id));
            match (point, node, at) {
                (None, None, _) => Err(self.src.at(
                    line,
                    format!("beam_line needs `{key}` (a point) or `{node_key}` (an existing node)"),
                )),
                (Some(p), Some(id), Some(x)) if distance(p, x) > tolerance => Err(self.src.at(
                    line,
                    format!(
                        "beam_line: `{key}` = {p:?} is not where `{node_key}` = {id} is ({x:?})"
                    ),
                )),
                (Some(p), _, _) => Ok(Some(p)),
                (None, Some(_), at) => Ok(at),
            }
        };
        Ok([
            end(b.from, b.start_node, "from", "start_node")?,
            end(b.to, b.end_node, "to", "end_node")?,
        ])
    }

    /// The diagonal of the bounding box of the nodes so far and `points`.
    fn extent<'p>(&self, points: impl Iterator<Item = &'p [f64; 3]>) -> f64 {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in self.nodes.iter().map(|n| n.coords).chain(points.copied()) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if lo[0] > hi[0] {
            return 0.0;
        }
        distance(lo, hi)
    }

    /// Point `i` of a line at `c`: the existing node there (the line's own
    /// id first), else the new node `first_node + i`.
    fn line_point(
        &mut self,
        line: &Spanned<RawBeamLine>,
        i: usize,
        c: [f64; 3],
        tolerance: f64,
    ) -> Result<u64, InputError> {
        let b = line.get_ref();
        let own = b.first_node.map(|f| f + i as u64);
        if b.share_nodes {
            let at_own = own.filter(|id| {
                self.position(*id)
                    .is_some_and(|x| distance(x, c) <= tolerance)
            });
            let existing = at_own.or_else(|| {
                self.nodes
                    .iter()
                    .find(|n| distance(n.coords, c) <= tolerance)
                    .map(|n| n.id)
            });
            if let Some(id) = existing {
                return Ok(id);
            }
        }
        let Some(id) = own else {
            return Err(self.src.at(
                line,
                format!("beam_line needs `first_node`: its point {i} at {c:?} is no existing node"),
            ));
        };
        if let (Some(x), Some(first)) = (self.position(id), self.node_line.get(&id)) {
            return Err(self.src.at(
                line,
                format!(
                    "node {id} is defined twice: at {c:?} by this beam_line and at {x:?} on line {first}"
                ),
            ));
        }
        self.add_node(id, c, line.span().start)?;
        Ok(id)
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}
