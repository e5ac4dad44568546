//! Element matrices against CalculiX 2.20's own (`*FREQUENCY,
//! SOLVER=MATRIXSTORAGE`, which writes K and M of the free DOFs to
//! `job.sti`, `job.mas`, `job.dof`).
//!
//! - `agrees_with_stored_calculix_products`: `K v` and `M v` of one
//!   distorted element per kind, as CalculiX 2.20 computed them, stored in
//!   `calculix_2_20.txt` (with the node coordinates, so the fixture does not
//!   depend on this file's generators). Always runs; each row must agree to
//!   [`PRODUCT_RTOL`] of the sum of its terms' magnitudes.
//! - `agrees_with_calculix_when_installed`: the full matrices of freshly
//!   generated distorted elements, entry by entry
//!   (`|a_ij - b_ij| <= RTOL |b_ij| + ATOL sqrt(b_ii b_jj)`), when `ccx`
//!   2.20 is on the `PATH`. Without it the test prints that it skipped, or
//!   fails when `FLEXBODY_REQUIRE_PEERS=1` (as in CI).
//! - `write_calculix_fixture` (ignored) regenerates the fixture with `ccx`.

use super::{distorted, solid, Random, E, NU, RHO};
use crate::element::mat_vec;
use crate::element::solid::SolidKind;
use faer::Mat;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Command;

/// Entry-wise agreement with CalculiX's matrices:
/// `|a_ij - b_ij| <= RTOL |b_ij| + ATOL sqrt(b_ii b_jj)`.
///
/// CalculiX writes 14 significant digits (`%.13e`, a rounding of up to
/// 5e-14 of the entry) of values with its own round-off. Measured over the
/// seventeen elements (nine kinds, two shapes but one for C3D8I), K and M:
/// `|a - b| / |b|` at most 7.3e-14 on the entries above the floor (`RTOL |b| > ATOL sqrt(b_ii
/// b_jj)`); `|a - b| / sqrt(b_ii b_jj)` at most 6.9e-15 on those below it
/// (small entries from cancellation, zeros in one program and round-off in
/// the other). The largest ratio to the allowance is 0.32.
const RTOL: f64 = 2e-13;
/// See [`RTOL`]: the absolute floor, relative to the row and column scale.
const ATOL: f64 = 2e-14;
/// Row agreement of the stored products: `|(A v)_i - p_i| <= PRODUCT_RTOL
/// sum_j |a_ij v_j|`. The fixture's products come from CalculiX's 14-digit
/// entries (5e-14 each); measured at most 1.8e-14.
const PRODUCT_RTOL: f64 = 1e-13;

/// Whether a missing peer program must fail the test instead of skipping it
/// (`FLEXBODY_REQUIRE_PEERS=1`, set by `.ci/run`).
fn peers_required() -> bool {
    std::env::var_os("FLEXBODY_REQUIRE_PEERS").is_some_and(|v| v == "1")
}

/// The vector the fixture multiplies K and M with: small integers, exact in
/// any format.
fn probe(n: usize) -> Vec<f64> {
    (0..n).map(|i| ((7 * i + 3) % 11) as f64 - 5.0).collect()
}

/// True if `ccx` on the PATH is version 2.20.
fn ccx_2_20() -> bool {
    match Command::new("ccx").arg("-v").output() {
        Ok(out) => String::from_utf8_lossy(&out.stdout).contains("Version 2.20"),
        Err(_) => false,
    }
}

/// A number as CalculiX reads it: it takes at most 20 characters of a
/// field, so up to 15 significant digits, fewer for a negative number with a
/// two-digit exponent.
fn ccx_number(v: f64) -> String {
    (0..=14)
        .rev()
        .map(|digits| format!("{v:.digits$e}"))
        .find(|s| s.len() <= 20)
        .unwrap()
}

/// Coordinates rounded to what CalculiX reads ([`ccx_number`]); both sides
/// of a comparison use the rounded values.
fn rounded(coords: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
    coords
        .into_iter()
        .map(|x| x.map(|v| ccx_number(v).parse().unwrap()))
        .collect()
}

/// Runs CalculiX on a one-element deck and returns its K and M in the
/// element's DOF order (`ux, uy, uz` per node). For C3D8I, CalculiX adds
/// three nodes for the incompatible modes (9-11 here); their DOFs are
/// condensed out of K (the Schur complement) and left out of M, as
/// flexbody builds the element (see the module docs of `solid`).
fn calculix_matrices(kind: SolidKind, coords: &[[f64; 3]], tag: &str) -> (Mat<f64>, Mat<f64>) {
    let dir: PathBuf = std::env::temp_dir().join(format!(
        "flexbody-solid-{}-{}-{tag}",
        std::process::id(),
        kind.name()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let mut deck = String::from("*NODE\n");
    for (i, x) in coords.iter().enumerate() {
        let [a, b, c] = x.map(ccx_number);
        writeln!(deck, "{}, {a}, {b}, {c}", i + 1).unwrap();
    }
    writeln!(deck, "*ELEMENT, TYPE={}, ELSET=EALL", kind.name()).unwrap();
    // Element data lines hold at most 16 entries; a trailing comma continues.
    let ids: Vec<String> = std::iter::once(1)
        .chain(1..=kind.node_count())
        .map(|i| i.to_string())
        .collect();
    for (c, chunk) in ids.chunks(15).enumerate() {
        let last = (c + 1) * 15 >= ids.len();
        writeln!(deck, "{}{}", chunk.join(", "), if last { "" } else { "," }).unwrap();
    }
    write!(
        deck,
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n{E:e}, {NU}\n*DENSITY\n{RHO:e}\n\
         *SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n\
         *STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n1\n*END STEP\n"
    )
    .unwrap();
    std::fs::write(dir.join("one.inp"), deck).unwrap();
    let out = Command::new("ccx")
        .args(["-i", "one"])
        .current_dir(&dir)
        .env("OMP_NUM_THREADS", "1")
        .output()
        .expect("ccx runs");
    let read = |ext: &str| {
        std::fs::read_to_string(dir.join(format!("one.{ext}"))).unwrap_or_else(|e| {
            panic!(
                "{kind:?}: no one.{ext} ({e}); ccx said:\n{}",
                String::from_utf8_lossy(&out.stdout)
            )
        })
    };
    // Equation e (1-based) is DOF "node.direction".
    let dof: Vec<usize> = read("dof")
        .lines()
        .map(|l| {
            let (node, dir) = l.trim().split_once('.').unwrap();
            3 * (node.parse::<usize>().unwrap() - 1) + dir.parse::<usize>().unwrap() - 1
        })
        .collect();
    let nd = 3 * kind.node_count();
    let all = nd + 3 * kind.incompatible_modes();
    assert_eq!(dof.len(), all, "{kind:?}: CalculiX has {} DOFs", dof.len());
    let matrix = |ext: &str| {
        let mut a = Mat::<f64>::zeros(all, all);
        for l in read(ext).lines() {
            let v: Vec<&str> = l.split_whitespace().collect();
            let (i, j): (usize, usize) = (v[0].parse().unwrap(), v[1].parse().unwrap());
            let x: f64 = v[2].parse().unwrap();
            let (r, c) = (dof[i - 1], dof[j - 1]);
            a[(r, c)] = x;
            a[(c, r)] = x;
        }
        a
    };
    let (k, m) = (matrix("sti"), matrix("mas"));
    std::fs::remove_dir_all(&dir).ok();
    if all == nd {
        return (k, m);
    }
    let (k, _) = crate::element::condense(&k, nd).expect("CalculiX's incompatible modes are stiff");
    (k, m.as_ref().submatrix(0, 0, nd, nd).to_owned())
}

/// The entry-wise comparison of `a` with the reference `b`.
struct Agreement {
    /// Largest `|a_ij - b_ij| / (RTOL |b_ij| + ATOL sqrt(b_ii b_jj))`: the
    /// test passes at most 1.
    worst: f64,
    /// Where `worst` is, with `a_ij` and `b_ij`.
    at: (usize, usize, f64, f64),
    /// Largest `|a_ij - b_ij| / |b_ij|` over entries above the absolute
    /// floor (`RTOL |b_ij| > ATOL sqrt(b_ii b_jj)`).
    relative: f64,
    /// Largest `|a_ij - b_ij| / sqrt(b_ii b_jj)` over entries below it.
    scaled: f64,
}

fn agreement(a: &Mat<f64>, b: &Mat<f64>) -> Agreement {
    let mut out = Agreement {
        worst: 0.0,
        at: (0, 0, 0.0, 0.0),
        relative: 0.0,
        scaled: 0.0,
    };
    for j in 0..b.ncols() {
        for i in 0..b.nrows() {
            let (x, y) = (a[(i, j)], b[(i, j)]);
            let scale = (b[(i, i)] * b[(j, j)]).abs().sqrt();
            let d = (x - y).abs();
            let ratio = d / (RTOL * y.abs() + ATOL * scale);
            if ratio.is_nan() || ratio > out.worst {
                out.worst = ratio;
                out.at = (i, j, x, y);
            }
            if RTOL * y.abs() > ATOL * scale {
                out.relative = out.relative.max(d / y.abs());
            } else {
                out.scaled = out.scaled.max(d / scale);
            }
        }
    }
    out
}

/// The elements each kind is compared on: one distorted by 15 % (curved
/// edges for the quadratic kinds) and one affine image of the reference
/// element, as `(seed, amplitude)` of [`compared_element`]. C3D8I only on
/// the affine one: on a distorted element CalculiX's incompatible modes are
/// not flexbody's (see the `solid` module docs).
fn shapes(kind: SolidKind) -> &'static [(u64, f64)] {
    match kind.incompatible_modes() {
        0 => &[(71, 0.15), (72, 0.0)],
        _ => &[(72, 0.0)],
    }
}

/// The element of each kind the stored fixture holds (`seed`, `amplitude`
/// of [`compared_element`]): distorted, C3D8I affine ([`shapes`]).
fn fixture_shape(kind: SolidKind) -> (u64, f64) {
    match kind.incompatible_modes() {
        0 => (61, 0.15),
        _ => (61, 0.0),
    }
}

/// Element `(seed, amplitude)` of [`distorted`], rounded as CalculiX reads
/// it; a C3D8R's distortion moves its nodes along z only: its hourglass
/// vectors are then CalculiX's, which keep only the z part of Flanagan and
/// Belytschko's (see the `solid` module docs).
fn compared_element(kind: SolidKind, seed: u64, amplitude: f64) -> Vec<[f64; 3]> {
    if kind != SolidKind::C3D8R {
        return rounded(distorted(kind, seed, amplitude));
    }
    let mut rng = Random::new(seed);
    rounded(
        distorted(kind, seed, 0.0)
            .into_iter()
            .map(|[x, y, z]| [x, y, z + amplitude * rng.vec3()[2]])
            .collect(),
    )
}

/// Largest entry of `b` and largest `|a_ij - b_ij|`.
fn largest_difference(a: &Mat<f64>, b: &Mat<f64>) -> (f64, f64) {
    let entries = (0..b.nrows()).flat_map(|i| (0..b.ncols()).map(move |j| (i, j)));
    entries.fold((0.0_f64, 0.0_f64), |(l, d), (i, j)| {
        (l.max(b[(i, j)].abs()), d.max((a[(i, j)] - b[(i, j)]).abs()))
    })
}

#[test]
fn distorted_c3d8i_and_c3d8r_are_not_calculixs() {
    // C3D8I: CalculiX leaves out the det J_0 / det J scaling of the
    // incompatible modes. C3D8R: CalculiX's hourglass vectors keep only
    // the z part of Flanagan and Belytschko's projection. Both: the same
    // element where the terms vanish (tested above), a different one on a
    // general distorted element; the difference is the formulation's, not
    // round-off, and the mass is the same.
    if !ccx_2_20() {
        assert!(
            !peers_required(),
            "FLEXBODY_REQUIRE_PEERS=1 but ccx 2.20 is not on the PATH"
        );
        return;
    }
    for (kind, low, high) in [
        (SolidKind::C3D8I, 1e-4, 0.05),
        (SolidKind::C3D8R, 1e-5, 0.01),
    ] {
        let x = rounded(distorted(kind, 71, 0.15));
        let ours = solid(kind).matrices(&x).unwrap();
        let (k, m) = calculix_matrices(kind, &x, "distorted");
        let (largest, diff) = largest_difference(&ours.stiffness, &k);
        eprintln!(
            "distorted {kind:?}: K differs from CalculiX's by {:.2e} of its largest entry",
            diff / largest
        );
        assert!(
            diff > low * largest && diff < high * largest,
            "{kind:?}: {:.2e}",
            diff / largest
        );
        assert!(
            agreement(&ours.mass, &m).worst <= 1.0,
            "{kind:?}: the mass is the same"
        );
    }
}

#[test]
fn agrees_with_calculix_when_installed() {
    if !ccx_2_20() {
        assert!(
            !peers_required(),
            "FLEXBODY_REQUIRE_PEERS=1 but ccx 2.20 is not on the PATH"
        );
        eprintln!("agrees_with_calculix_when_installed: SKIPPED, ccx 2.20 is not on the PATH");
        return;
    }
    let (mut relative, mut scaled) = ([0.0_f64; 2], [0.0_f64; 2]);
    for kind in SolidKind::ALL {
        for &(seed, amplitude) in shapes(kind) {
            let x = compared_element(kind, seed, amplitude);
            let ours = solid(kind).matrices(&x).unwrap();
            let (k, m) = calculix_matrices(kind, &x, &seed.to_string());
            for (slot, (name, a, b)) in [("K", &ours.stiffness, &k), ("M", &ours.mass, &m)]
                .into_iter()
                .enumerate()
            {
                let g = agreement(a, b);
                relative[slot] = relative[slot].max(g.relative);
                scaled[slot] = scaled[slot].max(g.scaled);
                let (i, j, x, y) = g.at;
                assert!(
                    g.worst <= 1.0,
                    "{kind:?} seed {seed}: {name}({i}, {j}) is {x:e}, CalculiX has {y:e} \
                     ({:.1} times the allowed {RTOL:e} |b| + {ATOL:e} sqrt(b_ii b_jj))",
                    g.worst
                );
            }
        }
    }
    let elements: usize = SolidKind::ALL.iter().map(|k| shapes(*k).len()).sum();
    eprintln!(
        "CalculiX 2.20 (live), full K and M of {elements} elements ({} kinds), entry by entry: \
         largest |a - b| / |b| K {:.1e}, M {:.1e} (allowed {RTOL:e}); below the floor, largest \
         |a - b| / sqrt(b_ii b_jj) K {:.1e}, M {:.1e} (allowed {ATOL:e})",
        SolidKind::ALL.len(),
        relative[0],
        relative[1],
        scaled[0],
        scaled[1]
    );
}

const FIXTURE: &str = include_str!("calculix_2_20.txt");

/// Per kind: node coordinates, `K v` and `M v` with `v = probe(3n)`.
struct Stored {
    kind: SolidKind,
    coords: Vec<[f64; 3]>,
    kv: Vec<f64>,
    mv: Vec<f64>,
}

fn parse_fixture(text: &str) -> Vec<Stored> {
    let mut out: Vec<Stored> = Vec::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize| f[i].parse::<f64>().unwrap();
        match f[0] {
            "kind" => out.push(Stored {
                kind: SolidKind::parse(f[1]).unwrap(),
                coords: Vec::new(),
                kv: Vec::new(),
                mv: Vec::new(),
            }),
            "x" => out
                .last_mut()
                .unwrap()
                .coords
                .push([num(1), num(2), num(3)]),
            "kv" => {
                let s = out.last_mut().unwrap();
                s.kv.push(num(1));
                s.mv.push(num(2));
            }
            other => panic!("fixture line starting with {other:?}"),
        }
    }
    out
}

#[test]
fn agrees_with_stored_calculix_products() {
    let stored = parse_fixture(FIXTURE);
    assert_eq!(stored.len(), SolidKind::ALL.len());
    let mut worst = 0.0_f64;
    for s in stored {
        let nd = 3 * s.kind.node_count();
        assert_eq!((s.coords.len(), s.kv.len()), (s.kind.node_count(), nd));
        let v = probe(nd);
        let em = solid(s.kind).matrices(&s.coords).unwrap();
        for (name, a, expected) in [("K", &em.stiffness, &s.kv), ("M", &em.mass, &s.mv)] {
            let got = mat_vec(a, &v);
            for (i, (g, e)) in got.iter().zip(expected).enumerate() {
                // Scale: the sum of |a_ij v_j| over the row.
                let scale: f64 = (0..nd).map(|j| (a[(i, j)] * v[j]).abs()).sum();
                let d = (g - e).abs() / scale;
                worst = worst.max(d);
                assert!(
                    d <= PRODUCT_RTOL,
                    "{:?}: row {i} of {name} v is {g:e}, CalculiX's {e:e} ({d:.1e} of the row's scale)",
                    s.kind
                );
            }
        }
    }
    eprintln!(
        "stored CalculiX 2.20 products: largest row difference {worst:.1e} of the row's scale"
    );
}

/// Regenerates `calculix_2_20.txt` with ccx 2.20:
/// `cargo test -p flexbody-fem write_calculix_fixture -- --ignored`.
#[test]
#[ignore = "needs ccx 2.20; rewrites the fixture"]
fn write_calculix_fixture() {
    assert!(ccx_2_20(), "ccx 2.20 must be on the PATH");
    let mut text = String::from(
        "# K v and M v of one distorted element per kind (C3D8I: an affine one;\n\
         # C3D8R: distorted along z only),\n\
         # computed from the matrices CalculiX 2.20 writes with *FREQUENCY,\n\
         # SOLVER=MATRIXSTORAGE (C3D8I: K condensed, M on the element's nodes)\n\
         # (E = 2.1e11 Pa, nu = 0.3, rho = 7850 kg/m^3), v_i = ((7 i + 3) mod 11) - 5\n\
         # for DOF i = 3 (node - 1) + direction (0-based). Written by the ignored\n\
         # test write_calculix_fixture in calculix.rs.\n",
    );
    for kind in SolidKind::ALL {
        let (seed, amplitude) = fixture_shape(kind);
        let x = compared_element(kind, seed, amplitude);
        let (k, m) = calculix_matrices(kind, &x, "fixture");
        let v = probe(3 * kind.node_count());
        writeln!(text, "kind {}", kind.name()).unwrap();
        for p in &x {
            writeln!(text, "x {:e} {:e} {:e}", p[0], p[1], p[2]).unwrap();
        }
        for (kv, mv) in mat_vec(&k, &v).iter().zip(mat_vec(&m, &v)) {
            writeln!(text, "kv {kv:e} {mv:e}").unwrap();
        }
    }
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/src/element/solid/tests/calculix_2_20.txt"
    );
    std::fs::write(path, text).unwrap();
}
