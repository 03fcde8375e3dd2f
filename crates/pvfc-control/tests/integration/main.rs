//! The controllers' integration tests, one module per subject, in one test binary. Run one
//! subject with `cargo test -p pvfc-control --test integration <module>::`.

mod axis_target;
mod bad_input;
mod coupling_rate;
mod gcode;
mod tcp;
