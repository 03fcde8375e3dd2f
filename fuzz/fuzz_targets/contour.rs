//! Any text as a `[contour]` table: a contour spec (then built as a joint contour, or a
//! Cartesian path's geometry) or an error; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pvfc_control::model::arm::DynJointContour;
use pvfc_control::model::contour::ContourSpec;
use std::path::Path;

fuzz_target!(|text: &str| {
    let Ok(spec) = toml::from_str::<ContourSpec>(text) else {
        return;
    };
    match spec {
        ContourSpec::Joint(j) => {
            if let Ok(c) = DynJointContour::new(&j, None) {
                let _ = c.sample(0.3);
            }
        }
        ContourSpec::Cartesian(c) => {
            if let Ok(p) = c.path(Path::new(".")) {
                let _ = p.point(0.25 * p.length());
            }
        }
        ContourSpec::Attitude(_) => {}
    }
});
