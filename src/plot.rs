//! SVG plots: of a study case, like the report's figures 6-10
//! (displacement w(x), bending moment M(x) and shear force Q(x), reduced
//! over reference; their real parts, in phase with the excitation), of a
//! study's convergence, of histories in time and of transfer functions
//! (magnitude on a logarithmic axis, phase below it).
//!
//! Each plot is a [`Plot`]: a [`figure::Figure`] and the file it goes to;
//! the `plot_*` functions write them, the `*_plots` functions give them
//! (for the HTML report). Every axis carries one quantity with its unit.

pub mod axis;
pub mod figure;
pub mod style;

use crate::simulate::{Histories, HistoryKind, Transfer};
use crate::study::{fmt_omega, BeamResponse, Field, StudyResult};
use axis::Scale;
use figure::{Axis, Curve, Figure, Panel};
use std::path::{Path, PathBuf};
use style::Style;

/// A figure and the name of its file.
#[derive(Clone, Debug)]
pub struct Plot {
    pub file: String,
    pub figure: Figure,
}

/// Writes each of `plots` into `dir`, each through a temporary file
/// renamed into place (only over a regular file), so that no half-written
/// plot is left behind. Points that are not finite are gaps in their
/// curve (a phase where the magnitude is zero), never numbers in the SVG.
/// Returns the files written.
pub fn write_plots(dir: &Path, plots: &[Plot]) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    for plot in plots {
        let path = dir.join(&plot.file);
        crate::export::write_atomically(&path, |out| {
            out.write_all(plot.figure.to_svg().as_bytes())
        })
        .map_err(|e| e.to_string())?;
        written.push(path);
    }
    Ok(written)
}

/// The plots of a study in `dir` (see [`study_plots`]).
pub fn plot_study(dir: &Path, result: &StudyResult) -> Result<Vec<PathBuf>, String> {
    write_plots(dir, &study_plots(result)?)
}

/// The name of the first plot of a study at excitation frequencies
/// `omegas` (rad/s), which its output folder must take.
pub fn first_study_plot(omegas: &[f64]) -> String {
    omegas.first().map_or_else(
        || "convergence.svg".to_string(),
        |o| format!("convergence_omega{}.svg", fmt_omega(*o)),
    )
}

/// The plots of a study: per excitation frequency a convergence plot
/// (`convergence_omega<Omega>.svg`), and per case with curves the reduced
/// response over the reference (`<method>_r<r>_omega<Omega>.svg`).
pub fn study_plots(result: &StudyResult) -> Result<Vec<Plot>, String> {
    let mut plots = Vec::new();
    for omega in result.references.iter().map(|(o, _)| *o) {
        let (what, series) = result.convergence(omega);
        let curves = series
            .into_iter()
            .enumerate()
            .map(|(k, (name, mut points))| {
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                Curve {
                    name,
                    points,
                    style: Style::nth(k),
                    markers: true,
                }
            })
            .collect();
        let o = fmt_omega(omega);
        plots.push(Plot {
            file: format!("convergence_omega{o}.svg"),
            figure: Figure {
                title: format!("Convergence at Omega = {o} rad/s"),
                panels: vec![Panel {
                    title: format!("relative error of {what} against the number of modes r"),
                    x: Axis::new("r (Ritz coordinates)", Scale::Integer),
                    y: Axis::new("relative error (1)", Scale::Log),
                    curves,
                    legend: true,
                }],
            },
        });
    }
    for case in result.cases.iter().filter(|c| !c.reduced.m.x.is_empty()) {
        let (method, r, omega) = (case.row.method, case.row.r, fmt_omega(case.row.omega));
        let reference = result
            .reference(case.row.omega)
            .ok_or_else(|| format!("no reference at Omega = {omega} rad/s"))?;
        plots.push(Plot {
            file: format!("{method}_r{r}_omega{omega}.svg"),
            figure: case_figure(
                &format!("{method}, r = {r}, Omega = {omega} rad/s: reduced over reference"),
                reference,
                &case.reduced,
            ),
        });
    }
    Ok(plots)
}

/// Three panels (w, M, Q along the beam): the reference solid, the
/// reduced body dashed; real parts of the complex amplitudes.
fn case_figure(title: &str, reference: &BeamResponse, reduced: &BeamResponse) -> Figure {
    let quantities: [(&str, &str, &Field, &Field); 3] = [
        ("displacement w(x)", "Re w (m)", &reference.w, &reduced.w),
        (
            "bending moment M(x)",
            "Re M (N m)",
            &reference.m,
            &reduced.m,
        ),
        ("shear force Q(x)", "Re Q (N)", &reference.q, &reduced.q),
    ];
    let real = |f: &Field| f.x.iter().copied().zip(f.re.iter().copied()).collect();
    let panels = quantities
        .into_iter()
        .map(|(caption, unit, refd, red)| Panel {
            title: format!("{caption}, real part (in phase with the excitation)"),
            x: Axis::new("x (m)", Scale::Linear),
            y: Axis::new(unit, Scale::Linear),
            curves: vec![
                Curve {
                    name: "reference (full model)".into(),
                    points: real(refd),
                    style: Style::REFERENCE,
                    markers: false,
                },
                Curve {
                    name: "reduced".into(),
                    points: real(red),
                    style: Style::COMPARED,
                    markers: false,
                },
            ],
            legend: true,
        })
        .collect();
    Figure {
        title: title.into(),
        panels,
    }
}

/// `name` without a trailing ` (unit)`, and the unit.
fn split_unit(name: &str) -> (&str, Option<&str>) {
    match name.strip_suffix(')').and_then(|s| s.rsplit_once(" (")) {
        Some((base, unit)) => (base, Some(unit)),
        None => (name, None),
    }
}

/// Curves over `x` from named columns, the `k`-th in [`Style::nth`]`(k)`;
/// the names without their unit (the axis carries it).
fn curves_over(x: &[f64], columns: &[(&str, &[f64])]) -> Vec<Curve> {
    columns
        .iter()
        .enumerate()
        .map(|(k, (name, values))| Curve {
            name: split_unit(name).0.to_string(),
            points: x.iter().copied().zip(values.iter().copied()).collect(),
            style: Style::nth(k),
            markers: false,
        })
        .collect()
}

/// The plots of a run in time in `dir` (see [`history_plots`]).
pub fn plot_histories(dir: &Path, h: &Histories, label: &str) -> Result<Vec<PathBuf>, String> {
    write_plots(dir, &history_plots(h, label))
}

/// The plots of a run in time: `connections.svg` (connection forces) and,
/// where there are such histories, `histories.svg` (rigid-body
/// translations and rotations, bending moments and shear forces at element
/// ends, one panel each, the curves of a panel styled apart). `label`
/// names what ran (reduced body or full FE model).
pub fn history_plots(h: &Histories, label: &str) -> Vec<Plot> {
    let t = || Axis::new("t (s)", Scale::Linear);
    let mut plots = vec![Plot {
        file: "connections.svg".into(),
        figure: Figure {
            title: format!("Connection forces ({label})"),
            panels: vec![Panel {
                title: "connection forces".into(),
                x: t(),
                y: Axis::new("F (N)", Scale::Linear),
                curves: curves_over(&h.times, &h.of_kind(HistoryKind::Connection)),
                legend: true,
            }],
        },
    }];
    let rigid = h.of_kind(HistoryKind::RigidBody);
    let (rotations, translations): (Vec<_>, Vec<_>) = rigid
        .into_iter()
        .partition(|(name, _)| split_unit(name).1 == Some("rad"));
    let groups = [
        ("rigid bodies: translations", "u (m)", translations),
        ("rigid bodies: rotations", "phi (rad)", rotations),
        (
            "bending moment at element ends (eq. 25)",
            "My (N m)",
            h.of_kind(HistoryKind::EndMoment),
        ),
        (
            "shear force at element ends (eq. 25)",
            "Qz (N)",
            h.of_kind(HistoryKind::EndShear),
        ),
    ];
    let panels: Vec<Panel> = groups
        .into_iter()
        .filter(|(_, _, columns)| !columns.is_empty())
        .map(|(title, unit, columns)| Panel {
            title: title.into(),
            x: t(),
            y: Axis::new(unit, Scale::Linear),
            curves: curves_over(&h.times, &columns),
            legend: true,
        })
        .collect();
    if !panels.is_empty() {
        plots.push(Plot {
            file: "histories.svg".into(),
            figure: Figure {
                title: format!("Histories ({label})"),
                panels,
            },
        });
    }
    plots
}

/// The plots of a frequency response in `dir` (see [`transfer_plots`]).
pub fn plot_transfer(dir: &Path, t: &Transfer, connections: usize) -> Result<Vec<PathBuf>, String> {
    write_plots(dir, &transfer_plots(t, connections))
}

/// The plots of a frequency response: the transfer functions from the
/// track amplitude to the first `connections` outputs (connection forces,
/// `frf_connections.svg`) and to the others (section forces,
/// `frf_sections.svg`, where there are any). Per unit of output, a panel
/// of magnitudes (logarithmic axis) and below it one of phases; an
/// output has the same style in both, and the k-th output of each unit
/// the same style (the same element's shear force and bending moment).
pub fn transfer_plots(t: &Transfer, connections: usize) -> Vec<Plot> {
    let split = connections.min(t.outputs.len());
    let parts = [
        (
            "frf_connections.svg",
            "Transfer functions H: track amplitude to connection forces",
            0..split,
        ),
        (
            "frf_sections.svg",
            "Transfer functions H: track amplitude to section forces (eq. 25)",
            split..t.outputs.len(),
        ),
    ];
    let mut plots = Vec::new();
    for (k, (file, title, range)) in parts.into_iter().enumerate() {
        if k > 0 && range.is_empty() {
            continue;
        }
        // Outputs by unit, in order of first appearance.
        let mut groups: Vec<(&str, Vec<usize>)> = Vec::new();
        for i in range {
            let unit = split_unit(&t.outputs[i].0).1.unwrap_or("1");
            match groups.iter_mut().find(|(u, _)| *u == unit) {
                Some((_, members)) => members.push(i),
                None => groups.push((unit, vec![i])),
            }
        }
        let mut panels = Vec::new();
        for (unit, members) in groups {
            // Magnitude (`false`) or phase (`true`) of each member; where
            // the magnitude is zero the phase is undefined and not drawn.
            let phases: Vec<Vec<f64>> = members
                .iter()
                .map(|&i| {
                    let (_, magnitude, angle) = &t.outputs[i];
                    magnitude
                        .iter()
                        .zip(angle)
                        .map(|(m, a)| if *m == 0.0 { f64::NAN } else { *a })
                        .collect()
                })
                .collect();
            let curves = |phase: bool| {
                let columns: Vec<(&str, &[f64])> = members
                    .iter()
                    .zip(&phases)
                    .map(|(&i, phase_of)| {
                        let (name, magnitude, _) = &t.outputs[i];
                        let values = if phase { phase_of } else { magnitude };
                        (name.as_str(), values.as_slice())
                    })
                    .collect();
                curves_over(&t.frequencies_hz, &columns)
            };
            let what = quantity(&t.outputs[members[0]].0);
            panels.push(Panel {
                title: format!("{what}: magnitude"),
                x: Axis::new("f (Hz)", Scale::Linear),
                y: Axis::new(format!("|H| ({unit})"), Scale::Log),
                curves: curves(false),
                legend: true,
            });
            panels.push(Panel {
                title: format!("{what}: phase"),
                x: Axis::new("f (Hz)", Scale::Linear),
                y: Axis::new("arg H (rad)", Scale::Linear)
                    .fixed(-std::f64::consts::PI, std::f64::consts::PI),
                curves: curves(true),
                legend: false,
            });
        }
        plots.push(Plot {
            file: file.into(),
            figure: Figure {
                title: title.into(),
                panels,
            },
        });
    }
    plots
}

/// What an output of a transfer function is: a section force by its
/// symbol (`Qz`, `My`), else a connection force.
fn quantity(name: &str) -> &'static str {
    match split_unit(name).0.rsplit(' ').next() {
        Some("Qz") => "shear force Qz",
        Some("My") => "bending moment My",
        _ => "connection forces",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_that_are_not_finite_are_gaps_not_numbers_in_the_svg() {
        let dir = tempfile::tempdir().unwrap();
        let plot = |scale: Scale| Plot {
            file: "p.svg".into(),
            figure: Figure {
                title: "t".into(),
                panels: vec![Panel {
                    title: "p".into(),
                    x: Axis::new("t (s)", Scale::Linear),
                    y: Axis::new("F (N)", scale),
                    curves: vec![Curve {
                        name: "spring".into(),
                        points: vec![
                            (0.0, 1.0),
                            (1.0, f64::NAN),
                            (2.0, f64::INFINITY),
                            (3.0, 2.0),
                            (f64::NEG_INFINITY, 3.0),
                        ],
                        style: Style::nth(0),
                        markers: true,
                    }],
                    legend: false,
                }],
            },
        };
        for scale in [Scale::Linear, Scale::Log] {
            let written = write_plots(dir.path(), &[plot(scale)]).unwrap();
            let svg = std::fs::read_to_string(&written[0]).unwrap();
            assert!(svg.starts_with("<svg"));
            assert!(!svg.contains("NaN") && !svg.contains("inf"), "{scale:?}");
        }
    }

    #[test]
    fn units_are_split_off_names() {
        assert_eq!(split_unit("car_body.uz (m)"), ("car_body.uz", Some("m")));
        assert_eq!(
            split_unit("element 10 end My (N m/m)"),
            ("element 10 end My", Some("N m/m"))
        );
        assert_eq!(split_unit("bump_stop"), ("bump_stop", None));
    }

    #[test]
    fn section_outputs_of_two_units_get_two_pairs_of_panels() {
        let f = vec![1.0, 2.0];
        let t = Transfer {
            frequencies_hz: f.clone(),
            outputs: vec![
                ("spring (N/m)".into(), vec![1.0, 2.0], vec![0.0, 0.1]),
                (
                    "element 3 end Qz (N/m)".into(),
                    vec![1.0, 3.0],
                    vec![0.0, 0.2],
                ),
                (
                    "element 3 end My (N m/m)".into(),
                    vec![2.0, 1.0],
                    vec![0.1, 0.3],
                ),
            ],
        };
        let plots = transfer_plots(&t, 1);
        let sections = &plots[1].figure;
        let labels: Vec<&str> = sections.panels.iter().map(|p| p.y.label.as_str()).collect();
        assert_eq!(
            labels,
            ["|H| (N/m)", "arg H (rad)", "|H| (N m/m)", "arg H (rad)"]
        );
        // Element 3's My curve looks like its Qz curve.
        assert_eq!(
            sections.panels[0].curves[0].style,
            sections.panels[2].curves[0].style
        );
    }
}
