//! pvfc from C and C++: a C ABI over the arm controllers of `pvfc-sim`, for a robot read from
//! URDF and a closed joint-space contour through waypoints, in the continuous-time form and
//! in the passive digital form (`pvfc_core::passive`). The header `include/pvfc.h` is
//! generated from this crate by cbindgen (a test checks it is fresh).
//!
//! Conventions of every function:
//! * it returns a [`pvfc_status`]; on an error, [`pvfc_last_error`] gives the message (per
//!   thread), naming the argument, joint, link or waypoint, and nothing the function was to
//!   change has changed;
//! * objects are opaque handles made by a `pvfc_*_new*` function and freed by its
//!   `pvfc_*_destroy` (which accepts NULL);
//! * arrays are a pointer and a length, checked against the robot's number of joints; a NULL
//!   pointer, a wrong length or a NaN/Inf is an error code, never undefined behaviour;
//! * no Rust panic crosses the boundary (it becomes [`pvfc_status::PVFC_ERROR_INTERNAL`]);
//! * the step functions allocate nothing, take no lock and make no system call.

// The C ABI is unsafe by nature: raw pointers from the caller, checked before use.
#![allow(unsafe_code)]
// The C names (`pvfc_robot`, `pvfc_status`, `PVFC_OK`) are those of the header.
#![allow(non_camel_case_types)]

use pvfc_core::ErrorKind;
use pvfc_sim::model::arm::{
    ArmController, ArmSettings, JointContourSpec, PassiveArm, PassiveOptions,
};
use pvfc_sim::model::arm_field::FieldSpec;
use pvfc_sim::model::robot::Robot;
use pvfc_sim::urdf::ChainDescription;
use pvfc_sim::SimError;
use std::cell::RefCell;
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// What a function did: `PVFC_OK`, or the kind of error ([`pvfc_last_error`] has the message).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum pvfc_status {
    /// Done.
    PVFC_OK = 0,
    /// A pointer that must not be NULL was.
    PVFC_ERROR_NULL_POINTER = 1,
    /// An array's length (or a struct's `size`) does not match.
    PVFC_ERROR_WRONG_SIZE = 2,
    /// An input was NaN or infinite.
    PVFC_ERROR_NON_FINITE = 3,
    /// An argument or setting is out of its range.
    PVFC_ERROR_INVALID_ARGUMENT = 4,
    /// A file could not be read.
    PVFC_ERROR_IO = 5,
    /// A URDF is malformed or not a serial chain (the message names the element).
    PVFC_ERROR_URDF = 6,
    /// A waypoint of a Cartesian path is unreachable, singular, beyond a joint limit or on
    /// another branch.
    PVFC_ERROR_WAYPOINT = 7,
    /// The energy level `Ē` is too low for the velocity field at this state (eq. 6).
    PVFC_ERROR_ENERGY_TOO_LOW = 8,
    /// A numerical failure (a singular inertia matrix, no convergence).
    PVFC_ERROR_NUMERICAL = 9,
    /// A bug in pvfc (a caught panic): please report it with the message.
    PVFC_ERROR_INTERNAL = 10,
}

use pvfc_status::*;

/// An error on its way to the caller: its status and message.
struct Failure(pvfc_status, String);

impl From<SimError> for Failure {
    fn from(e: SimError) -> Self {
        let status = match &e {
            SimError::Core(c) => match c.kind() {
                ErrorKind::NonFinite => PVFC_ERROR_NON_FINITE,
                ErrorKind::EnergyTooLow => PVFC_ERROR_ENERGY_TOO_LOW,
                ErrorKind::DimensionMismatch => PVFC_ERROR_WRONG_SIZE,
                ErrorKind::SingularInertia | ErrorKind::NoConvergence => PVFC_ERROR_NUMERICAL,
                _ => PVFC_ERROR_INVALID_ARGUMENT,
            },
            SimError::Io { .. } => PVFC_ERROR_IO,
            SimError::Urdf { .. } => PVFC_ERROR_URDF,
            SimError::Waypoint { .. } => PVFC_ERROR_WAYPOINT,
            _ => PVFC_ERROR_INVALID_ARGUMENT,
        };
        Failure(status, e.to_string())
    }
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    let c = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// Runs `f`, turning its error, or a panic, into a status and the thread's last error.
fn guard(f: impl FnOnce() -> Result<(), Failure>) -> pvfc_status {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => PVFC_OK,
        Ok(Err(Failure(status, message))) => {
            set_last_error(&message);
            status
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            set_last_error(&format!("internal error (a bug in pvfc): {what}"));
            PVFC_ERROR_INTERNAL
        }
    }
}

fn null(name: &str) -> Failure {
    Failure(PVFC_ERROR_NULL_POINTER, format!("{name}: NULL pointer"))
}

/// The `n` doubles at `p`, checked: not NULL (unless `n` is 0) and finite.
///
/// # Safety
/// `p` must point to `n` readable doubles that outlive the returned slice.
unsafe fn doubles<'a>(p: *const f64, n: usize, name: &str) -> Result<&'a [f64], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(null(name));
    }
    // SAFETY: the caller gives n readable doubles at p (the header documents it).
    let x = unsafe { std::slice::from_raw_parts(p, n) };
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(Failure(
            PVFC_ERROR_NON_FINITE,
            format!("{name}[{i}] is {}", x[i]),
        ));
    }
    Ok(x)
}

/// The doubles of a joint vector: exactly `dof` of them.
///
/// # Safety
/// As [`doubles`].
unsafe fn joints<'a>(
    p: *const f64,
    n: usize,
    dof: usize,
    name: &str,
) -> Result<&'a [f64], Failure> {
    if n != dof {
        return Err(Failure(
            PVFC_ERROR_WRONG_SIZE,
            format!("{name}: {n} entries for the {dof}-joint robot"),
        ));
    }
    // SAFETY: forwarded from the caller.
    unsafe { doubles(p, n, name) }
}

/// The caller's output array of `dof` doubles.
///
/// # Safety
/// `p` must point to `n` writable doubles.
unsafe fn output<'a>(
    p: *mut f64,
    n: usize,
    dof: usize,
    name: &str,
) -> Result<&'a mut [f64], Failure> {
    if p.is_null() {
        return Err(null(name));
    }
    if n != dof {
        return Err(Failure(
            PVFC_ERROR_WRONG_SIZE,
            format!("{name}: room for {n} entries, the robot has {dof} joints"),
        ));
    }
    // SAFETY: the caller gives n writable doubles at p.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// An optional C string (NULL: `None`), as UTF-8.
///
/// # Safety
/// `p` is NULL or a NUL-terminated string.
unsafe fn text<'a>(p: *const c_char, name: &str) -> Result<Option<&'a str>, Failure> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: the caller gives a NUL-terminated string.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map(Some)
        .map_err(|_| Failure(PVFC_ERROR_INVALID_ARGUMENT, format!("{name}: not UTF-8")))
}

/// The object behind a handle.
///
/// # Safety
/// `p` is NULL or a live handle of this type.
unsafe fn object<'a, T>(p: *const T, name: &str) -> Result<&'a T, Failure> {
    // SAFETY: a live handle made by this library.
    unsafe { p.as_ref() }.ok_or_else(|| null(name))
}

/// The object behind a handle, to change.
///
/// # Safety
/// `p` is NULL or a live handle of this type, not used elsewhere meanwhile.
unsafe fn object_mut<'a, T>(p: *mut T, name: &str) -> Result<&'a mut T, Failure> {
    // SAFETY: a live handle made by this library, used by one thread at a time.
    unsafe { p.as_mut() }.ok_or_else(|| null(name))
}

/// Stores a new object in `*out`.
///
/// # Safety
/// `out` is NULL or writable.
unsafe fn give<T>(out: *mut *mut T, x: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(null("out"));
    }
    // SAFETY: out is writable (checked not NULL).
    unsafe { *out = Box::into_raw(Box::new(x)) };
    Ok(())
}

/// The message of the last error on this thread (empty if none). The pointer stays valid
/// until the next call of a pvfc function on this thread.
#[no_mangle]
pub extern "C" fn pvfc_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// The library's version, e.g. "0.1.0" (a static string).
#[no_mangle]
pub extern "C" fn pvfc_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// A serial arm read from URDF (opaque).
pub struct pvfc_robot {
    robot: Robot,
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

/// The settings of a controller, apart from its robot, contour and navigation weights. Get
/// them from [`pvfc_settings_default`] and change what you need: `size` lets later versions
/// add fields without breaking callers.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct pvfc_settings {
    /// `sizeof(pvfc_settings)` as the caller was compiled with.
    pub size: usize,
    /// Self-pacing `R` of eq. (21) (0: off).
    pub self_pacing: f64,
    /// The energy level `Ē` (J).
    pub energy: f64,
    /// The flywheel's inertia `M_F`.
    pub flywheel_inertia: f64,
    /// The coupling gain `γ` (eq. 7).
    pub gamma: f64,
    /// Adds `g(q)` to the torque (1) or not (0).
    pub gravity_compensation: bool,
    /// Coulomb levels of the friction compensation (eq. 35), one per joint; NULL: none.
    pub friction_compensation: *const f64,
    /// The number of entries at `friction_compensation`.
    pub friction_compensation_len: usize,
    /// The velocity band of the friction compensation's sign (0: a pure sign).
    pub friction_band: f64,
    /// Nominal-speed control (eq. 36): the gain `c` (0: off).
    pub nominal_speed_c: f64,
    /// Nominal-speed control: the speed `r`.
    pub nominal_speed_r: f64,
    /// The contour parameter `τ` to start at.
    pub tau0: f64,
}

/// The default settings: no self-pacing, `Ē = 10`, `M_F = 1`, `γ = 1`, gravity
/// compensation on, no friction compensation, no nominal-speed control, `τ₀ = 0`.
#[no_mangle]
pub extern "C" fn pvfc_settings_default() -> pvfc_settings {
    pvfc_settings {
        size: std::mem::size_of::<pvfc_settings>(),
        self_pacing: 0.0,
        energy: 10.0,
        flywheel_inertia: 1.0,
        gamma: 1.0,
        gravity_compensation: true,
        friction_compensation: std::ptr::null(),
        friction_compensation_len: 0,
        friction_band: 0.0,
        nominal_speed_c: 0.0,
        nominal_speed_r: 1.0,
        tau0: 0.0,
    }
}

/// The numbers of one control step besides the torque.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct pvfc_diagnostics {
    /// The navigation function `U`.
    pub potential: f64,
    /// `β`: the augmented velocity's multiple of the field.
    pub beta: f64,
    /// The augmented kinetic energy `κ_a` (J).
    pub kinetic_energy: f64,
    /// The contour parameter `τ` (wrapped to its period) before the step.
    pub tau: f64,
    /// `τ̇` before the step.
    pub tau_dot: f64,
    /// The flywheel's speed `q̇_F` before the step.
    pub flywheel_speed: f64,
}

/// A PVFC controller of an arm (opaque).
pub struct pvfc_controller {
    ctl: ArmController,
    initial: ArmController,
}

/// Makes a controller of `robot` that follows the closed joint-space contour through
/// `n_waypoints` waypoints (row-major, `n_waypoints × dof` doubles, `dof` the robot's), one
/// every `spacing` of `τ`, with navigation weights `h` (`h_len` = dof; NULL: all 1) and
/// `settings` (NULL: [`pvfc_settings_default`]).
///
/// # Safety
/// The pointers are NULL or point to the documented number of readable values; `out` is
/// writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pvfc_controller_new_waypoints(
    robot: *const pvfc_robot,
    waypoints: *const f64,
    n_waypoints: usize,
    dof: usize,
    spacing: f64,
    h: *const f64,
    h_len: usize,
    settings: *const pvfc_settings,
    out: *mut *mut pvfc_controller,
) -> pvfc_status {
    guard(|| {
        // SAFETY: handles and arrays as documented.
        let robot = &unsafe { object(robot, "robot") }?.robot;
        let n = robot.dof();
        if dof != n {
            return Err(Failure(
                PVFC_ERROR_WRONG_SIZE,
                format!("waypoints: {dof} columns for the {n}-joint robot"),
            ));
        }
        let total = n_waypoints
            .checked_mul(n)
            .ok_or_else(|| Failure(PVFC_ERROR_WRONG_SIZE, "waypoints: too many".into()))?;
        let flat = unsafe { doubles(waypoints, total, "waypoints") }?;
        let points = flat.chunks(n).map(<[f64]>::to_vec).collect();
        let h = if h.is_null() {
            vec![1.0; n]
        } else {
            unsafe { joints(h, h_len, n, "h") }?.to_vec()
        };
        let defaults = pvfc_settings_default();
        let s = if settings.is_null() {
            &defaults
        } else {
            unsafe { object(settings, "settings") }?
        };
        if s.size != std::mem::size_of::<pvfc_settings>() {
            return Err(Failure(
                PVFC_ERROR_WRONG_SIZE,
                format!(
                    "settings: size {} but this library's pvfc_settings is {} bytes (get them from pvfc_settings_default)",
                    s.size,
                    std::mem::size_of::<pvfc_settings>()
                ),
            ));
        }
        let friction = if s.friction_compensation.is_null() {
            None
        } else {
            Some(
                unsafe {
                    joints(
                        s.friction_compensation,
                        s.friction_compensation_len,
                        n,
                        "settings.friction_compensation",
                    )
                }?
                .to_vec(),
            )
        };
        let settings = ArmSettings {
            contour: JointContourSpec::Waypoints { points, spacing },
            field: FieldSpec::Joint,
            h,
            self_pacing: s.self_pacing,
            energy: s.energy,
            flywheel_inertia: s.flywheel_inertia,
            gamma: s.gamma,
            gravity_compensation: s.gravity_compensation,
            friction_compensation: friction,
            friction_band: s.friction_band,
            nominal_speed: (s.nominal_speed_c != 0.0)
                .then_some((s.nominal_speed_c, s.nominal_speed_r)),
            tau0: s.tau0,
        };
        let ctl = ArmController::new(robot, &settings)?;
        unsafe {
            give(
                out,
                pvfc_controller {
                    initial: ctl.clone(),
                    ctl,
                },
            )
        }
    })
}

/// One control step at the measured joint positions `q` and velocities `qdot` (`n` = the
/// robot's joints each): writes the motor torques into `torque_out` (`torque_len` = n) and,
/// if `diagnostics` is not NULL, the step's numbers; advances the internal states over `dt`
/// (s). Allocates nothing. On error nothing changes.
///
/// # Safety
/// The pointers are NULL or point to the documented number of values; `ctl` is used by one
/// thread at a time.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pvfc_controller_step(
    ctl: *mut pvfc_controller,
    q: *const f64,
    qdot: *const f64,
    n: usize,
    dt: f64,
    torque_out: *mut f64,
    torque_len: usize,
    diagnostics: *mut pvfc_diagnostics,
) -> pvfc_status {
    guard(|| {
        // SAFETY: handle and arrays as documented.
        let c = &mut unsafe { object_mut(ctl, "ctl") }?.ctl;
        let dof = c.dof();
        let (q, v) = unsafe { (joints(q, n, dof, "q")?, joints(qdot, n, dof, "qdot")?) };
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Failure(
                PVFC_ERROR_INVALID_ARGUMENT,
                "dt: finite and > 0".into(),
            ));
        }
        let torque = unsafe { output(torque_out, torque_len, dof, "torque_out") }?;
        let d = c.step_into(q, v, dt, torque)?;
        // SAFETY: NULL or writable.
        if let Some(out) = unsafe { diagnostics.as_mut() } {
            *out = pvfc_diagnostics {
                potential: d.potential,
                beta: d.beta,
                kinetic_energy: d.kinetic_energy,
                tau: d.internal.0,
                tau_dot: d.internal.1,
                flywheel_speed: d.internal.2,
            };
        }
        Ok(())
    })
}

/// The number of joints of the controller's robot (0 for NULL).
///
/// # Safety
/// `ctl` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pvfc_controller_dof(ctl: *const pvfc_controller) -> usize {
    // SAFETY: NULL or a live handle.
    unsafe { ctl.as_ref() }.map_or(0, |c| c.ctl.dof())
}

/// The joint contour's point `x_d(τ)` at `tau`, into `out` (`out_len` = the robot's joints).
///
/// # Safety
/// `ctl` is NULL or a live handle; `out` is NULL or has room for `out_len` doubles.
#[no_mangle]
pub unsafe extern "C" fn pvfc_controller_contour_point(
    ctl: *const pvfc_controller,
    tau: f64,
    out: *mut f64,
    out_len: usize,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let c = &unsafe { object(ctl, "ctl") }?.ctl;
        if !tau.is_finite() {
            return Err(Failure(PVFC_ERROR_NON_FINITE, format!("tau is {tau}")));
        }
        let o = unsafe { output(out, out_len, c.dof(), "out") }?;
        o.copy_from_slice(&c.contour_point(tau));
        Ok(())
    })
}

/// Puts the controller back to its initial internal states.
///
/// # Safety
/// `ctl` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pvfc_controller_reset(ctl: *mut pvfc_controller) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let c = unsafe { object_mut(ctl, "ctl") }?;
        c.ctl = c.initial.clone();
        Ok(())
    })
}

/// Frees a controller (NULL: nothing).
///
/// # Safety
/// `ctl` is NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn pvfc_controller_destroy(ctl: *mut pvfc_controller) {
    if !ctl.is_null() {
        // SAFETY: a handle made by Box::into_raw in this library, freed once.
        drop(unsafe { Box::from_raw(ctl) });
    }
}

/// The options of the passive digital controller. Get them from
/// [`pvfc_passive_options_default`].
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct pvfc_passive_options {
    /// `sizeof(pvfc_passive_options)` as the caller was compiled with.
    pub size: usize,
    /// Per-joint torque limits (each > 0); NULL: none.
    pub torque_limit: *const f64,
    /// Per-joint encoder resolution (rad or m, each ≥ 0) charged to the storage; NULL: exact
    /// positions.
    pub encoder_resolution: *const f64,
    /// The number of entries of each of the two arrays above (the robot's joints).
    pub n: usize,
    /// The velocity estimate's filter time constant (s, ≥ 0), when only positions are given.
    pub velocity_filter: f64,
    /// The storage the tank keeps in hand (J, ≥ 0).
    pub reserve: f64,
}

/// Default passive options: no limits, exact positions, no filter, no reserve.
#[no_mangle]
pub extern "C" fn pvfc_passive_options_default() -> pvfc_passive_options {
    pvfc_passive_options {
        size: std::mem::size_of::<pvfc_passive_options>(),
        torque_limit: std::ptr::null(),
        encoder_resolution: std::ptr::null(),
        n: 0,
        velocity_filter: 0.0,
        reserve: 0.0,
    }
}

/// The energy account of one passive step (J).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct pvfc_energy_account {
    /// The storage after the last period's balance.
    pub storage: f64,
    /// The energy the coupling gave the robot over the last period.
    pub to_robot: f64,
    /// The add-ons' energy over the last period.
    pub add_ons: f64,
    /// What the hold's error would have created or destroyed, removed by the projection.
    pub correction: f64,
    /// The factor applied to the coupling torque this step (1: the tank paid for all).
    pub scale: f64,
    /// 1 when a torque limit clamped this step's command.
    pub saturated: bool,
    /// What the storage was charged for the encoders' resolution this step.
    pub quantisation: f64,
    /// The navigation function `U` at this step.
    pub potential: f64,
}

/// The passive digital controller (opaque): passive by construction at its samples.
pub struct pvfc_passive {
    p: PassiveArm,
}

/// The passive digital form of `ctl` (with its internal states as they are now) and
/// `options` (NULL: [`pvfc_passive_options_default`]).
///
/// # Safety
/// `ctl` is NULL or a live handle; `options` is NULL or readable (its arrays as documented);
/// `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_passive_new(
    ctl: *const pvfc_controller,
    options: *const pvfc_passive_options,
    out: *mut *mut pvfc_passive,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let c = &unsafe { object(ctl, "ctl") }?.ctl;
        let n = c.dof();
        let defaults = pvfc_passive_options_default();
        let o = if options.is_null() {
            &defaults
        } else {
            unsafe { object(options, "options") }?
        };
        if o.size != std::mem::size_of::<pvfc_passive_options>() {
            return Err(Failure(
                PVFC_ERROR_WRONG_SIZE,
                format!(
                    "options: size {} but this library's pvfc_passive_options is {} bytes (get them from pvfc_passive_options_default)",
                    o.size,
                    std::mem::size_of::<pvfc_passive_options>()
                ),
            ));
        }
        let array = |p: *const f64, name: &str| -> Result<Option<Vec<f64>>, Failure> {
            if p.is_null() {
                Ok(None)
            } else {
                // SAFETY: o.n readable doubles at p, as documented.
                Ok(Some(unsafe { joints(p, o.n, n, name) }?.to_vec()))
            }
        };
        let options = PassiveOptions {
            torque_limit: array(o.torque_limit, "options.torque_limit")?,
            encoder_resolution: array(o.encoder_resolution, "options.encoder_resolution")?,
            velocity_filter: o.velocity_filter,
            reserve: o.reserve,
        };
        let p = c.passive(&options)?;
        unsafe { give(out, pvfc_passive { p }) }
    })
}

/// One passive step at the measured positions `q` (and velocities `qdot`, NULL to estimate
/// them from the positions), with `applied` the torque the drive applied over the last period
/// (NULL: the last command): writes the torque to hold for the next period into `torque_out`
/// and, if `account` is not NULL, the period's energy account. Allocates nothing. On error
/// nothing changes.
///
/// # Safety
/// The pointers are NULL or point to `n` values each; `p` is used by one thread at a time.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pvfc_passive_step(
    p: *mut pvfc_passive,
    q: *const f64,
    qdot: *const f64,
    applied: *const f64,
    n: usize,
    dt: f64,
    torque_out: *mut f64,
    torque_len: usize,
    account: *mut pvfc_energy_account,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let p = &mut unsafe { object_mut(p, "p") }?.p;
        let dof = p.dof();
        let q = unsafe { joints(q, n, dof, "q") }?;
        let v = if qdot.is_null() {
            None
        } else {
            Some(unsafe { joints(qdot, n, dof, "qdot") }?)
        };
        let u = if applied.is_null() {
            None
        } else {
            Some(unsafe { joints(applied, n, dof, "applied") }?)
        };
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Failure(
                PVFC_ERROR_INVALID_ARGUMENT,
                "dt: finite and > 0".into(),
            ));
        }
        let torque = unsafe { output(torque_out, torque_len, dof, "torque_out") }?;
        let (potential, e) = p.step_into(q, v, u, dt, torque, None)?;
        // SAFETY: NULL or writable.
        if let Some(a) = unsafe { account.as_mut() } {
            *a = pvfc_energy_account {
                storage: e.storage,
                to_robot: e.to_robot,
                add_ons: e.add_ons,
                correction: e.correction,
                scale: e.scale,
                saturated: e.saturated,
                quantisation: e.quantisation,
                potential,
            };
        }
        Ok(())
    })
}

/// The storage `½τ̇² + ½M_F q̇_F²` as accounted (J; NaN for NULL).
///
/// # Safety
/// `p` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pvfc_passive_storage(p: *const pvfc_passive) -> f64 {
    // SAFETY: NULL or a live handle.
    unsafe { p.as_ref() }.map_or(f64::NAN, |p| p.p.storage())
}

/// Frees a passive controller (NULL: nothing).
///
/// # Safety
/// `p` is NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn pvfc_passive_destroy(p: *mut pvfc_passive) {
    if !p.is_null() {
        // SAFETY: a handle made by Box::into_raw in this library, freed once.
        drop(unsafe { Box::from_raw(p) });
    }
}
