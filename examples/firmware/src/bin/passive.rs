//! The passive digital controller (`pvfc_core::passive`) on the target: the SCARA of
//! `src/hil.rs` driven for 1,000 periods at 1 kHz by a `PassiveController` that measures
//! positions only, through a 2¹⁷-count encoder, with its command clamped to ±5 N·m, against
//! the plant integrated on the target. For the instruction counts
//! (`scripts/firmware_instructions.py --symbol …`), two shadow controllers are stepped at the
//! same measured states (`q` and the plant's `q̇`): `Controller::step`
//! (`pvfc_control_step`) and the passive step with the velocity measured, as the host's
//! criterion bench steps it (`pvfc_passive_step`); the loop's own step is
//! `pvfc_encoder_step`. Prints `U` at the start and the end and the storage, exits 0 if `U`
//! fell and nothing faulted.
#![no_std]
#![no_main]

#[path = "../hil.rs"]
#[allow(dead_code)] // the loop's constants and trace are the SysTick firmware's
mod hil;
#[path = "../step.rs"]
mod step;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use hil::Plant;
use panic_halt as _;
use pvfc_core::lie::Torus;
use pvfc_core::nalgebra::{ComplexField, Vector2};
use pvfc_core::prelude::*;
use step::pvfc_control_step;

/// The passive controller of the paper's SCARA.
type Passive = PassiveController<
    f32,
    Torus<f32, 2>,
    Scara<f32>,
    SuspendedField<
        f32,
        Torus<f32, 2>,
        Lissajous<f32, 2>,
        TorusNavigation<f32, 2>,
        ExponentialPacing<f32>,
        2,
    >,
    2,
>;

/// Control periods in the run.
const STEPS: usize = 1_000;
/// One encoder count (rad): 2¹⁷ counts per turn.
const COUNT: f32 = core::f32::consts::TAU / 131_072.0;
/// The drives' torque limit (N·m).
const LIMIT: f32 = 3.0;

/// The passive step with the velocity measured (as the host bench runs it), out of line.
#[no_mangle]
#[inline(never)]
fn pvfc_passive_step(
    ctl: &mut Passive,
    q: &Torus<f32, 2>,
    v: &Vector2<f32>,
) -> Result<PassiveStepOutput<f32, 2>, Error> {
    ctl.step(q, Some(v), None, hil::DT as f32)
}

/// The passive step from encoder positions only (the loop's controller), out of line.
#[no_mangle]
#[inline(never)]
fn pvfc_encoder_step(
    ctl: &mut Passive,
    q: &Torus<f32, 2>,
) -> Result<PassiveStepOutput<f32, 2>, Error> {
    ctl.step(q, None, None, hil::DT as f32)
}

/// The encoder's reading of an angle (rounded to a count).
fn encoder(q: &Vector2<f32>) -> Torus<f32, 2> {
    Torus::new(q.map(|x| ComplexField::round(x / COUNT) * COUNT))
}

#[entry]
fn main() -> ! {
    let code = match run() {
        Ok(r) if r.u1 < r.u0 => {
            hprintln!(
                "pvfc passive: U {} -> {} (1e-6), storage {} -> {} (mJ), {} periods saturated, no fault",
                (r.u0 * 1e6) as i32,
                (r.u1 * 1e6) as i32,
                (r.s0 * 1e3) as i32,
                (r.s1 * 1e3) as i32,
                r.saturated
            );
            debug::EXIT_SUCCESS
        }
        Ok(r) => {
            hprintln!(
                "pvfc passive: U did not fall: {} -> {} (1e-6)",
                (r.u0 * 1e6) as i32,
                (r.u1 * 1e6) as i32
            );
            debug::EXIT_FAILURE
        }
        Err(e) => {
            hprintln!("pvfc passive: FAULT: {}", e.kind().as_str());
            debug::EXIT_FAILURE
        }
    };
    debug::exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}

/// What the run reports.
struct Run {
    u0: f32,
    u1: f32,
    s0: f32,
    s1: f32,
    saturated: usize,
}

fn run() -> Result<Run, Error> {
    let mut shadow = hil::controller::<f32>()?;
    let mut shadow_passive = PassiveController::new(hil::controller::<f32>()?);
    let mut ctl = PassiveController::new(hil::controller::<f32>()?)
        .with_encoder_resolution(Vector2::repeat(COUNT))?
        .with_velocity_filter(2e-3)?
        .with_torque_limits(Vector2::repeat(LIMIT))?;
    let mut plant = Plant::<f32>::default();
    let mut r = Run {
        u0: f32::NAN,
        u1: f32::NAN,
        s0: ctl.storage(),
        s1: f32::NAN,
        saturated: 0,
    };
    for k in 0..STEPS {
        let q = Torus::new(plant.q);
        pvfc_control_step(&mut shadow, &q, &plant.v)?;
        pvfc_passive_step(&mut shadow_passive, &q, &plant.v)?;
        let out = pvfc_encoder_step(&mut ctl, &encoder(&plant.q))?;
        if k == 0 {
            r.u0 = out.diagnostics.potential;
        }
        r.u1 = out.diagnostics.potential;
        r.saturated += usize::from(out.energy.saturated);
        plant.advance(&out.torque);
    }
    r.s1 = ctl.storage();
    Ok(r)
}
