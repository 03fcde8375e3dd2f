//! `Controller::step` of the paper's SCARA behind a symbol of its own, shared by the SysTick
//! firmware and `--bin passive`.

use pvfc_core::nalgebra::Vector2;
use pvfc_core::prelude::*;

/// One control step, out of line so that its instructions can be counted from an execution
/// trace (`scripts/firmware_instructions.py`).
#[no_mangle]
#[inline(never)]
pub fn pvfc_control_step(
    ctl: &mut ScaraLissajousController<f32>,
    q: &Torus<f32, 2>,
    v: &Vector2<f32>,
) -> Result<StepOutput<f32, 2>, Error> {
    ctl.step(q, v, crate::hil::DT as f32)
}
