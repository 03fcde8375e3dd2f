//! The C ABI called as C would call it: the step gives the same torque as the Rust
//! controller (UR5, SCARA, Panda), the steps allocate nothing (a counting global allocator),
//! and bad pointers are error codes with messages.
#![allow(unsafe_code)]

use pvfc_c::*;
use std::ffi::{CStr, CString};

#[path = "../../../tests/common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

const WAYPOINTS: [f64; 18] = [
    0.0, -1.2, 1.4, -1.8, -1.57, 0.0, //
    0.3, -1.0, 1.2, -1.7, -1.57, 0.2, //
    -0.2, -1.3, 1.5, -1.9, -1.57, -0.1,
];

fn last_error() -> String {
    // SAFETY: a valid C string owned by the library.
    unsafe { CStr::from_ptr(pvfc_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn controller(robot: *const pvfc_robot) -> *mut pvfc_controller {
    let mut s = pvfc_settings_default();
    s.energy = 40.0;
    s.self_pacing = 50.0;
    controller_with(robot, &s)
}

/// The controller of `robot` with settings `s` on the contour through [`WAYPOINTS`].
fn controller_with(robot: *const pvfc_robot, s: &pvfc_settings) -> *mut pvfc_controller {
    let mut ctl = std::ptr::null_mut();
    // SAFETY: valid arrays and handles.
    let status = unsafe {
        pvfc_controller_new_waypoints(
            robot,
            WAYPOINTS.as_ptr(),
            3,
            6,
            1.5,
            std::ptr::null(),
            0,
            s,
            &mut ctl,
        )
    };
    assert_eq!(status, pvfc_status::PVFC_OK, "{}", last_error());
    ctl
}

/// The robot of `models/{file}` with tip `tip`, through the C ABI.
fn open_robot(file: &str, tip: &str) -> *mut pvfc_robot {
    let path = CString::new(format!(
        "{}/../../models/{file}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let tip = CString::new(tip).unwrap();
    let mut robot = std::ptr::null_mut();
    // SAFETY: valid strings and out pointer.
    let status = unsafe {
        pvfc_robot_from_urdf_file(path.as_ptr(), std::ptr::null(), tip.as_ptr(), &mut robot)
    };
    assert_eq!(status, pvfc_status::PVFC_OK, "{}", last_error());
    robot
}

#[test]
fn the_steps_and_the_dynamics_allocate_nothing() {
    let robot = open_robot("ur5/ur5_robot.urdf", "tool0");
    let ctl = controller(robot);
    let mut q = [0.1, -1.1, 1.3, -1.7, -1.5, 0.1];
    let v = [0.2, -0.1, 0.05, 0.0, 0.1, -0.2];
    let (mut torque, mut held) = ([0.0; 6], [0.0; 6]);
    let mut d = pvfc_diagnostics::default();
    let mut options = pvfc_passive_options_default();
    let limit = [150.0, 150.0, 150.0, 28.0, 28.0, 28.0];
    options.torque_limit = limit.as_ptr();
    options.n = 6;
    let mut passive = std::ptr::null_mut();
    // SAFETY: valid handles and options.
    assert_eq!(
        unsafe { pvfc_passive_new(ctl, &options, &mut passive) },
        pvfc_status::PVFC_OK
    );
    let mut account = pvfc_energy_account::default();
    let (mut m, mut cor, mut g) = ([0.0; 36], [0.0; 36], [0.0; 6]);
    let (mut rot, mut pos) = ([0.0; 9], [0.0; 3]);
    for k in 0..50 {
        let before = allocations();
        // SAFETY: arrays of 6, valid handles.
        let (a, b) = unsafe {
            (
                pvfc_controller_step(
                    ctl,
                    q.as_ptr(),
                    v.as_ptr(),
                    6,
                    1e-3,
                    torque.as_mut_ptr(),
                    6,
                    &mut d,
                ),
                pvfc_passive_step(
                    passive,
                    q.as_ptr(),
                    std::ptr::null(),
                    std::ptr::null(),
                    6,
                    1e-3,
                    held.as_mut_ptr(),
                    6,
                    &mut account,
                ),
            )
        };
        // SAFETY: arrays of the documented sizes, a valid handle.
        let c = unsafe {
            pvfc_robot_dynamics(
                robot,
                q.as_ptr(),
                v.as_ptr(),
                6,
                m.as_mut_ptr(),
                cor.as_mut_ptr(),
                g.as_mut_ptr(),
            )
        };
        // SAFETY: as above.
        let e = unsafe {
            pvfc_robot_tool_pose(robot, q.as_ptr(), 6, rot.as_mut_ptr(), pos.as_mut_ptr())
        };
        let allocated = allocations() - before;
        assert_eq!((c, e), (pvfc_status::PVFC_OK, pvfc_status::PVFC_OK));
        assert_eq!((a, b), (pvfc_status::PVFC_OK, pvfc_status::PVFC_OK));
        assert_eq!(allocated, 0, "step {k} allocated {allocated} times");
        q[0] += 1e-3;
    }
    // SAFETY: handles made above, freed once.
    unsafe {
        pvfc_passive_destroy(passive);
        pvfc_controller_destroy(ctl);
        pvfc_robot_destroy(robot);
    }
}

/// The thread's last error, read without allocating (a borrowed `&str`).
fn last_error_str<'a>() -> &'a str {
    // SAFETY: a valid C string owned by the library, read before the next pvfc call.
    unsafe { CStr::from_ptr(pvfc_last_error()) }
        .to_str()
        .unwrap_or("(not UTF-8)")
}

#[test]
fn the_real_time_functions_fail_without_allocating() {
    let robot = open_robot("ur5/ur5_robot.urdf", "tool0");
    let ctl = controller(robot);
    let mut options = pvfc_passive_options_default();
    let mut passive = std::ptr::null_mut();
    options.n = 0;
    // SAFETY: valid handles and options.
    assert_eq!(
        unsafe { pvfc_passive_new(ctl, &options, &mut passive) },
        pvfc_status::PVFC_OK
    );
    let q = [0.1, -1.1, 1.3, -1.7, -1.5, 0.1];
    let nan = [0.1, -1.1, f64::NAN, -1.7, -1.5, 0.1];
    let v = [2.0, -1.0, 0.5, 0.0, 1.0, -2.0];
    let (mut torque, mut m, mut rot, mut pos) = ([0.0; 6], [0.0; 35], [0.0; 9], [0.0; 3]);
    let (t, m, rot, pos) = (
        torque.as_mut_ptr(),
        m.as_mut_ptr(),
        rot.as_mut_ptr(),
        pos.as_mut_ptr(),
    );
    let null = std::ptr::null_mut::<f64>();
    let mut account = pvfc_energy_account::default();
    let account: *mut pvfc_energy_account = &mut account;
    // The controller's step at the velocity v, with what each case varies.
    let step = |ctl: *mut pvfc_controller, q: *const f64, n: usize, dt: f64, torque: *mut f64| {
        // SAFETY: q holds n doubles (or is NULL), torque has room for 6 (or is NULL), the
        // handle is live (or NULL), as each case says.
        unsafe { pvfc_controller_step(ctl, q, v.as_ptr(), n, dt, torque, 6, std::ptr::null_mut()) }
    };
    // Each case: the call, the status it must give, the message it must leave.
    type Call<'a> = Box<dyn FnMut() -> pvfc_status + 'a>;
    // SAFETY (every closure): the pointers are valid for the lengths given, or NULL where
    // the case says so; the handles are live.
    let cases: Vec<(&str, Call, pvfc_status, &str)> = vec![
        (
            "NaN in q",
            Box::new(|| step(ctl, nan.as_ptr(), 6, 1e-3, t)),
            pvfc_status::PVFC_ERROR_NON_FINITE,
            "q[2] is NaN",
        ),
        (
            "a wrong length",
            Box::new(|| step(ctl, q.as_ptr(), 5, 1e-3, t)),
            pvfc_status::PVFC_ERROR_WRONG_SIZE,
            "q: 5 entries for the 6-joint robot",
        ),
        (
            "no room for the torque",
            Box::new(|| step(ctl, q.as_ptr(), 6, 1e-3, null)),
            pvfc_status::PVFC_ERROR_NULL_POINTER,
            "torque_out: NULL pointer",
        ),
        (
            "dt = 0",
            Box::new(|| step(ctl, q.as_ptr(), 6, 0.0, t)),
            pvfc_status::PVFC_ERROR_INVALID_ARGUMENT,
            "dt: finite and > 0",
        ),
        (
            "a NULL controller",
            Box::new(|| step(std::ptr::null_mut(), q.as_ptr(), 6, 1e-3, t)),
            pvfc_status::PVFC_ERROR_NULL_POINTER,
            "ctl: NULL pointer",
        ),
        (
            "the internal states overflow (the law's own error)",
            Box::new(|| step(ctl, q.as_ptr(), 6, 1e300, t)),
            pvfc_status::PVFC_ERROR_NON_FINITE,
            "internal states overflowed",
        ),
        (
            "NaN in the passive step's q",
            Box::new(|| unsafe {
                pvfc_passive_step(
                    passive,
                    nan.as_ptr(),
                    std::ptr::null(),
                    std::ptr::null(),
                    6,
                    1e-3,
                    t,
                    6,
                    account,
                )
            }),
            pvfc_status::PVFC_ERROR_NON_FINITE,
            "q[2] is NaN",
        ),
        (
            "no room for M",
            Box::new(|| unsafe { pvfc_robot_inertia(robot, q.as_ptr(), 6, m, 35) }),
            pvfc_status::PVFC_ERROR_WRONG_SIZE,
            "m_out: room for 35 entries, the 6-joint robot's matrix has 36",
        ),
        (
            "NaN in the tool pose's q",
            Box::new(|| unsafe { pvfc_robot_tool_pose(robot, nan.as_ptr(), 6, rot, pos) }),
            pvfc_status::PVFC_ERROR_NON_FINITE,
            "q[2] is NaN",
        ),
    ];
    for (what, mut call, status, message) in cases {
        let before = allocations();
        let got = call();
        let error = last_error_str();
        let allocated = allocations() - before;
        assert_eq!(got, status, "{what}: {error}");
        assert!(error.contains(message), "{what}: the message is {error:?}");
        assert_eq!(
            allocated, 0,
            "{what}: the error allocated {allocated} times"
        );
    }
    // SAFETY: handles made above, freed once.
    unsafe {
        pvfc_passive_destroy(passive);
        pvfc_controller_destroy(ctl);
        pvfc_robot_destroy(robot);
    }
}

#[test]
fn bad_pointers_and_sizes_are_codes_with_messages() {
    let robot = open_robot("ur5/ur5_robot.urdf", "tool0");
    let ctl = controller(robot);
    let q = [0.0; 6];
    let mut t = [0.0; 6];
    // SAFETY: the pointers are valid or NULL, as each case says.
    unsafe {
        let s = pvfc_controller_step(
            ctl,
            q.as_ptr(),
            std::ptr::null(),
            6,
            1e-3,
            t.as_mut_ptr(),
            6,
            std::ptr::null_mut(),
        );
        assert_eq!(s, pvfc_status::PVFC_ERROR_NULL_POINTER);
        assert!(last_error().contains("qdot"), "{}", last_error());
        let s = pvfc_controller_step(
            ctl,
            q.as_ptr(),
            q.as_ptr(),
            7,
            1e-3,
            t.as_mut_ptr(),
            6,
            std::ptr::null_mut(),
        );
        assert_eq!(s, pvfc_status::PVFC_ERROR_WRONG_SIZE);
        assert!(last_error().contains("7 entries"), "{}", last_error());
        let s = pvfc_robot_from_urdf_string(
            c"<robot".as_ptr(),
            c"bad.urdf".as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            &mut std::ptr::null_mut(),
        );
        assert_eq!(s, pvfc_status::PVFC_ERROR_URDF);
        assert!(last_error().contains("bad.urdf"), "{}", last_error());
        // The last error is per thread.
        let other = std::thread::spawn(last_error).join().unwrap();
        assert_eq!(other, "");
        pvfc_controller_destroy(ctl);
        pvfc_robot_destroy(robot);
    }
}

/// Steps the C controller and the Rust one on `urdf` (tip `tip`) through the contour
/// `waypoints` (row-major) from `(q, v)`, moving `q` a little each step: the torques agree
/// bit for bit.
fn agree(urdf: &str, tip: &str, waypoints: &[f64], q: Vec<f64>, v: Vec<f64>) {
    agree_with(urdf, tip, waypoints, (q, v), pvfc_settings_default(), None);
}

/// [`agree`] with the settings `s`, which the Rust side reads as `pace` besides the defaults.
fn agree_with(
    urdf: &str,
    tip: &str,
    waypoints: &[f64],
    (mut q, v): (Vec<f64>, Vec<f64>),
    s: pvfc_settings,
    pace: Option<pvfc_control::model::pace::PaceSettings>,
) {
    let n = q.len();
    let robot = open_robot(urdf, tip);
    let mut ctl = std::ptr::null_mut();
    // SAFETY: valid arrays and out pointers.
    unsafe {
        assert_eq!(
            pvfc_controller_new_waypoints(
                robot,
                waypoints.as_ptr(),
                waypoints.len() / n,
                n,
                1.5,
                std::ptr::null(),
                0,
                &s,
                &mut ctl
            ),
            pvfc_status::PVFC_OK,
            "{}",
            last_error()
        );
    }
    let (r, settings) = rust_side(urdf, tip, waypoints, n, &s, pace);
    let mut rust = pvfc_control::model::arm::ArmController::new(&r, &settings).unwrap();
    let mut torque = vec![0.0; n];
    for k in 0..30 {
        let expected = rust.step(&q, &v, 1e-3).unwrap();
        // SAFETY: arrays of n, a valid handle.
        let st = unsafe {
            pvfc_controller_step(
                ctl,
                q.as_ptr(),
                v.as_ptr(),
                n,
                1e-3,
                torque.as_mut_ptr(),
                n,
                std::ptr::null_mut(),
            )
        };
        assert_eq!(st, pvfc_status::PVFC_OK);
        assert_eq!(torque, expected.torque, "{urdf}, step {k}");
        q[0] += 1e-3;
    }
    // SAFETY: handles made above, freed once.
    unsafe {
        pvfc_controller_destroy(ctl);
        pvfc_robot_destroy(robot);
    }
}

/// The Rust side of [`agree_with`]: the robot of `models/{urdf}` and the settings of `s`
/// (as the C ABI reads them) on the contour through `waypoints` (`n` joints), with `pace`.
fn rust_side(
    urdf: &str,
    tip: &str,
    waypoints: &[f64],
    n: usize,
    s: &pvfc_settings,
    pace: Option<pvfc_control::model::pace::PaceSettings>,
) -> (
    pvfc_control::model::robot::Robot,
    pvfc_control::model::arm::ArmSettings,
) {
    let r = pvfc_control::model::robot::Robot::from_urdf(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../models")
            .join(urdf),
        None,
        Some(tip),
    )
    .unwrap();
    let settings = pvfc_control::model::arm::ArmSettings {
        contour: pvfc_control::model::arm::JointContourSpec::Waypoints {
            points: waypoints.chunks(n).map(<[f64]>::to_vec).collect(),
            spacing: 1.5,
        },
        field: pvfc_control::model::arm_field::FieldSpec::Joint,
        h: vec![1.0; n],
        self_pacing: s.self_pacing,
        energy: s.energy,
        flywheel_inertia: s.flywheel_inertia,
        gamma: s.gamma,
        coupling_rate: (s.coupling_rate != 0.0).then_some(s.coupling_rate),
        gravity_compensation: s.gravity_compensation,
        friction_compensation: None,
        friction_band: 0.0,
        nominal_speed: None,
        nominal_speed_integral: 0.0,
        tau0: 0.0,
        field_energy_bound: None,
        obstacles: None,
        pace,
    };
    (r, settings)
}

/// The torque the model misses, learned beside the C ABI's passive controller
/// (`pvfc_passive_options.pace_learning_miss`) on its controller's pace, is the Rust passive
/// controller's with the same options: the same torques, step for step.
#[test]
fn the_c_passive_controller_learns_the_missed_torque_as_rusts() {
    use pvfc_control::model::arm::{ArmController, PassiveOptions};
    use pvfc_control::model::pace::{PaceLearningSpec, PaceSettings, PathSpeed};
    let limits = [150.0, 150.0, 150.0, 28.0, 28.0, 28.0];
    let mut s = pvfc_settings_default();
    s.pace_speed = 0.6;
    s.pace_torque_limit = limits.as_ptr();
    s.pace_torque_limit_len = limits.len();
    let pace = PaceSettings {
        speed: Some(PathSpeed::Joint(0.6)),
        torque_limit: limits.to_vec(),
        headroom: 0.8,
        level: 1.0,
    };
    let robot = open_robot("ur5/ur5_robot.urdf", "tool0");
    let ctl = controller_with(robot, &s);
    let mut p = std::ptr::null_mut();
    let mut o = pvfc_passive_options_default();
    o.torque_limit = limits.as_ptr();
    o.n = 6;
    o.pace_learning_target = 1.0;
    o.pace_learning_miss = 0.5;
    // SAFETY: valid options and out pointer.
    unsafe {
        let st = pvfc_passive_new(ctl, &o, &mut p);
        assert_eq!(st, pvfc_status::PVFC_OK, "{}", last_error());
    }
    let (r, settings) = rust_side("ur5/ur5_robot.urdf", "tool0", &WAYPOINTS, 6, &s, Some(pace));
    let options = PassiveOptions {
        torque_limit: Some(limits.to_vec()),
        pace_learning: Some(PaceLearningSpec {
            target: 1.0,
            fall: 0.3,
            rise: 0.1,
            slope: 0.03,
            floor: 0.2,
            miss: 0.5,
        }),
        ..PassiveOptions::default()
    };
    let ctl_rust = ArmController::new(&r, &settings).unwrap();
    let mut rust = ctl_rust.passive(&options, &settings).unwrap();
    assert!(rust.learns_miss());
    let (mut q, v) = (WAYPOINTS[..6].to_vec(), vec![0.1; 6]);
    let mut torque = vec![0.0; 6];
    for k in 0..30 {
        let expected = rust.step(&q, Some(&v), None, 1e-3).unwrap();
        // SAFETY: arrays of 6, a valid handle.
        let st = unsafe {
            pvfc_passive_step(
                p,
                q.as_ptr(),
                v.as_ptr(),
                std::ptr::null(),
                6,
                1e-3,
                torque.as_mut_ptr(),
                6,
                std::ptr::null_mut(),
            )
        };
        assert_eq!(st, pvfc_status::PVFC_OK, "{}", last_error());
        assert_eq!(torque, expected.torque, "step {k}");
        q[0] += 1e-4;
    }
    // SAFETY: handles made above, freed once.
    unsafe {
        pvfc_passive_destroy(p);
        pvfc_controller_destroy(ctl);
        pvfc_robot_destroy(robot);
    }
}

/// The pace of `pvfc_settings` (a joint speed asked for, bounded by the drives' limits) is the
/// Rust controller's `ArmSettings::pace`, step for step; a wrong number of limits or a bad
/// speed is a named error.
#[test]
fn the_c_pace_is_the_rust_controllers() {
    let limits = [60.0, 60.0, 30.0, 5.0, 5.0, 5.0];
    let mut s = pvfc_settings_default();
    s.pace_speed = 0.6;
    s.pace_torque_limit = limits.as_ptr();
    s.pace_torque_limit_len = limits.len();
    let pace = pvfc_control::model::pace::PaceSettings {
        speed: Some(pvfc_control::model::pace::PathSpeed::Joint(0.6)),
        torque_limit: limits.to_vec(),
        headroom: 0.8,
        level: 1.0,
    };
    agree_with(
        "ur5/ur5_robot.urdf",
        "tool0",
        &WAYPOINTS,
        (
            vec![0.1, -1.1, 1.3, -1.7, -1.5, 0.1],
            vec![0.2, -0.1, 0.05, 0.0, 0.1, -0.2],
        ),
        s,
        Some(pace),
    );
    let robot = open_robot("ur5/ur5_robot.urdf", "tool0");
    let mut ctl = std::ptr::null_mut();
    let new = |s: &pvfc_settings, ctl: &mut *mut pvfc_controller| {
        // SAFETY: valid arrays and out pointers.
        unsafe {
            pvfc_controller_new_waypoints(
                robot,
                WAYPOINTS.as_ptr(),
                WAYPOINTS.len() / 6,
                6,
                1.5,
                std::ptr::null(),
                0,
                s,
                ctl,
            )
        }
    };
    s.pace_torque_limit_len = 5;
    assert_ne!(new(&s, &mut ctl), pvfc_status::PVFC_OK);
    assert!(
        last_error().contains("pace_torque_limit"),
        "{}",
        last_error()
    );
    s.pace_torque_limit_len = 6;
    s.pace_speed = -1.0;
    assert_ne!(new(&s, &mut ctl), pvfc_status::PVFC_OK);
    assert!(last_error().contains("pace.speed"), "{}", last_error());
    assert!(ctl.is_null());
    // SAFETY: made above, freed once.
    unsafe { pvfc_robot_destroy(robot) };
}

#[test]
fn the_c_step_agrees_with_rust_on_the_ur5_the_scara_and_the_panda() {
    agree(
        "ur5/ur5_robot.urdf",
        "tool0",
        &WAYPOINTS,
        vec![0.1, -1.1, 1.3, -1.7, -1.5, 0.1],
        vec![0.2, -0.1, 0.05, 0.0, 0.1, -0.2],
    );
    agree(
        "scara.urdf",
        "tool",
        &[0.0, 1.0, 1.0, 0.0, 0.0, -1.0, -1.0, 0.0],
        vec![0.1, 0.9],
        vec![0.1, -0.2],
    );
    agree(
        "panda/panda.urdf",
        "panda_hand_tcp",
        &[
            0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8, //
            0.4, -0.1, 0.2, -2.0, 0.2, 2.1, 1.0, //
            0.7, -0.4, 0.3, -1.8, 0.1, 1.8, 1.2,
        ],
        vec![0.1, -0.2, 0.1, -2.1, 0.1, 2.0, 0.9],
        vec![0.1, 0.0, -0.1, 0.2, 0.0, 0.1, 0.0],
    );
}

#[test]
fn pvfc_version_and_the_header_constants_are_the_crate_version() {
    // SAFETY: a static C string.
    let v = unsafe { CStr::from_ptr(pvfc_version()) }.to_str().unwrap();
    assert_eq!(v, env!("CARGO_PKG_VERSION"));
    let header = format!("{PVFC_VERSION_MAJOR}.{PVFC_VERSION_MINOR}.{PVFC_VERSION_PATCH}");
    assert_eq!(
        header,
        env!("CARGO_PKG_VERSION"),
        "PVFC_VERSION_* are not the crate's version"
    );
}
