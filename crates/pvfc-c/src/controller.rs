//! The controller handle: the continuous-time PVFC law of an arm on a contour, its settings
//! and its step.

use crate::args::*;
use crate::contour::{pvfc_contour, pvfc_contour_destroy, pvfc_contour_waypoints};
use crate::robot::pvfc_robot;
use crate::status::*;
use pvfc_control::model::arm::{ArmController, ArmSettings};
use pvfc_control::model::pace::{PaceSettings, PathSpeed};

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
    /// The pace along the contour: the speed asked for (0: the contour's own pace), the
    /// tool's (m/s) along a Cartesian path, the joints' (rad/s, the norm of `q̇`) along a
    /// joint-space contour. Along a part program with feeds (F) the feeds are the speed asked
    /// for, this one on moves without F. With `energy = 0` the energy level is sized from it.
    pub pace_speed: f64,
    /// The drives' torque limits bounding the pace, one per joint (N·m or N); NULL: none.
    pub pace_torque_limit: *const f64,
    /// The number of entries at `pace_torque_limit`.
    pub pace_torque_limit_len: usize,
    /// The share of each limit the motion along the contour may use, in (0, 1].
    pub pace_headroom: f64,
    /// The rate `γβĒ` (1/s) at which the velocity error converges (Remark 1), in place of
    /// `gamma` (0: `gamma` is used): `γ = coupling_rate / (βĒ)` with `β` the nominal speed `r`
    /// (or 1) and `Ē` the energy level, also when it is sized from the pace (`energy = 0`).
    pub coupling_rate: f64,
    /// The gain `k_i` (1/s, ≥ 0) of the nominal speed's integral of its error, which takes `β`
    /// to `r` against friction (0: the paper's proportional law).
    pub nominal_speed_integral: f64,
    /// The bound on the field's kinetic energy as a share of `Ē`, in (0, 1) (0: no bound):
    /// where the field would carry more (an arm far off its contour) it is scaled onto it, so
    /// that the law is defined at every state instead of failing with
    /// `PVFC_ERROR_ENERGY_TOO_LOW`.
    pub field_energy_bound: f64,
}

/// The default settings: no self-pacing, `Ē = 10`, `M_F = 1`, `γ = 1`, gravity
/// compensation on, no friction compensation, no nominal-speed control, `τ₀ = 0`, the
/// contour's own pace (no speed asked for, no torque limits; headroom 0.8 if limits are
/// given), `γ` given directly (no coupling rate), no bound on the field's energy.
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
        pace_speed: 0.0,
        pace_torque_limit: std::ptr::null(),
        pace_torque_limit_len: 0,
        pace_headroom: 0.8,
        coupling_rate: 0.0,
        nominal_speed_integral: 0.0,
        field_energy_bound: 0.0,
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
    pub(crate) ctl: ArmController,
    initial: ArmController,
    /// The settings it was built from (its passive mode's learner of the torque the model
    /// misses plans on their pace).
    pub(crate) settings: ArmSettings,
}

impl SizedStruct for pvfc_settings {
    fn size(&self) -> usize {
        self.size
    }
}

/// Makes a controller of `robot` that follows `contour` (a Cartesian path's inverse
/// kinematics is solved here; errors name the waypoint), with navigation weights `h`
/// (`h_len` = the robot's joints; NULL: all 1; unused by the task-space field) and
/// `settings` (NULL: [`pvfc_settings_default`]). The contour may be destroyed afterwards.
///
/// # Safety
/// `robot`, `contour` are NULL or live handles; `h` is NULL or holds `h_len` doubles;
/// `settings` is NULL or readable (its arrays as documented); `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_controller_new(
    robot: *const pvfc_robot,
    contour: *const pvfc_contour,
    h: *const f64,
    h_len: usize,
    settings: *const pvfc_settings,
    out: *mut *mut pvfc_controller,
) -> pvfc_status {
    guard(|| {
        // SAFETY: handles and arrays as documented.
        let robot = &unsafe { object(robot, "robot") }?.robot;
        let contour = unsafe { object(contour, "contour") }?;
        let n = robot.dof();
        let h = unsafe { optional_joints(h, h_len, n, "h") }?
            .map_or_else(|| vec![1.0; n], <[f64]>::to_vec);
        let s = unsafe { sized(settings, pvfc_settings_default(), "settings") }?;
        let friction = unsafe {
            optional_joints(
                s.friction_compensation,
                s.friction_compensation_len,
                n,
                "settings.friction_compensation",
            )
        }?
        .map(<[f64]>::to_vec);
        let limits = unsafe {
            optional_joints(
                s.pace_torque_limit,
                s.pace_torque_limit_len,
                n,
                "settings.pace_torque_limit",
            )
        }?
        .map(<[f64]>::to_vec);
        let level = if s.nominal_speed_c != 0.0 {
            s.nominal_speed_r
        } else {
            1.0
        };
        let asked = (s.pace_speed != 0.0).then_some(s.pace_speed);
        // A part program's feeds are the speed asked for (pace_speed on moves without F).
        let speed = match contour.feeds(asked)? {
            Some(f) => Some(PathSpeed::Feeds(f)),
            None => asked.map(|v| match contour.is_cartesian() {
                true => PathSpeed::Tool(v),
                false => PathSpeed::Joint(v),
            }),
        };
        let pace = (speed.is_some() || limits.is_some()).then(|| PaceSettings {
            speed,
            torque_limit: limits.unwrap_or_default(),
            headroom: s.pace_headroom,
            level,
        });
        let (contour, field) = contour.resolve(robot)?;
        let settings = ArmSettings {
            contour,
            field,
            h,
            self_pacing: s.self_pacing,
            energy: s.energy,
            flywheel_inertia: s.flywheel_inertia,
            gamma: s.gamma,
            coupling_rate: (s.coupling_rate != 0.0).then_some(s.coupling_rate),
            gravity_compensation: s.gravity_compensation,
            friction_compensation: friction,
            friction_band: s.friction_band,
            nominal_speed: (s.nominal_speed_c != 0.0)
                .then_some((s.nominal_speed_c, s.nominal_speed_r)),
            nominal_speed_integral: s.nominal_speed_integral,
            tau0: s.tau0,
            field_energy_bound: (s.field_energy_bound != 0.0).then_some(s.field_energy_bound),
            obstacles: None,
            pace,
        };
        let ctl = ArmController::new(robot, &settings)?;
        unsafe {
            give(
                out,
                pvfc_controller {
                    initial: ctl.clone(),
                    ctl,
                    settings,
                },
            )
        }
    })
}

/// Makes a controller of `robot` that follows the closed joint-space contour through
/// `n_waypoints` waypoints (row-major, `n_waypoints × dof` doubles, `dof` the robot's), one
/// every `spacing` of `τ`: [`pvfc_contour_waypoints`] and [`pvfc_controller_new`] in one
/// call.
///
/// # Safety
/// As [`pvfc_contour_waypoints`] and [`pvfc_controller_new`].
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
    // SAFETY: as documented.
    let n = unsafe { robot.as_ref() }.map(|r| r.robot.dof());
    if let Some(n) = n.filter(|n| *n != dof) {
        return guard(|| {
            Err(Failure(
                PVFC_ERROR_WRONG_SIZE,
                format!("waypoints: {dof} columns for the {n}-joint robot").into(),
            ))
        });
    }
    let mut contour = std::ptr::null_mut();
    let status =
        unsafe { pvfc_contour_waypoints(waypoints, n_waypoints, dof, spacing, &mut contour) };
    if status != PVFC_OK {
        return status;
    }
    let status = unsafe { pvfc_controller_new(robot, contour, h, h_len, settings, out) };
    unsafe { pvfc_contour_destroy(contour) };
    status
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
            return Err(Failure::argument(
                PVFC_ERROR_NON_FINITE,
                "tau",
                Fault::NonFinite {
                    index: None,
                    value: tau,
                },
            ));
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
