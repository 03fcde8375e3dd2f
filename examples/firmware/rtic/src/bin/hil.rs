//! The RTIC drive in the loop with a plant on the host (issue 49): the passive controller of
//! `src/drive.rs` takes each period's encoder counts from the host over USART1 and sends the
//! torque back (`pvfc-link`'s frames). The host drives time: each `Sense` it sends is one
//! control period, answered by one `Actuate` of the same sequence number. Run it with
//! `scripts/hil.sh` (QEMU's USART1 on a Unix socket, the host's side in
//! `tests/firmware_twin.rs`).
//!
//! On the line:
//! * a frame the drive cannot read (a CRC that does not match, a stray byte) is counted and not
//!   answered: the host, getting no answer, sends the period again;
//! * the period just answered, sent again (the host did not get the answer in time), is
//!   answered again with the same frame, and no period runs;
//! * a period number that is not the last plus one (a period the host ran without this drive's
//!   torque) latches a link fault: the safe torque, zero, from then on, as after a controller
//!   error, reported in every answer (`DriveState::Fault`).
#![no_std]
#![no_main]

#[path = "../../../src/hil.rs"]
#[allow(dead_code)] // the plant is the host's here
mod hil;

#[path = "../../../src/drive.rs"]
#[allow(dead_code)] // the script is the host's here
mod drive;

use panic_halt as _;

/// The fault code of a link fault (`DriveState::Fault`): a controller error's code is its
/// `ErrorKind`'s index.
pub const LINK_FAULT: u8 = 255;

#[rtic::app(device = stm32f4::stm32f405, peripherals = true)]
mod app {
    use super::drive::{Drive, Setpoint};
    use super::LINK_FAULT;
    use cortex_m_semihosting::{debug, hprintln};
    use pvfc_link::{encode, Actuate, Decoder, DriveState, Sense, MAX_FRAME};
    use stm32f4::stm32f405::USART1;

    #[shared]
    struct Shared {}

    #[local]
    struct Local {
        usart: USART1,
        decoder: Decoder<Sense>,
        drive: Drive<f32>,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        let dp = cx.device;
        dp.RCC.apb2enr().modify(|_, w| w.usart1en().set_bit());
        let usart = dp.USART1;
        // 460,800 baud from APB2's 84 MHz (USARTDIV 11.375: mantissa 11, fraction 6/16; QEMU
        // models no baud rate), 8N1, receive interrupt on.
        usart.brr().write(|w| {
            w.div_mantissa().set(11);
            w.div_fraction().set(6)
        });
        usart.cr1().write(|w| {
            w.ue()
                .set_bit()
                .te()
                .set_bit()
                .re()
                .set_bit()
                .rxneie()
                .set_bit()
        });
        let drive = match Drive::new() {
            Ok(d) => d,
            Err(e) => {
                hprintln!(
                    "pvfc hil: invalid controller constants: {}",
                    e.kind().as_str()
                );
                debug::exit(debug::EXIT_FAILURE);
                #[allow(clippy::empty_loop)]
                loop {}
            }
        };
        hprintln!("pvfc hil: ready on USART1");
        (
            Shared {},
            Local {
                usart,
                decoder: Decoder::new(),
                drive,
            },
        )
    }

    #[idle]
    fn idle(_: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// Each byte the host sends: a whole `Sense` runs one control period and is answered.
    #[task(binds = USART1, priority = 3, local = [usart, decoder, drive,
           setpoint: Setpoint = Setpoint::STOPPED, next: Option<u32> = None,
           link_fault: bool = false, errors: u32 = 0,
           last: [u8; MAX_FRAME] = [0; MAX_FRAME], last_len: usize = 0])]
    fn link(cx: link::Context) {
        let l = cx.local;
        while l.usart.sr().read().rxne().bit_is_set() {
            let byte = l.usart.dr().read().dr().bits() as u8;
            let sense = match l.decoder.push(byte) {
                None => continue,
                Some(Err(_)) => {
                    *l.errors = l.errors.wrapping_add(1);
                    continue;
                }
                Some(Ok(sense)) => sense,
            };
            // The period just answered, asked again: the same answer, no period run.
            if l.next.is_some_and(|n| n == sense.seq.wrapping_add(1)) {
                send(l.usart, &l.last[..*l.last_len]);
                continue;
            }
            // A period the host ran without this drive's torque: the safe torque from now on.
            if l.next.is_some_and(|n| n != sense.seq) || sense.counts.len() != 2 {
                *l.link_fault = true;
            }
            *l.next = Some(sense.seq.wrapping_add(1));
            if let Some(c) = sense.command {
                *l.setpoint = l.setpoint.after(c);
            }
            let mut torque = [0.0f32; 2];
            if !*l.link_fault {
                let counts = [sense.counts[0], sense.counts[1]];
                let out = l.drive.period(*l.setpoint, counts);
                torque = [out.torque[0], out.torque[1]];
            }
            let state = match (*l.link_fault, l.drive.fault()) {
                (true, _) => DriveState::Fault(LINK_FAULT),
                (false, Some(kind)) => DriveState::Fault(kind as u8),
                (false, None) if l.setpoint.run => DriveState::Running,
                (false, None) => DriveState::Stopped,
            };
            let answer = Actuate {
                seq: sense.seq,
                torque: torque.iter().copied().collect(),
                state,
                errors: *l.errors,
            };
            // An Actuate of two joints always fits a frame.
            *l.last_len = encode(&answer, l.last).unwrap_or(0);
            send(l.usart, &l.last[..*l.last_len]);
        }
    }

    /// Writes `frame` to the USART, byte by byte as the transmitter empties.
    fn send(usart: &USART1, frame: &[u8]) {
        for b in frame {
            while usart.sr().read().txe().bit_is_clear() {}
            usart.dr().write(|w| w.dr().set(u16::from(*b)));
        }
    }
}
