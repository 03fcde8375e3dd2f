//! Contours: `pvfc.Lissajous`, `Ellipse`, `WaypointCurve`, `So3ConstantRate`.

use crate::convert::{matrix, out1, out_matrix, vector};
use crate::errors::core_err;
use nalgebra::{Vector2, Vector3};
use numpy::{PyArray1, PyArray2};
use pvfc_core::prelude::*;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `(x_d, dx_d/dτ, d²x_d/dτ²)` as three arrays.
pub(crate) type Sample3<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

pub(crate) fn sample2<'py>(
    py: Python<'py>,
    s: ContourSample<f64, Torus<f64, 2>, 2>,
) -> Sample3<'py> {
    (
        out1(py, s.point.angles().iter().cloned().collect()),
        out1(py, s.velocity.iter().cloned().collect()),
        out1(py, s.acceleration.iter().cloned().collect()),
    )
}

/// A Lissajous curve in joint space, x_i = c_i + a_i sin(2πτ/T_i + φ_i).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct Lissajous {
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
pub(crate) struct Ellipse {
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
pub(crate) struct WaypointCurve {
    s: AnySpline,
    period: f64,
}

#[pymethods]
impl WaypointCurve {
    #[new]
    fn new(waypoints: &Bound<'_, PyAny>, spacing: f64) -> PyResult<Self> {
        let n = waypoints.len().unwrap_or(0);
        let flat = crate::convert::array(waypoints, "waypoints", &[n, 2])?;
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
pub(crate) struct So3ConstantRate {
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
