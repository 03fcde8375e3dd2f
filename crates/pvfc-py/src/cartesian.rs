//! `pvfc.CartesianPath`: a closed tool path in the robot's base frame (a polyline with
//! rounded corners, a circle, or a CSV file of points), sampled and turned into the joint
//! waypoints of a contour by inverse kinematics (`pvfc_sim::cartesian`).

use crate::convert::{array, out1};
use crate::errors::sim_err;
use crate::robots::Robot;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pvfc_sim::cartesian::{CartesianSpec, CircleSpec};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;

/// A closed tool path: give `points` (an `(n, 3)` polyline, corners rounded to
/// `corner_radius`), or `circle=(center, radius, normal)`, or `csv` (a file of `x,y,z` lines).
#[pyclass(module = "pvfc")]
pub(crate) struct CartesianPath {
    spec: CartesianSpec,
}

#[pymethods]
impl CartesianPath {
    #[new]
    #[pyo3(signature = (points=None, corner_radius=0.0, circle=None, csv=None, samples=24))]
    fn new(
        points: Option<&Bound<'_, PyAny>>,
        corner_radius: f64,
        circle: Option<(Bound<'_, PyAny>, f64, Bound<'_, PyAny>)>,
        csv: Option<PathBuf>,
        samples: usize,
    ) -> PyResult<Self> {
        let points = match points {
            Some(p) => {
                let n = p.len()?;
                let flat = array(p, "points", &[n, 3])?;
                flat.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
            }
            None => Vec::new(),
        };
        let circle = match circle {
            Some((c, r, n)) => {
                let c = array(&c, "circle center", &[3])?;
                let n = array(&n, "circle normal", &[3])?;
                Some(CircleSpec {
                    center: [c[0], c[1], c[2]],
                    radius: r,
                    normal: [n[0], n[1], n[2]],
                })
            }
            None => None,
        };
        let spec = CartesianSpec {
            points,
            corner_radius,
            circle,
            csv,
            samples,
            ..CartesianSpec::default()
        };
        // Checked now (shape, counts, geometry), not at first use.
        spec.sample(std::path::Path::new(".")).map_err(sim_err)?;
        Ok(CartesianPath { spec })
    }

    /// The path sampled at `samples` points of equal arc length, `(samples, 3)`.
    fn sample<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = self
            .spec
            .sample(std::path::Path::new("."))
            .map_err(sim_err)?;
        let flat: Vec<f64> = p.iter().flat_map(|x| [x.x, x.y, x.z]).collect();
        Array2::from_shape_vec((p.len(), 3), flat)
            .map(|a| a.into_pyarray(py))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The joint waypoints `(samples, dof)` of the path for `robot`: inverse kinematics at
    /// every sample from `seed` (the tool's orientation free, or held at the seed's), checked
    /// for reach, singularity (`min_manipulability`), joint limits and branch jumps
    /// (`max_jump`); a failure raises `InvalidParameterError` naming the waypoint.
    #[pyo3(signature = (robot, seed, fixed_orientation=false, max_jump=0.6, min_manipulability=1e-4))]
    fn joint_waypoints<'py>(
        &self,
        py: Python<'py>,
        robot: &Robot,
        seed: &Bound<'_, PyAny>,
        fixed_orientation: bool,
        max_jump: f64,
        min_manipulability: f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let dof = robot.robot.dof();
        let spec = CartesianSpec {
            seed: array(seed, "seed", &[dof])?,
            fixed_orientation,
            max_jump: Some(max_jump),
            min_manipulability: Some(min_manipulability),
            ..self.spec.clone()
        };
        let q = spec
            .joint_waypoints(&robot.robot, std::path::Path::new("."))
            .map_err(sim_err)?;
        let flat: Vec<f64> = q.iter().flatten().copied().collect();
        Array2::from_shape_vec((q.len(), dof), flat)
            .map(|a| a.into_pyarray(py))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The distance (m) of each tool position `(n, 3)` to the path.
    fn distances<'py>(
        &self,
        py: Python<'py>,
        tool: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let n = tool.len()?;
        let flat = array(tool, "tool", &[n, 3])?;
        let pts: Vec<nalgebra::Vector3<f64>> = flat
            .chunks(3)
            .map(|c| nalgebra::Vector3::new(c[0], c[1], c[2]))
            .collect();
        let d = self
            .spec
            .distances(std::path::Path::new("."), &pts)
            .map_err(sim_err)?;
        Ok(out1(py, d))
    }
}
