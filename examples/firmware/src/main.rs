//! pvfc on a Cortex-M4F: the f32 PVFC controller of the paper's SCARA in a 1 kHz SysTick
//! interrupt, against a plant model integrated on the target (a hardware-in-the-loop
//! stand-in). Prints a compact trace over semihosting and exits with code 0, or 1 after any
//! controller error. Build and run: `cargo run --release` here (QEMU netduinoplus2).
//!
//! Structure, as in a motor controller:
//! * the controller and the plant live in `static`s behind `cortex_m::interrupt::Mutex`
//!   (`RefCell<Option<_>>`, filled once in `main` before the interrupt is enabled);
//! * the SysTick handler owns the control step: read the "encoders" (the plant's state), run
//!   `Controller::step`, apply the torque (the plant advances one period);
//! * on an error the handler applies the fallback torque, zero, and latches a fault: the arm
//!   coasts (the plant's friction stops it), the controller is not stepped again;
//! * `main` sleeps (`wfi`) and prints the trace when the run is over. No float is formatted:
//!   the trace is printed as scaled integers.
#![no_std]
#![no_main]

mod hil;
mod step;

use core::cell::RefCell;
use cortex_m::interrupt::{free, Mutex};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::{debug, hprintln};
use hil::{Plant, Sample, STEPS, TRACE_EVERY};
use panic_halt as _;
use pvfc_core::nalgebra::Vector2;
use pvfc_core::prelude::*;
use step::pvfc_control_step;

/// The core clock of the STM32F405 as QEMU models it (Hz).
const CORE_CLOCK: u32 = 168_000_000;
/// The control rate (Hz).
const RATE: u32 = 1_000;

/// Everything the control interrupt owns.
struct Loop {
    controller: ScaraLissajousController<f32>,
    plant: Plant<f32>,
    steps: usize,
    fault: Option<ErrorKind>,
}

static LOOP: Mutex<RefCell<Option<Loop>>> = Mutex::new(RefCell::new(None));

/// The trace, apart from `LOOP` so that its all-zero initial value lands in `.bss` (RAM
/// cleared at reset) rather than in `.data` (an initial image kept in flash).
static TRACE: Mutex<RefCell<[Sample<f32>; STEPS / TRACE_EVERY]>> = Mutex::new(RefCell::new(
    [Sample {
        step: 0,
        q: [0.0; 2],
        torque: [0.0; 2],
        tau: 0.0,
        potential: 0.0,
        kinetic_energy: 0.0,
    }; STEPS / TRACE_EVERY],
));

#[exception]
fn SysTick() {
    free(|cs| {
        let mut cell = LOOP.borrow(cs).borrow_mut();
        let Some(lp) = cell.as_mut() else { return };
        if lp.steps >= STEPS {
            return;
        }
        let (q, v) = (lp.plant.q, lp.plant.v);
        let mut torque = Vector2::zeros(); // the fallback: no torque
        let mut potential = f32::NAN;
        if lp.fault.is_none() {
            match pvfc_control_step(&mut lp.controller, &Torus::new(q), &v) {
                Ok(out) => {
                    torque = out.torque;
                    potential = out.diagnostics.potential;
                }
                Err(e) => lp.fault = Some(e.kind()),
            }
        }
        if lp.steps % TRACE_EVERY == 0 {
            let s = lp.controller.state();
            let mf = lp.controller.law().flywheel().inertia();
            TRACE.borrow(cs).borrow_mut()[lp.steps / TRACE_EVERY] = Sample {
                step: lp.steps,
                q: [q[0], q[1]],
                torque: [torque[0], torque[1]],
                tau: s.unwrapped_tau(lp.controller.law().field().period()),
                potential,
                kinetic_energy: lp.plant.kinetic_energy()
                    + 0.5 * (s.tau_dot * s.tau_dot + mf * s.flywheel_speed * s.flywheel_speed),
            };
        }
        lp.plant.advance(&torque);
        lp.steps += 1;
    });
}

#[entry]
fn main() -> ! {
    let controller = match hil::controller::<f32>() {
        Ok(c) => c,
        Err(_) => {
            hprintln!("pvfc: invalid controller constants");
            debug::exit(debug::EXIT_FAILURE);
            halt()
        }
    };
    free(|cs| {
        LOOP.borrow(cs).replace(Some(Loop {
            controller,
            plant: Plant::default(),
            steps: 0,
            fault: None,
        }))
    });
    let mut cp = match cortex_m::Peripherals::take() {
        Some(p) => p,
        None => halt(),
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(CORE_CLOCK / RATE - 1);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
    cp.SYST.enable_interrupt();
    loop {
        cortex_m::asm::wfi();
        let done = free(|cs| {
            LOOP.borrow(cs)
                .borrow()
                .as_ref()
                .is_some_and(|lp| lp.steps >= STEPS)
        });
        if done {
            cp.SYST.disable_interrupt();
            report();
        }
    }
}

/// Prints the trace (scaled 32-bit integers, so that no 64-bit division is linked: q in µrad,
/// torque in mN·m, τ in 1e-6, U in 1e-9 (U ≤ 2.1), κ_a in µJ (κ_a ≤ 2.1 kJ)) and the final line, then exits: 0, or 1 after a controller error.
fn report() -> ! {
    let (trace, fault) = free(|cs| {
        let fault = LOOP.borrow(cs).borrow().as_ref().and_then(|lp| lp.fault);
        (*TRACE.borrow(cs).borrow(), fault)
    });
    hprintln!("# step q1_urad q2_urad t1_mNm t2_mNm tau_e6 U_e9 kappa_uJ");
    for s in trace.iter() {
        hprintln!("{}", s.printed());
    }
    match fault {
        None => {
            hprintln!("pvfc: done, {} steps, no fault", STEPS);
            debug::exit(debug::EXIT_SUCCESS);
        }
        Some(kind) => {
            hprintln!("pvfc: FAULT: {}", kind.as_str());
            debug::exit(debug::EXIT_FAILURE);
        }
    }
    halt()
}

/// Sleeps for ever (after the exit request, or if the peripherals were already taken).
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
