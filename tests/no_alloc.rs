//! A control step allocates nothing: a counting global allocator, counting only this thread.
#![allow(unsafe_code)]

use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc::prelude::*;
use pvfc::sim::scenario::presets::pelican_example;
#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

#[test]
fn the_counter_sees_allocations() {
    let before = allocations();
    let v = std::hint::black_box(vec![1u8; 64]);
    assert!(allocations() > before, "the counting allocator works");
    drop(v);
}

#[test]
fn a_control_step_does_not_allocate() {
    let mut scara = pelican_example().controller().unwrap();
    let mut q = Torus::new(Vector2::new(0.1, -0.2));
    let v = Vector2::new(0.3, 0.1);

    let field = SuspendedField::new(
        ConstantRate::new(So3::<f64>::identity(), Vector3::new(0.0, 0.3, 0.6)).unwrap(),
        So3Navigation::new(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))).unwrap(),
        ExponentialPacing::new(20.0).unwrap(),
    );
    let law = PvfcLaw::new(
        RigidBody::new(Matrix3::from_diagonal(&Vector3::new(0.8, 1.2, 1.5))).unwrap(),
        field,
        Flywheel::new(1.0, 20.0).unwrap(),
        0.1,
    )
    .unwrap();
    let mut body = Controller::new(law).starting_at_rest(0.0);
    let r = So3::exp(&Vector3::new(0.3, 0.2, 0.1));
    let w = Vector3::new(0.1, 0.0, -0.2);

    let field32 = SuspendedField::new(
        Lissajous::<f32, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0f32, 1.0)).unwrap(),
        ExponentialPacing::new(100.0f32).unwrap(),
    );
    let law32 = PvfcLaw::new(
        Scara::<f32>::pelican(),
        field32,
        Flywheel::new(1.0f32, 50.0).unwrap(),
        0.05,
    )
    .unwrap();
    let mut scara32 = Controller::new(law32)
        .starting_at_rest(0.0)
        .with_nominal_speed(NominalSpeed::new(0.01f32, 1.0).unwrap())
        .with_friction_compensation(FrictionCompensation::new(Vector2::new(2.0f32, 3.0)).unwrap());

    let before = allocations();
    for _ in 0..1000 {
        let out = scara.step(&q, &v, 1e-3).unwrap();
        q = q.retract(&v, 1e-3);
        std::hint::black_box(out);
        std::hint::black_box(body.step(&r, &w, 1e-3).unwrap());
        std::hint::black_box(
            scara32
                .step(
                    &Torus::new(Vector2::new(0.1f32, 0.2)),
                    &Vector2::new(0.3f32, 0.0),
                    1e-3,
                )
                .unwrap(),
        );
        // The error path does not allocate either.
        std::hint::black_box(
            scara
                .step(&Torus::new(Vector2::new(f64::NAN, 0.0)), &v, 1e-3)
                .unwrap_err(),
        );
    }
    assert_eq!(allocations() - before, 0, "control steps allocated");
}

/// The UR5 (6 joints) and the Panda (7), f64 and f32: a control step allocates nothing.
#[test]
fn a_serial_arm_control_step_does_not_allocate() {
    use nalgebra::SVector;
    use pvfc_sim::urdf::ChainDescription;
    let models = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let ur5 = ChainDescription::from_file(&models.join("ur5/ur5_robot.urdf"), None, Some("tool0"))
        .unwrap()
        .chain::<6>()
        .unwrap();
    let panda = ChainDescription::from_file(
        &models.join("panda/panda.urdf"),
        None,
        Some("panda_hand_tcp"),
    )
    .unwrap()
    .chain::<7>()
    .unwrap();

    type Arm<T, const N: usize> = Controller<
        T,
        JointSpace<T, N>,
        SerialChain<T, N>,
        SuspendedField<
            T,
            JointSpace<T, N>,
            PeriodicBSpline<T, JointSpace<T, N>, N, 8>,
            JointNavigation<T, N>,
            ExponentialPacing<T>,
            N,
        >,
        N,
    >;
    fn controller<T: Real, const N: usize>(chain: SerialChain<T, N>) -> Arm<T, N> {
        let kinds = chain.kinds();
        let pts: [JointSpace<T, N>; 5] = core::array::from_fn(|k| {
            JointSpace::new(
                SVector::from_fn(|i, _| pvfc_core::scalar::cast((0.3 * (k + i) as f64).sin())),
                kinds,
            )
        });
        let field = SuspendedField::new(
            PeriodicBSpline::through_slice(&pts, T::one()).unwrap(),
            JointNavigation::new(SVector::repeat(pvfc_core::scalar::cast(2.0)), kinds).unwrap(),
            ExponentialPacing::new(pvfc_core::scalar::cast(20.0)).unwrap(),
        );
        let law = PvfcLaw::new(
            chain,
            field,
            Flywheel::new(T::one(), pvfc_core::scalar::cast(40.0)).unwrap(),
            T::one(),
        )
        .unwrap();
        Controller::new(law)
            .starting_at_rest(T::zero())
            .with_gravity_compensation()
            .with_friction_compensation(
                FrictionCompensation::new(SVector::repeat(pvfc_core::scalar::cast(0.5)))
                    .unwrap()
                    .with_band(pvfc_core::scalar::cast(0.01))
                    .unwrap(),
            )
    }
    let mut c6 = controller(ur5);
    let mut c7 = controller(panda);
    let mut c6f = controller(ur5.cast::<f32>());
    let mut c7f = controller(panda.cast::<f32>());
    let (k6, k7) = (ur5.kinds(), panda.kinds());
    let before = allocations();
    for i in 0..1000 {
        let x = 0.001 * i as f64;
        let q6 = JointSpace::new(SVector::repeat(x), k6);
        let q7 = JointSpace::new(SVector::repeat(x), k7);
        std::hint::black_box(c6.step(&q6, &SVector::repeat(0.1), 1e-3).unwrap());
        std::hint::black_box(c7.step(&q7, &SVector::repeat(0.1), 1e-3).unwrap());
        let q6f = JointSpace::new(SVector::repeat(x as f32), k6);
        let q7f = JointSpace::new(SVector::repeat(x as f32), k7);
        std::hint::black_box(c6f.step(&q6f, &SVector::repeat(0.1f32), 1e-3).unwrap());
        std::hint::black_box(c7f.step(&q7f, &SVector::repeat(0.1f32), 1e-3).unwrap());
        // The error path does not allocate either.
        let nan = JointSpace::new(SVector::repeat(f64::NAN), k6);
        std::hint::black_box(c6.step(&nan, &SVector::zeros(), 1e-3).unwrap_err());
    }
    assert_eq!(
        allocations() - before,
        0,
        "serial-arm control steps allocated"
    );
}

/// The passive digital controller's step (positions only, limits, encoder charge) allocates
/// nothing, nor does its error path.
#[test]
fn a_passive_control_step_does_not_allocate() {
    let scara = pelican_example().controller().unwrap();
    let mut ctl = pvfc::core::passive::PassiveController::new(scara)
        .with_torque_limits(Vector2::new(20.0, 10.0))
        .unwrap()
        .with_encoder_resolution(Vector2::new(1e-5, 1e-5))
        .unwrap()
        .with_velocity_filter(2e-3)
        .unwrap();
    let mut q = Torus::new(Vector2::new(0.1, -0.2));
    let v = Vector2::new(0.3, 0.1);
    let before = allocations();
    for _ in 0..1000 {
        std::hint::black_box(ctl.step(&q, None, None, 1e-3).unwrap());
        q = q.retract(&v, 1e-3);
        std::hint::black_box(
            ctl.step(&Torus::new(Vector2::new(f64::NAN, 0.0)), None, None, 1e-3)
                .unwrap_err(),
        );
    }
    assert_eq!(allocations() - before, 0, "passive control steps allocated");
}
