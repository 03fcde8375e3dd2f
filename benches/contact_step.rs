//! One contact step: an RKMK4 step of the closed loop (Fig. 6's controller, the wall scenario)
//! with the contact forces from Rapier at every stage — four placements of the colliders and
//! runs of Rapier's collision pipeline, four evaluations of the contact law and of the control
//! law — from a state where the tool presses on the wall. Also one contact query alone.

#[path = "common/baseline.rs"]
mod baseline;
#[path = "common/machine.rs"]
mod machine;

use criterion::{criterion_group, Criterion};
use nalgebra::Vector2;
use pvfc::core::prelude::*;
use pvfc::sim::contact::{ContactWorld, Environment};
use pvfc::sim::run::simulate;
use pvfc::sim::scenario::presets;
use pvfc::sim::ClosedLoop;
use std::hint::black_box;

fn contact_step(c: &mut Criterion) {
    let mut s = presets::contact_wall();
    s.duration = 2.0;
    s.baseline = None;
    // A state in contact, from a run: the tool presses on the wall at t = 2 s.
    let run = simulate(&s, &mut |_| {}).expect("the wall scenario runs");
    let k = run.len() - 1;
    assert!(run.contact.as_ref().expect("contact columns").depth[k] > 0.0);
    let st = AugmentedState {
        q: Torus::new(Vector2::from_column_slice(&run.q[k])),
        v: Vector2::from_column_slice(&run.v[k]),
        tau: run.tau[k],
        tau_dot: run.tau_dot[k],
        flywheel_speed: run.flywheel_speed[k],
    };
    let arm = s.scara().expect("arm");
    let sys = ClosedLoop {
        plant: Scara::new(arm).expect("arm"),
        controller: s.controller().expect("controller"),
    };
    let mut world = ContactWorld::new(s.contact.as_ref().expect("contact"), &arm).expect("world");
    let h = 1e-4;
    let mut g = c.benchmark_group("contact");
    baseline::scara_step_baseline(&mut g);
    g.bench_function("rk4_step_with_contact", |b| {
        b.iter(|| {
            let st = black_box(&st);
            let f = world.contact(2.0, &st.q, &st.v).expect("finite");
            let k1 = sys.derivative(st, &f.torque).expect("finite");
            sys.rk4_with_stages(st, &k1, h, |_, c, x| {
                let f = world.contact(2.0 + c, &x.q, &x.v)?;
                Ok::<_, pvfc::sim::SimError>(sys.derivative(x, &f.torque)?)
            })
            .expect("finite")
        })
    });
    g.bench_function("contact_query", |b| {
        b.iter(|| {
            world
                .contact(2.0, black_box(&st.q), black_box(&st.v))
                .expect("finite")
        })
    });
    g.finish();
}

/// The same for a URDF arm in 3-D: one RKMK4 step of the UR5's closed loop
/// (`scenarios/ur5_press.toml`: gravity, its compensation, the tool pressing on the box) with
/// the 3-D contact (`contact::spatial`) at every stage. The target: ≤ 20 µs.
fn spatial_contact_step(c: &mut Criterion) {
    use nalgebra::SVector;
    use pvfc::sim::contact::spatial::SpatialWorld;
    use pvfc::sim::scenario::Scenario;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/ur5_press.toml");
    let mut s = Scenario::from_file(&path).expect("the deburring scenario parses");
    s.duration = 3.0;
    let run = simulate(&s, &mut |_| {}).expect("the deburring scenario runs");
    let k = run.len() - 1;
    assert!(run.contact.as_ref().expect("contact columns").depth[k] > 0.0);
    let robot = s.robot().expect("robot");
    let chain =
        pvfc::core::mechanics::SerialChain::<f64, 6>::try_from(robot.model()).expect("6 joints");
    let ctl = pvfc::sim::model::arm::arm_controller(chain, &s.arm_settings().expect("settings"))
        .expect("controller");
    let sys = ClosedLoop::matched(ctl);
    let kinds = chain.kinds();
    let st = AugmentedState {
        q: JointSpace::new(SVector::<f64, 6>::from_column_slice(&run.q[k]), kinds),
        v: SVector::<f64, 6>::from_column_slice(&run.v[k]),
        tau: run.tau[k],
        tau_dot: run.tau_dot[k],
        flywheel_speed: run.flywheel_speed[k],
    };
    let world =
        SpatialWorld::new(s.contact_3d.as_ref().expect("contact_3d"), &robot).expect("world");
    let force = |x: &AugmentedState<f64, JointSpace<f64, 6>, 6>| -> Result<SVector<f64, 6>, pvfc::sim::SimError> {
        let c = world.contact(2.0, x.q.coords().as_slice(), x.v.as_slice())?;
        Ok(SVector::from_column_slice(&c.torque))
    };
    let h = 1e-4;
    let mut g = c.benchmark_group("contact_3d");
    baseline::scara_step_baseline(&mut g);
    g.bench_function("ur5_rk4_step_with_contact", |b| {
        b.iter(|| {
            let st = black_box(&st);
            let k1 = sys
                .derivative(st, &force(st).expect("finite"))
                .expect("finite");
            sys.rk4_with_stages(st, &k1, h, |_, _, x| {
                Ok::<_, pvfc::sim::SimError>(sys.derivative(x, &force(x)?)?)
            })
            .expect("finite")
        })
    });
    g.bench_function("ur5_rk4_step_free", |b| {
        b.iter(|| {
            sys.rk4_step(black_box(&st), h, &SVector::zeros())
                .expect("finite")
        })
    });
    g.bench_function("ur5_contact_query", |b| {
        b.iter(|| force(black_box(&st)).expect("finite"))
    });
    // The arm with the URDF's collision meshes as convex hulls (`arm = "urdf"`): the push
    // scenario (`scenarios/ur5_push.toml`) at t = 7.3 s, the ball pressing on the forearm's
    // hull; 7 hulls and the tool ball against the ball.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/ur5_push.toml");
    let mut push = Scenario::from_file(&path).expect("the push scenario parses");
    push.duration = 7.3;
    push.baseline = None;
    let run = simulate(&push, &mut |_| {}).expect("the push scenario runs");
    let k = run.len() - 1;
    assert!(run.contact.as_ref().expect("contact columns").depth[k] > 0.0);
    let pst = AugmentedState {
        q: JointSpace::new(SVector::<f64, 6>::from_column_slice(&run.q[k]), kinds),
        v: SVector::<f64, 6>::from_column_slice(&run.v[k]),
        tau: run.tau[k],
        tau_dot: run.tau_dot[k],
        flywheel_speed: run.flywheel_speed[k],
    };
    let hull_world = SpatialWorld::new_in(
        push.contact_3d.as_ref().expect("contact_3d"),
        &robot,
        &push.base_dir,
    )
    .expect("world with hulls");
    let hull_force = |x: &AugmentedState<f64, JointSpace<f64, 6>, 6>| -> Result<SVector<f64, 6>, pvfc::sim::SimError> {
        let c = hull_world.contact(7.3, x.q.coords().as_slice(), x.v.as_slice())?;
        Ok(SVector::from_column_slice(&c.torque))
    };
    g.bench_function("ur5_push_rk4_step_with_contact_hulls", |b| {
        b.iter(|| {
            let st = black_box(&pst);
            let k1 = sys
                .derivative(st, &hull_force(st).expect("finite"))
                .expect("finite");
            sys.rk4_with_stages(st, &k1, h, |_, _, x| {
                Ok::<_, pvfc::sim::SimError>(sys.derivative(x, &hull_force(x)?)?)
            })
            .expect("finite")
        })
    });
    g.bench_function("ur5_push_contact_query_hulls", |b| {
        b.iter(|| hull_force(black_box(&pst)).expect("finite"))
    });
    g.finish();
}

criterion_group!(benches, contact_step, spatial_contact_step);
fn main() {
    machine::print_machine();
    let start = std::time::SystemTime::now();
    benches();
    Criterion::default().configure_from_args().final_summary();
    baseline::print_ratios(&["contact", "contact_3d"], start);
}
