//! VTK XML unstructured-grid files (`.vtu`): the document (field data,
//! point data, points, cells) and its two encodings.
//!
//! - [`Encoding::Binary`] (the default): every array in one
//!   `<AppendedData encoding="raw">` section after the XML, zlib-compressed
//!   in VTK's block layout (module `zlib_blocks`: a `UInt64`
//!   header `[blocks, block size, last block size, compressed sizes..]`
//!   then the blocks); the root element says `header_type="UInt64"` and
//!   `compressor="vtkZLibDataCompressor"`, and each `DataArray` gives its
//!   byte `offset` in the section (counted after the leading `_`). Numbers
//!   are little-endian.
//! - [`Encoding::Ascii`]: every array as text inside its `DataArray`, the
//!   reals in the shortest digits that read back to the same `f64`.
//!
//! Both hold the same values; a non-finite real is refused before anything
//! is written ([`UnstructuredGrid::first_non_finite`]).

use crate::float_text::push_exp;
use crate::zlib_blocks;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::Write;

/// How the arrays of a `.vtu` file are stored.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Encoding {
    /// Appended raw binary, zlib-compressed (`vtkZLibDataCompressor`,
    /// `UInt64` headers): several times smaller and faster to read.
    #[default]
    Binary,
    /// Text inside each `DataArray`.
    Ascii,
}

/// The values of a data array, in one of the VTK types the files use.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// VTK `Float64`.
    Float64(Vec<f64>),
    /// VTK `Int64`.
    Int64(Vec<i64>),
    /// VTK `UInt8`.
    UInt8(Vec<u8>),
}

impl Values {
    /// The VTK type name.
    pub fn type_name(&self) -> &'static str {
        match self {
            Values::Float64(_) => "Float64",
            Values::Int64(_) => "Int64",
            Values::UInt8(_) => "UInt8",
        }
    }

    /// The number of values (tuples times components).
    pub fn len(&self) -> usize {
        match self {
            Values::Float64(v) => v.len(),
            Values::Int64(v) => v.len(),
            Values::UInt8(v) => v.len(),
        }
    }

    /// Whether there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A named `DataArray` of `components` values per tuple.
#[derive(Clone, Debug, PartialEq)]
pub struct DataArray {
    /// The `Name` attribute.
    pub name: String,
    /// Values per tuple (`NumberOfComponents`), at least 1.
    pub components: usize,
    /// The values, tuple after tuple.
    pub values: Values,
}

impl DataArray {
    /// A data array of `components` values per tuple.
    pub fn new(name: impl Into<String>, components: usize, values: Values) -> Self {
        Self {
            name: name.into(),
            components,
            values,
        }
    }

    /// The number of tuples.
    pub fn tuples(&self) -> usize {
        self.values.len() / self.components.max(1)
    }
}

/// The cells of a grid in VTK's layout.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cells {
    /// The point indices of every cell, one cell after the other.
    pub connectivity: Vec<i64>,
    /// Per cell, the end of its points in `connectivity`.
    pub offsets: Vec<i64>,
    /// Per cell, its VTK cell type.
    pub types: Vec<u8>,
}

/// A one-piece VTK unstructured grid with its data arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UnstructuredGrid {
    /// Arrays of the whole data set (`FieldData`), any number of tuples.
    pub field_data: Vec<DataArray>,
    /// Arrays with one tuple per point (`PointData`).
    pub point_data: Vec<DataArray>,
    /// The coordinates of the points, `x y z` per point (m).
    pub points: Vec<f64>,
    /// The cells.
    pub cells: Cells,
}

/// Where a grid holds a non-finite real.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NonFinite {
    /// Which array: field data, point data or the points.
    pub section: Section,
    /// The array's name.
    pub array: String,
    /// The tuple (for point data and points, the point).
    pub tuple: usize,
}

/// The part of a grid an array belongs to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Section {
    /// `FieldData`.
    FieldData,
    /// `PointData`: a tuple is a point.
    PointData,
    /// `Points`: a tuple is a point.
    Points,
}

/// The block size of the compressed arrays (VTK's default), bytes.
const BLOCK_SIZE: usize = 1 << 15;

impl UnstructuredGrid {
    /// The number of points.
    pub fn number_of_points(&self) -> usize {
        self.points.len() / 3
    }

    /// The first non-finite real of the field data, point data or points,
    /// in that order, if any.
    pub fn first_non_finite(&self) -> Option<NonFinite> {
        let in_array = |section, a: &DataArray| match &a.values {
            Values::Float64(v) => v.iter().position(|x| !x.is_finite()).map(|i| NonFinite {
                section,
                array: a.name.clone(),
                tuple: i / a.components.max(1),
            }),
            Values::Int64(_) | Values::UInt8(_) => None,
        };
        self.field_data
            .iter()
            .find_map(|a| in_array(Section::FieldData, a))
            .or_else(|| {
                self.point_data
                    .iter()
                    .find_map(|a| in_array(Section::PointData, a))
            })
            .or_else(|| {
                self.points
                    .iter()
                    .position(|x| !x.is_finite())
                    .map(|i| NonFinite {
                        section: Section::Points,
                        array: "coordinates".into(),
                        tuple: i / 3,
                    })
            })
    }

    /// The arrays in the order the file lists them.
    fn views(&self) -> Vec<View<'_>> {
        let field = self.field_data.iter().map(|a| View::of(a, true));
        let point = self.point_data.iter().map(|a| View::of(a, false));
        let named = |name, components, values| View {
            name,
            components,
            values,
            tuples: false,
        };
        let rest = [
            named("coordinates", 3, Slice::Float64(&self.points)),
            named("connectivity", 1, Slice::Int64(&self.cells.connectivity)),
            named("offsets", 1, Slice::Int64(&self.cells.offsets)),
            named("types", 1, Slice::UInt8(&self.cells.types)),
        ];
        field.chain(point).chain(rest).collect()
    }

    /// Writes the grid as a `.vtu` file in `encoding` to `out`. The caller
    /// checks [`first_non_finite`](Self::first_non_finite) first.
    pub fn write(&self, encoding: Encoding, out: &mut dyn Write) -> std::io::Result<()> {
        let views = self.views();
        match encoding {
            Encoding::Ascii => {
                let texts: Vec<String> = views.par_iter().map(ascii_values).collect();
                let xml = document(self, &views, encoding, |i| {
                    format!("format=\"ascii\">\n{}\n", texts[i])
                });
                out.write_all(xml.as_bytes())?;
            }
            Encoding::Binary => {
                let bytes: Vec<Vec<u8>> = views.iter().map(|v| v.values.le_bytes()).collect();
                let blobs = zlib_blocks::compress_all(&bytes, BLOCK_SIZE);
                drop(bytes);
                let offsets: Vec<usize> = blobs
                    .iter()
                    .scan(0, |at, b| {
                        let offset = *at;
                        *at += b.len();
                        Some(offset)
                    })
                    .collect();
                let xml = document(self, &views, encoding, |i| {
                    format!("format=\"appended\" offset=\"{}\">\n", offsets[i])
                });
                out.write_all(xml.as_bytes())?;
                out.write_all(b"  <AppendedData encoding=\"raw\">\n   _")?;
                for b in &blobs {
                    out.write_all(b)?;
                }
                out.write_all(b"\n  </AppendedData>\n")?;
            }
        }
        out.write_all(b"</VTKFile>\n")
    }
}

/// A borrowed array of values of one VTK type.
#[derive(Copy, Clone)]
enum Slice<'a> {
    Float64(&'a [f64]),
    Int64(&'a [i64]),
    UInt8(&'a [u8]),
}

impl Slice<'_> {
    fn type_name(self) -> &'static str {
        match self {
            Slice::Float64(_) => "Float64",
            Slice::Int64(_) => "Int64",
            Slice::UInt8(_) => "UInt8",
        }
    }

    /// The values as little-endian bytes.
    fn le_bytes(self) -> Vec<u8> {
        match self {
            Slice::Float64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Slice::Int64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Slice::UInt8(v) => v.to_vec(),
        }
    }
}

/// An array as the file lists it.
struct View<'a> {
    name: &'a str,
    components: usize,
    values: Slice<'a>,
    /// Whether the tag states `NumberOfTuples` (field data).
    tuples: bool,
}

impl<'a> View<'a> {
    fn of(a: &'a DataArray, tuples: bool) -> Self {
        let values = match &a.values {
            Values::Float64(v) => Slice::Float64(v),
            Values::Int64(v) => Slice::Int64(v),
            Values::UInt8(v) => Slice::UInt8(v),
        };
        View {
            name: &a.name,
            components: a.components,
            values,
            tuples,
        }
    }
}

/// The XML of `grid` up to the end of its `UnstructuredGrid` element;
/// `body(i)` ends the opening tag of the i-th of `views` (format, offset,
/// and the values if inline).
fn document(
    grid: &UnstructuredGrid,
    views: &[View<'_>],
    encoding: Encoding,
    body: impl Fn(usize) -> String,
) -> String {
    let mut s = String::new();
    let array = |s: &mut String, i: usize, indent: &str| {
        let v = &views[i];
        let _ = write!(
            s,
            "{indent}<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" ",
            v.values.type_name(),
            v.name,
            v.components
        );
        if v.tuples {
            let _ = write!(s, "NumberOfTuples=\"{}\" ", grid.field_data[i].tuples());
        }
        s.push_str(&body(i));
        let _ = writeln!(s, "{indent}</DataArray>");
    };
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\"");
    if encoding == Encoding::Binary {
        s.push_str(" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"");
    }
    s.push_str(">\n  <UnstructuredGrid>\n");
    let (nf, np) = (grid.field_data.len(), grid.point_data.len());
    if nf > 0 {
        s.push_str("    <FieldData>\n");
        (0..nf).for_each(|i| array(&mut s, i, "      "));
        s.push_str("    </FieldData>\n");
    }
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        grid.number_of_points(),
        grid.cells.types.len()
    );
    s.push_str("      <PointData>\n");
    (nf..nf + np).for_each(|i| array(&mut s, i, "        "));
    s.push_str("      </PointData>\n      <Points>\n");
    array(&mut s, nf + np, "        ");
    s.push_str("      </Points>\n      <Cells>\n");
    (nf + np + 1..nf + np + 4).for_each(|i| array(&mut s, i, "        "));
    s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
    s
}

/// The values of `a` as text: reals three tuples a line, integers twenty
/// values a line; blocks of lines are formatted in parallel.
fn ascii_values(a: &View<'_>) -> String {
    const LINES: usize = 2048;
    let per_line = match a.values {
        Slice::Float64(_) => 3 * a.components.max(1),
        Slice::Int64(_) | Slice::UInt8(_) => 20,
    };
    fn lines<T: Sync>(
        values: &[T],
        per_line: usize,
        push: impl Fn(&mut String, &T) + Sync,
    ) -> String {
        let blocks: Vec<String> = values
            .par_chunks(per_line * LINES)
            .map(|block| {
                let mut t = String::new();
                for (l, line) in block.chunks(per_line).enumerate() {
                    t.push_str(if l > 0 { "\n" } else { "" });
                    for (i, v) in line.iter().enumerate() {
                        if i > 0 {
                            t.push(' ');
                        }
                        push(&mut t, v);
                    }
                }
                t
            })
            .collect();
        blocks.join("\n")
    }
    match a.values {
        Slice::Float64(v) => lines(v, per_line, |t, x| push_exp(t, *x)),
        Slice::Int64(v) => lines(v, per_line, |t, x| {
            let _ = write!(t, "{x}");
        }),
        Slice::UInt8(v) => lines(v, per_line, |t, x| {
            let _ = write!(t, "{x}");
        }),
    }
}
