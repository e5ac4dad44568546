//! SVG plots: of a study case, like the report's figures 6-10
//! (displacement w(x), bending moment M(x) and shear force Q(x), reduced
//! over reference; real parts, the in-phase response), of a study's
//! convergence, of histories in time and of transfer functions. SVG needs no
//! fonts.

use crate::simulate::{Histories, HistoryKind, Transfer};
use crate::study::{fmt_omega, BeamResponse, Field, StudyResult};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// The plots of a study in `dir`: per excitation frequency a convergence
/// plot (`convergence_omega<Omega>.svg`), and per case with curves the
/// reduced response over the reference (`<method>_r<r>_omega<Omega>.svg`).
pub fn plot_study(dir: &Path, result: &StudyResult) -> Result<(), String> {
    for omega in result.references.iter().map(|(o, _)| *o) {
        let (what, series) = result.convergence(omega);
        plot_convergence(
            &dir.join(format!("convergence_omega{}.svg", fmt_omega(omega))),
            &format!(
                "error of {what} against r, Omega = {} rad/s",
                fmt_omega(omega)
            ),
            &series,
        )?;
    }
    for case in result.cases.iter().filter(|c| !c.reduced.m.x.is_empty()) {
        let (method, r, omega) = (case.row.method, case.row.r, fmt_omega(case.row.omega));
        let reference = result
            .reference(case.row.omega)
            .ok_or_else(|| format!("no reference at Omega = {omega} rad/s"))?;
        plot_case(
            &dir.join(format!("{method}_r{r}_omega{omega}.svg")),
            &format!("{method}, r = {r}, Omega = {omega} rad/s: reduced (dashed) over reference"),
            reference,
            &case.reduced,
        )?;
    }
    Ok(())
}

/// Writes one SVG with three panels (w, M, Q) to `path`.
pub fn plot_case(
    path: &Path,
    title: &str,
    reference: &BeamResponse,
    reduced: &BeamResponse,
) -> Result<(), String> {
    write_svg(path, |tmp| draw(tmp, title, reference, reduced))
}

type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// Draws into a temporary file beside `path` and renames it into place, so
/// that no half-drawn plot is left behind.
fn write_svg(path: &Path, draw: impl FnOnce(&Path) -> DrawResult) -> Result<(), String> {
    let tmp = path.with_extension("svg.tmp");
    let done = draw(&tmp)
        .map_err(|e| format!("{}: cannot draw: {e}", path.display()))
        .and_then(|()| {
            std::fs::rename(&tmp, path)
                .map_err(|e| format!("{}: cannot write: {e}", path.display()))
        });
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// The smallest and largest value (infinite bounds when there are none).
fn bounds<'a>(values: impl IntoIterator<Item = &'a f64>) -> (f64, f64) {
    values
        .into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        })
}

type LinearChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A chart on `area` with linear axes over `x` and over `y` padded by 8 %
/// (`[-1, 1]` where `y` has no finite bounds), its mesh labelled.
fn linear_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    (x0, x1): (f64, f64),
    (mut y0, mut y1): (f64, f64),
    (x_label, y_label): (&str, &str),
) -> Result<LinearChart<'a, 'b>, Box<dyn std::error::Error>> {
    if !(y0.is_finite() && y1.is_finite()) {
        (y0, y1) = (-1.0, 1.0);
    }
    let pad = ((y1 - y0) * 0.08)
        .max(y1.abs().max(y0.abs()) * 1e-3)
        .max(1e-12);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1.max(x0 + 1e-9), (y0 - pad)..(y1 + pad))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .y_label_formatter(&tick_label)
        .draw()?;
    Ok(chart)
}

/// The legend of a chart's labelled series, upper right.
fn draw_legend<'a, DB, CT>(chart: &mut ChartContext<'a, DB, CT>) -> DrawResult
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    Ok(())
}

fn draw(path: &Path, title: &str, reference: &BeamResponse, reduced: &BeamResponse) -> DrawResult {
    let root = SVGBackend::new(path, (900, 1000)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 22))?;
    let panels = root.split_evenly((3, 1));
    let quantities: [(&str, &str, &Field, &Field); 3] = [
        ("displacement w(x)", "w (m)", &reference.w, &reduced.w),
        ("bending moment M(x)", "M (N m)", &reference.m, &reduced.m),
        ("shear force Q(x)", "Q (N)", &reference.q, &reduced.q),
    ];
    for (area, (caption, unit, refd, red)) in panels.iter().zip(quantities) {
        panel(area, caption, unit, refd, red)?;
    }
    root.present()?;
    Ok(())
}

fn panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    caption: &str,
    unit: &str,
    reference: &Field,
    reduced: &Field,
) -> DrawResult {
    let mut chart = linear_chart(
        area,
        caption,
        bounds(reference.x.iter().chain(&reduced.x)),
        bounds(reference.re.iter().chain(&reduced.re)),
        ("x (m)", unit),
    )?;
    chart
        .draw_series(LineSeries::new(
            reference
                .x
                .iter()
                .copied()
                .zip(reference.re.iter().copied()),
            BLACK.stroke_width(2),
        ))?
        .label("reference (full model)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    chart
        .draw_series(DashedLineSeries::new(
            reduced.x.iter().copied().zip(reduced.re.iter().copied()),
            6,
            4,
            RED.stroke_width(2),
        ))?
        .label("reduced")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    draw_legend(&mut chart)
}

/// Tick labels: plain decimals for moderate magnitudes, else scientific.
fn tick_label(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-2..1e5).contains(&a) {
        format!("{v:.3}")
    } else {
        format!("{v:.2e}")
    }
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(0, 0, 0),
];

/// One panel of a multi-panel plot: title, y label, and named series over x.
pub struct Panel<'a> {
    pub title: &'a str,
    pub y_label: &'a str,
    pub series: Vec<(&'a str, &'a [f64])>,
}

/// Writes stacked panels of line series over a common `x` to an SVG.
pub fn plot_panels(
    path: &Path,
    title: &str,
    x_label: &str,
    x: &[f64],
    panels: &[Panel<'_>],
) -> Result<(), String> {
    write_svg(path, |tmp| {
        let height = 60 + 330 * panels.len().max(1) as u32;
        let root = SVGBackend::new(tmp, (1000, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let root = root.titled(title, ("sans-serif", 22))?;
        for (area, p) in root
            .split_evenly((panels.len().max(1), 1))
            .iter()
            .zip(panels)
        {
            let ys = p.series.iter().flat_map(|(_, v)| v.iter());
            let mut chart = linear_chart(
                area,
                p.title,
                bounds(x),
                bounds(ys.filter(|v| v.is_finite())),
                (x_label, p.y_label),
            )?;
            for (k, (name, values)) in p.series.iter().enumerate() {
                let color = PALETTE[k % PALETTE.len()];
                chart
                    .draw_series(LineSeries::new(
                        x.iter().copied().zip(values.iter().copied()),
                        color.stroke_width(2),
                    ))?
                    .label(*name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
            }
            draw_legend(&mut chart)?;
        }
        root.present()?;
        Ok(())
    })
}

/// Error against r, one line per method, logarithmic error axis.
pub fn plot_convergence(
    path: &Path,
    title: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> Result<(), String> {
    write_svg(path, |tmp| {
        let root = SVGBackend::new(tmp, (900, 600)).into_drawing_area();
        root.fill(&WHITE)?;
        let pts = series.iter().flat_map(|(_, p)| p.iter());
        let (r0, r1, e0, e1) = pts.fold(
            (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ),
            |(a, b, c, d), (r, e)| (a.min(*r), b.max(*r), c.min(*e), d.max(*e)),
        );
        let (r0, r1) = if r0.is_finite() {
            (r0 - 1.0, r1 + 1.0)
        } else {
            (0.0, 1.0)
        };
        let (e0, e1) = if e0.is_finite() {
            (e0 / 3.0, e1 * 3.0)
        } else {
            (1e-3, 1.0)
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(r0..r1, (e0..e1).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("r (Ritz coordinates)")
            .y_desc("relative error")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        for (k, (name, points)) in series.iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            let mut pts = points.clone();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))?
                .label(name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            chart.draw_series(pts.iter().map(|p| Circle::new(*p, 4, color.filled())))?;
        }
        draw_legend(&mut chart)?;
        root.present()?;
        Ok(())
    })
}

/// The plots of a run in time in `dir`: `connections.svg` (connection
/// forces) and, where there are such histories, `histories.svg` (rigid
/// bodies, bending moments and shear forces at element ends). `label`
/// names what ran (reduced body or full FE model). Returns the files
/// written.
pub fn plot_histories(dir: &Path, h: &Histories, label: &str) -> Result<Vec<PathBuf>, String> {
    let mut written = vec![dir.join("connections.svg")];
    plot_panels(
        &written[0],
        &format!("connection forces ({label})"),
        "t (s)",
        &h.times,
        &[Panel {
            title: "connection forces",
            y_label: "F (N)",
            series: h.of_kind(HistoryKind::Connection),
        }],
    )?;
    let rigid = h.of_kind(HistoryKind::RigidBody);
    let moments = h.of_kind(HistoryKind::EndMoment);
    let mut panels = vec![];
    if !rigid.is_empty() {
        panels.push(Panel {
            title: "rigid bodies",
            y_label: "m, rad",
            series: rigid,
        });
    }
    if !moments.is_empty() {
        panels.push(Panel {
            title: "bending moment at element ends (eq. 25)",
            y_label: "My (N m)",
            series: moments,
        });
        panels.push(Panel {
            title: "shear force at element ends (eq. 25)",
            y_label: "Qz (N)",
            series: h.of_kind(HistoryKind::EndShear),
        });
    }
    if panels.is_empty() {
        return Ok(written);
    }
    written.push(dir.join("histories.svg"));
    plot_panels(
        &written[1],
        &format!("histories ({label})"),
        "t (s)",
        &h.times,
        &panels,
    )?;
    Ok(written)
}

/// The plots of a frequency response in `dir`: magnitude and phase of the
/// transfer functions to the first `connections` outputs (connection
/// forces, `frf_connections.svg`) and to the others (section forces,
/// `frf_sections.svg`, where there are any). Returns the files written.
pub fn plot_transfer(dir: &Path, t: &Transfer, connections: usize) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let mags: Vec<(&str, &[f64])> = t
        .outputs
        .iter()
        .map(|(n, m, _)| (n.as_str(), m.as_slice()))
        .collect();
    let phases: Vec<(&str, &[f64])> = t
        .outputs
        .iter()
        .map(|(n, _, p)| (n.as_str(), p.as_slice()))
        .collect();
    let split = connections.min(mags.len());
    let parts = [
        (
            "frf_connections.svg",
            "transfer functions: track amplitude to connection forces",
            "N per m",
            0..split,
        ),
        (
            "frf_sections.svg",
            "transfer functions: track amplitude to section forces (eq. 25)",
            "per m",
            split..mags.len(),
        ),
    ];
    for (k, (file, title, unit, range)) in parts.into_iter().enumerate() {
        if k > 0 && range.is_empty() {
            continue;
        }
        written.push(dir.join(file));
        plot_panels(
            &dir.join(file),
            title,
            "f (Hz)",
            &t.frequencies_hz,
            &[
                Panel {
                    title: "magnitude",
                    y_label: unit,
                    series: mags[range.clone()].to_vec(),
                },
                Panel {
                    title: "phase",
                    y_label: "rad",
                    series: phases[range].to_vec(),
                },
            ],
        )?;
    }
    Ok(written)
}
