//! The robot handle: a serial arm read from URDF, and its dynamics.

use crate::args::*;
use crate::status::*;
use pvfc_sim::model::robot::Robot;
use pvfc_sim::urdf::ChainDescription;
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
unsafe fn state<'a>(r: &Robot, p: *const f64, n: usize, name: &str) -> Result<&'a [f64], Failure> {
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
    name: &str,
) -> Result<&'a mut [f64], Failure> {
    let n = r.dof();
    if !p.is_null() && len != n * n {
        return Err(Failure(
            PVFC_ERROR_WRONG_SIZE,
            format!(
                "{name}: room for {len} entries, the {n}-joint robot's matrix has {}",
                n * n
            ),
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
