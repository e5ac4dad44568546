//! Materials and beam cross-sections (SI units).

use crate::anisotropy::Anisotropy;
use crate::model::Rayleigh;
use crate::{require_non_negative, require_positive, FemError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Linear elastic material: isotropic (E, nu), or anisotropic for solids
/// ([`Material::anisotropy`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Young's modulus E (Pa); zero and unused if the material is
    /// anisotropic.
    pub youngs_modulus: f64,
    /// Shear modulus G (Pa).
    pub shear_modulus: f64,
    /// Poisson's ratio nu.
    pub poisson_ratio: f64,
    /// Density (kg/m^3).
    pub density: f64,
    /// Rayleigh damping of the material (Abaqus `*DAMPING, ALPHA=, BETA=`):
    /// each element of it adds `alpha M_e + beta K_e` to D.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<Rayleigh>,
    /// Anisotropic elasticity (solids only): when given, it replaces E, nu
    /// and G, and beams refuse the material.
    #[serde(skip)]
    pub anisotropy: Option<Arc<Anisotropy>>,
}

impl Material {
    /// What makes this material unusable for an element, if anything: a
    /// density that is negative or not finite, and for an isotropic
    /// material a Young's modulus that is not positive and finite or a
    /// Poisson's ratio outside (-1, 0.5). The elements' checks name the
    /// element with it.
    pub(crate) fn problem(&self) -> Option<String> {
        if self.anisotropy.is_none() {
            if !(self.youngs_modulus.is_finite() && self.youngs_modulus > 0.0) {
                return Some(format!(
                    "Young's modulus must be positive and finite, got {}",
                    self.youngs_modulus
                ));
            }
            if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
                return Some(format!(
                    "Poisson's ratio must be between -1 and 0.5, got {}",
                    self.poisson_ratio
                ));
            }
        }
        (!(self.density.is_finite() && self.density >= 0.0)).then(|| {
            format!(
                "density must be zero or positive and finite, got {}",
                self.density
            )
        })
    }

    /// Material from E, Poisson's ratio nu and density; G = E / (2 (1 + nu)).
    pub fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Result<Self, FemError> {
        require_positive("Young's modulus", youngs_modulus)?;
        if !(poisson_ratio > -1.0 && poisson_ratio < 0.5) {
            return Err(FemError::InvalidValue {
                what: "Poisson's ratio".into(),
                rule: "between -1 and 0.5",
                value: poisson_ratio,
            });
        }
        require_non_negative("density", density)?;
        Ok(Self {
            youngs_modulus,
            shear_modulus: youngs_modulus / (2.0 * (1.0 + poisson_ratio)),
            poisson_ratio,
            density,
            damping: None,
            anisotropy: None,
        })
    }

    /// The material with Rayleigh damping `alpha M_e + beta K_e` in each of
    /// its elements; `alpha` (1/s) and `beta` (s) must not be negative.
    pub fn with_damping(self, damping: Rayleigh) -> Result<Self, FemError> {
        require_non_negative("material damping alpha (1/s)", damping.alpha)?;
        require_non_negative("material damping beta (s)", damping.beta)?;
        Ok(Self {
            damping: Some(damping),
            ..self
        })
    }

    /// An anisotropic material for solids: elasticity `anisotropy` (its
    /// `C` checked by [`Anisotropy::new`]) and density.
    pub fn anisotropic(anisotropy: Anisotropy, density: f64) -> Result<Self, FemError> {
        require_non_negative("density", density)?;
        Ok(Self {
            youngs_modulus: 0.0,
            shear_modulus: 0.0,
            poisson_ratio: 0.0,
            density,
            damping: None,
            anisotropy: Some(Arc::new(anisotropy)),
        })
    }
}

/// Beam theory of an element.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BeamTheory {
    /// Shear-rigid; no rotary inertia unless asked for.
    #[default]
    EulerBernoulli,
    /// Shear-flexible (shear areas), with rotary inertia.
    Timoshenko,
}

/// Cross-section shapes with their section constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SectionShape {
    /// Constants given directly. Shear areas default to the area times 5/6.
    General {
        area: f64,
        iy: f64,
        iz: f64,
        torsion: f64,
        #[serde(default)]
        shear_area_y: Option<f64>,
        #[serde(default)]
        shear_area_z: Option<f64>,
    },
    /// Solid rectangle, `width` along local y, `height` along local z.
    Rect { width: f64, height: f64 },
    /// Solid circle.
    Circ { radius: f64 },
    /// Thin- or thick-walled tube.
    Pipe { radius: f64, wall: f64 },
    /// Rectangular hollow (box) section with uniform wall, `width` along local
    /// y, `height` along local z (outer dimensions).
    Box { width: f64, height: f64, wall: f64 },
}

/// Section constants of a beam: A, Iy (about local y: bending in the x-z
/// plane), Iz (about local z), torsion constant J, shear areas.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SectionConstants {
    pub area: f64,
    pub iy: f64,
    pub iz: f64,
    pub torsion: f64,
    pub shear_area_y: f64,
    pub shear_area_z: f64,
}

impl SectionShape {
    /// The section constants; fails on non-positive dimensions.
    pub fn constants(&self) -> Result<SectionConstants, FemError> {
        use std::f64::consts::PI;
        Ok(match *self {
            SectionShape::General {
                area,
                iy,
                iz,
                torsion,
                shear_area_y,
                shear_area_z,
            } => {
                require_positive("section area", area)?;
                require_positive("section iy", iy)?;
                require_positive("section iz", iz)?;
                require_positive("section torsion constant", torsion)?;
                let asy = shear_area_y.unwrap_or(area * 5.0 / 6.0);
                let asz = shear_area_z.unwrap_or(area * 5.0 / 6.0);
                require_positive("shear area y", asy)?;
                require_positive("shear area z", asz)?;
                SectionConstants {
                    area,
                    iy,
                    iz,
                    torsion,
                    shear_area_y: asy,
                    shear_area_z: asz,
                }
            }
            SectionShape::Rect {
                width: b,
                height: h,
            } => {
                require_positive("rect width", b)?;
                require_positive("rect height", h)?;
                let (long, short) = if b >= h { (b, h) } else { (h, b) };
                // Roark: J = a b^3 (1/3 - 0.21 (b/a)(1 - (b/a)^4/12)).
                let r = short / long;
                let torsion =
                    long * short.powi(3) * (1.0 / 3.0 - 0.21 * r * (1.0 - r.powi(4) / 12.0));
                SectionConstants {
                    area: b * h,
                    iy: b * h.powi(3) / 12.0,
                    iz: h * b.powi(3) / 12.0,
                    torsion,
                    shear_area_y: b * h * 5.0 / 6.0,
                    shear_area_z: b * h * 5.0 / 6.0,
                }
            }
            SectionShape::Circ { radius: r } => {
                require_positive("circle radius", r)?;
                let i = PI * r.powi(4) / 4.0;
                SectionConstants {
                    area: PI * r * r,
                    iy: i,
                    iz: i,
                    torsion: 2.0 * i,
                    shear_area_y: 0.9 * PI * r * r,
                    shear_area_z: 0.9 * PI * r * r,
                }
            }
            SectionShape::Pipe { radius: r, wall: t } => {
                require_positive("pipe radius", r)?;
                require_positive("pipe wall", t)?;
                if t >= r {
                    return Err(FemError::InvalidValue {
                        what: "pipe wall".into(),
                        rule: "smaller than the radius",
                        value: t,
                    });
                }
                let ri = r - t;
                let area = PI * (r * r - ri * ri);
                let i = PI * (r.powi(4) - ri.powi(4)) / 4.0;
                SectionConstants {
                    area,
                    iy: i,
                    iz: i,
                    torsion: 2.0 * i,
                    shear_area_y: 0.5 * area,
                    shear_area_z: 0.5 * area,
                }
            }
            SectionShape::Box {
                width: b,
                height: h,
                wall: t,
            } => {
                require_positive("box width", b)?;
                require_positive("box height", h)?;
                require_positive("box wall", t)?;
                if 2.0 * t >= b.min(h) {
                    return Err(FemError::InvalidValue {
                        what: "box wall".into(),
                        rule: "less than half the smaller outer dimension",
                        value: t,
                    });
                }
                let (bi, hi) = (b - 2.0 * t, h - 2.0 * t);
                // Bredt: J = 4 A_m^2 / (perimeter_m / t) on the wall's mid-line.
                let (bm, hm) = (b - t, h - t);
                let torsion = 4.0 * (bm * hm).powi(2) * t / (2.0 * (bm + hm));
                SectionConstants {
                    area: b * h - bi * hi,
                    iy: (b * h.powi(3) - bi * hi.powi(3)) / 12.0,
                    iz: (h * b.powi(3) - hi * bi.powi(3)) / 12.0,
                    torsion,
                    // Webs carry the shear: 2 t h along z, 2 t b along y.
                    shear_area_y: 2.0 * t * b,
                    shear_area_z: 2.0 * t * h,
                }
            }
        })
    }
}

/// Everything a beam element needs: material and section constants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BeamProperties {
    pub material: Material,
    pub section: SectionConstants,
    pub theory: BeamTheory,
    /// Rotary inertia of the cross-section in the mass matrix. Always on for
    /// Timoshenko; optional for Euler-Bernoulli (off in the classical element).
    pub rotary_inertia: bool,
}

impl BeamProperties {
    pub fn new(material: Material, section: SectionConstants, theory: BeamTheory) -> Self {
        Self {
            material,
            section,
            theory,
            rotary_inertia: theory == BeamTheory::Timoshenko,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_section_of_the_side_beam() {
        let c = SectionShape::Box {
            width: 0.24,
            height: 0.20,
            wall: 0.012,
        }
        .constants()
        .unwrap();
        assert!((c.area - (0.24 * 0.20 - 0.216 * 0.176)).abs() < 1e-15);
        assert!((c.iy - (0.24 * 0.2f64.powi(3) - 0.216 * 0.176f64.powi(3)) / 12.0).abs() < 1e-18);
    }

    #[test]
    fn negative_density_is_rejected() {
        let e = Material::new(2.1e11, 0.3, -1.0).unwrap_err();
        assert!(e.to_string().contains("density"), "{e}");
    }
}
