//! The tool path's error budget: the exact geometry of a path (arc length, closest points,
//! plane normal) against closed forms and brute force; the adaptive sampling puts the joint
//! contour within its tolerance of the path (checked with the robot's own forward kinematics
//! of the contour a controller follows); the spread and the steady passes of a run.

use nalgebra::Vector3;
use pvfc_sim::model::cartesian::{CartesianSpec, CircleSpec};
use pvfc_sim::model::robot::Robot;
use pvfc_sim::model::tool_path::ToolPath;
use pvfc_sim::trace::path_budget::{steady_passes, Spread};
use std::path::Path;

fn robot(path: &str, tip: &str) -> Robot {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path);
    Robot::from_urdf(&p, None, Some(tip)).unwrap()
}

fn rectangle(samples: usize) -> CartesianSpec {
    CartesianSpec {
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
    }
}

/// A small deterministic generator (no dependency needed for a few random points).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn a_rounded_rectangle_has_its_closed_form_length_and_normal() {
    let path = rectangle(24).path(Path::new(".")).unwrap();
    // 2(a + b) with each corner's two tangent lengths r replaced by a quarter circle.
    let (a, b, r) = (0.2, 0.35, 0.03);
    let expected = 2.0 * (a + b) - 8.0 * r + 2.0 * std::f64::consts::PI * r;
    assert!(
        (path.length() - expected).abs() < 1e-12,
        "{}",
        path.length()
    );
    // Counter-clockwise seen from above: the normal is +z.
    let n = path.normal().unwrap();
    assert!((n - Vector3::z()).norm() < 1e-12, "{n}");
    // It starts where the first corner's arc starts, on the last side.
    assert!((path.point(0.0) - Vector3::new(0.45, -0.12, 0.30)).norm() < 1e-12);
}

#[test]
fn every_point_of_the_path_is_its_own_closest_point() {
    let mut seed = 7;
    for path in [
        rectangle(24).path(Path::new(".")).unwrap(),
        ToolPath::ellipse(
            Vector3::new(0.5, 0.0, 0.4),
            Vector3::new(0.12, 0.0, 0.05),
            Vector3::new(0.0, 0.06, 0.0),
        ),
    ] {
        for _ in 0..200 {
            let s = lcg(&mut seed) * path.length();
            let c = path.closest(&path.point(s));
            assert!(c.distance < 1e-9, "{}", c.distance);
            let ds = (c.along - s).abs();
            assert!(ds.min(path.length() - ds) < 1e-7, "s {s} found {}", c.along);
            // The tangent is the derivative of the point by arc length.
            let h = 1e-6;
            let fd = (path.point(s + h) - path.point(s - h)) / (2.0 * h);
            assert!(
                (fd - path.tangent(s)).norm() < 1e-5,
                "{fd} {}",
                path.tangent(s)
            );
        }
    }
}

#[test]
fn the_closest_point_is_no_farther_than_any_point_of_the_path() {
    let mut seed = 11;
    let path = rectangle(24).path(Path::new(".")).unwrap();
    let dense: Vec<_> = (0..20_000)
        .map(|k| path.point(path.length() * k as f64 / 20_000.0))
        .collect();
    for _ in 0..100 {
        let p = Vector3::new(
            0.4 + 0.3 * lcg(&mut seed),
            -0.2 + 0.45 * lcg(&mut seed),
            0.28 + 0.04 * lcg(&mut seed),
        );
        let c = path.closest(&p);
        let brute = dense
            .iter()
            .map(|q| (p - q).norm())
            .fold(f64::INFINITY, f64::min);
        // Never farther than a sample of the path; closer by at most the samples' spacing.
        assert!(c.distance <= brute + 1e-12, "{} > {brute}", c.distance);
        assert!(c.distance >= brute - 1e-4, "{} ≪ {brute}", c.distance);
        assert!((path.point(c.along) - c.point).norm() < 1e-9);
    }
}

#[test]
fn an_ellipse_has_the_gauss_kummer_length() {
    let (a, b) = (0.12, 0.05);
    let path = ToolPath::ellipse(
        Vector3::zeros(),
        Vector3::new(a, 0.0, 0.0),
        Vector3::new(0.0, b, 0.0),
    );
    // The Gauss–Kummer series: π(a + b) Σ C(1/2, n)² hⁿ, h = ((a − b)/(a + b))².
    let h = ((a - b) / (a + b)).powi(2);
    let (mut c, mut sum) = (1.0f64, 0.0);
    for n in 0..40 {
        sum += c * c * h.powi(n);
        c *= (0.5 - n as f64) / (n as f64 + 1.0);
    }
    let exact = std::f64::consts::PI * (a + b) * sum;
    assert!(
        (path.length() - exact).abs() < 1e-12 * exact,
        "{} vs {exact}",
        path.length()
    );
    // Equal arc lengths: sample k lies k/64 of the length along the curve.
    for (k, p) in path.sample(64).iter().enumerate() {
        let along = path.closest(p).along;
        let expected = path.length() * k as f64 / 64.0;
        assert!(
            (along - expected).abs() < 1e-9,
            "{k}: {along} vs {expected}"
        );
    }
}

/// The adaptive sampling stops within its tolerance, and the contour a controller follows
/// (the robot's forward kinematics of `ArmController::contour_point`, not the budget's own
/// evaluation) is within it of the path.
#[test]
fn the_adaptive_sampling_puts_the_ur5_contour_within_its_tolerance() {
    use pvfc_sim::model::arm::{ArmController, ArmSettings, JointContourSpec};
    let ur5 = robot("models/ur5/ur5_robot.urdf", "tool0");
    let base = Path::new(".");
    let fixed = rectangle(24).joint_path(&ur5, base).unwrap();
    assert_eq!(fixed.geometry.samples, 24);
    assert!(fixed.geometry.max > 1e-3, "{:?}", fixed.geometry);
    let mut spec = rectangle(0);
    spec.tolerance = Some(2e-5);
    let adaptive = spec.joint_path(&ur5, base).unwrap();
    let g = adaptive.geometry;
    assert!(g.max <= 2e-5 && g.samples > 24, "{g:?}");
    assert!(g.max_angle.unwrap() < 1e-3, "{g:?}");
    let settings = ArmSettings {
        field: pvfc_sim::model::arm_field::FieldSpec::Joint,
        contour: JointContourSpec::Waypoints {
            points: adaptive.waypoints.clone(),
            spacing: 0.05,
        },
        h: vec![4.0; 6],
        self_pacing: 0.0,
        energy: 40.0,
        flywheel_inertia: 1.0,
        gamma: 1.0,
        coupling_rate: None,
        gravity_compensation: false,
        friction_compensation: None,
        friction_band: 0.0,
        nominal_speed: None,
        nominal_speed_integral: 0.0,
        tau0: 0.0,
        field_energy_bound: None,
        obstacles: None,
        pace: None,
    };
    let ctl = ArmController::new(&ur5, &settings).unwrap();
    let path = spec.path(base).unwrap();
    let period = 0.05 * g.samples as f64;
    let worst = (0..3000)
        .map(|k| {
            let q = ctl.contour_point(period * (k as f64 + 0.5) / 3000.0);
            path.closest(&ur5.tool_pose(&q).unwrap().1).distance
        })
        .fold(0.0, f64::max);
    assert!(worst <= 2e-5, "{worst}");
    // A tolerance no number of samples reaches is an error that says so.
    spec.tolerance = Some(1e-9);
    let e = spec.joint_path(&ur5, base).unwrap_err().to_string();
    assert!(e.contains("tolerance"), "{e}");
    spec.tolerance = Some(-1.0);
    assert!(spec.joint_path(&ur5, base).is_err());
}

#[test]
fn a_panda_circle_in_a_tilted_plane_is_sampled_to_ten_micrometres() {
    let panda = robot("models/panda/panda.urdf", "panda_hand_tcp");
    let seed = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8];
    let (_, p0) = panda.tool_pose(&seed).unwrap();
    let spec = CartesianSpec {
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
    let g = spec.joint_path(&panda, Path::new(".")).unwrap().geometry;
    assert!(g.max <= 1e-5 && g.samples >= 32, "{g:?}");
    assert!(g.max_angle.is_none());
}

#[test]
fn spreads_and_steady_passes() {
    let s = Spread::of(&(1..=100).map(f64::from).collect::<Vec<_>>());
    assert_eq!((s.mean, s.p95, s.max), (50.5, 95.0, 100.0));
    assert_eq!(Spread::of(&[]), Spread::default());
    let mut t = pvfc_sim::Trace::default();
    // τ from 0 to 3.5 periods of 1: the steady passes are the 2nd and 3rd, τ ∈ [1, 3].
    for k in 0..=350 {
        t.t.push(k as f64 * 0.01);
        t.tau.push(k as f64 * 0.01);
    }
    let r = steady_passes(&t, 1.0).unwrap();
    assert!((t.tau[r.start] - 1.0).abs() < 1e-9 && (t.tau[r.end - 1] - 3.0).abs() < 1e-9);
    // Only one complete pass: that one.
    let r = steady_passes(&t, 2.0).unwrap();
    assert!(t.tau[r.start].abs() < 1e-9 && (t.tau[r.end - 1] - 2.0).abs() < 1e-9);
    assert!(steady_passes(&t, 4.0).is_none());
}

/// The MCAP log of a run on a Cartesian path carries its error budget as a metadata record,
/// the same numbers `path_budget` gives.
#[test]
fn the_log_carries_the_budget() {
    use pvfc_sim::log::scene::{Scene, BUDGET_METADATA};
    use pvfc_sim::log::{write_mcap_with, LogOptions};
    use pvfc_sim::trace::path_budget::path_budget;
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut s = pvfc_sim::Scenario::from_file(&repo.join("scenarios/ur5_cartesian.toml")).unwrap();
    s.duration = 13.0; // one pass
    s.baseline = None;
    if let Some(c) = s.contour.cartesian_mut() {
        c.tolerance = Some(1e-4);
    }
    let t = pvfc_sim::simulate(&s, &mut |_| {}).unwrap();
    let b = path_budget(&s, &s.robot().unwrap(), &t).unwrap().unwrap();
    let scene = Scene::of_run(&s, &t).unwrap().unwrap();
    let dir = std::env::temp_dir().join(format!("pvfc-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ur5.mcap");
    let options = LogOptions {
        scene: Some(&scene),
        rate: Some(50.0),
    };
    write_mcap_with(&t, &options, &p).unwrap();
    let bytes = std::fs::read(&p).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let index = summary
        .metadata_indexes
        .iter()
        .find(|m| m.name == BUDGET_METADATA)
        .expect("the budget record");
    let m = mcap::read::metadata(&bytes, index).unwrap().metadata;
    let get = |k: &str| m[k].parse::<f64>().unwrap();
    assert_eq!(get("geometry.samples"), b.geometry.unwrap().samples as f64);
    assert_eq!(get("distance.max_m"), b.spread.max);
    assert_eq!(get("surface.mean_m"), b.surface.unwrap().mean);
    assert_eq!(get("speed_m_per_s"), b.speed);
    std::fs::remove_dir_all(&dir).ok();
}
