//! pvfc in RTIC 2 on the STM32F405 (QEMU's `netduinoplus2`): the template of a motor
//! controller. Build and run: `cargo run --release -p pvfc-firmware-rtic` in
//! `examples/firmware`.
//!
//! Tasks by priority, each owning what it alone touches:
//!
//! | task | priority | runs | owns (local) | shares |
//! |---|---|---|---|---|
//! | `control` | 3 (highest) | SysTick, 1 kHz | the controller, the plant, the telemetry sender | `setpoint` (reads), `period` (writes) |
//! | `command` | 2 | when a command arrives | | `setpoint` (writes) |
//! | `telemetry` | 1 | when a message is queued | the telemetry receiver | |
//! | `idle` | 0 | between interrupts: the operator's script | | `period` (reads) |
//!
//! The control task reads the encoders' counts, steps the passive controller
//! (`PassiveController`: positions only, 2¹⁷ counts a turn, the command clamped to the drives'
//! ±5 N·m) and applies the torque; here the "drives" are the Pelican SCARA of `src/hil.rs`
//! integrated on the chip (a hardware-in-the-loop stand-in). A command is a request: the
//! command task writes the setpoint, and the control task applies it at the start of its next
//! period, so the controller is never locked or shared. A controller error latches a fault:
//! from that period on the drives get the safe torque, zero (the arm coasts to rest against
//! its friction), and the controller is not stepped again.
//!
//! The telemetry task prints, over semihosting, one line per command applied
//! (`cmd STEP run SPEED_e3`), a sample every 100 periods (the bare firmware's integers, `q` in
//! µrad, torque in mN·m, `τ` in 1e-6, `U` in 1e-9, the arm's kinetic energy in µJ) and a last
//! line; QEMU exits 0 after 10,000 periods without a fault, 1 otherwise.
//!
//! The timer is SysTick, on the core clock: every Cortex-M has it (the template ports to
//! the M0+, M33 and M7 unchanged), and QEMU 7.2 models it exactly. QEMU 7.2's model of the
//! STM32F405's general-purpose timers does not keep their period (TIM2 programmed for 1 ms
//! update events, a 1 MHz count up to 999, interrupted every 1.6 ms here: its alarm is
//! re-armed from the last hit, not from the counter's reload; upstream QEMU rewrote the model
//! after 8.2); on the chip, a motor controller would put the control task on TIM1's or TIM8's
//! update interrupt, the timers that also drive its PWM, and nothing else here changes.
#![no_std]
#![no_main]

#[path = "../../src/hil.rs"]
#[allow(dead_code)] // the bare firmware's trace buffer and constants
mod hil;

#[path = "../../src/drive.rs"]
mod drive;

use panic_halt as _;

/// The core clock (Hz), SysTick's.
pub const CORE_CLOCK: u32 = 168_000_000;
/// The control rate (Hz).
pub const RATE: u32 = 1_000;
/// Control periods in a run.
pub const STEPS: u32 = 10_000;

/// What the control task reports.
#[derive(Clone, Copy, Debug)]
pub enum Telemetry {
    /// A setpoint applied at the start of period `step`.
    Command {
        step: u32,
        setpoint: drive::Setpoint,
    },
    /// A sample.
    Sample(hil::Sample<f32>),
    /// A latched fault.
    Fault {
        step: u32,
        kind: pvfc_core::ErrorKind,
    },
    /// The run is over: messages the channel could not take, and whether it faulted.
    Done { dropped: u32, faulted: bool },
}

/// One control period of the drive, out of line so that its instructions can be counted from
/// an execution trace (`scripts/firmware_instructions.py --symbol pvfc_drive_period`).
#[no_mangle]
#[inline(never)]
pub fn pvfc_drive_period(
    drive: &mut drive::Drive<f32>,
    setpoint: drive::Setpoint,
    counts: [i32; 2],
) -> drive::Period<f32> {
    drive.period(setpoint, counts)
}

#[rtic::app(device = stm32f4::stm32f405, peripherals = true, dispatchers = [EXTI0, EXTI1])]
mod app {
    use super::drive::{encoder_counts, Command, Drive, Setpoint, SCRIPT};
    use super::{hil, pvfc_drive_period, Telemetry, CORE_CLOCK, RATE, STEPS};
    use cortex_m::peripheral::syst::SystClkSource;
    use cortex_m_semihosting::{debug, hprintln};
    use pvfc_core::prelude::*;
    use rtic_sync::channel::{Receiver, Sender};
    use rtic_sync::make_channel;

    /// Telemetry messages in flight.
    const QUEUE: usize = 16;

    #[shared]
    struct Shared {
        setpoint: Setpoint,
        /// Control periods done.
        period: u32,
    }

    #[local]
    struct Local {
        drive: Drive<f32>,
        plant: hil::Plant<f32>,
        tx: Sender<'static, Telemetry, QUEUE>,
        rx: Receiver<'static, Telemetry, QUEUE>,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let drive = match Drive::new() {
            Ok(d) => d,
            Err(e) => {
                hprintln!(
                    "pvfc rtic: invalid controller constants: {}",
                    e.kind().as_str()
                );
                debug::exit(debug::EXIT_FAILURE);
                #[allow(clippy::empty_loop)]
                loop {}
            }
        };
        let (tx, rx) = make_channel!(Telemetry, QUEUE);
        telemetry::spawn().ok();
        // SysTick: an exception every core-clock period of the control rate.
        let mut syst = cx.core.SYST;
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(CORE_CLOCK / RATE - 1);
        syst.clear_current();
        syst.enable_counter();
        syst.enable_interrupt();
        (
            Shared {
                setpoint: Setpoint::STOPPED,
                period: 0,
            },
            Local {
                drive,
                plant: hil::Plant::default(),
                tx,
                rx,
            },
        )
    }

    /// The operator's script ([`SCRIPT`]): each command is sent once the control task has
    /// done the period before it.
    #[idle(shared = [period])]
    fn idle(mut cx: idle::Context) -> ! {
        let mut next = 0;
        loop {
            cortex_m::asm::wfi();
            let period = cx.shared.period.lock(|p| *p);
            if let Some(&(at, command)) = SCRIPT.get(next) {
                // One command at a time: a refused spawn (the last not yet taken) is retried.
                if period >= at && command::spawn(command).is_ok() {
                    next += 1;
                }
            }
        }
    }

    /// One control period: the setpoint, the encoders, the step, the drives, the telemetry.
    #[task(binds = SysTick, priority = 3, shared = [setpoint, period],
           local = [drive, plant, tx, dropped: u32 = 0, done: bool = false])]
    fn control(mut cx: control::Context) {
        let l = cx.local;
        let step = cx.shared.period.lock(|p| *p);
        if step >= STEPS {
            // The run is over: report once the channel takes it.
            let done = Telemetry::Done {
                dropped: *l.dropped,
                faulted: l.drive.fault().is_some(),
            };
            if !*l.done && l.tx.try_send(done).is_ok() {
                *l.done = true;
            }
            return;
        }
        let setpoint = cx.shared.setpoint.lock(|s| *s);
        let out = pvfc_drive_period(l.drive, setpoint, encoder_counts(&l.plant.q));
        let mut report = |message: Telemetry| {
            if l.tx.try_send(message).is_err() {
                *l.dropped += 1;
            }
        };
        if out.applied {
            report(Telemetry::Command { step, setpoint });
        }
        if let Some(kind) = out.fault {
            report(Telemetry::Fault { step, kind });
        }
        if step % hil::TRACE_EVERY as u32 == 0 {
            let c = l.drive.controller().controller();
            report(Telemetry::Sample(hil::Sample {
                step: step as usize,
                q: [l.plant.q[0], l.plant.q[1]],
                torque: [out.torque[0], out.torque[1]],
                tau: c.state().unwrapped_tau(c.law().field().period()),
                potential: out.potential.unwrap_or(f32::NAN),
                kinetic_energy: l.plant.kinetic_energy(),
            }));
        }
        // The drives.
        l.plant.advance(&out.torque);
        cx.shared.period.lock(|p| *p = step + 1);
    }

    /// Takes an operator's command: the control task applies it at its next period.
    #[task(priority = 2, shared = [setpoint])]
    async fn command(mut cx: command::Context, command: Command) {
        cx.shared.setpoint.lock(|s| *s = s.after(command));
    }

    /// Prints what the control task reports (semihosting: slow, and preempted by the control
    /// task), then ends the run.
    #[task(priority = 1, local = [rx])]
    async fn telemetry(cx: telemetry::Context) {
        hprintln!("# step q1_urad q2_urad t1_mNm t2_mNm tau_e6 U_e9 kappa_uJ");
        while let Ok(message) = cx.local.rx.recv().await {
            match message {
                Telemetry::Command { step, setpoint } => hprintln!(
                    "cmd {} {} {}",
                    step,
                    u8::from(setpoint.run),
                    (setpoint.speed * 1e3) as i32
                ),
                Telemetry::Sample(s) => {
                    hprintln!("{}", s.printed())
                }
                Telemetry::Fault { step, kind } => {
                    hprintln!("pvfc rtic: FAULT at period {}: {}", step, kind.as_str())
                }
                Telemetry::Done { dropped, faulted } => {
                    if faulted {
                        hprintln!("pvfc rtic: done, {} periods, faulted", STEPS);
                        debug::exit(debug::EXIT_FAILURE);
                    } else {
                        hprintln!(
                            "pvfc rtic: done, {} periods, {} messages dropped, no fault",
                            STEPS,
                            dropped
                        );
                        debug::exit(debug::EXIT_SUCCESS);
                    }
                }
            }
        }
    }
}
