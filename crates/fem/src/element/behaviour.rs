//! What every element type provides: the contract through which the
//! assembler, the model's checks, recovery and the VTK writer use an
//! element without knowing its type.

use super::{ElementMatrices, MassDistribution, SectionForces};
use crate::dof::Dof;
use crate::model::{Model, NodeId, Rayleigh};
use crate::FemError;

/// The behaviour of one element: its connectivity, its matrices and what
/// recovery computes from its displacements. Each element type implements
/// it in its own file of `element/` and is registered once in
/// [`Element`](super::Element) (and, if decks name it, in
/// [`ELEMENT_TYPES`](super::ELEMENT_TYPES)); see `docs/elements.md`.
///
/// `model` is the checked model the element belongs to: its nodes exist,
/// and its DOF map holds the DOFs the elements create.
pub trait ElementBehaviour {
    /// Element number (user id).
    fn id(&self) -> usize;

    /// The nodes the element connects, in its node order.
    fn nodes(&self) -> Vec<NodeId>;

    /// The DOFs the element acts on (before any are fixed): the rows and
    /// columns of its matrices, and the order of the element values `u_e`
    /// and `a_e` given to [`Self::section_forces`] and [`Self::stresses`].
    fn dofs(&self) -> Vec<Dof>;

    /// True if the element gives its nodes the DOFs of [`Self::dofs`]
    /// (it has stiffness). An element that does not (a point mass, a
    /// dashpot) only loads the DOFs others create: the assembler drops the
    /// rows and columns of its DOFs the model does not have, as it drops
    /// fixed ones, and carries those a coupling eliminated through the
    /// coupling's constraint, as for every element.
    fn creates_dofs(&self) -> bool {
        true
    }

    /// True if [`Self::matrices`] gives a damping matrix of the element's
    /// own ([`ElementMatrices::damping`]: a dashpot). The default: none.
    fn has_damping(&self) -> bool {
        false
    }

    /// Rayleigh damping of the element's material (Abaqus `*DAMPING,
    /// ALPHA=, BETA=`): [`Element::matrices`](super::Element::matrices)
    /// adds `alpha M_e + beta K_e` to the element's damping matrix. The
    /// default: none.
    fn material_damping(&self) -> Option<Rayleigh> {
        None
    }

    /// Checks the element's geometry and data (length, orientation,
    /// volume, material) without building its matrices. The default
    /// accepts every element.
    fn validate(&self, _model: &Model) -> Result<(), FemError> {
        Ok(())
    }

    /// Stiffness, mass and (dashpots) damping in global DOFs, symmetric;
    /// material damping is added by
    /// [`Element::matrices`](super::Element::matrices), not here.
    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError>;

    /// Where the element's mass is in space ([`MassDistribution`]), for
    /// the floating-frame invariants. The default: the nodal form of an
    /// isoparametric element with consistent mass (translations only,
    /// `M_e = S (x) I_3`), read from [`Self::matrices`]; an element whose
    /// mass is not of that form is refused, naming it.
    fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        MassDistribution::nodal(self.id(), &self.matrices(model)?)
    }

    /// True if [`Self::section_forces`] gives section forces (beams).
    fn has_section_forces(&self) -> bool {
        false
    }

    /// Report eq. 25 for one element: the end forces `K_e u_e + M_e a_e`
    /// as section forces at both ends; `None` for elements without
    /// section forces (the default).
    fn section_forces(
        &self,
        _model: &Model,
        _u_e: &[f64],
        _a_e: &[f64],
    ) -> Result<Option<SectionForces>, FemError> {
        Ok(None)
    }

    /// True if [`Self::stresses`] gives stresses (solids, shells).
    fn has_stresses(&self) -> bool {
        false
    }

    /// The layers [`Self::stresses`] gives at each node: one value through
    /// the volume (solids, the default), or the bottom, middle and top
    /// surfaces (shells).
    fn stress_layers(&self) -> &'static [StressLayer] {
        &[StressLayer::Volume]
    }

    /// Stresses at the element's nodes (Pa, global Voigt `[sxx, syy, szz,
    /// sxy, syz, szx]`) of `columns` displacement fields given one after
    /// the other in `u_e` (each in the order of [`Self::dofs`]): entry
    /// `(j L + l) n + a` is node `a`'s stress on layer `l` of
    /// [`Self::stress_layers`] in field `j`, `n` the node count and `L` the
    /// number of layers. `None` for elements without stresses (the
    /// default).
    fn stresses(
        &self,
        _model: &Model,
        _u_e: &[f64],
        _columns: usize,
    ) -> Result<Option<Vec<[f64; 6]>>, FemError> {
        Ok(None)
    }

    /// The VTK cell that draws the element, `None` for none (the default).
    fn vtk_cell(&self) -> Option<VtkCell> {
        None
    }
}

/// Where at a node an element gives its stress: through the volume (a
/// solid's one value per node) or on a shell's bottom (`-n/2` along its
/// normal), middle or top surface. Ordered as listed.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum StressLayer {
    Volume,
    Bottom,
    Middle,
    Top,
}

impl StressLayer {
    /// `""` for the volume, else `"bottom"`, `"middle"`, `"top"`: the suffix
    /// of a stress's name in outputs.
    pub const fn name(self) -> &'static str {
        match self {
            StressLayer::Volume => "",
            StressLayer::Bottom => "bottom",
            StressLayer::Middle => "middle",
            StressLayer::Top => "top",
        }
    }
}

/// A VTK cell: its type number (VTK's `VTKCellType`) and the element's
/// nodes in VTK's order, as indices into [`ElementBehaviour::nodes`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct VtkCell {
    pub cell_type: u8,
    pub order: &'static [usize],
}

/// `0, 1, 2, ...`: the prefix of length `n` is the order of a cell whose
/// nodes VTK numbers as the element does.
const IN_ORDER: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
];

impl VtkCell {
    /// A vertex (`VTK_VERTEX`) at a one-node element.
    pub const VERTEX: VtkCell = VtkCell::in_order(1, 1);
    /// A line (`VTK_LINE`) between the nodes of a two-node element.
    pub const LINE: VtkCell = VtkCell::in_order(3, 2);

    /// A cell of type `cell_type` over the element's first `nodes` nodes in
    /// their own order (at most 20).
    pub const fn in_order(cell_type: u8, nodes: usize) -> VtkCell {
        VtkCell {
            cell_type,
            order: IN_ORDER.split_at(nodes).0,
        }
    }
}
