//! A part program on a robot, from Rust: the bracket of `scenarios/parts/bracket.nc` (G1
//! lines, G2 and G3 arcs of both senses, feeds of 100 and 30 mm/s), placed on the table in
//! the part's frame, turned into the joint contour by inverse kinematics (adaptive sampling,
//! 10 µm), followed by PVFC paced by the program's feeds, with gravity compensation, in a
//! 1 kHz loop against the robot's own dynamics (semi-implicit Euler, `M v̇ = T − C v − g`).
//! The UR5 (6 joints, tip `tool0`) or the Panda (7 joints, tip `panda_hand_tcp`), each with
//! its own seed and part placement. The same program is `part_program.py` and
//! `part_program.cpp`; the three print the same numbers.
//!
//! `cargo run --release --example part_program -- models/ur5/ur5_robot.urdf tool0`

use pvfc::control::model::arm::{ArmController, ArmSettings};
use pvfc::control::model::cartesian::CartesianSpec;
use pvfc::control::model::pace::{PaceSettings, PathSpeed};
use pvfc::control::model::pose::PoseSpec;
use pvfc::control::model::robot::Robot;
use std::path::{Path, PathBuf};

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
    let mut args = std::env::args().skip(1);
    let urdf: PathBuf = args
        .next()
        .unwrap_or_else(|| "models/ur5/ur5_robot.urdf".into())
        .into();
    let tip = args.next().unwrap_or_else(|| "tool0".into());
    let robot = Robot::from_urdf(&urdf, None, Some(&tip))?;
    let n = robot.dof();
    // The seed of the inverse kinematics and the part's place on the table, per robot.
    let (seed, part) = if n == 6 {
        (
            vec![0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
            [0.45, -0.15, 0.30, 0.1],
        )
    } else {
        (
            vec![0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785],
            [0.35, -0.175, 0.30, 0.0],
        )
    };
    let path = CartesianSpec {
        points: Vec::new(),
        gcode: Some("scenarios/parts/bracket.nc".into()),
        part: Some(PoseSpec {
            xyz: [part[0], part[1], part[2]],
            rpy: [0.0, 0.0, part[3]],
        }),
        seed,
        fixed_orientation: true,
        period: Some(12.0),
        ..CartesianSpec::default()
    };
    let here = Path::new("");
    let feeds = path.feeds(here, None)?.ok_or("the program has no feeds")?;
    let settings = ArmSettings {
        self_pacing: 50.0,
        energy: 400.0,
        coupling_rate: Some(400.0),
        nominal_speed: Some((0.5, 1.0)),
        pace: Some(PaceSettings {
            speed: Some(PathSpeed::Feeds(feeds)),
            torque_limit: Vec::new(),
            headroom: 0.8,
            level: 1.0,
        }),
        ..ArmSettings::new(path.joint_contour(&robot, here)?, vec![16.0; n])
    };
    let mut ctl = ArmController::new(&robot, &settings)?;
    let mut q: Vec<f64> = ctl.contour_point(0.0).iter().map(|x| x + 0.02).collect();
    let mut v = vec![0.0; n];
    let dt = 1e-3;
    println!("part_program (Rust)");
    for k in 0..=4000 {
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
