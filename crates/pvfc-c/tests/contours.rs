//! Contours and dynamics through the C ABI: a Cartesian path (joint contour and task-space
//! field) agrees bit for bit with the same scenario built in Rust; the polygon and circle
//! constructors give the paths their TOML tables give; the joint contours are their formulas;
//! the joint contour of a Cartesian path stays within its tolerance of the path (forward
//! kinematics and the distance, both through the ABI); the dynamics equal the Rust model's and
//! satisfy `rnea = M a + C v + g`; bad input is a code that names the argument.

#![allow(unsafe_code)]
use pvfc_c::*;
use pvfc_control::model::cartesian::TaskSpec;
use pvfc_sim::scenario::Scenario;
use std::ffi::{CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};

const OK: pvfc_status = pvfc_status::PVFC_OK;

fn last_error() -> String {
    // SAFETY: a valid C string owned by the library.
    unsafe { CStr::from_ptr(pvfc_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn ur5() -> *mut pvfc_robot {
    let path = CString::new(repo().join("models/ur5/ur5_robot.urdf").to_str().unwrap()).unwrap();
    let tip = CString::new("tool0").unwrap();
    let mut robot = null_mut();
    // SAFETY: valid strings and out pointer.
    let status =
        unsafe { pvfc_robot_from_urdf_file(path.as_ptr(), null(), tip.as_ptr(), &mut robot) };
    assert_eq!(status, OK, "{}", last_error());
    robot
}

/// `scenarios/ur5_cartesian.toml`, with the task-space field or not, at navigation weights
/// 4 (the file's 16 ask more than its `Ē` at the states off the contour these tests step
/// from).
fn scenario(task: bool) -> Scenario {
    let mut s = Scenario::from_file(&repo().join("scenarios/ur5_cartesian.toml")).unwrap();
    s.controller.h = vec![4.0; 6];
    if task {
        s.contour.cartesian_mut().unwrap().task = Some(TaskSpec::default());
    }
    s
}

/// The scenario's controller settings as the C struct.
fn settings(s: &Scenario, friction: &[f64]) -> pvfc_settings {
    let c = &s.controller;
    let mut out = pvfc_settings_default();
    out.self_pacing = c.self_pacing;
    out.energy = c.energy;
    out.flywheel_inertia = c.flywheel_inertia;
    out.gamma = c.gamma;
    out.coupling_rate = c.coupling_rate.unwrap_or(0.0);
    out.gravity_compensation = c.gravity_compensation.unwrap_or(true);
    out.friction_compensation = friction.as_ptr();
    out.friction_compensation_len = friction.len();
    out.friction_band = c.friction_band.unwrap_or(0.0);
    let n = c.nominal_speed.unwrap();
    (out.nominal_speed_c, out.nominal_speed_r) = (n.c, n.r);
    out
}

/// The scenario's Cartesian path through `pvfc_contour_cartesian_toml`.
fn toml_contour(s: &Scenario) -> *mut pvfc_contour {
    let table = toml::to_string(s.contour.cartesian().unwrap()).unwrap();
    let table = CString::new(table).unwrap();
    let dir = CString::new(repo().join("scenarios").to_str().unwrap()).unwrap();
    let mut contour = null_mut();
    // SAFETY: valid strings and out pointer.
    let status = unsafe {
        pvfc_contour_cartesian_toml(
            table.as_ptr(),
            dir.as_ptr(),
            s.contour.period(),
            0.0,
            &mut contour,
        )
    };
    assert_eq!(status, OK, "{}", last_error());
    contour
}

fn controller(
    robot: *const pvfc_robot,
    contour: *const pvfc_contour,
    s: &Scenario,
) -> *mut pvfc_controller {
    let friction = s.controller.friction_compensation.clone().unwrap();
    let settings = settings(s, &friction);
    let mut ctl = null_mut();
    // SAFETY: valid handles, arrays and out pointer.
    let status = unsafe {
        pvfc_controller_new(
            robot,
            contour,
            s.controller.h.as_ptr(),
            s.controller.h.len(),
            &settings,
            &mut ctl,
        )
    };
    assert_eq!(status, OK, "{}", last_error());
    ctl
}

#[test]
fn a_cartesian_path_through_the_abi_is_the_scenarios_controller() {
    let robot = ur5();
    for task in [false, true] {
        let s = scenario(task);
        let mut rust = pvfc_control::model::arm::ArmController::new(
            &s.robot().unwrap(),
            &s.arm_settings().unwrap(),
        )
        .unwrap();
        let contour = toml_contour(&s);
        let ctl = controller(robot, contour, &s);
        let mut q = vec![0.05, -1.15, 1.35, -1.75, -1.5, 0.05];
        let v = vec![0.2, -0.1, 0.05, 0.0, 0.1, -0.2];
        let mut torque = [0.0; 6];
        for k in 0..40 {
            let expected = rust.step(&q, &v, 1e-3).unwrap();
            // SAFETY: arrays of 6, a valid handle.
            let st = unsafe {
                pvfc_controller_step(
                    ctl,
                    q.as_ptr(),
                    v.as_ptr(),
                    6,
                    1e-3,
                    torque.as_mut_ptr(),
                    6,
                    null_mut(),
                )
            };
            assert_eq!(st, OK, "{}", last_error());
            assert_eq!(torque.to_vec(), expected.torque, "task {task}, step {k}");
            q[1] += 2e-3;
        }
        // SAFETY: handles made above, freed once.
        unsafe {
            pvfc_controller_destroy(ctl);
            pvfc_contour_destroy(contour);
        }
    }
    // SAFETY: made above.
    unsafe { pvfc_robot_destroy(robot) };
}

/// The contour point of `ctl` at several `τ`.
fn points(ctl: *const pvfc_controller, period: f64) -> Vec<[f64; 6]> {
    (0..24)
        .map(|i| {
            let mut x = [0.0; 6];
            // SAFETY: room for 6.
            let st = unsafe {
                pvfc_controller_contour_point(ctl, period * i as f64 / 24.0, x.as_mut_ptr(), 6)
            };
            assert_eq!(st, OK, "{}", last_error());
            x
        })
        .collect()
}

#[test]
fn the_polygon_and_circle_constructors_give_the_paths_of_their_tables() {
    let robot = ur5();
    let s = scenario(false);
    let period = s.contour.period();
    let seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0];
    let mut o = pvfc_cartesian_options_default();
    o.seed = seed.as_ptr();
    o.seed_len = 6;
    o.fixed_orientation = true;
    let corners = [
        0.45, -0.15, 0.30, 0.65, -0.15, 0.30, 0.65, 0.20, 0.30, 0.45, 0.20, 0.30,
    ];
    let (mut polygon, mut circle, mut circle_toml) = (null_mut(), null_mut(), null_mut());
    let table = CString::new(
        "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\nfixed_orientation = true\n\
         circle = { center = [0.55, 0.0, 0.3], radius = 0.1, normal = [0.0, 0.0, 1.0] }\n",
    )
    .unwrap();
    // SAFETY: valid arrays, strings and out pointers.
    unsafe {
        assert_eq!(
            pvfc_contour_cartesian_polygon(corners.as_ptr(), 4, 0.03, period, &o, &mut polygon),
            OK,
            "{}",
            last_error()
        );
        let (center, normal) = ([0.55, 0.0, 0.3], [0.0, 0.0, 1.0]);
        assert_eq!(
            pvfc_contour_cartesian_circle(
                center.as_ptr(),
                normal.as_ptr(),
                0.1,
                null(),
                0.0,
                period,
                &o,
                &mut circle
            ),
            OK,
            "{}",
            last_error()
        );
        assert_eq!(
            pvfc_contour_cartesian_toml(table.as_ptr(), null(), period, 0.0, &mut circle_toml),
            OK,
            "{}",
            last_error()
        );
    }
    let with = |c| controller(robot, c, &s);
    let rectangle = toml_contour(&s);
    let (a, b) = (with(polygon), with(rectangle));
    assert_eq!(points(a, period), points(b, period));
    let (c, c2) = (with(circle), with(circle_toml));
    assert_eq!(points(c, period), points(c2, period));
    // The joint contour's tool position stays within the 10 µm tolerance of the exact path:
    // forward kinematics and the distance, through the ABI.
    for (ctl, contour) in [(a, polygon), (c, circle)] {
        let mut worst: f64 = 0.0;
        for i in 0..600 {
            let mut x = [0.0; 6];
            let (mut p, mut d) = ([0.0; 3], 0.0);
            // SAFETY: valid handles and room for the outputs.
            unsafe {
                let tau = period * i as f64 / 600.0;
                pvfc_controller_contour_point(ctl, tau, x.as_mut_ptr(), 6);
                assert_eq!(
                    pvfc_robot_tool_pose(robot, x.as_ptr(), 6, null_mut(), p.as_mut_ptr()),
                    OK
                );
                assert_eq!(
                    pvfc_contour_distance(contour, p.as_ptr(), &mut d, null_mut()),
                    OK
                );
            }
            worst = worst.max(d);
        }
        assert!(worst > 0.0 && worst <= 1e-5, "{worst}");
    }
    // The circle's distance from a point off its plane and radius.
    let (mut d, mut closest) = (0.0, [0.0; 3]);
    let p = [0.55 + 0.13, 0.0, 0.34];
    // SAFETY: valid handle and arrays.
    assert_eq!(
        unsafe { pvfc_contour_distance(circle, p.as_ptr(), &mut d, closest.as_mut_ptr()) },
        OK
    );
    assert!((d - 0.05).abs() < 1e-12, "{d}");
    assert!((closest[0] - 0.65).abs() < 1e-12 && closest[1].abs() < 1e-12);
    // SAFETY: handles made above, freed once.
    unsafe {
        for ctl in [a, b, c, c2] {
            pvfc_controller_destroy(ctl);
        }
        for contour in [polygon, rectangle, circle, circle_toml] {
            pvfc_contour_destroy(contour);
        }
        pvfc_robot_destroy(robot);
    }
}

#[test]
fn the_joint_contours_are_their_formulas() {
    let robot = ur5();
    let (a, t, phi, c) = (
        [0.2, 0.1, 0.15, 0.1, 0.05, 0.3],
        [4.0, 2.0, 4.0, 4.0, 2.0, 4.0],
        [0.0, 0.5, 1.0, 0.0, 0.0, 0.2],
        [0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
    );
    let (u, w) = (
        [0.1, 0.0, 0.1, 0.0, 0.0, 0.0],
        [0.0, 0.2, 0.0, 0.1, 0.0, 0.0],
    );
    let (mut lissajous, mut ellipse) = (null_mut(), null_mut());
    // SAFETY: arrays of 6, valid out pointers.
    unsafe {
        let st = pvfc_contour_lissajous(
            a.as_ptr(),
            t.as_ptr(),
            phi.as_ptr(),
            c.as_ptr(),
            6,
            4.0,
            &mut lissajous,
        );
        assert_eq!(st, OK, "{}", last_error());
        let st = pvfc_contour_ellipse(c.as_ptr(), u.as_ptr(), w.as_ptr(), 6, 3.0, &mut ellipse);
        assert_eq!(st, OK, "{}", last_error());
    }
    let s = pvfc_settings_default();
    for (contour, period) in [(lissajous, 4.0), (ellipse, 3.0)] {
        let mut ctl = null_mut();
        // SAFETY: valid handles.
        let st = unsafe { pvfc_controller_new(robot, contour, null(), 0, &s, &mut ctl) };
        assert_eq!(st, OK, "{}", last_error());
        for (k, x) in points(ctl, period).iter().enumerate() {
            let tau = period * k as f64 / 24.0;
            let two_pi = 2.0 * std::f64::consts::PI;
            for i in 0..6 {
                let expected = if period == 4.0 {
                    c[i] + a[i] * (two_pi * tau / t[i] + phi[i]).sin()
                } else {
                    let th = two_pi * tau / period;
                    c[i] + u[i] * th.cos() + w[i] * th.sin()
                };
                assert!(
                    (x[i] - expected).abs() < 1e-12,
                    "τ {tau}, joint {i}: {} vs {expected}",
                    x[i]
                );
            }
        }
        // SAFETY: made above.
        unsafe {
            pvfc_controller_destroy(ctl);
            pvfc_contour_destroy(contour);
        }
    }
    // SAFETY: made above.
    unsafe { pvfc_robot_destroy(robot) };
}

#[test]
fn the_dynamics_are_the_models_and_rnea_is_m_a_plus_c_v_plus_g() {
    let robot = ur5();
    let model = scenario(false).robot().unwrap();
    let q = [0.3, -1.1, 1.2, -0.7, -1.4, 0.5];
    let v = [0.4, -0.3, 0.2, 0.5, -0.6, 0.1];
    let acc = [1.0, -0.5, 0.3, 0.0, 2.0, -1.0];
    let (mut m, mut c, mut g) = ([0.0; 36], [0.0; 36], [0.0; 6]);
    let (mut m2, mut g2, mut tau) = ([0.0; 36], [0.0; 6], [0.0; 6]);
    // SAFETY: arrays of the documented sizes, a valid handle.
    unsafe {
        let p = (q.as_ptr(), v.as_ptr());
        assert_eq!(
            pvfc_robot_dynamics(
                robot,
                p.0,
                p.1,
                6,
                m.as_mut_ptr(),
                c.as_mut_ptr(),
                g.as_mut_ptr()
            ),
            OK
        );
        assert_eq!(pvfc_robot_inertia(robot, p.0, 6, m2.as_mut_ptr(), 36), OK);
        assert_eq!(pvfc_robot_gravity(robot, p.0, 6, g2.as_mut_ptr()), OK);
        assert_eq!(
            pvfc_robot_rnea(robot, p.0, p.1, acc.as_ptr(), 6, tau.as_mut_ptr()),
            OK
        );
    }
    let (mr, cr, gr) = (
        model.inertia(&q).unwrap(),
        model.coriolis(&q, &v).unwrap(),
        model.gravity(&q).unwrap(),
    );
    for i in 0..6 {
        // The one-pass dynamics and the separate algorithms (CRBA, the gravity pass) agree to
        // rounding; each function equals its Rust counterpart exactly.
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * (1.0 + b.abs());
        assert!(close(g[i], gr[i]), "{} vs {}", g[i], gr[i]);
        assert_eq!(g2[i], gr[i]);
        let mut expected = g[i];
        for j in 0..6 {
            assert!(close(m[6 * i + j], mr[(i, j)]), "M row-major");
            assert_eq!(c[6 * i + j], cr[(i, j)], "C row-major");
            assert_eq!(m2[6 * i + j], mr[(i, j)]);
            assert_eq!(m[6 * i + j], m[6 * j + i], "M symmetric");
            expected += m[6 * i + j] * acc[j] + c[6 * i + j] * v[j];
        }
        assert!(
            (tau[i] - expected).abs() < 1e-10 * (1.0 + expected.abs()),
            "{i}"
        );
    }
    // SAFETY: made above.
    unsafe { pvfc_robot_destroy(robot) };
}

#[test]
fn bad_contours_are_codes_that_name_the_argument() {
    let robot = ur5();
    let mut o = pvfc_cartesian_options_default();
    let (center, normal) = ([0.55, 0.0, 0.3], [0.0, 0.0, 1.0]);
    let mut contour = null_mut();
    let circle = |o: &pvfc_cartesian_options, radius: f64, out: &mut *mut pvfc_contour| {
        // SAFETY: valid arrays and out pointer.
        unsafe {
            pvfc_contour_cartesian_circle(
                center.as_ptr(),
                normal.as_ptr(),
                radius,
                null(),
                0.0,
                10.0,
                o,
                out,
            )
        }
    };
    assert_eq!(
        circle(&o, 0.1, &mut contour),
        pvfc_status::PVFC_ERROR_NULL_POINTER
    );
    assert!(last_error().contains("options.seed"), "{}", last_error());
    assert!(contour.is_null());
    let seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0];
    o.seed = seed.as_ptr();
    o.seed_len = 6;
    assert_eq!(
        circle(&o, -0.1, &mut contour),
        pvfc_status::PVFC_ERROR_INVALID_ARGUMENT
    );
    assert!(last_error().contains("radius"), "{}", last_error());
    let mut wrong = o;
    wrong.size -= 8;
    assert_eq!(
        circle(&wrong, 0.1, &mut contour),
        pvfc_status::PVFC_ERROR_WRONG_SIZE
    );
    // A circle 2 m across, beyond the UR5's reach: the controller names the waypoint.
    assert_eq!(circle(&o, 1.0, &mut contour), OK, "{}", last_error());
    let mut ctl = null_mut();
    // SAFETY: valid handles.
    let st = unsafe { pvfc_controller_new(robot, contour, null(), 0, null(), &mut ctl) };
    assert_eq!(st, pvfc_status::PVFC_ERROR_WAYPOINT, "{}", last_error());
    assert!(last_error().contains("waypoint"), "{}", last_error());
    assert!(ctl.is_null());
    // SAFETY: made above.
    unsafe { pvfc_contour_destroy(contour) };
    // An unknown key of the TOML table is named.
    let table = CString::new(
        "seed = [0.0]
radious = 3.0
",
    )
    .unwrap();
    let mut c2 = null_mut();
    // SAFETY: valid string and out pointer.
    let st = unsafe { pvfc_contour_cartesian_toml(table.as_ptr(), null(), 10.0, 0.0, &mut c2) };
    assert_eq!(st, pvfc_status::PVFC_ERROR_INVALID_ARGUMENT);
    assert!(last_error().contains("radious"), "{}", last_error());
    // A joint contour has no tool path; a matrix needs dof² entries.
    let w = [0.0; 18];
    let (mut joint, mut d, mut m) = (null_mut(), 0.0, [0.0; 36]);
    // SAFETY: valid arrays, handles and out pointers.
    unsafe {
        assert_eq!(
            pvfc_contour_waypoints(w.as_ptr(), 3, 6, 1.0, &mut joint),
            OK
        );
        let p = [0.0; 3];
        let st = pvfc_contour_distance(joint, p.as_ptr(), &mut d, null_mut());
        assert_eq!(st, pvfc_status::PVFC_ERROR_INVALID_ARGUMENT);
        assert_eq!(
            pvfc_robot_inertia(robot, seed.as_ptr(), 6, m.as_mut_ptr(), 35),
            pvfc_status::PVFC_ERROR_WRONG_SIZE
        );
        assert!(last_error().contains("m_out"), "{}", last_error());
        let nan = [f64::NAN; 6];
        assert_eq!(
            pvfc_robot_inertia(robot, nan.as_ptr(), 6, m.as_mut_ptr(), 36),
            pvfc_status::PVFC_ERROR_NON_FINITE
        );
        pvfc_contour_destroy(joint);
        pvfc_robot_destroy(robot);
    }
}

fn scara_joints() -> [pvfc_joint_spec; 2] {
    let joint = |xyz: [f64; 3], mass: f64, com: f64, i: [f64; 6]| pvfc_joint_spec {
        prismatic: false,
        origin_xyz: xyz,
        origin_rpy: [0.0; 3],
        axis: [0.0, 0.0, 1.0],
        lower: 0.0,
        upper: 0.0,
        mass,
        com: [com, 0.0, 0.0],
        inertia: i,
    };
    [
        joint([0.0, 0.0, 0.5], 15.0, 0.2, [0.05, 0.0, 0.0, 0.4, 0.0, 0.4]),
        joint(
            [0.4, 0.0, 0.0],
            6.0,
            0.15,
            [0.02, 0.0, 0.0, 0.15, 0.0, 0.15],
        ),
    ]
}

#[test]
fn an_arm_from_arrays_is_the_arm_of_its_urdf() {
    // models/scara.urdf, given as numbers.
    let joints = scara_joints();
    let tool = [0.35, 0.0, 0.0];
    let mut robot = null_mut();
    // SAFETY: valid arrays and out pointer.
    let st =
        unsafe { pvfc_robot_from_arrays(joints.as_ptr(), 2, tool.as_ptr(), null(), &mut robot) };
    assert_eq!(st, OK, "{}", last_error());
    let path = CString::new(repo().join("models/scara.urdf").to_str().unwrap()).unwrap();
    let tip = CString::new("tool").unwrap();
    let mut urdf = null_mut();
    // SAFETY: valid strings and out pointer.
    let st = unsafe { pvfc_robot_from_urdf_file(path.as_ptr(), null(), tip.as_ptr(), &mut urdf) };
    assert_eq!(st, OK, "{}", last_error());
    let (q, v) = ([0.3, -1.2], [0.5, 0.7]);
    let mut out = ([0.0; 4], [0.0; 4], [0.0; 2], [0.0; 3]);
    let mut reference = out;
    for (r, (m, c, g, p)) in [(robot, &mut out), (urdf, &mut reference)] {
        // SAFETY: arrays of the documented sizes, valid handles.
        unsafe {
            assert_eq!(
                pvfc_robot_dynamics(
                    r,
                    q.as_ptr(),
                    v.as_ptr(),
                    2,
                    m.as_mut_ptr(),
                    c.as_mut_ptr(),
                    g.as_mut_ptr()
                ),
                OK
            );
            assert_eq!(
                pvfc_robot_tool_pose(r, q.as_ptr(), 2, null_mut(), p.as_mut_ptr()),
                OK
            );
        }
    }
    assert_eq!(out, reference);
    // Bad numbers are named.
    let mut bad = scara_joints();
    bad[1].mass = -1.0;
    let mut none = null_mut();
    // SAFETY: valid arrays and out pointer.
    let st = unsafe { pvfc_robot_from_arrays(bad.as_ptr(), 2, null(), null(), &mut none) };
    assert_eq!(st, pvfc_status::PVFC_ERROR_URDF, "{}", last_error());
    assert!(last_error().contains("link1"), "{}", last_error());
    bad[1].mass = f64::NAN;
    // SAFETY: as above.
    let st = unsafe { pvfc_robot_from_arrays(bad.as_ptr(), 2, null(), null(), &mut none) };
    assert_eq!(st, pvfc_status::PVFC_ERROR_NON_FINITE);
    assert!(last_error().contains("joints[1]"), "{}", last_error());
    assert!(none.is_null());
    // SAFETY: made above.
    unsafe {
        pvfc_robot_destroy(robot);
        pvfc_robot_destroy(urdf);
    }
}

/// `pvfc_contour_toml` reads any `[contour]` table: a joint-space curve gives the points of its
/// typed constructor, a scenario's Cartesian path the scenario's controller; an attitude, an
/// unknown kind and a bad list are errors that name them.
#[test]
fn any_contour_table_is_the_contour_of_its_kind() {
    use pvfc_control::model::arm::JointContourSpec;
    use pvfc_control::model::contour::ContourSpec;
    let robot = ur5();
    let from_toml = |text: &str, dir: Option<&CString>| {
        let text = CString::new(text).unwrap();
        let mut contour = null_mut();
        // SAFETY: valid strings and out pointer.
        let st = unsafe {
            pvfc_contour_toml(
                text.as_ptr(),
                dir.map_or(null(), |d| d.as_ptr()),
                &mut contour,
            )
        };
        (st, contour)
    };
    let spec = JointContourSpec::Lissajous {
        amplitude: vec![0.2, 0.1, 0.15, 0.1, 0.05, 0.3],
        periods: vec![4.0, 2.0, 4.0, 4.0, 2.0, 4.0],
        phase: vec![0.0, 0.5, 1.0, 0.0, 0.0, 0.2],
        offset: vec![0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
        period: Some(4.0),
    };
    let text = toml::to_string(&ContourSpec::Joint(spec.clone())).unwrap();
    assert!(text.contains("[lissajous]"), "{text}");
    let (st, by_table) = from_toml(&text, None);
    assert_eq!(st, OK, "{}", last_error());
    let JointContourSpec::Lissajous {
        amplitude: a,
        periods: t,
        phase: phi,
        offset: c,
        ..
    } = &spec
    else {
        unreachable!()
    };
    let mut typed = null_mut();
    // SAFETY: arrays of 6, a valid out pointer.
    let st = unsafe {
        pvfc_contour_lissajous(
            a.as_ptr(),
            t.as_ptr(),
            phi.as_ptr(),
            c.as_ptr(),
            6,
            4.0,
            &mut typed,
        )
    };
    assert_eq!(st, OK, "{}", last_error());
    let s = pvfc_settings_default();
    let mut pts = Vec::new();
    for contour in [by_table, typed] {
        let mut ctl = null_mut();
        // SAFETY: valid handles.
        let st = unsafe { pvfc_controller_new(robot, contour, null(), 0, &s, &mut ctl) };
        assert_eq!(st, OK, "{}", last_error());
        pts.push(points(ctl, 4.0));
        // SAFETY: made above.
        unsafe {
            pvfc_controller_destroy(ctl);
            pvfc_contour_destroy(contour);
        }
    }
    assert_eq!(pts[0], pts[1]);

    // A scenario's Cartesian path, with its period inside its table.
    let sc = scenario(false);
    let text = toml::to_string(&sc.contour).unwrap();
    assert!(
        text.contains("[cartesian]") && text.contains("period"),
        "{text}"
    );
    let dir = CString::new(repo().join("scenarios").to_str().unwrap()).unwrap();
    let (st, by_table) = from_toml(&text, Some(&dir));
    assert_eq!(st, OK, "{}", last_error());
    let by_arguments = toml_contour(&sc);
    let mut pts = Vec::new();
    for contour in [by_table, by_arguments] {
        let ctl = controller(robot, contour, &sc);
        pts.push(points(ctl, sc.period()));
        // SAFETY: made above.
        unsafe {
            pvfc_controller_destroy(ctl);
            pvfc_contour_destroy(contour);
        }
    }
    assert_eq!(pts[0], pts[1]);

    for (text, named) in [
        ("[attitude]\nrate = [0.0, 0.0, 1.0]\n", "contour.attitude"),
        ("[spiral]\nturns = 3\n", "unknown variant `spiral`"),
        (
            "[ellipse]\ncenter = [0.0, 0.0]\nu = [1.0]\nw = [0.0, 1.0]\nperiod = 2.0\n",
            "ellipse.u",
        ),
        (
            "[cartesian]\npoints = [[0.5, 0.0, 0.3], [0.6, 0.0, 0.3], [0.6, 0.1, 0.3]]\n",
            "period",
        ),
    ] {
        let (st, contour) = from_toml(text, None);
        assert_eq!(st, pvfc_status::PVFC_ERROR_INVALID_ARGUMENT, "{text}");
        assert!(contour.is_null());
        let e = last_error();
        assert!(e.contains(named), "{text}: {e}");
    }
    // SAFETY: made above.
    unsafe { pvfc_robot_destroy(robot) };
}

/// Issue "Faults survived": the C inputs that were accepted and then failed every step, or
/// that hung, are refused where they enter with a code and a message naming them: a URDF
/// whose joints form a cycle, 2 or 1,025 waypoints, a `tau0` that is not a number, settings
/// each finite but together beyond a double.
#[test]
fn inputs_that_failed_later_are_refused_where_they_enter() {
    let cycle = CString::new(
        "<robot name=\"r\"><link name=\"r\"/><link name=\"a\"/><link name=\"b\"/>\
         <joint name=\"ab\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>\
         <joint name=\"ba\" type=\"continuous\"><parent link=\"b\"/><child link=\"a\"/></joint></robot>",
    )
    .unwrap();
    let mut robot = null_mut();
    // SAFETY: valid strings and out pointer.
    let st = unsafe {
        pvfc_robot_from_urdf_string(
            cycle.as_ptr(),
            c"cycle.urdf".as_ptr(),
            c"a".as_ptr(),
            c"r".as_ptr(),
            &mut robot,
        )
    };
    assert_eq!(st, pvfc_status::PVFC_ERROR_URDF);
    assert!(last_error().contains("cycle"), "{}", last_error());

    let rows = vec![0.1; 1025 * 2];
    for n in [0, 1, 2, 1025] {
        let mut contour = null_mut();
        // SAFETY: `rows` holds 1,025 × 2 doubles.
        let st = unsafe { pvfc_contour_waypoints(rows.as_ptr(), n, 2, 1.0, &mut contour) };
        assert_eq!(
            st,
            pvfc_status::PVFC_ERROR_INVALID_ARGUMENT,
            "{n} waypoints"
        );
        assert!(last_error().contains("n_waypoints"), "{}", last_error());
        assert!(contour.is_null());
    }

    let robot = ur5();
    let waypoints = [
        0.0, -1.2, 1.4, -1.8, -1.57, 0.0, //
        0.3, -1.0, 1.2, -1.7, -1.57, 0.2, //
        -0.2, -1.3, 1.5, -1.9, -1.57, -0.1,
    ];
    let mut contour = null_mut();
    // SAFETY: 3 × 6 doubles.
    let st = unsafe { pvfc_contour_waypoints(waypoints.as_ptr(), 3, 6, 1.5, &mut contour) };
    assert_eq!(st, OK, "{}", last_error());
    type Edit = fn(&mut pvfc_settings);
    let edits: [(Edit, &str); 4] = [
        (|s| s.tau0 = f64::NAN, "tau0"),
        (|s| s.energy = 1e308, "settings"),
        (|s| s.flywheel_inertia = 1e-308, "settings"),
        (|s| s.gamma = 1e308, "settings"),
    ];
    for (edit, named) in edits {
        let mut s = pvfc_settings_default();
        edit(&mut s);
        let mut ctl = null_mut();
        // SAFETY: valid handles and out pointer.
        let st = unsafe { pvfc_controller_new(robot, contour, null(), 0, &s, &mut ctl) };
        assert_ne!(st, OK, "{named}");
        assert!(ctl.is_null());
        assert!(last_error().contains(named), "{named}: {}", last_error());
    }
    // SAFETY: made above, freed once.
    unsafe {
        pvfc_contour_destroy(contour);
        pvfc_robot_destroy(robot);
    }
}
