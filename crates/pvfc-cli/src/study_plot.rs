//! A study's figures, one per metric: lines against the axis of a one-axis grid, a heat map
//! over a two-axis grid, a histogram over a random study's runs.

use crate::canvas::{figure, heat_map, histogram, panel, Series, Style};
use pvfc_sim::error::{Result, SimError};
use pvfc_sim::study::runner::StudyRow;
use pvfc_sim::study::spec::StudySpec;
use std::path::{Path, PathBuf};

/// The distinct values of column `k` of the rows' parameters, in the order they first come.
fn ticks(rows: &[StudyRow], k: usize) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for r in rows {
        let v = r.parameters[k];
        if !out.iter().any(|x| x.to_bits() == v.to_bits()) {
            out.push(v);
        }
    }
    out
}

/// Draws the figures of a study's `rows` into `dir` (`NAME_METRIC.png` per metric that has
/// a value); returns the files. A grid of three axes or more has no figure (its table has
/// every number).
pub fn study_figures(spec: &StudySpec, rows: &[StudyRow], dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| SimError::io(dir, e))?;
    let metrics = spec.metrics()?;
    let keys = spec.keys();
    let random = spec.axes.iter().any(|a| a.draw.is_some());
    let mut files = Vec::new();
    for (m, metric) in metrics.iter().enumerate() {
        let value = |r: &StudyRow| r.metrics.get(m).copied().flatten();
        if !rows.iter().any(|r| value(r).is_some()) {
            continue;
        }
        let label = if metric.unit.is_empty() {
            metric.name.to_string()
        } else {
            format!("{} ({})", metric.name, metric.unit)
        };
        let title = format!("{}: {}", spec.name, metric.name);
        let path = dir.join(format!("{}_{}.png", spec.name, metric.name));
        if random {
            let samples: Vec<f64> = rows.iter().filter_map(value).collect();
            let bins = ((samples.len() as f64).sqrt().ceil() as usize).clamp(5, 40);
            figure(&path, 1, |_, a| {
                histogram(a, &path, &title, &label, &samples, bins)
            })?;
        } else if keys.len() == 1 {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter_map(|r| Some((r.parameters[0], value(r)?)))
                .collect();
            let series = [Series {
                label: metric.name.into(),
                points,
                style: Style::Line,
            }];
            figure(&path, 1, |_, a| {
                panel(a, &path, &title, &keys[0], &label, &series, false)
            })?;
        } else if keys.len() == 2 {
            let (xs, ys) = (ticks(rows, 0), ticks(rows, 1));
            let mut grid = vec![vec![None; ys.len()]; xs.len()];
            for r in rows {
                let i = xs
                    .iter()
                    .position(|x| x.to_bits() == r.parameters[0].to_bits());
                let j = ys
                    .iter()
                    .position(|y| y.to_bits() == r.parameters[1].to_bits());
                if let (Some(i), Some(j)) = (i, j) {
                    grid[i][j] = value(r);
                }
            }
            figure(&path, 1, |_, a| {
                heat_map(a, &path, &title, &keys[0], &keys[1], &xs, &ys, &grid)
            })?;
        } else {
            continue;
        }
        files.push(path);
    }
    Ok(files)
}
