//! The SID dialects the reader takes, each a set of [`Rules`]: flexbody's
//! own layout, welib's (`welib/yams/sid.py`, `Beam2SID`) and PY_SID's (the
//! files of the EMBS Modelica library). The reader ([`super::read`]) asks
//! the rules and never the dialect's name, so a dialect is one more
//! constant here. What each writes differently, and how it is mapped, in
//! `docs/sid.md` (section "Dialects").

use super::ParseError;
use flexbody_io::text::{excerpt, finite_number};

/// A SID writer's layout.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// flexbody's own (`write_sid`): every entry listed, numbers that read
    /// back to the same bits.
    Flexbody,
    /// welib's `Beam2SID`: `new node = id`, symmetric blocks as their lower
    /// triangle (`structure = 2`), six decimals.
    Welib,
    /// PY_SID / EMBS: a counts line before `part`, sparse entries, Fortran
    /// `D` exponents, `J` as a 6 x 1 column, `m1` indexed (row, mode, col).
    PySid,
}

/// How `m1(a, b, c)` is indexed.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum M1Index {
    /// (row, column, coordinate): flexbody's and welib's.
    RowColCoordinate,
    /// (row, coordinate, column): PY_SID's, as the EMBS reader takes it
    /// (`getIndeces3(line, &idxr, &idxnq, &idxc)`).
    RowCoordinateCol,
}

/// How the inertia tensor `J` is written.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum JLayout {
    /// 3 x 3.
    Matrix,
    /// 6 x 1: `[xx, yy, zz, xy, xz, yz]`, the order in which the EMBS
    /// library rebuilds the tensor (`EMBS_Body` in `Components.mo`).
    Column6,
}

/// What a dialect writes differently. The reader keeps every check of the
/// strict layout (counts, indices, repeats, finiteness, symmetry) and
/// relaxes only what these rules name.
#[derive(Debug)]
pub(crate) struct Rules {
    /// The name in errors and in `inspect`.
    pub name: &'static str,
    /// A line `<nodes> <modes> : text` before `part`, whose counts the
    /// file must match.
    pub counts_header: bool,
    /// `new modal` may be written `new modal =`.
    pub modal_with_equals: bool,
    /// The keyword that opens the frame.
    pub frame: &'static str,
    /// The node id is on the `new node = <id>` line, and `rframe` names
    /// the frame of reference (`body ref`); else `new node` alone and
    /// `rframe = '<id>'`.
    pub id_on_new_node: bool,
    /// An entry not listed is zero. Else every entry of the block's
    /// `structure` is listed, once.
    pub sparse: bool,
    /// The `structure` codes taken, and how an error lists them.
    pub structures: &'static [usize],
    pub structures_text: &'static str,
    /// A zero block (`structure = 0`) may list its entries (all zero).
    pub zero_lists_entries: bool,
    /// A constant block may give `nq = 0`.
    pub constant_nq_zero: bool,
    pub m1_index: M1Index,
    pub j: JLayout,
    /// The blocks after the frame come in any order, `ksigma` and `De`
    /// may be missing (zero), and `ksigma` is Wallrapp's nq x 1
    /// initial-stress vector, which must be zero (flexbody's `ksigma`
    /// holds recovery rows, which these writers do not write).
    pub foreign_blocks: bool,
    /// Numbers may have a Fortran exponent (`1.0D+00`).
    pub fortran_exponent: bool,
}

const FLEXBODY: Rules = Rules {
    name: "flexbody",
    counts_header: false,
    modal_with_equals: false,
    frame: "new frame",
    id_on_new_node: false,
    sparse: false,
    structures: &[0, 3],
    structures_text: "0 or 3",
    zero_lists_entries: false,
    constant_nq_zero: false,
    m1_index: M1Index::RowColCoordinate,
    j: JLayout::Matrix,
    foreign_blocks: false,
    fortran_exponent: false,
};

const WELIB: Rules = Rules {
    name: "welib (Beam2SID)",
    counts_header: false,
    modal_with_equals: false,
    frame: "new frame",
    id_on_new_node: true,
    sparse: false,
    structures: &[0, 2, 3],
    structures_text: "0, 2 or 3",
    zero_lists_entries: true,
    constant_nq_zero: true,
    m1_index: M1Index::RowColCoordinate,
    j: JLayout::Matrix,
    foreign_blocks: true,
    fortran_exponent: false,
};

const PY_SID: Rules = Rules {
    name: "PY_SID (EMBS)",
    counts_header: true,
    modal_with_equals: true,
    frame: "frame",
    id_on_new_node: true,
    sparse: true,
    structures: &[0, 1, 2, 3, 4],
    structures_text: "0, 1, 2, 3 or 4",
    zero_lists_entries: false,
    constant_nq_zero: false,
    m1_index: M1Index::RowCoordinateCol,
    j: JLayout::Column6,
    foreign_blocks: true,
    fortran_exponent: true,
};

impl Dialect {
    /// All dialects.
    pub const ALL: [Dialect; 3] = [Dialect::Flexbody, Dialect::Welib, Dialect::PySid];

    pub(crate) fn rules(self) -> &'static Rules {
        match self {
            Dialect::Flexbody => &FLEXBODY,
            Dialect::Welib => &WELIB,
            Dialect::PySid => &PY_SID,
        }
    }

    /// The name `inspect` prints: `flexbody`, `welib (Beam2SID)`,
    /// `PY_SID (EMBS)`.
    pub fn name(self) -> &'static str {
        self.rules().name
    }

    /// The dialect of a SID `text`, from its first lines: a PY_SID counts
    /// line before `part`; else the first node, `new node = <id>` (welib)
    /// or `new node` (flexbody; also a file without nodes). Anything that
    /// does not begin with `part` (after the optional counts line) is
    /// refused, naming its first significant line.
    pub fn of(text: &str) -> Result<Dialect, ParseError> {
        let mut lines = significant(text);
        let Some((n, first)) = lines.next() else {
            return Err(ParseError {
                line: 1,
                block: "part".into(),
                message: "the file is empty: a SID begins with 'part'".into(),
            });
        };
        if first.eq_ignore_ascii_case("part") {
            for (_, l) in lines {
                if l.eq_ignore_ascii_case("end frame") {
                    break;
                }
                if let Some((k, _)) = l.split_once('=') {
                    if k.trim().eq_ignore_ascii_case("new node") {
                        return Ok(Dialect::Welib);
                    }
                }
                if l.eq_ignore_ascii_case("new node") {
                    break;
                }
            }
            return Ok(Dialect::Flexbody);
        }
        if counts_header(first).is_some() {
            return match lines.next() {
                Some((_, l)) if l.eq_ignore_ascii_case("part") => Ok(Dialect::PySid),
                next => {
                    let (line, found) = next.unwrap_or((n, ""));
                    Err(ParseError {
                        line,
                        block: "part".into(),
                        message: format!(
                            "not a SID in a known dialect (flexbody, welib, PY_SID): expected 'part' after the PY_SID counts line, found '{}'",
                            excerpt(found)
                        ),
                    })
                }
            };
        }
        Err(ParseError {
            line: n,
            block: "part".into(),
            message: format!(
                "not a SID in a known dialect (flexbody, welib, PY_SID): expected 'part', or a PY_SID line '<nodes> <modes> : ...' and then 'part'; found '{}'",
                excerpt(first)
            ),
        })
    }
}

impl std::fmt::Display for Dialect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Whether `text` begins as a SID of some dialect: `part` or a PY_SID
/// counts line as its first significant line (no other format begins so;
/// [`Dialect::of`] then says whether the rest is a SID). Only the first
/// line is looked at.
pub fn looks_like_sid(text: &str) -> bool {
    significant(text)
        .next()
        .is_some_and(|(_, l)| l.eq_ignore_ascii_case("part") || counts_header(l).is_some())
}

/// The significant lines of `text` (1-based number, trimmed): not blank,
/// not a comment (`#`, `!`).
pub(crate) fn significant(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .map(str::trim)
        .enumerate()
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#') && !l.starts_with('!'))
        .map(|(i, l)| (i + 1, l))
}

/// PY_SID's counts line, `<nodes> <modes>` and optionally `: text`.
pub(crate) fn counts_header(line: &str) -> Option<(usize, usize)> {
    let counts = line.split_once(':').map_or(line, |(c, _)| c);
    let mut words = counts.split_whitespace();
    let nodes = words.next()?.parse().ok()?;
    let modes = words.next()?.parse().ok()?;
    words.next().is_none().then_some((nodes, modes))
}

impl Rules {
    /// A number of the file: finite, at most 1e100 in magnitude; with
    /// [`Rules::fortran_exponent`], `D` taken as `E` (without allocating:
    /// a SID holds millions of numbers).
    pub fn number(&self, text: &str) -> Result<f64, String> {
        if !self.fortran_exponent || !text.bytes().any(|b| b == b'D' || b == b'd') {
            return finite_number(text);
        }
        let mut buffer = [0u8; 64];
        let bytes = text.as_bytes();
        let Some(copy) = buffer.get_mut(..bytes.len()) else {
            return Err(format!("'{}' is not a number", excerpt(text)));
        };
        for (to, &from) in copy.iter_mut().zip(bytes) {
            *to = if from == b'D' || from == b'd' {
                b'e'
            } else {
                from
            };
        }
        let Ok(converted) = std::str::from_utf8(copy) else {
            return Err(format!("'{}' is not a number", excerpt(text)));
        };
        finite_number(converted).map_err(|_| format!("'{}' is not a finite number", excerpt(text)))
    }

    /// Whether `line` opens the modal part: `new modal` (or `new modal =`
    /// where the dialect writes it so).
    pub fn is_modal(&self, line: &str) -> bool {
        line.eq_ignore_ascii_case("new modal")
            || (self.modal_with_equals
                && line.split_once('=').is_some_and(|(k, v)| {
                    k.trim().eq_ignore_ascii_case("new modal") && v.trim().is_empty()
                }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dialect_is_recognised_from_the_first_lines() {
        let flexbody = "# c\npart\nnew modal\nrefmod\nend refmod\nnew frame\nnew node\n";
        assert_eq!(Dialect::of(flexbody), Ok(Dialect::Flexbody));
        let welib = "part\nnew modal\nrefmod\nend refmod\n\nnew frame\nnew node = 1\n";
        assert_eq!(Dialect::of(welib), Ok(Dialect::Welib));
        let py_sid = "    3   1    :No. nodes, No. modes: PY_SID\n part \n";
        assert_eq!(Dialect::of(py_sid), Ok(Dialect::PySid));
        assert!(looks_like_sid(py_sid) && looks_like_sid(welib));
        let e = Dialect::of("\n\nmodal\npart\n").unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("not a SID in a known dialect"), "{e}");
        assert!(looks_like_sid("3 1 : text\nmodal\n"));
        assert!(!looks_like_sid("modal\npart\n"));
        assert!(!looks_like_sid("{\"part\": 1}"));
    }

    #[test]
    fn fortran_exponents_are_read_in_py_sid_only() {
        assert_eq!(PY_SID.number("-1.25D-01"), Ok(-0.125));
        assert_eq!(PY_SID.number("2.5"), Ok(2.5));
        assert!(FLEXBODY.number("1.0D+00").is_err());
        assert!(PY_SID.number("1.0D+999").is_err());
        assert!(PY_SID.number(&format!("1.{}D+00", "0".repeat(80))).is_err());
    }
}
