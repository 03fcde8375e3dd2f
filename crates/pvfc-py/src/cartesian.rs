//! `pvfc.CartesianPath`: a closed tool path in the robot's base frame or a part's frame (a
//! polyline with rounded corners, a circle or ellipse, a CSV file of points, or a part
//! program's cutting moves), sampled and turned into the joint waypoints of a contour by
//! inverse kinematics (`pvfc_sim::model::cartesian`).

use crate::convert::{array, out1};
use crate::errors::sim_err;
use crate::robots::Robot;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pvfc_sim::model::arm::JointContourSpec;
use pvfc_sim::model::arm_field::FieldSpec;
use pvfc_sim::model::cartesian::{
    CartesianSpec, CircleSpec, ContourGeometry, PoseSpec, TaskSpec, ToolFrameSpec,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A closed tool path: give `points` (an `(n, 3)` polyline, corners rounded to
/// `corner_radius`; with `orientations`, `(n, 3)` roll–pitch–yaw of the tool at each, a path
/// in SE(3)), or `circle=(center, radius, normal)`, or `ellipse=(center, semi_major,
/// semi_minor, normal, major_axis)`, or `csv` (a file of `x,y,z` lines). `samples=0` (the
/// default) samples it as many times as it takes for the joint contour to stay within
/// `tolerance` (default 10 µm) of the path; a number from 4 fixes the samples. With
/// `tool_frame=(lead, tilt, normal)` the tool's axis follows the path's own frame (against
/// the surface normal `normal`, `None` for the part's `+z`, leaning by `lead` towards the
/// direction of travel and by `tilt` across it, rad), its roll free.
#[pyclass(module = "pvfc")]
pub(crate) struct CartesianPath {
    spec: CartesianSpec,
}

impl CartesianPath {
    /// The part program's feeds along the path (moves without F at `fallback`), `None` for a
    /// path without them.
    pub(crate) fn feeds(
        &self,
        fallback: Option<f64>,
    ) -> PyResult<Option<pvfc_sim::model::feeds::FeedProfile>> {
        self.spec
            .feeds(std::path::Path::new("."), fallback)
            .map_err(sim_err)
    }
}

#[pymethods]
impl CartesianPath {
    #[new]
    #[pyo3(signature = (points=None, corner_radius=0.0, circle=None, csv=None, samples=0, orientations=None, ellipse=None, tolerance=None, gcode=None, part=None, tool_frame=None))]
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    fn new(
        points: Option<&Bound<'_, PyAny>>,
        corner_radius: f64,
        circle: Option<(Bound<'_, PyAny>, f64, Bound<'_, PyAny>)>,
        csv: Option<PathBuf>,
        samples: usize,
        orientations: Option<&Bound<'_, PyAny>>,
        ellipse: Option<(
            Bound<'_, PyAny>,
            f64,
            f64,
            Bound<'_, PyAny>,
            Bound<'_, PyAny>,
        )>,
        tolerance: Option<f64>,
        gcode: Option<PathBuf>,
        part: Option<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
        tool_frame: Option<(f64, f64, Option<Bound<'_, PyAny>>)>,
    ) -> PyResult<Self> {
        let triples = |p: Option<&Bound<'_, PyAny>>, name: &str| -> PyResult<Vec<[f64; 3]>> {
            match p {
                Some(p) => {
                    let n = p.len()?;
                    let flat = array(p, name, &[n, 3])?;
                    Ok(flat.chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
                }
                None => Ok(Vec::new()),
            }
        };
        let points = triples(points, "points")?;
        let orientations = triples(orientations, "orientations")?;
        let ellipse = match ellipse {
            Some((c, a, b, n, m)) => {
                let c = array(&c, "ellipse center", &[3])?;
                let n = array(&n, "ellipse normal", &[3])?;
                let m = array(&m, "ellipse major_axis", &[3])?;
                Some(CircleSpec {
                    center: [c[0], c[1], c[2]],
                    radius: a,
                    normal: [n[0], n[1], n[2]],
                    semi_minor: Some(b),
                    major_axis: Some([m[0], m[1], m[2]]),
                })
            }
            None => None,
        };
        let circle = match circle {
            Some((c, r, n)) => {
                let c = array(&c, "circle center", &[3])?;
                let n = array(&n, "circle normal", &[3])?;
                Some(CircleSpec {
                    center: [c[0], c[1], c[2]],
                    radius: r,
                    normal: [n[0], n[1], n[2]],
                    semi_minor: None,
                    major_axis: None,
                })
            }
            None => None,
        };
        if circle.is_some() && ellipse.is_some() {
            return Err(PyValueError::new_err("give circle or ellipse, not both"));
        }
        let part = match part {
            Some((xyz, rpy)) => {
                let xyz = array(&xyz, "part xyz", &[3])?;
                let rpy = array(&rpy, "part rpy", &[3])?;
                Some(PoseSpec {
                    xyz: [xyz[0], xyz[1], xyz[2]],
                    rpy: [rpy[0], rpy[1], rpy[2]],
                })
            }
            None => None,
        };
        let tool_frame = match tool_frame {
            Some((lead, tilt, normal)) => Some(ToolFrameSpec {
                normal: match normal {
                    Some(n) => {
                        let n = array(&n, "tool_frame normal", &[3])?;
                        Some([n[0], n[1], n[2]])
                    }
                    None => None,
                },
                lead,
                tilt,
            }),
            None => None,
        };
        let spec = CartesianSpec {
            points,
            corner_radius,
            tool_frame,
            circle: circle.or(ellipse),
            csv,
            samples,
            tolerance,
            orientations,
            gcode,
            part,
            ..CartesianSpec::default()
        };
        spec.tolerance().map_err(sim_err)?;
        // Checked now (shape, counts, geometry, orientations), not at first use.
        let sampled = spec.sample(std::path::Path::new(".")).map_err(sim_err)?;
        spec.sampled_orientations(&sampled).map_err(sim_err)?;
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
    /// (`max_jump`); a failure raises `InvalidParameterError` naming the waypoint. For a
    /// redundant arm, `rest` (a posture) is pulled towards in the task's null space with
    /// `rest_gain`.
    #[pyo3(signature = (robot, seed, fixed_orientation=false, max_jump=0.6, min_manipulability=1e-4, rest=None, rest_gain=0.1))]
    #[allow(clippy::too_many_arguments)]
    fn joint_waypoints<'py>(
        &self,
        py: Python<'py>,
        robot: &Robot,
        seed: &Bound<'_, PyAny>,
        fixed_orientation: bool,
        max_jump: f64,
        min_manipulability: f64,
        rest: Option<&Bound<'_, PyAny>>,
        rest_gain: f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let spec = self.with_ik(
            robot,
            seed,
            fixed_orientation,
            max_jump,
            min_manipulability,
            rest,
            rest_gain,
        )?;
        let dof = robot.robot.dof();
        let q = spec
            .joint_waypoints(&robot.robot, std::path::Path::new("."))
            .map_err(sim_err)?;
        let flat: Vec<f64> = q.iter().flatten().copied().collect();
        Array2::from_shape_vec((q.len(), dof), flat)
            .map(|a| a.into_pyarray(py))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// How far the joint contour through the waypoints of
    /// [`joint_waypoints`](Self::joint_waypoints) (same arguments) is from the path, by
    /// forward kinematics at 16 values of τ per waypoint: a dict `samples`, `mean` and `max`
    /// (m), `max_angle` (rad, for a path with an orientation, else None) and `length` (m).
    /// With `samples=0` the samples are as many as `tolerance` needs.
    #[pyo3(signature = (robot, seed, fixed_orientation=false, max_jump=0.6, min_manipulability=1e-4, rest=None, rest_gain=0.1))]
    #[allow(clippy::too_many_arguments)]
    fn geometry<'py>(
        &self,
        py: Python<'py>,
        robot: &Robot,
        seed: &Bound<'_, PyAny>,
        fixed_orientation: bool,
        max_jump: f64,
        min_manipulability: f64,
        rest: Option<&Bound<'_, PyAny>>,
        rest_gain: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let spec = self.with_ik(
            robot,
            seed,
            fixed_orientation,
            max_jump,
            min_manipulability,
            rest,
            rest_gain,
        )?;
        let g = spec
            .joint_path(&robot.robot, std::path::Path::new("."))
            .map_err(sim_err)?
            .geometry;
        geometry_dict(py, &g)
    }

    /// The task-space field on this path for `robot` (`Controller.compose` takes it in
    /// place of a joint contour): the tool's error to the exact path, `U = ½ k |e|²`
    /// (`stiffness` k, 1/s), with `fixed_orientation` the tool held at the seed's orientation
    /// (`U_R = k_R (1 − cos θ)`, `orientation_stiffness` k_R, default `stiffness`), pulled back
    /// through the damped inverse `Jᵀ(J Jᵀ + μ² I)⁻¹` (`damping` μ, m), and for a redundant
    /// arm a pull of `rest_gain` (1/s) towards `rest` (default: the seed) in the task's null
    /// space. `saturation` ℓ (m) saturates the position's function, `U = kℓ²(√(1 + |e|²/ℓ²) −
    /// 1)`, so that its pull stays below kℓ. One pass of the path every `period` of τ. The
    /// path's joint waypoints are solved too (same arguments as `joint_waypoints`):
    /// `Controller.contour_point` gives them.
    #[pyo3(signature = (robot, seed, period, *, fixed_orientation=false, stiffness=None, orientation_stiffness=None, damping=None, rest=None, rest_gain=None, max_jump=0.6, min_manipulability=1e-4, saturation=None))]
    #[allow(clippy::too_many_arguments)]
    fn task_field(
        &self,
        robot: &Robot,
        seed: &Bound<'_, PyAny>,
        period: f64,
        fixed_orientation: bool,
        stiffness: Option<f64>,
        orientation_stiffness: Option<f64>,
        damping: Option<f64>,
        rest: Option<&Bound<'_, PyAny>>,
        rest_gain: Option<f64>,
        max_jump: f64,
        min_manipulability: f64,
        saturation: Option<f64>,
    ) -> PyResult<TaskSpaceField> {
        if !(period.is_finite() && period > 0.0) {
            return Err(PyValueError::new_err(format!(
                "period: finite and > 0, got {period}"
            )));
        }
        let mut spec = self.with_ik(
            robot,
            seed,
            fixed_orientation,
            max_jump,
            min_manipulability,
            rest,
            0.1,
        )?;
        spec.task = Some(TaskSpec {
            stiffness,
            orientation_stiffness,
            damping,
            rest_gain,
            saturation,
        });
        let base = std::path::Path::new(".");
        let field = spec
            .task_field(&robot.robot, base)
            .map_err(sim_err)?
            .ok_or_else(|| PyValueError::new_err("task: no task-space field"))?;
        let points = spec.joint_waypoints(&robot.robot, base).map_err(sim_err)?;
        let spacing = period / points.len() as f64;
        Ok(TaskSpaceField {
            image: JointContourSpec::Waypoints { points, spacing },
            field: FieldSpec::Task(Box::new(field)),
        })
    }

    /// The path's length (m).
    #[getter]
    fn length(&self) -> PyResult<f64> {
        Ok(self
            .spec
            .path(std::path::Path::new("."))
            .map_err(sim_err)?
            .length())
    }

    /// The closest points of the path to tool positions `(n, 3)`: a dict of `along` (the arc
    /// length from the path's start, m), `point` `(n, 3)` and `distance` (m).
    fn closest<'py>(
        &self,
        py: Python<'py>,
        tool: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = tool.len()?;
        let flat = array(tool, "tool", &[n, 3])?;
        let path = self.spec.path(std::path::Path::new(".")).map_err(sim_err)?;
        let c: Vec<_> = flat
            .chunks(3)
            .map(|c| path.closest(&nalgebra::Vector3::new(c[0], c[1], c[2])))
            .collect();
        let d = PyDict::new(py);
        d.set_item("along", out1(py, c.iter().map(|c| c.along).collect()))?;
        let pts: Vec<f64> = c
            .iter()
            .flat_map(|c| [c.point.x, c.point.y, c.point.z])
            .collect();
        d.set_item(
            "point",
            Array2::from_shape_vec((n, 3), pts)
                .map_err(|e| PyValueError::new_err(e.to_string()))?
                .into_pyarray(py),
        )?;
        d.set_item("distance", out1(py, c.iter().map(|c| c.distance).collect()))?;
        Ok(d)
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

impl CartesianPath {
    /// The spec with the inverse kinematics' settings for `robot`.
    #[allow(clippy::too_many_arguments)]
    fn with_ik(
        &self,
        robot: &Robot,
        seed: &Bound<'_, PyAny>,
        fixed_orientation: bool,
        max_jump: f64,
        min_manipulability: f64,
        rest: Option<&Bound<'_, PyAny>>,
        rest_gain: f64,
    ) -> PyResult<CartesianSpec> {
        let dof = robot.robot.dof();
        Ok(CartesianSpec {
            seed: array(seed, "seed", &[dof])?,
            fixed_orientation,
            max_jump: Some(max_jump),
            min_manipulability: Some(min_manipulability),
            rest: rest.map(|r| array(r, "rest", &[dof])).transpose()?,
            rest_gain: Some(rest_gain),
            ..self.spec.clone()
        })
    }
}

/// A [`ContourGeometry`] as a dict.
pub(crate) fn geometry_dict<'py>(
    py: Python<'py>,
    g: &ContourGeometry,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("samples", g.samples)?;
    d.set_item("mean", g.mean)?;
    d.set_item("max", g.max)?;
    d.set_item("max_angle", g.max_angle)?;
    d.set_item("length", g.length)?;
    Ok(d)
}

/// The task-space field on a tool path for one robot (`CartesianPath.task_field`), which
/// `Controller.compose` takes in place of a joint contour.
#[pyclass(module = "pvfc", frozen)]
pub(crate) struct TaskSpaceField {
    /// The path's joint-space image (its joint waypoints, one pass per period).
    pub(crate) image: JointContourSpec,
    /// The field.
    pub(crate) field: FieldSpec,
}

#[pymethods]
impl TaskSpaceField {
    /// The number of joints of the robot it was made for.
    #[getter]
    fn dof(&self) -> usize {
        self.image.dim()
    }

    /// The period of τ per pass of the path.
    #[getter]
    fn period(&self) -> Option<f64> {
        self.image.period()
    }

    fn __repr__(&self) -> String {
        match &self.field {
            FieldSpec::Task(t) => format!(
                "TaskSpaceField(dof={}, stiffness={}, damping={}, orientation held: {})",
                self.image.dim(),
                t.stiffness,
                t.damping,
                t.orientation.is_some()
            ),
            FieldSpec::Joint => "TaskSpaceField()".into(),
        }
    }
}
