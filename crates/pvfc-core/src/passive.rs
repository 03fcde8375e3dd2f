//! A digital PVFC controller that is passive by construction: the energy it gives the robot is
//! accounted at the samples, exactly, and paid from its own storage (the flywheel and the
//! suspended coordinate), so that no sampling period, torque limit or velocity estimate can
//! make it create energy.
//!
//! # Why a zero-order hold breaks passivity, and what this controller does
//! The coupling of eq. (7) is workless in continuous time: `q̇_aᵀ T_a = 0`, so the energy the
//! robot receives, `T_robotᵀ q̇`, is exactly what the flywheel and `τ̇` lose (eq. 9). A motor
//! controller holds `T_k` over a period `h`, while `q̇` changes: the robot receives
//! `ΔW_k = T_kᵀ (q_{k+1} − q_k)`, but the internal states, integrated from the held virtual
//! torques, lose a different amount. The difference is `O(h²)` per step and has no sign:
//! over a run it creates energy (our figures: +0.32 J at a wall at 1 kHz).
//!
//! With a zero-order hold, `ΔW_k` is known **exactly** at the next sample, from positions
//! only. [`PassiveController`] keeps a storage `S` and updates it by that balance:
//! `S_{k+1} = S_k − (u_k − a_k)ᵀ (q_{k+1} − q_k) + E_k`, where `u_k` is the torque the drive
//! actually applied (after saturation), `a_k` the add-ons' part of it (friction and gravity
//! compensation, nominal speed: their command, or where the drive did not apply the command,
//! their torque first, up to what it applied) and `E_k` the energy the nominal-speed add-on put into the
//! virtual coordinates. The add-ons' energy, `a_kᵀΔq_k + E_k`, is reported, as the
//! continuous audit reports it. Then the internal velocities `(τ̇, q̇_F)`, integrated as
//! [`Controller::step`] does, are put back onto the storage's level set
//! `½τ̇² + ½M_F q̇_F² = S_{k+1}` by changing the flywheel speed (and `τ̇` only if the
//! flywheel alone cannot absorb the change): the flywheel is the energy tank of the
//! telemanipulation literature (Franken, Stramigioli et al., 2011), here already part of the
//! law. The correction is `O(h²)` per step, so the continuous-time behaviour (convergence
//! onto the field, self-pacing) is kept as `h → 0`.
//!
//! Hence, at every sample, `κ_a(t_k) = ½q̇ᵀMq̇ + S_k` satisfies
//! `κ_a(t_k) − κ_a(0) = W_env + W_friction + W_add-ons` exactly (up to rounding, and up to
//! the encoder's resolution when positions are quantised: see below): the robot's kinetic
//! energy changes by the work of all the forces on it, and the storage by exactly minus the
//! coupling's part of the motor work.
//!
//! A tank can run dry: before the torque is sent, the energy it would draw over the next
//! period is predicted, `P = cᵀ v̂ h` for the coupling torque `c`, and when
//! `S − P < reserve` the whole coupling torque (robot and virtual parts, so it stays
//! workless) is scaled by `λ = (S − reserve)/P ∈ [0, 1]`. If the prediction is wrong (an
//! impact within the period), `S` may still end below zero: it is reported, never hidden
//! (the velocities are then zero and the tank refills only from energy the robot gives back).
//!
//! # Encoders, velocity estimates, saturation
//! - The accounting uses positions only; the velocity `v̂` feeds the law (tracking) and the
//!   prediction above, never the balance. Without a measured velocity, `v̂` is the backward
//!   difference of the positions through a first-order low-pass filter of time constant
//!   `T_f` ([`with_velocity_filter`](PassiveController::with_velocity_filter); `T_f = 0`: the
//!   plain difference): `v̂_k = α v̂_{k−1} + (1 − α) Δq_k/h`, `α = T_f/(T_f + h)`.
//! - With positions quantised (rounded) to `δ_i`, the measured increments are off by the
//!   rounding errors `e_k` (`|e_{k,i}| ≤ δ_i/2`), and the true work of the held torques is
//!   `Σ_k u_kᵀ(Δm_k − (e_{k+1} − e_k))` for the measured `Δm_k`. Summed by parts,
//!   `Σ_k u_kᵀ(e_{k+1} − e_k) = u_{n−1}ᵀe_n − u_0ᵀe_0 − Σ_k (u_k − u_{k−1})ᵀe_k`: the last sum
//!   can grow (a chattering torque on a coarse encoder pumps energy), the rest is bounded by
//!   `½δᵀ(|u_0| + |u_{n−1}|)`. Given the resolution
//!   ([`with_encoder_resolution`](PassiveController::with_encoder_resolution)), the storage
//!   is also charged `½ Σ_i δ_i |u_{k,i} − u_{k−1,i}|` at every step (reported as
//!   [`quantisation`](EnergyAccount::quantisation)), which covers that sum whatever the
//!   errors: the controller then never gives more than it has, up to the bounded boundary
//!   term, and pays for a smooth torque almost nothing.
//! - Per-joint torque limits ([`with_torque_limits`](PassiveController::with_torque_limits))
//!   clamp the command; the torque the drive reports as applied (or the clamped command) is
//!   what the balance uses, so saturation costs tracking, never passivity. With a pace
//!   throttle ([`with_pace_throttle`](PassiveController::with_pace_throttle),
//!   [`crate::pace::throttle`]) the share of a limit the command uses slows the field's pace
//!   for the next step, so that the field asks for what the drives can give.
//!
//! The robot's configuration group must have coordinates ([`VectorGroup`]: the torus, `ℝⁿ`,
//! a serial chain's joint space): the work of a held joint torque is then exactly
//! `uᵀ Δq` with `Δq` the unwrapped increment, `log(q_k⁻¹ q_{k+1})`, valid while every joint
//! moves less than half a turn per period.

use crate::augmented::AugmentedState;
use crate::contour::VectorGroup;
use crate::controller::{Controller, Diagnostics, InternalState};
use crate::error::{Error, ErrorKind, Result};
use crate::field::VelocityField;
use crate::lie::Tangent;
use crate::mechanics::MechanicalSystem;
use crate::pace::PaceThrottle;
use crate::scalar::cast;
use crate::supervision::{unchanged, Fault, Supervision};
use crate::Real;

/// The energy account of one step of a [`PassiveController`], for logs and tests.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EnergyAccount<T: Real> {
    /// The storage `S_k` after the last period's balance (J): `½τ̇² + ½M_F q̇_F²` at the
    /// state the torque was computed at, or negative if the tank was overdrawn.
    pub storage: T,
    /// The energy the coupling gave the robot over the last period, `(u − a)ᵀΔq`, paid by
    /// the storage (J; negative when the robot gave energy back). When a frozen encoder's
    /// catch-up is confirmed at this step ([`PassiveController::step`]), the work of the
    /// torque held before it across the jump is in it too.
    pub to_robot: T,
    /// The add-ons' energy over the last period, `aᵀΔq + E` (J), and with supervision what
    /// is held aside as theirs for the readings that stand still (their share of
    /// [`PassiveController::set_aside`]: reported, not paid from the storage).
    pub add_ons: T,
    /// What the hold's error would have created or destroyed over the last period had the
    /// internal states simply been integrated (J): the storage's level minus the integrated
    /// states' energy, removed by the projection.
    pub correction: T,
    /// The factor `λ ∈ [0, 1]` applied to the coupling torque this step (1: the tank could
    /// pay for all of it).
    pub scale: T,
    /// `true` when a torque limit clamped this step's command.
    pub saturated: bool,
    /// What the storage was charged for the encoders' resolution this step,
    /// `½ Σ_i δ_i |u_{k,i} − u_{k−1,i}|` (J; 0 without a resolution).
    pub quantisation: T,
    /// What the storage was charged at a fault for the work the last torque may have done
    /// unseen over the period that ended: from the last good increment's speed where it is
    /// known, and never more than `Σ_i |u_i| v̄_i h` (J; 0 without a fault;
    /// [`PassiveController::step`] gives the bound). The
    /// add-ons' share is in it: their energy over that period is not reported in
    /// [`add_ons`](Self::add_ons).
    pub unseen: T,
    /// What the storage set aside this step for the coupling's work the readings that stand
    /// still may hide (J; negative when what was set aside came back: with supervision only,
    /// see [`PassiveController::set_aside`]; the add-ons' share is in
    /// [`add_ons`](Self::add_ons)).
    pub set_aside: T,
}

/// The energy a [`PassiveController`] holds aside for the motion its still readings may
/// hide, per joint, the coupling's and the add-ons' shares together
/// ([`PassiveController::set_aside`]). A joint's stretch opens when its reading stands still
/// and closes when the readings have shown where it went. Over the stretch, the part of
/// `energy` the hidden motion has not used, `energy − (W − accounted)`
/// for the drive's true work `W` over the stretch's periods (those over which `time` grew),
/// is still the controller's: an audit that knows the truth counts it beside the storage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetAsideAccount<T: Real, const D: usize> {
    /// What is set aside (J).
    pub energy: Tangent<T, D>,
    /// What the balances accounted (paid, or reported as the add-ons') of the stretch's
    /// periods (J).
    pub accounted: Tangent<T, D>,
    /// The time of the stretch's periods (s; zero: no stretch open).
    pub time: Tangent<T, D>,
}

/// What one step of a [`PassiveController`] returns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassiveStepOutput<T: Real, const D: usize> {
    /// The motor torques to apply (clamped to the limits, if any; zero at a fault).
    pub torque: Tangent<T, D>,
    /// The add-ons' share of [`torque`](Self::torque) (friction and gravity compensation,
    /// nominal speed): the rest is the coupling's, whose energy the storage pays.
    pub add_on: Tangent<T, D>,
    /// The velocity the law was evaluated at (measured, or estimated from positions).
    pub velocity: Tangent<T, D>,
    /// The internal states the torque was computed at (after the energy correction, before
    /// the update).
    pub state: InternalState<T>,
    /// `U`, `λ₁`, `λ₂`, `β`, `κ_a`, `V_F` at that state (at a fault: as of the last good
    /// step, zeros before the first).
    pub diagnostics: Diagnostics<T>,
    /// The energy account of the step.
    pub energy: EnergyAccount<T>,
    /// The fault detected at this sample, if any ([`Supervision`]); the torque is then the
    /// safe torque, zero.
    pub fault: Option<Fault>,
    /// The scale `s` of the field's pace this step's torque was computed at (a
    /// [`PaceThrottle`]'s; 1 without one).
    pub pace_scale: T,
}

/// What the controller remembers of the period it is holding a torque over.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Held<T: Real, G, const D: usize> {
    q: G,
    command: Tangent<T, D>,
    add_on: Tangent<T, D>,
    /// The nominal-speed add-on's energy into `(τ̇, q̇_F)` over the period.
    virtual_add_on: T,
    /// The torque applied over the period before (for the encoders' charge).
    previous: Option<Tangent<T, D>>,
    /// The time since `q` was read, less the period now ending (faulted periods since).
    elapsed: T,
}

/// The balance of the period a [`Held`] sample covers, from positions only.
struct Balance<T: Real, const D: usize> {
    /// The increment `log(q_held⁻¹ q)`.
    dq: Tangent<T, D>,
    /// `(u − a)ᵀΔq`: the coupling's energy to the robot.
    to_robot: T,
    /// `aᵀΔq + E`: the add-ons'.
    add_ons: T,
    /// `½ Σ δ_i |u_k − u_{k−1}|`: the encoders' charge (0 without a resolution).
    quantisation: T,
    /// The coupling's share `u − a` of the torque applied over the period.
    coupling: Tangent<T, D>,
    /// The add-ons' share `a` of it ([`Held::delivered_add_on`]).
    add_on: Tangent<T, D>,
}

impl<T: Real, G: VectorGroup<T, D>, const D: usize> Held<T, G, D> {
    /// The balance up to the reading `q`, with `applied` the torque the drive applied (`None`:
    /// the command) and `resolution` the encoders'.
    fn balance(
        &self,
        q: &G,
        applied: Option<&Tangent<T, D>>,
        resolution: Option<&Tangent<T, D>>,
    ) -> Balance<T, D> {
        let dq = self.q.inverse().compose(q).log();
        let u = applied.copied().unwrap_or(self.command);
        let quantisation = match (resolution, &self.previous) {
            // ½ Σ δ_i |u_k − u_{k−1}|: what the rounding of q_k can hide (summation by
            // parts, module documentation).
            (Some(res), Some(before)) => {
                res.iter()
                    .zip(u.iter().zip(before.iter()))
                    .fold(T::zero(), |acc, (d, (a, b))| acc + *d * (*a - *b).abs())
                    * cast::<T>(0.5)
            }
            _ => T::zero(),
        };
        let add_on = match applied {
            Some(u) => self.delivered_add_on(u),
            None => self.add_on,
        };
        let coupling = u - add_on;
        let to_robot = coupling.dot(&dq);
        Balance {
            // After a gap (readings rejected, each period charged the most its torque can
            // have done unseen), never a credit: the robot may have given energy back over
            // the gap, which the charges have already paid for at their bound.
            to_robot: if self.elapsed > T::zero() {
                to_robot.max(T::zero())
            } else {
                to_robot
            },
            add_ons: add_on.dot(&dq) + self.virtual_add_on,
            quantisation,
            dq,
            coupling,
            add_on,
        }
    }

    /// The add-ons' share of the torque `u` the drive applied: their command where the drive
    /// applied the command, and where it did not (it clamped the torque below its limits, or
    /// kept an older one), the add-ons' torque first, up to what was applied: per joint the
    /// part of `a_j` within `u_j` on the same side, `sign(a_j) min(|a_j|, |u_j|)`, or nothing.
    /// The coupling's share is the rest, so the storage does not pay for an add-on's torque
    /// the drive never gave (gravity compensation under a lowered limit, say).
    fn delivered_add_on(&self, u: &Tangent<T, D>) -> Tangent<T, D> {
        Tangent::from_fn(|j, _| {
            let (a, x) = (self.add_on[j], u[j]);
            if x == self.command[j] {
                a
            } else if a * x > T::zero() {
                if a.abs() <= x.abs() {
                    a
                } else {
                    x
                }
            } else {
                T::zero()
            }
        })
    }
}

/// What is held aside for one share of the torque (the coupling's, paid from the storage,
/// or the add-ons', reported as theirs) over each joint's stretch ([`SetAside`]): the
/// energy; the speed bound's reach `Σ |u_k| v̄ h_k`; over the stretch's periods, the torque's
/// integral, its steps weighted by the span's time at them (`Σ|Δu_k| t_k`, `Σ|Δu_k| t_k²`)
/// and its last value; and what the balances accounted of the stretch.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Escrow<T: Real, const D: usize> {
    energy: Tangent<T, D>,
    reach: Tangent<T, D>,
    integral: Tangent<T, D>,
    steps: [Tangent<T, D>; 2],
    last: Tangent<T, D>,
    accounted: Tangent<T, D>,
}

impl<T: Real, const D: usize> Escrow<T, D> {
    fn zero() -> Self {
        Escrow {
            energy: Tangent::zeros(),
            reach: Tangent::zeros(),
            integral: Tangent::zeros(),
            steps: [Tangent::zeros(); 2],
            last: Tangent::zeros(),
            accounted: Tangent::zeros(),
        }
    }

    /// A step `du` of joint `j`'s torque at the span's time `t`.
    fn step_of(&mut self, j: usize, du: T, t: T) {
        self.steps[0][j] += du * t;
        self.steps[1][j] += du * t * t;
    }

    /// Joint `j`'s torque `u` held over `elapsed` of the stretch's periods from the span's
    /// time `t` (`first`: the stretch's first period), `v̄` its speed bound. Returns the
    /// most it can have done over them, `|u| v̄ elapsed`.
    fn hold(&mut self, j: usize, (u, elapsed, t, first): (T, T, T, bool), max_speed: T) -> T {
        if !first {
            self.step_of(j, (u - self.last[j]).abs(), t);
        }
        self.last[j] = u;
        self.integral[j] += u * elapsed;
        let most = u.abs() * max_speed * elapsed;
        self.reach[j] += most;
        most
    }

    /// The torque steps to zero at the span's time `t` (periods whose work is charged apart).
    fn skip(&mut self, j: usize, t: T) {
        self.step_of(j, self.last[j].abs(), t);
        self.last[j] = T::zero();
    }

    /// The bound on the work `W` of this share over joint `j`'s stretch, the least of two:
    /// `Σ |u_k| v̄ h_k` (the speed bound alone); and over the span `T` with the joint's true
    /// motion `d` (the readings' `moved` within `count`), the work along the chord
    /// `d t / T`, `(∫u dt / T) d`, plus the work along the path's departure `e` from it
    /// (zero at both ends), `−Σ Δu_k e(t_k)` by parts, where `|e(t)| ≤ c t (T − t)` with
    /// `c = ā/2` (the acceleration bound) or `4 v̄ / T` (the speed bound): at most
    /// `c (T Σ|Δu_k| t_k − Σ|Δu_k| t_k²)`.
    fn bound(&self, j: usize, (span, moved, count): (T, T, T), sup: &Supervision<T, D>) -> T {
        let mean = self.integral[j] / span;
        let mut c = cast::<T>(4.0) * sup.max_speed()[j] / span;
        if let Some(a) = sup.max_acceleration() {
            c = c.min(a[j] * cast::<T>(0.5));
        }
        let departure = c * (span * self.steps[0][j] - self.steps[1][j]);
        let chord = mean * moved + mean.abs() * count + departure.max(T::zero());
        chord.min(self.reach[j])
    }

    /// Closes joint `j`'s stretch: what was held aside comes back, less what the bound asks
    /// beyond what the balances accounted. Returns what came back (J; negative: a charge).
    fn close(&mut self, j: usize, bound: T) -> T {
        let back = self.energy[j] - (bound - self.accounted[j]).max(T::zero());
        self.energy[j] = T::zero();
        self.reach[j] = T::zero();
        self.integral[j] = T::zero();
        self.steps[0][j] = T::zero();
        self.steps[1][j] = T::zero();
        self.last[j] = T::zero();
        self.accounted[j] = T::zero();
        back
    }
}

/// The energy held aside for the work a reading that stands still may hide (with
/// supervision): an encoder frozen while its joint is too slow for the acceleration bound to
/// tell looks like a joint at rest. Per joint, over the stretch since its reading stood
/// still: the coupling's share, paid from the storage, and the add-ons' share, reported as
/// theirs ([`Escrow`]); the time of the stretch's periods (those whose work the readings did
/// not show) and the whole span (rejected readings included); the readings' motion over it;
/// and how long the readings must still move cleanly before they are trusted with it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct SetAside<T: Real, const D: usize> {
    coupling: Escrow<T, D>,
    add_ons: Escrow<T, D>,
    time: Tangent<T, D>,
    span: Tangent<T, D>,
    moved: Tangent<T, D>,
    distrust: Tangent<T, D>,
    /// The last increment stood still: the next move ends the hidden motion.
    fresh: [bool; D],
}

impl<T: Real, const D: usize> SetAside<T, D> {
    fn zero() -> Self {
        SetAside {
            coupling: Escrow::zero(),
            add_ons: Escrow::zero(),
            time: Tangent::zeros(),
            span: Tangent::zeros(),
            moved: Tangent::zeros(),
            distrust: Tangent::zeros(),
            fresh: [false; D],
        }
    }

    /// A stretch of joint `j` meets periods whose work is charged apart (rejected readings,
    /// or a catch-up's jump): `elapsed` of the span with no torque of its own, and the
    /// readings' motion `dq` over it, not trusted until they have moved cleanly as long as
    /// the span.
    fn skip(&mut self, j: usize, dq: T, elapsed: T) {
        self.coupling.skip(j, self.span[j]);
        self.add_ons.skip(j, self.span[j]);
        self.span[j] += elapsed;
        self.moved[j] += dq;
        self.distrust[j] = self.span[j];
        self.fresh[j] = false;
    }

    /// Closes joint `j`'s stretch (`count`: its encoder's resolution). Returns what came
    /// back to the storage and to the add-ons (J; negative: a charge).
    fn close(&mut self, j: usize, sup: &Supervision<T, D>, count: T) -> (T, T) {
        let at = (self.span[j], self.moved[j], count);
        let coupling = self.coupling.bound(j, at, sup);
        let add_ons = self.add_ons.bound(j, at, sup);
        let back = (
            self.coupling.close(j, coupling),
            self.add_ons.close(j, add_ons),
        );
        self.time[j] = T::zero();
        self.span[j] = T::zero();
        self.moved[j] = T::zero();
        self.distrust[j] = T::zero();
        self.fresh[j] = false;
        back
    }

    /// After a good increment `dq` over `elapsed` to the reading `q`, with the coupling's
    /// torque `c` and the add-ons' `a` held over it. Returns the net held aside from the
    /// storage and reported as the add-ons' (J; negative: given back):
    /// - where a joint's reading stood still, the most each share can have done unseen at
    ///   the speed bound, `|c_j| v̄_j elapsed` and `|a_j| v̄_j elapsed`, is held aside;
    /// - where it moved after standing still, the stretch closes if the increment is
    ///   `clean` (one period after a good reading): what was held aside comes back, less
    ///   what the bound on each share's work over the stretch ([`Escrow::bound`]) asks
    ///   beyond what the balances accounted of it (`c_j dq_j` paid, `a_j dq_j` reported).
    ///   After rejected readings (or a catch-up) the stretch stays open until the readings
    ///   have moved cleanly for as long as its span: a spike taken for a reading is not
    ///   trusted with the stretch's motion, and what the readings moved adds up, so that a
    ///   spike's way out and back cancel.
    fn settle<G: VectorGroup<T, D>>(
        &mut self,
        (dq, elapsed, clean): (&Tangent<T, D>, T, bool),
        (c, a): (&Tangent<T, D>, &Tangent<T, D>),
        q: &G,
        sup: &Supervision<T, D>,
        resolution: Option<&Tangent<T, D>>,
    ) -> (T, T) {
        let at = q.coordinates();
        let (mut from_storage, mut reported) = (T::zero(), T::zero());
        for j in 0..D {
            let still = unchanged(dq[j], at[j]);
            if self.span[j] == T::zero() && !still {
                continue;
            }
            if still || (clean && self.fresh[j]) {
                // A period of the hidden motion (or the move that ends it).
                let v = sup.max_speed()[j];
                let held = |u: T| (u, elapsed, self.span[j], self.span[j] == T::zero());
                let rc = self.coupling.hold(j, held(c[j]), v);
                let ra = self.add_ons.hold(j, held(a[j]), v);
                self.time[j] += elapsed;
                self.span[j] += elapsed;
                self.fresh[j] = still;
                if still {
                    self.coupling.energy[j] += rc;
                    self.add_ons.energy[j] += ra;
                    from_storage += rc;
                    reported += ra;
                    continue;
                }
                self.moved[j] += dq[j];
                self.coupling.accounted[j] += c[j] * dq[j];
                self.add_ons.accounted[j] += a[j] * dq[j];
            } else if !clean {
                self.skip(j, dq[j], elapsed);
                continue;
            } else {
                self.distrust[j] -= elapsed;
            }
            if self.distrust[j] <= T::zero() {
                let count = resolution.map_or(T::zero(), |r| r[j]);
                let (bc, ba) = self.close(j, sup, count);
                from_storage -= bc;
                reported -= ba;
            }
        }
        (from_storage, reported)
    }

    /// At a frozen encoder's confirmed catch-up from the last good reading over `jump`,
    /// `t_fault` s of rejected readings between (charged as unseen work): every open stretch
    /// takes the jump as the readings' motion, and stays open until the readings have moved
    /// cleanly for as long as its span (a spike taken for a catch-up is then undone by the
    /// jump back before anything comes back).
    fn caught_up(&mut self, jump: &Tangent<T, D>, t_fault: T) {
        for j in 0..D {
            if self.span[j] > T::zero() {
                self.skip(j, jump[j], t_fault);
            }
        }
    }

    /// The account for an audit ([`SetAsideAccount`]).
    fn account(&self) -> SetAsideAccount<T, D> {
        SetAsideAccount {
            energy: self.coupling.energy + self.add_ons.energy,
            accounted: self.coupling.accounted + self.add_ons.accounted,
            time: self.time,
        }
    }
}

/// PVFC for a sampled-data loop, passive for any sampling period: see the
/// [module documentation](self) for the energy accounting.
///
/// ```
/// use pvfc_core::prelude::*;
/// use pvfc_core::passive::PassiveController;
/// use nalgebra::Vector2;
/// let field = SuspendedField::new(
///     Lissajous::<f64, 2>::paper(),
///     TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
///     ExponentialPacing::new(100.0).unwrap(),
/// );
/// let law = PvfcLaw::new(Scara::pelican(), field, Flywheel::new(1.0, 50.0).unwrap(), 0.05).unwrap();
/// let mut ctl = PassiveController::new(Controller::new(law).starting_at_rest(0.0))
///     .with_torque_limits(Vector2::new(20.0, 10.0)).unwrap();
/// // Encoder positions only; the drive applied what it was told.
/// let q = Torus::new(Vector2::new(0.0, 0.0));
/// let out = ctl.step(&q, None, None, 1e-3).unwrap();
/// assert!(out.torque.iter().zip([20.0, 10.0]).all(|(t, l)| t.abs() <= l));
/// assert_eq!(out.energy.storage, 50.0); // all of Ē in the flywheel at the start
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassiveController<T: Real, G, Sys, F, const D: usize> {
    controller: Controller<T, G, Sys, F, D>,
    limits: Option<Tangent<T, D>>,
    resolution: Option<Tangent<T, D>>,
    filter: T,
    reserve: T,
    storage: T,
    held: Option<Held<T, G, D>>,
    velocity_estimate: Tangent<T, D>,
    supervision: Option<Supervision<T, D>>,
    /// The last good increment's speed and the time it was measured over.
    rate: Option<(Tangent<T, D>, T)>,
    /// The joint whose encoder was found frozen, until its reading changes.
    frozen: Option<usize>,
    /// How long each joint's reading had not changed at the last good reading (s): a
    /// catch-up must be a motion the joint could have made while its encoder stood still.
    still_for: Tangent<T, D>,
    /// What the storage holds aside for the motion a still reading may hide.
    set_aside: SetAside<T, D>,
    /// The diagnostics of the last good step (reported at a fault).
    last_diagnostics: Diagnostics<T>,
    /// A rejected reading that may be the truth after a frozen encoder ([`Candidate`]).
    candidate: Option<Candidate<T, G>>,
    /// The pace scaled on the torque margin, if any.
    throttle: Option<PaceThrottle<T>>,
    /// The rule by which the field's pace learns from the torque margin, if it does.
    learning: Option<crate::pace::PaceLearning<T>>,
}

/// A reading rejected where the joint at fault had not moved since the reading before (an
/// encoder that may have been frozen, undetected, and now reads the truth again). If the
/// next reading continues from it and not from the last good one, it was the truth: it
/// becomes the last good reading, and the work the torque held before the fault did across
/// the jump is charged, as the balance would have, so that the motion the frozen encoder hid
/// is paid for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Candidate<T: Real, G> {
    q: G,
    /// `max(0, (u − a)ᵀ(q − q_good))` of the torque held over the period that ended at the
    /// reading: a debt is charged, a credit is not taken (a spike that lasts two samples looks
    /// like a catch-up both ways, and the torques of the two differ).
    work: T,
    /// The time since it was read, less the period now ending.
    elapsed: T,
}

/// How long each joint's reading has not changed after a good increment `dq` over `elapsed`
/// to the reading `q`: `still` plus `elapsed` where the joint's reading is unchanged, zero
/// where it moved.
fn still_for<T: Real, G: VectorGroup<T, D>, const D: usize>(
    still: &Tangent<T, D>,
    dq: &Tangent<T, D>,
    elapsed: T,
    q: &G,
) -> Tangent<T, D> {
    let at = q.coordinates();
    Tangent::from_fn(|j, _| {
        if unchanged(dq[j], at[j]) {
            still[j] + elapsed
        } else {
            T::zero()
        }
    })
}

impl<T, G, Sys, F, const D: usize> PassiveController<T, G, Sys, F, D>
where
    T: Real,
    G: VectorGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    /// The passive stepper around a [`Controller`] (its law, add-ons and internal states;
    /// the storage starts at their energy `½τ̇² + ½M_F q̇_F²`). No torque limits, velocity
    /// filter `T_f = 0`, reserve 0.
    pub fn new(controller: Controller<T, G, Sys, F, D>) -> Self {
        let storage = virtual_energy(&controller, controller.state());
        PassiveController {
            controller,
            limits: None,
            resolution: None,
            filter: T::zero(),
            reserve: T::zero(),
            storage,
            held: None,
            velocity_estimate: Tangent::zeros(),
            supervision: None,
            rate: None,
            frozen: None,
            still_for: Tangent::zeros(),
            set_aside: SetAside::zero(),
            candidate: None,
            throttle: None,
            learning: None,
            last_diagnostics: Diagnostics {
                potential: T::zero(),
                lambda1: T::zero(),
                lambda2: T::zero(),
                beta: T::zero(),
                kinetic_energy: T::zero(),
                flywheel_field_speed: T::zero(),
                momentum_along_field: T::zero(),
            },
        }
    }

    /// Checks every sample against `supervision`'s bounds (the period, each joint's speed
    /// and acceleration): a sample that breaks one is a [`Fault`], answered with the safe
    /// torque instead of an error ([`step`](Self::step)).
    pub fn with_supervision(mut self, supervision: Supervision<T, D>) -> Self {
        self.supervision = Some(supervision);
        self
    }

    /// The bounds the samples are checked against, if any.
    pub fn supervision(&self) -> Option<&Supervision<T, D>> {
        self.supervision.as_ref()
    }

    /// Scales the field's pace on the torque margin ([`crate::pace::throttle`]): after every
    /// step, the largest share of a limit the command used before the clamp,
    /// `max_i |T_i|/L_i`, moves the throttle's scale, which the field's pace takes for the
    /// next step. Needs the torque limits ([`with_torque_limits`](Self::with_torque_limits)
    /// first) and a field with a pace scale ([`VelocityField::set_pace_scale`]: a
    /// [`crate::pace::Paced`] pacing with a [`crate::pace::Throttled`] profile); either
    /// missing is an `InvalidParameter` error. Passivity is untouched: the scale is a
    /// parameter of the field, and the coupling is workless whatever the field.
    pub fn with_pace_throttle(mut self, throttle: PaceThrottle<T>) -> Result<Self> {
        if self.limits.is_none() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: a pace throttle reads the torque limits: set them first",
            ));
        }
        if !self.controller.set_pace_scale(throttle.scale()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: the field has no pace scale for a throttle (a Paced \
                 pacing with a Throttled profile has)",
            ));
        }
        self.throttle = Some(throttle);
        Ok(self)
    }

    /// Lets the field's pace learn lap over lap from the torque margin this controller
    /// measures, by `rule` ([`crate::pace::LearnedPace`]): at every step the largest share of
    /// a limit the unclamped command uses goes to the field
    /// ([`VelocityField::learn_pace`]).
    ///
    /// Errors: `InvalidParameter` without torque limits, or for a field with no pace to
    /// learn (a `Paced` pacing whose profile holds a
    /// [`LearnedPace`](crate::pace::LearnedPace) made `periodic` has one).
    pub fn with_pace_learning(mut self, rule: crate::pace::PaceLearning<T>) -> Result<Self> {
        if self.limits.is_none() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: a learned pace reads the torque limits: set them first",
            ));
        }
        // A reading of no share over no time records nothing; the field says whether it
        // learns.
        let tau = self.controller.state().tau;
        if !self.controller.learn_pace(tau, T::zero(), T::zero(), &rule) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: the field has no pace to learn (a pace profile planned \
                 along a closed contour, in a LearnedPace with its period, has)",
            ));
        }
        self.learning = Some(rule);
        Ok(self)
    }

    /// The rule by which the field's pace learns, if it does.
    pub fn pace_learning(&self) -> Option<&crate::pace::PaceLearning<T>> {
        self.learning.as_ref()
    }

    /// The pace throttle, if any (its scale is the one the next step's torque uses).
    pub fn pace_throttle(&self) -> Option<&PaceThrottle<T>> {
        self.throttle.as_ref()
    }

    /// Per-joint torque limits `|u_i| ≤ limit_i` (each > 0, finite).
    pub fn with_torque_limits(mut self, limits: Tangent<T, D>) -> Result<Self> {
        crate::error::ensure_finite(limits.iter(), "PassiveController: torque limits")?;
        if limits.iter().any(|l| *l <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: torque limits must be > 0",
            ));
        }
        self.limits = Some(limits);
        Ok(self)
    }

    /// The encoders' resolution `δ_i` per joint (rad or m, each ≥ 0, finite): the storage is
    /// charged for what rounding the positions can hide (module documentation).
    pub fn with_encoder_resolution(mut self, resolution: Tangent<T, D>) -> Result<Self> {
        crate::error::ensure_finite(resolution.iter(), "PassiveController: encoder resolution")?;
        if resolution.iter().any(|d| *d < T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: encoder resolution must be ≥ 0",
            ));
        }
        self.resolution = Some(resolution);
        Ok(self)
    }

    /// The time constant `T_f ≥ 0` (s) of the first-order filter on the backward difference
    /// that estimates the velocity when none is measured.
    pub fn with_velocity_filter(mut self, time_constant: T) -> Result<Self> {
        if !(time_constant.is_finite() && time_constant >= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: the velocity filter's time constant must be finite and ≥ 0",
            ));
        }
        self.filter = time_constant;
        Ok(self)
    }

    /// The storage the tank keeps in hand (J, ≥ 0): the coupling torque is scaled down when
    /// the energy it would draw over the next period would leave less.
    pub fn with_reserve(mut self, reserve: T) -> Result<Self> {
        if !(reserve.is_finite() && reserve >= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController: the reserve must be finite and ≥ 0",
            ));
        }
        self.reserve = reserve;
        Ok(self)
    }

    /// The wrapped controller (law, add-ons, internal states).
    pub fn controller(&self) -> &Controller<T, G, Sys, F, D> {
        &self.controller
    }

    /// The wrapped controller, to schedule the nominal speed on line.
    pub fn controller_mut(&mut self) -> &mut Controller<T, G, Sys, F, D> {
        &mut self.controller
    }

    /// The storage `S` (J) as of the last step.
    pub fn storage(&self) -> T {
        self.storage
    }

    /// What the storage holds aside, per joint, for the work the joint's reading may hide
    /// while it stands still (with supervision only, zero otherwise: see
    /// [`step`](Self::step)), and what an audit needs to count the part of it the hidden
    /// motion has not used as the controller's energy ([`SetAsideAccount`]).
    pub fn set_aside(&self) -> SetAsideAccount<T, D> {
        self.set_aside.account()
    }

    /// One control step at the measured positions `q` (and velocities `v`, if measured),
    /// with `applied` the torque the drive applied over the last period (after its own
    /// saturation; `None`: the command this controller sent). Returns the next torque to
    /// hold for `dt`. On any error nothing changes (the storage, the internal states and the
    /// held sample stay as they were); a safe fallback is to apply zero torque.
    ///
    /// Errors: `InvalidParameter` for `dt ≤ 0` or not finite; `NonFinite` for NaN/∞ in `q`,
    /// `v` or `applied`, or an overflow; the law's errors ([`EnergyTooLow`](ErrorKind)).
    ///
    /// # With supervision
    /// With [`with_supervision`](Self::with_supervision), a sample that breaks a bound
    /// (a non-finite reading or period, a period out of bounds, a joint beyond its speed or
    /// acceleration bound, a frozen encoder: [`Supervision`]) is not an error: the step
    /// returns `Ok` with [`fault`](PassiveStepOutput::fault) set and the **safe torque,
    /// zero**, and:
    /// - if the positions are good (the period is at fault, the reading within its bounds),
    ///   the last period's balance is made as usual;
    /// - if they are not, the work the last torque did over the period is unseen: the
    ///   storage is charged its bound (reported as [`unseen`](EnergyAccount::unseen)), so
    ///   that no fault can make the controller give more than it has: per joint, with an
    ///   acceleration bound and a joint whose reading was moving, from the last good
    ///   increment's speed `w_i` (measured over `e_w`),
    ///   `u_i w_i h + |u_i| (ā_i h (e_w/2 + s + h/2) + δ_i h/e_w)` for a period beginning `s`
    ///   after the last good reading, at most `|u_i| v̄_i h` and at least zero; otherwise
    ///   `|u_i| v̄_i h`. The last good positions are kept;
    /// - the internal states are not advanced (the internal velocities are put on the
    ///   storage's level), and nothing is integrated from the faulty sample.
    ///
    /// The next good sample is checked against the last good one over the time elapsed
    /// since it, so the controller resumes at the first reading that motion can explain;
    /// the periods of zero torque between are balanced exactly.
    ///
    /// An encoder frozen while its joint is too slow for the acceleration bound to tell is
    /// not seen: the joint looks at rest. So over every period a joint's reading stands
    /// still, the most its torque can have done unseen, `|u_j| v̄_j h`, is held aside
    /// ([`set_aside`](Self::set_aside)): the coupling's share from the storage (reported as
    /// [`set_aside`](EnergyAccount::set_aside)), the add-ons' share reported as theirs (in
    /// [`add_ons`](EnergyAccount::add_ons)); the motion a still reading hides is paid for
    /// before it is given. When the reading moves again, what was held aside comes back,
    /// less what each share's work over the stretch may have been beyond the balance's: over
    /// a stretch `T` long, its work along the straight path plus `(ā/2) Σ|Δu_k| t_k (T − t_k)`
    /// for its changes `Δu_k` at times `t_k` (`4 v̄ / T` in place of `ā/2` without an
    /// acceleration bound), and never more than `Σ |u_k| v̄ h_k`, however the joint moved.
    /// A frozen encoder's reading then jumps, and the jump is rejected;
    /// if the joint at fault
    /// had not moved since the reading before, and the jump is a motion it could have made at
    /// its speed bound while its reading stood still (so that two samples of a spike are not
    /// taken for a catch-up), the rejected reading is kept, and if the next
    /// reading continues from it and not from the last good one, it was the truth: it
    /// becomes the last good reading, and the storage is charged the work the coupling
    /// torque held before the jump did across it, as the balance would have (a credit is not
    /// taken); the jump joins the stretch's motion, and what was set aside comes back at the
    /// next clean increment, less the same bound.
    /// If the step then fails, nothing changes, the catch-up's settlement included: the
    /// candidate stays for the next reading to confirm.
    pub fn step(
        &mut self,
        q: &G,
        v: Option<&Tangent<T, D>>,
        applied: Option<&Tangent<T, D>>,
        dt: T,
    ) -> Result<PassiveStepOutput<T, D>> {
        // A confirmed catch-up's work across the jump, paid by the storage.
        let mut caught_up = T::zero();
        // What the settlement changes, to put back if the step then fails.
        let mut undo = None;
        if let Some(sup) = self.supervision {
            // A frozen encoder's catch-up confirmed: the books of the past are settled first.
            if let Some(c) = self.confirmed_catch_up(&sup, q, dt) {
                undo = Some((
                    self.storage,
                    (self.rate, self.still_for, self.set_aside),
                    self.frozen,
                    self.candidate,
                    self.held,
                ));
                let (jump, t_fault) = self
                    .held
                    .as_ref()
                    .map_or((Tangent::zeros(), T::zero()), |h| {
                        (h.q.inverse().compose(&c.q).log(), h.elapsed - c.elapsed)
                    });
                self.set_aside.caught_up(&jump, t_fault);
                caught_up = c.work;
                self.storage -= c.work;
                self.rate = None;
                self.frozen = None;
                self.still_for = Tangent::zeros();
                self.candidate = None;
                if let Some(h) = self.held.as_mut() {
                    h.q = c.q;
                    h.elapsed = c.elapsed;
                }
            }
        }
        let Some((storage, (rate, still_for, set_aside), frozen, candidate, held)) = undo else {
            // Nothing settled: the output goes straight to the caller (no copy of it).
            return self.step_settled(q, v, applied, dt, caught_up);
        };
        let out = self.step_settled(q, v, applied, dt, caught_up);
        if out.is_err() {
            (
                self.storage,
                (self.rate, self.still_for, self.set_aside),
                self.frozen,
                self.candidate,
                self.held,
            ) = (
                storage,
                (rate, still_for, set_aside),
                frozen,
                candidate,
                held,
            );
        }
        out
    }

    /// [`step`](Self::step) after a catch-up's settlement (`caught_up`: the work it
    /// charged): the fault check, then the safe step or the law's.
    fn step_settled(
        &mut self,
        q: &G,
        v: Option<&Tangent<T, D>>,
        applied: Option<&Tangent<T, D>>,
        dt: T,
        caught_up: T,
    ) -> Result<PassiveStepOutput<T, D>> {
        if let Some(sup) = self.supervision {
            if let Some(fault) = self.detect(&sup, q, v, applied, dt) {
                return self.safe_step(&sup, q, applied, dt, fault, caught_up);
            }
        } else if !(dt.is_finite() && dt > T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "PassiveController::step: dt must be finite and > 0",
            ));
        }
        // (NaN or ∞ in `q` or `v` reaches the law's own check, before anything is committed.)
        if !applied.is_none_or(|u| crate::scalar::all_finite(u.iter())) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "PassiveController::step: NaN or infinite applied torque",
            ));
        }
        let mf = self.controller.law().flywheel().inertia();
        let mut state = *self.controller.state();
        // 1. The last period's balance, from positions only.
        let mut to_robot = T::zero();
        let mut add_ons = T::zero();
        let mut storage = self.storage;
        let mut velocity_estimate = self.velocity_estimate;
        let mut quantisation = T::zero();
        let mut increment = None;
        if let Some(held) = &self.held {
            let b = held.balance(q, applied, self.resolution.as_ref());
            // The time since `held.q` was read (longer than `dt` after faulted periods).
            let elapsed = held.elapsed + dt;
            (to_robot, add_ons, quantisation) = (b.to_robot, b.add_ons, b.quantisation);
            storage = storage - to_robot + held.virtual_add_on - quantisation;
            if v.is_none() {
                velocity_estimate = self.filtered_velocity(&b.dq, elapsed);
            }
            increment = Some((b, elapsed));
        }
        // 1b. With supervision, the work a still reading may hide: set aside, or given back.
        // (A copy to commit only with supervision: a step without it copies nothing.)
        let mut settled = None;
        let mut set_aside = T::zero();
        if let (Some(sup), Some(held), Some((b, elapsed))) =
            (&self.supervision, &self.held, &increment)
        {
            let mut aside = self.set_aside;
            let reported;
            (set_aside, reported) = aside.settle(
                (&b.dq, *elapsed, held.elapsed == T::zero()),
                (&b.coupling, &b.add_on),
                q,
                sup,
                self.resolution.as_ref(),
            );
            storage -= set_aside;
            add_ons += reported;
            settled = Some(aside);
        }
        // 2. The internal velocities put back onto the storage's level set.
        let integrated = virtual_energy(&self.controller, &state);
        let correction = storage - integrated;
        if self.held.is_some() {
            project(&mut state, storage, mf);
        }
        // 3. The law at the measured (or estimated) velocity.
        let velocity = v.copied().unwrap_or(velocity_estimate);
        let s = AugmentedState {
            q: *q,
            v: velocity,
            tau: state.tau,
            tau_dot: state.tau_dot,
            flywheel_speed: state.flywheel_speed,
        };
        let (coupling, add_on, diagnostics) = self.controller.coupling_add_ons_diagnostics(&s)?;
        // 4. The tank: scale the (workless) coupling if the storage cannot pay for it.
        let predicted = coupling.robot.dot(&velocity) * dt;
        let available = storage - self.reserve;
        let scale = if predicted > T::zero() && predicted > available {
            (available / predicted).max(T::zero()).min(T::one())
        } else {
            T::one()
        };
        // (Unscaled, the usual case: the same sum without the four products by 1.)
        let torque = if scale < T::one() {
            coupling * scale + add_on
        } else {
            coupling + add_on
        };
        let mut command = torque.robot;
        let mut saturated = false;
        // The throttle's next scale, from the share of a limit the command uses unclamped.
        let share = match &self.limits {
            Some(limits) if self.throttle.is_some() || self.learning.is_some() => Some(
                command
                    .iter()
                    .zip(limits.iter())
                    .fold(T::zero(), |m, (u, l)| {
                        let r = u.abs() / *l;
                        if r > m || !r.is_finite() {
                            r
                        } else {
                            m
                        }
                    }),
            ),
            _ => None,
        };
        let pace = match (&self.throttle, share) {
            (Some(throttle), Some(share)) => Some((throttle.scale(), throttle.next(share, dt))),
            _ => None,
        };
        if let Some(limits) = &self.limits {
            // Two comparisons per joint, not `max`/`min` (calls to libm's `fmaxf`/`fminf` on
            // a Cortex-M4: ~46 instructions a step). A NaN passes through unclamped, and the
            // overflow check below rejects it.
            for (u, l) in command.iter_mut().zip(limits.iter()) {
                if *u > *l {
                    *u = *l;
                    saturated = true;
                } else if *u < -*l {
                    *u = -*l;
                    saturated = true;
                }
            }
        }
        // 5. The virtual states over the period (semi-implicit Euler, as Controller::step).
        let tau_dot = state.tau_dot + torque.tau * dt;
        let flywheel_speed = state.flywheel_speed
            + torque.flywheel * dt * self.controller.law().flywheel().inverse_inertia();
        let (tau, laps) = self
            .controller
            .wrap_tau(state.tau + tau_dot * dt, state.laps)?;
        let virtual_add_on =
            (add_on.tau * state.tau_dot + add_on.flywheel * state.flywheel_speed) * dt;
        let next = InternalState {
            tau,
            tau_dot,
            flywheel_speed,
            laps,
        };
        if !crate::scalar::all_finite_in(
            command.iter(),
            [&tau, &tau_dot, &flywheel_speed, &storage],
        ) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "PassiveController::step: the torque or the internal states overflowed",
            ));
        }
        // Commit.
        *self.controller.state_mut() = next;
        self.controller.integrate_nominal_speed(&diagnostics, dt);
        if let (Some(throttle), Some((_, scale))) = (self.throttle.as_mut(), pace) {
            throttle.set_scale(scale);
            // The field took this scale when the throttle was set; it takes any in (0, 1].
            self.controller.set_pace_scale(throttle.scale());
        }
        if let (Some(rule), Some(share)) = (&self.learning, share) {
            self.controller.learn_pace(state.tau, share, dt, rule);
        }
        self.storage = storage;
        self.velocity_estimate = velocity_estimate;
        if self.supervision.is_some() {
            if let Some((b, e)) = &increment {
                self.still_for = still_for(&self.still_for, &b.dq, *e, q);
            }
            self.rate = increment.map(|(b, e)| (b.dq / e, e));
            if let Some(aside) = settled {
                self.set_aside = aside;
            }
            self.frozen = None;
            self.candidate = None;
            self.last_diagnostics = diagnostics;
        }
        // The torque applied over the period that just ended (for the encoders' charge).
        let previous = match (&self.resolution, &self.held) {
            (Some(_), Some(h)) => Some(applied.copied().unwrap_or(h.command)),
            _ => None,
        };
        self.held = Some(Held {
            q: *q,
            command,
            add_on: add_on.robot,
            virtual_add_on,
            previous,
            elapsed: T::zero(),
        });
        Ok(PassiveStepOutput {
            torque: command,
            add_on: add_on.robot,
            velocity,
            state,
            diagnostics,
            energy: EnergyAccount {
                storage,
                to_robot: to_robot + caught_up,
                add_ons,
                correction,
                scale,
                saturated,
                quantisation,
                unseen: T::zero(),
                set_aside,
            },
            fault: None,
            pace_scale: pace.map_or(T::one(), |(s, _)| s),
        })
    }

    /// The velocity estimate after an increment `dq` read over `elapsed`: the backward
    /// difference through the first-order filter of time constant `T_f`,
    /// `v̂ ← α v̂ + (1 − α) dq / elapsed`, `α = T_f / (T_f + elapsed)`.
    fn filtered_velocity(&self, dq: &Tangent<T, D>, elapsed: T) -> Tangent<T, D> {
        let alpha = self.filter / (self.filter + elapsed);
        self.velocity_estimate * alpha + dq * ((T::one() - alpha) / elapsed)
    }

    /// The fault of a sample, if any, and whether its positions are good (the order:
    /// non-finite readings, the period, the frozen encoder, the speed and acceleration
    /// bounds). A period at fault is reported first, but its positions are still checked.
    fn detect(
        &self,
        sup: &Supervision<T, D>,
        q: &G,
        v: Option<&Tangent<T, D>>,
        applied: Option<&Tangent<T, D>>,
        dt: T,
    ) -> Option<(Fault, bool)> {
        let finite = |x: &Tangent<T, D>| x.iter().all(|e| e.is_finite());
        if !(finite(&q.coordinates()) && v.is_none_or(finite) && applied.is_none_or(finite)) {
            return Some((Fault::NonFinite, false));
        }
        let reading = match &self.held {
            Some(held) => {
                let dq = held.q.inverse().compose(q).log();
                let at = held.q.coordinates();
                match self.frozen {
                    Some(joint) if unchanged(dq[joint], at[joint]) => Some(Fault::Frozen { joint }),
                    _ => sup.check_increment(
                        (&dq, &at),
                        held.elapsed + sup.elapsed(dt),
                        self.rate.as_ref(),
                        self.resolution.as_ref(),
                    ),
                }
            }
            None => None,
        }
        .or_else(|| v.and_then(|v| sup.check_velocity(v)));
        if !sup.period_ok(dt) {
            return Some((Fault::Period, reading.is_none()));
        }
        reading.map(|f| (f, false))
    }

    /// The candidate ([`Candidate`]) this reading confirms: it continues from the candidate
    /// within the bounds, and not from the last good reading.
    fn confirmed_catch_up(&self, sup: &Supervision<T, D>, q: &G, dt: T) -> Option<Candidate<T, G>> {
        let c = self.candidate?;
        let held = self.held.as_ref()?;
        if !q.coordinates().iter().all(|x| x.is_finite()) {
            return None;
        }
        let period = sup.elapsed(dt);
        let resolution = self.resolution.as_ref();
        let from_candidate = c.q.inverse().compose(q).log();
        let from_good = held.q.inverse().compose(q).log();
        let fits_candidate = sup
            .check_increment(
                (&from_candidate, &c.q.coordinates()),
                c.elapsed + period,
                None,
                resolution,
            )
            .is_none();
        let fits_good = sup
            .check_increment(
                (&from_good, &held.q.coordinates()),
                held.elapsed + period,
                self.rate.as_ref(),
                resolution,
            )
            .is_none();
        (fits_candidate && !fits_good).then_some(c)
    }

    /// The step at a fault: the safe torque (zero), the storage charged for what the last
    /// torque may have done unseen, nothing integrated ([`step`](Self::step)).
    fn safe_step(
        &mut self,
        sup: &Supervision<T, D>,
        q: &G,
        applied: Option<&Tangent<T, D>>,
        dt: T,
        (fault, good_positions): (Fault, bool),
        caught_up: T,
    ) -> Result<PassiveStepOutput<T, D>> {
        let mf = self.controller.law().flywheel().inertia();
        let period = sup.elapsed(dt);
        let applied = applied.filter(|u| u.iter().all(|x| x.is_finite()));
        let mut storage = self.storage;
        let (mut to_robot, mut add_ons, mut unseen, mut quantisation) =
            (T::zero(), T::zero(), T::zero(), T::zero());
        let mut velocity_estimate = self.velocity_estimate;
        let mut rate = self.rate;
        let mut candidate = self.candidate;
        let mut good_increment = None;
        let mut aside = self.set_aside;
        let mut set_aside = T::zero();
        let held = match &self.held {
            Some(held) => {
                let u = applied.copied().unwrap_or(held.command);
                let previous = self.resolution.map(|_| u);
                storage += held.virtual_add_on;
                // A reading rejected where the joint had not moved since the last good one
                // may be a frozen encoder's catch-up: kept until the next reading tells.
                // And the jump must be a motion the joint could have made, at its speed bound,
                // while its reading stood still: two samples of a spike are not a catch-up.
                let at = held.q.coordinates();
                let still = |j: usize| self.rate.is_some_and(|(w, e)| unchanged(w[j] * e, at[j]));
                let jump = || held.q.inverse().compose(q).log();
                let reachable = |j: usize| {
                    let hidden = self.still_for[j] + held.elapsed + period;
                    let count = self.resolution.map_or(T::zero(), |r| r[j]);
                    jump()[j].abs() <= sup.max_speed()[j] * hidden + count
                };
                match (fault, candidate.as_mut()) {
                    (_, Some(c)) => c.elapsed += period,
                    (Fault::Speed { joint } | Fault::Acceleration { joint }, None)
                        if !good_positions && still(joint) && reachable(joint) =>
                    {
                        let jump = jump();
                        candidate = Some(Candidate {
                            q: *q,
                            // Never a credit: if the reading was a spike that lasted, the
                            // work across it and back would not cancel (the torques differ).
                            work: (u - held.delivered_add_on(&u)).dot(&jump).max(T::zero()),
                            elapsed: T::zero(),
                        });
                    }
                    _ => {}
                }
                if good_positions {
                    let b = held.balance(q, applied, self.resolution.as_ref());
                    let dq = b.dq;
                    let elapsed = held.elapsed + period;
                    (to_robot, add_ons, quantisation) = (b.to_robot, b.add_ons, b.quantisation);
                    storage = storage - to_robot - quantisation;
                    let reported;
                    (set_aside, reported) = aside.settle(
                        (&dq, elapsed, held.elapsed == T::zero()),
                        (&b.coupling, &b.add_on),
                        q,
                        sup,
                        self.resolution.as_ref(),
                    );
                    storage -= set_aside;
                    add_ons += reported;
                    velocity_estimate = self.filtered_velocity(&dq, elapsed);
                    rate = Some((dq / elapsed, elapsed));
                    good_increment = Some((dq, elapsed));
                    Some((*q, T::zero(), previous))
                } else {
                    // The add-ons' share too: their work is not reported for this period.
                    // From the last good increment's speed where it is known (the joint's
                    // reading had not stood still), else from the speed bound.
                    let still_since = |j: usize| self.still_for[j] > T::zero() || still(j);
                    unseen = sup.unseen_work_after(
                        (&u, period),
                        held.elapsed,
                        self.rate.as_ref(),
                        self.resolution.as_ref(),
                        still_since,
                    );
                    add_ons = held.virtual_add_on;
                    storage -= unseen;
                    Some((held.q, held.elapsed + period, previous))
                }
            }
            None => good_positions.then_some((*q, T::zero(), None)),
        };
        let mut state = *self.controller.state();
        let integrated = virtual_energy(&self.controller, &state);
        let correction = storage - integrated;
        if self.held.is_some() {
            project(&mut state, storage, mf);
        }
        if !(storage.is_finite() && velocity_estimate.iter().all(|x| x.is_finite())) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "PassiveController::step: the storage overflowed at a fault",
            ));
        }
        // Commit: nothing integrated, the safe torque held.
        *self.controller.state_mut() = state;
        self.storage = storage;
        self.velocity_estimate = velocity_estimate;
        self.rate = rate;
        self.set_aside = aside;
        if let Some((dq, e)) = &good_increment {
            self.still_for = still_for(&self.still_for, dq, *e, q);
        }
        self.candidate = if good_positions { None } else { candidate };
        if let Fault::Frozen { joint } = fault {
            self.frozen = Some(joint);
        } else if good_positions {
            self.frozen = None;
        }
        self.held = held.map(|(q, elapsed, previous)| Held {
            q,
            command: Tangent::zeros(),
            add_on: Tangent::zeros(),
            virtual_add_on: T::zero(),
            previous,
            elapsed,
        });
        Ok(PassiveStepOutput {
            torque: Tangent::zeros(),
            add_on: Tangent::zeros(),
            velocity: velocity_estimate,
            state,
            diagnostics: self.last_diagnostics,
            energy: EnergyAccount {
                storage,
                to_robot: to_robot + caught_up,
                add_ons,
                correction,
                scale: T::zero(),
                saturated: false,
                quantisation,
                unseen,
                set_aside,
            },
            fault: Some(fault),
            pace_scale: self.throttle.as_ref().map_or(T::one(), |t| t.scale()),
        })
    }
}
/// `½τ̇² + ½M_F q̇_F²` of the controller's internal states.
fn virtual_energy<T: Real, G, Sys, F, const D: usize>(
    c: &Controller<T, G, Sys, F, D>,
    s: &InternalState<T>,
) -> T
where
    G: crate::lie::LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    let mf = c.law().flywheel().inertia();
    (s.tau_dot * s.tau_dot + mf * s.flywheel_speed * s.flywheel_speed) * cast::<T>(0.5)
}

/// Puts `(τ̇, q̇_F)` on the level set `½τ̇² + ½M_F q̇_F² = storage`: the flywheel takes the
/// change; `τ̇` only if the flywheel alone cannot (then the flywheel stops); both stop when
/// the storage is overdrawn.
fn project<T: Real>(state: &mut InternalState<T>, storage: T, mf: T) {
    let two = cast::<T>(2.0);
    let rest = two * storage - state.tau_dot * state.tau_dot;
    if rest >= T::zero() {
        let speed = (rest / mf).sqrt_fast();
        state.flywheel_speed = if state.flywheel_speed < T::zero() {
            -speed
        } else {
            speed
        };
    } else {
        state.flywheel_speed = T::zero();
        let speed = (two * storage).max(T::zero()).sqrt_fast();
        state.tau_dot = if state.tau_dot < T::zero() {
            -speed
        } else {
            speed
        };
    }
}
