//! The core's integration and property tests, one module per subject, in one test binary (one
//! link and one compilation of the generic laws instead of one per file). Run one subject with
//! `cargo test -p pvfc-core --test integration <module>::`.

mod common;

mod control_law;
mod errors;
mod fast_math;
mod forward_dynamics;
mod learned_pace;
mod lie_axioms;
mod navigation_contours;
mod obstacles;
mod pace;
mod passive;
mod serial_chain;
mod throttle;
