//! The checks of what the caller passes: pointers, lengths, finite numbers, strings,
//! handles.

use crate::status::*;
use std::ffi::{c_char, CStr};

/// The error of a NULL pointer that must not be.
pub(crate) fn null(name: &'static str) -> Failure {
    Failure::argument(PVFC_ERROR_NULL_POINTER, name, Fault::Null)
}

/// The `n` doubles at `p`, checked: not NULL (unless `n` is 0) and finite.
///
/// # Safety
/// `p` must point to `n` readable doubles that outlive the returned slice.
pub(crate) unsafe fn doubles<'a>(
    p: *const f64,
    n: usize,
    name: &'static str,
) -> Result<&'a [f64], Failure> {
    // SAFETY: forwarded from the caller.
    let x = unsafe { any_doubles(p, n, name) }?;
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(Failure::argument(
            PVFC_ERROR_NON_FINITE,
            name,
            Fault::NonFinite {
                index: Some(i),
                value: x[i],
            },
        ));
    }
    Ok(x)
}

/// An optional array: the `n` doubles at `p` (checked as [`doubles`]), or `None` for NULL.
///
/// # Safety
/// `p` is NULL or points to `n` readable doubles.
pub(crate) unsafe fn optional(
    p: *const f64,
    n: usize,
    name: &'static str,
) -> Result<Option<Vec<f64>>, Failure> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: forwarded from the caller.
    Ok(Some(unsafe { doubles(p, n, name) }?.to_vec()))
}

/// An optional point or vector of 3 doubles, `None` for NULL.
///
/// # Safety
/// `p` is NULL or points to 3 readable doubles.
pub(crate) unsafe fn triple(
    p: *const f64,
    name: &'static str,
) -> Result<Option<[f64; 3]>, Failure> {
    // SAFETY: forwarded from the caller.
    Ok(unsafe { optional(p, 3, name) }?.map(|x| [x[0], x[1], x[2]]))
}

/// The doubles of a joint vector: exactly `dof` of them.
///
/// # Safety
/// As [`doubles`].
pub(crate) unsafe fn joints<'a>(
    p: *const f64,
    n: usize,
    dof: usize,
    name: &'static str,
) -> Result<&'a [f64], Failure> {
    if n != dof {
        return Err(Failure::argument(
            PVFC_ERROR_WRONG_SIZE,
            name,
            Fault::Entries { n, dof },
        ));
    }
    // SAFETY: forwarded from the caller.
    unsafe { doubles(p, n, name) }
}

/// `n` doubles at `p`, whatever their values (NaN and infinities included: a reading the
/// passive controller's supervision judges).
///
/// # Safety
/// `p` must point to `n` readable doubles, or be NULL (an error).
pub(crate) unsafe fn any_doubles<'a>(
    p: *const f64,
    n: usize,
    name: &'static str,
) -> Result<&'a [f64], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(null(name));
    }
    // SAFETY: the caller gives n readable doubles at p (the header documents it).
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// A joint vector of exactly `dof` doubles at `p`, whatever their values ([`any_doubles`]);
/// `None` for NULL when `optional`.
///
/// # Safety
/// `p` is NULL or points to `n` readable doubles.
pub(crate) unsafe fn any_joints<'a>(
    p: *const f64,
    n: usize,
    dof: usize,
    (name, optional): (&'static str, bool),
) -> Result<Option<&'a [f64]>, Failure> {
    if optional && p.is_null() {
        return Ok(None);
    }
    if n != dof {
        return Err(Failure::argument(
            PVFC_ERROR_WRONG_SIZE,
            name,
            Fault::Entries { n, dof },
        ));
    }
    // SAFETY: forwarded from the caller.
    unsafe { any_doubles(p, n, name) }.map(Some)
}

/// An optional joint vector: `None` for NULL, else exactly `dof` doubles (as [`joints`]).
///
/// # Safety
/// `p` is NULL or points to `n` readable doubles.
pub(crate) unsafe fn optional_joints<'a>(
    p: *const f64,
    n: usize,
    dof: usize,
    name: &'static str,
) -> Result<Option<&'a [f64]>, Failure> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: forwarded from the caller.
    unsafe { joints(p, n, dof, name) }.map(Some)
}

/// The caller's output array of `dof` doubles.
///
/// # Safety
/// `p` must point to `n` writable doubles.
pub(crate) unsafe fn output<'a>(
    p: *mut f64,
    n: usize,
    dof: usize,
    name: &'static str,
) -> Result<&'a mut [f64], Failure> {
    if p.is_null() {
        return Err(null(name));
    }
    if n != dof {
        return Err(Failure::argument(
            PVFC_ERROR_WRONG_SIZE,
            name,
            Fault::Room { n, dof },
        ));
    }
    // SAFETY: the caller gives n writable doubles at p.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// An optional C string (NULL: `None`), as UTF-8.
///
/// # Safety
/// `p` is NULL or a NUL-terminated string.
pub(crate) unsafe fn text<'a>(
    p: *const c_char,
    name: &'static str,
) -> Result<Option<&'a str>, Failure> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: the caller gives a NUL-terminated string.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str().map(Some).map_err(|_| {
        Failure(
            PVFC_ERROR_INVALID_ARGUMENT,
            format!("{name}: not UTF-8").into(),
        )
    })
}

/// The object behind a handle.
///
/// # Safety
/// `p` is NULL or a live handle of this type.
pub(crate) unsafe fn object<'a, T>(p: *const T, name: &'static str) -> Result<&'a T, Failure> {
    // SAFETY: a live handle made by this library.
    unsafe { p.as_ref() }.ok_or_else(|| null(name))
}

/// The object behind a handle, to change.
///
/// # Safety
/// `p` is NULL or a live handle of this type, not used elsewhere meanwhile.
pub(crate) unsafe fn object_mut<'a, T>(
    p: *mut T,
    name: &'static str,
) -> Result<&'a mut T, Failure> {
    // SAFETY: a live handle made by this library, used by one thread at a time.
    unsafe { p.as_mut() }.ok_or_else(|| null(name))
}

/// Stores a new object in `*out`.
///
/// # Safety
/// `out` is NULL or writable.
pub(crate) unsafe fn give<T>(out: *mut *mut T, x: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(null("out"));
    }
    // SAFETY: out is writable (checked not NULL).
    unsafe { *out = Box::into_raw(Box::new(x)) };
    Ok(())
}

/// A settings struct whose first field is its `size` as the caller was compiled with.
pub(crate) trait SizedStruct {
    /// The `size` field.
    fn size(&self) -> usize;
}

/// The struct at `p` (NULL: `default`), checked for its `size` (a caller compiled against
/// another version of the header gets an error, not a misread struct).
///
/// # Safety
/// `p` is NULL or points to a readable `T`.
pub(crate) unsafe fn sized<T: SizedStruct + Copy>(
    p: *const T,
    default: T,
    name: &'static str,
) -> Result<T, Failure> {
    // SAFETY: NULL or readable.
    let s = unsafe { p.as_ref() }.copied().unwrap_or(default);
    let expected = std::mem::size_of::<T>();
    if s.size() != expected {
        return Err(Failure(
            PVFC_ERROR_WRONG_SIZE,
            format!(
                "{name}: size {} but this library's {} is {expected} bytes (start from its _default function)",
                s.size(),
                std::any::type_name::<T>().rsplit("::").next().unwrap_or("struct"),
            )
            .into(),
        ));
    }
    Ok(s)
}
