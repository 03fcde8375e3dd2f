//! Any text as a part program (G-code): a closed tool path (then sampled, and a point's
//! closest point found) or an error with a line and column; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pvfc_control::model::gcode::PartProgram;

fuzz_target!(|text: &str| {
    let program = match PartProgram::parse(text) {
        Ok(p) => p,
        Err(e) => {
            assert!(e.line >= 1 && e.column >= 1);
            return;
        }
    };
    if let Ok(path) = program.tool_path() {
        let l = path.length();
        assert!(l.is_finite() && l > 0.0);
        let p = path.point(0.37 * l);
        let c = path.closest(&(p + nalgebra::Vector3::new(1e-3, -2e-3, 5e-4)));
        assert!(c.distance.is_finite());
    }
});
