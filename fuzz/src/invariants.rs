//! What a reader must give for any input: an error that names where, or
//! a value with finite numbers. A broken invariant panics with the reason,
//! and libFuzzer records the input.

use std::fmt::Debug;
use std::path::Path;

/// Whether a reader's errors must name a line as well as the file.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Lines {
    /// Line-oriented text (decks, SID, Matrix Market, CalculiX, TOML,
    /// JSON): an error names the line, except the documented ones in
    /// [`WITHOUT_LINE`].
    Required,
    /// A folder of several files (the Matrix Market body): the file is
    /// enough where the error is about how the files fit together.
    FileOnly,
}

/// Errors that name the file but no line, by a fragment of their message,
/// each because no single line is wrong:
pub const WITHOUT_LINE: &[&str] = &[
    // a file the input names is missing or not readable: the error names
    // that file;
    "cannot read",
    // the model as a whole (a deck or model file without elements);
    "the model has no DOFs",
    // CalculiX matrices: a missing diagonal entry names its equation, the
    // line it would have in the DOF file;
    "no diagonal entry for equation",
    // CalculiX and Matrix Market: a matrix whose size differs from the DOF
    // file's names both files;
    "the matrix has",
    // Matrix Market: a file that ends before its size line.
    "no `rows cols entries` line",
];

/// The longest error message without its paths: the readers' own
/// bound and a little more (a message names a file more than once, each
/// time with a line).
pub const MESSAGE_BYTES: usize = flexbody::io::text::MESSAGE_BYTES + 200;

/// Panics unless `message` (an error's Display) is at most
/// [`MESSAGE_BYTES`] long without its paths, names one of the
/// bundle's files, in `dir`, and, with [`Lines::Required`], a line number
/// (`file:LINE:` or `line LINE`) unless it is one of [`WITHOUT_LINE`].
/// With `FLEXBODY_FUZZ_LINES_REPORT` set, an error without a line is
/// printed (`fuzz: no line: ...`) instead, to survey them.
pub fn error_located(message: &str, dir: &Path, lines: Lines) {
    let dir = dir.to_string_lossy();
    assert!(
        message.contains(dir.as_ref()),
        "the error names no input file: {message}"
    );
    // Paths aside, a message quotes at most a short excerpt of its input.
    let own = message.replace(dir.as_ref(), "").len();
    assert!(
        own <= MESSAGE_BYTES,
        "the error is {own} bytes long, paths aside: {}",
        flexbody::io::text::shortened(message)
    );
    if lines == Lines::FileOnly || WITHOUT_LINE.iter().any(|w| message.contains(w)) {
        return;
    }
    if names_line(message, &dir) {
        return;
    }
    if std::env::var_os("FLEXBODY_FUZZ_LINES_REPORT").is_some() {
        // Survey mode: list such errors instead of stopping at the first.
        eprintln!("fuzz: no line: {message}");
        return;
    }
    panic!("the error names no line: {message}");
}

/// Whether `message` holds `<dir>/<name>:<digits>` or `line <digits>`.
fn names_line(message: &str, dir: &str) -> bool {
    let after_path = message.match_indices(dir).any(|(at, _)| {
        let rest = &message[at + dir.len()..];
        let end = rest
            .find(|c: char| c == ':' || c.is_whitespace())
            .unwrap_or(rest.len());
        rest[end..]
            .strip_prefix(':')
            .is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()))
    });
    after_path
        || message
            .match_indices("line ")
            .any(|(at, _)| message[at + 5..].starts_with(|c: char| c.is_ascii_digit()))
}

/// Panics if `values` holds a NaN or an infinity.
pub fn finite_values(what: &str, values: &[f64]) {
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        panic!("accepted input gives a non-finite value {v} in {what}");
    }
}

/// Panics if the `Debug` text of `value` shows a NaN or an infinity
/// outside string and character literals: a check over every number of
/// a returned structure, whatever its shape.
pub fn finite_debug(what: &str, value: &impl Debug) {
    let text = format!("{value:?}");
    if let Some(token) = non_finite_token(&text) {
        panic!("accepted input gives a non-finite value ({token}) in {what}");
    }
}

/// The first `NaN` or `inf` token of Debug text, outside quotes.
fn non_finite_token(text: &str) -> Option<&'static str> {
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            quote @ (b'"' | b'\'') => {
                i += 1;
                while i < bytes.len() && bytes[i] != quote {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            b if b.is_ascii_alphanumeric() || b == b'_' => {
                let start = i;
                while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                    i += 1;
                }
                match &text[start..i] {
                    "NaN" => return Some("NaN"),
                    "inf" => return Some("inf"),
                    _ => {}
                }
            }
            _ => i += 1,
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn debug_text_with_a_nan_or_infinity_is_caught_outside_strings() {
        assert_eq!(non_finite_token("[1.0, NaN]"), Some("NaN"));
        assert_eq!(non_finite_token("x: -inf }"), Some("inf"));
        assert_eq!(non_finite_token("name: \"inf NaN\", c: 'x'"), None);
        assert_eq!(non_finite_token("Info { infinite: 1e308 }"), None);
        assert_eq!(non_finite_token(&format!("{:?}", [f64::MAX, -0.0])), None);
    }

    #[test]
    fn a_line_is_found_after_the_path_or_as_line_n() {
        assert!(names_line("/d/a.inp:12: bad", "/d"));
        assert!(names_line("/d/body.json: line 3, block 'r'", "/d"));
        assert!(!names_line("/d/a.inp: bad", "/d"));
    }
}
