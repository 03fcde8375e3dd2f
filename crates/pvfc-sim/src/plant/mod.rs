//! What the simulated plant does besides its rigid-body dynamics: joint friction
//! ([`friction`]) and disturbance torques ([`disturbance`]).

pub mod disturbance;
pub mod friction;
