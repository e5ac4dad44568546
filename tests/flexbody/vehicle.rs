//! The vehicle model in time and frequency: the bundled example, reduced
//! against full, steady state against the harmonic response, closed forms
//! of one- and two-mass oscillators, modal damping, and bad input.

use super::support::{flexbody, max_difference, run_ok};
use flexbody::fem::{Dof, DofKind, Substructure};
use flexbody::linalg::memory::Budget;
use flexbody::linalg::progress::NoProgress;
use flexbody::mbs::{damped_modes, harmonic_response, FlexibleBody, System};
use flexbody::reduce::ReducedBody;
use flexbody::scenario::{parse_model_file, read_model_file, ModelFile};
use flexbody::simulate::{run_frf, run_simulation, simulation_body, Histories};
use std::path::PathBuf;

fn vehicle_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml")
}

fn vehicle_text() -> String {
    std::fs::read_to_string(vehicle_path()).unwrap()
}

/// The vehicle without its bump stop: a linear system. Its structural
/// damping is Rayleigh damping of the FE model instead of modal damping of
/// the reduced body, so that the reduced and the full body are damped alike
/// (D_red = T^T D T).
fn linear_vehicle() -> ModelFile {
    let text = vehicle_text();
    let start = text.find("# Bump stop").unwrap();
    let end = text.find("[simulation]").unwrap();
    let linear = format!("{}{}", &text[..start], &text[end..]);
    let linear = linear
        .replace("{ node = 11, dof = \"uz\" },\n", "")
        .replace("modal_damping = [0.02]\n", "")
        .replace(
            "[track]",
            "[damping]\nalpha = 1.0\nbeta = 2.0e-5\n\n[track]",
        );
    parse_model_file("linear_vehicle.toml".as_ref(), &linear).unwrap()
}

/// The FE substructure of `file`'s model and the body its simulation
/// reduces it to.
fn simulated_body(file: &ModelFile) -> (Substructure, ReducedBody) {
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = simulation_body(
        file,
        &sub,
        file.simulation.as_ref().unwrap(),
        Budget::MACHINE,
        &NoProgress,
    )
    .unwrap();
    (sub, body)
}

fn run(file: &ModelFile, full: bool) -> Histories {
    let (sub, body) = simulated_body(file);
    let flexible = if full {
        FlexibleBody::Full {
            dof_map: &sub.dof_map,
            matrices: &sub.matrices,
        }
    } else {
        FlexibleBody::Reduced(&body)
    };
    run_simulation(file, flexible).unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn the_vehicle_example_runs_and_its_bump_stop_works() {
    let file = read_model_file(&vehicle_path()).unwrap();
    let h = run(&file, false);
    let stop = h.column("bump_stop (N)").expect("bump stop history");
    assert!(
        stop.iter().any(|f| *f < -1e3),
        "the stop closes: {}",
        max_abs(stop)
    );
    assert!(
        stop.iter().filter(|f| **f == 0.0).count() > stop.len() / 2,
        "and is open most of the time"
    );
    assert!(h.column("element 10 end My (N m)").is_some());
    assert!(h.column("car_body.uz (m)").is_some());
    // Reduced and full agree on the stop's peak force (nonlinear run; the
    // step cutbacks at the stop differ, so compare extremes).
    let full = run(&file, true);
    let (a, b) = (
        max_abs(stop),
        max_abs(full.column("bump_stop (N)").unwrap()),
    );
    assert!((a - b).abs() < 2e-3 * b, "{a} vs {b}");
}

#[test]
fn section_force_histories_of_reduced_and_full_models_agree() {
    // Free-residual with one eigenmode; excitation at 19 Hz, far below the
    // second elastic mode (687 Hz); both integrated the same way.
    let file = linear_vehicle();
    let (red, full) = (run(&file, false), run(&file, true));
    assert!(
        red.times == full.times,
        "the same steps ({} and {})",
        red.times.len(),
        full.times.len()
    );
    for name in [
        "element 1 end Qz (N)",
        "element 6 end My (N m)",
        "element 10 end My (N m)",
        "element 14 start Qz (N)",
    ] {
        let (a, b) = (red.column(name).unwrap(), full.column(name).unwrap());
        let scale = max_abs(b);
        let err = max_difference(a, b) / scale;
        // measured 7.1e-5, 1.0e-5, 1.4e-6 and 2.2e-4 (the eigenmodes the
        // basis leaves out)
        assert!(err < 7e-4, "{name}: {err:e}");
    }
}

#[test]
fn steady_state_equals_the_harmonic_response() {
    let file = linear_vehicle();
    let spec = file.simulation.as_ref().unwrap();
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = simulation_body(&file, &sub, spec, Budget::MACHINE, &NoProgress).unwrap();
    let h = run(&file, false);
    let track = file.track.unwrap();
    let omega = 2.0 * std::f64::consts::PI * spec.excitation.speed / track.wavelength;
    let system = file.system(FlexibleBody::Reduced(&body));
    let r = harmonic_response(&system, omega).unwrap();
    // Node 7 (a secondary seat) and the front primary spring over the last period.
    let row = body.row_of(Dof::new(7, DofKind::Uz)).unwrap();
    let (re, im) = r.flexible_coords[0].clone();
    let w_re: f64 = row.iter().zip(&re).map(|(a, b)| a * b).sum();
    let w_im: f64 = row.iter().zip(&im).map(|(a, b)| a * b).sum();
    let w = h.column("node 7 uz (m)").unwrap();
    let f = h.column("primary_front (N)").unwrap();
    let period = 2.0 * std::f64::consts::PI / omega;
    let (f_re, f_im) = r.forces[0];
    for (k, t) in h
        .times
        .iter()
        .enumerate()
        .filter(|(_, t)| **t > spec.settings.duration - period)
    {
        let (c, s) = ((omega * t).cos(), (omega * t).sin());
        // measured up to 1.5e-4 (w) and 8.4e-5 (F): the time integration's
        // error and what is left of the start transient
        assert!(
            (w[k] - (w_re * c - w_im * s)).abs() < 5e-4 * w_re.hypot(w_im),
            "t = {t}"
        );
        assert!(
            (f[k] - (f_re * c - f_im * s)).abs() < 3e-4 * f_re.hypot(f_im),
            "t = {t}"
        );
    }
}

#[test]
fn frf_matches_single_harmonic_solutions() {
    let file = linear_vehicle();
    let (_, body) = simulated_body(&file);
    let t = run_frf(&file, FlexibleBody::Reduced(&body)).unwrap();
    assert_eq!(t.frequencies_hz.len(), 240);
    let k = 100;
    let omega = 2.0 * std::f64::consts::PI * t.frequencies_hz[k];
    let system = file.system(FlexibleBody::Reduced(&body));
    let r = harmonic_response(&system, omega).unwrap();
    let a = file.track.unwrap().amplitude;
    let (name, mag, phase) = &t.outputs[0];
    assert!(name.starts_with("primary_front"));
    assert!((mag[k] - r.forces[0].0.hypot(r.forces[0].1) / a).abs() < 1e-12 * mag[k]);
    assert!((phase[k] - r.forces[0].1.atan2(r.forces[0].0)).abs() < 1e-12);
    // The coupled system (eq. 21): car-body modes near 1 Hz, the frame's
    // heave near 19 Hz; a passive system has no negative damping.
    let modes = flexbody::simulate::coupled_modes(&file, FlexibleBody::Reduced(&body)).unwrap();
    assert!(modes.iter().all(|m| m.damping_ratio >= -1e-9), "{modes:?}");
    assert!(modes[..2].iter().all(|m| m.natural_hz < 2.0));
    // Independent estimates from the file's values: the car body (mass m_c)
    // heaves on each side's secondary spring k_s in series with the
    // primary k_p, f = sqrt(2 (k_s k_p / (k_s + k_p)) / m_c) / 2 pi, the
    // frame's mass (35 times smaller) neglected; the frame heaves as a
    // rigid beam of mass rho A L between both sets of springs, the car body
    // at rest (35 times heavier), f = sqrt(2 (k_p + k_s) / m_f) / 2 pi.
    let stiffness = |name: &str| {
        let c = file.connections.iter().find(|c| c.name == name).unwrap();
        c.law.linearized().0
    };
    let (k_p, k_s) = (stiffness("primary_front"), stiffness("secondary_front"));
    assert_eq!(
        (k_p, k_s),
        (stiffness("primary_rear"), stiffness("secondary_rear"))
    );
    let m_c = file.rigid_bodies[0].mass;
    let (b, h, t) = (0.24_f64, 0.20_f64, 0.012);
    let m_f = 6800.0 * (b * h - (b - 2.0 * t) * (h - 2.0 * t)) * 2.5;
    let two_pi = 2.0 * std::f64::consts::PI;
    let car_heave = (2.0 * k_s * k_p / (k_s + k_p) / m_c).sqrt() / two_pi;
    let frame_heave = (2.0 * (k_p + k_s) / m_f).sqrt() / two_pi;
    let near = |f: f64, tol: f64| modes.iter().any(|m| (m.natural_hz - f).abs() < tol * f);
    // Measured: 1.3040 Hz against 1.2995 (0.35 %: the frame's mass) and
    // 19.06 Hz against 19.32 (1.3 %: the frame's bending, the car body's
    // coupling).
    assert!(
        near(car_heave, 0.015),
        "car heave {car_heave} Hz: {modes:?}"
    );
    assert!(
        near(frame_heave, 0.04),
        "frame heave {frame_heave} Hz: {modes:?}"
    );
}

/// The vehicle's side beam made 10^4 times stiffer (its first free bending
/// mode 100x higher, near 25 kHz) on its primary spring-dampers to the
/// track, with the car body held at rest (`fixed`) or free in heave and
/// pitch: at and below 60 Hz the beam moves as a rigid body, a one-mass (or
/// two-mass) oscillator with a closed-form FRF. No Rayleigh or modal
/// damping, no bump stop.
fn stiff_beam_vehicle(car_body_fixed: bool) -> ModelFile {
    let text = vehicle_text();
    let start = text.find("# Bump stop").unwrap();
    let end = text.find("[simulation]").unwrap();
    let mut text = format!("{}{}", &text[..start], &text[end..])
        .replace("{ node = 11, dof = \"uz\" },\n", "")
        .replace("modal_damping = [0.02]\n", "")
        .replace("youngs_modulus = 2.1e11", "youngs_modulus = 2.1e15");
    if car_body_fixed {
        text = text.replace(
            "inertia = [0.0, 4000.0, 0.0, 0.0, 0.0, 0.0]\n",
            "fixed = true\n",
        );
        text = text.replace("dofs = [\"uz\", \"ry\"]\n", "");
    }
    assert!(!text.contains("bump-stop") && text.contains("2.1e15"));
    parse_model_file("stiff_beam_vehicle.toml".as_ref(), &text).unwrap()
}

/// `(a + i b)`, `(c + i d)` products and quotients for the closed forms.
fn c_mul(x: (f64, f64), y: (f64, f64)) -> (f64, f64) {
    (x.0 * y.0 - x.1 * y.1, x.0 * y.1 + x.1 * y.0)
}

fn c_div(x: (f64, f64), y: (f64, f64)) -> (f64, f64) {
    let d = y.0 * y.0 + y.1 * y.1;
    ((x.0 * y.0 + x.1 * y.1) / d, (x.1 * y.0 - x.0 * y.1) / d)
}

/// The parameters of examples/vehicle.toml: the rigid side beam's mass
/// `rho A L` (box 0.24 x 0.20 m, wall 0.012 m, 2.5 m of steel at 6800
/// kg/m^3), the car body's mass, and per spring the primary and secondary
/// stiffness (N/m) and damping (N s/m); two of each act in parallel.
const BEAM_MASS: f64 = 6800.0 * (0.24 * 0.20 - 0.216 * 0.176) * 2.5;
const CAR_MASS: f64 = 6000.0;
const PRIMARY: (f64, f64) = (1.0e6, 4.0e3);
const SECONDARY: (f64, f64) = (0.25e6, 1.0e4);

#[test]
fn frf_of_a_one_mass_oscillator_matches_its_closed_form() {
    // Base excitation through two primary spring-dampers (K1 + i W C1 in
    // total), two secondary ones to the car body at rest (K2 + i W C2): the
    // beam's heave w and the primary spring's tension F = (k1 + i W c1)(w - a),
    //   w / a = (K1 + i W C1) / (K1 + K2 - W^2 m + i W (C1 + C2)),
    //   F / a = -(k1 + i W c1) (K2 - W^2 m + i W C2)
    //           / (K1 + K2 - W^2 m + i W (C1 + C2))
    // (transmissibility of a base-excited one-mass oscillator, e.g. Rao,
    // Mechanical Vibrations, section 3.6). The elongation is the beam's node
    // against the other end, so tension is negative when the track pushes
    // the beam up statically.
    let file = stiff_beam_vehicle(true);
    let (sub, body) = simulated_body(&file);
    let full = FlexibleBody::Full {
        dof_map: &sub.dof_map,
        matrices: &sub.matrices,
    };
    let m = BEAM_MASS;
    let (k1, c1) = PRIMARY;
    let (k2, c2) = SECONDARY;
    let (big_k, big_c) = (2.0 * (k1 + k2), 2.0 * (c1 + c2));
    for (label, flexible) in [("reduced", FlexibleBody::Reduced(&body)), ("full", full)] {
        let t = run_frf(&file, flexible).unwrap();
        let (name, mag, phase) = &t.outputs[0];
        assert!(name.starts_with("primary_front"));
        let mut worst = 0.0_f64;
        for (k, f) in t.frequencies_hz.iter().enumerate() {
            let w = 2.0 * std::f64::consts::PI * f;
            let num = c_mul((-k1, -w * c1), (2.0 * k2 - w * w * m, w * 2.0 * c2));
            let want = c_div(num, (big_k - w * w * m, w * big_c));
            let got = (mag[k] * phase[k].cos(), mag[k] * phase[k].sin());
            let err = (got.0 - want.0).hypot(got.1 - want.1) / want.0.hypot(want.1);
            worst = worst.max(err);
        }
        // The beam's elastic modes: (60 Hz / 24.9 kHz)^2 = 5.8e-6 at the top
        // of the band; measured 3.9e-6 (reduced) and 5.0e-6 (full). A stiffer beam
        // trades this for round-off (E x 1e5: 1.7e-6, E x 1e6: 1.3e-5).
        assert!(worst < 2e-5, "{label}: {worst:e}");
    }
    // The one heave mode: sqrt((K1 + K2) / m), zeta = (C1 + C2) / (2 sqrt((K1
    // + K2) m)); measured 6.7e-7 and 3.7e-7 off (the beam's elastic modes).
    let modes = flexbody::simulate::coupled_modes(&file, FlexibleBody::Reduced(&body)).unwrap();
    let heave = modes
        .iter()
        .find(|m| m.natural_hz > 1.0)
        .expect("a heave mode");
    let (f_n, zeta) = (
        (big_k / m).sqrt() / (2.0 * std::f64::consts::PI),
        big_c / (2.0 * (big_k * m).sqrt()),
    );
    assert!(
        (heave.natural_hz - f_n).abs() < 5e-6 * f_n,
        "{heave:?} vs {f_n}"
    );
    assert!(
        (heave.damping_ratio - zeta).abs() < 5e-6 * zeta,
        "{heave:?} vs {zeta}"
    );
}

#[test]
fn frf_of_a_two_mass_oscillator_matches_its_closed_form() {
    // The car body free (heave and pitch; the symmetric track input excites
    // no pitch): beam heave w, car-body heave z,
    //   [K1 + K2 - W^2 m1 + i W (C1 + C2)   -(K2 + i W C2)        ] [w]   [(K1 + i W C1) a]
    //   [-(K2 + i W C2)                    K2 - W^2 m2 + i W C2 ] [z] = [0              ]
    // solved by Cramer's rule; the front primary spring's tension is
    // (k1 + i W c1)(w - a) and the front secondary one's (k2 + i W c2)(w - z)
    // (elongation: the beam's node against the other end).
    let file = stiff_beam_vehicle(false);
    let (_, body) = simulated_body(&file);
    let t = run_frf(&file, FlexibleBody::Reduced(&body)).unwrap();
    let (k1, c1) = PRIMARY;
    let (k2, c2) = SECONDARY;
    let (m1, m2) = (BEAM_MASS, CAR_MASS);
    let mut worst = [0.0_f64; 2];
    for (k, f) in t.frequencies_hz.iter().enumerate() {
        let w = 2.0 * std::f64::consts::PI * f;
        let p = (2.0 * k1, 2.0 * w * c1);
        let s = (2.0 * k2, 2.0 * w * c2);
        let a11 = (p.0 + s.0 - w * w * m1, p.1 + s.1);
        let a22 = (s.0 - w * w * m2, s.1);
        let det = {
            let d = c_mul(a11, a22);
            let o = c_mul(s, s);
            (d.0 - o.0, d.1 - o.1)
        };
        let wa = c_div(c_mul(p, a22), det);
        let za = c_div(c_mul(p, s), det);
        let primary = c_mul((k1, w * c1), (wa.0 - 1.0, wa.1));
        let secondary = c_mul((k2, w * c2), (wa.0 - za.0, wa.1 - za.1));
        for (j, want) in [(0, primary), (2, secondary)] {
            let (_, mag, phase) = &t.outputs[j];
            let got = (mag[k] * phase[k].cos(), mag[k] * phase[k].sin());
            let err = (got.0 - want.0).hypot(got.1 - want.1) / want.0.hypot(want.1);
            worst[j / 2] = worst[j / 2].max(err);
        }
    }
    // The beam's elastic modes, as above; measured 3.9e-6 and 5.9e-6.
    assert!(worst[0] < 2e-5 && worst[1] < 2e-5, "{worst:?}");
}

#[test]
fn modal_damping_gives_each_mode_its_ratio() {
    let file = read_model_file(&vehicle_path()).unwrap();
    let (_, body) = simulated_body(&file);
    // The free reduced body alone (eq. 21): rigid modes at 0, every elastic
    // mode with the file's 2 %.
    let system = System {
        flexible: vec![FlexibleBody::Reduced(&body)],
        ..Default::default()
    };
    let modes = damped_modes(&system).unwrap();
    let elastic: Vec<_> = modes.iter().filter(|m| m.natural_hz > 1.0).collect();
    assert_eq!(elastic.len(), body.r() - 2);
    for m in elastic {
        assert!((m.damping_ratio - 0.02).abs() < 1e-9, "{m:?}");
    }
}

fn fails(text: &str, needles: &[&str]) {
    let dir = std::env::temp_dir().join(format!("flexbody-vehicle-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("track.csv"),
        "s (m), z (m)\n0.0, 0.0\n10.0, 0.01\n20.0, x\n",
    )
    .unwrap();
    let model = dir.join(format!("m{}.toml", needles.len()));
    std::fs::write(&model, text).unwrap();
    let out = flexbody(&[
        "simulate",
        model.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for n in needles {
        assert!(err.contains(n), "expected '{n}' in: {err}");
    }
}

#[test]
fn bad_simulation_input_is_named() {
    let text = vehicle_text();
    fails(
        &text.replace("step = 2.5e-4", "step = 5.0"),
        &["vehicle", "longer than the duration"],
    );
    fails(
        &text.replace("alpha = -0.05", "alpha = -0.6"),
        &["outside [-1/3, 0]"],
    );
    fails(
        &text.replacen("to = \"car_body\"", "to = \"bogie\"", 1),
        &["'bogie'", "neither ground, track nor a rigid body"],
    );
    fails(
        &text.replacen("node = 15", "node = 150", 1),
        &["node 150", "does not exist"],
    );
    fails(
        &text.replace("ramp = 0.3 ", "profile = \"track.csv\"\nramp = 0.3 "),
        &["track.csv:4:", "expected two numbers"],
    );
}

#[test]
fn simulate_writes_histories_and_plots() {
    let dir = std::env::temp_dir().join(format!("flexbody-simulate-{}", std::process::id()));
    run_ok(&[
        "simulate",
        vehicle_path().to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    let csv = std::fs::read_to_string(dir.join("histories.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for column in [
        "time (s)",
        "car_body.uz (m)",
        "node 11 uz (m)",
        "bump_stop (N)",
        "element 10 end My (N m)",
    ] {
        assert!(header.contains(column), "{column} in {header}");
    }
    assert_eq!(csv.lines().count(), 6002, "header + 6001 states");
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    for svg in ["connections.svg", "histories.svg"] {
        assert!(std::fs::read_to_string(dir.join(svg))
            .unwrap()
            .contains("<svg"));
    }
}
