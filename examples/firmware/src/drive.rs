//! One control period of a motor controller, shared by the RTIC firmware (`rtic/`, f32) and
//! its host twin (`tests/firmware_twin.rs`, f32 and f64): the operator's setpoint applied at
//! the period's start, the encoders' counts turned into angles, the passive controller's step,
//! and the safe torque (zero) while stopped or after a fault, which latches. Generic over the
//! scalar, `no_std`, no allocation.

use crate::hil;
use pvfc_core::coupling::NominalSpeed;
use pvfc_core::nalgebra::Vector2;
use pvfc_core::prelude::*;
use pvfc_core::scalar::cast;

/// Encoder counts per turn (2¹⁷).
pub const COUNTS_PER_TURN: f64 = 131_072.0;
/// The drives' torque limit (N·m).
pub const LIMIT: f64 = 5.0;
/// The gain `c` of the nominal speed (eq. 36).
pub const SPEED_GAIN: f64 = 0.2;

/// The passive controller of the paper's SCARA.
pub type Passive<T> = PassiveController<
    T,
    Torus<T, 2>,
    Scara<T>,
    SuspendedField<T, Torus<T, 2>, Lissajous<T, 2>, TorusNavigation<T, 2>, ExponentialPacing<T>, 2>,
    2,
>;

/// What an operator asks for: the command the hardware-in-the-loop frames carry
/// (`pvfc_link::Command`: start at a nominal speed `r` of eq. (36), change `r`, stop).
pub use pvfc_link::Command;

/// The operator's script of the RTIC firmware (`rtic/`), the commands one would send over the
/// serial line in a hardware-in-the-loop run, by control period: start at `r = 1`, faster at
/// 4 s, `r = 0` at 7 s (the nominal speed's term then brakes the motion along the field), the
/// drives off at 9.5 s.
pub const SCRIPT: [(u32, Command); 4] = [
    (200, Command::Start(1.0)),
    (4_000, Command::Speed(2.0)),
    (7_000, Command::Speed(0.0)),
    (9_500, Command::Stop),
];

/// The setpoint the operator's commands build and the control period applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setpoint {
    /// Whether the controller runs.
    pub run: bool,
    /// The nominal speed `r`.
    pub speed: f32,
}

impl Setpoint {
    /// Stopped, `r = 0`.
    pub const STOPPED: Setpoint = Setpoint {
        run: false,
        speed: 0.0,
    };

    /// The setpoint after `command`.
    pub fn after(self, command: Command) -> Setpoint {
        match command {
            Command::Start(speed) => Setpoint { run: true, speed },
            Command::Speed(speed) => Setpoint { speed, ..self },
            Command::Stop => Setpoint { run: false, ..self },
        }
    }
}

/// What one period did.
#[derive(Clone, Copy, Debug)]
pub struct Period<T> {
    /// The torque for the drives over the period.
    pub torque: Vector2<T>,
    /// `U(E)` if the controller was stepped.
    pub potential: Option<T>,
    /// Whether the setpoint changed at this period's start.
    pub applied: bool,
    /// A fault latched in this period.
    pub fault: Option<ErrorKind>,
}

/// The control loop's state: the controller, the setpoint in force, the latched fault.
pub struct Drive<T: Real> {
    controller: Passive<T>,
    setpoint: Setpoint,
    fault: Option<ErrorKind>,
}

impl<T: Real> Drive<T> {
    /// The passive controller: `hil::controller` (the paper's SCARA controller with friction
    /// compensation) with the nominal speed of eq. (36) (`c =` [`SPEED_GAIN`], `r = 0` until
    /// started), positions only from the encoders, a 2 ms velocity filter, the drives'
    /// limits; stopped.
    pub fn new() -> Result<Self, Error> {
        let nominal = NominalSpeed::new(cast(SPEED_GAIN), T::zero())?;
        let controller =
            PassiveController::new(hil::controller::<T>()?.with_nominal_speed(nominal))
                .with_encoder_resolution(Vector2::repeat(cast(
                    core::f64::consts::TAU / COUNTS_PER_TURN,
                )))?
                .with_velocity_filter(cast(2e-3))?
                .with_torque_limits(Vector2::repeat(cast(LIMIT)))?;
        Ok(Drive {
            controller,
            setpoint: Setpoint::STOPPED,
            fault: None,
        })
    }

    /// The controller.
    pub fn controller(&self) -> &Passive<T> {
        &self.controller
    }

    /// The latched fault, if any.
    pub fn fault(&self) -> Option<ErrorKind> {
        self.fault
    }

    /// One control period from the encoders' `counts` under the operator's `setpoint`.
    pub fn period(&mut self, setpoint: Setpoint, counts: [i32; 2]) -> Period<T> {
        let mut out = Period {
            torque: Vector2::zeros(), // the safe torque
            potential: None,
            applied: false,
            fault: None,
        };
        if setpoint != self.setpoint {
            self.setpoint = setpoint;
            out.applied = true;
            if let Some(nominal) = self.controller.controller_mut().nominal_speed_mut() {
                if let Err(e) = nominal.set_speed(cast(setpoint.speed as f64)) {
                    self.latch(e.kind(), &mut out);
                }
            }
        }
        if !self.setpoint.run || self.fault.is_some() {
            return out;
        }
        let count: T = cast(core::f64::consts::TAU / COUNTS_PER_TURN);
        let q = Torus::new(Vector2::new(
            cast::<T>(counts[0] as f64) * count,
            cast::<T>(counts[1] as f64) * count,
        ));
        match self.controller.step(&q, None, None, cast(hil::DT)) {
            Ok(step) => {
                out.torque = step.torque;
                out.potential = Some(step.diagnostics.potential);
            }
            Err(e) => self.latch(e.kind(), &mut out),
        }
        out
    }

    fn latch(&mut self, kind: ErrorKind, out: &mut Period<T>) {
        if self.fault.is_none() {
            self.fault = Some(kind);
            out.fault = Some(kind);
        }
        out.torque = Vector2::zeros();
    }
}

/// The encoders' counts of the angles `q` (rounded to the nearest count).
pub fn encoder_counts<T: Real>(q: &Vector2<T>) -> [i32; 2] {
    let per_rad: T = cast(COUNTS_PER_TURN / core::f64::consts::TAU);
    [0, 1].map(|i| {
        let x = (q[i] * per_rad).round();
        x.to_i64_checked().unwrap_or(0) as i32
    })
}
