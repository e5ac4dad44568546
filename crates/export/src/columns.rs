//! Columns of numbers as CSV (time histories, transfer functions): the
//! checked writer every table output goes through. A value that is not
//! finite is refused before anything is written, naming the file, the
//! column, the row and its abscissa, so no output holds NaN or inf.

use crate::{write_atomically, ExportError};
use std::path::Path;

/// Writes `x` (titled `x_name`, e.g. `time (s)`, `f (Hz)`) and one column
/// per `(name, values)` as CSV, atomically; every column as long as `x`
/// and every value finite, else nothing is written.
pub fn write_columns(
    path: &Path,
    x_name: &str,
    x: &[f64],
    columns: &[(String, Vec<f64>)],
) -> Result<(), ExportError> {
    check(x_name, x, columns).map_err(|message| ExportError::Format {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomically(path, |out| {
        let header: Vec<String> = std::iter::once(x_name.to_string())
            .chain(columns.iter().map(|(n, _)| format!("\"{n}\"")))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for (k, t) in x.iter().enumerate() {
            let row: Vec<String> = std::iter::once(format!("{t:.9e}"))
                .chain(columns.iter().map(|(_, v)| format!("{:.9e}", v[k])))
                .collect();
            writeln!(out, "{}", row.join(","))?;
        }
        Ok(())
    })
}

/// The first column of the wrong length or value that is not finite.
fn check(x_name: &str, x: &[f64], columns: &[(String, Vec<f64>)]) -> Result<(), String> {
    if let Some((row, v)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(format!(
            "refusing to write {v} in column '{x_name}', row {}",
            row + 1
        ));
    }
    for (name, values) in columns {
        if values.len() != x.len() {
            return Err(format!(
                "column '{name}' has {} values for {} rows",
                values.len(),
                x.len()
            ));
        }
        if let Some((row, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(format!(
                "refusing to write {v} in column '{name}', row {} ({x_name} = {:e}): \
                 the computation did not give a finite value",
                row + 1,
                x[row]
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_finite_value_is_refused_naming_column_and_row_and_nothing_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("histories.csv");
        let good = vec![("u (m)".to_string(), vec![0.0, 1e-3, 2e-3])];
        write_columns(&path, "time (s)", &[0.0, 0.1, 0.2], &good).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 4);
        assert!(text.starts_with("time (s),\"u (m)\"\n0.000000000e0,0.000000000e0\n"));

        let bad = vec![
            ("u (m)".to_string(), vec![0.0, 1e-3, 2e-3]),
            ("F (N)".to_string(), vec![0.0, f64::NAN, f64::INFINITY]),
        ];
        let e = write_columns(&path, "time (s)", &[0.0, 0.1, 0.2], &bad).unwrap_err();
        assert!(
            e.to_string()
                .ends_with("histories.csv: refusing to write NaN in column 'F (N)', row 2 (time (s) = 1e-1): the computation did not give a finite value"),
            "{e}"
        );
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            text,
            "the old file stays"
        );
        let e = write_columns(&path, "f (Hz)", &[1.0, f64::NAN, 3.0], &good).unwrap_err();
        assert!(
            e.to_string().contains("NaN in column 'f (Hz)', row 2"),
            "{e}"
        );
        let e = write_columns(&path, "f (Hz)", &[1.0], &good).unwrap_err();
        assert!(e.to_string().contains("has 3 values for 1 rows"), "{e}");
    }
}
