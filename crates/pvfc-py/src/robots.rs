//! `pvfc.Robot`: any serial chain from its URDF, with its rigid-body algorithms.

use crate::contours::joint_contour_spec;
use crate::convert::{array, dyn_vector, out1, out_dmatrix};
use crate::errors::sim_err;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pvfc_core::lie::JointKind;
use pvfc_core::mechanics::Pose;
use pvfc_sim::model::arm::drive_limited_rates;
use pvfc_sim::model::pace::{DriveFriction, PaceSettings};
use pvfc_sim::model::robot::Robot as SimRobot;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A serial arm read from a URDF file: `M(q)`, `C(q, v)`, `g(q)`, RNEA, forward kinematics and
/// the tool Jacobian, for 1 to 8 joints.
#[pyclass(module = "pvfc", frozen, from_py_object, name = "Robot")]
#[derive(Clone)]
pub struct Robot {
    pub(crate) robot: SimRobot,
}

fn homogeneous(p: &Pose<f64>) -> [[f64; 4]; 4] {
    let mut h = [[0.0; 4]; 4];
    for (i, row) in h.iter_mut().enumerate().take(3) {
        for (j, x) in row.iter_mut().enumerate().take(3) {
            *x = p.rotation[(i, j)];
        }
        row[3] = p.translation[i];
    }
    h[3][3] = 1.0;
    h
}

fn out_poses<'py>(py: Python<'py>, poses: &[Pose<f64>]) -> Bound<'py, PyArray3<f64>> {
    let hs: Vec<[[f64; 4]; 4]> = poses.iter().map(homogeneous).collect();
    Array3::from_shape_fn((hs.len(), 4, 4), |(k, i, j)| hs[k][i][j]).into_pyarray(py)
}

impl Robot {
    fn v(&self, obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
        dyn_vector(obj, name, self.robot.dof())
    }
}

#[pymethods]
impl Robot {
    /// Reads the chain from `base` (default: the root link) to `tip` (default: the only leaf;
    /// required when the URDF is a tree).
    #[staticmethod]
    #[pyo3(signature = (path, tip=None, base=None))]
    fn from_urdf(path: PathBuf, tip: Option<&str>, base: Option<&str>) -> PyResult<Self> {
        Ok(Robot {
            robot: SimRobot::from_urdf(&path, base, tip).map_err(sim_err)?,
        })
    }

    /// The same robot under another gravity vector (world frame, m/s²).
    fn with_gravity(&self, g: &Bound<'_, PyAny>) -> PyResult<Self> {
        let g = array(g, "g", &[3])?;
        Ok(Robot {
            robot: self
                .robot
                .clone()
                .with_gravity(nalgebra::Vector3::new(g[0], g[1], g[2]))
                .map_err(sim_err)?,
        })
    }

    /// The same robot with its tool centre point (TCP) at `xyz` (m) and `rpy` (roll, pitch,
    /// yaw in rad, about the fixed axes, URDF's convention) in the tip link's frame, replacing
    /// the one it had; gravity is kept. Tool poses, Jacobians, inverse kinematics and
    /// Cartesian paths then use the TCP.
    #[pyo3(signature = (xyz, rpy=None))]
    fn with_tool(&self, xyz: &Bound<'_, PyAny>, rpy: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let xyz = array(xyz, "xyz", &[3])?;
        let rpy = match rpy {
            Some(r) => array(r, "rpy", &[3])?,
            None => vec![0.0; 3],
        };
        let spec = pvfc_sim::model::pose::PoseSpec {
            xyz: [xyz[0], xyz[1], xyz[2]],
            rpy: [rpy[0], rpy[1], rpy[2]],
        };
        let tcp = spec.pose("with_tool").map_err(sim_err)?;
        Ok(Robot {
            robot: self.robot.clone().with_tool(tcp).map_err(sim_err)?,
        })
    }

    /// The tool centre point in the tip link's frame, a `(4, 4)` homogeneous transform
    /// (identity unless set by `with_tool`).
    #[getter]
    fn tcp<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = homogeneous(self.robot.tcp())
            .iter()
            .flatten()
            .copied()
            .collect();
        Ok(numpy::ndarray::Array2::from_shape_vec((4, 4), flat)
            .map_err(|e| PyValueError::new_err(e.to_string()))?
            .into_pyarray(py))
    }

    /// The number of joints.
    #[getter]
    fn dof(&self) -> usize {
        self.robot.dof()
    }

    /// The robot's name in the URDF.
    #[getter]
    fn name(&self) -> String {
        self.robot.description().name.clone()
    }

    /// The joints' names, base to tip.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.robot.description().joint_names()
    }

    /// `"revolute"` or `"prismatic"` per joint.
    #[getter]
    fn joint_kinds(&self) -> Vec<&'static str> {
        self.robot
            .description()
            .kinds()
            .iter()
            .map(|k| match k {
                JointKind::Circular => "revolute",
                JointKind::Linear => "prismatic",
            })
            .collect()
    }

    /// The base and tip links.
    #[getter]
    fn base_link(&self) -> String {
        self.robot.description().base_link.clone()
    }

    #[getter]
    fn tip_link(&self) -> String {
        self.robot.description().tip_link.clone()
    }

    /// Movable joints of side branches locked at 0 and folded into the chain.
    #[getter]
    fn locked_joints(&self) -> Vec<String> {
        self.robot.description().locked_joints.clone()
    }

    /// The joint limits: a dict of arrays `lower`, `upper`, `effort`, `velocity` (NaN where
    /// the URDF gives none).
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let joints = &self.robot.description().joints;
        let col = |f: &dyn Fn(&pvfc_sim::urdf::JointLimits) -> Option<f64>| -> Vec<f64> {
            joints
                .iter()
                .map(|j| f(&j.limits).unwrap_or(f64::NAN))
                .collect()
        };
        d.set_item("lower", out1(py, col(&|l| l.lower)))?;
        d.set_item("upper", out1(py, col(&|l| l.upper)))?;
        d.set_item("effort", out1(py, col(&|l| l.effort)))?;
        d.set_item("velocity", out1(py, col(&|l| l.velocity)))?;
        Ok(d)
    }

    /// `M(q)` (composite rigid body algorithm), `(dof, dof)`.
    fn inertia<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.v(q, "q")?;
        Ok(out_dmatrix(py, &self.robot.inertia(&q).map_err(sim_err)?))
    }

    /// `C(q, v)` in Christoffel form (`Ṁ = C + Cᵀ`), `(dof, dof)`.
    fn coriolis<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (q, v) = (self.v(q, "q")?, self.v(v, "v")?);
        Ok(out_dmatrix(
            py,
            &self.robot.coriolis(&q, &v).map_err(sim_err)?,
        ))
    }

    /// `g(q)`, the torque that holds the arm against gravity.
    fn gravity<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = self.v(q, "q")?;
        let g = self.robot.gravity(&q).map_err(sim_err)?;
        Ok(out1(py, g.as_slice().to_vec()))
    }

    /// The recursive Newton–Euler algorithm: `M(q) a + C(q, v) v + g(q)`.
    fn rnea<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
        a: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (q, v, a) = (self.v(q, "q")?, self.v(v, "v")?, self.v(a, "a")?);
        let t = self.robot.rnea(&q, &v, &a).map_err(sim_err)?;
        Ok(out1(py, t.as_slice().to_vec()))
    }

    /// The poses of the moving links' frames and, last, of the tool frame, in the world frame:
    /// `(dof + 1, 4, 4)` homogeneous transforms.
    fn forward_kinematics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let q = self.v(q, "q")?;
        Ok(out_poses(py, &self.robot.link_poses(&q).map_err(sim_err)?))
    }

    /// The tool frame's pose, a `(4, 4)` homogeneous transform.
    fn tool_pose<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.v(q, "q")?;
        let (r, p) = self.robot.tool_pose(&q).map_err(sim_err)?;
        let h = homogeneous(&Pose {
            rotation: r,
            translation: p,
        });
        let flat: Vec<f64> = h.iter().flatten().copied().collect();
        Ok(numpy::ndarray::Array2::from_shape_vec((4, 4), flat)
            .map_err(|e| PyValueError::new_err(e.to_string()))?
            .into_pyarray(py))
    }

    /// The joint coordinates that put the tool at `target`: a point `(3,)` (the orientation
    /// free) or a `(4, 4)` pose, by damped least squares from `seed` `(dof,)`. Raises
    /// `NoConvergenceError` (with the distance left) when it cannot.
    #[pyo3(signature = (target, seed, tolerance=1e-9))]
    fn inverse_kinematics<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'_, PyAny>,
        seed: &Bound<'_, PyAny>,
        tolerance: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let seed = self.v(seed, "seed")?;
        let (position, rotation) = match array(target, "target", &[3]) {
            Ok(p) => (nalgebra::Vector3::new(p[0], p[1], p[2]), None),
            Err(_) => {
                let h = array(target, "target", &[4, 4])?;
                let r =
                    nalgebra::Matrix3::new(h[0], h[1], h[2], h[4], h[5], h[6], h[8], h[9], h[10]);
                (nalgebra::Vector3::new(h[3], h[7], h[11]), Some(r))
            }
        };
        let q = self
            .robot
            .inverse_kinematics(position, rotation, &seed, tolerance)
            .map_err(sim_err)?;
        Ok(out1(py, q.as_slice().to_vec()))
    }

    /// The fastest rates `τ̇` the drives allow along a closed joint-space `contour` at
    /// `points` evenly spaced values of `τ` over one period: the time-optimal
    /// parameterisation under the torque limits `torque_limit` (one per joint, > 0), each
    /// used up to `headroom` (in (0, 1]), with the friction compensation
    /// `friction_compensation` (eq. 35; or a plant's Coulomb levels), the viscous friction
    /// `viscous_friction` (a plant's `b_i`, torque `b_i q̇_i`) and, if `gravity`, `g(q)`
    /// counted against them, at most `rate` (the rate asked for). Shape `(points,)`.
    #[pyo3(signature = (contour, torque_limit, *, headroom=1.0, friction_compensation=None, viscous_friction=None, gravity=true, rate=1e6, points=4096))]
    #[allow(clippy::too_many_arguments)]
    fn drive_limited_rates<'py>(
        &self,
        py: Python<'py>,
        contour: &Bound<'_, PyAny>,
        torque_limit: &Bound<'_, PyAny>,
        headroom: f64,
        friction_compensation: Option<&Bound<'_, PyAny>>,
        viscous_friction: Option<&Bound<'_, PyAny>>,
        gravity: bool,
        rate: f64,
        points: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let spec = joint_contour_spec(contour)?;
        let pace = PaceSettings {
            speed: None,
            torque_limit: self.v(torque_limit, "torque_limit")?,
            headroom,
            level: rate,
        };
        let friction = DriveFriction {
            coulomb: friction_compensation
                .map(|f| self.v(f, "friction_compensation"))
                .transpose()?
                .unwrap_or_default(),
            viscous: viscous_friction
                .map(|f| self.v(f, "viscous_friction"))
                .transpose()?
                .unwrap_or_default(),
        };
        let rates = drive_limited_rates(&self.robot, &spec, &pace, &friction, gravity, points)
            .map_err(sim_err)?;
        Ok(out1(py, rates))
    }

    /// Yoshikawa's manipulability of the tool's position at `q` (0 at a singularity).
    fn manipulability(&self, q: &Bound<'_, PyAny>) -> PyResult<f64> {
        let q = self.v(q, "q")?;
        self.robot.manipulability(&q).map_err(sim_err)
    }

    /// The tool's geometric Jacobian `(6, dof)`, rows `[linear; angular]`: `frame="world"`
    /// (Pinocchio's LOCAL_WORLD_ALIGNED: the tool origin's velocity and the angular velocity
    /// in world axes) or `"local"` (both in the tool frame).
    #[pyo3(signature = (q, frame="world"))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
        frame: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let world = match frame {
            "world" => true,
            "local" => false,
            other => {
                return Err(PyValueError::new_err(format!(
                    "frame: expected 'world' or 'local', got {other:?}"
                )))
            }
        };
        let q = self.v(q, "q")?;
        Ok(out_dmatrix(
            py,
            &self.robot.jacobian(&q, world).map_err(sim_err)?,
        ))
    }

    fn __repr__(&self) -> String {
        let d = self.robot.description();
        format!(
            "Robot({:?}, dof={}, base={:?}, tip={:?})",
            d.name,
            d.dof(),
            d.base_link,
            d.tip_link
        )
    }
}

#[pymethods]
impl Robot {
    /// A robot from plain arrays, one row per joint (no URDF): `kinds` ("revolute" or
    /// "prismatic"), each joint's origin in the previous link's frame (`origins_xyz`,
    /// `origins_rpy`, shape (n, 3), URDF conventions), its axis (n, 3), and the inertia of the
    /// link it moves in that link's frame: `masses` (n,), `coms` (n, 3), `inertias` (n, 3, 3)
    /// about the centre of mass. The tool frame is optional (in the last link's frame).
    #[staticmethod]
    #[pyo3(signature = (kinds, origins_xyz, origins_rpy, axes, masses, coms, inertias, *,
        tool_xyz=None, tool_rpy=None, name="robot"))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        kinds: Vec<String>,
        origins_xyz: &Bound<'_, PyAny>,
        origins_rpy: &Bound<'_, PyAny>,
        axes: &Bound<'_, PyAny>,
        masses: &Bound<'_, PyAny>,
        coms: &Bound<'_, PyAny>,
        inertias: &Bound<'_, PyAny>,
        tool_xyz: Option<&Bound<'_, PyAny>>,
        tool_rpy: Option<&Bound<'_, PyAny>>,
        name: &str,
    ) -> PyResult<Self> {
        use pvfc_core::mechanics::{ChainJoint, RigidInertia};
        let n = kinds.len();
        let xyz = array(origins_xyz, "origins_xyz", &[n, 3])?;
        let rpy = array(origins_rpy, "origins_rpy", &[n, 3])?;
        let ax = array(axes, "axes", &[n, 3])?;
        let m = array(masses, "masses", &[n])?;
        let c = array(coms, "coms", &[n, 3])?;
        let i3 = array(inertias, "inertias", &[n, 3, 3])?;
        let three = |v: &[f64], k: usize| [v[3 * k], v[3 * k + 1], v[3 * k + 2]];
        let mut joints = Vec::with_capacity(n);
        let mut links = Vec::with_capacity(n);
        for (k, kind) in kinds.iter().enumerate() {
            let kind = match kind.as_str() {
                "revolute" | "continuous" => JointKind::Circular,
                "prismatic" => JointKind::Linear,
                other => {
                    return Err(PyValueError::new_err(format!(
                        "kinds[{k}]: expected 'revolute' or 'prismatic', got {other:?}"
                    )))
                }
            };
            joints.push(ChainJoint {
                kind,
                origin: Pose::from_xyz_rpy(three(&xyz, k), three(&rpy, k)),
                axis: nalgebra::Vector3::from(three(&ax, k)),
            });
            links.push(RigidInertia {
                mass: m[k],
                com: nalgebra::Vector3::from(three(&c, k)),
                inertia: nalgebra::Matrix3::from_row_slice(&i3[9 * k..9 * k + 9]),
            });
        }
        let tool = Pose::from_xyz_rpy(
            tool_xyz
                .map(|t| array(t, "tool_xyz", &[3]))
                .transpose()?
                .map_or([0.0; 3], |v| three(&v, 0)),
            tool_rpy
                .map(|t| array(t, "tool_rpy", &[3]))
                .transpose()?
                .map_or([0.0; 3], |v| three(&v, 0)),
        );
        let d = pvfc_sim::urdf::ChainDescription::from_parts(name, joints, links, tool)
            .map_err(sim_err)?;
        Ok(Robot {
            robot: SimRobot::from_description(d).map_err(sim_err)?,
        })
    }
}
