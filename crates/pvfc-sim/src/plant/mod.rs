//! What the simulated plant does besides its rigid-body dynamics: joint friction
//! ([`friction`]), disturbance torques ([`disturbance`]), and the faults of the loop
//! ([`faults`]): its sensors, clock, drive and impacts.

pub mod disturbance;
pub mod faults;
pub mod friction;
