//! A serial chain whose number of joints is known at run time (from its URDF), dispatched into
//! the core's const-generic [`SerialChain`] for `N = 1 … 8`.

use crate::error::{Result, SimError};
use crate::urdf::chain::{ChainDescription, MAX_JOINTS};
use crate::with_dof;
use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector, Vector3};
use pvfc_core::mechanics::{Pose, SerialChain};
use std::path::Path;

/// A serial chain of `N` joints, in f64.
pub type ChainN<const N: usize> = SerialChain<f64, N>;

crate::dof_enum! {
    /// A serial chain of 1 to 8 joints.
    #[derive(Clone, Debug, PartialEq)]
    pub enum ChainModel of ChainN
}

macro_rules! on_chain {
    ($self:expr, $c:ident, $N:ident => $body:expr) => {
        crate::on_joints!(ChainModel, $self, $c, $N => $body)
    };
}

/// A robot: its URDF description (names, limits) and its dynamic model, with vectors and
/// matrices sized at run time. Every vector argument is checked against [`Self::dof`].
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    description: ChainDescription,
    model: ChainModel,
}

impl Robot {
    /// Reads the chain from `base` (default: the URDF's root) to `tip` (default: its only
    /// leaf) of a URDF file.
    pub fn from_urdf(path: &Path, base: Option<&str>, tip: Option<&str>) -> Result<Self> {
        Self::from_description(ChainDescription::from_file(path, base, tip)?)
    }

    /// The model of a chain description.
    pub fn from_description(description: ChainDescription) -> Result<Self> {
        let model = with_dof!(description.dof(), N => ChainModel::from(description.chain::<N>()?),
        otherwise return Err(SimError::Setting(format!(
            "robot {}: {} joints; pvfc supports 1 to {MAX_JOINTS}",
            description.name, description.dof()
        ))));
        Ok(Robot { description, model })
    }

    /// The same robot under another gravity vector (world frame, m/s²).
    pub fn with_gravity(mut self, g: Vector3<f64>) -> Result<Self> {
        self.model = on_chain!(&self.model, c, N => ChainModel::from(c.with_gravity(g)?));
        Ok(self)
    }

    /// The same robot with its tool centre point (TCP) at `tcp` in the tip link's frame
    /// (identity: the tip link's origin), replacing the one it had; gravity is kept. Every
    /// tool pose, Jacobian, inverse kinematics, tool-path measure and contact then uses the
    /// TCP. Errors when `tcp` is not a finite rigid transform.
    pub fn with_tool(mut self, tcp: Pose<f64>) -> Result<Self> {
        let g = on_chain!(&self.model, c, N => *c.gravity_vector());
        self.description.tcp = tcp;
        let rebuilt = Self::from_description(self.description)?;
        rebuilt.with_gravity(g)
    }

    /// The tool centre point in the tip link's frame.
    pub fn tcp(&self) -> &Pose<f64> {
        &self.description.tcp
    }

    /// The URDF description.
    pub fn description(&self) -> &ChainDescription {
        &self.description
    }

    /// The const-generic model.
    pub fn model(&self) -> &ChainModel {
        &self.model
    }

    /// The number of joints.
    pub fn dof(&self) -> usize {
        self.description.dof()
    }

    /// Each joint's coordinate: circular (revolute, continuous) or linear (prismatic).
    pub fn joint_kinds(&self) -> Vec<pvfc_core::lie::JointKind> {
        on_chain!(&self.model, c, N => c.kinds().to_vec())
    }

    fn vector<const N: usize>(&self, x: &[f64], name: &str) -> Result<SVector<f64, N>> {
        let v = super::fixed::<N>(x, name)?;
        if !v.iter().all(|v| v.is_finite()) {
            return Err(SimError::Core(pvfc_core::Error::new(
                pvfc_core::ErrorKind::NonFinite,
                "Robot: a state entry is NaN or infinite",
            )));
        }
        Ok(v)
    }

    /// `M(q)` (composite rigid body algorithm).
    pub fn inertia(&self, q: &[f64]) -> Result<DMatrix<f64>> {
        let n = self.dof();
        let mut m = vec![0.0; n * n];
        self.inertia_into(q, &mut m)?;
        Ok(DMatrix::from_row_slice(n, n, &m))
    }

    /// `C(q, v)` (Christoffel-consistent: `Ṁ = C + Cᵀ`).
    pub fn coriolis(&self, q: &[f64], v: &[f64]) -> Result<DMatrix<f64>> {
        on_chain!(&self.model, c, N => {
            let (q, v) = (self.vector::<N>(q, "q")?, self.vector::<N>(v, "v")?);
            Ok(dm(&c.dynamics(&q, &v).1))
        })
    }

    /// `g(q)`.
    pub fn gravity(&self, q: &[f64]) -> Result<DVector<f64>> {
        let mut g = vec![0.0; self.dof()];
        self.gravity_into(q, &mut g)?;
        Ok(DVector::from_vec(g))
    }

    /// The recursive Newton–Euler algorithm: `M a + C v + g`.
    pub fn rnea(&self, q: &[f64], v: &[f64], a: &[f64]) -> Result<DVector<f64>> {
        let mut tau = vec![0.0; self.dof()];
        self.rnea_into(q, v, a, &mut tau)?;
        Ok(DVector::from_vec(tau))
    }

    /// `M(q)` into `m` (`dof × dof`, row-major), allocating nothing.
    pub fn inertia_into(&self, q: &[f64], m: &mut [f64]) -> Result<()> {
        on_chain!(&self.model, c, N => {
            let q = self.vector::<N>(q, "q")?;
            row_major(&c.crba(&q), m, "M")
        })
    }

    /// `g(q)` into `g` (`dof`), allocating nothing.
    pub fn gravity_into(&self, q: &[f64], g: &mut [f64]) -> Result<()> {
        on_chain!(&self.model, c, N => {
            let q = self.vector::<N>(q, "q")?;
            copy(&c.gravity_torque(&q), g, "g")
        })
    }

    /// The recursive Newton–Euler algorithm `M a + C v + g` into `tau` (`dof`), allocating
    /// nothing.
    pub fn rnea_into(&self, q: &[f64], v: &[f64], a: &[f64], tau: &mut [f64]) -> Result<()> {
        on_chain!(&self.model, c, N => {
            let q = self.vector::<N>(q, "q")?;
            let v = self.vector::<N>(v, "v")?;
            let a = self.vector::<N>(a, "a")?;
            copy(&c.rnea(&q, &v, &a), tau, "tau")
        })
    }

    /// `M(q)`, `C(q, v)` and `g(q)` in one pass over the chain into `m`, `c` (`dof × dof`,
    /// row-major) and `g` (`dof`), allocating nothing.
    pub fn dynamics_into(
        &self,
        q: &[f64],
        v: &[f64],
        m: &mut [f64],
        c_out: &mut [f64],
        g: &mut [f64],
    ) -> Result<()> {
        on_chain!(&self.model, c, N => {
            let (q, v) = (self.vector::<N>(q, "q")?, self.vector::<N>(v, "v")?);
            let (mm, cc, gg) = c.dynamics(&q, &v);
            row_major(&mm, m, "M")?;
            row_major(&cc, c_out, "C")?;
            copy(&gg, g, "g")
        })
    }

    /// The tool frame's pose in the world frame: `(R, p)`.
    pub fn tool_pose(&self, q: &[f64]) -> Result<(Matrix3<f64>, Vector3<f64>)> {
        on_chain!(&self.model, c, N => {
            let p = c.tool_pose(&self.vector::<N>(q, "q")?);
            Ok((p.rotation, p.translation))
        })
    }

    /// The joint coordinates that put the tool at `position` (orientation free) or, with
    /// `rotation`, at that pose, by damped least squares from `seed`
    /// ([`SerialChain::inverse_kinematics`], default settings, tolerance `tolerance` m).
    pub fn inverse_kinematics(
        &self,
        position: Vector3<f64>,
        rotation: Option<Matrix3<f64>>,
        seed: &[f64],
        tolerance: f64,
    ) -> Result<DVector<f64>> {
        on_chain!(&self.model, c, N => {
            let seed = self.vector::<N>(seed, "seed")?;
            let target = match rotation {
                Some(rotation) => pvfc_core::mechanics::IkTarget::Pose(Pose { rotation, translation: position }),
                None => pvfc_core::mechanics::IkTarget::Position(position),
            };
            let settings = pvfc_core::mechanics::IkSettings { tolerance, ..Default::default() };
            Ok(dv(&c.inverse_kinematics(&target, &seed, &settings)?))
        })
    }

    /// The manipulability of the tool's position at `q` (0 at a singularity).
    pub fn manipulability(&self, q: &[f64]) -> Result<f64> {
        on_chain!(&self.model, c, N => Ok(c.manipulability(&self.vector::<N>(q, "q")?)))
    }

    /// Every link's pose (the frames of the moving links, base to tip), then the tool's.
    pub fn link_poses(&self, q: &[f64]) -> Result<Vec<Pose<f64>>> {
        on_chain!(&self.model, c, N => {
            let k = c.kinematics(&self.vector::<N>(q, "q")?);
            let mut out: Vec<Pose<f64>> = k.link_poses.to_vec();
            out.push(k.link_poses[N - 1].compose(c.tool()));
            Ok(out)
        })
    }

    /// The tool's geometric Jacobian, rows `[linear; angular]`, in the world frame
    /// (`world = true`, Pinocchio's `LOCAL_WORLD_ALIGNED`) or the tool frame (`LOCAL`).
    pub fn jacobian(&self, q: &[f64], world: bool) -> Result<DMatrix<f64>> {
        on_chain!(&self.model, c, N => {
            let q = self.vector::<N>(q, "q")?;
            let j = if world { c.tool_jacobian_world(&q) } else { c.tool_jacobian_body(&q) };
            Ok(dm(&j))
        })
    }
}

/// Writes `x` into `out`, which must hold exactly its entries.
fn copy<const N: usize>(x: &SVector<f64, N>, out: &mut [f64], name: &str) -> Result<()> {
    if out.len() != N {
        return Err(SimError::Setting(format!(
            "{name}: room for {} entries, the robot has {N} joints",
            out.len()
        )));
    }
    out.copy_from_slice(x.as_slice());
    Ok(())
}

/// Writes the `N × N` matrix `x` into `out` row by row.
fn row_major<const N: usize>(x: &SMatrix<f64, N, N>, out: &mut [f64], name: &str) -> Result<()> {
    if out.len() != N * N {
        return Err(SimError::Setting(format!(
            "{name}: room for {} entries, the {N}-joint robot's matrix has {}",
            out.len(),
            N * N
        )));
    }
    for (i, row) in out.chunks_exact_mut(N).enumerate() {
        for (j, o) in row.iter_mut().enumerate() {
            *o = x[(i, j)];
        }
    }
    Ok(())
}

fn dm<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn dv<const N: usize>(v: &SVector<f64, N>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}
