//! The SID file's FFRF invariants against the full model: mass properties
//! and elastic modes of solids and beams.

use super::support::{hex_beam, reduce_with, welib_clamped_beam, write_beam_case, SKEW_TIMOSHENKO};
use flexbody::export::sid::Sid;
use flexbody::fem::{Model, Substructure};
use flexbody::input::{load, MatrixFiles};
use flexbody::output;
use flexbody::reduce::{Method, ReducedBody};

/// A free 3D beam (10 Euler-Bernoulli elements along x, offset from the
/// origin), with its analytical mass properties.
const BEAM_3D: &str = r#"
title = "free 3D beam"
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
"#;

fn beam_3d() -> (Substructure, Model) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("beam.toml");
    std::fs::write(&path, BEAM_3D).unwrap();
    let c = load(&path, &MatrixFiles::default()).unwrap();
    (c.sub, c.model.unwrap())
}

fn assert_close(what: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= 1e-11 * scale,
        "{what}: {got} against {want} (scale {scale})"
    );
}

/// Mass, centre of mass and inertia tensor (about the origin) of the SID
/// against the analytical values of the full model.
fn check_mass_properties(sid: &Sid, mass: f64, center: [f64; 3], inertia: [[f64; 3]; 3]) {
    assert_close("mass", sid.refmod.mass, mass, mass);
    let c = sid.center_of_mass();
    for i in 0..3 {
        assert_close("centre of mass", c[i], center[i], 1.0);
    }
    let scale = inertia[0][0]
        .abs()
        .max(inertia[1][1].abs())
        .max(inertia[2][2].abs());
    for (i, row) in inertia.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert_close(&format!("J({i}, {j})"), sid.j.m0[(i, j)], *want, scale);
        }
    }
}

/// Mean-axis elastic modes: no rigid-body part (`Ct = Cr = 0`), unit modal
/// mass, and the non-zero frequencies of the reduced body.
fn check_elastic_modes(sid: &Sid, body: &ReducedBody, rigid: usize) {
    let nq = sid.nq();
    assert_eq!(nq + rigid, body.r());
    let scale = sid.refmod.mass.sqrt() * 10.0;
    assert!(sid.ct.m0.norm_max() < 1e-9 * scale, "Ct = {:?}", sid.ct.m0);
    assert!(sid.cr.m0.norm_max() < 1e-9 * scale, "Cr = {:?}", sid.cr.m0);
    for i in 0..nq {
        for j in 0..nq {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((sid.me.m0[(i, j)] - want).abs() < 1e-9, "Me({i}, {j})");
        }
    }
    let ours = sid.frequencies_hz().unwrap();
    let full = body.frequencies_hz().unwrap();
    for (a, b) in ours.iter().zip(&full[rigid..]) {
        assert!((a - b).abs() < 1e-7 * b, "{a} Hz against {b} Hz");
    }
}

fn box_inertia(m: f64, a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    // Box [0,a] x [0,b] x [0,c] about the origin.
    let (xx, yy, zz) = (m * a * a / 3.0, m * b * b / 3.0, m * c * c / 3.0);
    let (xy, yz, zx) = (m * a * b / 4.0, m * b * c / 4.0, m * c * a / 4.0);
    [
        [yy + zz, -xy, -zx],
        [-xy, xx + zz, -yz],
        [-zx, -yz, xx + yy],
    ]
}

/// The SID of `body`, a reduction of the hex-element beam `sub` with mesh
/// `model`, checked against the beam's mass properties (steel, 0.6 x 0.1 x
/// 0.1 m from the origin) and its elastic modes.
fn hex_beam_sid(sub: &Substructure, model: &Model, body: &ReducedBody) -> Sid {
    let sid = output::sid(sub, Some(model), body).unwrap();
    let mass = 7850.0 * 0.6 * 0.1 * 0.1;
    check_mass_properties(
        &sid,
        mass,
        [0.3, 0.05, 0.05],
        box_inertia(mass, 0.6, 0.1, 0.1),
    );
    check_elastic_modes(&sid, body, 6);
    sid
}

#[test]
fn sid_of_a_solid_has_the_mass_properties_of_the_full_model() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 4, &[13]);
    let sid = hex_beam_sid(&sub, &model, &body);
    // First-order J: for a translation-free mode, int Phi dm = 0 (mdCM m1
    // equals Ct), and J(q) stays symmetric.
    for k in 0..sid.nq() {
        let j1 = &sid.j.m1[k];
        assert!((j1 - j1.transpose()).norm_max() < 1e-9 * j1.norm_max().max(1.0));
        for i in 0..3 {
            assert_eq!(sid.md_cm.m1[k][(i, 0)], sid.ct.m0[(k, i)]);
        }
    }
    // One interface node with 3 translations; 6 stress rows per node.
    assert_eq!(sid.nodes.len(), 1);
    assert_eq!(sid.nodes[0].origin.m0[(0, 0)], 0.6);
    assert_eq!(sid.ksigma.nrow, 6 * model.nodes().len());
}

#[test]
fn sid_of_a_craig_bampton_solid_removes_the_rigid_motion_of_its_constraint_modes() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::CraigBampton, 3, &[1, 27, 79, 13]);
    hex_beam_sid(&sub, &model, &body);
}

#[test]
fn sid_of_a_beam_has_the_mass_properties_of_the_full_model() {
    let (sub, model) = beam_3d();
    let body = reduce_with(&sub, Method::FreeResidual, 3, &[1, 11]);
    let sid = output::sid(&sub, Some(&model), &body).unwrap();
    let (rho, area, l, ip) = (7850.0, 0.01, 2.0, 3.0e-5);
    let mass = rho * area * l;
    let c = [1.5, 0.2, -0.1];
    // Slender rod along x about its centre, torsional inertia rho Ip L,
    // then the parallel-axis theorem to the origin.
    let jc = [rho * ip * l, mass * l * l / 12.0, mass * l * l / 12.0];
    let c2 = c.iter().map(|x| x * x).sum::<f64>();
    let inertia: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { jc[i] + mass * c2 } else { 0.0 }) - mass * c[i] * c[j])
    });
    check_mass_properties(&sid, mass, c, inertia);
    check_elastic_modes(&sid, &body, 6);
    assert_eq!(sid.nodes.len(), 2);
    assert_eq!(sid.ksigma.nrow, 12 * 10);
}

/// Every invariant of a free and of a clamped beam body against an
/// integration written apart from flexbody's, in numpy
/// (`scripts/beam_invariants.py`: Przemieniecki's shape functions from
/// their closed form, six Gauss points, the section's rotary inertia as
/// the mass matrix has it), over the same mesh and mode shapes: equal to
/// 1e-10 of each invariant's largest entry. The clamped beam's mass is the
/// mesh's whole mass (the clamped node's share included).
#[test]
fn beam_invariants_equal_an_independent_numpy_integration() {
    use super::support::{python_imports, run_script, skip_without_peer};
    if let Err(why) = python_imports("numpy") {
        skip_without_peer(
            "beam_invariants_equal_an_independent_numpy_integration",
            &format!("numpy (python3: {why})"),
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut cases = Vec::new();
    for (name, text, method, interface) in [
        (
            "skew_free",
            SKEW_TIMOSHENKO.to_string(),
            Method::FreeResidual,
            vec![1, 7],
        ),
        (
            "welib_clamped",
            welib_clamped_beam(),
            Method::CraigBampton,
            vec![11],
        ),
    ] {
        let toml = dir.path().join(format!("{name}.toml"));
        std::fs::write(&toml, text).unwrap();
        let c = load(&toml, &MatrixFiles::default()).unwrap();
        let model = c.model.unwrap();
        let body = reduce_with(&c.sub, method, 4, &interface);
        let json = dir.path().join(format!("{name}.json"));
        write_beam_case(&model, &c.sub, &body, &json);
        cases.push(json);
    }
    let out = run_script("beam_invariants.py", &cases);
    // The clamped node's share included: 157 kg, not the 147.13 kg of the
    // free DOFs' mass matrix.
    assert!(
        out.contains("welib_clamped.json: mass 157.000000 kg"),
        "{out}"
    );
}

/// The invariants of the lowest elastic mode of a bar clamped at x = 0
/// (1 m, 0.05 m wide along y, 0.08 m high along z, steel): the frequency
/// and the terms linear in the mode, `[f, Ct, Cr, J m1, Gr, Oe]`, with the
/// mode's sign such that its largest tip displacement is positive, and
/// `Oe m1` of the mode with itself.
fn lowest_mode_invariants(model: &Model) -> Vec<(&'static str, Vec<f64>)> {
    use flexbody::reduce::ffrf::FloatingFrame;
    let sub = Substructure::from_model(model).unwrap();
    let body = reduce_with(&sub, Method::Free, 2, &[]);
    let frame = FloatingFrame::new(&sub, Some(model), &body).unwrap();
    let (inv, phi) = (&frame.invariants, &frame.elastic.shapes);
    // The sign: the largest displacement at x = 1.
    let tip = (0..phi.nrows())
        .filter(|&i| {
            let d = sub.dof_map.dof(i);
            !d.kind.is_rotation() && sub.node_coordinates(d.node).unwrap()[0] == 1.0
        })
        .max_by(|&a, &b| phi[(a, 0)].abs().total_cmp(&phi[(b, 0)].abs()))
        .unwrap();
    let s = phi[(tip, 0)].signum();
    let row = |m: &faer::Mat<f64>, cols: std::ops::Range<usize>| -> Vec<f64> {
        cols.map(|c| s * m[(0, c)]).collect()
    };
    vec![
        ("frequency", vec![frame.elastic.frequencies_hz[0]]),
        ("Ct", row(&inv.ct, 0..3)),
        ("Cr", row(&inv.cr, 0..3)),
        ("J m1", inv.j1[0].iter().flatten().map(|v| s * v).collect()),
        (
            "Gr",
            (0..3)
                .flat_map(|a| (0..3).map(move |b| (a, b)))
                .map(|(a, b)| s * inv.gr[(a, b)])
                .collect(),
        ),
        ("Oe", row(&inv.oe, 0..6)),
        ("Oe m1", (0..6).map(|c| inv.oe1[0][(0, c)]).collect()),
    ]
}

/// Largest difference of each term, relative to the term's largest entry.
fn term_differences(a: &[(&'static str, Vec<f64>)], b: &[(&'static str, Vec<f64>)]) -> Vec<f64> {
    a.iter()
        .zip(b)
        .map(|((_, x), (_, y))| {
            let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            x.iter()
                .zip(y)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()))
                / scale
        })
        .collect()
}

/// A beam body's invariants against those of the same bar meshed in C3D20
/// solids, under refinement of the solid: the difference falls as the
/// solid mesh converges, to what beam theory leaves out (Poisson's
/// contraction held at the clamped face, the section's warping). The
/// table (printed with `--nocapture`):
///
/// | solid cells | frequency | Ct | Cr | J m1 | Gr | Oe | Oe m1 |
///
/// each the largest difference relative to the term's largest entry. The
/// beam: 40 Timoshenko elements with rotary inertia and shear area 5/6 A.
#[test]
fn beam_invariants_approach_those_of_a_solid_mesh_of_the_beam() {
    use flexbody::fem::element::SolidKind;
    use flexbody::fem::mesh::{BeamLine, BeamLineKind, SolidBlock};
    use flexbody::fem::{BeamProperties, BeamTheory, Dof, DofKind, Material, SectionShape};
    let (l, b, h) = (1.0, 0.05, 0.08);
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    let section = SectionShape::Rect {
        width: b,
        height: h,
    }
    .constants()
    .unwrap();
    let beam = BeamLine {
        cells: 40,
        start: [0.0, 0.0, 0.0],
        end: [l, 0.0, 0.0],
        kind: BeamLineKind::Spatial {
            orientation: [0.0, 1.0, 0.0],
        },
        properties: BeamProperties::new(steel.clone(), section, BeamTheory::Timoshenko),
    }
    .model(DofKind::ALL.iter().map(|&k| Dof::new(1, k)).collect())
    .unwrap();
    let reference = lowest_mode_invariants(&beam);
    eprintln!(
        "| solid cells | {} |",
        reference
            .iter()
            .map(|t| t.0)
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let mut table = Vec::new();
    for cells in [[5, 1, 1], [10, 1, 2], [20, 2, 3]] {
        let mesh = SolidBlock {
            kind: SolidKind::C3D20,
            cells,
            origin: [0.0, -b / 2.0, -h / 2.0],
            size: [l, b, h],
            corner_distortion: 0.0,
            edge_distortion: 0.0,
            seed: 1,
        }
        .mesh();
        let nodes = mesh.nodes();
        let clamped = nodes
            .iter()
            .filter(|n| n.coords[0] == 0.0)
            .flat_map(|n| DofKind::ALL[..3].iter().map(move |&k| Dof::new(n.id, k)))
            .collect();
        let solid = Model::of(nodes, mesh.elements(&steel))
            .fixed(clamped)
            .build()
            .unwrap();
        let d = term_differences(&lowest_mode_invariants(&solid), &reference);
        eprintln!(
            "| {:?} | {} |",
            cells,
            d.iter()
                .map(|v| format!("{v:.2e}"))
                .collect::<Vec<_>>()
                .join(" | ")
        );
        table.push(d);
    }
    // Measured: each difference about halves per refinement, the finest
    // 6.2e-3 (frequency), 1.5e-3 (Ct), 3.7e-4 (Cr, J m1, Gr, Oe), 6e-6
    // (Oe m1).
    for (k, (name, _)) in reference.iter().enumerate() {
        for pair in table.windows(2) {
            assert!(
                pair[1][k] < 0.7 * pair[0][k],
                "{name}: {:.2e} then {:.2e} on refining",
                pair[0][k],
                pair[1][k]
            );
        }
        let fine = table[table.len() - 1][k];
        assert!(fine < 0.01, "{name}: {fine:.2e} at the finest solid mesh");
    }
}

/// flexbody's SID of the clamped beam that welib's `Beam2SID` wrote a SID
/// for (`tests/fixtures/sid/welib_clamped_beam.*`: 10 Euler-Bernoulli
/// elements, clamped at node 1, the 4 lowest bending modes) against
/// welib's file, mode by mode. welib scales each mode to a unit tip
/// displacement, flexbody to unit modal mass: flexbody's terms are scaled
/// by `c_k` (the tip ratio) per mode in them. welib prints six decimals.
///
/// Where welib is right, they agree to its printed digits: the frequencies,
/// the mass, `mdCM` (both orders), `Ct`, `Cr` (m0), `Me`, `Ke` and
/// `J` (m0) except its xx entry. Where it is not:
/// - `J` xx: welib puts `rho A` on the torsion DOF (157 kg m^2 for this
///   beam); the polar inertia is `rho Ip L` = 0.471 kg m^2;
/// - `Oe` m1: welib adds geometric stiffening; flexbody's is the mass
///   integral of the table in `docs/sid.md` alone;
/// - the other products of two fields (`J` m1, `Cr` m1, `Gr`, `Ge`, `Oe`
///   m0) differ by 0.13 % to 1.7 % of each term; flexbody's equal an
///   integration of the beam's own shape functions
///   ([`beam_invariants_equal_an_independent_numpy_integration`]), which
///   welib's do not.
#[test]
fn welib_sid_agrees_where_welib_is_right() {
    use flexbody::export::sid::{read_sid_dialect, Dialect, Taylor};
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/sid");
    let (welib, dialect) = read_sid_dialect(&fixtures.join("welib_clamped_beam.sid")).unwrap();
    assert_eq!(dialect, Dialect::Welib);
    let c = load(
        &fixtures.join("welib_clamped_beam.toml"),
        &MatrixFiles::default(),
    )
    .unwrap();
    let model = c.model.unwrap();
    let body = reduce_with(&c.sub, Method::Free, 4, &[11]);
    let ours = output::sid(&c.sub, Some(&model), &body).unwrap();
    // The scale of each mode: welib's tip displacement over ours.
    let tip = |s: &Sid| s.nodes.iter().find(|n| n.id == 11).unwrap().phi.m0.clone();
    let (t_ours, t_welib) = (tip(&ours), tip(&welib));
    let scale: Vec<f64> = (0..4)
        .map(|k| {
            let d = (0..3)
                .max_by(|&a, &b| t_ours[(a, k)].abs().total_cmp(&t_ours[(b, k)].abs()))
                .unwrap();
            t_welib[(d, k)] / t_ours[(d, k)]
        })
        .collect();
    // flexbody's entry (i, j) of order 0 (k = None) or of m1 for q_k,
    // scaled as welib's modes: by c per mode index the entry carries (in
    // the rows of Ct, Cr, Me, Ke, Oe; the columns of Me, Ke; the column
    // blocks of Gr and Ge; and k).
    let scaled = |name: &str, t: &Taylor, i: usize, j: usize, k: Option<usize>| {
        let m = k.map_or(&t.m0, |k| &t.m1[k]);
        let mut v = m[(i, j)];
        if ["Ct", "Cr", "Me", "Ke", "Oe", "Ge"].contains(&name) {
            v *= scale[i];
        }
        if ["Me", "Ke"].contains(&name) {
            v *= scale[j];
        }
        if ["Gr", "Ge"].contains(&name) {
            v *= scale[j / 3];
        }
        k.map_or(v, |k| v * scale[k])
    };
    let pairs = |s: &Sid| -> Vec<(&'static str, Taylor)> {
        [
            ("mdCM", &s.md_cm),
            ("J", &s.j),
            ("Ct", &s.ct),
            ("Cr", &s.cr),
            ("Me", &s.me),
            ("Gr", &s.gr),
            ("Ge", &s.ge),
            ("Oe", &s.oe),
            ("Ke", &s.ke),
        ]
        .into_iter()
        .map(|(n, t)| (n, t.clone()))
        .collect()
    };
    // The largest difference of each term and order, relative to the
    // term's largest entry (welib's), leaving out J xx.
    let mut worst = std::collections::BTreeMap::new();
    for ((name, a), (_, b)) in pairs(&ours).into_iter().zip(pairs(&welib)) {
        let orders: Vec<Option<usize>> = std::iter::once(None)
            .chain((0..b.m1.len().min(a.m1.len())).map(Some))
            .collect();
        for k in orders {
            let m = k.map_or(&b.m0, |k| &b.m1[k]);
            let mut largest = 0.0_f64;
            let mut diff = 0.0_f64;
            for i in 0..m.nrows() {
                for j in 0..m.ncols() {
                    if name == "J" && k.is_none() && (i, j) == (0, 0) {
                        continue;
                    }
                    largest = largest.max(m[(i, j)].abs());
                    diff = diff.max((scaled(name, &a, i, j, k) - m[(i, j)]).abs());
                }
            }
            let key = format!("{name} {}", if k.is_some() { "m1" } else { "m0" });
            let e = worst.entry(key).or_insert(0.0_f64);
            *e = e.max(diff / largest.max(1e-300));
        }
    }
    eprintln!("welib against flexbody, relative: {worst:?}");
    for term in [
        "mdCM m0", "mdCM m1", "Ct m0", "Cr m0", "Me m0", "Ke m0", "J m0",
    ] {
        assert!(worst[term] < 1e-7, "{term}: {:e}", worst[term]);
    }
    for term in ["J m1", "Cr m1", "Gr m0", "Ge m0", "Oe m0"] {
        assert!(
            worst[term] > 1e-4 && worst[term] < 0.02,
            "{term}: {:e}",
            worst[term]
        );
    }
    assert!(
        worst["Oe m1"] > 0.5,
        "welib's Oe m1 holds geometric stiffening"
    );
    assert!((welib.refmod.mass - ours.refmod.mass).abs() < 1e-12 * welib.refmod.mass);
    assert_eq!(welib.j.m0[(0, 0)], 157.0);
    let polar = 7850.0 * 3.0e-5 * 2.0;
    assert!((ours.j.m0[(0, 0)] - polar).abs() < 1e-12 * polar);
    let (fa, fb) = (
        ours.frequencies_hz().unwrap(),
        welib.frequencies_hz().unwrap(),
    );
    for (a, b) in fa.iter().zip(&fb) {
        assert!((a - b).abs() < 1e-6 * b, "{a} Hz against welib's {b} Hz");
    }
}
