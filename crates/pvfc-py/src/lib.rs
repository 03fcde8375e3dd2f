//! Python bindings of pvfc: the native module `pvfc._pvfc` of the `pvfc` wheel.

#![forbid(unsafe_code)]
#![allow(missing_docs)] // The Python API is documented in the `.pyi` stubs and docstrings.

mod arm;
mod convert;
mod errors;
mod robots;

use convert::{matrix, out1, out_matrix, out_rows, out_series, vector};
use errors::{core_err, sim_err};
use nalgebra::{Vector2, Vector3};
use numpy::{PyArray1, PyArray2};
use pvfc_core::prelude::*;
use pvfc_sim::paper::PaperController;
use pvfc_sim::scenario::Scenario as SimScenario;
use pvfc_sim::simulate::Trace;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::path::PathBuf;

// ---------------------------------------------------------------- robots

/// A two-link SCARA in the horizontal plane (closed-form M and C).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct Scara {
    arm: pvfc_core::mechanics::Scara<f64>,
}

#[pymethods]
impl Scara {
    #[new]
    #[pyo3(signature = (*, m1, m2, l1, l2, lc1, lc2, i1, i2))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        m1: f64,
        m2: f64,
        l1: f64,
        l2: f64,
        lc1: f64,
        lc2: f64,
        i1: f64,
        i2: f64,
    ) -> PyResult<Self> {
        let p = ScaraParameters {
            m1,
            m2,
            l1,
            l2,
            lc1,
            lc2,
            i1,
            i2,
        };
        Ok(Scara {
            arm: pvfc_core::mechanics::Scara::new(p).map_err(core_err)?,
        })
    }

    /// The CICESE Pelican arm (control-law.md §1).
    #[staticmethod]
    fn pelican() -> Self {
        Scara {
            arm: pvfc_core::mechanics::Scara::pelican(),
        }
    }

    /// The direct-drive arm of the experiments (`models/scara.urdf`).
    #[staticmethod]
    fn direct_drive() -> PyResult<Self> {
        Ok(Scara {
            arm: pvfc_core::mechanics::Scara::new(pvfc_sim::scenario::direct_drive_arm())
                .map_err(core_err)?,
        })
    }

    /// Reads the arm from a URDF file.
    #[staticmethod]
    fn from_urdf(path: PathBuf) -> PyResult<Self> {
        let p = pvfc_sim::urdf::scara_from_urdf(&path).map_err(sim_err)?;
        Ok(Scara {
            arm: pvfc_core::mechanics::Scara::new(p).map_err(core_err)?,
        })
    }

    /// The physical parameters, as a dict.
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self.arm.parameters();
        let d = PyDict::new(py);
        for (k, v) in [
            ("m1", p.m1),
            ("m2", p.m2),
            ("l1", p.l1),
            ("l2", p.l2),
            ("lc1", p.lc1),
            ("lc2", p.lc2),
            ("i1", p.i1),
            ("i2", p.i2),
        ] {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// The inertia matrix M(q), shape (2, 2).
    fn inertia<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = Torus::new(Vector2::from(vector::<2>(q, "q")?));
        Ok(out_matrix(py, &self.arm.inertia(&q)))
    }

    /// The Coriolis matrix C(q, q̇), shape (2, 2).
    fn coriolis<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = Torus::new(Vector2::from(vector::<2>(q, "q")?));
        let v = Vector2::from(vector::<2>(qdot, "qdot")?);
        Ok(out_matrix(py, &self.arm.coriolis(&q, &v)))
    }

    /// ½ q̇ᵀ M(q) q̇.
    fn kinetic_energy(&self, q: &Bound<'_, PyAny>, qdot: &Bound<'_, PyAny>) -> PyResult<f64> {
        let q = Torus::new(Vector2::from(vector::<2>(q, "q")?));
        let v = Vector2::from(vector::<2>(qdot, "qdot")?);
        Ok(self.arm.kinetic_energy(&q, &v))
    }

    fn __repr__(&self) -> String {
        let p = self.arm.parameters();
        format!(
            "Scara(m1={}, m2={}, l1={}, l2={}, lc1={}, lc2={}, i1={}, i2={})",
            p.m1, p.m2, p.l1, p.l2, p.lc1, p.lc2, p.i1, p.i2
        )
    }
}

// ---------------------------------------------------------------- contours

/// `(x_d, dx_d/dτ, d²x_d/dτ²)` as three arrays.
type Sample3<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

fn sample2<'py>(py: Python<'py>, s: ContourSample<f64, Torus<f64, 2>, 2>) -> Sample3<'py> {
    (
        out1(py, s.point.angles().iter().cloned().collect()),
        out1(py, s.velocity.iter().cloned().collect()),
        out1(py, s.acceleration.iter().cloned().collect()),
    )
}

/// A Lissajous curve in joint space, x_i = c_i + a_i sin(2πτ/T_i + φ_i).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct Lissajous {
    c: pvfc_core::contour::Lissajous<f64, 2>,
}

#[pymethods]
impl Lissajous {
    #[new]
    #[pyo3(signature = (amplitude, periods, phase=None, offset=None, period=None))]
    fn new(
        amplitude: &Bound<'_, PyAny>,
        periods: &Bound<'_, PyAny>,
        phase: Option<&Bound<'_, PyAny>>,
        offset: Option<&Bound<'_, PyAny>>,
        period: Option<f64>,
    ) -> PyResult<Self> {
        let z = [0.0; 2];
        let phase = phase
            .map(|p| vector::<2>(p, "phase"))
            .transpose()?
            .unwrap_or(z);
        let offset = offset
            .map(|p| vector::<2>(p, "offset"))
            .transpose()?
            .unwrap_or(z);
        let mut c = pvfc_core::contour::Lissajous::new(
            Vector2::from(vector::<2>(amplitude, "amplitude")?),
            Vector2::from(vector::<2>(periods, "periods")?),
            Vector2::from(phase),
            Vector2::from(offset),
        )
        .map_err(core_err)?;
        if let Some(p) = period {
            c = c.with_period(p).map_err(core_err)?;
        }
        Ok(Lissajous { c })
    }

    /// The paper's contour, (sin(2πτ/3), 1.5 cos(2πτ/6)), period 6.
    #[staticmethod]
    fn paper() -> Self {
        Lissajous {
            c: pvfc_core::contour::Lissajous::paper(),
        }
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (2,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample2(py, self.c.sample(tau))
    }

    /// The common period, if declared.
    #[getter]
    fn period(&self) -> Option<f64> {
        <pvfc_core::contour::Lissajous<f64, 2> as Contour<f64, Torus<f64, 2>, 2>>::period(&self.c)
    }
}

/// An ellipse (or circle) in joint space, x = c + u cos(2πτ/T) + w sin(2πτ/T).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct Ellipse {
    c: pvfc_core::contour::Ellipse<f64, 2>,
}

#[pymethods]
impl Ellipse {
    #[new]
    fn new(
        center: &Bound<'_, PyAny>,
        u: &Bound<'_, PyAny>,
        w: &Bound<'_, PyAny>,
        period: f64,
    ) -> PyResult<Self> {
        Ok(Ellipse {
            c: pvfc_core::contour::Ellipse::new(
                Vector2::from(vector::<2>(center, "center")?),
                Vector2::from(vector::<2>(u, "u")?),
                Vector2::from(vector::<2>(w, "w")?),
                period,
            )
            .map_err(core_err)?,
        })
    }

    /// A circle of the given radius.
    #[staticmethod]
    fn circle(center: &Bound<'_, PyAny>, radius: f64, period: f64) -> PyResult<Self> {
        Ok(Ellipse {
            c: pvfc_core::contour::Ellipse::circle(
                Vector2::from(vector::<2>(center, "center")?),
                radius,
                period,
            )
            .map_err(core_err)?,
        })
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (2,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample2(py, self.c.sample(tau))
    }
}

macro_rules! waypoint_curves {
    ($($k:literal => $var:ident),*) => {
        #[derive(Clone)]
        enum AnySpline { $($var(PeriodicBSpline<f64, Torus<f64, 2>, 2, $k>)),* }
        fn make_spline(points: &[[f64; 2]], spacing: f64) -> PyResult<AnySpline> {
            let pts: Vec<Torus<f64, 2>> = points.iter().map(|p| Torus::new(Vector2::from(*p))).collect();
            match pts.len() {
                $($k => {
                    let arr: [Torus<f64, 2>; $k] = core::array::from_fn(|i| pts[i]);
                    Ok(AnySpline::$var(PeriodicBSpline::through(arr, spacing).map_err(core_err)?))
                })*
                n => Err(PyValueError::new_err(format!("waypoints: expected 3 to 16 points, got {n}"))),
            }
        }
        impl AnySpline {
            fn sample(&self, tau: f64) -> ContourSample<f64, Torus<f64, 2>, 2> {
                match self { $(AnySpline::$var(s) => s.sample(tau)),* }
            }
        }
    };
}
waypoint_curves!(3 => K3, 4 => K4, 5 => K5, 6 => K6, 7 => K7, 8 => K8, 9 => K9, 10 => K10, 11 => K11, 12 => K12, 13 => K13, 14 => K14, 15 => K15, 16 => K16);

/// A smooth (C²) closed curve through 3 to 16 waypoints in joint space, one every `spacing`
/// units of τ (periodic cubic spline).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct WaypointCurve {
    s: AnySpline,
    period: f64,
}

#[pymethods]
impl WaypointCurve {
    #[new]
    fn new(waypoints: &Bound<'_, PyAny>, spacing: f64) -> PyResult<Self> {
        let n = waypoints.len().unwrap_or(0);
        let flat = convert::array(waypoints, "waypoints", &[n, 2])?;
        let pts: Vec<[f64; 2]> = flat.chunks(2).map(|c| [c[0], c[1]]).collect();
        Ok(WaypointCurve {
            s: make_spline(&pts, spacing)?,
            period: spacing * n as f64,
        })
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (2,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample2(py, self.s.sample(tau))
    }

    #[getter]
    fn period(&self) -> f64 {
        self.period
    }
}

/// A rotation at constant body rate on SO(3): x_d(τ) = R₀ exp(τ ω̂).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct So3ConstantRate {
    c: ConstantRate<f64, So3<f64>, 3>,
}

#[pymethods]
impl So3ConstantRate {
    #[new]
    fn new(start: &Bound<'_, PyAny>, rate: &Bound<'_, PyAny>) -> PyResult<Self> {
        let r0 = So3::from_matrix(matrix::<3, 3>(start, "start")?, 1e-6).map_err(core_err)?;
        Ok(So3ConstantRate {
            c: ConstantRate::new(r0, Vector3::from(vector::<3>(rate, "rate")?))
                .map_err(core_err)?,
        })
    }

    /// (R(τ) of shape (3, 3), body rate ω (3,), dω/dτ (3,)).
    #[allow(clippy::type_complexity)]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        tau: f64,
    ) -> (
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
    ) {
        let s = self.c.sample(tau);
        (
            out_matrix(py, s.point.matrix()),
            out1(py, s.velocity.iter().cloned().collect()),
            out1(py, s.acceleration.iter().cloned().collect()),
        )
    }
}

// ---------------------------------------------------------------- navigation functions

/// U(E) = k Σ h_i (1 − cos E_i) on the torus; k = ½ (eq. 17, default) or 1 (eq. 28).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct TorusNavigation {
    n: pvfc_core::navigation::TorusNavigation<f64, 2>,
}

#[pymethods]
impl TorusNavigation {
    #[new]
    #[pyo3(signature = (h, convention="eq17"))]
    fn new(h: &Bound<'_, PyAny>, convention: &str) -> PyResult<Self> {
        let conv = match convention {
            "eq17" => TorusConvention::HalfSum,
            "eq28" => TorusConvention::Sum,
            other => {
                return Err(PyValueError::new_err(format!(
                    "convention: expected 'eq17' or 'eq28', got {other:?}"
                )))
            }
        };
        Ok(TorusNavigation {
            n: pvfc_core::navigation::TorusNavigation::new(
                Vector2::from(vector::<2>(h, "h")?),
                conv,
            )
            .map_err(core_err)?,
        })
    }

    /// U(E) for joint-angle errors E, shape (2,).
    fn value(&self, e: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self
            .n
            .value(&Torus::new(Vector2::from(vector::<2>(e, "e")?))))
    }

    /// grad U(E), shape (2,).
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let g = self
            .n
            .gradient(&Torus::new(Vector2::from(vector::<2>(e, "e")?)));
        Ok(out1(py, g.iter().cloned().collect()))
    }
}

/// U(E) = tr(P(I − E))/π' on SO(3) (eq. 26); P is validated.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct So3Navigation {
    n: pvfc_core::navigation::So3Navigation<f64>,
}

#[pymethods]
impl So3Navigation {
    #[new]
    fn new(p: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(So3Navigation {
            n: pvfc_core::navigation::So3Navigation::new(matrix::<3, 3>(p, "p")?)
                .map_err(core_err)?,
        })
    }

    /// U(E) for a rotation matrix E, shape (3, 3).
    fn value(&self, e: &Bound<'_, PyAny>) -> PyResult<f64> {
        let e = So3::from_matrix(matrix::<3, 3>(e, "e")?, 1e-6).map_err(core_err)?;
        Ok(self.n.value(&e))
    }

    /// grad U(E) in body coordinates, shape (3,).
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        e: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let e = So3::from_matrix(matrix::<3, 3>(e, "e")?, 1e-6).map_err(core_err)?;
        Ok(out1(py, self.n.gradient(&e).iter().cloned().collect()))
    }

    /// The eigenvalues π₁ < π₂ < π₃ of P.
    #[getter]
    fn eigenvalues(&self) -> (f64, f64, f64) {
        let e = self.n.eigenvalues();
        (e[0], e[1], e[2])
    }
}

// ---------------------------------------------------------------- scenarios and runs

/// Everything one run needs: plant, contour, controller, initial state, duration, rates.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
struct Scenario {
    s: SimScenario,
}

#[pymethods]
impl Scenario {
    /// Reads a TOML scenario file.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        Ok(Scenario {
            s: SimScenario::from_file(&path).map_err(sim_err)?,
        })
    }

    /// Parses TOML text.
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Self> {
        Ok(Scenario {
            s: SimScenario::from_toml(text, std::path::Path::new("<string>")).map_err(sim_err)?,
        })
    }

    /// Builds a scenario from a dict with the layout of the TOML files (see `to_dict`).
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>) -> PyResult<Self> {
        let text: String = py.import("json")?.call_method1("dumps", (d,))?.extract()?;
        let mut s: SimScenario = serde_json::from_str(&text)
            .map_err(|e| errors::ScenarioError::new_err(format!("scenario dict: {e}")))?;
        s.base_dir = PathBuf::new();
        s.validate()
            .map_err(|e| errors::ScenarioError::new_err(format!("scenario dict: {e}")))?;
        Ok(Scenario { s })
    }

    /// A built-in scenario of the paper's section V by name (see `presets()`).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        pvfc_sim::presets::all()
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
        pvfc_sim::presets::all()
            .into_iter()
            .map(|s| s.name)
            .collect()
    }

    /// The scenario as a dict (edit it and pass it to `from_dict`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.s)
            .map_err(|e| errors::ScenarioError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
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

    fn __repr__(&self) -> String {
        format!("Scenario({:?}, duration={})", self.s.name, self.s.duration)
    }
}

/// The time series of a run, as fresh numpy arrays (sampled at the controller's rate).
#[pyclass(module = "pvfc", frozen)]
struct SimulationResult {
    t: Trace,
    period: f64,
}

macro_rules! series {
    ($($name:ident => $field:ident, $doc:literal;)*) => {
        #[pymethods]
        impl SimulationResult {
            $(
                #[doc = $doc]
                #[getter]
                fn $name<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
                    out1(py, self.t.$field.clone())
                }
            )*
        }
    };
}

series! {
    t => t, "Time (s).";
    tau => tau, "Contour parameter τ (unwrapped).";
    tau_dot => tau_dot, "dτ/dt.";
    flywheel_speed => flywheel_speed, "Flywheel speed q̇_F (rad/s).";
    beta => beta, "β = √(κ_a/Ē).";
    potential => potential, "U(E), eq. (17).";
    lambda1 => lambda1, "Self-pacing gain λ₁.";
    lambda2 => lambda2, "Self-pacing gain λ₂.";
    energy => energy, "Augmented kinetic energy κ_a (J).";
    friction_power => friction_power, "Power of the plant's friction (W, ≤ 0).";
}

#[pymethods]
impl SimulationResult {
    /// Joint angles, shape (n, 2).
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        out_series(py, &self.t.q)
    }

    /// Joint velocities, shape (n, 2).
    #[getter]
    fn qdot<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        out_series(py, &self.t.v)
    }

    /// Motor torques, shape (n, 2).
    #[getter]
    fn torque<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        out_series(py, &self.t.torque)
    }

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

    /// The contact columns of a run with a `[contact]` world, or None: a dict of fresh
    /// arrays `force` (n, 2), `normal_force`, `depth`, `torque` (n, 2, `F_e = Jᵀf`), `tool`
    /// (n, 2), `work_contact` (∫F_eᵀq̇ dt), `work_friction`, `work_controller` (the
    /// add-ons' work), `nominal_speed`, and `audit_residual` (energy − energy[0] − the works).
    #[getter]
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = &self.t.contact else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("force", out_rows(py, &c.force))?;
        d.set_item("normal_force", out1(py, c.normal_force.clone()))?;
        d.set_item("depth", out1(py, c.depth.clone()))?;
        d.set_item("torque", out_rows(py, &c.torque))?;
        d.set_item("tool", out_rows(py, &c.tool))?;
        d.set_item("work_contact", out1(py, c.work_contact.clone()))?;
        d.set_item("work_friction", out1(py, c.work_friction.clone()))?;
        d.set_item("work_controller", out1(py, c.work_controller.clone()))?;
        d.set_item("nominal_speed", out1(py, c.nominal_speed.clone()))?;
        d.set_item("audit_residual", out1(py, c.audit_residual(&self.t.energy)))?;
        Ok(Some(d))
    }

    /// For a run with contact, a dict: `peak_force` (N), `energy_pumped` (J, the most the
    /// arm had put into the contact), `work_contact` (J), `energy_scale` (J), `audit`
    /// (relative), `passivity_margin` and `energy_bound_margin` (J, ≥ 0 when passivity
    /// holds), `last_contact` (s or None). None without contact.
    fn contact_summary<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = pvfc_sim::metrics::contact_summary(&self.t) else {
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

    /// The mean of U over the last complete pass of the contour, or None.
    fn mean_potential_over_pass(&self) -> Option<f64> {
        pvfc_sim::metrics::mean_potential_over_pass(&self.t, self.period)
    }

    /// Writes the run as an MCAP log.
    fn write_mcap(&self, path: PathBuf) -> PyResult<()> {
        pvfc_sim::log::write_mcap(&self.t, &path).map_err(sim_err)
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
fn simulate(py: Python<'_>, scenario: &Scenario) -> PyResult<SimulationResult> {
    let s = scenario.s.clone();
    let t = py
        .detach(move || pvfc_sim::simulate::simulate(&s, &mut |_| {}))
        .map_err(sim_err)?;
    Ok(SimulationResult {
        t,
        period: scenario.s.contour.period,
    })
}

/// Runs many scenarios in parallel in Rust (rayon), with the GIL released; the results are
/// in the order of the scenarios.
#[pyfunction]
#[pyo3(signature = (scenarios, threads=None))]
fn simulate_many(
    py: Python<'_>,
    scenarios: Vec<Scenario>,
    threads: Option<usize>,
) -> PyResult<Vec<SimulationResult>> {
    let ss: Vec<SimScenario> = scenarios.into_iter().map(|s| s.s).collect();
    let periods: Vec<f64> = ss.iter().map(|s| s.contour.period).collect();
    let run = move || -> Vec<pvfc_sim::Result<Trace>> {
        ss.par_iter()
            .map(|s| pvfc_sim::simulate::simulate(s, &mut |_| {}))
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
    let traces = traces.map_err(errors::PvfcError::new_err)?;
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

/// The timed-trajectory baseline of a scenario (computed torque + PD) at a τ rate.
#[pyfunction]
#[pyo3(signature = (scenario, kp, kd, tau_rate))]
fn simulate_timed(
    py: Python<'_>,
    scenario: &Scenario,
    kp: &Bound<'_, PyAny>,
    kd: &Bound<'_, PyAny>,
    tau_rate: f64,
) -> PyResult<SimulationResult> {
    let b = pvfc_sim::scenario::BaselineSpec {
        kp: vector::<2>(kp, "kp")?,
        kd: vector::<2>(kd, "kd")?,
        tau_rate: Some(tau_rate),
    };
    let s = scenario.s.clone();
    let t = py
        .detach(move || pvfc_sim::simulate::simulate_timed(&s, &b, tau_rate, &mut |_| {}))
        .map_err(sim_err)?;
    Ok(SimulationResult {
        t,
        period: scenario.s.contour.period,
    })
}

/// Reads an MCAP log; returns a list of (topic, log_time_ns, message dict).
#[pyfunction]
fn read_mcap(py: Python<'_>, path: PathBuf) -> PyResult<Vec<(String, u64, Bound<'_, PyAny>)>> {
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

// ---------------------------------------------------------------- the controller

/// The PVFC controller of a scenario (SCARA, its contour, its settings and add-ons).
/// `step` keeps the internal states τ, τ̇, q̇_F; `evaluate`/`torque` are pure.
#[pyclass(module = "pvfc")]
struct Controller {
    ctl: PaperController,
    initial: PaperController,
}

fn state(
    q: &Bound<'_, PyAny>,
    qdot: &Bound<'_, PyAny>,
    tau: f64,
    tau_dot: f64,
    flywheel_speed: f64,
) -> PyResult<AugmentedState<f64, Torus<f64, 2>, 2>> {
    Ok(AugmentedState {
        q: Torus::new(Vector2::from(vector::<2>(q, "q")?)),
        v: Vector2::from(vector::<2>(qdot, "qdot")?),
        tau,
        tau_dot,
        flywheel_speed,
    })
}

#[pymethods]
impl Controller {
    #[new]
    fn new(scenario: &Scenario) -> PyResult<Self> {
        let ctl = scenario.s.controller().map_err(sim_err)?;
        Ok(Controller { ctl, initial: ctl })
    }

    /// The augmented torque (T₁, T₂, T_τ, T_F) at a full state, shape (4,): coupling (eq. 7)
    /// plus the scenario's nominal-speed and friction-compensation terms.
    fn torque<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (t, _) = self
            .ctl
            .evaluate(&state(q, qdot, tau, tau_dot, flywheel_speed)?)
            .map_err(core_err)?;
        Ok(out1(py, vec![t.robot[0], t.robot[1], t.tau, t.flywheel]))
    }

    /// Everything about the control law at a full state, as a dict of numbers and arrays.
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        tau: f64,
        tau_dot: f64,
        flywheel_speed: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (t, o) = self
            .ctl
            .evaluate(&state(q, qdot, tau, tau_dot, flywheel_speed)?)
            .map_err(core_err)?;
        let aug =
            |a: &AugmentedVector<f64, 2>| out1(py, vec![a.robot[0], a.robot[1], a.tau, a.flywheel]);
        let d = PyDict::new(py);
        d.set_item("torque", aug(&t))?;
        d.set_item("coupling_torque", aug(&o.torque))?;
        d.set_item("field_velocity", aug(&o.field_velocity))?;
        d.set_item("desired_momentum", aug(&o.desired_momentum))?;
        d.set_item("momentum", aug(&o.momentum))?;
        d.set_item("w", aug(&o.w))?;
        d.set_item("kinetic_energy", o.kinetic_energy)?;
        d.set_item("beta", o.beta)?;
        d.set_item("potential", o.field.potential)?;
        d.set_item("lambda1", o.field.lambda1)?;
        d.set_item("lambda2", o.field.lambda2)?;
        let (g, r) = o.coupling_matrices::<4>().map_err(core_err)?;
        d.set_item("G", out_matrix(py, &g))?;
        d.set_item("R", out_matrix(py, &r))?;
        Ok(d)
    }

    /// One control step at the measured (q, q̇): returns the motor torques, shape (2,), and
    /// advances τ, τ̇, q̇_F over dt (semi-implicit Euler). On error the state is unchanged.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qdot: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = Torus::new(Vector2::from(vector::<2>(q, "q")?));
        let v = Vector2::from(vector::<2>(qdot, "qdot")?);
        let out = self.ctl.step(&q, &v, dt).map_err(core_err)?;
        Ok(out1(py, vec![out.torque[0], out.torque[1]]))
    }

    /// The internal states (τ, τ̇, q̇_F, laps).
    #[getter]
    fn state(&self) -> (f64, f64, f64, i64) {
        let s = self.ctl.state();
        (s.tau, s.tau_dot, s.flywheel_speed, s.laps)
    }

    /// Back to the scenario's initial internal states.
    fn reset(&mut self) {
        self.ctl = self.initial;
    }
}

#[pymodule]
fn _pvfc(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<Scara>()?;
    m.add_class::<robots::Robot>()?;
    m.add_class::<arm::ArmController>()?;
    m.add_class::<Lissajous>()?;
    m.add_class::<Ellipse>()?;
    m.add_class::<WaypointCurve>()?;
    m.add_class::<So3ConstantRate>()?;
    m.add_class::<TorusNavigation>()?;
    m.add_class::<So3Navigation>()?;
    m.add_class::<Scenario>()?;
    m.add_class::<SimulationResult>()?;
    m.add_class::<Controller>()?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_many, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_timed, m)?)?;
    m.add_function(wrap_pyfunction!(read_mcap, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
