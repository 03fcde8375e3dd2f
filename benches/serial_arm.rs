//! One control step of the UR5 (6 joints) and the Franka Panda (7), f64 and f32, as in a
//! 1 kHz loop: a fresh controller steps through 1000 states recorded from a closed-loop run
//! (gravity compensation, waypoint contour, self-pacing). Criterion reports the 1000 steps;
//! divide by 1000. The paper's SCARA step runs in the same group as the baseline of the ratio.

#[path = "common/baseline.rs"]
mod baseline;
#[path = "common/machine.rs"]
mod machine;

use criterion::{criterion_group, Criterion, Throughput};
use nalgebra::SVector;
use pvfc::prelude::*;
use pvfc::sim::model::arm::{
    arm_controller, ArmControllerN, ArmSettings, JointContour, JointContourSpec,
};
use pvfc::sim::model::cartesian::{CartesianSpec, CircleSpec};
use pvfc::sim::model::robot::Robot;
use pvfc::sim::urdf::ChainDescription;
use pvfc::sim::ClosedLoop;
use pvfc_core::augmented::AugmentedState;
use pvfc_core::task_field::TaskSpaceField;
use std::hint::black_box;
use std::path::Path;

const STEPS: usize = 1000;

/// Recorded measurements `(q, q̇)` of an `N`-joint arm.
type Samples<const N: usize> = Vec<(JointSpace<f64, N>, SVector<f64, N>)>;
const DT: f64 = 1e-3;

fn settings(waypoints: Vec<Vec<f64>>, n: usize) -> ArmSettings {
    ArmSettings {
        field: pvfc_sim::model::arm_field::FieldSpec::Joint,
        contour: JointContourSpec::Waypoints {
            points: waypoints,
            spacing: 1.0,
        },
        h: vec![4.0; n],
        self_pacing: 50.0,
        energy: 40.0,
        flywheel_inertia: 1.0,
        gamma: 1.0,
        coupling_rate: None,
        gravity_compensation: true,
        friction_compensation: None,
        friction_band: 0.0,
        nominal_speed: None,
        nominal_speed_integral: 0.0,
        tau0: 0.0,
        field_energy_bound: None,
        obstacles: None,
        pace: None,
    }
}

/// The controller and 1000 (q, q̇) recorded along its closed loop from off the contour.
fn arm<const N: usize>(
    file: &str,
    tip: &str,
    waypoints: Vec<Vec<f64>>,
) -> (ArmControllerN<N>, Samples<N>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models")
        .join(file);
    let chain = ChainDescription::from_file(&path, None, Some(tip))
        .expect("shipped URDF")
        .chain::<N>()
        .expect("dof");
    let first = SVector::<f64, N>::from_column_slice(&waypoints[0]);
    let ctl = arm_controller(chain, &settings(waypoints, N)).expect("valid settings");
    let sys = ClosedLoop::matched(ctl.clone());
    let i = *ctl.state();
    let mut s = AugmentedState {
        q: chain.configuration(first + SVector::repeat(0.2)),
        v: SVector::zeros(),
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    let samples = (0..STEPS)
        .map(|_| {
            let x = (s.q, s.v);
            s = sys.rk4_step(&s, DT, &SVector::zeros()).expect("valid run");
            x
        })
        .collect();
    (ctl, samples)
}

fn bench_arm<const N: usize>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    ctl: &ArmControllerN<N>,
    samples: &[(JointSpace<f64, N>, SVector<f64, N>)],
) {
    // Each batch starts from the same controller (a clone, outside the timing: the spline
    // lives on the heap).
    g.bench_function(name, |b| {
        b.iter_batched_ref(
            || ctl.clone(),
            |c| {
                for (q, v) in samples {
                    black_box(c.step(black_box(q), black_box(v), DT).expect("valid"));
                }
            },
            criterion::BatchSize::SmallInput,
        )
    });
}

fn serial_arm(c: &mut Criterion) {
    let mut g = c.benchmark_group("control_step_x1000");
    g.throughput(Throughput::Elements(STEPS as u64));

    // The baseline of the ratios: the paper's SCARA step.
    baseline::scara_step_baseline(&mut g);

    let (ur5, ur5_samples) = arm::<6>(
        "ur5/ur5_robot.urdf",
        "tool0",
        vec![
            vec![0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
            vec![0.5, -1.0, 1.2, -1.7, -1.4, 0.3],
            vec![0.8, -1.4, 1.6, -1.6, -1.2, 0.6],
            vec![0.3, -1.7, 1.9, -1.9, -1.5, 0.2],
            vec![-0.3, -1.5, 1.7, -2.0, -1.8, -0.3],
        ],
    );
    bench_arm::<6>(&mut g, "ur5_f64", &ur5, &ur5_samples);
    // The rigid-body part alone: M, C and g (what Pinocchio's crba + computeCoriolisMatrix +
    // computeGeneralizedGravity compute).
    let chain = *ur5.law().system();
    g.bench_function("ur5_dynamics_f64", |b| {
        b.iter(|| {
            for (q, v) in &ur5_samples {
                black_box(chain.dynamics(black_box(q.coords()), black_box(v)));
            }
        })
    });
    let (panda, panda_samples) = arm::<7>(
        "panda/panda.urdf",
        "panda_hand_tcp",
        vec![
            vec![0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8],
            vec![0.4, -0.1, 0.2, -2.0, 0.2, 2.1, 1.0],
            vec![0.7, -0.4, 0.3, -1.8, 0.1, 1.8, 1.2],
            vec![0.3, -0.7, 0.1, -2.3, -0.2, 1.7, 0.9],
            vec![-0.3, -0.5, -0.2, -2.5, -0.1, 2.0, 0.6],
        ],
    );
    bench_arm::<7>(&mut g, "panda_f64", &panda, &panda_samples);

    // A Cartesian path's contour: the UR5 rounded rectangle with 24 waypoints and sampled to
    // 10 µm, and a Panda circle sampled to 10 µm. The spline is evaluated in constant time,
    // so the step should cost the same whatever the number of waypoints.
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let ur5_robot = Robot::from_urdf(&models.join("ur5/ur5_robot.urdf"), None, Some("tool0"))
        .expect("shipped URDF");
    let rectangle = |samples| CartesianSpec {
        points: vec![
            [0.45, -0.15, 0.30],
            [0.65, -0.15, 0.30],
            [0.65, 0.20, 0.30],
            [0.45, 0.20, 0.30],
        ],
        corner_radius: 0.03,
        samples,
        seed: vec![0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
        fixed_orientation: true,
        ..CartesianSpec::default()
    };
    let mut near_rectangle = Vec::new();
    for (name, samples) in [("ur5_rectangle_24_f64", 24), ("ur5_rectangle_10um_f64", 0)] {
        let path = rectangle(samples)
            .joint_path(&ur5_robot, Path::new("."))
            .expect("the rectangle is reachable");
        println!("{name}: {} waypoints", path.geometry.samples);
        let (ctl, samples) = arm::<6>("ur5/ur5_robot.urdf", "tool0", path.waypoints);
        bench_arm::<6>(&mut g, name, &ctl, &samples);
        near_rectangle = samples;
    }
    // The task-space field on the same path (a C² curve on ℝ³ through 128 of its points),
    // stepped through the same states.
    let rectangle_points = rectangle(24)
        .path(Path::new("."))
        .expect("valid path")
        .sample(128);
    let ur5_chain = *ur5.law().system();
    task_arm(
        &mut g,
        "ur5_task_f64",
        ur5_chain,
        &rectangle_points,
        None,
        None,
        &near_rectangle,
    );
    task_arm(
        &mut g,
        "ur5_task_f32",
        ur5_chain.cast::<f32>(),
        &rectangle_points,
        None,
        None,
        &near_rectangle,
    );
    // With the tool held pointing down (a six-dimensional task, as `ur5_cartesian_task`).
    let down = ur5_robot
        .tool_pose(&[0.0, -1.2, 1.4, -1.8, -1.57, 0.0])
        .expect("6 joints")
        .0;
    task_arm(
        &mut g,
        "ur5_task_held_f64",
        ur5_chain,
        &rectangle_points,
        None,
        Some(down),
        &near_rectangle,
    );
    task_arm(
        &mut g,
        "ur5_task_held_f32",
        ur5_chain.cast::<f32>(),
        &rectangle_points,
        None,
        Some(down),
        &near_rectangle,
    );
    let panda_robot = Robot::from_urdf(
        &models.join("panda/panda.urdf"),
        None,
        Some("panda_hand_tcp"),
    )
    .expect("shipped URDF");
    let seed = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8];
    let (_, p0) = panda_robot.tool_pose(&seed).expect("7 joints");
    let circle_spec = CartesianSpec {
        circle: Some(CircleSpec {
            center: [p0.x, p0.y + 0.1, p0.z],
            radius: 0.1,
            normal: [0.0, 0.3, 1.0],
            semi_minor: None,
            major_axis: Some([0.0, -1.0, 0.0]),
        }),
        samples: 0,
        seed: seed.to_vec(),
        ..CartesianSpec::default()
    };
    let circle = circle_spec
        .joint_path(&panda_robot, Path::new("."))
        .expect("the circle is reachable");
    println!(
        "panda_circle_10um_f64: {} waypoints",
        circle.geometry.samples
    );
    let (ctl, samples) = arm::<7>("panda/panda.urdf", "panda_hand_tcp", circle.waypoints);
    bench_arm::<7>(&mut g, "panda_circle_10um_f64", &ctl, &samples);
    let circle_points = circle_spec
        .path(Path::new("."))
        .expect("valid path")
        .sample(128);
    let panda_chain = *panda.law().system();
    let rest = Some(SVector::from(seed));
    task_arm(
        &mut g,
        "panda_task_f64",
        panda_chain,
        &circle_points,
        rest,
        None,
        &samples,
    );
    task_arm(
        &mut g,
        "panda_task_f32",
        panda_chain.cast::<f32>(),
        &circle_points,
        rest,
        None,
        &samples,
    );
    let panda_held = panda_robot.tool_pose(&seed).expect("7 joints").0;
    task_arm(
        &mut g,
        "panda_task_held_f64",
        panda_chain,
        &circle_points,
        rest,
        Some(panda_held),
        &samples,
    );

    // f32: the same chains and contours in single precision.
    f32_arm(&mut g, "ur5_f32", &ur5, &ur5_samples);
    f32_arm(&mut g, "panda_f32", &panda, &panda_samples);
    g.finish();
}

fn f32_arm<const N: usize>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    ctl: &ArmControllerN<N>,
    samples: &[(JointSpace<f64, N>, SVector<f64, N>)],
) {
    let law = ctl.law();
    let chain = law.system().cast::<f32>();
    let kinds = chain.kinds();
    let JointContour::Spline(spline) = law.field().joint_contour() else {
        unreachable!("the bench's arms follow waypoints")
    };
    let pts: Vec<JointSpace<f32, N>> = spline
        .control_points()
        .iter()
        .map(|p| JointSpace::new(p.coords().map(|x| x as f32), kinds))
        .collect();
    let field = SuspendedField::new(
        PeriodicBSpline::<f32, JointSpace<f32, N>, N, 8>::from_control_slice(&pts, 1.0)
            .expect("valid"),
        JointNavigation::new(SVector::repeat(4.0f32), kinds).expect("valid"),
        ExponentialPacing::new(50.0f32).expect("valid"),
    );
    let law32 = PvfcLaw::new(
        chain,
        field,
        Flywheel::new(1.0f32, 40.0).expect("valid"),
        1.0,
    )
    .expect("valid");
    let ctl32 = Controller::new(law32)
        .starting_at_rest(0.0)
        .with_gravity_compensation();
    let s32: Vec<_> = samples
        .iter()
        .map(|(q, v)| {
            (
                JointSpace::new(q.coords().map(|x| x as f32), kinds),
                v.map(|x| x as f32),
            )
        })
        .collect();
    g.bench_function(name, |b| {
        b.iter(|| {
            let mut c = ctl32;
            for (q, v) in &s32 {
                black_box(c.step(black_box(q), black_box(v), 1e-3).expect("valid"));
            }
        })
    });
}

/// The task-space field's control step (`pvfc_core::task_field`) of `chain` on the closed
/// path through `points` (a periodic B-spline on ℝ³, 0.1 of τ between points), with the
/// null-space pull towards `rest` and the tool's orientation held at `held`, if given,
/// through the recorded states.
fn task_arm<T: Real, const N: usize>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    chain: SerialChain<T, N>,
    points: &[nalgebra::Vector3<f64>],
    rest: Option<SVector<f64, N>>,
    held: Option<nalgebra::Matrix3<f64>>,
    samples: &[(JointSpace<f64, N>, SVector<f64, N>)],
) {
    let c = |x: f64| nalgebra::convert::<f64, T>(x);
    let pts: Vec<Rn<T, 3>> = points.iter().map(|p| Rn::new(p.cast::<T>())).collect();
    let path = PeriodicBSpline::<T, Rn<T, 3>, 3, 256>::through_slice(&pts, c(0.1)).expect("valid");
    let mut field = TaskSpaceField::new(
        chain,
        path,
        ExponentialPacing::new(c(50.0)).expect("valid"),
        c(4.0),
        c(0.01),
    )
    .expect("valid");
    if let Some(r) = rest {
        field = field.with_rest(r.cast::<T>(), c(2.0)).expect("valid");
    }
    if let Some(r) = held {
        field = field
            .with_orientation(r.cast::<T>(), c(4.0))
            .expect("valid");
    }
    let law = PvfcLaw::new(
        chain,
        field,
        Flywheel::new(c(1.0), c(40.0)).expect("valid"),
        c(10.0),
    )
    .expect("valid");
    let ctl = Controller::new(law)
        .starting_at_rest(T::zero())
        .with_gravity_compensation();
    let kinds = chain.kinds();
    let samples: Vec<(JointSpace<T, N>, SVector<T, N>)> = samples
        .iter()
        .map(|(q, v)| {
            (
                JointSpace::new(q.coords().cast::<T>(), kinds),
                v.cast::<T>(),
            )
        })
        .collect();
    let dt = c(DT);
    g.bench_function(name, |b| {
        b.iter(|| {
            let mut c = ctl;
            for (q, v) in &samples {
                black_box(c.step(black_box(q), black_box(v), dt).expect("valid"));
            }
        })
    });
}

criterion_group!(benches, serial_arm);
fn main() {
    machine::print_machine();
    let start = std::time::SystemTime::now();
    benches();
    Criterion::default().configure_from_args().final_summary();
    baseline::print_ratios(&["control_step_x1000"], start);
}
