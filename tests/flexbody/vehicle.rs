//! The vehicle model in time and frequency (issue: MBS response in time):
//! the bundled example, reduced against full, steady state against the
//! harmonic response, modal damping, and bad input.

use flexbody::fem::{Dof, DofKind, Substructure};
use flexbody::io::{parse_model_file, read_model_file, ModelFile};
use flexbody::mbs::{damped_modes, harmonic_response, FlexibleBody, System};
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

fn run(file: &ModelFile, full: bool) -> Histories {
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = simulation_body(file, &sub, file.simulation.as_ref().unwrap()).unwrap();
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
        let err = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
            / scale;
        assert!(err < 1e-3, "{name}: {err:e}");
    }
}

#[test]
fn steady_state_equals_the_harmonic_response() {
    let file = linear_vehicle();
    let spec = file.simulation.as_ref().unwrap();
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = simulation_body(&file, &sub, spec).unwrap();
    let h = run(&file, false);
    let track = file.track.unwrap();
    let omega = 2.0 * std::f64::consts::PI * spec.excitation.speed / track.wavelength;
    let system = System {
        flexible: vec![FlexibleBody::Reduced(&body)],
        rigid: file.rigid_bodies.clone(),
        connections: file.connections.clone(),
        track: file.track,
    };
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
        assert!(
            (w[k] - (w_re * c - w_im * s)).abs() < 1e-3 * w_re.hypot(w_im),
            "t = {t}"
        );
        assert!(
            (f[k] - (f_re * c - f_im * s)).abs() < 1e-3 * f_re.hypot(f_im),
            "t = {t}"
        );
    }
}

#[test]
fn frf_matches_single_harmonic_solutions() {
    let file = linear_vehicle();
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = simulation_body(&file, &sub, file.simulation.as_ref().unwrap()).unwrap();
    let t = run_frf(&file, FlexibleBody::Reduced(&body)).unwrap();
    assert_eq!(t.frequencies_hz.len(), 240);
    let k = 100;
    let omega = 2.0 * std::f64::consts::PI * t.frequencies_hz[k];
    let system = System {
        flexible: vec![FlexibleBody::Reduced(&body)],
        rigid: file.rigid_bodies.clone(),
        connections: file.connections.clone(),
        track: file.track,
    };
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
    assert!(
        modes.iter().any(|m| (15.0..25.0).contains(&m.natural_hz)),
        "{modes:?}"
    );
}

#[test]
fn modal_damping_gives_each_mode_its_ratio() {
    let file = read_model_file(&vehicle_path()).unwrap();
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = simulation_body(&file, &sub, file.simulation.as_ref().unwrap()).unwrap();
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
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args([
            "simulate",
            model.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ])
        .output()
        .unwrap();
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
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args([
            "simulate",
            vehicle_path().to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
