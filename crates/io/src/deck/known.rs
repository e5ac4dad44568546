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
];

/// Keywords skipped with a warning: they do not change the stiffness or
/// the mass of the linear model (steps, loads, output, thermal and
/// nonlinear material data, definitions only used by refused keywords).
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
    "SURFACEINTERACTION",
    "SURFACEBEHAVIOR",
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
    "DAMPING",
    "MODALDAMPING",
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
    ("TIE", "stiffness matrix (constraints between DOFs)"),
    ("CONTACTPAIR", "stiffness matrix"),
    ("CONTACT", "stiffness matrix"),
    ("GAP", "stiffness matrix"),
    ("SHELLSECTION", "stiffness and mass matrices"),
    ("MEMBRANESECTION", "stiffness and mass matrices"),
    ("BEAMGENERALSECTION", "stiffness and mass matrices"),
    ("FLUIDSECTION", "stiffness and mass matrices"),
    ("CONNECTORSECTION", "stiffness and mass matrices"),
    ("NODALTHICKNESS", "stiffness and mass matrices"),
    ("NORMAL", "stiffness matrix (beam and shell directions)"),
    ("TRANSFORM", "stiffness matrix (DOF directions at nodes)"),
    ("SYSTEM", "node coordinates"),
    ("ROTARYINERTIA", "mass matrix"),
    ("NONSTRUCTURALMASS", "mass matrix"),
    ("DASHPOT", "damping matrix"),
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
    nearest(keyword, known)
}

/// The known keyword nearest to `keyword` (both upper case without spaces)
/// when it is close enough to be a misspelling: at most 1 edit for
/// keywords of up to 4 letters, 2 for longer ones.
pub(super) fn nearest<'a>(
    keyword: &str,
    known: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let limit = if keyword.chars().count() <= 4 { 1 } else { 2 };
    known
        .into_iter()
        .map(|k| (edit_distance(keyword, &k.replace(' ', "")), k))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Levenshtein distance (insertions, deletions, substitutions).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != *cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_nearest() {
        assert_eq!(edit_distance("BOUNDRY", "BOUNDARY"), 1);
        assert_eq!(edit_distance("ELASTC", "ELASTIC"), 1);
        assert_eq!(edit_distance("NODE", "NSET"), 3);
        assert_eq!(edit_distance("", "ABC"), 3);
        let known = ["BOUNDARY", "SOLID SECTION", "NODE", "NSET"];
        assert_eq!(nearest("BOUNDRY", known), Some("BOUNDARY"));
        assert_eq!(nearest("SOLIDSECTON", known), Some("SOLID SECTION"));
        assert_eq!(nearest("NOD", known), Some("NODE"));
        assert_eq!(nearest("FOOBAR", known), None);
        // Short keywords take one edit only.
        assert_eq!(nearest("NSAT", ["NODE"]), None);
        // Read, skipped and refused keywords are all suggested.
        assert_eq!(nearest_known("BOUNDRY"), Some("BOUNDARY"));
        assert_eq!(nearest_known("BEAMSECTON"), Some("BEAM SECTION"));
        assert_eq!(nearest_known("HEDING"), Some("HEADING"));
        assert_eq!(nearest_known("EQUATON"), Some("EQUATION"));
        assert_eq!(nearest_known("XYZZY"), None);
    }
}
