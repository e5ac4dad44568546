//! What a deck defines by name, for `flexbody info`: its materials and
//! its property keywords (sections) with the element sets they apply to.

use super::elasticity::ElasticKind;
use super::keywords::Reader;
use super::properties::SectionData;
use serde::Serialize;

/// A `*MATERIAL` as read: name, elasticity kind (`isotropic`,
/// `orthotropic`, `anisotropic`), `E` (Pa) and `nu` of an isotropic one,
/// density (kg/m^3); the first record of temperature tables.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MaterialEntry {
    pub name: String,
    pub kind: Option<&'static str>,
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

/// The first record's `E, nu` of an isotropic material.
fn isotropic(m: &super::properties::RawMaterial) -> Option<&[f64]> {
    match &m.elastic {
        Some((ElasticKind::Isotropic, table, _)) => Some(&table.records[0].values),
        _ => None,
    }
}

impl Catalogue {
    pub(super) fn of(reader: &Reader<'_>) -> Catalogue {
        let materials = reader
            .materials
            .iter()
            .map(|m| MaterialEntry {
                name: m.name.clone(),
                kind: m.elastic.as_ref().map(|e| e.0.class()),
                youngs_modulus: isotropic(m).map(|v| v[0]),
                poisson: isotropic(m).map(|v| v[1]),
                density: m.density.as_ref().map(|d| d.0.records[0].values[0]),
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
