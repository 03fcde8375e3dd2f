//! The SCARA of `models/scara.urdf` on the paper's Lissajous contour, from Rust: the robot
//! read from its URDF, the controller built, and a 1 kHz loop that steps it against the
//! robot's own dynamics (semi-implicit Euler, `M v̇ = T − C v − g`). The same program is
//! `scara_contour.py` and `scara_contour.cpp`; the three print the same numbers.
//!
//! `cargo run --release --example scara_contour -- models/scara.urdf`

use pvfc::control::model::arm::{ArmController, ArmSettings, JointContourSpec};
use pvfc::control::model::robot::Robot;
use std::path::PathBuf;

/// `x` with `M x = b` (`M` symmetric positive definite, row-major `n × n`), by Cholesky with
/// the loops in the order of the Python and C++ programs.
fn solve(m: &[f64], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = m[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = if i == j { s.sqrt() } else { s / l[j * n + j] };
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * y[k];
        }
        y[i] = s / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut s = y[i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
    x
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let urdf: PathBuf = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "models/scara.urdf".into())
        .into();
    let robot = Robot::from_urdf(&urdf, None, Some("tool"))?;
    let settings = ArmSettings {
        self_pacing: 5.0,
        energy: 50.0,
        gamma: 1.0,
        ..ArmSettings::new(
            JointContourSpec::Lissajous {
                amplitude: vec![1.0, 1.5],
                periods: vec![3.0, 6.0],
                phase: vec![0.0, std::f64::consts::FRAC_PI_2],
                offset: vec![0.0, 0.0],
                period: Some(6.0),
            },
            vec![1.0, 1.0],
        )
    };
    let mut ctl = ArmController::new(&robot, &settings)?;
    let n = robot.dof();
    let mut q: Vec<f64> = ctl.contour_point(0.0).iter().map(|x| x + 0.1).collect();
    let mut v = vec![0.0; n];
    let dt = 1e-3;
    println!("scara_contour (Rust)");
    for k in 0..=6000 {
        let (tau, tau_dot, _, _) = ctl.state();
        let torque = ctl.step(&q, &v, dt)?.torque;
        if k % 500 == 0 {
            let xd = ctl.contour_point(tau);
            let e = q
                .iter()
                .zip(&xd)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            println!(
                "t {:.1} tau {:.6e} tau_dot {:.6e} error {:.6e}",
                k as f64 * dt,
                tau,
                tau_dot,
                e
            );
        }
        let m: Vec<f64> = robot.inertia(&q)?.transpose().iter().copied().collect();
        let c = robot.coriolis(&q, &v)?;
        let g = robot.gravity(&q)?;
        let mut b = vec![0.0; n];
        for i in 0..n {
            let mut s = torque[i] - g[i];
            for j in 0..n {
                s -= c[(i, j)] * v[j];
            }
            b[i] = s;
        }
        let a = solve(&m, &b);
        for i in 0..n {
            v[i] += dt * a[i];
            q[i] += dt * v[i];
        }
    }
    Ok(())
}
