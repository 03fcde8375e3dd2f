//! pvfc from C and C++: a C ABI over the arm controllers of `pvfc-control` (no simulator is
//! linked), for a robot read from URDF and a closed joint-space contour through waypoints, in
//! the continuous-time form and in the passive digital form (`pvfc_core::passive`). The
//! header `include/pvfc.h` is generated from this crate by cbindgen (a test checks it is
//! fresh).
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

mod args;
pub mod contour;
pub mod controller;
pub mod passive;
pub mod robot;
pub mod status;

pub use contour::*;
pub use controller::*;
pub use passive::*;
pub use robot::*;
pub use status::*;
