//! Splitting a deck into cards: a keyword line with its parameters and the
//! data lines under it. Comment lines (`**`) and blank lines are dropped,
//! `*INCLUDE` files are read in place (relative to the including file's
//! folder), and every line keeps its file and line number for errors.

use crate::InputError;
use flexbody_linalg::dense_check::LARGEST;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Deepest `*INCLUDE` nesting accepted (a deeper one is taken as a cycle).
const MAX_INCLUDE_DEPTH: usize = 16;

/// Most `*INCLUDE`s of one deck that read a file read before. Files that
/// include each other several times over (each of 13 files including the
/// next four times) expand to millions of reads; a deck needs few.
pub const MAX_REPEATED_INCLUDES: usize = 10_000;

/// Most bytes the `*INCLUDE`s of one deck read from files read before
/// (1 GB). The first read of each file does not count.
pub const MAX_REPEATED_BYTES: u64 = 1_000_000_000;

/// The longest name or data field a deck may hold (80 characters, the
/// length of a label in Abaqus and CalculiX). Longer ones are refused as
/// the deck is split into cards, so that no message quotes a long name.
/// File names (`INPUT=`) and the text of `*HEADING` are exempt.
pub const MAX_FIELD_CHARS: usize = 80;

/// Where a line comes from: the file (index into [`Files::paths`]) and the
/// 1-based line number.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) struct Loc {
    pub file: usize,
    pub line: usize,
}

/// The files a deck is read from, the main file first.
#[derive(Debug)]
pub(super) struct Files {
    pub paths: Vec<PathBuf>,
}

/// What the `*INCLUDE` files of a deck have read so far, against
/// [`MAX_REPEATED_INCLUDES`] and [`MAX_REPEATED_BYTES`].
#[derive(Debug, Default)]
struct Expansion {
    repeats: usize,
    repeated_bytes: u64,
    /// The files read, by the path they were read under.
    seen: std::collections::HashSet<PathBuf>,
}

impl Files {
    /// An error at `loc`: that file and that line.
    pub fn error(&self, loc: Loc, message: impl Into<String>) -> InputError {
        InputError::Invalid {
            path: self.paths[loc.file].clone(),
            line: Some(loc.line),
            message: message.into(),
        }
    }

    /// An error at `loc` where there is one, else of the main file.
    pub fn error_near(&self, loc: Option<Loc>, message: impl Into<String>) -> InputError {
        match loc {
            Some(loc) => self.error(loc, message),
            None => InputError::Invalid {
                path: self.paths[0].clone(),
                line: None,
                message: message.into(),
            },
        }
    }

    /// `"line 40"` in the main file, `"nodes.inp line 4"` in an included one.
    pub fn describe(&self, loc: Loc) -> String {
        if loc.file == 0 {
            format!("line {}", loc.line)
        } else {
            let p = &self.paths[loc.file];
            let name = p.file_name().map_or_else(
                || p.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            format!("{name} line {}", loc.line)
        }
    }
}

/// A keyword parameter: `KEY` or `KEY=value`. The key is upper-case without
/// spaces; the value is trimmed, without surrounding quotes, case kept.
#[derive(Clone, Debug)]
pub(super) struct Param {
    pub key: String,
    pub value: Option<String>,
}

/// One data line split at the commas (fields trimmed). A trailing comma is
/// removed and recorded in `continued`.
#[derive(Clone, Debug)]
pub(super) struct DataLine {
    pub loc: Loc,
    pub fields: Vec<String>,
    pub continued: bool,
}

impl DataLine {
    /// Field `i`, if present and not empty.
    pub fn get(&self, i: usize) -> Option<&str> {
        self.fields
            .get(i)
            .map(String::as_str)
            .filter(|f| !f.is_empty())
    }

    /// Field `i` as a finite number; `what` names it in the error.
    pub fn float(&self, files: &Files, i: usize, what: &str) -> Result<f64, InputError> {
        let field = self
            .get(i)
            .ok_or_else(|| files.error(self.loc, format!("{what} is missing")))?;
        parse_float(field).ok_or_else(|| {
            files.error(
                self.loc,
                format!(
                    "{what}: expected a finite number (at most 1e100 in magnitude), got '{field}'",
                    field = crate::text::excerpt(field)
                ),
            )
        })
    }

    /// Field `i` as a finite number, or `default` if absent or empty.
    pub fn float_or(
        &self,
        files: &Files,
        i: usize,
        what: &str,
        default: f64,
    ) -> Result<f64, InputError> {
        match self.get(i) {
            None => Ok(default),
            Some(_) => self.float(files, i, what),
        }
    }

    /// Field `i` as a positive integer id (node, element, DOF).
    pub fn id(&self, files: &Files, i: usize, what: &str) -> Result<u64, InputError> {
        let field = self
            .get(i)
            .ok_or_else(|| files.error(self.loc, format!("{what} is missing")))?;
        parse_id(field).ok_or_else(|| {
            files.error(
                self.loc,
                format!(
                    "{what}: expected a positive integer, got '{field}'",
                    field = crate::text::excerpt(field)
                ),
            )
        })
    }
}

/// A finite number at most [`LARGEST`] in magnitude; Fortran exponents
/// (`1.0D3`) are accepted.
pub(super) fn parse_float(s: &str) -> Option<f64> {
    let v: f64 = s.replace(['d', 'D'], "e").parse().ok()?;
    (v.abs() <= LARGEST).then_some(v)
}

/// A positive integer.
pub(super) fn parse_id(s: &str) -> Option<u64> {
    s.parse::<u64>().ok().filter(|&v| v > 0)
}

/// True if `s` looks like a number rather than a set name.
pub(super) fn is_numeric(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_digit() || c == '+' || c == '-' || c == '.')
}

/// A keyword line and its data lines.
#[derive(Clone, Debug)]
pub(super) struct Card {
    /// Upper case, spaces removed (`"SOLIDSECTION"`): what is matched.
    pub keyword: String,
    /// Upper case with single spaces (`"*SOLID SECTION"`): what is shown.
    pub display: String,
    pub params: Vec<Param>,
    pub loc: Loc,
    pub data: Vec<DataLine>,
}

impl Card {
    /// The parameter `key` (upper case, no spaces), if given.
    pub fn param(&self, key: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.key == key)
    }

    /// True if the parameter is given (with or without a value).
    pub fn has(&self, key: &str) -> bool {
        self.param(key).is_some()
    }

    /// The value of `key`, if given with a non-empty value.
    pub fn value(&self, key: &str) -> Option<&str> {
        self.param(key)
            .and_then(|p| p.value.as_deref())
            .filter(|v| !v.is_empty())
    }

    /// The value of `key`, or an error naming the keyword and the parameter.
    pub fn require(&self, files: &Files, key: &str) -> Result<&str, InputError> {
        self.value(key).ok_or_else(|| {
            files.error(
                self.loc,
                format!("{} needs the parameter {key}=...", self.display),
            )
        })
    }

    /// A name parameter (set, material): upper case, as Abaqus and CalculiX
    /// compare names.
    pub fn require_name(&self, files: &Files, key: &str) -> Result<String, InputError> {
        self.require(files, key).map(name)
    }

    /// Parameters other than `known`, as `"KEY"` for warnings.
    pub fn unknown_params(&self, known: &[&str]) -> Vec<&str> {
        self.params
            .iter()
            .filter(|p| !known.contains(&p.key.as_str()))
            .map(|p| p.key.as_str())
            .collect()
    }
}

/// A set or material name as compared: upper case, trimmed.
pub(super) fn name(s: &str) -> String {
    s.trim().to_uppercase()
}

/// Reads the deck text (and its include files) into cards.
pub(super) fn read_cards(path: &Path, text: &str) -> Result<(Files, Vec<Card>), InputError> {
    let mut files = Files {
        paths: vec![path.to_path_buf()],
    };
    let mut lines = Vec::new();
    let mut expansion = Expansion::default();
    expansion.seen.insert(path.to_path_buf());
    collect_lines(&mut files, 0, text, 0, &mut expansion, &mut lines)?;
    let cards = split_cards(&files, &lines)?;
    Ok((files, cards))
}

/// Appends the significant lines of file `file` (its `text`) to `out`,
/// reading `*INCLUDE` files in place.
fn collect_lines(
    files: &mut Files,
    file: usize,
    text: &str,
    depth: usize,
    expansion: &mut Expansion,
    out: &mut Vec<(Loc, String)>,
) -> Result<(), InputError> {
    for (i, raw) in text.lines().enumerate() {
        let loc = Loc { file, line: i + 1 };
        let line = raw.trim_matches(|c: char| c.is_whitespace() || c == '\u{feff}');
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if line.starts_with('*') {
            let (keyword, _, params) = parse_keyword(line);
            if keyword == "INCLUDE" {
                let input = params
                    .iter()
                    .find(|p| p.key == "INPUT")
                    .and_then(|p| p.value.clone())
                    .filter(|v| !v.is_empty())
                    .ok_or_else(|| files.error(loc, "*INCLUDE needs INPUT=file"))?;
                if depth >= MAX_INCLUDE_DEPTH {
                    return Err(files.error(
                        loc,
                        format!(
                            "*INCLUDE of '{input}': more than {MAX_INCLUDE_DEPTH} nested \
                             includes (does a file include itself?)",
                            input = crate::text::excerpt(&input)
                        ),
                    ));
                }
                let folder = files.paths[file]
                    .parent()
                    .map(Path::to_path_buf)
                    .unwrap_or_default();
                let included = folder.join(&input);
                let bytes = crate::text::read_bytes(&included).map_err(|e| match e {
                    InputError::Read { cause, .. } => files.error(
                        loc,
                        format!("*INCLUDE: cannot read '{}': {cause}", included.display()),
                    ),
                    invalid => invalid,
                })?;
                if !expansion.seen.insert(included.clone()) {
                    expansion.repeats += 1;
                    expansion.repeated_bytes += bytes.len() as u64;
                    if expansion.repeats > MAX_REPEATED_INCLUDES
                        || expansion.repeated_bytes > MAX_REPEATED_BYTES
                    {
                        return Err(files.error(
                            loc,
                            format!(
                                "*INCLUDE of '{input}': the deck's includes read files read \
                                 before more than {MAX_REPEATED_INCLUDES} times or more than \
                                 {MAX_REPEATED_BYTES} bytes (files that include each other \
                                 several times over); include each file once",
                                input = crate::text::excerpt(&input)
                            ),
                        ));
                    }
                }
                let included_text = String::from_utf8_lossy(&bytes).into_owned();
                files.paths.push(included);
                let index = files.paths.len() - 1;
                collect_lines(files, index, &included_text, depth + 1, expansion, out)?;
                continue;
            }
        }
        out.push((loc, line.to_string()));
    }
    Ok(())
}

/// Groups lines into cards. A keyword line ending with a comma continues on
/// the next line if that line starts with a `KEY=value` parameter.
fn split_cards(files: &Files, lines: &[(Loc, String)]) -> Result<Vec<Card>, InputError> {
    let mut cards: Vec<Card> = Vec::new();
    // The data lines of each card, split at the commas afterwards, all
    // cards in parallel (the node and element lines are most of a deck).
    let mut data: Vec<std::ops::Range<usize>> = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let (loc, text) = &lines[i];
        if text.starts_with('*') {
            let mut full = text.clone();
            while full.ends_with(',') {
                let Some((_, next)) = lines.get(i + 1) else {
                    break;
                };
                let first = next.split(',').next().unwrap_or("");
                if next.starts_with('*') || !first.contains('=') {
                    break;
                }
                full.push_str(next);
                i += 1;
            }
            let (keyword, display, params) = parse_keyword(&full);
            if keyword.is_empty() {
                return Err(files.error(*loc, "a keyword line needs a keyword after '*'"));
            }
            let long = params
                .iter()
                .filter(|p| p.key != "INPUT")
                .flat_map(|p| std::iter::once(p.key.as_str()).chain(p.value.as_deref()))
                .find(|v| v.chars().count() > MAX_FIELD_CHARS);
            if let Some(v) = long {
                return Err(too_long(files, *loc, &display, v));
            }
            cards.push(Card {
                keyword,
                display,
                params,
                loc: *loc,
                data: Vec::new(),
            });
            data.push(i + 1..i + 1);
        } else {
            let Some(range) = data.last_mut() else {
                return Err(files.error(
                    *loc,
                    "data line before the first keyword (keyword lines start with '*')",
                ));
            };
            range.end = i + 1;
        }
        i += 1;
    }
    cards.par_iter_mut().zip(data).for_each(|(card, range)| {
        card.data = lines[range]
            .par_iter()
            .map(|(loc, text)| parse_data(*loc, text))
            .collect();
    });
    for card in cards.iter().filter(|c| c.keyword != "HEADING") {
        for line in &card.data {
            if let Some(f) = line
                .fields
                .iter()
                .find(|f| f.len() > MAX_FIELD_CHARS && f.chars().count() > MAX_FIELD_CHARS)
            {
                return Err(too_long(files, line.loc, &card.display, f));
            }
        }
    }
    Ok(cards)
}

/// The error for a name or field longer than [`MAX_FIELD_CHARS`].
fn too_long(files: &Files, loc: Loc, keyword: &str, field: &str) -> InputError {
    files.error(
        loc,
        format!(
            "{keyword}: '{}' is longer than {MAX_FIELD_CHARS} characters, the most a \
             name or field of a deck may have",
            crate::text::excerpt(field)
        ),
    )
}

/// Splits `*KEYWORD, KEY=value, FLAG` into the matched keyword (no spaces),
/// the displayed keyword and the parameters.
fn parse_keyword(line: &str) -> (String, String, Vec<Param>) {
    let body = line.trim_start_matches('*');
    let mut parts = body.split(',');
    let head = parts.next().unwrap_or("").to_uppercase();
    let words: Vec<&str> = head.split_whitespace().collect();
    let keyword = words.concat();
    let display = format!("*{}", words.join(" "));
    let params = parts
        .filter(|p| !p.trim().is_empty())
        .map(|p| match p.split_once('=') {
            Some((k, v)) => Param {
                key: squeeze_upper(k),
                value: Some(unquote(v.trim()).to_string()),
            },
            None => Param {
                key: squeeze_upper(p),
                value: None,
            },
        })
        .collect();
    (keyword, display, params)
}

fn squeeze_upper(s: &str) -> String {
    s.split_whitespace().collect::<String>().to_uppercase()
}

fn unquote(s: &str) -> &str {
    s.strip_prefix('"')
        .and_then(|t| t.strip_suffix('"'))
        .unwrap_or(s)
}

fn parse_data(loc: Loc, text: &str) -> DataLine {
    let mut fields: Vec<String> = text.split(',').map(|f| f.trim().to_string()).collect();
    let continued = fields.len() > 1 && fields.last().is_some_and(|f| f.is_empty());
    if continued {
        fields.pop();
    }
    DataLine {
        loc,
        fields,
        continued,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyword_parameters_and_data() {
        let text = "** comment\n*Solid  Section, elset=\"Eall\", MATERIAL = steel\n\n1., 2,\n";
        let (_, cards) = read_cards(Path::new("a.inp"), text).unwrap();
        assert_eq!(cards.len(), 1);
        let c = &cards[0];
        assert_eq!(c.keyword, "SOLIDSECTION");
        assert_eq!(c.display, "*SOLID SECTION");
        assert_eq!(c.value("ELSET"), Some("Eall"));
        assert_eq!(c.value("MATERIAL"), Some("steel"));
        assert_eq!(c.loc.line, 2);
        assert_eq!(c.data[0].fields, vec!["1.", "2"]);
        assert!(c.data[0].continued);
        assert_eq!(c.data[0].loc.line, 4);
    }

    #[test]
    fn keyword_line_continues_with_a_parameter() {
        let text = "*ELEMENT, TYPE=C3D8,\nELSET=E1\n1, 2\n";
        let (_, cards) = read_cards(Path::new("a.inp"), text).unwrap();
        assert_eq!(cards[0].value("ELSET"), Some("E1"));
        assert_eq!(cards[0].data.len(), 1);
    }

    #[test]
    fn names_and_fields_longer_than_80_characters_are_refused() {
        let name = "N".repeat(81);
        for text in [
            format!("*NSET, NSET={name}\n1\n"),
            format!("*NSET, NSET=A\n1, {name}\n"),
        ] {
            let e = read_cards(Path::new("a.inp"), &text)
                .unwrap_err()
                .to_string();
            assert!(e.contains("longer than 80 characters"), "{e}");
            assert!(e.len() < 300, "the message quotes an excerpt: {e}");
        }
        let ok = format!("*HEADING\n{name}\n*NSET, NSET={}\n1\n", "N".repeat(80));
        read_cards(Path::new("a.inp"), &ok).unwrap();
    }

    #[test]
    fn data_before_a_keyword_is_an_error() {
        let e = read_cards(Path::new("a.inp"), "\n1, 2, 3\n").unwrap_err();
        assert!(e.to_string().contains("a.inp:2:"), "{e}");
    }
}
