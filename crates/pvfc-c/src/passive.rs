//! The passive digital controller's handle, its options and its step.

use crate::args::*;
use crate::controller::pvfc_controller;
use crate::status::*;
use pvfc_control::model::arm::{PassiveArm, PassiveOptions, SupervisionOptions};
use pvfc_control::model::pace::{PaceLearningSpec, SpeedScaling};
use pvfc_core::supervision::Fault;

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
    /// Supervision: the fastest each joint can move (rad/s, m/s; `n` entries, each > 0).
    /// NULL: no supervision (a non-finite reading or period is an error, every other reading
    /// is believed). With it, a sample that breaks a bound is a fault: `pvfc_passive_step`
    /// returns `PVFC_FAULT` with the safe torque, zero.
    pub max_speed: *const f64,
    /// Supervision: the most each joint can be accelerated (rad/s², m/s²; `n` entries, each
    /// > 0). NULL: only the speed is checked, and no encoder is found frozen.
    pub max_acceleration: *const f64,
    /// Supervision: the shortest period accepted (s, > 0; with `max_speed`).
    pub min_period: f64,
    /// Supervision: the longest period accepted (s, ≥ `min_period`; with `max_speed`).
    pub max_period: f64,
    /// The pace throttle's time constant (s, > 0; needs `torque_limit`): the field's pace is
    /// slowed while the command uses more than `pace_throttle_threshold` of a limit, never
    /// below `pace_throttle_floor`. 0: no throttle.
    pub pace_throttle_time_constant: f64,
    /// The share of a limit above which the throttle slows the pace, in [0, 1).
    pub pace_throttle_threshold: f64,
    /// The least scale of the pace, in (0, 1].
    pub pace_throttle_floor: f64,
    /// The learned pace's target (needs `torque_limit` and a pace planned along a closed
    /// contour): the pace of each 64th of the period rises, lap over lap, while the command's
    /// peak share of a limit there stays below it, in (0, 1]. 0: no learning.
    pub pace_learning_target: f64,
    /// The largest fraction a stretch's pace falls in one lap where the command passed a
    /// limit, in [0, 1).
    pub pace_learning_fall: f64,
    /// The largest fraction a stretch's pace rises in one lap (≥ 0).
    pub pace_learning_rise: f64,
    /// The largest difference between neighbouring stretches' scales, in (0, 1].
    pub pace_learning_slope: f64,
    /// The least scale of the planned pace, in (0, 1].
    pub pace_learning_floor: f64,
    /// With the learned pace, the torque the model misses learned beside it: the share of
    /// each lap's measurement taken in, in (0, 1]; the pace is planned again against it once
    /// a lap and caps each stretch's scale (the controller's pace, `pvfc_settings.pace_speed`
    /// or `pace_torque_limit`, on a closed contour). 0: not learned.
    pub pace_learning_miss: f64,
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
        max_speed: std::ptr::null(),
        max_acceleration: std::ptr::null(),
        min_period: 0.0,
        max_period: 0.0,
        pace_throttle_time_constant: 0.0,
        pace_throttle_threshold: 0.8,
        pace_throttle_floor: 0.05,
        pace_learning_target: 0.0,
        pace_learning_fall: 0.3,
        pace_learning_rise: 0.1,
        pace_learning_slope: 0.03,
        pace_learning_floor: 0.2,
        pace_learning_miss: 0.0,
    }
}

/// The fault a supervised passive step found (`pvfc_energy_account.fault`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum pvfc_fault {
    /// No fault.
    #[default]
    PVFC_FAULT_NONE = 0,
    /// A measured position or velocity, or the applied torque, is NaN or infinite.
    PVFC_FAULT_NON_FINITE = 1,
    /// The period is not finite, or outside `[min_period, max_period]`.
    PVFC_FAULT_PERIOD = 2,
    /// A joint moved further since the last good reading than its speed bound allows.
    PVFC_FAULT_SPEED = 3,
    /// A joint's speed changed more than its acceleration bound allows.
    PVFC_FAULT_ACCELERATION = 4,
    /// A joint's encoder stopped dead while the joint was moving, and has not changed since.
    PVFC_FAULT_FROZEN = 5,
}

impl From<Option<Fault>> for pvfc_fault {
    fn from(f: Option<Fault>) -> Self {
        match f {
            None => pvfc_fault::PVFC_FAULT_NONE,
            Some(Fault::NonFinite) => pvfc_fault::PVFC_FAULT_NON_FINITE,
            Some(Fault::Period) => pvfc_fault::PVFC_FAULT_PERIOD,
            Some(Fault::Speed { .. }) => pvfc_fault::PVFC_FAULT_SPEED,
            Some(Fault::Acceleration { .. }) => pvfc_fault::PVFC_FAULT_ACCELERATION,
            Some(Fault::Frozen { .. }) => pvfc_fault::PVFC_FAULT_FROZEN,
        }
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
    /// The navigation function `U` at this step (at a fault: as of the last good step).
    pub potential: f64,
    /// What the storage was charged at a fault for the work the last torque may have done
    /// unseen over the period that ended (0 without a fault).
    pub unseen: f64,
    /// The fault found at this sample (`PVFC_FAULT_NONE` without one).
    pub fault: pvfc_fault,
    /// The joint (0-based) the fault names, or -1.
    pub fault_joint: i32,
    /// What the storage set aside this step for the work the readings that stand still may
    /// hide (negative when it came back; with supervision only).
    pub set_aside: f64,
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
        let handle = unsafe { object(ctl, "ctl") }?;
        let c = &handle.ctl;
        let n = c.dof();
        let o = &unsafe { sized(options, pvfc_passive_options_default(), "options") }?;
        let array = |p: *const f64, name: &'static str| -> Result<Option<Vec<f64>>, Failure> {
            // SAFETY: NULL or o.n readable doubles at p, as documented.
            Ok(unsafe { optional_joints(p, o.n, n, name) }?.map(<[f64]>::to_vec))
        };
        let supervision = match array(o.max_speed, "options.max_speed")? {
            Some(max_speed) => Some(SupervisionOptions {
                max_speed,
                max_acceleration: array(o.max_acceleration, "options.max_acceleration")?,
                period: (o.min_period, o.max_period),
            }),
            None if !o.max_acceleration.is_null() => {
                return Err(Failure(
                    PVFC_ERROR_INVALID_ARGUMENT,
                    "options.max_acceleration: given without options.max_speed".into(),
                ))
            }
            None => None,
        };
        let options = PassiveOptions {
            torque_limit: array(o.torque_limit, "options.torque_limit")?,
            encoder_resolution: array(o.encoder_resolution, "options.encoder_resolution")?,
            velocity_filter: o.velocity_filter,
            reserve: o.reserve,
            supervision,
            pace_throttle: (o.pace_throttle_time_constant != 0.0).then_some(SpeedScaling {
                threshold: o.pace_throttle_threshold,
                time_constant: o.pace_throttle_time_constant,
                floor: o.pace_throttle_floor,
            }),
            pace_learning: (o.pace_learning_target != 0.0).then_some(PaceLearningSpec {
                target: o.pace_learning_target,
                fall: o.pace_learning_fall,
                rise: o.pace_learning_rise,
                slope: o.pace_learning_slope,
                floor: o.pace_learning_floor,
                miss: o.pace_learning_miss,
            }),
        };
        let p = c.passive(&options, &handle.settings)?;
        unsafe { give(out, pvfc_passive { p }) }
    })
}

/// One passive step at the measured positions `q` (and velocities `qdot`, NULL to estimate
/// them from the positions), with `applied` the torque the drive applied over the last period
/// (NULL: the last command): writes the torque to hold for the next period into `torque_out`
/// and, if `account` is not NULL, the period's energy account. Allocates nothing. On error
/// nothing changes.
///
/// With supervision (`pvfc_passive_options.max_speed`), NaN or infinite readings and periods
/// are not errors but faults: a sample that breaks a bound returns `PVFC_FAULT`, writes the
/// safe torque (zero) and the account (its `fault`, `fault_joint`, `unseen`), and the
/// controller resumes at the next good sample.
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
        let supervised = p.supervised();
        let (q, v, u) = if supervised {
            // The readings as they are: the supervision judges them.
            (
                unsafe { any_joints(q, n, dof, ("q", false)) }?.unwrap_or(&[]),
                unsafe { any_joints(qdot, n, dof, ("qdot", true)) }?,
                unsafe { any_joints(applied, n, dof, ("applied", true)) }?,
            )
        } else {
            (
                unsafe { joints(q, n, dof, "q") }?,
                unsafe { optional_joints(qdot, n, dof, "qdot") }?,
                unsafe { optional_joints(applied, n, dof, "applied") }?,
            )
        };
        // (With supervision a bad period is a fault, judged by the controller.)
        let period_ok = dt.is_finite() && dt > 0.0;
        if !(supervised || period_ok) {
            return Err(Failure(
                PVFC_ERROR_INVALID_ARGUMENT,
                "dt: finite and > 0".into(),
            ));
        }
        let torque = unsafe { output(torque_out, torque_len, dof, "torque_out") }?;
        let (potential, e, fault) = p.step_into(q, v, u, dt, torque, None)?;
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
                unseen: e.unseen,
                fault: fault.into(),
                fault_joint: fault.and_then(|f| f.joint()).map_or(-1, |j| j as i32),
                set_aside: e.set_aside,
            };
        }
        match fault {
            Some(f) => Err(Failure(PVFC_FAULT, Message::Supervision(f))),
            None => Ok(()),
        }
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

/// The scale of the field's pace the next step uses: the pace throttle's, in
/// `[floor, 1]`, 1 without a throttle (NaN for NULL).
///
/// # Safety
/// `p` is NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn pvfc_passive_pace_scale(p: *const pvfc_passive) -> f64 {
    // SAFETY: NULL or a live handle.
    unsafe { p.as_ref() }.map_or(f64::NAN, |p| p.p.pace_scale())
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

impl SizedStruct for pvfc_passive_options {
    fn size(&self) -> usize {
        self.size
    }
}
