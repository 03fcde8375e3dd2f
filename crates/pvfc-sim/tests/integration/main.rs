//! The simulator's integration tests, one module per subject, in one test binary (one link
//! and one compilation of the generic runs instead of one per file). Run one subject with
//! `cargo test -p pvfc-sim --test integration <module>::`.

mod common;

mod cartesian_paths;
mod chain_scenarios;
mod contact;
mod contour_kinds;
mod convergence_rate;
mod disturbance;
mod energy_level;
mod energy_loop;
mod faults;
mod files;
mod friction;
mod obstacles;
mod pace;
mod pace_learning;
mod pace_throttle;
mod rigid_body;
mod robot_kinds;
mod spatial_contact;
mod speed_along;
mod study;
mod task_field;
mod task_scenarios;
mod tool_frame;
mod tool_path_budget;
mod unsaturated_accuracy;
mod urdf_chain;
