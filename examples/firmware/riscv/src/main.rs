//! The SCARA step of `examples/firmware` on RISC-V (RV32IMAC, f32 in software), in QEMU's
//! `virt` machine: the bare firmware's closed loop (`src/hil.rs`: the paper's controller with
//! friction compensation against the plant integrated on the target), stepped in `main`
//! rather than in a timer interrupt, so that it runs on any RISC-V core as it is. Prints the
//! same trace as the Cortex-M firmware (compared with the host twin by `scripts/cores.sh`),
//! then the instructions of a step read from the core's `minstret` counter around
//! `pvfc_control_step` (QEMU counts them exactly with `-icount`), and exits 0, or 1 after a
//! controller error.
#![no_std]
#![no_main]

#[path = "../../src/hil.rs"]
mod hil;
#[path = "../../src/step.rs"]
mod step;

use hil::{Plant, Sample, STEPS, TRACE_EVERY};
use pvfc_core::prelude::*;
use riscv::register::minstret;
use semihosting::{println, process};
use step::pvfc_control_step;

/// Steps whose instructions are counted.
const COUNTED: usize = 1_000;

/// The stack below `main`'s frame painted with this before the run; the deepest word no
/// longer holding it marks how far the stack grew.
const PAINT: u32 = 0x5A5A_A5A5;
/// How much of the stack below `main`'s frame is painted (bytes).
const PAINTED: usize = 64 * 1024;

extern "C" {
    /// The top of the stack (riscv-rt's linker script): `sp` at reset.
    static _stack_start: u8;
}

/// The stack pointer.
#[inline(always)]
fn stack_pointer() -> usize {
    let sp: usize;
    // SAFETY: reads a register into a local; touches no memory.
    unsafe { core::arch::asm!("mv {}, sp", out(reg) sp) };
    sp
}

/// Paints the `PAINTED` bytes below the stack pointer `sp` (less a margin for this function's
/// own use, which needs none: its locals are in registers, and RISC-V has no red zone).
/// Returns the lowest painted address.
fn paint_stack(sp: usize) -> usize {
    let bottom = (sp - PAINTED) & !3;
    let mut a = bottom;
    while a < (sp - 64) & !3 {
        // SAFETY: the words between `bottom` and `sp` are the free stack below main's frame:
        // nothing lives there until a call made after this one.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
        a += 4;
    }
    bottom
}

/// The deepest address the stack reached since [`paint_stack`] painted from `bottom` up.
fn deepest(bottom: usize, sp: usize) -> usize {
    let mut a = bottom;
    // SAFETY: reads the words painted above, within the stack.
    while a < sp && unsafe { core::ptr::read_volatile(a as *const u32) } == PAINT {
        a += 4;
    }
    a
}

#[riscv_rt::entry]
fn main() -> ! {
    let sp = stack_pointer();
    let painted = paint_stack(sp);
    let mut controller = match hil::controller::<f32>() {
        Ok(c) => c,
        Err(e) => {
            println!("pvfc: invalid controller constants: {}", e.kind().as_str());
            process::exit(1)
        }
    };
    let mut plant = Plant::<f32>::default();
    let mut counts = [0u32; COUNTED];
    println!("# step q1_urad q2_urad t1_mNm t2_mNm tau_e6 U_e9 kappa_uJ");
    for step in 0..STEPS {
        let (q, v) = (plant.q, plant.v);
        let before = minstret::read();
        let out = pvfc_control_step(&mut controller, &Torus::new(q), &v);
        let spent = minstret::read().wrapping_sub(before) as u32;
        let out = match out {
            Ok(o) => o,
            Err(e) => {
                println!("pvfc: FAULT: {}", e.kind().as_str());
                process::exit(1)
            }
        };
        if let Some(c) = counts.get_mut(step) {
            *c = spent;
        }
        if step % TRACE_EVERY == 0 {
            let s = controller.state();
            let mf = controller.law().flywheel().inertia();
            let sample = Sample {
                step,
                q: [q[0], q[1]],
                torque: [out.torque[0], out.torque[1]],
                tau: s.unwrapped_tau(controller.law().field().period()),
                potential: out.diagnostics.potential,
                kinetic_energy: plant.kinetic_energy()
                    + 0.5 * (s.tau_dot * s.tau_dot + mf * s.flywheel_speed * s.flywheel_speed),
            };
            println!("{}", sample.printed());
        }
        plant.advance(&out.torque);
    }
    println!("pvfc: done, {} steps, no fault", STEPS);
    let deepest = deepest(painted, sp);
    // The address of a linker symbol; never read.
    let top = core::ptr::addr_of!(_stack_start) as usize;
    println!(
        "stack: {} B at most ({} B from the top to main's frame, whose counts of instructions take {} B; {} B below it)",
        top - deepest,
        top - sp,
        core::mem::size_of::<[u32; COUNTED]>(),
        sp - deepest
    );
    counts.sort_unstable();
    println!(
        "instructions per step (minstret, {} steps): median {}, min {}, max {}",
        COUNTED,
        counts[COUNTED / 2],
        counts[0],
        counts[COUNTED - 1]
    );
    process::exit(0)
}
