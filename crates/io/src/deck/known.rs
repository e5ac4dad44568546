//! The keywords the deck reader knows: those it reads, those it skips
//! because they do not change K, M or D of the linear model, and those it
//! refuses; and the nearest of them to an unknown keyword, for the error
//! that refuses it.

/// Keywords read, as they are written (spaces are ignored when matching).
pub(super) const READ: &[&str] = &[
    "NODE",
    "ELEMENT",
    "NSET",
    "ELSET",
    "BOUNDARY",
    "MATERIAL",
    "ELASTIC",
    "DENSITY",
    "ORIENTATION",
    "SOLID SECTION",
    "BEAM SECTION",
    "MASS",
    "SPRING",
    "DASHPOT",
    "DAMPING",
    "MODAL DAMPING",
    "INSTANCE",
    "SURFACE",
    "COUPLING",
    "KINEMATIC",
    "DISTRIBUTING",
    "INCLUDE",
    "EQUATION",
    "MPC",
    "RIGID BODY",
    "DISTRIBUTING COUPLING",
    "TIE",
    "TRANSFORM",
    "CONTACT PAIR",
    "SURFACE INTERACTION",
    "SURFACE BEHAVIOR",
];

/// Keywords skipped with a warning: they do not change the stiffness, the
/// mass or the damping of the linear model (steps, loads, output, thermal
/// and nonlinear material data, definitions only used by refused keywords).
/// `*FREQUENCY` and `*STATIC` ignore damping, as in CalculiX.
pub(super) const IGNORED: &[&str] = &[
    "HEADING",
    "PREPRINT",
    "STEP",
    "ENDSTEP",
    "STATIC",
    "FREQUENCY",
    "BUCKLE",
    "DYNAMIC",
    "MODALDYNAMIC",
    "STEADYSTATEDYNAMICS",
    "COMPLEXFREQUENCY",
    "HEATTRANSFER",
    "COUPLEDTEMPERATURE-DISPLACEMENT",
    "UNCOUPLEDTEMPERATURE-DISPLACEMENT",
    "VISCO",
    "GREEN",
    "SENSITIVITY",
    "NODEFILE",
    "ELFILE",
    "NODEPRINT",
    "ELPRINT",
    "CONTACTFILE",
    "CONTACTPRINT",
    "SECTIONPRINT",
    "NODEOUTPUT",
    "ELEMENTOUTPUT",
    "CONTACTOUTPUT",
    "OUTPUT",
    "CLOAD",
    "DLOAD",
    "DSLOAD",
    "CFLUX",
    "DFLUX",
    "FILM",
    "RADIATE",
    "TEMPERATURE",
    "INITIALCONDITIONS",
    "RESTART",
    "AMPLITUDE",
    "TIMEPOINTS",
    "PHYSICALCONSTANTS",
    "VALUESATINFINITY",
    "FRICTION",
    "GAPCONDUCTANCE",
    "CONTROLS",
    "FILEFORMAT",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFICHEAT",
    "PLASTIC",
    "CYCLICHARDENING",
    "CREEP",
    "DEPVAR",
    "SELECTCYCLICSYMMETRYMODES",
    "PART",
    "ENDPART",
    "ASSEMBLY",
    "ENDASSEMBLY",
    "ENDINSTANCE",
];

/// Keywords refused because ignoring them would change the model, with
/// what they would change.
pub(super) const REFUSED: &[(&str, &str)] = &[
    (
        "KINEMATICCOUPLING",
        "stiffness matrix (constraints between DOFs)",
    ),
    ("CONTACT", "stiffness matrix"),
    ("GAP", "stiffness matrix"),
    ("MEMBRANESECTION", "stiffness and mass matrices"),
    ("BEAMGENERALSECTION", "stiffness and mass matrices"),
    ("FLUIDSECTION", "stiffness and mass matrices"),
    ("CONNECTORSECTION", "stiffness and mass matrices"),
    ("NODALTHICKNESS", "stiffness and mass matrices"),
    ("NORMAL", "stiffness matrix (beam and shell directions)"),
    ("SYSTEM", "node coordinates"),
    ("ROTARYINERTIA", "mass matrix"),
    ("NONSTRUCTURALMASS", "mass matrix"),
    ("USERELEMENT", "stiffness and mass matrices"),
    ("USERMATERIAL", "stiffness matrix (material)"),
    ("HYPERELASTIC", "stiffness matrix (material)"),
    ("HYPERFOAM", "stiffness matrix (material)"),
    ("DEFORMATIONPLASTICITY", "stiffness matrix (material)"),
    ("PRE-TENSIONSECTION", "stiffness matrix"),
    ("MODELCHANGE", "stiffness and mass matrices"),
    ("CYCLICSYMMETRYMODEL", "stiffness and mass matrices"),
    ("SUBMODEL", "boundary conditions"),
    ("NGEN", "model (it creates nodes)"),
    ("NFILL", "model (it creates nodes)"),
    ("NCOPY", "model (it creates nodes)"),
    ("ELGEN", "model (it creates elements)"),
    ("ELCOPY", "model (it creates elements)"),
    (
        "MATRIXASSEMBLE",
        "stiffness and mass matrices (user matrices added to them)",
    ),
    ("MATRIXINPUT", "stiffness and mass matrices (user matrices)"),
];

/// The known keyword nearest to `keyword` (upper case, no spaces), as it
/// is written, when it is close enough to be a misspelling.
pub(super) fn nearest_known(keyword: &str) -> Option<&'static str> {
    let known = READ
        .iter()
        .chain(IGNORED)
        .chain(REFUSED.iter().map(|(k, _)| k))
        .copied();
    crate::spelling::nearest(keyword, known)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_known_keywords() {
        // Read, skipped and refused keywords are all suggested.
        assert_eq!(nearest_known("BOUNDRY"), Some("BOUNDARY"));
        assert_eq!(nearest_known("BEAMSECTON"), Some("BEAM SECTION"));
        assert_eq!(nearest_known("HEDING"), Some("HEADING"));
        assert_eq!(nearest_known("EQUATON"), Some("EQUATION"));
        assert_eq!(nearest_known("XYZZY"), None);
    }
}
