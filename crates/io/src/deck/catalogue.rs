//! What a deck defines by name, for `flexbody info`: its materials and
//! its property keywords (sections) with the element sets they apply to.

use super::keywords::Reader;
use super::properties::SectionData;
use serde::Serialize;

/// A `*MATERIAL` as read: name, `E` (Pa), `nu`, density (kg/m^3).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MaterialEntry {
    pub name: String,
    pub youngs_modulus: Option<f64>,
    pub poisson: Option<f64>,
    pub density: Option<f64>,
}

/// A property keyword (`*SOLID SECTION`, `*BEAM SECTION`, `*MASS`,
/// `*SPRING`), the element set it applies to and its material.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SectionEntry {
    pub keyword: String,
    pub elset: String,
    pub material: Option<String>,
    /// Elements of the set.
    pub elements: usize,
    /// The mass of a `*MASS` (kg), where it is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
}

/// The named definitions of a deck.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Catalogue {
    pub materials: Vec<MaterialEntry>,
    pub sections: Vec<SectionEntry>,
}

impl Catalogue {
    pub(super) fn of(reader: &Reader<'_>) -> Catalogue {
        let materials = reader
            .materials
            .iter()
            .map(|m| MaterialEntry {
                name: m.name.clone(),
                youngs_modulus: m.elastic.map(|e| e.0),
                poisson: m.elastic.map(|e| e.1),
                density: m.density.map(|d| d.0),
            })
            .collect();
        let sections = reader
            .sections
            .iter()
            .map(|s| SectionEntry {
                keyword: s.keyword.clone(),
                elset: s.elset.clone(),
                material: s.material.clone(),
                elements: reader.element_sets.get(&s.elset).map_or(0, Vec::len),
                mass: match s.data {
                    SectionData::Mass(m) => Some(m),
                    _ => None,
                },
            })
            .collect();
        Catalogue {
            materials,
            sections,
        }
    }
}
