//! The study as one self-contained HTML page for a design review: what was
//! run (flexbody's version, the command line, the date in UTC), the model
//! (nodes, elements, DOFs, mass along each axis, the study's cases and
//! excitation frequencies), the error table with the figures `study`
//! prints, and every plot of the study as inline SVG.
//!
//! Plain HTML with inline CSS: no scripts, no fonts or images from
//! elsewhere; the page reads the same offline. (Not to be confused with
//! [`crate::report`], the figures the command line prints.)

use crate::export::{write_atomically, ExportError};
use crate::fem::{FemError, Substructure};
use crate::plot::{self, figure::escape};
use crate::report::mass_along_axes;
use crate::scenario::ModelFile;
use crate::study::{fmt_omega, CaseRow, StudyResult};
use std::fmt::Write as _;
use std::path::Path;

/// Errors of the report, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("report: the model's mass: {0}")]
    Mass(#[from] FemError),
    #[error("report: {0}")]
    Plot(String),
    #[error(transparent)]
    Write(#[from] ExportError),
}

/// What the page says about the run besides the study's result.
#[derive(Clone, Debug)]
pub struct RunInfo {
    /// The command line as typed (arguments quoted where they need it).
    pub command_line: String,
    /// flexbody's version.
    pub version: String,
    /// When the page was written: `YYYY-MM-DD hh:mm:ss UTC`.
    pub date: String,
}

impl RunInfo {
    /// This process: its arguments, the crate's version, the time now.
    pub fn of_this_process() -> RunInfo {
        RunInfo {
            command_line: std::env::args()
                .map(|a| shell_quoted(&a))
                .collect::<Vec<_>>()
                .join(" "),
            version: env!("CARGO_PKG_VERSION").to_string(),
            date: utc_now(),
        }
    }
}

/// `arg` as a shell reads it back: unchanged when it holds only safe
/// characters, else in single quotes.
fn shell_quoted(arg: &str) -> String {
    let safe = !arg.is_empty()
        && arg
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    if safe {
        arg.to_string()
    } else {
        format!("'{}'", arg.replace('\'', r"'\''"))
    }
}

/// The time now in UTC, `YYYY-MM-DD hh:mm:ss UTC`.
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    utc_text(secs)
}

/// Seconds since 1970-01-01 00:00:00 UTC as `YYYY-MM-DD hh:mm:ss UTC`
/// (the proleptic Gregorian calendar: days to a civil date after
/// H. Hinnant's `civil_from_days`).
fn utc_text(secs: u64) -> String {
    let (days, rest) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

/// Writes the page of `result`, the study of `file`, to `path` (through a
/// temporary file renamed into place).
pub fn write_study_report(
    path: &Path,
    file: &ModelFile,
    result: &StudyResult,
    run: &RunInfo,
) -> Result<(), ReportError> {
    let html = study_page(file, result, run)?;
    write_atomically(path, |w| w.write_all(html.as_bytes()))?;
    Ok(())
}

/// The page of `result`, the study of `file`.
pub fn study_page(
    file: &ModelFile,
    result: &StudyResult,
    run: &RunInfo,
) -> Result<String, ReportError> {
    let sub = Substructure::from_model(&file.model)?;
    let mass = mass_along_axes(&sub);
    let plots = plot::study_plots(result).map_err(ReportError::Plot)?;
    let title = result
        .title
        .clone()
        .unwrap_or_else(|| format!("Study of {}", file.path.display()));
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{t}</title><style>{STYLE}</style></head><body><h1>{t}</h1>",
        t = escape(&title)
    );
    h.push_str("<h2>Run</h2><table class=\"facts\">");
    for (k, v) in [
        ("flexbody version", run.version.as_str()),
        ("command line", run.command_line.as_str()),
        ("date", run.date.as_str()),
        ("model file", &file.path.display().to_string()),
    ] {
        let _ = write!(
            h,
            "<tr><th>{k}</th><td><code>{}</code></td></tr>",
            escape(v)
        );
    }
    h.push_str("</table><h2>Model</h2><table class=\"facts\">");
    let model = &file.model;
    let facts = [
        ("nodes", model.nodes().len().to_string()),
        ("elements", model.elements().len().to_string()),
        ("DOFs", sub.dof_map.len().to_string()),
        (
            "mass along x, y, z (kg)",
            mass.map(|m| format!("{m:.6e}")).join(", "),
        ),
        ("interface DOFs", file.interface.len().to_string()),
    ];
    for (k, v) in facts {
        let _ = write!(h, "<tr><th>{k}</th><td>{}</td></tr>", escape(&v));
    }
    h.push_str("</table>");
    if let Some(spec) = &file.study {
        let omegas: Vec<String> = spec.omegas.iter().map(|o| fmt_omega(*o)).collect();
        let _ = write!(
            h,
            "<p>Excitation frequencies Omega (rad/s): {}.</p><table class=\"cases\"><caption>Cases of the study</caption><tr><th>method</th><th>eigenmodes</th><th>below (Hz)</th></tr>",
            omegas.join(", ")
        );
        for c in &spec.cases {
            let fmax = c.fmax.map_or("-".into(), |f| format!("{f}"));
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
                c.method.name(),
                c.modes,
                fmax
            );
        }
        h.push_str("</table>");
    }
    h.push_str("<h2>Errors</h2>");
    error_table(&mut h, &result.rows(), sub.dof_map.len());
    if !result.failures.is_empty() {
        h.push_str("<h2>Failed cases</h2><ul class=\"failed\">");
        for f in &result.failures {
            let _ = write!(
                h,
                "<li><b>{}, {}</b>: {}</li>",
                f.method.name(),
                f.fmax.map_or(format!("{} eigenmodes", f.modes), |hz| {
                    format!("the eigenmodes below {hz} Hz")
                }),
                escape(&f.error)
            );
        }
        h.push_str("</ul>");
    }
    h.push_str("<h2>Plots</h2>");
    for p in &plots {
        let _ = write!(
            h,
            "<figure>{}<figcaption>{}</figcaption></figure>",
            p.figure.to_svg(),
            escape(&p.file)
        );
    }
    h.push_str("</body></html>\n");
    Ok(h)
}

/// The study's table: the figures `flexbody study` prints, in the same
/// format (`{:.2e}`).
fn error_table(h: &mut String, rows: &[CaseRow], dofs: usize) {
    let beams = rows.first().is_some_and(|r| r.err_m.is_some());
    let solids = rows.first().is_some_and(|r| r.err_vm.is_some());
    let _ = write!(
        h,
        "<table class=\"errors\"><caption>Reference: the full model, {dofs} DOFs; each error max |reduced - reference| / max |reference|</caption><tr><th>method</th><th>r</th><th>Omega (rad/s)</th><th>err w</th>"
    );
    if beams {
        h.push_str("<th>err M</th><th>err Q</th>");
    }
    h.push_str("<th>err F</th>");
    if solids {
        h.push_str("<th>err vm</th>");
    }
    h.push_str("</tr>");
    for row in rows {
        let mut cells = vec![
            row.method.name().to_string(),
            row.r.to_string(),
            fmt_omega(row.omega),
            format!("{:.2e}", row.err_w),
        ];
        if beams {
            for e in [row.err_m, row.err_q] {
                cells.push(e.map_or("-".into(), |e| format!("{e:.2e}")));
            }
        }
        cells.push(format!("{:.2e}", row.err_force));
        if solids {
            cells.push(row.err_vm.map_or("-".into(), |e| format!("{e:.2e}")));
        }
        h.push_str("<tr>");
        for c in cells {
            let _ = write!(h, "<td>{}</td>", escape(&c));
        }
        h.push_str("</tr>");
    }
    h.push_str("</table>");
}

const STYLE: &str = "body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;margin:2em auto;max-width:1100px;color:#111;padding:0 1em}\
h1{font-size:1.5em}h2{font-size:1.2em;border-bottom:1px solid #999;margin-top:1.6em}\
table{border-collapse:collapse;margin:0.6em 0}th,td{border:1px solid #bbb;padding:0.25em 0.6em}\
table.errors td,table.cases td{text-align:right;font-variant-numeric:tabular-nums}\
table.facts th{text-align:left;background:#f3f3f3}caption{text-align:left;font-size:0.9em;padding:0.3em 0}\
figure{margin:1.2em 0}figure svg{max-width:100%;height:auto}figcaption{font-size:0.85em;color:#444}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_civil_dates_in_utc() {
        assert_eq!(utc_text(0), "1970-01-01 00:00:00 UTC");
        // 2000-02-29 12:34:56 UTC, a leap day: 11016 days after the epoch.
        assert_eq!(
            utc_text(11_016 * 86_400 + 12 * 3600 + 34 * 60 + 56),
            "2000-02-29 12:34:56 UTC"
        );
    }

    #[test]
    fn arguments_are_quoted_only_where_a_shell_needs_it() {
        assert_eq!(
            shell_quoted("examples/side_beam.toml"),
            "examples/side_beam.toml"
        );
        assert_eq!(shell_quoted("my model.toml"), "'my model.toml'");
        assert_eq!(shell_quoted("it's"), r"'it'\''s'");
    }
}
