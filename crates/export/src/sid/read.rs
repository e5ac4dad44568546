//! Reading a SID text of any [`Dialect`] into a [`Sid`] in flexbody's
//! conventions. One pass over the lines, no allocation per line (a SID
//! of a large body is hundreds of MB); each block's shape and count of
//! entries are checked before storage is taken for it.

use super::dialect::{counts_header, JLayout, M1Index, Rules};
use super::{Dialect, ParseError, Refmod, Sid, SidNode, Taylor, FULL, ZERO};
use faer::Mat;
use flexbody_io::text::excerpt;
use flexbody_linalg::memory::Budget;

/// Line cursor over the significant lines of a SID text.
struct Lines<'a> {
    text: &'a str,
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            text,
            lines: text.lines().enumerate(),
        }
    }

    fn next(&mut self, block: &str, opened: usize) -> Result<(usize, &'a str), ParseError> {
        for (i, l) in self.lines.by_ref() {
            let l = l.trim();
            if !l.is_empty() && !l.starts_with('#') && !l.starts_with('!') {
                return Ok((i + 1, l));
            }
        }
        Err(ParseError {
            line: self.text.lines().count(),
            block: block.to_string(),
            message: format!("the file ends inside block '{block}' (opened at line {opened})"),
        })
    }

    fn expect(&mut self, keyword: &str, block: &str, opened: usize) -> Result<usize, ParseError> {
        let (n, l) = self.next(block, opened)?;
        if l.eq_ignore_ascii_case(keyword) {
            Ok(n)
        } else {
            Err(unexpected(n, block, keyword, l))
        }
    }
}

fn unexpected(line: usize, block: &str, keyword: &str, found: &str) -> ParseError {
    ParseError {
        line,
        block: block.to_string(),
        message: format!("expected '{keyword}', found '{}'", excerpt(found)),
    }
}

fn key_value(l: &str) -> Option<(&str, &str)> {
    let (k, v) = l.split_once('=')?;
    Some((k.trim(), v.trim()))
}

/// `name(1, 2, 3)` -> ("name", [1, 2, 3]): a name and one to three
/// indices.
fn indexed(key: &str) -> Option<(&str, Indices)> {
    let (name, rest) = key.split_once('(')?;
    let inner = rest.trim_end().strip_suffix(')')?;
    let mut idx = Indices::default();
    for s in inner.split(',') {
        *idx.values.get_mut(idx.len)? = s.trim().parse().ok()?;
        idx.len += 1;
    }
    Some((name.trim(), idx))
}

/// The indices of an entry `name(i, j, k)`, without a heap allocation
/// (a SID holds millions of entries).
#[derive(Default)]
struct Indices {
    values: [usize; 3],
    len: usize,
}

impl Indices {
    fn as_slice(&self) -> &[usize] {
        &self.values[..self.len]
    }
}

/// The entries a block's `structure` lists: 0 zero (none), 1 diagonal,
/// 2 symmetric (the lower triangle of `m0`; every entry of `m1`),
/// 3 full, 4 identity (none).
fn in_structure(structure: usize, i: usize, j: usize, first_order: bool) -> bool {
    match structure {
        1 => i == j,
        2 => first_order || j <= i,
        4 => false,
        _ => true,
    }
}

/// How many entries `structure` lists in an `nrow` x `ncol` matrix (of
/// `m1` if `first_order`), saturating.
fn listed(structure: usize, nrow: usize, ncol: usize, first_order: bool) -> usize {
    match structure {
        0 | 4 => 0,
        1 => nrow,
        2 if !first_order => nrow.saturating_mul(nrow.saturating_add(1)) / 2,
        _ => nrow.saturating_mul(ncol),
    }
}

/// One block `name` (a Taylor expansion) of `nq` coordinates that must be
/// `shape` (rows, columns; `usize::MAX` rows: any), read by `rules`. Its
/// shape and its count of entries are checked before storage is taken for
/// it, and the storage against the memory left ([`Budget::MACHINE`]).
/// The result is in flexbody's conventions: `m1` per coordinate, every
/// entry stored, `structure` [`FULL`] or [`ZERO`].
fn parse_taylor(
    lines: &mut Lines<'_>,
    rules: &Rules,
    name: &str,
    opened: usize,
    nq: usize,
    shape: (usize, usize),
) -> Result<Taylor, ParseError> {
    let err = |line: usize, message: String| ParseError {
        line,
        block: name.to_string(),
        message,
    };
    let mut header = [None::<usize>; 6];
    const KEYS: [&str; 6] = ["order", "nrow", "ncol", "nq", "nqn", "structure"];
    let mut m0: Vec<(usize, usize, usize, f64)> = Vec::new();
    // As the file indexes them.
    let mut m1: Vec<(usize, [usize; 3], f64)> = Vec::new();
    let end_line = loop {
        let (n, l) = lines.next(name, opened)?;
        if l.len() == 4 + name.len()
            && l.get(..4).is_some_and(|e| e.eq_ignore_ascii_case("end "))
            && l.get(4..).is_some_and(|n| n.eq_ignore_ascii_case(name))
        {
            break n;
        }
        if l.starts_with("end ") || l.starts_with("new ") {
            return Err(err(
                n,
                format!(
                    "'{l}' before 'end {name}' (block opened at line {opened})",
                    l = excerpt(l)
                ),
            ));
        }
        let (k, v) = key_value(l).ok_or_else(|| {
            err(
                n,
                format!("expected 'key = value', found '{l}'", l = excerpt(l)),
            )
        })?;
        if let Some(slot) = KEYS.iter().position(|key| k.eq_ignore_ascii_case(key)) {
            if header[slot].is_some() {
                return Err(err(n, format!("'{}' is given twice", KEYS[slot])));
            }
            header[slot] = Some(
                v.parse()
                    .map_err(|_| err(n, format!("{k} = '{v}' is not a count", v = excerpt(v))))?,
            );
            continue;
        }
        let (kind, idx) =
            indexed(k).ok_or_else(|| err(n, format!("unknown entry '{k}'", k = excerpt(k))))?;
        let value = rules.number(v).map_err(|m| err(n, m))?;
        match (kind, idx.as_slice()) {
            ("m0", [i, j]) => m0.push((n, *i, *j, value)),
            ("m1", [a, b, c]) => m1.push((n, [*a, *b, *c], value)),
            _ => return Err(err(n, format!("unknown entry '{k}'", k = excerpt(k)))),
        }
    };
    let mut h = [0usize; 6];
    for (slot, key) in KEYS.iter().enumerate() {
        h[slot] = header[slot].ok_or_else(|| err(end_line, format!("'{key}' is missing")))?;
    }
    let [order, nrow, ncol, tq, nqn, structure] = h;
    if order > 1 {
        return Err(err(
            end_line,
            format!("order {order} is not supported (0 or 1)"),
        ));
    }
    if tq != nq && !(rules.constant_nq_zero && order == 0 && tq == 0) {
        return Err(err(
            end_line,
            format!("nq = {tq}, but refmod has nelastq = {nq}"),
        ));
    }
    if !rules.structures.contains(&structure) {
        return Err(err(
            end_line,
            format!(
                "structure {structure} is not supported ({})",
                rules.structures_text
            ),
        ));
    }
    let (rows, cols) = shape;
    if (rows != usize::MAX && nrow != rows) || ncol != cols {
        let rows = if rows == usize::MAX { nrow } else { rows };
        return Err(err(
            opened,
            format!("is {nrow} x {ncol}, expected {rows} x {cols}"),
        ));
    }
    if [1, 2, 4].contains(&structure) && nrow != ncol {
        return Err(err(
            opened,
            format!("structure {structure} needs a square block, this is {nrow} x {ncol}"),
        ));
    }
    let matrices = if order == 1 { nq + 1 } else { 1 };
    let entries = nrow.checked_mul(ncol);
    let bytes = entries
        .and_then(|e| e.checked_mul(matrices))
        .and_then(|e| e.checked_mul(std::mem::size_of::<f64>()));
    let what = format!("{matrices} matrices of {nrow} x {ncol}");
    Budget::MACHINE
        .ensure(bytes.map_or(u64::MAX, |b| b as u64), &what)
        .map_err(|e| err(opened, e.to_string()))?;
    if !rules.sparse {
        // Every entry of the structure once: with the count right, a
        // repeated entry (found below) hides a missing one. A zero block
        // lists none, or (where the dialect writes them) all.
        let expect = |count: usize, want: usize, what: &str| {
            let want = if structure == ZERO && rules.zero_lists_entries && count > 0 {
                if what == "m0" {
                    entries.unwrap_or(usize::MAX)
                } else {
                    entries.map_or(usize::MAX, |e| e.saturating_mul(nq))
                }
            } else {
                want
            };
            if count == want {
                Ok(())
            } else {
                Err(err(end_line, format!("{count} {what} entries, expected {want} (nrow = {nrow}, ncol = {ncol}, nq = {nq}, structure = {structure})")))
            }
        };
        expect(m0.len(), listed(structure, nrow, ncol, false), "m0")?;
        let first = if order == 1 {
            listed(structure, nrow, ncol, true).saturating_mul(nq)
        } else {
            0
        };
        expect(m1.len(), first, "m1")?;
    } else if order == 0 && !m1.is_empty() {
        return Err(err(m1[0].0, "an m1 entry in a block of order 0".into()));
    }
    // An entry not yet given is NaN (values read are finite), so a repeat
    // is seen without a second table.
    let mut a0 = Mat::from_fn(nrow, ncol, |_, _| f64::NAN);
    let mut a1 = vec![a0.clone(); if order == 1 { nq } else { 0 }];
    let outside_structure = |i: usize, j: usize| match structure {
        0 => "structure 0 (zero) lists no entries other than zeros".to_string(),
        1 => format!("({i}, {j}) is off the diagonal of a diagonal block (structure 1)"),
        2 => format!("({i}, {j}) is above the diagonal: structure 2 lists the lower triangle"),
        _ => format!("structure {structure} (identity) lists no entries"),
    };
    for &(n, i, j, v) in &m0 {
        if i == 0 || j == 0 || i > nrow || j > ncol {
            return Err(err(n, format!("m0({i}, {j}) is outside {nrow} x {ncol}")));
        }
        if !in_structure(structure, i, j, false) || (structure == ZERO && v != 0.0) {
            return Err(err(n, format!("m0({i}, {j}): {}", outside_structure(i, j))));
        }
        if !a0[(i - 1, j - 1)].is_nan() {
            let first = m0.iter().find(|e| (e.1, e.2) == (i, j)).map_or(0, |e| e.0);
            return Err(err(
                n,
                format!("m0({i}, {j}) is given twice (first at line {first})"),
            ));
        }
        a0[(i - 1, j - 1)] = v;
    }
    for &(n, abc, v) in &m1 {
        let [a, b, c] = abc;
        // (row, column, coordinate), 1-based.
        let (i, j, k) = match rules.m1_index {
            M1Index::RowColCoordinate => (a, b, c),
            M1Index::RowCoordinateCol => (a, c, b),
        };
        if i == 0 || j == 0 || k == 0 || i > nrow || j > ncol || k > nq {
            let extent = match rules.m1_index {
                M1Index::RowColCoordinate => format!("{nrow} x {ncol} x {nq}"),
                M1Index::RowCoordinateCol => {
                    format!("{nrow} x {nq} x {ncol} (row, mode, column)")
                }
            };
            return Err(err(n, format!("m1({a}, {b}, {c}) is outside {extent}")));
        }
        if !in_structure(structure, i, j, true) || (structure == ZERO && v != 0.0) {
            return Err(err(
                n,
                format!("m1({a}, {b}, {c}): {}", outside_structure(i, j)),
            ));
        }
        if !a1[k - 1][(i - 1, j - 1)].is_nan() {
            let first = m1.iter().find(|e| e.1 == abc).map_or(0, |e| e.0);
            return Err(err(
                n,
                format!("m1({a}, {b}, {c}) is given twice (first at line {first})"),
            ));
        }
        a1[k - 1][(i - 1, j - 1)] = v;
    }
    // The entries not listed: the upper triangle of a symmetric block is
    // its lower one, an identity block is I (its m1 zero), the rest zero.
    let complete = |a: &mut Mat<f64>, identity: bool| {
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                if a[(i, j)].is_nan() {
                    a[(i, j)] = if structure == 2 && i < j && !a[(j, i)].is_nan() {
                        a[(j, i)]
                    } else if identity && i == j {
                        1.0
                    } else {
                        0.0
                    };
                }
            }
        }
    };
    complete(&mut a0, structure == 4);
    for a in &mut a1 {
        complete(a, false);
    }
    Ok(Taylor {
        order,
        nrow,
        ncol,
        nq,
        nqn,
        structure: if structure == ZERO { ZERO } else { FULL },
        m0: a0,
        m1: a1,
    })
}

/// `J` written as the column `[xx, yy, zz, xy, xz, yz]` (each order), as
/// the symmetric 3 x 3 tensor.
fn j_from_column(t: Taylor) -> Taylor {
    let tensor = |v: &Mat<f64>| {
        let at = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];
        Mat::from_fn(3, 3, |i, j| v[(at[i][j], 0)])
    };
    Taylor {
        nrow: 3,
        ncol: 3,
        m0: tensor(&t.m0),
        m1: t.m1.iter().map(tensor).collect(),
        ..t
    }
}

/// The inertia tensor `J` and the modal mass, stiffness and damping
/// `Me`, `Ke`, `De` are symmetric (each order); `J`, `Me` and `De` are
/// positive semi-definite (their constant part), and `Ke` with `Me` has
/// no negative eigenvalue (checked by the caller): a file where they are
/// not describes no body.
fn check_symmetric_semi_definite(t: &Taylor, name: &str, line: usize) -> Result<(), ParseError> {
    use flexbody_linalg::dense_check::{semi_definite, symmetric};
    let err = |message: String| ParseError {
        line,
        block: name.to_string(),
        message,
    };
    symmetric(t.m0.as_ref()).map_err(|e| err(format!("m0 {e}")))?;
    for (k, m1) in t.m1.iter().enumerate() {
        symmetric(m1.as_ref()).map_err(|e| err(format!("m1(:, :, {}) {e}", k + 1)))?;
    }
    if name == "Ke" {
        return Ok(());
    }
    semi_definite(t.m0.as_ref()).map_err(|e| err(format!("m0 {e}")))
}

/// The blocks after the frame, in flexbody's order.
const BLOCKS: [&str; 11] = [
    "mdCM", "J", "Ct", "Cr", "Me", "Gr", "Ge", "Oe", "ksigma", "Ke", "De",
];

/// Parses SID text of any dialect (see the module docs of [`super`]).
pub fn parse_sid(text: &str) -> Result<Sid, ParseError> {
    parse_sid_dialect(text).map(|(sid, _)| sid)
}

/// [`parse_sid`], with the dialect it was read in.
pub fn parse_sid_dialect(text: &str) -> Result<(Sid, Dialect), ParseError> {
    let dialect = Dialect::of(text)?;
    let rules = dialect.rules();
    let mut lines = Lines::new(text);
    let counts = if rules.counts_header {
        let (n, l) = lines.next("part", 1)?;
        counts_header(l).map(|c| (n, c))
    } else {
        None
    };
    let part = lines.expect("part", "part", 1)?;
    let (modal, l) = lines.next("part", part)?;
    if !rules.is_modal(l) {
        return Err(unexpected(modal, "part", "new modal", l));
    }
    let refmod_line = lines.expect("refmod", "modal", modal)?;
    let mut mass = None;
    let mut nelastq = None;
    let mut names: Vec<(usize, usize, String)> = Vec::new();
    let bad = |line, message: String| ParseError {
        line,
        block: "refmod".into(),
        message,
    };
    let refmod_end = loop {
        let (n, l) = lines.next("refmod", refmod_line)?;
        if l.eq_ignore_ascii_case("end refmod") {
            break n;
        }
        let (k, v) = key_value(l).ok_or_else(|| {
            bad(
                n,
                format!("expected 'key = value', found '{l}'", l = excerpt(l)),
            )
        })?;
        if k.eq_ignore_ascii_case("mass") {
            let m = rules.number(v).map_err(|m| bad(n, format!("mass: {m}")))?;
            if m <= 0.0 || mass.is_some() {
                let why = if m <= 0.0 {
                    "is not positive"
                } else {
                    "is given twice"
                };
                return Err(bad(n, format!("mass {v} {why}", v = excerpt(v))));
            }
            mass = Some(m);
        } else if k.eq_ignore_ascii_case("nelastq") {
            if nelastq.is_some() {
                return Err(bad(n, "nelastq is given twice".into()));
            }
            nelastq =
                Some(v.parse::<usize>().map_err(|_| {
                    bad(n, format!("nelastq '{v}' is not a count", v = excerpt(v)))
                })?);
        } else if let Some(("ielastq", idx)) = indexed(k) {
            let [i] = idx.as_slice() else {
                return Err(bad(n, format!("'{k}' needs one index", k = excerpt(k))));
            };
            names.push((n, *i, v.trim_matches('\'').trim().to_string()));
        } else {
            return Err(bad(n, format!("unknown entry '{k}'", k = excerpt(k))));
        }
    };
    let mass = mass.ok_or_else(|| bad(refmod_end, "'mass' is missing".into()))?;
    let nq = nelastq.ok_or_else(|| bad(refmod_end, "'nelastq' is missing".into()))?;
    if names.len() != nq {
        return Err(bad(
            refmod_end,
            format!("{} ielastq names, nelastq = {nq}", names.len()),
        ));
    }
    let mut ielastq = vec![None; nq];
    for (n, i, name) in names {
        if i == 0 || i > nq {
            return Err(bad(n, format!("ielastq({i}) is outside 1..{nq}")));
        }
        if ielastq[i - 1].replace(name).is_some() {
            return Err(bad(n, format!("ielastq({i}) is given twice")));
        }
    }
    let ielastq = ielastq.into_iter().map(Option::unwrap_or_default).collect();
    let frame = lines.expect(rules.frame, "modal", modal)?;
    let (nodes, end_frame) = parse_frame(&mut lines, rules, frame, nq)?;
    if let Some((line, (count_nodes, count_modes))) = counts {
        if (count_nodes, count_modes) != (nodes.len(), nq) {
            return Err(ParseError {
                line,
                block: "header".into(),
                message: format!(
                    "the counts line gives {count_nodes} nodes and {count_modes} modes, the file has {} nodes (frame ending at line {end_frame}) and nelastq = {nq}",
                    nodes.len()
                ),
            });
        }
    }
    let mut blocks = parse_blocks(&mut lines, rules, modal, nq)?.into_iter();
    lines.expect("end part", "part", part)?;
    let mut take = |_| blocks.next().expect("eleven blocks");
    let sid = Sid {
        refmod: Refmod { mass, ielastq },
        nodes,
        md_cm: take(0),
        j: take(1),
        ct: take(2),
        cr: take(3),
        me: take(4),
        gr: take(5),
        ge: take(6),
        oe: take(7),
        ksigma: take(8),
        ke: take(9),
        de: take(10),
    };
    Ok((sid, dialect))
}

/// The nodes of the frame, up to `end frame` (and its line).
fn parse_frame(
    lines: &mut Lines<'_>,
    rules: &Rules,
    frame: usize,
    nq: usize,
) -> Result<(Vec<SidNode>, usize), ParseError> {
    let mut nodes = Vec::new();
    let mut node_lines: Vec<(u64, usize)> = Vec::new();
    let end = loop {
        let (n, l) = lines.next("frame", frame)?;
        if l.eq_ignore_ascii_case("end frame") {
            break n;
        }
        let opens = if rules.id_on_new_node {
            "'new node = <id>'"
        } else {
            "'new node'"
        };
        let not_a_node = || ParseError {
            line: n,
            block: "frame".into(),
            message: format!(
                "expected {opens} or 'end frame', found '{l}'",
                l = excerpt(l)
            ),
        };
        let (rn, rl) = lines.next("node", n)?;
        let rframe = key_value(rl).filter(|(k, _)| k.eq_ignore_ascii_case("rframe"));
        let id = if rules.id_on_new_node {
            let (k, v) = key_value(l).ok_or_else(not_a_node)?;
            if !k.eq_ignore_ascii_case("new node") {
                return Err(not_a_node());
            }
            let id = v.parse::<u64>().map_err(|_| ParseError {
                line: n,
                block: "node".into(),
                message: format!("node id '{v}' is not a number", v = excerpt(v)),
            })?;
            rframe.ok_or_else(|| ParseError {
                line: rn,
                block: "node".into(),
                message: format!(
                    "expected 'rframe = <frame of reference>', found '{rl}'",
                    rl = excerpt(rl)
                ),
            })?;
            id
        } else {
            if !l.eq_ignore_ascii_case("new node") {
                return Err(not_a_node());
            }
            rframe
                .and_then(|(_, v)| v.trim_matches('\'').trim().parse::<u64>().ok())
                .ok_or_else(|| ParseError {
                    line: rn,
                    block: "node".into(),
                    message: format!(
                        "expected \"rframe = '<node id>'\", found '{rl}'",
                        rl = excerpt(rl)
                    ),
                })?
        };
        let mut part = |name: &str, shape: (usize, usize)| {
            let opened = lines.expect(name, "node", n)?;
            parse_taylor(lines, rules, name, opened, nq, shape)
        };
        let node = SidNode {
            id,
            origin: part("origin", (3, 1))?,
            phi: part("phi", (3, nq))?,
            psi: part("psi", (3, nq))?,
            ap: part("AP", (3, 3))?,
        };
        lines.expect("end node", "node", n)?;
        node_lines.push((id, rn));
        nodes.push(node);
    };
    // Each node once; a repeat is named at its second line.
    node_lines.sort_unstable();
    if let Some(w) = node_lines.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(ParseError {
            line: w[1].1,
            block: "node".into(),
            message: format!("node {} is given twice (first at line {})", w[0].0, w[0].1),
        });
    }
    Ok((nodes, end))
}

/// The blocks after the frame up to `end modal`, in [`BLOCKS`] order:
/// in that order in the file (flexbody), or in any order with `ksigma`
/// and `De` optional (the other dialects).
fn parse_blocks(
    lines: &mut Lines<'_>,
    rules: &Rules,
    modal: usize,
    nq: usize,
) -> Result<Vec<Taylor>, ParseError> {
    let mut blocks: Vec<Option<(usize, Taylor)>> = vec![None; BLOCKS.len()];
    let mut count = 0;
    let mut pencil_checked = false;
    let end_modal = loop {
        let (n, l) = lines.next("modal", modal)?;
        let slot = BLOCKS.iter().position(|b| l.eq_ignore_ascii_case(b));
        let slot = if rules.foreign_blocks {
            if l.eq_ignore_ascii_case("end modal") {
                break n;
            }
            let slot = slot.ok_or_else(|| ParseError {
                line: n,
                block: "modal".into(),
                message: format!(
                    "unknown block '{l}' (a SID has {})",
                    BLOCKS.join(", "),
                    l = excerpt(l)
                ),
            })?;
            if let Some((first, _)) = &blocks[slot] {
                return Err(ParseError {
                    line: n,
                    block: BLOCKS[slot].into(),
                    message: format!(
                        "block '{}' is given twice (first at line {first})",
                        BLOCKS[slot]
                    ),
                });
            }
            slot
        } else {
            match BLOCKS.get(count) {
                Some(_) if slot == Some(count) => count,
                Some(want) => return Err(unexpected(n, "modal", want, l)),
                None if l.eq_ignore_ascii_case("end modal") => break n,
                None => return Err(unexpected(n, "modal", "end modal", l)),
            }
        };
        let name = BLOCKS[slot];
        let shape = match name {
            "mdCM" => (3, 1),
            "J" if rules.j == JLayout::Column6 => (6, 1),
            "J" => (3, 3),
            "Ct" | "Cr" => (nq, 3),
            "Gr" => (3, 3 * nq),
            "Ge" => (nq, 3 * nq),
            "Oe" => (nq, 6),
            "ksigma" if rules.foreign_blocks => (nq, 1),
            "ksigma" => (usize::MAX, nq),
            _ => (nq, nq),
        };
        let mut t = parse_taylor(lines, rules, name, n, nq, shape)?;
        if name == "J" && rules.j == JLayout::Column6 {
            t = j_from_column(t);
        }
        if name == "ksigma" && rules.foreign_blocks {
            if t.m0.norm_max() != 0.0 {
                return Err(ParseError {
                    line: n,
                    block: name.into(),
                    message: "a non-zero initial-stress vector ksigma (nq x 1) has no place in flexbody's SID, whose ksigma holds recovery rows".into(),
                });
            }
            t = Taylor::constant(Mat::zeros(0, nq), nq);
        }
        if ["J", "Me", "Ke", "De"].contains(&name) {
            check_symmetric_semi_definite(&t, name, n)?;
        }
        blocks[slot] = Some((n, t));
        count += 1;
        // Me and Ke, once both are read: the elastic modes are stable.
        if let (Some((_, me)), Some((ke_line, ke)), false) =
            (&blocks[4], &blocks[9], pencil_checked)
        {
            flexbody_linalg::dense_check::stable_pencil(ke.m0.as_ref(), me.m0.as_ref()).map_err(
                |e| ParseError {
                    line: *ke_line,
                    block: "Ke".into(),
                    message: format!("m0 {e}"),
                },
            )?;
            pencil_checked = true;
        }
    };
    BLOCKS
        .iter()
        .zip(blocks)
        .map(|(name, block)| match (block, *name) {
            (Some((_, t)), _) => Ok(t),
            (None, "ksigma") => Ok(Taylor::constant(Mat::zeros(0, nq), nq)),
            (None, "De") => Ok(Taylor::constant(Mat::zeros(nq, nq), nq)),
            (None, _) => Err(ParseError {
                line: end_modal,
                block: "modal".into(),
                message: format!("block '{name}' is missing"),
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block `name` of `body` (header and entries) read by `dialect`'s
    /// rules as a 2 x 2 block of 1 coordinate.
    fn block(dialect: Dialect, name: &str, body: &str) -> Result<Taylor, ParseError> {
        let text = format!("{name}\n{body}\nend {name}\n");
        let mut lines = Lines::new(&text);
        let (opened, _) = lines.next(name, 1)?;
        parse_taylor(&mut lines, dialect.rules(), name, opened, 1, (2, 2))
    }

    const HEAD: &str = "order = 1\nnrow = 2\nncol = 2\nnq = 1\nnqn = 0\n";

    #[test]
    fn structures_fill_what_they_do_not_list() {
        // Symmetric: m0's lower triangle, mirrored; m1 whole.
        let entries = "m0(1, 1) = 1\nm0(2, 1) = 2\nm0(2, 2) = 3\n\
                       m1(1, 1, 1) = 4\nm1(1, 2, 1) = 5\nm1(2, 1, 1) = 5\nm1(2, 2, 1) = 6";
        let t = block(
            Dialect::Welib,
            "Me",
            &format!("{HEAD}structure = 2\n{entries}"),
        )
        .unwrap();
        assert_eq!(t.m0[(0, 1)], 2.0);
        assert_eq!(t.m1[0][(1, 0)], 5.0);
        assert_eq!(t.structure, FULL);
        // Identity: no entries, m1 zero; diagonal: the rest zero.
        let t = block(Dialect::PySid, "AP", &format!("{HEAD}structure = 4")).unwrap();
        assert_eq!(t.m0, Mat::<f64>::identity(2, 2));
        assert_eq!(t.m1[0].norm_max(), 0.0);
        let t = block(
            Dialect::PySid,
            "Ke",
            &format!("{HEAD}structure = 1\nm0(2, 2) = 7.5D+00"),
        )
        .unwrap();
        assert_eq!((t.m0[(1, 1)], t.m0[(0, 0)], t.m0[(1, 0)]), (7.5, 0.0, 0.0));
    }

    #[test]
    fn entries_outside_their_structure_are_refused_at_their_line() {
        let e = block(
            Dialect::PySid,
            "Ke",
            &format!("{HEAD}structure = 1\nm0(1, 2) = 1"),
        )
        .unwrap_err();
        assert_eq!(e.line, 8, "{e}");
        assert!(e.message.contains("off the diagonal"), "{e}");
        let e = block(
            Dialect::Welib,
            "De",
            &format!("{HEAD}structure = 0\nm0(1, 1) = 0\nm0(1, 2) = 0\nm0(2, 1) = 1\nm0(2, 2) = 0"),
        )
        .unwrap_err();
        assert!(e.message.contains("structure 0 (zero)"), "{e}");
        // welib lists every entry of its structure: one missing is refused.
        let constant = "order = 0\nnrow = 2\nncol = 2\nnq = 0\nnqn = 0\nstructure = 2\n";
        let e = block(
            Dialect::Welib,
            "Me",
            &format!("{constant}m0(1, 1) = 1\nm0(2, 2) = 3"),
        )
        .unwrap_err();
        assert!(e.message.contains("2 m0 entries, expected 3"), "{e}");
        // PY_SID's m1 is (row, mode, column): mode 2 of 1 is outside.
        let e = block(
            Dialect::PySid,
            "AP",
            &format!("{HEAD}structure = 3\nm1(1, 2, 1) = 1"),
        )
        .unwrap_err();
        assert!(
            e.message.contains("outside 2 x 1 x 2 (row, mode, column)"),
            "{e}"
        );
        // A repeat hides nothing in a sparse dialect either.
        let e = block(
            Dialect::PySid,
            "AP",
            &format!("{HEAD}structure = 3\nm0(1, 1) = 1\nm0(1, 1) = 1"),
        )
        .unwrap_err();
        assert_eq!(e.line, 9, "{e}");
        assert!(e.message.contains("given twice (first at line 8)"), "{e}");
    }
}
