#!/usr/bin/env python3
"""Reads two .vtu files of one grid with meshio and checks that they hold the
same points, cells (types and connectivity), point data and field data:
names, components and values (at most 1 unit in the last place apart).

usage: vtu_compare.py ASCII.vtu BINARY.vtu

BINARY.vtu must be the appended raw, zlib-compressed kind (its root element
says so); ASCII.vtu the inline text kind. Prints one line of what was
compared; exits non-zero on the first difference.

meshio 5.3's reader of raw appended data finds each array by its offset while
it rewrites the offsets of the arrays it has passed, so an array whose
rewritten offset equals a later array's raw offset is taken for it (the file
is then read as corrupt, by chance of the compressed sizes). The binary file
is therefore handed to meshio with each array's raw bytes moved, unchanged
and base64-encoded as the VTK format specifies, into its DataArray
(format="binary"): meshio still decodes the header and inflates the zlib
blocks itself.
"""
import base64
import sys
import tempfile
import xml.etree.ElementTree as ET

import meshio
import numpy as np


def root_attributes(path):
    """The attributes of the VTKFile element (the XML before any binary)."""
    with open(path, "rb") as f:
        head = f.read(4096)
    start = head.index(b"<VTKFile")
    end = head.index(b">", start)
    return ET.fromstring(head[start : end + 1].decode() + "</VTKFile>").attrib


def inline_binary(path):
    """The raw appended, zlib-compressed file at `path` as a file whose
    arrays are inline base64 (header and blocks encoded separately, as VTK
    writes them), in a temporary directory; returns its path."""
    with open(path, "rb") as f:
        raw = f.read()
    tag = b'<AppendedData encoding="raw">'
    start = raw.index(tag)
    stop = raw.index(b"</AppendedData>")
    data = raw[raw.index(b"_", start) + 1 : stop]
    root = ET.fromstring(raw[:start] + raw[stop + len(b"</AppendedData>") :])
    for array in root.iter("DataArray"):
        if array.get("format") != "appended":
            continue
        at = int(array.attrib.pop("offset"))
        blocks = int(np.frombuffer(data[at : at + 8], "<u8")[0])
        header = data[at : at + 8 * (3 + blocks)]
        sizes = np.frombuffer(header, "<u8")[3:]
        body = data[at + len(header) : at + len(header) + int(sizes.sum())]
        array.text = (base64.b64encode(header) + base64.b64encode(body)).decode()
        array.set("format", "binary")
    out = tempfile.mkdtemp() + "/inline.vtu"
    ET.ElementTree(root).write(out)
    return out


def same(what, a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        sys.exit(f"{what}: shapes {a.shape} and {b.shape} differ")
    if a.dtype.kind != b.dtype.kind:
        sys.exit(f"{what}: types {a.dtype} and {b.dtype} differ")
    if a.dtype.kind == "f":
        if not (np.isfinite(a).all() and np.isfinite(b).all()):
            sys.exit(f"{what}: non-finite values")
        a, b = np.ascontiguousarray(a, np.float64), np.ascontiguousarray(b, np.float64)
        ulps = np.abs(a.view(np.int64) - b.view(np.int64))
        # Equal values (+0 and -0 among them) are 0 apart.
        ulps[a == b] = 0
        if ulps.size and ulps.max() > 1:
            sys.exit(f"{what}: values differ by {ulps.max()} units in the last place")
    elif not np.array_equal(a, b):
        sys.exit(f"{what}: values differ")


def main():
    ascii_path, binary_path = sys.argv[1], sys.argv[2]
    attributes = root_attributes(binary_path)
    if attributes.get("compressor") != "vtkZLibDataCompressor" or attributes.get(
        "header_type"
    ) != "UInt64":
        sys.exit(f"{binary_path}: not a zlib-compressed file with UInt64 headers: {attributes}")
    with open(binary_path, "rb") as f:
        if b'<AppendedData encoding="raw">' not in f.read():
            sys.exit(f"{binary_path}: no raw appended data")
    a = meshio.read(ascii_path)
    b = meshio.read(inline_binary(binary_path))
    same("points", a.points, b.points)
    if [c.type for c in a.cells] != [c.type for c in b.cells]:
        sys.exit(f"cell types: {[c.type for c in a.cells]} and {[c.type for c in b.cells]}")
    for k, (ca, cb) in enumerate(zip(a.cells, b.cells)):
        same(f"cell block {k} ({ca.type})", ca.data, cb.data)
    for data in ("point_data", "field_data"):
        da, db = getattr(a, data), getattr(b, data)
        if sorted(da) != sorted(db):
            sys.exit(f"{data} names: {sorted(da)} and {sorted(db)}")
        for name in da:
            same(f"{data} '{name}'", da[name], db[name])
    cells = sum(len(c.data) for c in b.cells)
    print(
        f"meshio {meshio.__version__}: {len(b.points)} points, {cells} cells "
        f"({', '.join(sorted({c.type for c in b.cells}))}), "
        f"{len(b.point_data)} point-data and {len(b.field_data)} field-data arrays agree"
    )


if __name__ == "__main__":
    main()
