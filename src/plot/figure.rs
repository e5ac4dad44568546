//! A figure as SVG text: panels stacked one above the other, each a framed
//! plotting area with its axes and curves and, to the right of the frame
//! (never over the data), its legend.
//!
//! The SVG names its parts, so that a reader (or a test) can find them:
//! `rect.plot-area` is a panel's frame, `g.axis[data-axis][data-scale]`
//! holds an axis's ticks with `text.tick-label` and, where the labels are
//! scaled, `text.axis-multiplier`; `polyline.curve[data-name]` and
//! `circle.marker` draw a curve, `rect.legend-box` and
//! `g.legend-entry[data-name]` with its `line.swatch` the legend. A swatch
//! has its curve's colour, width and dash pattern. Needs no fonts, scripts
//! or other files.

use super::axis::{Scale, TickText, Ticks};
use super::style::Style;
use std::fmt::Write as _;

/// An axis: its label (quantity and unit) and scale; the range follows the
/// data unless fixed.
#[derive(Clone, Debug)]
pub struct Axis {
    pub label: String,
    pub scale: Scale,
    pub range: Option<(f64, f64)>,
}

impl Axis {
    pub fn new(label: impl Into<String>, scale: Scale) -> Axis {
        Axis {
            label: label.into(),
            scale,
            range: None,
        }
    }

    /// The axis over `(lo, hi)` whatever the data (a linear axis over
    /// exactly that range).
    pub fn fixed(self, lo: f64, hi: f64) -> Axis {
        Axis {
            range: Some((lo, hi)),
            ..self
        }
    }
}

/// A named line through `points`; with `markers`, a dot at each point.
#[derive(Clone, Debug)]
pub struct Curve {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    pub markers: bool,
}

/// One plotting area with its axes, curves and (if `legend`) legend.
#[derive(Clone, Debug)]
pub struct Panel {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub curves: Vec<Curve>,
    pub legend: bool,
}

/// Panels under a title.
#[derive(Clone, Debug)]
pub struct Figure {
    pub title: String,
    pub panels: Vec<Panel>,
}

const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";
/// From a panel's left edge to its frame (y tick labels and y label).
const LEFT: f64 = 88.0;
const PLOT_WIDTH: f64 = 600.0;
/// The smallest height of a frame.
const PLOT_HEIGHT: f64 = 220.0;
const TITLE_HEIGHT: f64 = 40.0;
/// Above a frame: the panel's title.
const PANEL_TOP: f64 = 30.0;
/// Below a frame: x tick labels and the x label.
const PANEL_BOTTOM: f64 = 56.0;
/// Between a frame and its legend.
const LEGEND_GAP: f64 = 20.0;
const LEGEND_ROW: f64 = 18.0;
const LEGEND_PAD: f64 = 8.0;
const SWATCH: f64 = 34.0;
const LEGEND_FONT: f64 = 12.0;
/// A generous width of a character of the legend's font, relative to its size.
const CHAR_WIDTH: f64 = 0.56;
const RIGHT: f64 = 16.0;

impl Figure {
    /// The figure as one SVG document.
    pub fn to_svg(&self) -> String {
        let legend_width = self
            .panels
            .iter()
            .filter(|p| p.legend)
            .flat_map(|p| {
                p.curves
                    .iter()
                    .map(|c| legend_text_width(&legend_label(c, &p.y)))
            })
            .fold(None, |w: Option<f64>, c| Some(w.map_or(c, |w| w.max(c))))
            .map_or(0.0, |w| LEGEND_GAP + 2.0 * LEGEND_PAD + SWATCH + 8.0 + w);
        let width = (LEFT + PLOT_WIDTH + legend_width + RIGHT).ceil();
        let heights: Vec<f64> = self.panels.iter().map(plot_height).collect();
        let height = (TITLE_HEIGHT
            + heights
                .iter()
                .map(|h| PANEL_TOP + h + PANEL_BOTTOM)
                .sum::<f64>())
        .ceil();
        let mut svg = String::new();
        let _ = write!(
            svg,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="{FONT}">"##
        );
        let _ = write!(
            svg,
            r##"<rect width="{width}" height="{height}" fill="#ffffff"/><text class="figure-title" x="{}" y="26" font-size="15" text-anchor="middle">{}</text>"##,
            width / 2.0,
            escape(&self.title)
        );
        let mut top = TITLE_HEIGHT;
        for (panel, h) in self.panels.iter().zip(heights) {
            let frame = Frame {
                left: LEFT,
                top: top + PANEL_TOP,
                width: PLOT_WIDTH,
                height: h,
            };
            draw_panel(&mut svg, panel, &frame);
            top += PANEL_TOP + h + PANEL_BOTTOM;
        }
        svg.push_str("</svg>\n");
        svg
    }
}

/// Width of a legend entry's text (px).
fn legend_text_width(name: &str) -> f64 {
    name.chars().count() as f64 * LEGEND_FONT * CHAR_WIDTH
}

/// A curve's name in the legend; on a log axis, with `(zero)` where it has
/// no positive value to draw.
fn legend_label(c: &Curve, y: &Axis) -> String {
    let drawable = c.points.iter().any(|p| p.1.is_finite() && p.1 > 0.0);
    if y.scale == Scale::Log && !drawable {
        format!("{} (zero)", c.name)
    } else {
        c.name.clone()
    }
}

/// The height of a panel's frame: room for its legend at least.
fn plot_height(p: &Panel) -> f64 {
    let legend = if p.legend {
        2.0 * LEGEND_PAD + LEGEND_ROW * p.curves.len() as f64
    } else {
        0.0
    };
    PLOT_HEIGHT.max(legend)
}

/// A frame's rectangle (px).
struct Frame {
    left: f64,
    top: f64,
    width: f64,
    height: f64,
}

impl Frame {
    fn right(&self) -> f64 {
        self.left + self.width
    }
    fn bottom(&self) -> f64 {
        self.top + self.height
    }
}

/// The smallest and largest of the drawable values (on a log axis: of
/// the positive ones).
fn data_bounds(values: impl Iterator<Item = f64>, scale: Scale) -> (f64, f64) {
    values
        .filter(|v| v.is_finite() && (scale != Scale::Log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

fn ticks_of(axis: &Axis, values: impl Iterator<Item = f64>) -> Ticks {
    match axis.range {
        Some((lo, hi)) if axis.scale == Scale::Linear => Ticks::exactly(lo, hi),
        Some(range) => Ticks::new(axis.scale, range),
        None => Ticks::new(axis.scale, data_bounds(values, axis.scale)),
    }
}

fn draw_panel(svg: &mut String, p: &Panel, f: &Frame) {
    let points = || p.curves.iter().flat_map(|c| c.points.iter());
    let x = ticks_of(&p.x, points().map(|q| q.0));
    let y = ticks_of(&p.y, points().map(|q| q.1));
    svg.push_str(r#"<g class="panel">"#);
    let _ = write!(
        svg,
        r##"<text class="panel-title" x="{}" y="{}" font-size="13" text-anchor="middle">{}</text>"##,
        f.left + f.width / 2.0,
        f.top - 10.0,
        escape(&p.title)
    );
    draw_x_axis(svg, &p.x, &x, f);
    draw_y_axis(svg, &p.y, &y, f);
    let px = |v: f64| x.fraction(v).map(|t| f.left + t * f.width);
    let py = |v: f64| y.fraction(v).map(|t| f.bottom() - t * f.height);
    for c in &p.curves {
        let at: Vec<Option<(f64, f64)>> = c.points.iter().map(|&(a, b)| px(a).zip(py(b))).collect();
        // A point that cannot be drawn (a zero on a log axis) breaks the
        // line; a curve with none to draw stays as an empty line.
        let runs: Vec<&[Option<(f64, f64)>]> =
            at.split(|q| q.is_none()).filter(|r| r.len() > 1).collect();
        let runs = if runs.is_empty() { vec![&[][..]] } else { runs };
        for run in runs {
            let pts: Vec<String> = run
                .iter()
                .flatten()
                .map(|(a, b)| format!("{a:.1},{b:.1}"))
                .collect();
            let _ = write!(
                svg,
                r##"<polyline class="curve" data-name="{}" points="{}" fill="none" stroke-linejoin="round" {}/>"##,
                escape(&c.name),
                pts.join(" "),
                stroke(&c.style)
            );
        }
        if c.markers {
            for (a, b) in at.iter().flatten() {
                let _ = write!(
                    svg,
                    r##"<circle class="marker" data-name="{}" cx="{a:.1}" cy="{b:.1}" r="3.5" fill="{}"/>"##,
                    escape(&c.name),
                    c.style.color
                );
            }
        }
    }
    let _ = write!(
        svg,
        r##"<rect class="plot-area" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#000000" stroke-width="1"/>"##,
        f.left, f.top, f.width, f.height
    );
    if p.legend && !p.curves.is_empty() {
        draw_legend(svg, p, f);
    }
    svg.push_str("</g>");
}

/// The stroke attributes of a curve or swatch.
fn stroke(s: &Style) -> String {
    let dash = s
        .dash
        .dasharray()
        .map_or(String::new(), |d| format!(r#" stroke-dasharray="{d}""#));
    format!(r#"stroke="{}" stroke-width="1.8"{dash}"#, s.color)
}

fn tick_text(t: &TickText) -> String {
    match t {
        TickText::Plain(s) => escape(s),
        TickText::Power(k) => {
            format!(r#"10<tspan dy="-0.45em" font-size="0.75em">{k}</tspan>"#)
        }
    }
}

fn multiplier_text(e: i32) -> String {
    format!(r#"×10<tspan dy="-0.45em" font-size="0.75em">{e}</tspan>"#)
}

fn draw_x_axis(svg: &mut String, axis: &Axis, t: &Ticks, f: &Frame) {
    let _ = write!(
        svg,
        r#"<g class="axis" data-axis="x" data-scale="{}">"#,
        t.scale.name()
    );
    let px = |v: f64| t.fraction(v).map(|s| f.left + s * f.width);
    for x in t.minor.iter().filter_map(|v| px(*v)) {
        let _ = write!(
            svg,
            r##"<line x1="{x:.1}" y1="{b}" x2="{x:.1}" y2="{}" stroke="#000000" stroke-width="0.8"/>"##,
            f.bottom() - 3.0,
            b = f.bottom()
        );
    }
    for (v, label) in &t.major {
        let Some(x) = px(*v) else { continue };
        let _ = write!(
            svg,
            r##"<line class="grid" x1="{x:.1}" y1="{}" x2="{x:.1}" y2="{}" stroke="#e0e0e0" stroke-width="0.8"/><line x1="{x:.1}" y1="{}" x2="{x:.1}" y2="{}" stroke="#000000" stroke-width="1"/><text class="tick-label" x="{x:.1}" y="{}" font-size="11" text-anchor="middle">{}</text>"##,
            f.top,
            f.bottom(),
            f.bottom(),
            f.bottom() - 5.0,
            f.bottom() + 16.0,
            tick_text(label)
        );
    }
    if let Some(e) = t.multiplier {
        let _ = write!(
            svg,
            r#"<text class="axis-multiplier" x="{}" y="{}" font-size="11" text-anchor="end">{}</text>"#,
            f.right(),
            f.bottom() + 40.0,
            multiplier_text(e)
        );
    }
    let _ = write!(
        svg,
        r#"<text class="axis-label" x="{}" y="{}" font-size="12" text-anchor="middle">{}</text></g>"#,
        f.left + f.width / 2.0,
        f.bottom() + 40.0,
        escape(&axis.label)
    );
}

fn draw_y_axis(svg: &mut String, axis: &Axis, t: &Ticks, f: &Frame) {
    let _ = write!(
        svg,
        r#"<g class="axis" data-axis="y" data-scale="{}">"#,
        t.scale.name()
    );
    let py = |v: f64| t.fraction(v).map(|s| f.bottom() - s * f.height);
    for y in t.minor.iter().filter_map(|v| py(*v)) {
        let _ = write!(
            svg,
            r##"<line x1="{l}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#000000" stroke-width="0.8"/>"##,
            f.left + 3.0,
            l = f.left
        );
    }
    for (v, label) in &t.major {
        let Some(y) = py(*v) else { continue };
        let _ = write!(
            svg,
            r##"<line class="grid" x1="{}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#e0e0e0" stroke-width="0.8"/><line x1="{}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#000000" stroke-width="1"/><text class="tick-label" x="{}" y="{:.1}" font-size="11" text-anchor="end">{}</text>"##,
            f.left,
            f.right(),
            f.left,
            f.left + 5.0,
            f.left - 6.0,
            y + 4.0,
            tick_text(label)
        );
    }
    if let Some(e) = t.multiplier {
        let _ = write!(
            svg,
            r#"<text class="axis-multiplier" x="{}" y="{}" font-size="11" text-anchor="end">{}</text>"#,
            f.left - 6.0,
            f.top - 10.0,
            multiplier_text(e)
        );
    }
    let (x, y) = (f.left - 70.0, f.top + f.height / 2.0);
    let _ = write!(
        svg,
        r#"<text class="axis-label" x="{x}" y="{y}" font-size="12" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text></g>"#,
        escape(&axis.label)
    );
}

/// The legend, to the right of the frame `f`, its top level with the frame's.
fn draw_legend(svg: &mut String, p: &Panel, f: &Frame) {
    let curves = &p.curves;
    let text = curves
        .iter()
        .map(|c| legend_text_width(&legend_label(c, &p.y)))
        .fold(0.0, f64::max);
    let (left, top) = (f.right() + LEGEND_GAP, f.top);
    let width = 2.0 * LEGEND_PAD + SWATCH + 8.0 + text;
    let height = 2.0 * LEGEND_PAD + LEGEND_ROW * curves.len() as f64;
    let _ = write!(
        svg,
        r##"<g class="legend"><rect class="legend-box" x="{left}" y="{top}" width="{width:.1}" height="{height}" fill="#ffffff" stroke="#808080" stroke-width="0.8"/>"##
    );
    for (k, c) in curves.iter().enumerate() {
        let y = top + LEGEND_PAD + LEGEND_ROW * (k as f64 + 0.5);
        let x0 = left + LEGEND_PAD;
        let _ = write!(
            svg,
            r#"<g class="legend-entry" data-name="{}"><line class="swatch" x1="{x0}" y1="{y}" x2="{}" y2="{y}" {}/>"#,
            escape(&c.name),
            x0 + SWATCH,
            stroke(&c.style)
        );
        if c.markers {
            let _ = write!(
                svg,
                r#"<circle cx="{}" cy="{y}" r="3.5" fill="{}"/>"#,
                x0 + SWATCH / 2.0,
                c.style.color
            );
        }
        let _ = write!(
            svg,
            r#"<text x="{}" y="{}" font-size="{LEGEND_FONT}">{}</text></g>"#,
            x0 + SWATCH + 8.0,
            y + 4.0,
            escape(&legend_label(c, &p.y))
        );
    }
    svg.push_str("</g>");
}

/// `s` with the characters XML gives a meaning escaped.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(ch),
        }
    }
    out
}
