//! The binary VTU file (`reduce --vtu`, appended raw zlib blocks) against
//! the ASCII one (`--vtu-ascii`): decoded here with flate2 alone, and read
//! by meshio (`scripts/vtu_compare.py`); its size; non-finite values
//! refused.

use super::support::{
    fails_with, hex_beam, hex_beam_deck, python_imports, reduce_args, reduce_with, run_ok,
    run_script, skip_without_peer,
};
use flexbody::export::vtk;
use flexbody::export::vtu::Encoding;
use flexbody::output;
use flexbody::reduce::Method;
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Values of an array as the file gives them: reals, or integers (Int64
/// and UInt8).
#[derive(Clone, Debug, PartialEq)]
enum Numbers {
    Reals(Vec<f64>),
    Integers(Vec<i64>),
}

/// A `DataArray` read from a file.
#[derive(Clone, Debug, PartialEq)]
struct Array {
    kind: String,
    components: usize,
    values: Numbers,
}

/// The value of attribute `name` in the XML tag `tag`.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// The opening tags of the `DataArray`s in `xml`, each with the text after
/// it up to its closing tag.
fn data_arrays(xml: &str) -> Vec<(&str, &str)> {
    xml.match_indices("<DataArray ")
        .map(|(at, _)| {
            let end = at + xml[at..].find('>').unwrap();
            let close = end + xml[end..].find("</DataArray>").unwrap();
            (&xml[at..=end], &xml[end + 1..close])
        })
        .collect()
}

/// The arrays of an ASCII `.vtu` file by name, parsed with Rust's own
/// number parsing.
fn ascii_arrays(path: &Path) -> BTreeMap<String, Array> {
    let text = std::fs::read_to_string(path).unwrap();
    data_arrays(&text)
        .into_iter()
        .map(|(tag, body)| {
            assert_eq!(attribute(tag, "format"), Some("ascii"), "{tag}");
            let kind = attribute(tag, "type").unwrap().to_string();
            let words = body.split_whitespace();
            let values = if kind == "Float64" {
                Numbers::Reals(words.map(|w| w.parse().unwrap()).collect())
            } else {
                Numbers::Integers(words.map(|w| w.parse().unwrap()).collect())
            };
            array_of(tag, kind, values)
        })
        .collect()
}

fn array_of(tag: &str, kind: String, values: Numbers) -> (String, Array) {
    let components = attribute(tag, "NumberOfComponents").map_or(1, |c| c.parse().unwrap());
    let name = attribute(tag, "Name").unwrap().to_string();
    (
        name,
        Array {
            kind,
            components,
            values,
        },
    )
}

fn u64_at(b: &[u8], i: usize) -> usize {
    u64::from_le_bytes(b[8 * i..8 * i + 8].try_into().unwrap()) as usize
}

/// The arrays of a binary `.vtu` file by name: the XML says where each one
/// starts in the appended section; its `UInt64` header gives the blocks,
/// each inflated here with flate2 and checked against the sizes the header
/// states. Also checks that the arrays fill the section exactly.
fn binary_arrays(path: &Path) -> BTreeMap<String, Array> {
    let bytes = std::fs::read(path).unwrap();
    let marker = b"<AppendedData encoding=\"raw\">";
    let tag_at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("an appended section");
    let xml = std::str::from_utf8(&bytes[..tag_at]).unwrap();
    assert!(xml.contains("header_type=\"UInt64\""), "{xml}");
    assert!(
        xml.contains("compressor=\"vtkZLibDataCompressor\""),
        "{xml}"
    );
    let start = tag_at + bytes[tag_at..].iter().position(|&b| b == b'_').unwrap() + 1;
    let data = &bytes[start..];
    let mut end_of_arrays = 0;
    let arrays = data_arrays(xml)
        .into_iter()
        .map(|(tag, body)| {
            assert_eq!(attribute(tag, "format"), Some("appended"), "{tag}");
            assert!(body.trim().is_empty(), "{tag}");
            let offset: usize = attribute(tag, "offset").unwrap().parse().unwrap();
            let array = &data[offset..];
            let (blocks, block_size, last) = (u64_at(array, 0), u64_at(array, 1), u64_at(array, 2));
            let mut at = 8 * (3 + blocks);
            let mut raw = Vec::new();
            for k in 0..blocks {
                let size = u64_at(array, 3 + k);
                let before = raw.len();
                flate2::read::ZlibDecoder::new(&array[at..at + size])
                    .read_to_end(&mut raw)
                    .unwrap();
                let expected = if k + 1 == blocks { last } else { block_size };
                assert_eq!(raw.len() - before, expected, "{tag}: block {k}");
                at += size;
            }
            end_of_arrays = end_of_arrays.max(offset + at);
            let kind = attribute(tag, "type").unwrap().to_string();
            let values = match kind.as_str() {
                "Float64" => Numbers::Reals(
                    raw.chunks_exact(8)
                        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                        .collect(),
                ),
                "Int64" => Numbers::Integers(
                    raw.chunks_exact(8)
                        .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
                        .collect(),
                ),
                "UInt8" => Numbers::Integers(raw.iter().map(|&b| i64::from(b)).collect()),
                other => panic!("unexpected type {other}"),
            };
            array_of(tag, kind, values)
        })
        .collect();
    assert_eq!(
        &data[end_of_arrays..],
        b"\n  </AppendedData>\n</VTKFile>\n",
        "the arrays fill the appended section"
    );
    arrays
}

/// `reduce MODEL` by `method` with `modes`, written as `dir/NAME.vtu` and
/// `dir/NAME_ascii.vtu` (`--vtu-ascii`): the two paths.
fn both_vtu(
    dir: &Path,
    model: &Path,
    method: &str,
    modes: &str,
    extra: &[&str],
) -> (PathBuf, PathBuf) {
    let name = model.file_stem().unwrap().to_str().unwrap();
    let (binary, ascii) = (
        dir.join(format!("{name}.vtu")),
        dir.join(format!("{name}_ascii.vtu")),
    );
    for (path, flag) in [(&binary, None), (&ascii, Some("--vtu-ascii"))] {
        let mut args = vec!["--vtu", path.to_str().unwrap()];
        args.extend(flag);
        args.extend(extra);
        run_ok(&reduce_args(
            model,
            method,
            modes,
            dir.join(format!("{name}.json")),
            &args,
        ));
    }
    (binary, ascii)
}

/// A steel plate 0.4 x 0.2 m, 2 mm thick, of 4 x 2 cells in the x-y
/// plane, clamped along x = 0: S4 cells, the last column cut into S3
/// pairs. Written as `dir/shell_plate.inp`.
fn shell_plate_deck(dir: &Path) -> PathBuf {
    let (nx, ny) = (4, 2);
    let id = |i: usize, j: usize| 1 + i + (nx + 1) * j;
    let mut text = String::from("*NODE, NSET=ALL\n");
    for j in 0..=ny {
        for i in 0..=nx {
            text += &format!("{}, {}, {}, 0.\n", id(i, j), 0.1 * i as f64, 0.1 * j as f64);
        }
    }
    let (mut quads, mut tris) = (String::new(), String::new());
    let mut e = 0;
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if i + 1 < nx {
                e += 1;
                quads += &format!("{e}, {a}, {b}, {c}, {d}\n");
            } else {
                e += 1;
                tris += &format!("{e}, {a}, {b}, {c}\n");
                e += 1;
                tris += &format!("{e}, {a}, {c}, {d}\n");
            }
        }
    }
    text +=
        &format!("*ELEMENT, TYPE=S4, ELSET=PLATE\n{quads}*ELEMENT, TYPE=S3, ELSET=PLATE\n{tris}");
    text += "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n";
    text += "*SHELL SECTION, ELSET=PLATE, MATERIAL=STEEL\n0.002\n*BOUNDARY\n";
    for j in 0..=ny {
        text += &format!("{}, 1, 6\n", id(0, j));
    }
    let path = dir.join("shell_plate.inp");
    std::fs::write(&path, text).unwrap();
    path
}

/// The hex beam deck (solids: stresses), the side beam (beams: rotations)
/// and a shell plate (stresses on three surfaces, rotations), each written
/// both ways into `dir`.
fn both_models(dir: &Path) -> Vec<(PathBuf, PathBuf)> {
    let plate = shell_plate_deck(dir);
    vec![
        both_vtu(
            dir,
            &hex_beam_deck(),
            "free-residual",
            "2",
            &["--interface", "13"],
        ),
        both_vtu(dir, &super::side_beam_path(), "free", "4", &[]),
        both_vtu(dir, &plate, "free", "6", &[]),
    ]
}

/// The binary file, decoded here with flate2 alone, holds the ASCII file's
/// arrays: the same names, types, components and values, bit for bit (the
/// ASCII digits read back to the same `f64`); and the hex beam's points,
/// node ids and cell types are the mesh's.
#[test]
fn binary_vtu_decodes_to_the_ascii_arrays() {
    let dir = tempfile::tempdir().unwrap();
    for (binary, ascii) in both_models(dir.path()) {
        let (b, a) = (binary_arrays(&binary), ascii_arrays(&ascii));
        assert_eq!(
            b.keys().collect::<Vec<_>>(),
            a.keys().collect::<Vec<_>>(),
            "{}",
            binary.display()
        );
        for (name, array) in &a {
            let other = &b[name];
            assert_eq!(
                (&other.kind, other.components),
                (&array.kind, array.components),
                "{name}"
            );
            match (&other.values, &array.values) {
                (Numbers::Reals(x), Numbers::Reals(y)) => {
                    assert_eq!(x.len(), y.len(), "{name}");
                    let differ = x
                        .iter()
                        .zip(y)
                        .filter(|(p, q)| p.to_bits() != q.to_bits())
                        .count();
                    assert_eq!(differ, 0, "{name}: {differ} values differ");
                }
                (x, y) => assert_eq!(x, y, "{name}"),
            }
        }
        assert!(
            a.keys().any(|k| k.ends_with("stress")) || a.keys().any(|k| k.ends_with("rotation"))
        );
    }
    // The hex beam against its mesh, independently of either file.
    let (_, model) = hex_beam();
    let b = binary_arrays(&dir.path().join("hex_beam.vtu"));
    let coordinates: Vec<f64> = model.nodes().iter().flat_map(|n| n.coords).collect();
    assert_eq!(b["coordinates"].values, Numbers::Reals(coordinates));
    let ids: Vec<i64> = model.nodes().iter().map(|n| n.id as i64).collect();
    assert_eq!(b["node id"].values, Numbers::Integers(ids));
    let types: Vec<i64> = vtk::cell_types(&model).into_iter().map(i64::from).collect();
    assert_eq!(b["types"].values, Numbers::Integers(types));
    assert_eq!(b["mode 01"].components, 3);
    assert_eq!(b["mode 01 stress"].components, 6);
    // The shell plate: quadrilateral and triangle cells, rotations, and
    // stresses on the bottom, middle and top surfaces, which bending makes
    // opposite on the two faces.
    let p = binary_arrays(&dir.path().join("shell_plate.vtu"));
    let Numbers::Integers(types) = &p["types"].values else {
        panic!("cell types are integers")
    };
    assert_eq!(types.iter().filter(|&&t| t == 9).count(), 6);
    assert_eq!(types.iter().filter(|&&t| t == 5).count(), 4);
    assert!(!p.contains_key("mode 01 stress"));
    for layer in ["bottom", "middle", "top"] {
        assert_eq!(p[&format!("mode 01 stress {layer}")].components, 6);
        assert_eq!(p[&format!("mode 01 von Mises {layer}")].components, 1);
    }
    let reals = |name: &str| match &p[name].values {
        Numbers::Reals(v) => v.clone(),
        _ => panic!("{name} holds reals"),
    };
    let (top, bottom) = (reals("mode 01 stress top"), reals("mode 01 stress bottom"));
    let largest = top.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    assert!(largest > 0.0);
    // The first mode bends the plate: sxx on the faces opposite, to the
    // membrane part, which is small.
    for (t, b) in top.iter().zip(&bottom).step_by(6) {
        assert!((t + b).abs() < 1e-6 * largest, "top {t}, bottom {b}");
    }
}

/// meshio, an independent reader, reads the binary file (appended raw,
/// zlib, UInt64 headers) as the same grid as the ASCII one: points, cell
/// blocks, point and field data (`scripts/vtu_compare.py`). Skipped, with
/// a message, when `python3` cannot import meshio, unless
/// [`peers_required`](super::support::peers_required).
#[test]
fn binary_vtu_reads_in_meshio_as_the_ascii_one() {
    if python_imports("meshio").is_err() {
        skip_without_peer("binary_vtu_reads_in_meshio_as_the_ascii_one", "meshio");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (binary, ascii) in both_models(dir.path()) {
        let log = run_script("vtu_compare.py", &[&ascii, &binary]);
        assert!(log.contains("arrays agree"), "{}: {log}", binary.display());
    }
}

/// A steel block of `nx x ny x nz` C3D8 elements (2.0 x 0.24 x 0.2 m), as
/// `bench/gen_block.py` writes it.
fn block_deck(nx: usize, ny: usize, nz: usize) -> String {
    let id = |i, j, k| 1 + i + (nx + 1) * (j + (ny + 1) * k);
    let mut s = String::from("*NODE, NSET=NALL\n");
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let (x, y, z) = (
                    2.0 * i as f64 / nx as f64,
                    0.24 * j as f64 / ny as f64,
                    0.2 * k as f64 / nz as f64,
                );
                s += &format!("{}, {x}, {y}, {z}\n", id(i, j, k));
            }
        }
    }
    s += "*ELEMENT, TYPE=C3D8, ELSET=EALL\n";
    let mut e = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                e += 1;
                let n = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                s += &format!("{e}, {}\n", n.map(|v| v.to_string()).join(", "));
            }
        }
    }
    s + "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n"
}

/// The binary file is at least 3 times smaller than the ASCII one on a
/// solid block (3,000 DOFs here; `docs/performance.md` has the 60k-DOF
/// figure): both hold the same arrays (the tests above), so the ratio is
/// the encoding's.
#[test]
fn binary_vtu_is_at_least_3x_smaller_than_ascii() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("block.inp");
    std::fs::write(&deck, block_deck(24, 6, 5)).unwrap();
    let (binary, ascii) = both_vtu(dir.path(), &deck, "free", "10", &[]);
    let size = |p: &Path| std::fs::metadata(p).unwrap().len() as f64;
    let ratio = size(&ascii) / size(&binary);
    eprintln!(
        "block 24x6x5 C3D8, 10 modes: ASCII {} B, binary {} B, ratio {ratio:.2}",
        size(&ascii),
        size(&binary)
    );
    assert!(ratio >= 3.0, "ASCII / binary = {ratio:.2}");
}

/// A NaN or infinity in the fields is refused in both encodings, naming the
/// file, the array and the node, and leaves an existing file as it was.
#[test]
fn vtu_refuses_non_finite_values() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 2, &[13]);
    let mut fields = output::mode_fields(&model, &body).unwrap();
    let node = fields.stress_nodes[3];
    fields.stress[3][(2, 1)] = f64::NAN;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.vtu");
    std::fs::write(&path, "before").unwrap();
    for encoding in [Encoding::Binary, Encoding::Ascii] {
        let e = vtk::write_vtu(&model, &fields, encoding, &path)
            .unwrap_err()
            .to_string();
        for needle in [
            "body.vtu",
            "non-finite",
            "\"mode 02 stress\"",
            &format!("node {node}"),
        ] {
            assert!(e.contains(needle), "{encoding:?}: '{needle}' in {e}");
        }
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "before");
    }
    // An infinite displacement in the first mode.
    let mut fields = output::mode_fields(&model, &body).unwrap();
    fields.modes.basis[(0, 0)] = f64::INFINITY;
    let dof = fields.modes.dof_map.dofs()[0];
    let e = vtk::write_vtu(&model, &fields, Encoding::Binary, &path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("\"mode 01\" at node {}", dof.node)),
        "{e}"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary left"
    );
}

/// `--vtu-ascii` without `--vtu` is a usage error (exit 2).
#[test]
fn vtu_ascii_needs_vtu() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.json");
    fails_with(
        &reduce_args(hex_beam_deck(), "free", "4", &out, &["--vtu-ascii"]),
        &["--vtu"],
    );
}
