//! The paper's Fig. 2: a *time-invariant* velocity field on the configuration space that
//! traces a circle, without suspension, as an example of the `VelocityField` extension point.
//! The same coupling (eq. 7) and the same flywheel make the SCARA follow it passively.
//! `cargo run --release --example circle_field` (optional arguments: ρ, α, k, seconds).
//!
//! The field, on the chart `x = q − c` of the torus (`|qᵢ| < π`), is
//!
//! `V(x) = α J x − k (|x|² − ρ²) x`,  `J` the quarter turn,
//!
//! a smooth (polynomial) field whose only closed orbit is the circle `|x| = ρ`: on it the
//! field is the tangent `α J x` (speed `αρ`); off it, the radial part `−k (|x|² − ρ²) x` is
//! `−grad U` of `U = ¼ k (|x|² − ρ²)²`, which pulls every point but the centre onto the
//! circle. Its rate along a motion is `V̇ = α J ẋ − k (|x|² − ρ²) ẋ − 2k (xᵀẋ) x`, exact, as
//! the trait asks. `τ` is not used: `V_I = 0`, so the suspended coordinate comes to rest.
//!
//! As the paper says of its Lissajous curve, a contour that crosses itself has no such field:
//! that is what the suspension of section III is for.

use nalgebra::{Matrix2, Vector2};
use pvfc::prelude::*;
use pvfc::sim::ClosedLoop;

/// The time-invariant circle field of Fig. 2 on the SCARA's joint space.
#[derive(Clone, Copy, Debug)]
pub struct CircleField {
    /// The centre `c` (rad).
    pub centre: Vector2<f64>,
    /// The radius `ρ` (rad).
    pub radius: f64,
    /// The angular speed `α` on the circle (rad/s at `β = 1`).
    pub angular_speed: f64,
    /// The gain `k` of the pull onto the circle.
    pub gain: f64,
}

impl CircleField {
    /// The chart coordinate `x = q − c`.
    fn chart(&self, q: &Torus<f64, 2>) -> Vector2<f64> {
        q.angles() - self.centre
    }

    /// The point of the circle nearest to `q` (the centre's own nearest point is taken
    /// along the first axis).
    pub fn nearest(&self, q: &Torus<f64, 2>) -> Vector2<f64> {
        let x = self.chart(q);
        let n = x.norm();
        let dir = if n > 0.0 { x / n } else { Vector2::x() };
        self.centre + dir * self.radius
    }
}

impl VelocityField<f64, Torus<f64, 2>, 2> for CircleField {
    fn sample(
        &self,
        q: &Torus<f64, 2>,
        v: &Vector2<f64>,
        _tau: f64,
        _tau_dot: f64,
    ) -> FieldSample<f64, Torus<f64, 2>, 2> {
        let j = Matrix2::new(0.0, -1.0, 1.0, 0.0);
        let x = self.chart(q);
        let s = x.norm_squared() - self.radius * self.radius;
        let gradient = x * (self.gain * s);
        let velocity = j * x * self.angular_speed - gradient;
        let rate =
            j * v * self.angular_speed - v * (self.gain * s) - x * (2.0 * self.gain * x.dot(v));
        let nearest = Torus::new(self.nearest(q));
        FieldSample {
            contour: ContourSample {
                point: nearest,
                velocity: j * (nearest.angles() - self.centre) * self.angular_speed,
                acceleration: Vector2::zeros(),
            },
            error: Torus::new(q.angles() - nearest.angles()),
            potential: 0.25 * self.gain * s * s,
            gradient,
            lambda1: 1.0,
            lambda2: 1.0,
            velocity,
            velocity_tau: 0.0,
            rate,
            rate_tau: 0.0,
            error_velocity: Vector2::zeros(),
        }
    }
}

/// The controller: the Pelican SCARA of the paper's experiment, this field, a flywheel of
/// inertia 1 holding `Ē`, and the coupling gain `γ`.
pub fn controller(
    field: CircleField,
    energy: f64,
    gamma: f64,
) -> Result<Controller<f64, Torus<f64, 2>, Scara<f64>, CircleField, 2>, Error> {
    let law = PvfcLaw::new(Scara::pelican(), field, Flywheel::new(1.0, energy)?, gamma)?;
    Ok(Controller::new(law).starting_at_rest(0.0))
}

/// What a run of [`run`] shows.
#[derive(Clone, Copy, Debug)]
pub struct Outcome {
    /// `max |κ_a(t) − κ_a(0)| / κ_a(0)`.
    pub energy_drift: f64,
    /// The largest `|q̇_aᵀ T_a|` of the coupling over the run, relative to `κ_a(0)` (1/s).
    pub coupling_power: f64,
    /// `||x| − ρ|` over the last second (rad).
    pub radial_error: f64,
    /// The mean angular speed of `x` about the centre over the last second (rad/s).
    pub angular_speed: f64,
    /// `β` at the end.
    pub beta: f64,
    /// The largest `|qᵢ − cᵢ|` over the run: the chart is valid below π.
    pub reach: f64,
}

/// The closed loop without friction from `q0` at rest, the energy in the flywheel, RK4 at
/// 1 kHz for `seconds`; `print` every `print` steps (0: never).
pub fn run(
    field: CircleField,
    q0: Vector2<f64>,
    seconds: f64,
    print: usize,
) -> Result<Outcome, Error> {
    let ctl = controller(field, 50.0, 0.5)?;
    let sys = ClosedLoop::matched(ctl);
    let init = ctl.state();
    let mut s = AugmentedState {
        q: Torus::new(q0),
        v: Vector2::zeros(),
        tau: init.tau,
        tau_dot: init.tau_dot,
        flywheel_speed: init.flywheel_speed,
    };
    let (dt, zero) = (1e-3, Vector2::zeros());
    let steps = (seconds / dt).round() as usize;
    let e0 = sys.kinetic_energy(&s);
    let mut out = Outcome {
        energy_drift: 0.0,
        coupling_power: 0.0,
        radial_error: 0.0,
        angular_speed: 0.0,
        beta: 0.0,
        reach: 0.0,
    };
    let mut turned = 0.0;
    let last = steps.saturating_sub(1000);
    for k in 0..=steps {
        let c = sys.evaluate(&s, &zero)?.coupling;
        let x = s.q.angles() - field.centre;
        out.energy_drift = out
            .energy_drift
            .max((sys.kinetic_energy(&s) - e0).abs() / e0);
        out.coupling_power = out
            .coupling_power
            .max(c.torque.dot(&s.velocity()).abs() / e0);
        out.reach = out.reach.max(x.amax());
        out.beta = c.beta;
        if k >= last {
            out.radial_error = out.radial_error.max((x.norm() - field.radius).abs());
            // dθ/dt = (x × ẋ) / |x|².
            turned += (x.x * s.v.y - x.y * s.v.x) / x.norm_squared() * dt;
        }
        if print > 0 && k % print == 0 {
            println!(
                "{:>6.2} {:>9.4} {:>9.4} {:>10.3e} {:>8.5} {:>12.3e}",
                k as f64 * dt,
                x.norm(),
                c.field.potential,
                c.velocity_field_error_energy(),
                c.beta,
                sys.kinetic_energy(&s) - e0
            );
        }
        if k < steps {
            s = sys.rk4_step(&s, dt, &zero)?;
        }
    }
    out.angular_speed = turned / (dt * (steps - last + 1) as f64);
    Ok(out)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let field = CircleField {
        centre: Vector2::zeros(),
        radius: args.first().copied().unwrap_or(0.8),
        angular_speed: args.get(1).copied().unwrap_or(1.0),
        gain: args.get(2).copied().unwrap_or(2.0),
    };
    let seconds = args.get(3).copied().unwrap_or(20.0);
    println!(
        "Fig. 2: a time-invariant field tracing a circle of radius {} rad at {} rad/s (k = {}), Pelican SCARA, no friction",
        field.radius, field.angular_speed, field.gain
    );
    for q0 in [Vector2::new(0.1, -0.05), Vector2::new(1.6, 1.2)] {
        println!("from q = ({}, {}) at rest:", q0.x, q0.y);
        println!(
            "{:>6} {:>9} {:>9} {:>10} {:>8} {:>12}",
            "t [s]", "|q − c|", "U", "W_β", "β", "κ_a − κ_a(0)"
        );
        let o = run(field, q0, seconds, (seconds * 50.0) as usize)?;
        println!(
            "  last second: ||q − c| − ρ| ≤ {:.2e} rad, angular speed {:.4} rad/s (β α = {:.4}); energy drift {:.1e}, |q̇_aᵀT_a|/κ_a ≤ {:.1e}",
            o.radial_error,
            o.angular_speed,
            o.beta * field.angular_speed,
            o.energy_drift,
            o.coupling_power
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `d/dt g(t)` at 0 by central differences.
    fn finite_difference_rate(g: impl Fn(f64) -> Vector2<f64>) -> Vector2<f64> {
        let h = 1e-6;
        (g(h) - g(-h)) / (2.0 * h)
    }

    fn field() -> CircleField {
        CircleField {
            centre: Vector2::new(0.1, -0.2),
            radius: 0.8,
            angular_speed: 1.0,
            gain: 2.0,
        }
    }

    /// From inside and from outside the circle, at rest: the arm ends on the circle, going
    /// round at `βα`, with the energy kept and the coupling workless.
    #[test]
    fn the_scara_traces_the_circle_passively() {
        for q0 in [Vector2::new(0.2, -0.1), Vector2::new(1.6, 1.2)] {
            let o = run(field(), q0, 20.0, 0).unwrap();
            assert!(o.reach < 2.5, "the run leaves the chart: {}", o.reach);
            assert!(o.energy_drift < 1e-6, "energy drift {:e}", o.energy_drift);
            assert!(o.coupling_power < 1e-9, "q̇ᵀT = {:e} κ_a", o.coupling_power);
            assert!((o.beta - 1.0).abs() < 1e-6, "β = {}", o.beta);
            assert!(
                o.radial_error < 1e-3,
                "off the circle by {}",
                o.radial_error
            );
            assert!(
                (o.angular_speed - o.beta).abs() < 1e-4,
                "angular speed {} for βα = {}",
                o.angular_speed,
                o.beta
            );
        }
    }

    /// The field's rate is its derivative along the motion (against finite differences).
    #[test]
    fn the_rate_is_the_derivative_along_the_motion() {
        let f = field();
        for (q, v) in [
            (Vector2::new(0.3, 0.4), Vector2::new(0.7, -1.1)),
            (Vector2::new(-1.2, 0.9), Vector2::new(-0.2, 0.5)),
        ] {
            let analytic = f.sample(&Torus::new(q), &v, 0.0, 0.0).rate;
            let numeric =
                finite_difference_rate(|t| f.sample(&Torus::new(q + v * t), &v, 0.0, 0.0).velocity);
            assert!(
                (analytic - numeric).norm() < 1e-6 * (1.0 + analytic.norm()),
                "{analytic} vs {numeric}"
            );
        }
    }
}
