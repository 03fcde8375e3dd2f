//! Studies from Python: `pvfc.Study` (a spec and its base scenario, its runs expanded and
//! checked once), whose `run` runs any of its runs in parallel with the GIL released. It
//! pickles (its spec as TOML, its base as JSON), so `pvfc.sweep` can ship it to Dask workers.

use crate::errors::sim_err;
use crate::runs::Scenario;
use pvfc_sim::scenario::Scenario as SimScenario;
use pvfc_sim::study::metrics::Metric;
use pvfc_sim::study::runner::{run_study, StudyRow};
use pvfc_sim::study::spec::{StudyRun, StudySpec};
use pvfc_sim::study::table;
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::path::{Path, PathBuf};

/// A study: a base scenario, axes over its keys, the metrics to keep; its runs expanded and
/// validated when it is built.
#[pyclass(module = "pvfc", frozen)]
pub(crate) struct Study {
    spec: StudySpec,
    base: SimScenario,
    runs: Vec<StudyRun>,
    metrics: Vec<&'static Metric>,
}

impl Study {
    /// Run `index`, or an `IndexError` naming the argument.
    fn get(&self, index: usize, argument: &str) -> PyResult<&StudyRun> {
        self.runs.get(index).ok_or_else(|| {
            PyIndexError::new_err(format!("{argument}: {index}, of {} runs", self.runs.len()))
        })
    }

    fn build(spec: StudySpec, base: SimScenario) -> PyResult<Self> {
        let runs = spec.runs(&base).map_err(sim_err)?;
        let metrics = spec.metrics().map_err(sim_err)?;
        Ok(Study {
            spec,
            base,
            runs,
            metrics,
        })
    }
}

/// A row as the tuple `(index, parameters, metrics, error)`.
type RowTuple = (usize, Vec<f64>, Vec<Option<f64>>, Option<String>);

fn tuple(r: StudyRow) -> RowTuple {
    (r.index, r.parameters, r.metrics, r.error)
}

#[pymethods]
impl Study {
    /// Reads a study's TOML file; its `base` scenario is relative to it.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let (spec, base) = StudySpec::from_file(&path).map_err(sim_err)?;
        Study::build(spec, base)
    }

    /// Parses a study's TOML text over the scenario `base` (the text's `base` key, if any,
    /// is not read).
    #[staticmethod]
    fn from_toml(text: &str, base: &Scenario) -> PyResult<Self> {
        let spec = StudySpec::from_toml(text, Path::new("<string>")).map_err(sim_err)?;
        Study::build(spec, base.s.clone())
    }

    /// Rebuilds a pickled study: its spec as TOML, its base scenario as JSON, the folder
    /// the base's relative paths are read from.
    #[staticmethod]
    fn _from_state(spec: &str, base: &str, base_dir: PathBuf) -> PyResult<Self> {
        let spec = StudySpec::from_toml(spec, Path::new("<pickle>")).map_err(sim_err)?;
        // Validated with every run by `build`.
        Study::build(spec, crate::runs::scenario_from_json(base, base_dir)?)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let me = slf.get();
        let spec = me.spec.to_toml().map_err(sim_err)?;
        let base = serde_json::to_string(&me.base)
            .map_err(|e| crate::errors::ScenarioError::new_err(e.to_string()))?;
        let rebuild = slf.get_type().getattr("_from_state")?;
        let args = (spec, base, me.base.base_dir.clone()).into_pyobject(py)?;
        PyTuple::new(py, [rebuild, args.into_any()])
    }

    /// The study's name.
    #[getter]
    fn name(&self) -> String {
        self.spec.name.clone()
    }

    /// The axes' keys, in order.
    #[getter]
    fn keys(&self) -> Vec<String> {
        self.spec.keys()
    }

    /// The names of the metrics it keeps, in order.
    #[getter]
    fn metrics(&self) -> Vec<&'static str> {
        self.metrics.iter().map(|m| m.name).collect()
    }

    /// The columns of its table: `run`, the keys, the metrics, `error`.
    #[getter]
    fn columns(&self) -> Vec<String> {
        table::header(&self.spec.keys(), &self.metrics())
    }

    /// The base scenario.
    #[getter]
    fn base(&self) -> Scenario {
        Scenario {
            s: self.base.clone(),
        }
    }

    /// The values of the axes of run `index`.
    fn parameters(&self, index: usize) -> PyResult<Vec<f64>> {
        Ok(self
            .get(index, "index")?
            .parameters
            .iter()
            .map(|p| p.1)
            .collect())
    }

    /// The scenario of run `index`.
    fn scenario(&self, index: usize) -> PyResult<Scenario> {
        Ok(Scenario {
            s: self.get(index, "index")?.scenario.clone(),
        })
    }

    /// Runs the runs `indices` (all when `None`) on `threads` threads (default: every core),
    /// with the GIL released; returns one `(index, parameters, metrics, error)` per run, by
    /// index. A failed run is a row with its error (and `None` metrics), never an exception.
    #[pyo3(signature = (indices=None, threads=None))]
    fn run(
        &self,
        py: Python<'_>,
        indices: Option<Vec<usize>>,
        threads: Option<usize>,
    ) -> PyResult<Vec<RowTuple>> {
        let todo: Vec<StudyRun> = match indices {
            None => self.runs.clone(),
            Some(ix) => ix
                .iter()
                .map(|&i| {
                    self.runs.get(i).cloned().ok_or_else(|| {
                        PyIndexError::new_err(format!("indices: {i}, of {} runs", self.runs.len()))
                    })
                })
                .collect::<PyResult<_>>()?,
        };
        let threads = threads.unwrap_or_else(pvfc_sim::study::runner::default_threads);
        let metrics = &self.metrics;
        let mut rows = py.detach(move || {
            let mut rows = Vec::with_capacity(todo.len());
            run_study(&todo, metrics, threads, &mut |r| {
                rows.push(r);
                true
            });
            rows
        });
        rows.sort_by_key(|r| r.index);
        Ok(rows.into_iter().map(tuple).collect())
    }

    fn __len__(&self) -> usize {
        self.runs.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Study({:?}, {} runs over {})",
            self.spec.name,
            self.runs.len(),
            self.spec.keys().join(", ")
        )
    }
}
