//! Scenarios and runs: `pvfc.Scenario`, `SimulationResult`, `simulate`, `simulate_many`,
//! `simulate_timed`, `read_mcap`.

use crate::convert::{dyn_vector, out1, out_column};
use crate::errors::sim_err;
use pvfc_sim::scenario::Scenario as SimScenario;
use pvfc_sim::trace::Trace;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::path::PathBuf;

/// A scenario from its pickled JSON, its relative paths read from `base_dir` (not yet
/// validated).
pub(crate) fn scenario_from_json(json: &str, base_dir: PathBuf) -> PyResult<SimScenario> {
    let mut s: SimScenario = serde_json::from_str(json)
        .map_err(|e| crate::errors::ScenarioError::new_err(format!("pickled scenario: {e}")))?;
    s.base_dir = base_dir;
    Ok(s)
}

/// Raises a `DeprecationWarning` (at the caller's line) for each deprecated form `s` was read
/// in, and gives `s`.
fn warned(py: Python<'_>, s: SimScenario) -> PyResult<Scenario> {
    for d in &s.deprecations {
        let message = std::ffi::CString::new(format!("scenario: {d}")).unwrap_or_default();
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyDeprecationWarning>(),
            &message,
            1,
        )?;
    }
    Ok(Scenario { s })
}

/// Everything one run needs: plant, contour, controller, initial state, duration, rates.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct Scenario {
    pub(crate) s: SimScenario,
}

#[pymethods]
impl Scenario {
    /// Reads a TOML scenario file.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        warned(py, SimScenario::from_file(&path).map_err(sim_err)?)
    }

    /// Parses TOML text.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &str) -> PyResult<Self> {
        let s = SimScenario::from_toml(text, std::path::Path::new("<string>")).map_err(sim_err)?;
        warned(py, s)
    }

    /// Builds a scenario from a dict with the layout of the TOML files (see `to_dict`).
    /// Relative paths in it (a URDF, a CSV of points) are read from `base_dir` (default: the
    /// current directory); `Scenario.from_file(p)` uses `p`'s folder.
    #[staticmethod]
    #[pyo3(signature = (d, base_dir=None))]
    fn from_dict(
        py: Python<'_>,
        d: &Bound<'_, PyDict>,
        base_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
        let mut s: SimScenario = serde_json::from_str(&text)
            .map_err(|e| crate::errors::ScenarioError::new_err(format!("scenario dict: {e}")))?;
        s.base_dir = base_dir.unwrap_or_default();
        s.deprecations = pvfc_sim::scenario::legacy::in_json(&text);
        s.validate()
            .map_err(|e| crate::errors::ScenarioError::new_err(format!("scenario dict: {e}")))?;
        warned(py, s)
    }

    /// A built-in scenario of the paper's section V by name (see `presets()`).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        pvfc_sim::scenario::presets::all()
            .into_iter()
            .find(|s| s.name == name)
            .map(|s| Scenario { s })
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "name: no preset {name:?}; see pvfc.Scenario.presets()"
                ))
            })
    }

    /// The names of the built-in scenarios.
    #[staticmethod]
    fn presets() -> Vec<String> {
        pvfc_sim::scenario::presets::all()
            .into_iter()
            .map(|s| s.name)
            .collect()
    }

    /// The scenario as a dict (edit it and pass it to `from_dict`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.s)
            .map_err(|e| crate::errors::ScenarioError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// Rebuilds a pickled scenario: its JSON, and the folder its relative paths are read
    /// from.
    #[staticmethod]
    fn _from_state(json: &str, base_dir: PathBuf) -> PyResult<Self> {
        let s = scenario_from_json(json, base_dir)?;
        s.validate()
            .map_err(|e| crate::errors::ScenarioError::new_err(format!("pickled scenario: {e}")))?;
        Ok(Scenario { s })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let py = slf.py();
        let s = &slf.get().s;
        let json = serde_json::to_string(s)
            .map_err(|e| crate::errors::ScenarioError::new_err(e.to_string()))?;
        let rebuild = slf.get_type().getattr("_from_state")?;
        let args = (json, s.base_dir.clone()).into_pyobject(py)?;
        pyo3::types::PyTuple::new(py, [rebuild, args.into_any()])
    }

    /// The scenario as TOML text.
    fn to_toml(&self) -> PyResult<String> {
        self.s.to_toml().map_err(sim_err)
    }

    #[getter]
    fn name(&self) -> String {
        self.s.name.clone()
    }

    #[getter]
    fn duration(&self) -> f64 {
        self.s.duration
    }

    /// The least lap time (s) any controller can make on the scenario's plant at its demanded
    /// speed: the time-optimal parameterisation of its contour under the drives' limits
    /// (`[controller.pace]` and torque limits), against the plant's own Coulomb and viscous
    /// friction and model error (`plant.mass_scale`), and gravity on a serial chain. A run's
    /// lap time ÷ this is how near the drives' limit it went.
    fn least_lap(&self, py: Python<'_>) -> PyResult<f64> {
        py.detach(|| self.s.least_lap()).map_err(sim_err)
    }

    fn __repr__(&self) -> String {
        format!("Scenario({:?}, duration={})", self.s.name, self.s.duration)
    }
}

/// The time series of a run, as fresh numpy arrays (sampled at the controller's rate).
#[pyclass(module = "pvfc", frozen)]
pub(crate) struct SimulationResult {
    t: Trace,
    period: f64,
}

/// The run's columns as properties, one per entry of `pvfc_sim::trace_columns!` (the one
/// list of them: the MCAP log writes the same).
macro_rules! trace_getters {
    (
        trace { $($n:ident as $p:ident : $shape:ident $log:ident $doc:literal;)* }
        contact { $($rest:tt)* }
    ) => {
        #[pymethods]
        impl SimulationResult {
            $(
                #[doc = $doc]
                #[getter]
                fn $p<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
                    out_column(py, pvfc_sim::trace::Values::from(&self.t.$n))
                }
            )*
        }
    };
}

pvfc_sim::trace_columns!(trace_getters);

#[pymethods]
impl SimulationResult {
    /// The run's name.
    #[getter]
    fn name(&self) -> String {
        self.t.name.clone()
    }

    /// The contour's period in τ.
    #[getter]
    fn period(&self) -> f64 {
        self.period
    }

    /// Rebuilds a pickled result from its name, period and columns (`crate::pickle`).
    #[staticmethod]
    fn _from_state(
        name: String,
        period: f64,
        columns: Vec<(String, usize, Bound<'_, pyo3::types::PyBytes>)>,
        contact: Option<Vec<(String, usize, Bound<'_, pyo3::types::PyBytes>)>>,
    ) -> PyResult<Self> {
        let owned = |cs: Vec<(String, usize, Bound<'_, pyo3::types::PyBytes>)>| -> Vec<crate::pickle::ColumnState> {
            cs.into_iter()
                .map(|(n, w, b)| (n, w, b.as_bytes().to_vec()))
                .collect()
        };
        let contact = contact.map(owned);
        let t = crate::pickle::from_state(name, &owned(columns), contact.as_deref())
            .map_err(crate::errors::PvfcError::new_err)?;
        Ok(SimulationResult { t, period })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let py = slf.py();
        let me = slf.get();
        let (columns, contact) = crate::pickle::to_state(&me.t);
        // Bytes as Python bytes, not lists of ints.
        let bytes = |cs: Vec<crate::pickle::ColumnState>| -> Vec<(String, usize, Bound<'py, pyo3::types::PyBytes>)> {
            cs.into_iter()
                .map(|(n, w, b)| (n, w, pyo3::types::PyBytes::new(py, &b)))
                .collect()
        };
        let args = (
            me.t.name.clone(),
            me.period,
            bytes(columns),
            contact.map(bytes),
        )
            .into_pyobject(py)?;
        let rebuild = slf.get_type().getattr("_from_state")?;
        pyo3::types::PyTuple::new(py, [rebuild, args.into_any()])
    }

    /// The contact columns of a run with a `[contact]` or `[contact_3d]` world, or None: a
    /// dict of fresh arrays `force` (n, 2 or 3), `normal_force`, `depth`, `torque` (n, dof,
    /// `F_e = Jᵀf`), `tool` (n, 2 or 3), `work_contact` (∫F_eᵀq̇ dt), `work_friction`,
    /// `work_controller` (the add-ons' work), `work_gravity` (−∫g(q)ᵀq̇ dt), `nominal_speed`,
    /// and `audit_residual` (energy − energy[0] − the works).
    #[getter]
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = &self.t.contact else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        for col in pvfc_sim::trace::CONTACT_COLUMNS {
            d.set_item(col.python, out_column(py, (col.get)(c)))?;
        }
        d.set_item("audit_residual", out1(py, c.audit_residual(&self.t.energy)))?;
        Ok(Some(d))
    }

    /// For a run with contact, a dict: `peak_force` (N), `energy_pumped` (J, the most the
    /// arm had put into the contact), `work_contact` (J), `energy_scale` (J), `audit`
    /// (relative), `passivity_margin` and `energy_bound_margin` (J, ≥ 0 when passivity
    /// holds), `last_contact` (s or None). None without contact.
    fn contact_summary<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = pvfc_sim::trace::metrics::contact_summary(&self.t) else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        for (k, v) in [
            ("peak_force", c.peak_force),
            ("energy_pumped", c.energy_pumped),
            ("work_contact", c.work_contact),
            ("energy_scale", c.energy_scale),
            ("audit", c.audit),
            ("passivity_margin", c.passivity_margin),
            ("energy_bound_margin", c.energy_bound_margin),
        ] {
            d.set_item(k, v)?;
        }
        d.set_item("last_contact", c.last_contact)?;
        Ok(Some(d))
    }

    /// The error budget of a run on a Cartesian path (`[contour.cartesian]`), given its
    /// scenario: a dict of `geometry` (the joint contour's own distance to the path, see
    /// `CartesianPath.geometry`), the tool's distance to the path over the steady passes
    /// (every complete pass after the first) as `distance` (3-D), `surface` (in the path's
    /// plane, along the surface it lies on) each a dict `mean`, `p95`, `max` (m), `normal`
    /// (the offset normal to the plane, a dict `mean`, `min`, `max` (m) and the unit
    /// `normal`: in contact, the press-in, not an error), `speed` (m/s along the path),
    /// `tool_speed` (m/s), `when` (s, the largest distance's time), `along` (m, where along
    /// the path) and `window` (s, the times covered). None for another contour or a run
    /// shorter than a pass.
    fn path_budget<'py>(
        &self,
        py: Python<'py>,
        scenario: &Scenario,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        if scenario.s.contour.cartesian().is_none() {
            return Ok(None);
        }
        let robot = scenario.s.robot().map_err(sim_err)?;
        let Some(b) = pvfc_sim::trace::path_budget::path_budget(&scenario.s, &robot, &self.t)
            .map_err(sim_err)?
        else {
            return Ok(None);
        };
        let spread = |s: pvfc_sim::trace::path_budget::Spread| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            d.set_item("mean", s.mean)?;
            d.set_item("p95", s.p95)?;
            d.set_item("max", s.max)?;
            Ok(d)
        };
        let d = PyDict::new(py);
        let geometry = match &b.geometry {
            Some(g) => Some(crate::cartesian::geometry_dict(py, g)?),
            None => None,
        };
        d.set_item("geometry", geometry)?;
        d.set_item("distance", spread(b.spread)?)?;
        d.set_item("surface", b.surface.map(spread).transpose()?)?;
        let normal = match b.normal {
            Some(n) => {
                let nd = PyDict::new(py);
                nd.set_item("mean", n.mean)?;
                nd.set_item("min", n.min)?;
                nd.set_item("max", n.max)?;
                nd.set_item("normal", out1(py, n.normal.as_slice().to_vec()))?;
                Some(nd)
            }
            None => None,
        };
        d.set_item("normal", normal)?;
        d.set_item("speed", b.speed)?;
        d.set_item("tool_speed", b.tool_speed)?;
        d.set_item("when", b.when)?;
        d.set_item("along", b.distance.along)?;
        d.set_item("window", b.window)?;
        Ok(Some(d))
    }

    /// The mean of U over the last complete pass of the contour, or None.
    fn mean_potential_over_pass(&self) -> Option<f64> {
        pvfc_sim::trace::metrics::mean_potential_over_pass(&self.t, self.period)
    }

    /// Writes the run as an MCAP log; given the run's scenario of a URDF arm, with its 3-D
    /// scene for Foxglove (link frames, the arm, the desired tool path); `rate` (Hz) thins
    /// the plot channels (default: every sample).
    #[pyo3(signature = (path, scenario=None, rate=None))]
    fn write_mcap(
        &self,
        path: PathBuf,
        scenario: Option<&Scenario>,
        rate: Option<f64>,
    ) -> PyResult<()> {
        let scene = match scenario {
            Some(s) => pvfc_sim::log::scene::Scene::of_run(&s.s, &self.t).map_err(sim_err)?,
            None => None,
        };
        let options = pvfc_sim::log::LogOptions {
            scene: scene.as_ref(),
            rate,
        };
        pvfc_sim::log::write_mcap_with(&self.t, &options, &path).map_err(sim_err)
    }

    fn __len__(&self) -> usize {
        self.t.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "SimulationResult({:?}, {} samples)",
            self.t.name,
            self.t.len()
        )
    }
}

/// Runs a scenario (the GIL is released while it runs).
#[pyfunction]
pub(crate) fn simulate(py: Python<'_>, scenario: &Scenario) -> PyResult<SimulationResult> {
    let s = scenario.s.clone();
    let t = py
        .detach(move || pvfc_sim::run::simulate(&s, &mut |_| {}))
        .map_err(sim_err)?;
    Ok(SimulationResult {
        t,
        period: scenario.s.period(),
    })
}

/// Runs many scenarios in parallel in Rust (rayon), with the GIL released; the results are
/// in the order of the scenarios.
#[pyfunction]
#[pyo3(signature = (scenarios, threads=None))]
pub(crate) fn simulate_many(
    py: Python<'_>,
    scenarios: Vec<Scenario>,
    threads: Option<usize>,
) -> PyResult<Vec<SimulationResult>> {
    let ss: Vec<SimScenario> = scenarios.into_iter().map(|s| s.s).collect();
    let periods: Vec<f64> = ss.iter().map(|s| s.period()).collect();
    let run = move || -> Vec<pvfc_sim::Result<Trace>> {
        ss.par_iter()
            .map(|s| pvfc_sim::run::simulate(s, &mut |_| {}))
            .collect()
    };
    let traces = py.detach(move || match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map(|p| p.install(run))
            .map_err(|e| e.to_string()),
        None => Ok(run()),
    });
    let traces = traces.map_err(crate::errors::PvfcError::new_err)?;
    traces
        .into_iter()
        .zip(periods)
        .map(|(t, period)| {
            Ok(SimulationResult {
                t: t.map_err(sim_err)?,
                period,
            })
        })
        .collect()
}

/// The timed-trajectory baseline of a scenario (computed torque + PD) at a τ rate; with
/// `torque_limit` (one per joint), its command is clamped as a drive saturates.
#[pyfunction]
#[pyo3(signature = (scenario, kp, kd, tau_rate, torque_limit=None))]
pub(crate) fn simulate_timed(
    py: Python<'_>,
    scenario: &Scenario,
    kp: &Bound<'_, PyAny>,
    kd: &Bound<'_, PyAny>,
    tau_rate: f64,
    torque_limit: Option<&Bound<'_, PyAny>>,
) -> PyResult<SimulationResult> {
    let n = scenario.s.dof().map_err(sim_err)?;
    let b = pvfc_sim::scenario::BaselineSpec {
        kp: dyn_vector(kp, "kp", n)?,
        kd: dyn_vector(kd, "kd", n)?,
        tau_rate: Some(tau_rate),
        torque_limit: match torque_limit {
            Some(l) => dyn_vector(l, "torque_limit", n)?,
            None => Vec::new(),
        },
        speed_scaling: None,
    };
    let s = scenario.s.clone();
    let t = py
        .detach(move || pvfc_sim::run::simulate_timed(&s, &b, tau_rate, &mut |_| {}))
        .map_err(sim_err)?;
    Ok(SimulationResult {
        t,
        period: scenario.s.period(),
    })
}

/// Reads an MCAP log; returns a list of (topic, log_time_ns, message dict).
#[pyfunction]
pub(crate) fn read_mcap(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<Vec<(String, u64, Bound<'_, PyAny>)>> {
    let msgs = pvfc_sim::log::read_mcap(&path).map_err(sim_err)?;
    let json = py.import("json")?;
    msgs.into_iter()
        .map(|m| {
            Ok((
                m.topic,
                m.log_time,
                json.call_method1("loads", (m.data.to_string(),))?,
            ))
        })
        .collect()
}
