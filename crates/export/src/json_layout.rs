//! The layout of JSON reduced-body files: pretty-printed for the top-level
//! keys and the elements of their arrays, one line per element inside them.
//! A row of the basis, a DOF or a mode is then one line: a file of 3e5 DOFs
//! has 3e5 basis lines instead of 1.1e7, is a third smaller and quicker to
//! write, and a reading error still names a line that shows what is wrong.

use serde_json::ser::Formatter;
use std::io::{self, Write};

/// Levels of nesting laid out over several lines; deeper ones stay on one.
const PRETTY_LEVELS: usize = 2;

/// A [`Formatter`] like serde_json's `PrettyFormatter` (two-space indent)
/// for the outer [`PRETTY_LEVELS`] levels and compact below them.
#[derive(Default)]
pub(crate) struct RowsFormatter {
    level: usize,
    has_value: bool,
}

impl RowsFormatter {
    fn pretty(&self) -> bool {
        self.level <= PRETTY_LEVELS
    }

    fn open<W: ?Sized + Write>(&mut self, w: &mut W, bracket: &[u8]) -> io::Result<()> {
        self.level += 1;
        self.has_value = false;
        w.write_all(bracket)
    }

    fn close<W: ?Sized + Write>(&mut self, w: &mut W, bracket: &[u8]) -> io::Result<()> {
        let pretty = self.pretty();
        self.level -= 1;
        if pretty && self.has_value {
            w.write_all(b"\n")?;
            indent(w, self.level)?;
        }
        w.write_all(bracket)
    }

    fn element<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if self.pretty() {
            w.write_all(if first { b"\n" } else { b",\n" })?;
            indent(w, self.level)
        } else if first {
            Ok(())
        } else {
            w.write_all(b",")
        }
    }
}

fn indent<W: ?Sized + Write>(w: &mut W, level: usize) -> io::Result<()> {
    for _ in 0..level {
        w.write_all(b"  ")?;
    }
    Ok(())
}

impl Formatter for RowsFormatter {
    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.close(w, b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        self.element(w, first)
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.close(w, b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        self.element(w, first)
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(if self.pretty() { b": " } else { b":" })
    }

    fn end_object_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }
}

/// Writes `value` in this layout.
pub(crate) fn to_writer<W: Write, T: serde::Serialize + ?Sized>(
    w: W,
    value: &T,
) -> serde_json::Result<()> {
    let mut ser = serde_json::Serializer::with_formatter(w, RowsFormatter::default());
    value.serialize(&mut ser)
}

/// Serialises `rows` (a JSON array of arrays) with each row's text made in
/// parallel, as compact JSON: the text the layout writes below
/// [`PRETTY_LEVELS`] (serde_json's own digits), for JSON only. The basis of
/// a 3e5-DOF body is 1.1e7 numbers.
pub(crate) fn rows_in_parallel<S: serde::Serializer>(
    rows: &[Vec<f64>],
    serializer: S,
) -> Result<S::Ok, S::Error> {
    use rayon::prelude::*;
    use serde::ser::Error as _;
    let texts: Vec<Box<serde_json::value::RawValue>> = rows
        .par_iter()
        .map(serde_json::value::to_raw_value)
        .collect::<Result<_, _>>()
        .map_err(S::Error::custom)?;
    serde::Serialize::serialize(&texts, serializer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn outer_levels_pretty_rows_on_one_line() {
        let doc = json!({
            "format": "x",
            "empty": [],
            "basis": [[1.0, -2.5], [0.0, 3.0]],
            "dofs": [{"node": 1, "kind": "ux"}],
        });
        let mut out = Vec::new();
        to_writer(&mut out, &doc).unwrap();
        let text = String::from_utf8(out).unwrap();
        let want = "{\n  \"basis\": [\n    [1.0,-2.5],\n    [0.0,3.0]\n  ],\n  \
                    \"dofs\": [\n    {\"kind\":\"ux\",\"node\":1}\n  ],\n  \"empty\": [],\n  \
                    \"format\": \"x\"\n}";
        assert_eq!(text, want);
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, doc);
    }

    /// Rows made in parallel are the text the layout makes of them itself.
    #[test]
    fn rows_made_in_parallel_are_laid_out_the_same() {
        #[derive(serde::Serialize)]
        struct Direct {
            basis: Vec<Vec<f64>>,
        }
        #[derive(serde::Serialize)]
        struct Parallel {
            #[serde(serialize_with = "rows_in_parallel")]
            basis: Vec<Vec<f64>>,
        }
        let basis: Vec<Vec<f64>> = (0..1000)
            .map(|i| {
                (0..7)
                    .map(|j| ((i * 7 + j) as f64).sin() * 10f64.powi(j - 3))
                    .collect()
            })
            .chain([vec![], vec![0.0, -0.0, 1e300, -5e-324]])
            .collect();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        to_writer(
            &mut a,
            &Direct {
                basis: basis.clone(),
            },
        )
        .unwrap();
        to_writer(&mut b, &Parallel { basis }).unwrap();
        assert_eq!(String::from_utf8(a).unwrap(), String::from_utf8(b).unwrap());
    }
}
