//! A drive in the loop over a serial line (hardware in the loop): the controller runs on the
//! drive (a microcontroller, or its firmware in QEMU), the plant here. Each control period the
//! host sends the encoders' counts and the operator's command due (`pvfc_link::Sense`), waits
//! for the drive's torque (`pvfc_link::Actuate`) and holds it over the period: lockstep, the
//! host keeping time, so the run is the same whatever either side's speed.
//!
//! On the line: an answer that does not come within the line's read timeout is asked for
//! again (the same frame; the drive answers a period it has answered with the same torque), a
//! late answer to an earlier period is passed over, and a drive that reports a fault is
//! recorded (its torque, the safe one, is held). The drive boots after the line opens, so the
//! first period is sent until it is answered.

use crate::error::{Result, SimError};
use crate::plant::faults::FaultState;
use crate::run::loops::Coordinates;
use crate::run::stepper::{Sample, Stepper};
use crate::scenario::operator::Operator;
use crate::scenario::{PassiveSpec, Scenario};
use nalgebra::SVector;
use pvfc_core::coupling::NominalSpeed;
use pvfc_core::prelude::*;
use pvfc_link::{Actuate, Decoder, DriveState, Sense};
use std::io::{ErrorKind as IoKind, Read, Write};
use std::time::{Duration, Instant};

/// A serial line to a drive: bytes both ways, reads that time out (a `UnixStream` or a
/// `TcpStream` with a read timeout, a serial port).
pub trait Line: Read + Write {}

impl<L: Read + Write> Line for L {}

/// How the host runs the line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkOptions {
    /// Frames sent again for one period before the run stops (the line's read timeout apart).
    pub retries: u32,
    /// How long the first period is sent again while the drive boots.
    pub boot: Duration,
    /// A period whose first frame is sent with one bit flipped, to see the drive refuse it.
    pub corrupt_at: Option<u32>,
}

impl Default for LinkOptions {
    fn default() -> Self {
        LinkOptions {
            retries: 10,
            boot: Duration::from_secs(30),
            corrupt_at: None,
        }
    }
}

/// What happened on the line over a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkReport {
    /// Control periods answered.
    pub periods: u32,
    /// Frames sent (once per period, and again for each period not answered in time), from
    /// the first answer on.
    pub sent: u32,
    /// Frames sent again because no answer came in time.
    pub resent: u32,
    /// Frames corrupted on purpose ([`LinkOptions::corrupt_at`]).
    pub corrupted: u32,
    /// Frames the drive could not read (its own count, from its first answer on).
    pub unread: u32,
    /// Answers to an earlier period, passed over.
    pub late: u32,
    /// The first fault the drive reported: the period and its code.
    pub fault: Option<(u32, u8)>,
    /// Each period's time from its first frame sent to its answer (s), from the first answer
    /// on.
    pub round_trips: Vec<f64>,
}

impl LinkReport {
    /// The median and largest round trip (s); zeros without periods.
    pub fn round_trip(&self) -> (f64, f64) {
        let mut r = self.round_trips.clone();
        if r.is_empty() {
            return (0.0, 0.0);
        }
        r.sort_by(f64::total_cmp);
        (r[r.len() / 2], r[r.len() - 1])
    }
}

/// The drive across the line, as a controller of the sampled loop: the plant's joint angles
/// become encoder counts, the answer's torque is held over the period. The controller's
/// internal states live on the drive: they are logged as not measured (NaN).
pub struct LinkDrive<'a> {
    line: &'a mut dyn Line,
    options: LinkOptions,
    decoder: Decoder<Actuate>,
    operator: Option<Operator>,
    /// The drive's encoders (`[controller.passive]`, with its counts per turn): the counts
    /// it reads are those the host's own drive rounds its positions to.
    encoder: PassiveSpec,
    period: u32,
    /// The drive's count of unread frames at its first answer (lost while it booted).
    boot_unread: Option<u32>,
    report: LinkReport,
}

impl<'a> LinkDrive<'a> {
    /// The drive of scenario `s` (its `[controller.passive]` gives the encoders' counts per
    /// turn, its `[[operator]]` the commands) across `line`.
    pub fn new(s: &Scenario, line: &'a mut dyn Line, options: LinkOptions) -> Result<Self> {
        let encoder = s
            .controller
            .passive
            .clone()
            .filter(|p| p.encoder_counts.is_some())
            .ok_or_else(|| {
                SimError::Setting(
                    "hardware in the loop: the drive reads encoders: set controller.passive.encoder_counts"
                        .into(),
                )
            })?;
        if !s.faults.is_empty() {
            // The simulated faults act on the host's own drive (its readings, its clock, its
            // torque); across the line the drive is the firmware's, which they cannot reach.
            return Err(SimError::Setting(
                "hardware in the loop: [[faults]] act on the host's drive, not on one across the line: remove them"
                    .into(),
            ));
        }
        Ok(LinkDrive {
            line,
            options,
            decoder: Decoder::new(),
            operator: Operator::of(s)?,
            encoder,
            period: 0,
            boot_unread: None,
            report: LinkReport::default(),
        })
    }

    /// What happened on the line so far.
    pub fn report(&self) -> &LinkReport {
        &self.report
    }

    /// The report, the run over.
    pub fn into_report(self) -> LinkReport {
        self.report
    }

    fn error(&self, message: String) -> SimError {
        SimError::Link {
            period: self.period,
            message,
        }
    }

    /// Reads until the answer to period `seq`; `None` when the line's timeout passes first.
    fn answer(&mut self, seq: u32) -> Result<Option<Actuate>> {
        let mut byte = [0u8; 1];
        loop {
            match self.line.read(&mut byte) {
                Ok(1) => match self.decoder.push(byte[0]) {
                    Some(Ok(a)) if a.seq == seq => return Ok(Some(a)),
                    Some(Ok(a)) if a.seq < seq => self.report.late += 1,
                    Some(Ok(a)) => {
                        return Err(self.error(format!(
                            "the drive answered period {} to period {seq}",
                            a.seq
                        )))
                    }
                    Some(Err(e)) => return Err(self.error(format!("the drive's answer: {e}"))),
                    None => {}
                },
                Ok(_) => return Err(self.error("the drive closed the line".into())),
                Err(e) if matches!(e.kind(), IoKind::WouldBlock | IoKind::TimedOut) => {
                    return Ok(None)
                }
                Err(e) if e.kind() == IoKind::Interrupted => {}
                Err(e) => return Err(self.error(format!("the line: {e}"))),
            }
        }
    }

    /// Sends period `seq`'s `sense` until it is answered (corrupting the first frame if asked).
    fn exchange(&mut self, sense: &Sense) -> Result<Actuate> {
        let mut frame = [0u8; pvfc_link::MAX_FRAME];
        let n = pvfc_link::encode(sense, &mut frame)
            .map_err(|e| self.error(format!("the frame: {e}")))?;
        let started = Instant::now();
        let booting = self.boot_unread.is_none();
        let mut corrupt = self.options.corrupt_at == Some(sense.seq);
        let mut tries = 0u32;
        loop {
            let mut bytes = frame;
            if corrupt && n > 3 {
                bytes[2] ^= 0x10;
                self.report.corrupted += 1;
            }
            self.line
                .write_all(&bytes[..n])
                .and_then(|()| self.line.flush())
                .map_err(|e| self.error(format!("the line: {e}")))?;
            if !booting {
                self.report.sent += 1;
            }
            match self.answer(sense.seq)? {
                Some(a) if corrupt => {
                    return Err(self.error(format!(
                        "the drive answered a frame corrupted on purpose: {a:?}"
                    )))
                }
                Some(a) => {
                    // (The first period's wait is the drive's boot, not the line's.)
                    if !booting {
                        self.report
                            .round_trips
                            .push(started.elapsed().as_secs_f64());
                    }
                    return Ok(a);
                }
                None => {}
            }
            corrupt = false;
            tries += 1;
            if booting {
                if started.elapsed() > self.options.boot {
                    return Err(self.error(format!(
                        "the drive did not answer within {:?} of the line opening",
                        self.options.boot
                    )));
                }
            } else {
                self.report.resent += 1;
                if tries > self.options.retries {
                    return Err(self.error(format!(
                        "no answer after {} frames",
                        self.options.retries + 1
                    )));
                }
            }
        }
    }
}

impl<G: Coordinates<N>, const N: usize> Stepper<G, N> for LinkDrive<'_> {
    fn sample(
        &mut self,
        q: &G,
        _: &SVector<f64, N>,
        _: (f64, f64),
        _: &mut FaultState<'_, N>,
    ) -> Result<Sample<N>> {
        if N > pvfc_link::MAX_JOINTS {
            return Err(self.error(format!(
                "{N} joints; a frame carries at most {}",
                pvfc_link::MAX_JOINTS
            )));
        }
        let seq = self.period;
        let x = q.coordinates();
        let mut each = [0i32; N];
        for (c, xi) in each.iter_mut().zip(x.iter()) {
            let count = self.encoder.count(*xi).unwrap_or(f64::NAN);
            if !(count.is_finite() && count.abs() <= f64::from(i32::MAX)) {
                return Err(self.error(format!("a joint at {xi} rad: no encoder count")));
            }
            *c = count as i32;
        }
        // Within a frame's capacity: N ≤ MAX_JOINTS, checked above.
        let counts = each.iter().copied().collect();
        let command = self.operator.as_mut().and_then(|o| o.due(u64::from(seq)));
        let a = self.exchange(&Sense {
            seq,
            counts,
            command,
        })?;
        let boot = *self.boot_unread.get_or_insert(a.errors);
        self.report.unread = a.errors.saturating_sub(boot);
        self.report.periods += 1;
        self.period = self.period.wrapping_add(1);
        if a.torque.len() != N {
            return Err(self.error(format!("{} torques for {N} joints", a.torque.len())));
        }
        let fault = match a.state {
            DriveState::Fault(code) => {
                self.report.fault.get_or_insert((seq, code));
                code.max(1)
            }
            DriveState::Stopped | DriveState::Running => 0,
        };
        let nan = f64::NAN;
        let mut out = Sample::stopped(
            InternalState {
                tau: nan,
                tau_dot: nan,
                flywheel_speed: nan,
                laps: 0,
            },
            nan,
        );
        out.torque = SVector::from_fn(|i, _| f64::from(a.torque[i]));
        out.fault = fault;
        Ok(out)
    }

    fn nominal_speed_mut(&mut self) -> Option<&mut NominalSpeed<f64>> {
        None
    }
}
