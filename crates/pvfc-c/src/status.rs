//! Status codes, the thread's last error, and the guard that turns errors and panics into
//! them.

use pvfc_control::SimError;
use pvfc_core::ErrorKind;
use std::cell::RefCell;
use std::ffi::c_char;
use std::fmt;
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
    /// Not an error: the passive controller's supervision found a fault at this sample (a
    /// non-finite reading, a period out of bounds, a reading no motion can make, a frozen
    /// encoder). The torque written is the safe torque, zero; the energy account says which
    /// fault and which joint; [`pvfc_last_error`] names it. The controller resumes at the
    /// next good sample.
    PVFC_FAULT = 11,
}

pub(crate) use pvfc_status::*;

/// An error on its way to the caller: its status and message. The message is kept as its
/// parts and formatted only when [`guard`] records it, into the thread's fixed buffer: an error
/// of a real-time function (a NaN in `q`, a wrong length, an overflow) allocates nothing.
pub(crate) struct Failure(pub(crate) pvfc_status, pub(crate) Message);

/// The message of a [`Failure`], formatted on demand ([`fmt::Display`]).
pub(crate) enum Message {
    /// Formatted already, by a function that may allocate (a constructor).
    Text(String),
    /// A fixed text.
    Fixed(&'static str),
    /// The library's error, as it displays itself.
    Sim(SimError),
    /// What is wrong with the argument `name`.
    Argument(&'static str, Fault),
    /// The fault the passive controller's supervision found ([`PVFC_FAULT`]).
    Supervision(pvfc_core::supervision::Fault),
}

/// What is wrong with an argument ([`Message::Argument`]).
pub(crate) enum Fault {
    /// A NULL pointer that must not be.
    Null,
    /// The entry `index` is `value`, NaN or infinite (`index` `None`: a scalar).
    NonFinite { index: Option<usize>, value: f64 },
    /// A joint vector of `n` entries for a `dof`-joint robot.
    Entries { n: usize, dof: usize },
    /// An output joint vector with room for `n` entries, for a `dof`-joint robot.
    Room { n: usize, dof: usize },
    /// An output matrix with room for `n` entries, for a `dof`-joint robot (`dof²` needed).
    MatrixRoom { n: usize, dof: usize },
}

impl From<String> for Message {
    fn from(s: String) -> Self {
        Message::Text(s)
    }
}

impl From<&'static str> for Message {
    fn from(s: &'static str) -> Self {
        Message::Fixed(s)
    }
}

impl fmt::Display for Message {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Message::Text(s) => f.write_str(s),
            Message::Fixed(s) => f.write_str(s),
            Message::Sim(e) => write!(f, "{e}"),
            Message::Supervision(fault) => write!(f, "supervision: {fault}"),
            Message::Argument(name, Fault::Null) => write!(f, "{name}: NULL pointer"),
            Message::Argument(name, Fault::NonFinite { index, value }) => match index {
                Some(i) => write!(f, "{name}[{i}] is {value}"),
                None => write!(f, "{name} is {value}"),
            },
            Message::Argument(name, Fault::Entries { n, dof }) => {
                write!(f, "{name}: {n} entries for the {dof}-joint robot")
            }
            Message::Argument(name, Fault::Room { n, dof }) => {
                write!(
                    f,
                    "{name}: room for {n} entries, the robot has {dof} joints"
                )
            }
            Message::Argument(name, Fault::MatrixRoom { n, dof }) => write!(
                f,
                "{name}: room for {n} entries, the {dof}-joint robot's matrix has {}",
                dof * dof
            ),
        }
    }
}

impl Failure {
    /// The failure of the argument `name`.
    pub(crate) fn argument(status: pvfc_status, name: &'static str, fault: Fault) -> Self {
        Failure(status, Message::Argument(name, fault))
    }
}

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
        Failure(status, Message::Sim(e))
    }
}

/// The thread's last error message, NUL-terminated, in a fixed buffer (a longer message is cut
/// at a character boundary): recording one allocates nothing.
struct LastError {
    bytes: [u8; LAST_ERROR_CAPACITY],
    len: usize,
}

/// The room for the last error's message, its terminating NUL included.
const LAST_ERROR_CAPACITY: usize = 4096;

impl fmt::Write for LastError {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let room = LAST_ERROR_CAPACITY - 1 - self.len;
        let mut take = s.len().min(room);
        while !s.is_char_boundary(take) {
            take -= 1;
        }
        for (to, from) in self.bytes[self.len..self.len + take]
            .iter_mut()
            .zip(s.bytes())
        {
            // A NUL inside the message would end it early for C: a space instead.
            *to = if from == 0 { b' ' } else { from };
        }
        self.len += take;
        self.bytes[self.len] = 0;
        Ok(())
    }
}

thread_local! {
    static LAST_ERROR: RefCell<LastError> = const {
        RefCell::new(LastError {
            bytes: [0; LAST_ERROR_CAPACITY],
            len: 0,
        })
    };
}

fn set_last_error(message: &dyn fmt::Display) {
    LAST_ERROR.with(|e| {
        let mut e = e.borrow_mut();
        e.len = 0;
        e.bytes[0] = 0;
        // Writing into the buffer cannot fail; a message too long is cut.
        let _ = fmt::Write::write_fmt(&mut *e, format_args!("{message}"));
    });
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
            set_last_error(&format_args!("internal error (a bug in pvfc): {what}"));
            PVFC_ERROR_INTERNAL
        }
    }
}

/// The message of the last error on this thread (empty if none). The pointer stays valid
/// until the next call of a pvfc function on this thread. The message is kept in a fixed
/// buffer of the thread (a message longer than 4,095 bytes is cut): recording it allocates
/// nothing, so the real-time functions allocate nothing even when they fail.
#[no_mangle]
pub extern "C" fn pvfc_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().bytes.as_ptr().cast())
}

/// The major version of the library this header belongs to (`PVFC_VERSION_MAJOR`); compare it
/// with [`pvfc_version`] at run time to check that the header and the library agree.
pub const PVFC_VERSION_MAJOR: u32 = 0;
/// The minor version of the header (`PVFC_VERSION_MINOR`). Before 1.0 a new minor version may
/// change the ABI: the shared library's soname is then `libpvfc_c.so.0.MINOR`.
pub const PVFC_VERSION_MINOR: u32 = 1;
/// The patch version of the header (`PVFC_VERSION_PATCH`).
pub const PVFC_VERSION_PATCH: u32 = 0;

/// The library's version, "MAJOR.MINOR.PATCH" (a static string): the crate's, the CMake
/// package's and the header's `PVFC_VERSION_*`.
#[no_mangle]
pub extern "C" fn pvfc_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}
