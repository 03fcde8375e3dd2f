//! Any text as a URDF: a chain (with any of its links as the tip), or an error; never a
//! panic, an abort or a loop without end.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pvfc_control::model::robot::Robot;
use pvfc_control::urdf::ChainDescription;
use std::path::Path;

fuzz_target!(|text: &str| {
    let path = Path::new("fuzz.urdf");
    for tip in [None, Some("tool"), Some("a")] {
        if let Ok(d) = ChainDescription::from_str(text, path, None, tip) {
            if let Ok(robot) = Robot::from_description(d) {
                let q = vec![0.1; robot.dof()];
                let _ = robot.inertia(&q);
                let _ = robot.gravity(&q);
            }
        }
    }
});
