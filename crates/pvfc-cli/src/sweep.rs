//! `pvfc sweep`: a study's runs in parallel on this machine into its table (`NAME.csv`),
//! resuming where an interrupted sweep stopped, and the same table as an Arrow IPC file
//! (`NAME.arrow`); then its figures.

use pvfc_sim::error::{Result, SimError};
use pvfc_sim::study::runner::{run_study, StudyRow};
use pvfc_sim::study::spec::{StudyController, StudySpec};
use pvfc_sim::study::{arrow, table};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

/// What a sweep did.
#[derive(Debug)]
pub struct SweepOutcome {
    /// The study's spec.
    pub spec: StudySpec,
    /// Every row, by index.
    pub rows: Vec<StudyRow>,
    /// The number of runs this sweep ran (the rest were in the table already).
    pub ran: usize,
    /// The number of rows taken from the table of an earlier, interrupted sweep.
    pub resumed: usize,
    /// The table.
    pub csv: PathBuf,
    /// The table as an Arrow IPC file.
    pub arrow: PathBuf,
    /// The wall time of the runs (s).
    pub seconds: f64,
}

impl SweepOutcome {
    /// The rows whose run failed.
    pub fn failed(&self) -> usize {
        self.rows.iter().filter(|r| r.error.is_some()).count()
    }
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> SimError + '_ {
    move |e| SimError::io(path, e)
}

/// Writes `header` and `rows` to `path` through a temporary file, so that the table is
/// never half written.
fn write_table(path: &Path, header: &[String], rows: &[StudyRow]) -> Result<()> {
    let tmp = path.with_extension("csv.tmp");
    let mut text = table::header_line(header);
    for r in rows {
        text.push_str(&table::row_line(r));
    }
    std::fs::write(&tmp, text).map_err(io(&tmp))?;
    std::fs::rename(&tmp, path).map_err(io(path))
}

/// Runs the study of the file `study` into `out/NAME.csv` on `threads` threads, and writes
/// the whole table as `out/NAME.arrow` once every run asked for is in. Rows already
/// in that table (from an interrupted sweep of the same study) are kept and their runs not
/// run again. `limit` stops after that many new runs (the table then holds a partial study
/// that a later sweep completes). `progress(done, total)` is called after each run.
pub fn sweep(
    study: &Path,
    out: &Path,
    threads: usize,
    limit: Option<usize>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<SweepOutcome> {
    sweep_with(study, None, out, threads, limit, progress)
}

/// [`sweep`] with the study's controller set to `controller` (when given and not the
/// study's own): the same runs with a baseline tracker instead of PVFC (or the reverse),
/// into `out/NAME-CONTROLLER.csv` (`timed`, `speed_scaling`, `pvfc`), so that every
/// controller is measured on the same draws.
pub fn sweep_with(
    study: &Path,
    controller: Option<StudyController>,
    out: &Path,
    threads: usize,
    limit: Option<usize>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<SweepOutcome> {
    let (mut spec, base) = StudySpec::from_file(study)?;
    if let Some(c) = controller.filter(|c| *c != spec.controller) {
        spec.controller = c;
        spec.name = format!("{}-{}", spec.name, c.label());
    }
    let runs = spec.runs(&base)?;
    let metrics = spec.metrics()?;
    let names: Vec<&str> = metrics.iter().map(|m| m.name).collect();
    let header = table::header(&spec.keys(), &names);
    std::fs::create_dir_all(out).map_err(io(out))?;
    let csv = out.join(format!("{}.csv", spec.name));
    let mut done: BTreeMap<usize, StudyRow> = BTreeMap::new();
    if csv.exists() {
        let expected = |i: usize| -> Option<Vec<f64>> {
            Some(runs.get(i)?.parameters.iter().map(|p| p.1).collect())
        };
        for r in table::read(&csv, &header, &expected)? {
            done.insert(r.index, r);
        }
    }
    let resumed = done.len();
    // The table as it stands (a line cut short dropped), then appended to run by run.
    let kept: Vec<StudyRow> = done.values().cloned().collect();
    write_table(&csv, &header, &kept)?;
    let todo: Vec<_> = runs
        .iter()
        .filter(|r| !done.contains_key(&r.index))
        .take(limit.unwrap_or(usize::MAX))
        .cloned()
        .collect();
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .open(&csv)
        .map_err(io(&csv))?;
    let total = runs.len();
    let start = std::time::Instant::now();
    let mut failure: Option<SimError> = None;
    let mut ran = 0;
    run_study(&todo, &metrics, threads, &mut |row| {
        let line = table::row_line(&row);
        if let Err(e) = file.write_all(line.as_bytes()).and_then(|_| file.flush()) {
            failure = Some(SimError::io(&csv, e));
            return false;
        }
        done.insert(row.index, row);
        ran += 1;
        progress(done.len(), total);
        true
    });
    if let Some(e) = failure {
        return Err(e);
    }
    let seconds = start.elapsed().as_secs_f64();
    let rows: Vec<StudyRow> = done.into_values().collect();
    // In index order once every run is in.
    write_table(&csv, &header, &rows)?;
    let arrow = csv.with_extension("arrow");
    arrow::write(&arrow, &spec.keys(), &names, &rows)?;
    Ok(SweepOutcome {
        spec,
        rows,
        ran,
        resumed,
        csv,
        arrow,
        seconds,
    })
}
