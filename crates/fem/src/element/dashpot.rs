//! Viscous dashpots: along the line between two nodes (DASHPOTA), from one
//! DOF to ground (DASHPOT1) or between two DOFs (DASHPOT2). A dashpot of
//! coefficient `c` adds to the damping matrix D only (report eq. 1): the
//! force `c v` on the relative velocity `v` along its direction.
//!
//! A dashpot creates no DOFs ([`ElementBehaviour::creates_dofs`]): a DOF
//! that only a dashpot acts on would have neither stiffness nor mass. It
//! loads the DOFs other elements and couplings give its nodes; a DOF the
//! model does not have does not move, so a dashpot end there is held, as
//! on a fixed DOF.

use super::discrete::{
    axial_matrix, line_direction, scalar_dofs, scalar_element_dofs, scalar_matrix, scalar_nodes,
};
use super::registry::wrong_section;
use super::{node_dofs, Element, ElementBehaviour, ElementMatrices, ElementType};
use super::{SectionKind, SectionValues, VtkCell, TRANSLATIONS};
use crate::dof::Dof;
use crate::model::{Model, NodeId};
use crate::FemError;
use faer::Mat;

/// The deck's dashpots: DASHPOTA along the line between its nodes,
/// DASHPOT1 from one DOF to ground, DASHPOT2 between two DOFs.
pub(super) const ELEMENT_TYPES: &[ElementType] = &[
    ElementType {
        name: "DASHPOTA",
        nodes: 2,
        section: SectionKind::Dashpot { dofs: 0 },
        reference_nodes: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        build: |id, nodes, section| match (section, nodes) {
            (SectionValues::Dashpot { coefficient, .. }, &[a, b]) => Ok(AxialDashpot {
                id,
                nodes: [a, b],
                coefficient: *coefficient,
            }
            .into()),
            _ => Err(wrong_section("DASHPOTA", id, section)),
        },
    },
    ElementType {
        name: "DASHPOT1",
        nodes: 1,
        section: SectionKind::Dashpot { dofs: 1 },
        reference_nodes: &[[0.0, 0.0, 0.0]],
        build: |id, nodes, section| scalar_dashpot("DASHPOT1", id, nodes, section, false),
    },
    ElementType {
        name: "DASHPOT2",
        nodes: 2,
        section: SectionKind::Dashpot { dofs: 2 },
        reference_nodes: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        build: |id, nodes, section| scalar_dashpot("DASHPOT2", id, nodes, section, true),
    },
];

/// A DASHPOT1 (`between: false`) or DASHPOT2 on the DOFs of its section.
fn scalar_dashpot(
    name: &str,
    id: usize,
    nodes: &[NodeId],
    section: &SectionValues,
    between: bool,
) -> Result<Element, FemError> {
    let SectionValues::Dashpot { dofs, coefficient } = section else {
        return Err(wrong_section(name, id, section));
    };
    let (first, second) = scalar_dofs("dashpot", id, nodes, dofs, between)?;
    Ok(Dashpot {
        id,
        first,
        second,
        coefficient: *coefficient,
    }
    .into())
}

/// The coefficient's check: finite and not negative (a negative one would
/// feed energy into the structure).
fn check_coefficient(id: usize, c: f64) -> Result<(), FemError> {
    crate::require_non_negative(format!("dashpot element {id}: coefficient (N s/m)"), c).map(|_| ())
}

/// Dashpot of coefficient `coefficient` (N s/m, or N m s/rad on
/// rotations) on one DOF to ground or between two DOFs:
/// `D_e = c [1 -1; -1 1]` (or `[c]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Dashpot {
    pub id: usize,
    pub first: Dof,
    /// `None`: grounded dashpot.
    pub second: Option<Dof>,
    pub coefficient: f64,
}

impl ElementBehaviour for Dashpot {
    fn id(&self) -> usize {
        self.id
    }

    fn nodes(&self) -> Vec<NodeId> {
        scalar_nodes(self.first, self.second)
    }

    fn dofs(&self) -> Vec<Dof> {
        scalar_element_dofs(self.first, self.second)
    }

    fn creates_dofs(&self) -> bool {
        false
    }

    fn has_damping(&self) -> bool {
        true
    }

    fn validate(&self, _model: &Model) -> Result<(), FemError> {
        check_coefficient(self.id, self.coefficient)
    }

    fn matrices(&self, _model: &Model) -> Result<ElementMatrices, FemError> {
        check_coefficient(self.id, self.coefficient)?;
        let dofs = self.dofs();
        let n = dofs.len();
        Ok(ElementMatrices {
            dofs,
            stiffness: Mat::zeros(n, n),
            mass: Mat::zeros(n, n),
            damping: Some(scalar_matrix(self.coefficient, n)),
        })
    }

    /// A line between two DOFs' nodes, a vertex at a grounded dashpot.
    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(match self.second {
            Some(_) => VtkCell::LINE,
            None => VtkCell::VERTEX,
        })
    }
}

/// Dashpot along the line between two nodes (CalculiX and Abaqus
/// DASHPOTA, linear): with `e` the unit vector from the first node to the
/// second, `D_e = c [e e^T, -e e^T; -e e^T, e e^T]` on their translations.
#[derive(Clone, Debug, PartialEq)]
pub struct AxialDashpot {
    pub id: usize,
    pub nodes: [NodeId; 2],
    /// Coefficient c (N s/m).
    pub coefficient: f64,
}

impl ElementBehaviour for AxialDashpot {
    fn id(&self) -> usize {
        self.id
    }

    fn nodes(&self) -> Vec<NodeId> {
        self.nodes.to_vec()
    }

    fn dofs(&self) -> Vec<Dof> {
        node_dofs(&self.nodes, &TRANSLATIONS)
    }

    fn creates_dofs(&self) -> bool {
        false
    }

    fn has_damping(&self) -> bool {
        true
    }

    fn validate(&self, model: &Model) -> Result<(), FemError> {
        check_coefficient(self.id, self.coefficient)?;
        line_direction(model, self.id, self.nodes).map(|_| ())
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        check_coefficient(self.id, self.coefficient)?;
        let e = line_direction(model, self.id, self.nodes)?;
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness: Mat::zeros(6, 6),
            mass: Mat::zeros(6, 6),
            damping: Some(axial_matrix(self.coefficient, e)),
        })
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::LINE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dof::DofKind;
    use crate::Node;

    /// Two nodes 1 -> 2 along `d` (not unit), each given its translations
    /// by a stiff axial spring to a third node so that the model has them.
    fn model_along(d: [f64; 3], dashpot: Element) -> Model {
        let nodes = vec![
            Node {
                id: 1,
                coords: [0.5, -0.2, 1.0],
            },
            Node {
                id: 2,
                coords: [0.5 + d[0], -0.2 + d[1], 1.0 + d[2]],
            },
            Node {
                id: 3,
                coords: [3.0, 4.0, 5.0],
            },
        ];
        let springs = [1, 2].map(|n| {
            Element::from(crate::element::AxialSpring {
                id: 10 + n as usize,
                nodes: [n, 3],
                stiffness: 1.0,
            })
        });
        let mut elements = springs.to_vec();
        elements.push(dashpot);
        Model::of(nodes, elements).build().unwrap()
    }

    #[test]
    fn an_axial_dashpot_is_c_e_e_transposed_with_opposite_signs_across_its_nodes() {
        let d = [3.0, -1.5, 2.0];
        let l: f64 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let e = d.map(|x| x / l.sqrt());
        let c = 2.5e3;
        let dashpot = Element::from(AxialDashpot {
            id: 7,
            nodes: [1, 2],
            coefficient: c,
        });
        let model = model_along(d, dashpot.clone());
        let em = dashpot.matrices(&model).unwrap();
        assert_eq!(em.dofs, node_dofs(&[1, 2], &TRANSLATIONS));
        let de = em.damping.unwrap();
        for a in 0..2 {
            for b in 0..2 {
                let sign = if a == b { 1.0 } else { -1.0 };
                for i in 0..3 {
                    for j in 0..3 {
                        let want = sign * c * e[i] * e[j];
                        let got = de[(3 * a + i, 3 * b + j)];
                        assert!((got - want).abs() <= 1e-12 * c, "{a}{b} {i}{j}");
                    }
                }
            }
        }
        // No stiffness, no mass; a rigid translation has no damping force
        // and the relative velocity along e gives c on each node.
        assert_eq!(
            crate::element::mat_vec(&em.stiffness, &[1.0; 6]),
            vec![0.0; 6]
        );
        assert_eq!(crate::element::mat_vec(&em.mass, &[1.0; 6]), vec![0.0; 6]);
        let v = [0.0, 0.0, 0.0, e[0], e[1], e[2]];
        let f = crate::element::mat_vec(&de, &v);
        for i in 0..3 {
            assert!((f[3 + i] - c * e[i]).abs() < 1e-12 * c);
            assert!((f[i] + c * e[i]).abs() < 1e-12 * c);
        }
    }

    #[test]
    fn scalar_dashpots_and_bad_ones() {
        let model = model_along(
            [1.0, 0.0, 0.0],
            Element::from(AxialDashpot {
                id: 7,
                nodes: [1, 2],
                coefficient: 1.0,
            }),
        );
        let grounded = Dashpot {
            id: 8,
            first: Dof::new(2, DofKind::Uy),
            second: None,
            coefficient: 40.0,
        };
        let em = grounded.matrices(&model).unwrap();
        assert_eq!(em.damping.unwrap()[(0, 0)], 40.0);
        let between = Dashpot {
            second: Some(Dof::new(1, DofKind::Uz)),
            ..grounded
        };
        let de = between.matrices(&model).unwrap().damping.unwrap();
        assert_eq!(
            [de[(0, 0)], de[(0, 1)], de[(1, 0)], de[(1, 1)]],
            [40.0, -40.0, -40.0, 40.0]
        );
        let negative = AxialDashpot {
            id: 9,
            nodes: [1, 2],
            coefficient: -1.0,
        };
        let err = negative.validate(&model).unwrap_err().to_string();
        assert!(err.contains("dashpot element 9"), "{err}");
        let flat = AxialDashpot {
            id: 10,
            nodes: [1, 1],
            coefficient: 1.0,
        };
        assert!(matches!(
            flat.validate(&model),
            Err(FemError::ZeroLength { element: 10 })
        ));
    }
}
