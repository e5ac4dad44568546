//! The plots of `study`, `simulate` and `frf` read as a journal's figures:
//! legends beside the data, never over it; legend swatches drawn like
//! their curves; curves of a plot told apart; one number format per axis;
//! integer ticks on a count; one quantity per axis; transfer functions as
//! magnitude on a logarithmic axis with the phase in a panel below.
//!
//! The checks read the SVG's named parts (see `flexbody::plot::figure`):
//! `rect.plot-area`, `rect.legend-box`, `g.axis`, `text.tick-label`,
//! `polyline.curve`, `g.legend-entry` with its `line.swatch`.

use super::support::run_ok;
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
}

/// Runs `flexbody <command> <example> --out <dir>` and returns the SVG
/// files written, by name.
fn plots_of(command: &str, model: &str, dir: &Path) -> Vec<(String, String)> {
    run_ok(&[
        command,
        example(model).to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    let mut svgs: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    svgs.sort();
    assert!(!svgs.is_empty(), "{command} wrote no plots");
    svgs
}

#[test]
fn study_plots_read_as_journal_figures() {
    let dir = tempfile::tempdir().unwrap();
    let svgs = plots_of("study", "side_beam.toml", dir.path());
    for (name, svg) in &svgs {
        assert_journal_figure(name, svg);
    }
    for (name, svg) in svgs.iter().filter(|(n, _)| n.starts_with("convergence")) {
        let panel = &panels(svg)[0];
        // r counts Ritz coordinates: an integer axis with integer labels.
        let r = axis(panel, "x");
        assert_eq!(attr(r.head, "data-scale"), Some("integer"), "{name}");
        for label in tick_labels(r.body) {
            assert!(label.parse::<i64>().is_ok(), "{name}: r tick '{label}'");
        }
        assert_eq!(attr(axis(panel, "y").head, "data-scale"), Some("log"));
    }
    // The reduced curve is dashed, the reference solid, in plot and legend.
    let (_, case) = svgs
        .iter()
        .find(|(n, _)| n == "free-residual_r7_omega122.svg")
        .expect("the plot of free-residual r = 7 at 122 rad/s");
    let reduced = curve_style(&panels(case)[0], "reduced");
    assert!(reduced.1.is_some(), "the reduced curve is dashed");
    assert_eq!(
        curve_style(&panels(case)[0], "reference (full model)").1,
        None
    );
}

#[test]
fn simulate_plots_read_as_journal_figures_with_one_unit_per_axis() {
    let dir = tempfile::tempdir().unwrap();
    let svgs = plots_of("simulate", "vehicle.toml", dir.path());
    let names: Vec<&str> = svgs.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["connections.svg", "histories.svg"]);
    for (name, svg) in &svgs {
        assert_journal_figure(name, svg);
    }
    // The rigid bodies move in m and turn in rad: two panels, one unit each.
    let units: Vec<String> = panels(&svgs[1].1)
        .iter()
        .map(|p| axis_label(axis(p, "y").body))
        .collect();
    assert_eq!(units, ["u (m)", "phi (rad)", "My (N m)", "Qz (N)"]);
}

#[test]
fn frf_plots_show_log_magnitudes_with_the_phase_below() {
    let dir = tempfile::tempdir().unwrap();
    let svgs = plots_of("frf", "vehicle.toml", dir.path());
    let names: Vec<&str> = svgs.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["frf_connections.svg", "frf_sections.svg"]);
    for (name, svg) in &svgs {
        assert_journal_figure(name, svg);
        let panels = panels(svg);
        assert!(
            panels.len().is_multiple_of(2),
            "{name}: magnitude and phase in pairs"
        );
        for pair in panels.chunks(2) {
            let (magnitude, phase) = (axis(&pair[0], "y"), axis(&pair[1], "y"));
            assert_eq!(attr(magnitude.head, "data-scale"), Some("log"), "{name}");
            assert!(axis_label(magnitude.body).starts_with("|H| ("), "{name}");
            assert_eq!(axis_label(phase.body), "arg H (rad)", "{name}");
            // The same outputs in the same styles in both panels.
            let mut a = curves(&pair[0]);
            let mut b = curves(&pair[1]);
            a.dedup();
            b.dedup();
            assert_eq!(a, b, "{name}: phase curves follow the magnitude's");
        }
    }
    // The section forces come in N/m (Qz) and N m/m (My): two pairs.
    let units: Vec<String> = panels(&svgs[1].1)
        .iter()
        .map(|p| axis_label(axis(p, "y").body))
        .collect();
    assert_eq!(
        units,
        ["|H| (N/m)", "arg H (rad)", "|H| (N m/m)", "arg H (rad)"]
    );
}

/// What every figure must satisfy, panel by panel.
fn assert_journal_figure(name: &str, svg: &str) {
    let panels = panels(svg);
    assert!(!panels.is_empty(), "{name}: no panel");
    for (k, panel) in panels.iter().enumerate() {
        let at = format!("{name}, panel {k}");
        let frame = rect(panel, "plot-area").unwrap_or_else(|| panic!("{at}: no plot area"));
        // The legend lies outside the frame: the two rectangles do not overlap.
        if let Some(legend) = rect(panel, "legend-box") {
            assert!(
                !frame.overlaps(&legend),
                "{at}: legend {legend:?} over the plot area {frame:?}"
            );
            // Each swatch is drawn like its curve: colour and dash pattern.
            let curves = curves(panel);
            for (entry, swatch) in legend_entries(panel) {
                let curve = curves
                    .iter()
                    .find(|(n, _)| *n == entry)
                    .unwrap_or_else(|| panic!("{at}: legend entry '{entry}' has no curve"));
                assert_eq!(swatch, curve.1, "{at}: swatch of '{entry}'");
            }
        }
        // No two curves of a panel look alike; none share a colour while
        // there are no more curves than colours.
        let mut styles = curves(panel);
        styles.dedup_by(|a, b| a.0 == b.0);
        let looks: Vec<String> = styles.iter().map(|(_, s)| format!("{s:?}")).collect();
        assert_all_differ(&looks, &at);
        if styles.len() <= 10 {
            let colours: Vec<String> = styles.iter().map(|(_, s)| s.0.clone()).collect();
            assert_all_differ(&colours, &at);
        }
        // Each axis: one number format for all of its tick labels.
        for which in ["x", "y"] {
            let labels = tick_labels(axis(panel, which).body);
            assert!(labels.len() >= 2, "{at}: {which} has {labels:?}");
            let formats: Vec<String> = labels.iter().map(|l| number_format(l)).collect();
            assert!(
                formats.iter().all(|f| *f == formats[0]),
                "{at}: {which} tick labels {labels:?} mix formats {formats:?}"
            );
            let label = axis_label(axis(panel, which).body);
            assert!(
                !label.contains(", "),
                "{at}: {which} axis '{label}' mixes quantities"
            );
        }
    }
}

/// The format of a tick label: `10^k`, or a decimal number with `d`
/// decimals (`plain.d`); anything else (`-2.00e6`) is its own format.
fn number_format(label: &str) -> String {
    if let Some(k) = label.strip_prefix("10^") {
        if k.parse::<i32>().is_ok() {
            return "power of ten".into();
        }
    }
    let digits = label.strip_prefix('-').unwrap_or(label);
    let (int, frac) = digits.split_once('.').unwrap_or((digits, ""));
    let numeric = |s: &str| s.chars().all(|c| c.is_ascii_digit());
    if !int.is_empty() && numeric(int) && numeric(frac) {
        format!("plain.{}", frac.len())
    } else {
        format!("other: {label}")
    }
}

fn assert_all_differ(items: &[String], at: &str) {
    for (i, a) in items.iter().enumerate() {
        assert!(!items[..i].contains(a), "{at}: '{a}' repeats in {items:?}");
    }
}

// Reading the SVG's named parts.

/// The text of each `g.panel`.
fn panels(svg: &str) -> Vec<String> {
    svg.split(r#"<g class="panel">"#)
        .skip(1)
        .map(str::to_string)
        .collect()
}

/// An axis group: its opening tag and what follows up to its end.
struct AxisPart<'a> {
    head: &'a str,
    body: &'a str,
}

fn axis<'a>(panel: &'a str, which: &str) -> AxisPart<'a> {
    let start = panel
        .find(&format!(r#"<g class="axis" data-axis="{which}""#))
        .unwrap_or_else(|| panic!("no {which} axis"));
    let rest = &panel[start..];
    let head_end = rest.find('>').unwrap() + 1;
    let body_end = rest.find("</g>").unwrap();
    AxisPart {
        head: &rest[..head_end],
        body: &rest[head_end..body_end],
    }
}

/// The value of attribute `name` in an opening tag.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    Some(&tag[start..start + tag[start..].find('"')?])
}

/// The opening tags `<tag ...>` with `class="class"`.
fn tags<'a>(text: &'a str, tag: &str, class: &str) -> Vec<&'a str> {
    let open = format!("<{tag} ");
    text.match_indices(&open)
        .map(|(i, _)| &text[i..i + text[i..].find('>').unwrap() + 1])
        .filter(|t| attr(t, "class") == Some(class))
        .collect()
}

/// The text of each `text` element of `class`; a superscript (`tspan`) as `^`.
fn texts(text: &str, class: &str) -> Vec<String> {
    tags(text, "text", class)
        .into_iter()
        .map(|t| {
            let start = text.find(t).unwrap() + t.len();
            let inner = &text[start..start + text[start..].find("</text>").unwrap()];
            let mut out = String::new();
            let mut rest = inner;
            while let Some(i) = rest.find('<') {
                out.push_str(&rest[..i]);
                if rest[i..].starts_with("<tspan") {
                    out.push('^');
                }
                rest = &rest[i + rest[i..].find('>').unwrap() + 1..];
            }
            out.push_str(rest);
            out
        })
        .collect()
}

fn tick_labels(axis_body: &str) -> Vec<String> {
    texts(axis_body, "tick-label")
}

fn axis_label(axis_body: &str) -> String {
    texts(axis_body, "axis-label").remove(0)
}

#[derive(Debug, PartialEq)]
struct Rect {
    x: f64,
    y: f64,
    width: f64,
    height: f64,
}

impl Rect {
    fn overlaps(&self, o: &Rect) -> bool {
        self.x < o.x + o.width
            && o.x < self.x + self.width
            && self.y < o.y + o.height
            && o.y < self.y + self.height
    }
}

fn rect(panel: &str, class: &str) -> Option<Rect> {
    let t = *tags(panel, "rect", class).first()?;
    let f = |name| attr(t, name).unwrap().parse::<f64>().unwrap();
    Some(Rect {
        x: f("x"),
        y: f("y"),
        width: f("width"),
        height: f("height"),
    })
}

/// Colour and dash pattern.
#[derive(Clone, Debug, PartialEq)]
struct Style(String, Option<String>);

fn style_of(tag: &str) -> Style {
    Style(
        attr(tag, "stroke").unwrap().to_string(),
        attr(tag, "stroke-dasharray").map(str::to_string),
    )
}

/// `(name, style)` of each polyline of a curve, in order.
fn curves(panel: &str) -> Vec<(String, Style)> {
    tags(panel, "polyline", "curve")
        .into_iter()
        .map(|t| (attr(t, "data-name").unwrap().to_string(), style_of(t)))
        .collect()
}

fn curve_style(panel: &str, name: &str) -> Style {
    curves(panel)
        .into_iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no curve '{name}'"))
        .1
}

/// `(name, swatch style)` of each legend entry.
fn legend_entries(panel: &str) -> Vec<(String, Style)> {
    tags(panel, "g", "legend-entry")
        .into_iter()
        .map(|entry| {
            let at = panel.find(entry).unwrap();
            let swatch = tags(&panel[at..], "line", "swatch")[0];
            (
                attr(entry, "data-name").unwrap().to_string(),
                style_of(swatch),
            )
        })
        .collect()
}
