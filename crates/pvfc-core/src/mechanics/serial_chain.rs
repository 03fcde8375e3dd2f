//! Serial chains of rigid links with revolute and prismatic joints: the arms users bring in
//! their URDF files, with the algorithms Pinocchio's users know (CRBA, RNEA, the Coriolis
//! matrix, gravity, forward kinematics, Jacobians).

use super::spatial::{
    force_cross_apply, force_cross_bar, Pose, RigidInertia, Spatial, Spatial6, WorldInertia,
};
use super::{LawProducts, MechanicalSystem};
use crate::contour::VectorGroup;
use crate::error::{Error, ErrorKind, Result};
use crate::lie::{JointKind, JointSpace, Tangent};
use crate::scalar::cast;
use crate::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// One joint of a [`SerialChain`]: its kind, the pose of the joint frame in the parent link's
/// frame at `q = 0` (URDF `<origin>`), and its axis in the joint frame (URDF `<axis>`).
/// The child link's frame is the joint frame moved by `q` about (revolute) or along
/// (prismatic) the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainJoint<T: Real> {
    /// Revolute/continuous (circular) or prismatic (linear).
    pub kind: JointKind,
    /// The joint frame in the parent link's frame at `q = 0`.
    pub origin: Pose<T>,
    /// The joint axis in the joint frame (normalised by [`SerialChain::new`]).
    pub axis: Vector3<T>,
}

/// The world-frame kinematics of a chain at one configuration: every link's pose and every
/// joint's spatial axis `S_i = [a_i; p_i × a_i]` (revolute) or `[0; a_i]` (prismatic).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainKinematics<T: Real, const N: usize> {
    /// The pose of link `i`'s frame in the base frame.
    pub link_poses: [Pose<T>; N],
    /// The spatial axis of joint `i` in the base frame, `[angular; linear]`.
    pub axes: [Spatial<T>; N],
}

/// A fully actuated serial chain of `N` rigid links, each moved by one revolute or prismatic
/// joint, with an optional tool frame on the last link and gravity.
///
/// Built from plain data ([`ChainJoint`], [`RigidInertia`]), so firmware can construct it from
/// constants without a URDF parser; `pvfc-sim` reads URDF files into it.
///
/// The dynamics `M(q) q̈ + C(q, q̇) q̇ + g(q) = T + F_e` are computed in the base frame with
/// spatial algebra: `M` by the composite-rigid-body algorithm, `C` in the factorisation of
/// Echeandia & Wensing (2021), `C = Σ_i J_iᵀ(I_i J̇_i + B_i J_i)` with
/// `B_i = ½(v_i×* I_i − I_i v_i× + (I_i v_i)×̄*)`, which gives the Christoffel symbols of the
/// first kind: `C(q, v)_{jk} = Σ_l Γ_{jkl} v_l` with `Γ_{jkl} = Γ_{jlk}`, hence
/// `Ṁ = C + Cᵀ` identically (not only `Ṁ − 2C` skew), and `C v` is the Coriolis and
/// centrifugal torque of the recursive Newton–Euler algorithm ([`Self::rnea`]).
///
/// It is a [`MechanicalSystem`] on every coordinate group ([`VectorGroup`]): the mixed
/// [`JointSpace`] (see [`Self::configuration`]), the torus `Tᴺ` of an all-revolute arm, `ℝᴺ`.
///
/// ```
/// use pvfc_core::mechanics::{ChainJoint, MechanicalSystem, Pose, RigidInertia, SerialChain};
/// use pvfc_core::lie::JointKind;
/// use nalgebra::{Matrix3, Vector1, Vector3};
/// // A pendulum: a 1 kg point-like bob 0.5 m down the link, swinging about y.
/// let joint = ChainJoint {
///     kind: JointKind::Circular,
///     origin: Pose::identity(),
///     axis: Vector3::y(),
/// };
/// let bob = RigidInertia { mass: 1.0, com: Vector3::new(0.0, 0.0, -0.5), inertia: Matrix3::identity() * 1e-6 };
/// let chain: SerialChain<f64, 1> = SerialChain::new([joint], [bob]).unwrap();
/// let q = chain.configuration(Vector1::new(0.3));
/// let m = chain.inertia(&q);
/// assert!((m[(0, 0)] - (0.25 + 1e-6)).abs() < 1e-12);
/// // g(q) = m g l sin q.
/// let g = pvfc_core::mechanics::STANDARD_GRAVITY;
/// assert!((chain.gravity(&q)[0] - g * 0.5 * 0.3f64.sin()).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SerialChain<T: Real, const N: usize> {
    joints: [ChainJoint<T>; N],
    links: [RigidInertia<T>; N],
    base: Pose<T>,
    tool: Pose<T>,
    gravity: Vector3<T>,
}

/// Standard gravity, m/s².
pub const STANDARD_GRAVITY: f64 = 9.80665;

impl<T: Real, const N: usize> SerialChain<T, N> {
    /// A chain from its joints and the inertias of the links they move (each in its link's
    /// frame), with gravity `(0, 0, −9.81)` in the base frame, the base frame at the first
    /// joint's parent, and the tool frame at the last link's frame.
    ///
    /// Errors: `NonFinite` for a NaN or infinite number; `InvalidParameter` for a zero axis, a
    /// rotation that is not orthonormal, a mass ≤ 0 or an asymmetric inertia;
    /// `SingularInertia` for a rotational inertia that is not positive definite. The
    /// error's value is the index of the joint or link at fault.
    pub fn new(joints: [ChainJoint<T>; N], links: [RigidInertia<T>; N]) -> Result<Self> {
        if N == 0 {
            return Err(Error::new(
                ErrorKind::DimensionMismatch,
                "SerialChain: a chain needs at least one joint",
            ));
        }
        let mut joints = joints;
        for (i, j) in joints.iter_mut().enumerate() {
            let at = |e: Error| e.with_value(i as f64);
            check_pose(&j.origin, "SerialChain: joint origin").map_err(at)?;
            crate::error::ensure_finite(j.axis.iter(), "SerialChain: joint axis").map_err(at)?;
            let norm = j.axis.norm();
            if norm <= T::default_epsilon() {
                return Err(at(Error::new(
                    ErrorKind::InvalidParameter,
                    "SerialChain: joint axis must not be zero",
                )));
            }
            j.axis /= norm;
        }
        for (i, l) in links.iter().enumerate() {
            l.validate("SerialChain: link inertia (mass > 0, symmetric positive definite)")
                .map_err(|e| e.with_value(i as f64))?;
        }
        Ok(SerialChain {
            joints,
            links,
            base: Pose::identity(),
            tool: Pose::identity(),
            gravity: Vector3::new(T::zero(), T::zero(), -cast::<T>(STANDARD_GRAVITY)),
        })
    }

    /// The same chain with a tool frame: its pose in the last link's frame.
    pub fn with_tool(mut self, tool: Pose<T>) -> Result<Self> {
        check_pose(&tool, "SerialChain: tool pose")?;
        self.tool = tool;
        Ok(self)
    }

    /// The same chain mounted at `base` (the pose of the first joint's parent frame in the
    /// world frame, in which gravity, poses and Jacobians are written).
    pub fn with_base(mut self, base: Pose<T>) -> Result<Self> {
        check_pose(&base, "SerialChain: base pose")?;
        self.base = base;
        Ok(self)
    }

    /// The same chain under the gravity acceleration `g` (world frame, m/s²); zero for a
    /// horizontal arm.
    pub fn with_gravity(mut self, g: Vector3<T>) -> Result<Self> {
        crate::error::ensure_finite(g.iter(), "SerialChain: gravity")?;
        self.gravity = g;
        Ok(self)
    }

    /// The same chain in another scalar type (e.g. an `f32` model for a microcontroller from
    /// an `f64` one read on a host).
    pub fn cast<U: Real>(&self) -> SerialChain<U, N> {
        let c = |x: &T| cast::<U>(nalgebra::try_convert::<T, f64>(*x).unwrap_or(f64::NAN));
        let pose = |p: &Pose<T>| Pose {
            rotation: p.rotation.map(|x| c(&x)),
            translation: p.translation.map(|x| c(&x)),
        };
        SerialChain {
            joints: self.joints.map(|j| ChainJoint {
                kind: j.kind,
                origin: pose(&j.origin),
                axis: j.axis.map(|x| c(&x)),
            }),
            links: self.links.map(|l| RigidInertia {
                mass: c(&l.mass),
                com: l.com.map(|x| c(&x)),
                inertia: l.inertia.map(|x| c(&x)),
            }),
            base: pose(&self.base),
            tool: pose(&self.tool),
            gravity: self.gravity.map(|x| c(&x)),
        }
    }

    /// The joints.
    pub fn joints(&self) -> &[ChainJoint<T>; N] {
        &self.joints
    }

    /// The link inertias, each in its link's frame.
    pub fn links(&self) -> &[RigidInertia<T>; N] {
        &self.links
    }

    /// The tool frame in the last link's frame.
    pub fn tool(&self) -> &Pose<T> {
        &self.tool
    }

    /// The gravity acceleration in the world frame.
    pub fn gravity_vector(&self) -> &Vector3<T> {
        &self.gravity
    }

    /// The kind of every joint.
    pub fn kinds(&self) -> [JointKind; N] {
        self.joints.map(|j| j.kind)
    }

    /// The configuration `q` as an element of the chain's joint space `T^r × ℝ^p`.
    pub fn configuration(&self, q: SVector<T, N>) -> JointSpace<T, N> {
        JointSpace::new(q, self.kinds())
    }

    /// Forward kinematics: every link's pose and every joint's spatial axis in the world
    /// frame.
    pub fn kinematics(&self, q: &SVector<T, N>) -> ChainKinematics<T, N> {
        // Filled in the value returned (two local arrays cost two copies into it at the end).
        let mut k = ChainKinematics {
            link_poses: [Pose::identity(); N],
            axes: [Spatial::zeros(); N],
        };
        let joint = self.joint_steps(q);
        let mut parent = self.base;
        for i in 0..N {
            let (pose, s) = joint(i, &parent);
            k.link_poses[i] = pose;
            k.axes[i] = s;
            parent = pose;
        }
        k
    }

    /// The forward kinematics at `q` one joint at a time: `(i, parent's pose)` to link `i`'s
    /// pose and joint `i`'s spatial axis ([`joint_step`](Self::joint_step)), the joint's
    /// rotation by Rodrigues' formula ([`axis_angle`](super::axis_angle)).
    ///
    /// On a core that executes out of order, every joint's sine and cosine is taken first, all
    /// at once: each is a long chain of dependent operations but independent of the others, so
    /// side by side they overlap, where inside the pose recursion each would hold up the next
    /// link's pose (UR5 control step −9 % on x86-64, measured with `cargo bench --bench
    /// serial_arm`). On a bare-metal target (`target_os = "none"`: a microcontroller, in
    /// order, where nothing overlaps) each is taken where its joint needs it, which keeps the
    /// Cortex-M4F's 6-joint step within its budget (the table costs it 37 instructions). The
    /// same values either way, so the same kinematics to the bit. (A prismatic joint's sine and
    /// cosine, taken in the table, are not used.)
    #[inline(always)]
    pub(super) fn joint_steps<'a>(
        &'a self,
        q: &'a SVector<T, N>,
    ) -> impl Fn(usize, &Pose<T>) -> (Pose<T>, Spatial<T>) + 'a {
        #[cfg(not(target_os = "none"))]
        {
            let table: [(T, T); N] = core::array::from_fn(|i| q[i].sin_cos_fast());
            move |i: usize, parent: &Pose<T>| {
                self.joint_step(i, parent, q[i], |axis| {
                    super::spatial::axis_rotation(axis, table[i])
                })
            }
        }
        #[cfg(target_os = "none")]
        {
            move |i: usize, parent: &Pose<T>| {
                self.joint_step(i, parent, q[i], |axis| {
                    super::spatial::axis_angle(axis, q[i])
                })
            }
        }
    }

    /// One joint of the forward kinematics: link `i`'s pose in the base frame from its
    /// parent's, and joint `i`'s spatial axis `[a; p × a]` (revolute) or `[0; a]` (prismatic),
    /// with `rotation` giving the joint's rotation about its axis (from
    /// [`joint_steps`](Self::joint_steps)).
    #[inline(always)]
    fn joint_step(
        &self,
        i: usize,
        parent: &Pose<T>,
        qi: T,
        rotation: impl FnOnce(&Vector3<T>) -> Matrix3<T>,
    ) -> (Pose<T>, Spatial<T>) {
        let j = &self.joints[i];
        let pre = parent.compose(&j.origin);
        let a = pre.rotation * j.axis;
        let p = pre.translation;
        match j.kind {
            JointKind::Circular => (
                Pose {
                    rotation: pre.rotation * rotation(&j.axis),
                    translation: p,
                },
                spatial(a, p.cross(&a)),
            ),
            JointKind::Linear => (
                Pose {
                    rotation: pre.rotation,
                    translation: p + a * qi,
                },
                spatial(Vector3::zeros(), a),
            ),
        }
    }

    /// Whether `other` has the same forward kinematics (joints and base; the tool frame and
    /// the inertias may differ): then either one's [`kinematics`](Self::kinematics) serve
    /// both.
    pub fn same_kinematics(&self, other: &Self) -> bool {
        self.joints == other.joints && self.base == other.base
    }

    /// The base frame's pose in the world frame.
    pub(super) fn base(&self) -> &Pose<T> {
        &self.base
    }

    /// The tool frame's pose in the world frame.
    pub fn tool_pose(&self, q: &SVector<T, N>) -> Pose<T> {
        let k = self.kinematics(q);
        k.link_poses[N - 1].compose(&self.tool)
    }

    /// The tool's geometric Jacobian in the world frame, rows `[linear; angular]`: the
    /// velocity of the tool frame's origin and the angular velocity, both in world axes
    /// (Pinocchio's `LOCAL_WORLD_ALIGNED`).
    pub fn tool_jacobian_world(&self, q: &SVector<T, N>) -> SMatrix<T, 6, N> {
        let k = self.kinematics(q);
        let x = k.link_poses[N - 1].compose(&self.tool).translation;
        let mut jac = SMatrix::<T, 6, N>::zeros();
        for (i, s) in k.axes.iter().enumerate() {
            let w = Vector3::new(s[0], s[1], s[2]);
            let lin = Vector3::new(s[3], s[4], s[5]) + w.cross(&x);
            jac.fixed_view_mut::<3, 1>(0, i).copy_from(&lin);
            jac.fixed_view_mut::<3, 1>(3, i).copy_from(&w);
        }
        jac
    }

    /// The tool's geometric Jacobian in the tool frame, rows `[linear; angular]`
    /// (Pinocchio's `LOCAL`).
    pub fn tool_jacobian_body(&self, q: &SVector<T, N>) -> SMatrix<T, 6, N> {
        let rt = self.tool_pose(q).rotation.transpose();
        let world = self.tool_jacobian_world(q);
        let mut jac = SMatrix::<T, 6, N>::zeros();
        for i in 0..N {
            let lin: Vector3<T> = rt * world.fixed_view::<3, 1>(0, i);
            let ang: Vector3<T> = rt * world.fixed_view::<3, 1>(3, i);
            jac.fixed_view_mut::<3, 1>(0, i).copy_from(&lin);
            jac.fixed_view_mut::<3, 1>(3, i).copy_from(&ang);
        }
        jac
    }

    /// The spatial inertias of the links in the world frame.
    /// (Written in place: returning the array by value cost a 6-joint f32 step ~3,000
    /// instructions of copies on a Cortex-M4, measured.)
    #[inline(always)]
    fn world_inertias(&self, k: &ChainKinematics<T, N>, out: &mut [Spatial6<T>; N]) {
        for ((o, l), pose) in out.iter_mut().zip(&self.links).zip(&k.link_poses) {
            *o = l.transformed(pose).spatial();
        }
    }

    /// The spatial acceleration standing for gravity, `[0; −g]` (Featherstone's trick: the
    /// base accelerates upwards).
    fn gravity_acceleration(&self) -> Spatial<T> {
        spatial(Vector3::zeros(), -self.gravity)
    }

    /// RNEA's forward pass: each link's spatial force `I a + v ×* I v` at the joint rates `v`
    /// and accelerations `a`, gravity included (written in place, as `world_inertias`).
    fn link_forces(
        &self,
        k: &ChainKinematics<T, N>,
        v: &SVector<T, N>,
        a: &SVector<T, N>,
        forces: &mut [Spatial<T>; N],
    ) {
        let mut vel = Spatial::zeros();
        let mut acc = self.gravity_acceleration();
        for i in 0..N {
            let s = k.axes[i];
            let inertia = WorldInertia::of(&self.links[i], &k.link_poses[i]);
            vel += s * v[i];
            acc += motion_cross_apply(&vel, &s) * v[i] + s * a[i];
            forces[i] = inertia.apply(&acc) + force_cross_apply(&vel, &inertia.apply(&vel));
        }
    }

    /// The recursive Newton–Euler algorithm: the joint torques `M q̈ + C q̇ + g` that produce
    /// the accelerations `a` at the state `(q, v)`, gravity included.
    pub fn rnea(&self, q: &SVector<T, N>, v: &SVector<T, N>, a: &SVector<T, N>) -> SVector<T, N> {
        let k = self.kinematics(q);
        let mut forces = [Spatial::zeros(); N];
        self.link_forces(&k, v, a, &mut forces);
        let mut tau = SVector::zeros();
        let mut f = Spatial::zeros();
        for i in (0..N).rev() {
            f += forces[i];
            tau[i] = k.axes[i].dot(&f);
        }
        tau
    }

    /// `M(q)` and the bias `h(q, v) = C(q, v) v + g(q)` over one kinematics pass: the
    /// composite-rigid-body algorithm for `M` and the recursive Newton–Euler algorithm at
    /// `q̈ = 0` for `h` (what the forward dynamics needs, without forming `C`).
    pub fn mass_and_bias(
        &self,
        q: &SVector<T, N>,
        v: &SVector<T, N>,
    ) -> (SMatrix<T, N, N>, SVector<T, N>) {
        let k = self.kinematics(q);
        let mut forces = [Spatial::zeros(); N];
        self.link_forces(&k, v, &SVector::zeros(), &mut forces);
        let mut m = SMatrix::<T, N, N>::zeros();
        let mut h = SVector::zeros();
        let mut ic = WorldInertia::zeros();
        let mut f = Spatial::zeros();
        for j in (0..N).rev() {
            ic += WorldInertia::of(&self.links[j], &k.link_poses[j]);
            f += forces[j];
            h[j] = k.axes[j].dot(&f);
            let ics = ic.apply(&k.axes[j]);
            for i in 0..=j {
                let mij = k.axes[i].dot(&ics);
                m[(i, j)] = mij;
                m[(j, i)] = mij;
            }
        }
        (m, h)
    }

    /// `M(q)`, `C(q, v)` and `g(q)` in one pass (see the type's documentation).
    pub fn dynamics(
        &self,
        q: &SVector<T, N>,
        v: &SVector<T, N>,
    ) -> (SMatrix<T, N, N>, SMatrix<T, N, N>, SVector<T, N>) {
        let k = self.kinematics(q);
        let mut inertias = [Spatial6::zeros(); N];
        self.world_inertias(&k, &mut inertias);
        let half: T = cast(0.5);
        // Forward: the links' velocities, the axes' rates Ṡ_i = v_i × S_i and B_i.
        let mut axis_rates = [Spatial::zeros(); N];
        let mut b = [Spatial6::zeros(); N];
        let mut vel = Spatial::zeros();
        for i in 0..N {
            vel += k.axes[i] * v[i];
            axis_rates[i] = motion_cross_apply(&vel, &k.axes[i]);
            let iv = inertias[i] * vel;
            // B_i = ½(v×* I − I v×) + ½(I v)×̄*, and v×* I = −(v×)ᵀ I = −(I v×)ᵀ (I symmetric).
            let ivx = inertia_times_motion_cross(&inertias[i], &vel);
            b[i] = (ivx + ivx.transpose()) * (-half) + force_cross_bar(&iv) * half;
        }
        // Backward: composite inertias I^c_i = Σ_{l ≥ i} I_l and B^c_i likewise.
        let mut m = SMatrix::<T, N, N>::zeros();
        let mut c = SMatrix::<T, N, N>::zeros();
        let mut g = SVector::<T, N>::zeros();
        let mut ic = Spatial6::zeros();
        let mut bc = Spatial6::zeros();
        let a0 = self.gravity_acceleration();
        for j in (0..N).rev() {
            ic += inertias[j];
            bc += b[j];
            let s = k.axes[j];
            let ics = ic * s;
            // Column/row j against every joint i ≤ j: M_ij = S_iᵀ I^c_j S_j.
            let f = ic * axis_rates[j] + bc * s;
            let bts = bc.transpose() * s;
            for i in 0..=j {
                let mij = k.axes[i].dot(&ics);
                m[(i, j)] = mij;
                m[(j, i)] = mij;
                // C_ij (i ≤ j) = S_iᵀ (I^c_j Ṡ_j + B^c_j S_j).
                c[(i, j)] = k.axes[i].dot(&f);
                if i < j {
                    // C_ji (j > i) = S_jᵀ (I^c_j Ṡ_i + B^c_j S_i).
                    c[(j, i)] = ics.dot(&axis_rates[i]) + bts.dot(&k.axes[i]);
                }
            }
            g[j] = ics.dot(&a0);
        }
        (m, c, g)
    }

    /// `M(q)` alone, by the composite-rigid-body algorithm (CRBA):
    /// `M_ij = S_iᵀ I^c_j S_j` for `i ≤ j`.
    pub fn crba(&self, q: &SVector<T, N>) -> SMatrix<T, N, N> {
        let k = self.kinematics(q);
        let mut m = SMatrix::<T, N, N>::zeros();
        let mut ic = WorldInertia::zeros();
        for j in (0..N).rev() {
            ic += WorldInertia::of(&self.links[j], &k.link_poses[j]);
            let ics = ic.apply(&k.axes[j]);
            for i in 0..=j {
                let mij = k.axes[i].dot(&ics);
                m[(i, j)] = mij;
                m[(j, i)] = mij;
            }
        }
        m
    }

    /// `g(q)`, the torques that hold the chain still against gravity: `g_j = S_jᵀ I^c_j a_0`
    /// with `a_0 = [0; −g]`, which needs of the composite inertia only its mass and first
    /// moment, `I^c a_0 = [h × (−g); −m g]`.
    pub fn gravity_torque(&self, q: &SVector<T, N>) -> SVector<T, N> {
        let k = self.kinematics(q);
        let up = -self.gravity;
        let mut g = SVector::zeros();
        let (mut mass, mut moment) = (T::zero(), Vector3::zeros());
        for j in (0..N).rev() {
            let l = &self.links[j];
            mass += l.mass;
            moment += k.link_poses[j].transform_point(&l.com) * l.mass;
            g[j] = k.axes[j].dot(&spatial(moment.cross(&up), up * mass));
        }
        g
    }
}

impl<T: Real, G: VectorGroup<T, N>, const N: usize> MechanicalSystem<T, G, N>
    for SerialChain<T, N>
{
    const HAS_GRAVITY: bool = true;

    fn inertia(&self, q: &G) -> SMatrix<T, N, N> {
        self.crba(&q.coordinates())
    }

    fn coriolis(&self, q: &G, v: &Tangent<T, N>) -> SMatrix<T, N, N> {
        self.dynamics(&q.coordinates(), v).1
    }

    #[inline]
    fn inertia_and_coriolis(
        &self,
        q: &G,
        v: &Tangent<T, N>,
    ) -> (SMatrix<T, N, N>, SMatrix<T, N, N>) {
        let (m, c, _) = self.dynamics(&q.coordinates(), v);
        (m, c)
    }

    fn gravity(&self, q: &G) -> Tangent<T, N> {
        self.gravity_torque(&q.coordinates())
    }

    #[inline]
    fn inertia_coriolis_gravity(
        &self,
        q: &G,
        v: &Tangent<T, N>,
    ) -> (SMatrix<T, N, N>, SMatrix<T, N, N>, Tangent<T, N>) {
        self.dynamics(&q.coordinates(), v)
    }

    #[inline]
    fn law_products(
        &self,
        q: &G,
        v: &Tangent<T, N>,
        x: &Tangent<T, N>,
        a: &Tangent<T, N>,
        with_gravity: bool,
    ) -> LawProducts<T, N> {
        SerialChain::law_products(self, &q.coordinates(), v, x, a, with_gravity)
    }

    /// The forward dynamics `q̈ = M⁻¹ (T + F_e − h)` with `M` and `h = C v + g` from
    /// [`mass_and_bias`](SerialChain::mass_and_bias) (Cholesky; no allocation).
    fn acceleration(
        &self,
        q: &G,
        v: &Tangent<T, N>,
        force: &Tangent<T, N>,
    ) -> Result<Tangent<T, N>> {
        let (m, h) = self.mass_and_bias(&q.coordinates(), v);
        super::solve_acceleration(&m, force - h)
    }

    #[inline]
    fn serial_chain(&self) -> Option<&SerialChain<T, N>> {
        Some(self)
    }

    #[inline]
    fn chain_kinematics(&self, q: &G) -> Option<ChainKinematics<T, N>> {
        Some(self.kinematics(&q.coordinates()))
    }

    #[inline]
    fn law_products_with_kinematics(
        &self,
        kinematics: &ChainKinematics<T, N>,
        _q: &G,
        v: &Tangent<T, N>,
        x: &Tangent<T, N>,
        a: &Tangent<T, N>,
        with_gravity: bool,
    ) -> LawProducts<T, N> {
        SerialChain::law_products_with_kinematics(self, kinematics, v, x, a, with_gravity)
    }
}

/// `v × m` for spatial motion vectors (Featherstone eq. 2.31), without forming `v×`.
#[inline]
fn motion_cross_apply<T: Real>(v: &Spatial<T>, m: &Spatial<T>) -> Spatial<T> {
    let (w, u) = (v.fixed_rows::<3>(0), v.fixed_rows::<3>(3));
    let (mw, mu) = (m.fixed_rows::<3>(0), m.fixed_rows::<3>(3));
    spatial(w.cross(&mw), w.cross(&mu) + u.cross(&mw))
}

/// `I (v×)` for a spatial inertia `I = [[A, B], [C, D]]` and `v× = [[W, 0], [U, W]]`:
/// `[[A W + B U, B W], [C W + D U, D W]]`, four 3×3 products instead of a 6×6 one.
#[inline]
fn inertia_times_motion_cross<T: Real>(inertia: &Spatial6<T>, v: &Spatial<T>) -> Spatial6<T> {
    let w = Vector3::new(v[0], v[1], v[2]).cross_matrix();
    let u = Vector3::new(v[3], v[4], v[5]).cross_matrix();
    let a = inertia.fixed_view::<3, 3>(0, 0);
    let b = inertia.fixed_view::<3, 3>(0, 3);
    let c = inertia.fixed_view::<3, 3>(3, 0);
    let d = inertia.fixed_view::<3, 3>(3, 3);
    let mut out = Spatial6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(a * w + b * u));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(b * w));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(c * w + d * u));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&(d * w));
    out
}

#[inline]
fn spatial<T: Real>(angular: Vector3<T>, linear: Vector3<T>) -> Spatial<T> {
    Spatial::new(
        angular[0], angular[1], angular[2], linear[0], linear[1], linear[2],
    )
}

fn check_pose<T: Real>(pose: &Pose<T>, context: &'static str) -> Result<()> {
    if !pose.is_finite() {
        return Err(Error::new(ErrorKind::NonFinite, context));
    }
    let r = &pose.rotation;
    let off = (r.transpose() * r - Matrix3::identity()).amax();
    if off > cast(1e-5) || r.determinant() <= T::zero() {
        return Err(Error::new(ErrorKind::InvalidParameter, context));
    }
    Ok(())
}
