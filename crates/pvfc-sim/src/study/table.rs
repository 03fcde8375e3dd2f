//! A study's table as CSV: one row per run (`run`, the axes' values, the metrics, `error`),
//! numbers written so that they read back bit for bit, an absent metric an empty cell. The
//! file is appended to a row at a time as runs finish, so that an interrupted study resumes:
//! [`read`] gives back the rows already written (a last line cut short is dropped).

use crate::error::{Result, SimError};
use crate::study::runner::StudyRow;
use std::path::Path;

/// The table's header: `run`, the axes' keys, the metrics' names, `error`.
pub fn header(keys: &[String], metrics: &[&str]) -> Vec<String> {
    let mut h = vec!["run".to_string()];
    h.extend(keys.iter().cloned());
    h.extend(metrics.iter().map(|m| m.to_string()));
    h.push("error".into());
    h
}

/// A CSV field: quoted if it holds a comma, a quote or a line break (quotes doubled).
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The header as one CSV line (with its line break).
pub fn header_line(header: &[String]) -> String {
    let cells: Vec<String> = header.iter().map(|h| field(h)).collect();
    format!("{}\n", cells.join(","))
}

/// A row as one CSV line (with its line break): numbers in Rust's shortest form that reads
/// back to the same `f64`, an error's line breaks as spaces.
pub fn row_line(row: &StudyRow) -> String {
    let mut cells = vec![row.index.to_string()];
    cells.extend(row.parameters.iter().map(|v| format!("{v:?}")));
    cells.extend(
        row.metrics
            .iter()
            .map(|m| m.map(|v| format!("{v:?}")).unwrap_or_default()),
    );
    cells.push(field(
        &row.error
            .as_deref()
            .unwrap_or("")
            .replace(['\n', '\r'], " "),
    ));
    format!("{}\n", cells.join(","))
}

/// Splits one CSV line into its fields (quoted fields unquoted).
fn split(line: &str) -> Option<Vec<String>> {
    let mut out = Vec::new();
    let mut cell = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cell.push('"');
            }
            (true, '"') => quoted = false,
            (false, '"') if cell.is_empty() => quoted = true,
            (false, ',') => out.push(std::mem::take(&mut cell)),
            (_, c) => cell.push(c),
        }
    }
    if quoted {
        return None;
    }
    out.push(cell);
    Some(out)
}

/// The rows of a study's table at `path` written by [`header_line`] and [`row_line`]; the
/// header must be `header` (else the file is another study's: an error naming it). A last
/// line without its line break (a run cut short while writing) is dropped; so is a row whose
/// parameters are not `expected(index)` (the run's parameters today, bit for bit; `None` for
/// an index the study no longer has), which a changed study runs again.
pub fn read(
    path: &Path,
    header: &[String],
    expected: &dyn Fn(usize) -> Option<Vec<f64>>,
) -> Result<Vec<StudyRow>> {
    let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
    let bad = |message: String| SimError::Setting(format!("{}: {message}", path.display()));
    let mut lines = text.split_inclusive('\n');
    if lines.next().unwrap_or("") != header_line(header) {
        return Err(bad(format!(
            "its columns are not this study's ({}); write to another directory or remove it",
            header.join(",")
        )));
    }
    let mut out = Vec::new();
    for (k, line) in lines.enumerate() {
        let Some(line) = line.strip_suffix('\n') else {
            break;
        };
        let at = |m: String| bad(format!("line {}: {m}", k + 2));
        let cells = split(line)
            .filter(|c| c.len() == header.len())
            .ok_or_else(|| at(format!("not a row of {} cells", header.len())))?;
        let number = |s: &String| -> Result<Option<f64>> {
            if s.is_empty() {
                return Ok(None);
            }
            s.parse::<f64>()
                .map(Some)
                .map_err(|_| at(format!("`{s}` is not a number")))
        };
        let index: usize = cells[0]
            .parse()
            .map_err(|_| at(format!("`{}` is not a run index", cells[0])))?;
        let Some(parameters) = expected(index) else {
            continue;
        };
        let (axes, rest) = cells[1..].split_at(parameters.len().min(cells.len() - 2));
        let (metrics, error) = rest.split_at(rest.len() - 1);
        let given = axes.iter().map(number).collect::<Result<Vec<_>>>()?;
        let same = given.len() == parameters.len()
            && given
                .iter()
                .zip(&parameters)
                .all(|(g, p)| g.map(f64::to_bits) == Some(p.to_bits()));
        if !same {
            continue;
        }
        out.push(StudyRow {
            index,
            parameters,
            metrics: metrics.iter().map(number).collect::<Result<Vec<_>>>()?,
            error: Some(error[0].clone()).filter(|e| !e.is_empty()),
        });
    }
    Ok(out)
}
