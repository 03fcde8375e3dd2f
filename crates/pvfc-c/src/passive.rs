//! The passive digital controller's handle, its options and its step.

use crate::args::*;
use crate::controller::pvfc_controller;
use crate::status::*;
use pvfc_control::model::arm::{PassiveArm, PassiveOptions};
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
        let o = &unsafe { sized(options, pvfc_passive_options_default(), "options") }?;
        let array = |p: *const f64, name: &'static str| -> Result<Option<Vec<f64>>, Failure> {
            // SAFETY: NULL or o.n readable doubles at p, as documented.
            Ok(unsafe { optional_joints(p, o.n, n, name) }?.map(<[f64]>::to_vec))
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
        let v = unsafe { optional_joints(qdot, n, dof, "qdot") }?;
        let u = unsafe { optional_joints(applied, n, dof, "applied") }?;
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

impl SizedStruct for pvfc_passive_options {
    fn size(&self) -> usize {
        self.size
    }
}
