//! `pvfc.Scara`: the paper's two-link arm in closed form.

use crate::convert::{out_matrix, vector};
use crate::errors::{core_err, sim_err};
use nalgebra::Vector2;
use numpy::PyArray2;
use pvfc_core::prelude::*;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A two-link SCARA in the horizontal plane (closed-form M and C).
#[pyclass(module = "pvfc", frozen, from_py_object)]
#[derive(Clone)]
pub(crate) struct Scara {
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

    /// The CICESE Pelican arm (the manual's control law, `docs/src/reference/control-law.md` §1).
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
