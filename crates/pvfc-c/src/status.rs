//! Status codes, the thread's last error, and the guard that turns errors and panics into
//! them.

use pvfc_core::ErrorKind;
use pvfc_sim::SimError;
use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

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

pub(crate) use pvfc_status::*;

/// An error on its way to the caller: its status and message.
pub(crate) struct Failure(pub(crate) pvfc_status, pub(crate) String);

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
pub(crate) fn guard(f: impl FnOnce() -> Result<(), Failure>) -> pvfc_status {
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
