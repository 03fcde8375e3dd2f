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

#[riscv_rt::entry]
fn main() -> ! {
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
