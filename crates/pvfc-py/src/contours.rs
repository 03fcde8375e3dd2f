//! Contours: `pvfc.Lissajous`, `Ellipse`, `WaypointCurve` (joint space, 1 to 8 coordinates),
//! `So3ConstantRate`.

use crate::convert::{any_array, dyn_vector, out1, out_matrix, rotation, vector};
use crate::errors::{core_err, sim_err, InvalidParameterError};
use nalgebra::Vector3;
use numpy::{PyArray1, PyArray2};
use pvfc_core::prelude::*;
use pvfc_sim::model::arm::{DynJointContour, JointContourSpec};
use pvfc_sim::model::{MAX_JOINTS, MAX_WAYPOINTS};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `(x_d, dx_d/dτ, d²x_d/dτ²)` as three arrays.
pub(crate) type Sample3<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// The three arrays of a joint-space contour's sample.
fn sample_n<'py>(py: Python<'py>, c: &DynJointContour, tau: f64) -> Sample3<'py> {
    let [x, dx, ddx] = c.sample(tau);
    (out1(py, x), out1(py, dx), out1(py, ddx))
}

/// A 1-D array-like of any length.
fn list(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    Ok(any_array(obj, name, 1)?.1)
}

/// A 1-D array-like of length `n`, or zeros when not given.
fn list_or_zeros(obj: Option<&Bound<'_, PyAny>>, name: &str, n: usize) -> PyResult<Vec<f64>> {
    obj.map_or(Ok(vec![0.0; n]), |o| dyn_vector(o, name, n))
}

/// A joint-space contour built once from its plain data, with the data kept to rebuild it for
/// a robot's joint kinds (`Controller.compose`).
#[derive(Clone)]
pub(crate) struct JointSpaceContour {
    pub(crate) spec: JointContourSpec,
    c: DynJointContour,
}

impl JointSpaceContour {
    fn new(spec: JointContourSpec) -> PyResult<Self> {
        let c = DynJointContour::new(&spec, None).map_err(sim_err)?;
        Ok(JointSpaceContour { spec, c })
    }
}

/// The plain data of a joint-space contour object (`Lissajous`, `Ellipse`, `WaypointCurve`).
pub(crate) fn joint_contour_spec(contour: &Bound<'_, PyAny>) -> PyResult<JointContourSpec> {
    if let Ok(c) = contour.cast::<WaypointCurve>() {
        Ok(c.get().c.spec.clone())
    } else if let Ok(c) = contour.cast::<Lissajous>() {
        Ok(c.get().c.spec.clone())
    } else if let Ok(c) = contour.cast::<Ellipse>() {
        Ok(c.get().c.spec.clone())
    } else if let Ok(c) = contour.cast::<JointCurve>() {
        Ok(c.get().c.spec.clone())
    } else {
        Err(pyo3::exceptions::PyTypeError::new_err(
            "contour: expected a pvfc.WaypointCurve, pvfc.Lissajous, pvfc.Ellipse or pvfc.JointCurve",
        ))
    }
}

/// Any closed joint-space curve a scenario's `[contour]` can hold, from its dict: one key
/// named for the kind, e.g. `pvfc.JointCurve({"ellipse": {"center": [...], "u": [...],
/// "w": [...], "period": 8.0}})` (`lissajous`, `waypoints`, `ellipse`, and every kind the
/// library adds). `Lissajous`, `Ellipse` and `WaypointCurve` are the typed constructors of
/// the same curves.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct JointCurve {
    pub(crate) c: JointSpaceContour,
}

#[pymethods]
impl JointCurve {
    #[new]
    fn new(py: Python<'_>, spec: &Bound<'_, pyo3::types::PyDict>) -> PyResult<Self> {
        let text: String = py
            .import("json")?
            .call_method1("dumps", (spec,))?
            .extract()?;
        let value: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| PyValueError::new_err(format!("spec: {e}")))?;
        let spec = match pvfc_sim::scenario::ContourSpec::from_value(value)
            .map_err(PyValueError::new_err)?
        {
            pvfc_sim::scenario::ContourSpec::Joint(j) => j,
            other => {
                return Err(PyValueError::new_err(format!(
                    "spec: a {} contour is not a joint-space curve (see pvfc.CartesianPath, pvfc.So3ConstantRate)",
                    other.kind()
                )))
            }
        };
        Ok(JointCurve {
            c: JointSpaceContour::new(spec)?,
        })
    }

    /// The curve's dict, as `JointCurve(d)` takes it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.c.spec)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// The kind: `"lissajous"`, `"waypoints"`, `"ellipse"`, ….
    #[getter]
    fn kind(&self) -> &'static str {
        self.c.spec.kind()
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (n,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample_n(py, &self.c.c, tau)
    }

    /// The period, if it has one.
    #[getter]
    fn period(&self) -> Option<f64> {
        self.c.c.period()
    }

    /// The number of coordinates.
    #[getter]
    fn dim(&self) -> usize {
        self.c.c.dim()
    }
}

/// A Lissajous curve in joint space, x_i = c_i + a_i sin(2πτ/T_i + φ_i), any number of joints
/// (1 to 8).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct Lissajous {
    pub(crate) c: JointSpaceContour,
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
        let amplitude = list(amplitude, "amplitude")?;
        let n = amplitude.len();
        Ok(Lissajous {
            c: JointSpaceContour::new(JointContourSpec::Lissajous {
                periods: dyn_vector(periods, "periods", n)?,
                phase: list_or_zeros(phase, "phase", n)?,
                offset: list_or_zeros(offset, "offset", n)?,
                amplitude,
                period,
            })?,
        })
    }

    /// The paper's contour, (sin(2πτ/3), 1.5 cos(2πτ/6)), period 6.
    #[staticmethod]
    fn paper() -> PyResult<Self> {
        Ok(Lissajous {
            c: JointSpaceContour::new(JointContourSpec::Lissajous {
                amplitude: vec![1.0, 1.5],
                periods: vec![3.0, 6.0],
                phase: vec![0.0, std::f64::consts::FRAC_PI_2],
                offset: vec![0.0, 0.0],
                period: Some(6.0),
            })?,
        })
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (n,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample_n(py, &self.c.c, tau)
    }

    /// The common period, if declared.
    #[getter]
    fn period(&self) -> Option<f64> {
        self.c.c.period()
    }

    /// The number of coordinates.
    #[getter]
    fn dim(&self) -> usize {
        self.c.c.dim()
    }
}

/// An ellipse (or circle) in joint space, x = c + u cos(2πτ/T) + w sin(2πτ/T), any number of
/// joints (1 to 8).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct Ellipse {
    pub(crate) c: JointSpaceContour,
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
        let center = list(center, "center")?;
        let n = center.len();
        Ok(Ellipse {
            c: JointSpaceContour::new(JointContourSpec::Ellipse {
                u: dyn_vector(u, "u", n)?,
                w: dyn_vector(w, "w", n)?,
                center,
                period,
            })?,
        })
    }

    /// A circle of the given radius in the plane of the first two coordinates.
    #[staticmethod]
    fn circle(center: &Bound<'_, PyAny>, radius: f64, period: f64) -> PyResult<Self> {
        let center = list(center, "center")?;
        let n = center.len();
        if n < 2 {
            return Err(PyValueError::new_err(
                "center: a circle needs at least two coordinates",
            ));
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(InvalidParameterError::new_err(
                "Ellipse.circle: radius must be finite and > 0",
            ));
        }
        let (mut u, mut w) = (vec![0.0; n], vec![0.0; n]);
        u[0] = radius;
        w[1] = radius;
        Ok(Ellipse {
            c: JointSpaceContour::new(JointContourSpec::Ellipse {
                center,
                u,
                w,
                period,
            })?,
        })
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (n,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample_n(py, &self.c.c, tau)
    }

    /// The period.
    #[getter]
    fn period(&self) -> Option<f64> {
        self.c.c.period()
    }

    /// The number of coordinates.
    #[getter]
    fn dim(&self) -> usize {
        self.c.c.dim()
    }
}

/// A smooth (C²) closed curve through 3 to 1024 waypoints in joint space (any number of joints,
/// 1 to 8), one every `spacing` units of τ (periodic cubic spline). Sampled with every
/// coordinate an angle; composed with a robot, its prismatic joints are lengths.
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct WaypointCurve {
    pub(crate) c: JointSpaceContour,
}

#[pymethods]
impl WaypointCurve {
    #[new]
    fn new(waypoints: &Bound<'_, PyAny>, spacing: f64) -> PyResult<Self> {
        let (shape, flat) = any_array(waypoints, "waypoints", 2)?;
        let (k, n) = (shape[0], shape[1]);
        if !(3..=MAX_WAYPOINTS).contains(&k) {
            return Err(PyValueError::new_err(format!(
                "waypoints: expected 3 to {MAX_WAYPOINTS} points, got {k}"
            )));
        }
        if !(1..=MAX_JOINTS).contains(&n) {
            return Err(PyValueError::new_err(format!(
                "waypoints: expected 1 to {MAX_JOINTS} coordinates per point, got {n}"
            )));
        }
        Ok(WaypointCurve {
            c: JointSpaceContour::new(JointContourSpec::Waypoints {
                points: flat.chunks(n).map(<[f64]>::to_vec).collect(),
                spacing,
            })?,
        })
    }

    /// (x_d(τ), dx_d/dτ, d²x_d/dτ²), each of shape (n,).
    fn sample<'py>(&self, py: Python<'py>, tau: f64) -> Sample3<'py> {
        sample_n(py, &self.c.c, tau)
    }

    /// The period, `spacing × waypoints`.
    #[getter]
    fn period(&self) -> f64 {
        self.c.spec.period().unwrap_or(f64::NAN)
    }

    /// The number of coordinates.
    #[getter]
    fn dim(&self) -> usize {
        self.c.c.dim()
    }
}

/// A rotation at constant body rate on SO(3): x_d(τ) = R₀ exp(τ ω̂).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct So3ConstantRate {
    pub(crate) c: ConstantRate<f64, So3<f64>, 3>,
}

#[pymethods]
impl So3ConstantRate {
    #[new]
    fn new(start: &Bound<'_, PyAny>, rate: &Bound<'_, PyAny>) -> PyResult<Self> {
        let r0 = rotation(start, "start")?;
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
