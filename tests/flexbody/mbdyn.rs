//! MBDyn's modal FEM file (`--format mbdyn`) read back by a reader written
//! here from MBDyn's input manual ("FEM File Format" of the modal element),
//! not from the writer: the record groups against the SID of the same
//! reduction, the lumped masses against the body's mass.

use super::support::{fails_with, hex_beam, hex_beam_deck, reduce_args, reduce_with, run_ok};
use flexbody::export::{read_sid, write_mbdyn, Sid};
use flexbody::input::{load, MatrixFiles};
use flexbody::output;
use flexbody::reduce::Method;
use std::path::{Path, PathBuf};

/// What MBDyn takes from a modal FEM file, by record group.
#[derive(Debug, Default)]
struct FemFile {
    /// Group 1: `REV NNODES NNORMAL NATTACHED NCONSTRAINT NREJECTED`.
    nodes: usize,
    modes: usize,
    /// Group 2.
    labels: Vec<u64>,
    /// Groups 3 and 4 (zero if absent).
    initial: [Vec<f64>; 2],
    /// Groups 5, 6, 7: X, Y, Z per node.
    coordinates: Vec<[f64; 3]>,
    /// Group 8: per mode, per node `X Y Z RX RY RZ`.
    shapes: Vec<Vec<[f64; 6]>>,
    /// Groups 9, 10, 13 (nq x nq, row by row).
    mass: Vec<f64>,
    stiffness: Vec<f64>,
    damping: Option<Vec<f64>>,
    /// Group 11: per node `M M M JX JY JZ`.
    lumped: Option<Vec<[f64; 6]>>,
    /// Group 12: mass, centre of mass, inertia about the centre of mass.
    inertia: Option<(f64, [f64; 3], [[f64; 3]; 3])>,
}

/// The numbers of `lines`, skipping comment lines (`**`).
fn numbers(lines: &[&str]) -> Vec<f64> {
    lines
        .iter()
        .filter(|l| !l.trim_start().starts_with("**"))
        .flat_map(|l| l.split_whitespace())
        .map(|t| t.parse().unwrap_or_else(|_| panic!("not a number: {t}")))
        .collect()
}

/// Reads a modal FEM file as the manual lays it out: a group starts at a
/// line `** RECORD GROUP n, ...` and runs to the next one (or to
/// `** END OF FILE`); group 1's first line after the title is a comment;
/// group 8 has a comment line before each mode. Every count is checked.
fn read_fem(path: &Path) -> FemFile {
    let text = std::fs::read_to_string(path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut groups: Vec<(usize, Vec<&str>)> = Vec::new();
    for l in &lines {
        if l.starts_with("** END OF FILE") {
            break;
        }
        if let Some(rest) = l.strip_prefix("** RECORD GROUP ") {
            let n = rest.split(',').next().unwrap().trim().parse().unwrap();
            assert!(groups.iter().all(|(g, _)| *g != n), "group {n} twice");
            groups.push((n, Vec::new()));
        } else if let Some((_, body)) = groups.last_mut() {
            body.push(l);
        }
    }
    assert_eq!(groups.first().map(|g| g.0), Some(1), "group 1 comes first");
    let mut f = FemFile::default();
    for (g, body) in &groups {
        let g = *g;
        if g == 1 {
            assert!(body[0].starts_with("**"), "group 1: a comment line first");
            let t: Vec<&str> = body[1].split_whitespace().collect();
            assert_eq!(t[0], "REV0");
            let n: Vec<usize> = t[1..].iter().map(|x| x.parse().unwrap()).collect();
            f.nodes = n[0];
            f.modes = n[1] + n[2] + n[3] - n[4];
            continue;
        }
        let (nn, nq) = (f.nodes, f.modes);
        match g {
            2 => {
                f.labels = numbers(body).iter().map(|&x| x as u64).collect();
                assert_eq!(f.labels.len(), nn);
            }
            3 | 4 => {
                f.initial[g - 3] = numbers(body);
                assert_eq!(f.initial[g - 3].len(), nq);
            }
            5..=7 => {
                let v = numbers(body);
                assert_eq!(v.len(), nn);
                f.coordinates.resize(nn, [0.0; 3]);
                for (p, x) in v.into_iter().enumerate() {
                    f.coordinates[p][g - 5] = x;
                }
            }
            8 => {
                // Per mode: a comment line, then 6 numbers per node.
                let mut modes: Vec<Vec<f64>> = Vec::new();
                for l in body {
                    if l.starts_with("**") {
                        modes.push(Vec::new());
                    } else if let Some(m) = modes.last_mut() {
                        m.extend(numbers(&[l]));
                    } else {
                        panic!("group 8: numbers before a mode's comment line");
                    }
                }
                // The group's closing comment line opens no mode.
                while modes.last().is_some_and(|m| m.is_empty()) {
                    modes.pop();
                }
                assert_eq!(modes.len(), nq);
                f.shapes = modes
                    .into_iter()
                    .map(|m| {
                        assert_eq!(m.len(), 6 * nn);
                        m.chunks(6).map(|c| c.try_into().unwrap()).collect()
                    })
                    .collect();
            }
            9 | 10 | 13 => {
                let v = numbers(body);
                assert_eq!(v.len(), nq * nq, "group {g}");
                match g {
                    9 => f.mass = v,
                    10 => f.stiffness = v,
                    _ => f.damping = Some(v),
                }
            }
            11 => {
                let v = numbers(body);
                assert_eq!(v.len(), 6 * nn);
                f.lumped = Some(v.chunks(6).map(|c| c.try_into().unwrap()).collect());
            }
            12 => {
                let v = numbers(body);
                assert_eq!(v.len(), 13);
                let j = std::array::from_fn(|i| std::array::from_fn(|k| v[4 + 3 * i + k]));
                f.inertia = Some((v[0], [v[1], v[2], v[3]], j));
            }
            _ => panic!("record group {g} is not MBDyn's"),
        }
    }
    f
}

/// Reduces `model` with `args` twice through the CLI, as a SID and as an
/// MBDyn file, and reads both back.
fn reduce_both(model: &Path, method: &str, modes: &str, args: &[&str]) -> (Sid, FemFile) {
    let dir = tempfile::tempdir().unwrap();
    let (sid, fem) = (dir.path().join("body.sid"), dir.path().join("body.fem"));
    for (out, format) in [(&sid, "sid"), (&fem, "mbdyn")] {
        let mut extra = args.to_vec();
        extra.extend(["--format", format]);
        run_ok(&reduce_args(model, method, modes, out, &extra));
    }
    (read_sid(&sid).unwrap(), read_fem(&fem))
}

fn close(what: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= 1e-12 * scale,
        "{what}: {got} against {want}"
    );
}

/// The record groups against the SID of the same reduction: the counts,
/// the modal matrices, the interface nodes' mode shapes and coordinates,
/// the rigid inertia (moved from the frame origin to the centre of mass)
/// and the lumped masses' sum, which is the whole body's mass.
fn check_against_sid(sid: &Sid, fem: &FemFile) {
    let nq = sid.nq();
    assert_eq!(fem.modes, nq);
    assert_eq!(fem.labels.len(), fem.nodes);
    for (name, got, want) in [
        ("Me", &fem.mass, &sid.me.m0),
        ("Ke", &fem.stiffness, &sid.ke.m0),
    ] {
        let scale = want.norm_max();
        for i in 0..nq {
            for j in 0..nq {
                close(name, got[i * nq + j], want[(i, j)], scale);
            }
        }
    }
    let de = &sid.de.m0;
    match &fem.damping {
        Some(d) => {
            (0..nq * nq).for_each(|i| close("De", d[i], de[(i / nq, i % nq)], de.norm_max()))
        }
        None => assert_eq!(de.norm_max(), 0.0, "the SID has damping, the file none"),
    }
    assert!(fem.initial.iter().all(|v| v.iter().all(|&x| x == 0.0)));
    // Every interface node is listed with its coordinates and its rows.
    for node in &sid.nodes {
        let p = fem.labels.iter().position(|&l| l == node.id).unwrap();
        for d in 0..3 {
            assert_eq!(fem.coordinates[p][d], node.origin.m0[(d, 0)]);
        }
        for k in 0..nq {
            let s = fem.shapes[k][p];
            for d in 0..3 {
                let scale = node.phi.m0.norm_max().max(node.psi.m0.norm_max());
                close("phi", s[d], node.phi.m0[(d, k)], scale);
                close("psi", s[3 + d], node.psi.m0[(d, k)], scale);
            }
        }
    }
    // Group 12: J about the centre of mass, J_o = J_c + m (|c|^2 I - c c^T).
    let (m, c, jc) = fem.inertia.unwrap();
    close("mass", m, sid.refmod.mass, m);
    let cm = sid.center_of_mass();
    let c2: f64 = c.iter().map(|x| x * x).sum();
    let scale = sid.j.m0.norm_max();
    for i in 0..3 {
        close("centre of mass", c[i], cm[i], 1.0);
        for j in 0..3 {
            let delta = if i == j { c2 } else { 0.0 };
            let jo = jc[i][j] + m * (delta - c[i] * c[j]);
            close("J", jo, sid.j.m0[(i, j)], scale);
            close("J symmetric", jc[i][j], jc[j][i], scale);
        }
    }
    // Group 11: non-negative, one mass per node in all three directions,
    // summing to the body's mass (every node of the mesh is listed).
    let lumped = fem.lumped.as_ref().unwrap();
    assert!(lumped.iter().flatten().all(|&v| v >= 0.0));
    assert!(lumped.iter().all(|l| l[0] == l[1] && l[1] == l[2]));
    let total: f64 = lumped.iter().map(|l| l[0]).sum();
    close("lumped mass", total, sid.refmod.mass, sid.refmod.mass);
}

/// The hex-element beam (free, free-residual, one interface node): every
/// mesh node is listed, solids have no rotations.
#[test]
fn a_solid_body_reads_back_as_its_sid() {
    let deck = hex_beam_deck();
    let (sid, fem) = reduce_both(&deck, "free-residual", "4", &["--interface", "13"]);
    check_against_sid(&sid, &fem);
    // Every node of the mesh, ascending, at its coordinates.
    let (_, model) = hex_beam();
    let ids: Vec<u64> = model.nodes().iter().map(|n| n.id).collect();
    assert_eq!(fem.labels, ids);
    for (p, n) in model.nodes().iter().enumerate() {
        assert_eq!(fem.coordinates[p], n.coords);
    }
    assert!(fem.shapes.iter().flatten().all(|s| s[3..] == [0.0; 3]));
    let lumped = fem.lumped.unwrap();
    assert!(lumped.iter().all(|l| l[3..] == [0.0; 3]));
    // Steel, 0.6 x 0.1 x 0.1 m.
    let mass = 7850.0 * 0.6 * 0.1 * 0.1;
    close("mass", fem.inertia.unwrap().0, mass, mass);
}

/// A 3D beam clamped at node 1, with Rayleigh damping, reduced by
/// Craig-Bampton at node 11: the clamped node keeps its mass in group 11,
/// the beam nodes their rotations and torsional inertia, group 13 the
/// damping.
const CLAMPED_BEAM: &str = r#"
title = "clamped 3D beam"
[[material]]
name = "steel"
youngs_modulus = 2.1e11
density = 7850.0
[[section]]
name = "s"
shape = "general"
area = 0.01
iy = 2.0e-5
iz = 1.0e-5
torsion = 3.0e-5
[[beam_line]]
element = "beam"
rotary_inertia = false
from = [0.5, 0.2, -0.1]
to = [2.5, 0.2, -0.1]
elements = 10
first_node = 1
material = "steel"
section = "s"
orientation = [0.0, 0.0, 1.0]
[[boundary]]
node = 1
dofs = ["ux", "uy", "uz", "rx", "ry", "rz"]
[damping]
alpha = 0.5
beta = 1.0e-5
"#;

#[test]
fn a_clamped_beam_body_keeps_the_clamped_mass_and_its_damping() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("beam.toml");
    std::fs::write(&model, CLAMPED_BEAM).unwrap();
    let (sid, fem) = reduce_both(&model, "craig-bampton", "3", &["--interface", "11"]);
    check_against_sid(&sid, &fem);
    assert_eq!(fem.labels, (1..=11).collect::<Vec<u64>>());
    // Six constraint modes and three eigenmodes, none rigid (the frame is
    // held by the clamp).
    assert_eq!(fem.modes, 9);
    assert!(fem.damping.is_some());
    let lumped = fem.lumped.unwrap();
    // 157 kg of beam; the clamped node carries half an element.
    let mass = 7850.0 * 0.01 * 2.0;
    close("lumped mass", lumped.iter().map(|l| l[0]).sum(), mass, mass);
    close("clamped node", lumped[0][0], mass / 20.0, mass);
    // Torsion lumps rho Ip L over the nodes.
    let torsion: f64 = lumped.iter().map(|l| l[3]).sum();
    let ip = 7850.0 * 3.0e-5 * 2.0;
    close("torsional inertia", torsion, ip, ip);
    // The clamped node does not move; the free end twists.
    assert!(fem.shapes.iter().all(|m| m[0] == [0.0; 6]));
    assert!(fem.shapes.iter().any(|m| m[10][3] != 0.0));
}

/// Matrices alone have no node coordinates: refused before the reduction,
/// exit code 2, nothing written.
#[test]
fn matrices_without_coordinates_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_string_lossy().into_owned()
    };
    let header = "%%MatrixMarket matrix coordinate real symmetric\n";
    let k = write(
        "K.mtx",
        &format!("{header}3 3 5\n1 1 2e4\n2 1 -1e4\n2 2 2e4\n3 2 -1e4\n3 3 1e4\n"),
    );
    let m = write("M.mtx", &format!("{header}3 3 3\n1 1 1\n2 2 1\n3 3 1\n"));
    let dofs = write("dofs.txt", "1 uz\n2 uz\n3 uz\n");
    let out = dir.path().join("body.fem");
    let mut args = reduce_args(&k, "craig-bampton", "1", &out, &["--interface", "3"]);
    args.extend(
        [
            "--mass",
            m.as_str(),
            "--dofs",
            dofs.as_str(),
            "--format",
            "mbdyn",
        ]
        .map(String::from),
    );
    fails_with(&args, &["--format mbdyn needs node coordinates", "K.mtx"]);
    assert!(!out.exists());
}

/// Two blocks joined by a tie, clamped at one end: the tied nodes' DOFs
/// are eliminated, and in the file they move with the tie's constraint,
/// so every node that is not clamped moves in some mode.
#[test]
fn tied_nodes_move_with_their_constraint() {
    let deck = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix/tie_blocks/tie_blocks.inp");
    let model = load(&deck, &MatrixFiles::default()).unwrap().model.unwrap();
    assert!(model.has_constraints(), "the tie eliminates DOFs");
    let (sid, fem) = reduce_both(&deck, "craig-bampton", "3", &["--interface", "7"]);
    check_against_sid(&sid, &fem);
    let clamped = [1, 15, 29, 71, 85, 99, 141, 155, 169];
    for (p, label) in fem.labels.iter().enumerate() {
        let moves = fem.shapes.iter().any(|m| m[p][..3] != [0.0; 3]);
        assert_eq!(moves, !clamped.contains(label), "node {label}");
    }
}

/// A substructure with coordinates but no mesh (the library's case; the
/// CLI's matrices have no coordinates): the interface nodes alone, no
/// group 11, and the file says why.
#[test]
fn without_a_mesh_the_file_has_the_interface_nodes_and_no_lumped_masses() {
    let (sub, _) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 4, &[7, 13]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.fem");
    write_mbdyn(&output::mbdyn(&sub, None, &body).unwrap(), &path).unwrap();
    let fem = read_fem(&path);
    assert_eq!(fem.labels, [7, 13]);
    assert!(fem.lumped.is_none());
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("** no lumped masses (record group 11)"));
    let sid = output::sid(&sub, None, &body).unwrap();
    assert_eq!(fem.modes, sid.nq());
    let (m, c, _) = fem.inertia.unwrap();
    close("mass", m, sid.refmod.mass, m);
    close("centre of mass", c[0], sid.center_of_mass()[0], 1.0);
}
