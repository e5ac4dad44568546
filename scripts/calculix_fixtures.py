#!/usr/bin/env python3
"""CalculiX fixtures for flexbody's cross-check (tests/flexbody/calculix.rs).

    calculix_fixtures.py generate OUT_DIR       write decks, run ccx, keep the results
    calculix_fixtures.py compare STORED FRESH   compare two fixture folders numerically

Each fixture OUT_DIR/<name>/ holds
  <name>.inp         the deck: mesh, steel, and two steps, *FREQUENCY with a
                     mode count, then *FREQUENCY, SOLVER=MATRIXSTORAGE;
  <name>.sti/.mas    stiffness K and mass M as `row col value` (1-based, upper
                     triangle) and <name>.dof (`node.direction` per equation),
                     written by the MATRIXSTORAGE step;
  frequencies.txt    the lowest natural frequencies in Hz, one per line, as
                     ccx prints them in <name>.dat (8 significant digits).

SI units: m, kg, s, N, Pa. Steel: E = 2.1e11 Pa, nu = 0.3, rho = 7850 kg/m^3.
Element node numbering is that of Abaqus/CalculiX. ccx runs single-threaded
(`OMP_NUM_THREADS=1 ccx -i <name>` in a temporary folder), which makes its
output repeat exactly. Only python3's standard library is used.
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

YOUNGS_MODULUS = 2.1e11
POISSON_RATIO = 0.3
DENSITY = 7850.0

# Corner offsets of a hexahedron in Abaqus/CalculiX order (face z = 0
# counter-clockwise seen from +z, then face z = 1).
HEX_CORNERS = [
    (0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
    (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),
]
# Mid-side nodes 9..20 of C3D20/C3D20R: the edges between these corners.
HEX20_EDGES = [
    (0, 1), (1, 2), (2, 3), (3, 0),
    (4, 5), (5, 6), (6, 7), (7, 4),
    (0, 4), (1, 5), (2, 6), (3, 7),
]
# Mid-side nodes 5..10 of C3D10.
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
# Mid-edge nodes 7-15 of the 15-node wedge: bottom triangle, top triangle,
# vertical edges.
WEDGE15_EDGES = [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)]
# Freudenthal (Kuhn) split of the unit cube into 6 tetrahedra along the
# diagonal 0-6; the same split in every cube of a grid is conforming.
KUHN_TETS = [
    (0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6),
    (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6),
]
# Two wedges per hexahedron, cut along the diagonal 0-2 of the z faces.
HEX_WEDGES = [(0, 1, 2, 4, 5, 6), (0, 2, 3, 4, 6, 7)]


class Mesh:
    """Nodes on a lattice of spacing (lx/nx, ly/ny, lz/nz) / 2, so that
    corner and mid-side nodes share one numbering: id = lattice index + 1."""

    def __init__(self, n, size):
        self.n = n
        self.size = size
        self.used = {}

    def node(self, i, j, k):
        """Node id of lattice point (i, j, k), in half-element steps."""
        nx, ny, nz = (2 * m + 1 for m in self.n)
        node_id = 1 + i + nx * (j + ny * k)
        self.used[node_id] = (i, j, k)
        return node_id

    def coordinates(self, node_id):
        ijk = self.used[node_id]
        return tuple(round(c * s / (2 * m), 12) for c, s, m in zip(ijk, self.size, self.n))

    def cells(self):
        nx, ny, nz = self.n
        for k in range(nz):
            for j in range(ny):
                for i in range(nx):
                    yield i, j, k


def corner(cell, offset):
    return tuple(2 * c + o * 2 for c, o in zip(cell, offset))


def midpoint(a, b):
    return tuple((x + y) // 2 for x, y in zip(a, b))


def signed_volume(mesh, ids):
    p = [mesh.coordinates(n) for n in ids[:4]]
    a = [p[1][d] - p[0][d] for d in range(3)]
    b = [p[2][d] - p[0][d] for d in range(3)]
    c = [p[3][d] - p[0][d] for d in range(3)]
    return (a[0] * (b[1] * c[2] - b[2] * c[1])
            - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))


def hex_elements(mesh, quadratic):
    elements = []
    for cell in mesh.cells():
        points = [corner(cell, o) for o in HEX_CORNERS]
        if quadratic:
            points += [midpoint(points[a], points[b]) for a, b in HEX20_EDGES]
        elements.append([mesh.node(*p) for p in points])
    return elements


def tet_elements(mesh, quadratic):
    elements = []
    for cell in mesh.cells():
        cube = [corner(cell, o) for o in HEX_CORNERS]
        for tet in KUHN_TETS:
            points = [cube[c] for c in tet]
            ids = [mesh.node(*p) for p in points]
            if signed_volume(mesh, ids) < 0.0:
                points[1], points[2] = points[2], points[1]
            if quadratic:
                points += [midpoint(points[a], points[b]) for a, b in TET10_EDGES]
            elements.append([mesh.node(*p) for p in points])
    return elements


def wedge_elements(mesh, quadratic=False):
    elements = []
    for cell in mesh.cells():
        cube = [corner(cell, o) for o in HEX_CORNERS]
        for wedge in HEX_WEDGES:
            points = [cube[c] for c in wedge]
            if quadratic:
                points += [midpoint(points[a], points[b]) for a, b in WEDGE15_EDGES]
            elements.append([mesh.node(*p) for p in points])
    return elements


# name: (element type, elements per direction, size in m, generator, clamped
# face x = 0, requested frequencies). ccx's ARPACK (ncv = 5 x requested, tol
# 1e-2, shift 1 rad^2/s^2) returns spurious modes of free bodies when ncv
# comes close to the number of equations: keep 5 x requested below ~0.6 N.
# tests/flexbody/calculix.rs checks the stored frequencies against a dense
# solve of the stored K and M.
#
# The C3D20R plate has two elements across its width: with one element across
# both width and thickness (2 x 1 x 1), the 2x2x2 rule leaves hourglass modes
# in K that are also null vectors of M (integrated with the same rule), so
# K - sigma M is singular for every shift.
FIXTURES = {
    "hex_beam": ("C3D8", (6, 1, 1), (0.6, 0.1, 0.1), lambda m: hex_elements(m, False), False, 10),
    "hex20_beam": ("C3D20", (2, 1, 1), (0.4, 0.1, 0.1), lambda m: hex_elements(m, True), False, 12),
    "plate_c3d20r": ("C3D20R", (2, 2, 1), (0.2, 0.2, 0.02), lambda m: hex_elements(m, True), True, 10),
    "tet_beam": ("C3D10", (1, 1, 1), (0.2, 0.1, 0.1), lambda m: tet_elements(m, True), False, 10),
    "tet4_beam": ("C3D4", (6, 1, 1), (0.6, 0.1, 0.1), lambda m: tet_elements(m, False), False, 10),
    "wedge_block": ("C3D6", (2, 2, 2), (0.2, 0.2, 0.2), wedge_elements, False, 10),
    "wedge15_beam": ("C3D15", (2, 1, 1), (0.4, 0.1, 0.1), lambda m: wedge_elements(m, True), False, 12),
    "hex8r_beam": ("C3D8R", (6, 2, 2), (0.6, 0.1, 0.1), lambda m: hex_elements(m, False), False, 10),
}


# Decks built on a mesh of FIXTURES with more cards: name -> (mesh fixture
# tuple, function of (mesh, elements) returning a dict of optional line
# lists: "nodes" (more *NODE lines), "elements" (whole *ELEMENT cards),
# "material" (replaces the material and section cards), "model" (cards
# after the boundary conditions, before the steps), "place" (a function
# moving each node's (x, y, z), for curved meshes), "perturbation" (True:
# an unloaded *STATIC step first, the frequency steps PERTURBATION: ccx
# computes the coefficients of *MPCs in a static step only)). Lists of their own
# per topic are merged into CUSTOM below.
CUSTOM = {}


def tip_face(mesh):
    """Corner nodes of the face x = lx (the last lattice plane)."""
    last = 2 * mesh.n[0]
    return sorted(i for i, ijk in mesh.used.items() if ijk[0] == last)


def node_at(mesh, i, j, k):
    """The id of an existing lattice node (half-element steps)."""
    ids = [n for n, ijk in mesh.used.items() if ijk == (i, j, k)]
    if not ids:
        raise SystemExit(f"no node at lattice point {(i, j, k)}")
    return ids[0]


def constraint_equations(mesh, elements):
    """*EQUATION: the tip face's uz tied together, and a two-term inclined
    equation between a tip node's ux and another's uy."""
    tip = tip_face(mesh)
    lines = ["*EQUATION"]
    for n in tip[1:]:
        lines += ["2", f"{n}, 3, 1.0, {tip[0]}, 3, -1.0"]
    lines += ["3", f"{tip[1]}, 1, 2.0, {tip[2]}, 2, -1.0, {tip[3]}, 1, 0.5"]
    return {"model": lines}


def constraint_mpcs(mesh, elements):
    """*MPC PLANE (a tip corner in the plane of the other three), STRAIGHT
    (two nodes of an edge on the line through two others) and BEAM (a
    constant distance across the bar) on a clamped bar."""
    nx = 2 * mesh.n[0]
    plane = [node_at(mesh, nx, 0, 0), node_at(mesh, nx, 2, 0), node_at(mesh, nx, 0, 2), node_at(mesh, nx, 2, 2)]
    straight = [node_at(mesh, 2, 0, 0), node_at(mesh, nx, 0, 0), node_at(mesh, 6, 0, 0), node_at(mesh, 8, 0, 0)]
    # Not chained: ccx 2.20 gets a chain of these (a BEAM's dependent DOF
    # among a PLANE's terms) wrong; flexbody's elimination of chains is
    # checked against a null-space solve in crates/fem.
    beam = [node_at(mesh, nx - 2, 0, 2), node_at(mesh, 4, 2, 0)]
    return {"perturbation": True, "model": [
        "*MPC", "PLANE, " + ", ".join(map(str, plane)),
        "*MPC", "STRAIGHT, " + ", ".join(map(str, straight)),
        "*MPC", "BEAM, " + ", ".join(map(str, beam)),
    ]}


def tip_reference(mesh):
    x, y, z = (s for s in mesh.size)
    return [f"9001, {x!r}, {y / 2!r}, {z / 2!r}"]


def constraint_rigid_body(mesh, elements):
    """*RIGID BODY of the tip face with a point mass on its reference node."""
    tip = tip_face(mesh)
    return {
        "nodes": tip_reference(mesh),
        "elements": ["*ELEMENT, TYPE=MASS, ELSET=TIPMASS", "9001, 9001"],
        "model": [
            "*NSET, NSET=TIP", ", ".join(map(str, tip)),
            "*RIGID BODY, NSET=TIP, REF NODE=9001",
            "*MASS, ELSET=TIPMASS", "2.5",
        ],
    }


def constraint_distributing(mesh, elements):
    """*DISTRIBUTING COUPLING (DCOUP3D) of the tip face, equal weights given
    as 2.0, a point mass on the reference node. (With unequal weights, whose
    weighted centre is off the reference node, ccx 2.20 differs from the
    moment-consistent RBE3 flexbody implements.)"""
    tip = tip_face(mesh)
    return {
        "nodes": tip_reference(mesh),
        "elements": [
            "*ELEMENT, TYPE=DCOUP3D, ELSET=DIST", "9002, 9001",
            "*ELEMENT, TYPE=MASS, ELSET=TIPMASS", "9001, 9001",
        ],
        "model": [
            "*DISTRIBUTING COUPLING, ELSET=DIST",
        ] + [f"{n}, 2.0" for n in tip] + [
            "*MASS, ELSET=TIPMASS", "2.5",
        ],
    }


def constraint_tie(mesh, elements):
    """*TIE of a second, finer block (x from lx to 2 lx, 4 x 3 x 3 C3D8,
    numbered from 10001) to the bar's far face: slave the block's face S6,
    master the bar's faces S4; non-matching nodes."""
    lx, ly, lz = mesh.size
    n = (4, 3, 3)
    ids = {}
    nodes = []
    for k in range(n[2] + 1):
        for j in range(n[1] + 1):
            for i in range(n[0] + 1):
                ids[(i, j, k)] = 10001 + len(ids)
                x = (lx + lx * i / n[0], ly * j / n[1], lz * k / n[2])
                nodes.append(f"{ids[(i, j, k)]}, {round(x[0], 12)!r}, {round(x[1], 12)!r}, {round(x[2], 12)!r}")
    cells = []
    for k in range(n[2]):
        for j in range(n[1]):
            for i in range(n[0]):
                cells.append([ids[(i + a, j + b, k + c)] for a, b, c in HEX_CORNERS])
    block = ["*ELEMENT, TYPE=C3D8, ELSET=EB"]
    block += [f"{10001 + e}, " + ", ".join(map(str, c)) for e, c in enumerate(cells)]
    slave = [10001 + e for e, _ in enumerate(cells) if e % n[0] == 0]
    master = [number for number, ids_ in enumerate(elements, start=1)
              if all(mesh.used[i][0] >= 2 * mesh.n[0] - 2 for i in ids_)]
    return {
        "nodes": nodes,
        "elements": block,
        "model": [
            "*SOLID SECTION, ELSET=EB, MATERIAL=STEEL",
            "*ELSET, ELSET=SLAVEELEMENTS", ", ".join(map(str, slave)),
            "*ELSET, ELSET=MASTERELEMENTS", ", ".join(map(str, master)),
            "*SURFACE, NAME=SLAVE, TYPE=ELEMENT", "SLAVEELEMENTS, S6",
            "*SURFACE, NAME=MASTER, TYPE=ELEMENT", "MASTERELEMENTS, S4",
            "*TIE, NAME=JOINT", "SLAVE, MASTER",
        ],
    }


def local_systems(mesh, elements):
    """*TRANSFORM: the tip face held tangentially in a cylindrical system
    about the bar's axis (radial and axial free), a node held along an
    inclined axis of a rectangular system, and an *EQUATION with a term
    along a local axis."""
    lx, ly, lz = mesh.size
    nx = 2 * mesh.n[0]
    tip = tip_face(mesh)
    inclined = node_at(mesh, 6, 0, 0)
    local_term = node_at(mesh, 8, 2, 2)
    other = node_at(mesh, 8, 0, 2)
    return {"model": [
        "*NSET, NSET=TIPT", ", ".join(map(str, tip)),
        "*TRANSFORM, NSET=TIPT, TYPE=C", f"0.0, {ly / 2!r}, {lz / 2!r}, 1.0, {ly / 2!r}, {lz / 2!r}",
        "*NSET, NSET=INCLINED", f"{inclined}",
        "*TRANSFORM, NSET=INCLINED", "1.0, 1.0, 0.0, -1.0, 1.0, 1.0",
        "*NSET, NSET=LOCALTERM", f"{local_term}",
        "*TRANSFORM, NSET=LOCALTERM", "0.0, 1.0, 1.0, 1.0, 0.0, 0.0",
        "*BOUNDARY", "TIPT, 2", f"{inclined}, 1",
        "*EQUATION", "2", f"{local_term}, 1, 1.0, {other}, 3, -1.0",
    ]}


CLAMPED_BAR = ("C3D8", (6, 1, 1), (0.6, 0.1, 0.1), lambda m: hex_elements(m, False), True, 10)
CUSTOM.update({
    "equation_bar": (CLAMPED_BAR, constraint_equations),
    "mpc_bar": (CLAMPED_BAR, constraint_mpcs),
    "rigid_body_bar": (CLAMPED_BAR, constraint_rigid_body),
    "distributing_bar": (CLAMPED_BAR, constraint_distributing),
    "tie_blocks": (("C3D8", (3, 2, 2), (0.3, 0.1, 0.1), lambda m: hex_elements(m, False), True, 10),
                   constraint_tie),
    "transform_bar": (CLAMPED_BAR, local_systems),
})


# Anisotropic materials (tests/flexbody/calculix_materials.rs): clamped
# bars, orthotropic by engineering constants in a rotated rectangular
# system, fully anisotropic, orthotropic in a cylindrical system on a ring
# segment, and an isotropic *ELASTIC and *DENSITY read from temperature
# tables at a uniform initial temperature.
ENGINEERING = "1.4e11, 9.0e9, 1.1e10, 0.28, 0.31, 0.4, 5.0e9, 4.0e9"


def material_cards(elastic, orientation=None, density=None):
    section = "*SOLID SECTION, ELSET=EALL, MATERIAL=COMPOSITE"
    if orientation:
        section += ", ORIENTATION=" + orientation
    return ["*MATERIAL, NAME=COMPOSITE"] + elastic + (density or ["*DENSITY", "1600."]) + [section]


def ortho_rotated(mesh, elements):
    return {
        "model": [],
        "material": [
            "*ORIENTATION, NAME=TURNED, SYSTEM=RECTANGULAR",
            "0.8, 0.5, -0.3, -0.2, 0.9, 0.4",
            "1, 25.",
        ] + material_cards(["*ELASTIC, TYPE=ENGINEERING CONSTANTS", ENGINEERING, "3.0e9, 0."], "TURNED"),
    }


def aniso_block(mesh, elements):
    # Symmetric positive definite, every coupling present (GPa), in
    # CalculiX's order D1111, D1122, D2222, D1133, D2233, D3333, D1112, ...
    d = [210, 60, 180, 55, 50, 160, 8, -6, 4, 70, 5, 3, -7, 2, 65, 6, -4, 9, -3, 5, 60]
    v = [f"{x}.e9" for x in d]
    return {"material": [
        "*ORIENTATION, NAME=SKEW",
        "1., 1., 0., -1., 1., 1.",
    ] + material_cards(["*ELASTIC, TYPE=ANISO", ", ".join(v[:8]), ", ".join(v[8:16]), ", ".join(v[16:]) + ", 0."], "SKEW")}


def ring(p):
    # x along the arc (60 degrees over the bar's length), y inwards from
    # radius 0.3 m, z along the axis: a right-handed map of the bar.
    import math
    x, y, z = p
    theta = math.radians(60.0) * x / 0.6
    r = 0.3 - y
    return (round(r * math.cos(theta), 12), round(r * math.sin(theta), 12), z)


def cylindrical_ring(mesh, elements):
    # ORTHO: D1111, D1122, D2222, D1133, D2233, D3333, D1212, D1313 / D2323.
    return {"place": ring, "material": [
        "*ORIENTATION, NAME=POLAR, SYSTEM=CYLINDRICAL",
        "0., 0., 0., 0., 0., 1.",
    ] + material_cards([
        "*ELASTIC, TYPE=ORTHO",
        "2.0e10, 6.0e9, 1.5e11, 5.0e9, 7.0e9, 1.8e10, 4.0e9, 3.0e9",
        "5.5e9, 0.",
    ], "POLAR")}


def temperature_table(mesh, elements):
    return {"material": [
        "*MATERIAL, NAME=HOT",
        "*ELASTIC",
        "2.1e11, 0.30, 20.",
        "1.9e11, 0.31, 200.",
        "1.5e11, 0.33, 500.",
        "*DENSITY",
        "7850., 20.",
        "7700., 400.",
        "*SOLID SECTION, ELSET=EALL, MATERIAL=HOT",
    ], "model": ["*NSET, NSET=NALL"] + [
        ", ".join(map(str, sorted(mesh.used)[i:i + 16])) for i in range(0, len(mesh.used), 16)
    ] + [
        "*INITIAL CONDITIONS, TYPE=TEMPERATURE",
        "NALL, 310.",
    ]}


CLAMPED_HEX8R = ("C3D8R", (6, 2, 2), (0.6, 0.1, 0.1), lambda m: hex_elements(m, False), True, 10)
CLAMPED_HEX20 = ("C3D20", (2, 1, 1), (0.4, 0.1, 0.1), lambda m: hex_elements(m, True), True, 10)
CUSTOM.update({
    "ortho_rotated_block": (CLAMPED_HEX20, ortho_rotated),
    "ortho_rotated_c3d8r": (CLAMPED_HEX8R, ortho_rotated),
    "aniso_block": (CLAMPED_BAR, aniso_block),
    "cylindrical_ring": (CLAMPED_BAR, cylindrical_ring),
    "temperature_bar": (CLAMPED_BAR, temperature_table),
})


def all_fixtures():
    names = list(FIXTURES) + list(CUSTOM)
    if len(set(names)) != len(names):
        raise SystemExit("a fixture name is used twice")
    return names


def deck(name):
    if name in CUSTOM:
        params, customise = CUSTOM[name]
    else:
        params, customise = FIXTURES[name], None
    kind, n, size, generate, clamped, count = params
    mesh = Mesh(n, size)
    elements = generate(mesh)
    extra = customise(mesh, elements) if customise else {}
    lines = [
        f"** {name}: {len(elements)} {kind} elements, {size[0]} x {size[1]} x {size[2]} m, steel, SI units.",
        "** Generated by scripts/calculix_fixtures.sh; do not edit.",
        "*NODE",
    ]
    place = extra.get("place", lambda p: p)
    for node_id in sorted(mesh.used):
        x, y, z = place(mesh.coordinates(node_id))
        lines.append(f"{node_id}, {x!r}, {y!r}, {z!r}")
    lines += extra.get("nodes", [])
    lines.append(f"*ELEMENT, TYPE={kind}, ELSET=EALL")
    for number, ids in enumerate(elements, start=1):
        fields = [str(number)] + [str(i) for i in ids]
        # At most 16 entries per line: continue longer elements on the next line.
        lines.append(", ".join(fields[:16]) + ("," if len(fields) > 16 else ""))
        if len(fields) > 16:
            lines.append(", ".join(fields[16:]))
    lines += extra.get("elements", [])
    if clamped:
        lines.append("*NSET, NSET=CLAMPED")
        fixed = sorted(i for i, ijk in mesh.used.items() if ijk[0] == 0)
        for start in range(0, len(fixed), 16):
            lines.append(", ".join(str(i) for i in fixed[start:start + 16]))
    lines += extra.get("material", [
        "*MATERIAL, NAME=STEEL",
        "*ELASTIC",
        f"{YOUNGS_MODULUS!r}, {POISSON_RATIO!r}",
        "*DENSITY",
        f"{DENSITY!r}",
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
    ])
    if clamped:
        lines += ["*BOUNDARY", "CLAMPED, 1, 3"]
    lines += extra.get("model", [])
    step = "*STEP"
    if extra.get("perturbation"):
        lines += ["*STEP", "*STATIC", "*END STEP"]
        step = "*STEP, PERTURBATION"
    lines += [
        step,
        "*FREQUENCY",
        f"{count}",
        "*END STEP",
        step,
        "*FREQUENCY, SOLVER=MATRIXSTORAGE",
        "*END STEP",
    ]
    return "\n".join(lines) + "\n"


def frequencies_from_dat(path):
    """Frequencies (cycles/time) of the first eigenvalue table of a .dat file."""
    with open(path) as f:
        text = f.read()
    start = text.find("E I G E N V A L U E   O U T P U T")
    if start < 0:
        raise SystemExit(f"{path}: no eigenvalue output")
    values = []
    for line in text[start:].splitlines()[1:]:
        fields = line.split()
        if not fields:
            if values:
                break
            continue
        if re.fullmatch(r"\d+", fields[0]) and len(fields) == 5:
            values.append(fields[3])
        elif values:
            break
    if not values:
        raise SystemExit(f"{path}: empty eigenvalue table")
    return values


def run_ccx(directory, name):
    # One thread: with two, SPOOLES's threaded factorisation changes the
    # round-off from run to run, and ARPACK's frequencies (tol 1e-2) move by
    # ~5e-7. Single-threaded runs of the same ccx build repeat exactly.
    single = {v: "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBER_OF_CPUS",
                               "CCX_NPROC_EQUATION_SOLVER", "CCX_NPROC_STIFFNESS", "CCX_NPROC_RESULTS")}
    env = dict(os.environ, **single)
    log_path = os.path.join(directory, "ccx.log")
    with open(log_path, "w") as log:
        result = subprocess.run(["ccx", "-i", name], cwd=directory, env=env,
                                stdout=log, stderr=subprocess.STDOUT)
    with open(log_path) as f:
        log_text = f.read()
    if result.returncode != 0 or "*ERROR" in log_text:
        raise SystemExit(f"ccx failed on {directory}/{name}.inp (status {result.returncode}):\n{log_text}")


def generate(out_dir, only=None):
    for name in all_fixtures():
        if only and name not in only:
            continue
        with tempfile.TemporaryDirectory(prefix=f"ccx_{name}_") as work:
            with open(os.path.join(work, f"{name}.inp"), "w") as f:
                f.write(deck(name))
            run_ccx(work, name)
            target = os.path.join(out_dir, name)
            os.makedirs(target, exist_ok=True)
            for ext in ("inp", "sti", "mas", "dof"):
                shutil.copyfile(os.path.join(work, f"{name}.{ext}"), os.path.join(target, f"{name}.{ext}"))
            freqs = frequencies_from_dat(os.path.join(work, f"{name}.dat"))
            with open(os.path.join(target, "frequencies.txt"), "w") as f:
                f.write("\n".join(freqs) + "\n")


def read_matrix(path):
    entries = []
    with open(path) as f:
        for number, line in enumerate(f, start=1):
            fields = line.split()
            if len(fields) != 3:
                raise SystemExit(f"{path}:{number}: expected `row col value`")
            entries.append((int(fields[0]), int(fields[1]), float(fields[2])))
    return entries


# Stored against fresh matrices, entry by entry (see compare).
FRESH_RTOL = 1e-12
FRESH_ATOL = 1e-13


def compare(stored_dir, fresh_dir):
    problems = []
    for name in all_fixtures():
        stored = os.path.join(stored_dir, name)
        fresh = os.path.join(fresh_dir, name)
        if not os.path.isdir(stored):
            problems.append(f"{name}: stored fixture {stored} is missing (run `scripts/calculix_fixtures.sh write`)")
            continue
        for ext in ("inp", "dof"):
            with open(os.path.join(stored, f"{name}.{ext}")) as a, open(os.path.join(fresh, f"{name}.{ext}")) as b:
                if a.read().split() != b.read().split():
                    problems.append(f"{name}/{name}.{ext}: differs from a fresh run")
        for ext in ("sti", "mas"):
            a = read_matrix(os.path.join(stored, f"{name}.{ext}"))
            b = read_matrix(os.path.join(fresh, f"{name}.{ext}"))
            if [e[:2] for e in a] != [e[:2] for e in b]:
                line = next((i for i, (x, y) in enumerate(zip(a, b), start=1) if x[:2] != y[:2]),
                            min(len(a), len(b)) + 1)
                problems.append(f"{name}/{name}.{ext}: indices differ from a fresh run from line {line} on "
                                f"({len(a)} entries stored, {len(b)} fresh)")
                continue
            # Entry by entry, on the scale of the entry and of its row and
            # column: |x - y| <= RTOL |y| + ATOL sqrt(y_ii y_jj). A fresh
            # single-threaded run of the same ccx build writes the same text
            # (measured difference 0); the allowance covers another build's
            # round-off in the last of the 14 digits.
            diagonal = {e[0]: abs(e[2]) for e in b if e[0] == e[1]}
            worst = (0.0, None, None)
            for x, y in zip(a, b):
                scale = (diagonal.get(y[0], 0.0) * diagonal.get(y[1], 0.0)) ** 0.5
                ratio = abs(x[2] - y[2]) / (FRESH_RTOL * abs(y[2]) + FRESH_ATOL * scale or 1e-300)
                worst = max(worst, (ratio, x, y), key=lambda w: w[0])
            if worst[0] > 1.0:
                _, x, y = worst
                problems.append(f"{name}/{name}.{ext}: entry ({x[0]}, {x[1]}) is {x[2]!r} stored, {y[2]!r} fresh "
                                f"({worst[0]:.2e} times the allowed {FRESH_RTOL:g} |fresh| + {FRESH_ATOL:g} sqrt(d_i d_j))")
        with open(os.path.join(stored, "frequencies.txt")) as a, open(os.path.join(fresh, "frequencies.txt")) as b:
            fa = [float(v) for v in a.read().split()]
            fb = [float(v) for v in b.read().split()]
        if len(fa) != len(fb):
            problems.append(f"{name}/frequencies.txt: {len(fa)} frequencies stored, {len(fb)} fresh")
        else:
            # Rigid-body frequencies are round-off: compare them on the scale of the largest.
            floor = 1e-6 * max(fa + fb, default=0.0)
            for i, (x, y) in enumerate(zip(fa, fb), start=1):
                if abs(x - y) > 1e-9 * max(abs(x), abs(y)) and max(abs(x), abs(y)) > floor:
                    problems.append(f"{name}/frequencies.txt: mode {i} is {x!r} Hz stored, {y!r} Hz fresh")
    return problems


def main(argv):
    if len(argv) >= 3 and argv[1] == "generate":
        generate(argv[2], argv[3:])
    elif len(argv) == 4 and argv[1] == "compare":
        problems = compare(argv[2], argv[3])
        if problems:
            print("CalculiX fixtures differ from a fresh ccx run:", file=sys.stderr)
            for p in problems:
                print(f"  {p}", file=sys.stderr)
            print("If the change is intended, run `scripts/calculix_fixtures.sh write` and review the diff.",
                  file=sys.stderr)
            return 1
        print(f"CalculiX fixtures agree with a fresh ccx run ({len(all_fixtures())} decks)")
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
