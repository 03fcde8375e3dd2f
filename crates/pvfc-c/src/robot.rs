//! The robot handle: a serial arm read from URDF, and its dynamics.

use crate::args::*;
use crate::status::*;
use pvfc_control::model::robot::Robot;
use pvfc_control::urdf::ChainDescription;
use std::ffi::c_char;
use std::path::Path;

/// A serial arm read from URDF (opaque).
pub struct pvfc_robot {
    pub(crate) robot: Robot,
}

/// Reads a serial arm from the URDF file `path`: `base` and `tip` name its base and tip links
/// (NULL: the URDF's root, and its only leaf).
///
/// # Safety
/// `path` is a NUL-terminated string; `base`, `tip` are NULL or such strings; `out` is
/// writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_from_urdf_file(
    path: *const c_char,
    base: *const c_char,
    tip: *const c_char,
    out: *mut *mut pvfc_robot,
) -> pvfc_status {
    guard(|| {
        // SAFETY: strings and out as documented.
        let path = unsafe { text(path, "path") }?.ok_or_else(|| null("path"))?;
        let (base, tip) = unsafe { (text(base, "base")?, text(tip, "tip")?) };
        let robot = Robot::from_urdf(Path::new(path), base, tip)?;
        unsafe { give(out, pvfc_robot { robot }) }
    })
}

/// Reads a serial arm from the text of a URDF (`name` names it in error messages; NULL:
/// "urdf").
///
/// # Safety
/// `urdf` is a NUL-terminated string; `name`, `base`, `tip` are NULL or such strings; `out`
/// is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_from_urdf_string(
    urdf: *const c_char,
    name: *const c_char,
    base: *const c_char,
    tip: *const c_char,
    out: *mut *mut pvfc_robot,
) -> pvfc_status {
    guard(|| {
        // SAFETY: strings and out as documented.
        let urdf = unsafe { text(urdf, "urdf") }?.ok_or_else(|| null("urdf"))?;
        let name = unsafe { text(name, "name") }?.unwrap_or("urdf");
        let (base, tip) = unsafe { (text(base, "base")?, text(tip, "tip")?) };
        let d = ChainDescription::from_str(urdf, Path::new(name), base, tip)?;
        let robot = Robot::from_description(d)?;
        unsafe { give(out, pvfc_robot { robot }) }
    })
}

/// One joint of a serial arm given as numbers, and the link it moves (URDF's conventions:
/// the joint's frame in its parent link's frame, then the link's inertial in the joint's
/// frame).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct pvfc_joint_spec {
    /// 0: revolute (continuous when `lower == upper == 0`), 1: prismatic.
    pub prismatic: bool,
    /// The joint frame's position in the parent link's frame (m).
    pub origin_xyz: [f64; 3],
    /// The joint frame's roll, pitch, yaw in the parent link's frame (rad).
    pub origin_rpy: [f64; 3],
    /// The joint's axis in its own frame (normalised by the library).
    pub axis: [f64; 3],
    /// The lower limit (rad or m).
    pub lower: f64,
    /// The upper limit (rad or m).
    pub upper: f64,
    /// The link's mass (kg, > 0).
    pub mass: f64,
    /// The link's centre of mass in the joint's frame (m).
    pub com: [f64; 3],
    /// The link's rotational inertia about its centre of mass, in the joint frame's axes:
    /// `ixx, ixy, ixz, iyy, iyz, izz` (kg·m²).
    pub inertia: [f64; 6],
}

/// Makes a serial arm of `n` joints from numbers: `joints[0]` is attached to the base, each
/// next one to the link before; the tool frame sits at `tool_xyz`, `tool_rpy` (3 doubles
/// each; NULL: zeros) in the last link's frame. The same checks as a URDF's apply (an error
/// names the joint, `joint{i}`, or link, `link{i}`). Gravity is `−9.80665 m/s²` along the
/// base's z.
///
/// # Safety
/// `joints` holds `n` readable specs; `tool_xyz`, `tool_rpy` are NULL or hold 3 doubles;
/// `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_from_arrays(
    joints: *const pvfc_joint_spec,
    n: usize,
    tool_xyz: *const f64,
    tool_rpy: *const f64,
    out: *mut *mut pvfc_robot,
) -> pvfc_status {
    guard(|| {
        if joints.is_null() {
            return Err(null("joints"));
        }
        // SAFETY: n readable specs, as documented.
        let specs = unsafe { std::slice::from_raw_parts(joints, n) };
        // SAFETY: NULL or 3 readable doubles, as documented.
        let three = |p: *const f64, name: &'static str| -> Result<[f64; 3], Failure> {
            Ok(unsafe { triple(p, name) }?.unwrap_or([0.0; 3]))
        };
        let urdf = urdf_of(
            specs,
            three(tool_xyz, "tool_xyz")?,
            three(tool_rpy, "tool_rpy")?,
        )?;
        let d = ChainDescription::from_str(&urdf, Path::new("arrays"), Some("base"), Some("tool"))?;
        let robot = Robot::from_description(d)?;
        unsafe { give(out, pvfc_robot { robot }) }
    })
}

/// The URDF of a chain given as numbers (every number written exactly: Rust's shortest
/// round-trip form), so that an arm from arrays takes the one path every arm takes.
fn urdf_of(
    specs: &[pvfc_joint_spec],
    tool_xyz: [f64; 3],
    tool_rpy: [f64; 3],
) -> Result<String, Failure> {
    use std::fmt::Write;
    let v3 = |x: &[f64; 3]| format!("{:?} {:?} {:?}", x[0], x[1], x[2]);
    let mut u = String::from("<robot name=\"arrays\">\n  <link name=\"base\"/>\n");
    for (i, j) in specs.iter().enumerate() {
        let scalars = [j.lower, j.upper, j.mass];
        let mut numbers = j
            .origin_xyz
            .iter()
            .chain(&j.origin_rpy)
            .chain(&j.axis)
            .chain(&scalars)
            .chain(&j.com)
            .chain(&j.inertia);
        if let Some(x) = numbers.find(|x| !x.is_finite()) {
            return Err(Failure(
                PVFC_ERROR_NON_FINITE,
                format!("joints[{i}]: a number is {x}").into(),
            ));
        }
        let kind = match (j.prismatic, j.lower == 0.0 && j.upper == 0.0) {
            (true, _) => "prismatic",
            (false, true) => "continuous",
            (false, false) => "revolute",
        };
        let parent = if i == 0 {
            "base".to_string()
        } else {
            format!("link{}", i - 1)
        };
        let limit = if kind == "continuous" {
            String::new()
        } else {
            format!(
                "    <limit lower=\"{:?}\" upper=\"{:?}\" effort=\"0\" velocity=\"0\"/>\n",
                j.lower, j.upper
            )
        };
        let _ = write!(
            u,
            "  <joint name=\"joint{i}\" type=\"{kind}\">\n    <parent link=\"{parent}\"/>\n    \
             <child link=\"link{i}\"/>\n    <origin xyz=\"{}\" rpy=\"{}\"/>\n    \
             <axis xyz=\"{}\"/>\n{limit}  </joint>\n  <link name=\"link{i}\">\n    <inertial>\n      \
             <origin xyz=\"{}\" rpy=\"0 0 0\"/>\n      <mass value=\"{:?}\"/>\n      \
             <inertia ixx=\"{:?}\" ixy=\"{:?}\" ixz=\"{:?}\" iyy=\"{:?}\" iyz=\"{:?}\" izz=\"{:?}\"/>\n    \
             </inertial>\n  </link>\n",
            v3(&j.origin_xyz),
            v3(&j.origin_rpy),
            v3(&j.axis),
            v3(&j.com),
            j.mass,
            j.inertia[0],
            j.inertia[1],
            j.inertia[2],
            j.inertia[3],
            j.inertia[4],
            j.inertia[5],
        );
    }
    let last = match specs.len() {
        0 => "base".to_string(),
        n => format!("link{}", n - 1),
    };
    let _ = write!(
        u,
        "  <joint name=\"tool_joint\" type=\"fixed\">\n    <parent link=\"{last}\"/>\n    \
         <child link=\"tool\"/>\n    <origin xyz=\"{}\" rpy=\"{}\"/>\n  </joint>\n  \
         <link name=\"tool\"/>\n</robot>\n",
        v3(&tool_xyz),
        v3(&tool_rpy)
    );
    Ok(u)
}

/// The number of joints of `robot` (0 for NULL).
///
/// # Safety
/// `robot` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_dof(robot: *const pvfc_robot) -> usize {
    // SAFETY: NULL or a live handle.
    unsafe { robot.as_ref() }.map_or(0, |r| r.robot.dof())
}

/// A joint vector of `robot` as a slice (NULL, a wrong length or NaN: an error).
///
/// # Safety
/// `p` holds `n` readable doubles.
unsafe fn state<'a>(
    r: &Robot,
    p: *const f64,
    n: usize,
    name: &'static str,
) -> Result<&'a [f64], Failure> {
    if p.is_null() {
        return Err(null(name));
    }
    // SAFETY: forwarded from the caller.
    unsafe { joints(p, n, r.dof(), name) }
}

/// The caller's room for an `n × n` matrix.
///
/// # Safety
/// `p` is NULL or has room for `len` doubles.
unsafe fn matrix<'a>(
    r: &Robot,
    p: *mut f64,
    len: usize,
    name: &'static str,
) -> Result<&'a mut [f64], Failure> {
    let n = r.dof();
    if !p.is_null() && len != n * n {
        return Err(Failure::argument(
            PVFC_ERROR_WRONG_SIZE,
            name,
            Fault::MatrixRoom { n: len, dof: n },
        ));
    }
    // SAFETY: forwarded from the caller.
    unsafe { output(p, len, n * n, name) }
}

/// The joint-space inertia `M(q)` (composite rigid body algorithm, CRBA) into `m_out`
/// (`m_len` = dof², row-major). Allocates nothing.
///
/// # Safety
/// `robot` is NULL or a live handle; `q` holds `n` doubles; `m_out` has room for `m_len`.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_inertia(
    robot: *const pvfc_robot,
    q: *const f64,
    n: usize,
    m_out: *mut f64,
    m_len: usize,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let r = &unsafe { object(robot, "robot") }?.robot;
        let q = unsafe { state(r, q, n, "q") }?;
        let m = unsafe { matrix(r, m_out, m_len, "m_out") }?;
        Ok(r.inertia_into(q, m)?)
    })
}

/// The gravity torque `g(q)` into `g_out` (`n` = dof). Allocates nothing.
///
/// # Safety
/// `robot` is NULL or a live handle; `q` holds `n` doubles; `g_out` has room for `n`.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_gravity(
    robot: *const pvfc_robot,
    q: *const f64,
    n: usize,
    g_out: *mut f64,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let r = &unsafe { object(robot, "robot") }?.robot;
        let q = unsafe { state(r, q, n, "q") }?;
        let g = unsafe { output(g_out, n, r.dof(), "g_out") }?;
        Ok(r.gravity_into(q, g)?)
    })
}

/// Inverse dynamics by the recursive Newton–Euler algorithm (RNEA): `M(q) a + C(q, v) v +
/// g(q)` into `tau_out` (`n` = dof each). Allocates nothing.
///
/// # Safety
/// `robot` is NULL or a live handle; `q`, `v`, `a` hold `n` doubles; `tau_out` has room for
/// `n`.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_rnea(
    robot: *const pvfc_robot,
    q: *const f64,
    v: *const f64,
    a: *const f64,
    n: usize,
    tau_out: *mut f64,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let r = &unsafe { object(robot, "robot") }?.robot;
        let (q, v, a) = unsafe {
            (
                state(r, q, n, "q")?,
                state(r, v, n, "v")?,
                state(r, a, n, "a")?,
            )
        };
        let tau = unsafe { output(tau_out, n, r.dof(), "tau_out") }?;
        Ok(r.rnea_into(q, v, a, tau)?)
    })
}

/// `M(q)`, the Coriolis matrix `C(q, v)` (with `Ṁ = C + Cᵀ`, the factorisation PVFC's
/// passivity rests on) and `g(q)` in one pass over the chain: `m_out`, `c_out` (dof²,
/// row-major) and `g_out` (dof). Allocates nothing.
///
/// # Safety
/// `robot` is NULL or a live handle; `q`, `v` hold `n` doubles; `m_out`, `c_out` have room
/// for `n × n` doubles and `g_out` for `n`.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_dynamics(
    robot: *const pvfc_robot,
    q: *const f64,
    v: *const f64,
    n: usize,
    m_out: *mut f64,
    c_out: *mut f64,
    g_out: *mut f64,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let r = &unsafe { object(robot, "robot") }?.robot;
        let (q, v) = unsafe { (state(r, q, n, "q")?, state(r, v, n, "v")?) };
        let nn = n * n;
        let m = unsafe { matrix(r, m_out, nn, "m_out") }?;
        let c = unsafe { matrix(r, c_out, nn, "c_out") }?;
        let g = unsafe { output(g_out, n, r.dof(), "g_out") }?;
        Ok(r.dynamics_into(q, v, m, c, g)?)
    })
}

/// The tool frame's pose at `q` (`n` = dof): its rotation into `rotation_out` (9 doubles,
/// row-major) and its position into `position_out` (3 doubles, m), in the base frame. Either
/// output may be NULL. Allocates nothing.
///
/// # Safety
/// `robot` is NULL or a live handle; `q` holds `n` doubles; the outputs are NULL or have room
/// for 9 and 3 doubles.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_tool_pose(
    robot: *const pvfc_robot,
    q: *const f64,
    n: usize,
    rotation_out: *mut f64,
    position_out: *mut f64,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let r = &unsafe { object(robot, "robot") }?.robot;
        let q = unsafe { state(r, q, n, "q") }?;
        let (rotation, position) = r.tool_pose(q)?;
        if !rotation_out.is_null() {
            // SAFETY: room for 9 doubles.
            let o = unsafe { std::slice::from_raw_parts_mut(rotation_out, 9) };
            for (i, row) in o.chunks_exact_mut(3).enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x = rotation[(i, j)];
                }
            }
        }
        if !position_out.is_null() {
            // SAFETY: room for 3 doubles.
            unsafe { std::slice::from_raw_parts_mut(position_out, 3) }
                .copy_from_slice(position.as_slice());
        }
        Ok(())
    })
}

/// Sets the robot's tool centre point (TCP): its position `xyz` (m) and orientation `rpy`
/// (roll, pitch, yaw in rad about the fixed axes, URDF's convention) in the tip link's frame
/// (NULL: zeros), replacing the one it had; gravity is kept. Tool poses, contours and
/// controllers made from the robot afterwards use the TCP; those made before keep the tool
/// they were made with. On an error (a non-finite number: `PVFC_ERROR_NON_FINITE`) the robot is unchanged.
///
/// # Safety
/// `robot` is NULL or a live handle not used by another thread meanwhile; `xyz`, `rpy` are
/// NULL or hold 3 doubles.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_set_tool(
    robot: *mut pvfc_robot,
    xyz: *const f64,
    rpy: *const f64,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let r = unsafe { object_mut(robot, "robot") }?;
        let spec = pvfc_control::model::pose::PoseSpec {
            xyz: unsafe { triple(xyz, "xyz") }?.unwrap_or([0.0; 3]),
            rpy: unsafe { triple(rpy, "rpy") }?.unwrap_or([0.0; 3]),
        };
        let tcp = spec.pose("tool")?;
        r.robot = r.robot.clone().with_tool(tcp)?;
        Ok(())
    })
}

/// Frees a robot (NULL: nothing).
///
/// # Safety
/// `robot` is NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn pvfc_robot_destroy(robot: *mut pvfc_robot) {
    if !robot.is_null() {
        // SAFETY: a handle made by Box::into_raw in this library, freed once.
        drop(unsafe { Box::from_raw(robot) });
    }
}
