//! Navigation functions (critical points, Hessians) and contours (derivatives, periodicity,
//! interpolation), over random parameters.

use crate::common;

use common::{close_vec, f, vec, Tolerance, CASES};
use nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;
use pvfc_core::prelude::*;
use pvfc_core::scalar::cast;
use std::f64::consts::PI;
use std::result::Result;

/// The Hessian of U at `e`, column k = d/dt grad U(E exp(t e_k)) (exact at critical points).
fn hessian<T: Real, G: LieGroup<T, D>, N: NavigationFunction<T, G, D>, const D: usize>(
    nav: &N,
    e: &G,
) -> SMatrix<T, D, D> {
    SMatrix::from_fn(|r, c| {
        let mut dir = SVector::<T, D>::zeros();
        dir[c] = T::one();
        nav.evaluate(e, &dir).gradient_rate[r] * nav.metric_weight()
    })
}

fn positive_definite<T: Real, const D: usize>(h: &SMatrix<T, D, D>) -> bool {
    let sym = (h + h.transpose()) * cast::<T>(0.5);
    sym.cholesky().is_some() && f((h - h.transpose()).norm()) < 1e-6 * (1.0 + f(h.norm()))
}

/// All critical points of the torus function: gradient 0 at every E_i ∈ {0, π}; Hessian
/// positive definite only at the identity; U = 0 only there.
fn torus_critical_points<T: Tolerance>(
    h: [f64; 3],
    convention: TorusConvention,
) -> Result<(), String> {
    let nav = TorusNavigation::new(vec::<T, 3>(h), convention).map_err(|e| e.to_string())?;
    for mask in 0..8u32 {
        let angles: [f64; 3] = core::array::from_fn(|i| if mask >> i & 1 == 1 { PI } else { 0.0 });
        let e = Torus::<T, 3>::new(vec(angles));
        let s = nav.evaluate(&e, &SVector::zeros());
        close_vec(
            &s.gradient,
            &SVector::zeros(),
            T::ROUNDING * 10.0,
            1.0,
            "gradient at a critical point",
        )?;
        let pd = positive_definite(&hessian(&nav, &e));
        if pd != (mask == 0) {
            return Err(format!("Hessian PD = {pd} at critical point {angles:?}"));
        }
        if (f(s.value) <= T::ROUNDING) != (mask == 0) {
            return Err(format!("U = {} at {angles:?}", f(s.value)));
        }
    }
    Ok(())
}

/// SO(3): the four critical points are I and the half-turns about P's eigenvectors; only I is
/// a minimum (PD Hessian), and U(I) = 0 < U elsewhere.
fn so3_critical_points<T: Tolerance>(h: [f64; 3]) -> Result<(), String> {
    let p = common::setups::so3_p::<f64>(h);
    let nav = So3Navigation::new(p.map(cast::<T>)).map_err(|e| e.to_string())?;
    let eig = p.symmetric_eigen();
    let id = So3::<T>::identity();
    if !positive_definite(&hessian(&nav, &id)) {
        return Err("Hessian at I not positive definite".into());
    }
    if f(nav.value(&id)).abs() > T::ROUNDING {
        return Err("U(I) ≠ 0".into());
    }
    for k in 0..3 {
        let axis: Vector3<f64> = eig.eigenvectors.column(k).into_owned();
        let e = So3::<T>::from_axis_angle(&axis.map(cast), T::pi());
        let g = nav.gradient(&e);
        close_vec(
            &g,
            &Vector3::zeros(),
            T::LOOSE * 10.0,
            1.0,
            "gradient at a half-turn",
        )?;
        if positive_definite(&hessian(&nav, &e)) {
            return Err(format!("Hessian PD at the half-turn about eigenvector {k}"));
        }
        if f(nav.value(&e)) <= 0.0 {
            return Err("U ≤ 0 at a half-turn".into());
        }
    }
    // The Hessian at I is (tr P·I − P)/π' (times the metric weight 2, over 2).
    let pi_prime = eig.eigenvalues.sum() - 2.0 * eig.eigenvalues.min();
    let expected = (Matrix3::identity() * p.trace() - p) / pi_prime;
    let got = hessian(&nav, &id).map(f);
    if (got - expected).norm() > 1e-4 * (1.0 + expected.norm()) {
        return Err(format!("Hessian at I: {got} vs {expected}"));
    }
    Ok(())
}

/// Body derivatives of a contour against central differences of its points.
fn contour_derivatives<G: LieGroup<f64, D>, X: Contour<f64, G, D>, const D: usize>(
    c: &X,
    tau: f64,
) -> Result<(), String> {
    let h = 1e-4;
    let s = c.sample(tau);
    let xi = |t: f64| s.point.inverse().compose(&c.point(tau + t)).log();
    let d = |g: &dyn Fn(f64) -> SVector<f64, D>, h: f64| (g(h) - g(-h)) / (2.0 * h);
    let rich = |g: &dyn Fn(f64) -> SVector<f64, D>| (d(g, h / 2.0) * 4.0 - d(g, h)) / 3.0;
    close_vec(
        &rich(&xi),
        &s.velocity,
        1e-8,
        1.0 + s.velocity.norm(),
        "ξ_d vs finite differences",
    )?;
    let vel = |t: f64| c.sample(tau + t).velocity;
    close_vec(
        &rich(&vel),
        &s.acceleration,
        1e-7,
        1.0 + s.acceleration.norm(),
        "dξ_d/dτ vs finite differences",
    )?;
    if let Some(p) = c.period() {
        let d = s.point.distance(&c.point(tau + p));
        if d > 1e-9 {
            return Err(format!("not periodic: {d:e}"));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn torus_navigation_critical_points(h in proptest::array::uniform(0.1..10.0)) {
        for conv in [TorusConvention::HalfSum, TorusConvention::Sum] {
            let r = torus_critical_points::<f64>(h, conv).and_then(|_| torus_critical_points::<f32>(h, conv));
            prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        }
    }

    #[test]
    fn so3_navigation_critical_points(h in proptest::array::uniform(0.2..5.0)) {
        let r = so3_critical_points::<f64>(h).and_then(|_| so3_critical_points::<f32>(h));
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }

    #[test]
    fn so3_navigation_rejects_bad_p(a in -5.0..5.0f64, b in -5.0..5.0f64, c in -5.0..5.0f64) {
        let p = Matrix3::from_diagonal(&Vector3::new(a, b, c));
        let mut e = [a, b, c];
        e.sort_by(|x, y| x.total_cmp(y));
        let tol = 1e-8 * p.norm();
        let valid = e[1] - e[0] > tol && e[2] - e[1] > tol && e[0] + e[1] > tol;
        match So3Navigation::new(p) {
            Ok(_) => prop_assert!(valid, "accepted invalid P = diag({a}, {b}, {c})"),
            Err(err) => {
                prop_assert!(!valid, "rejected valid P = diag({a}, {b}, {c})");
                prop_assert_eq!(err.kind(), ErrorKind::InvalidNavigationMatrix);
            }
        }
    }

    #[test]
    fn lissajous_and_ellipse_derivatives(tau in -20.0..20.0f64, a in proptest::array::uniform(0.1..2.0), per in proptest::array::uniform(0.5..8.0), ph in proptest::array::uniform(-PI..PI)) {
        let l = Lissajous::<f64, 3>::new(vec(a), vec(per), vec(ph), vec([0.1, -0.2, 0.3])).unwrap();
        let r = contour_derivatives::<Torus<f64, 3>, _, 3>(&l, tau);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        let e = Ellipse::<f64, 3>::new(vec([0.1, 0.0, -0.4]), vec(a), vec(ph), per[0]).unwrap();
        let r = contour_derivatives::<Rn<f64, 3>, _, 3>(&e, tau);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }

    /// A curve's coordinates and their derivatives are the closed form, with its period
    /// declared or not, in f64 and f32, at frequencies that are whole multiples of the period's
    /// and at any phase (quarter turns included).
    #[test]
    fn lissajous_harmonics_are_the_closed_form(
        k in proptest::array::uniform3(1u8..7),
        quarters in proptest::array::uniform3(-4i32..8),
        free in proptest::array::uniform3(-PI..PI),
        turn in proptest::array::uniform3(proptest::bool::ANY),
        a in proptest::array::uniform3(0.1..2.0f64),
        period in 0.5..10.0f64,
        u in 0.0..1.0f64,
    ) {
        let phase: [f64; 3] = std::array::from_fn(|i| if turn[i] { quarters[i] as f64 * PI / 2.0 } else { free[i] });
        let per: [f64; 3] = std::array::from_fn(|i| period / k[i] as f64);
        let offset = [0.1, -0.2, 0.3];
        let tau = u * period;
        let closed = |i: usize| {
            let w = 2.0 * PI / per[i];
            let (s, c) = (w * tau + phase[i]).sin_cos();
            (offset[i] + a[i] * s, a[i] * w * c, -a[i] * w * w * s)
        };
        let curve = Lissajous::<f64, 3>::new(vec(a), vec(per), vec(phase), vec(offset)).unwrap();
        for l in [curve, curve.with_period(period).unwrap()] {
            let [x, dx, ddx] = l.coordinates(tau);
            for i in 0..3 {
                let (ex, edx, eddx) = closed(i);
                let w = 2.0 * PI / per[i];
                prop_assert!((x[i] - ex).abs() <= 1e-13 * (1.0 + a[i]), "x[{i}] {} vs {ex}", x[i]);
                prop_assert!((dx[i] - edx).abs() <= 1e-13 * (1.0 + a[i] * w), "dx[{i}] {} vs {edx}", dx[i]);
                prop_assert!((ddx[i] - eddx).abs() <= 1e-13 * (1.0 + a[i] * w * w), "ddx[{i}] {} vs {eddx}", ddx[i]);
            }
        }
        let l32 = Lissajous::<f32, 3>::new(
            SVector::from_fn(|i, _| a[i] as f32),
            SVector::from_fn(|i, _| per[i] as f32),
            SVector::from_fn(|i, _| phase[i] as f32),
            SVector::from_fn(|i, _| offset[i] as f32),
        )
        .unwrap()
        .with_period(period as f32)
        .unwrap();
        let [x, _, _] = l32.coordinates(tau as f32);
        for i in 0..3 {
            let (ex, _, _) = closed(i);
            // f32: the phase, the frequency and τ each rounded (~6e-8 relative), times up to
            // six turns of the argument.
            prop_assert!((x[i] as f64 - ex).abs() <= 2e-5 * (1.0 + a[i]), "f32 x[{i}] {} vs {ex}", x[i]);
        }
    }

    #[test]
    fn bspline_derivatives_on_torus_and_so3(k in -10i32..10, u in 0.01..0.99f64, tau in -20.0..20.0f64) {
        // Finite differences need smoothness: the third derivative of a cubic spline jumps at
        // its knots, so the difference quotient is taken inside a segment (continuity at the
        // knots is checked in `bspline_is_c2_at_the_knots`).
        let pts = common::setups::waypoints::<f64>();
        let spline = PeriodicBSpline::through(pts, 1.3).unwrap();
        let r = contour_derivatives::<Torus<f64, 2>, _, 2>(&spline, (k as f64 + u) * 1.3);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        let spline = PeriodicBSpline::through(common::setups::key_orientations::<f64>(), 2.0).unwrap();
        let r = contour_derivatives::<So3<f64>, _, 3>(&spline, (k as f64 + u) * 2.0);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        let spin = ConstantRate::new(So3::exp(&Vector3::new(0.1, 0.2, 0.3)), Vector3::new(0.3, -0.2, 0.5)).unwrap();
        let r = contour_derivatives::<So3<f64>, _, 3>(&spin, tau);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }
}

#[test]
fn paper_lissajous_is_the_published_curve() {
    let c = Lissajous::<f64, 2>::paper();
    for k in 0..600 {
        let tau = k as f64 * 0.01;
        let p: Torus<f64, 2> = c.point(tau);
        let expected = Vector2::new(
            (2.0 * PI * tau / 3.0).sin(),
            1.5 * (2.0 * PI * tau / 6.0).cos(),
        );
        assert!((p.angles() - expected).norm() < 1e-14);
    }
    // It crosses itself at the centre: x_d(τ) = 0 at τ = 1.5 and τ = 4.5 with different
    // tangents, so no time-invariant field on T² can encode it.
    let a: ContourSample<f64, Torus<f64, 2>, 2> = c.sample(1.5);
    let b: ContourSample<f64, Torus<f64, 2>, 2> = c.sample(4.5);
    assert!(a.point.angles().norm() < 1e-14 && b.point.angles().norm() < 1e-14);
    assert!((a.velocity.normalize() - b.velocity.normalize()).norm() > 0.5);
}

#[test]
fn interpolating_spline_passes_through_waypoints() {
    let pts = common::setups::waypoints::<f32>();
    let spline = PeriodicBSpline::through(pts, 1.3).unwrap();
    for (k, p) in pts.iter().enumerate() {
        assert!(spline.point(1.3 * k as f32).distance(p) < 1e-5);
    }
    let keys = common::setups::key_orientations::<f64>();
    let spline = PeriodicBSpline::through(keys, 2.0).unwrap();
    for (k, p) in keys.iter().enumerate() {
        assert!(spline.point(2.0 * k as f64).distance(p) < 1e-12);
    }
    // Key orientations too coarse for an interpolating spline are a typed error.
    let coarse = [
        [0.0, 0.0, 0.0],
        [0.9, 0.1, 0.0],
        [0.4, 1.0, -0.5],
        [-0.3, 0.5, 1.1],
    ]
    .map(|a| So3::<f64>::exp(&Vector3::from(a)));
    assert_eq!(
        PeriodicBSpline::through(coarse, 1.0).unwrap_err().kind(),
        ErrorKind::NoConvergence
    );
}

/// The fit of `through_slice` updates its spline in place: the result is, to the bit, the
/// spline `from_control_slice` builds from the fitted control points (its segment logarithms
/// included, compared by `PartialEq` over the whole capacity), and a capacity far above the
/// number of waypoints fits the same control points as an exact one.
#[test]
fn the_fit_in_place_is_the_spline_of_its_control_points() {
    let keys = common::setups::key_orientations::<f64>();
    let exact = PeriodicBSpline::through(keys, 2.0).unwrap();
    let roomy = PeriodicBSpline::<f64, So3<f64>, 3, 256>::through_slice(&keys, 2.0).unwrap();
    assert_eq!(roomy.control_points(), exact.control_points());
    let rebuilt =
        PeriodicBSpline::<f64, So3<f64>, 3, 256>::from_control_slice(roomy.control_points(), 2.0)
            .unwrap();
    assert_eq!(roomy, rebuilt);
    let pts = common::setups::waypoints::<f32>();
    let roomy = PeriodicBSpline::<f32, _, 2, 64>::through_slice(&pts, 1.3).unwrap();
    let rebuilt = PeriodicBSpline::from_control_slice(roomy.control_points(), 1.3).unwrap();
    assert_eq!(roomy, rebuilt);
    assert_eq!(
        roomy.control_points(),
        PeriodicBSpline::through(pts, 1.3).unwrap().control_points()
    );
}

#[test]
fn bspline_is_c2_at_the_knots() {
    let spline = PeriodicBSpline::through(common::setups::key_orientations::<f64>(), 2.0).unwrap();
    for k in -6..12 {
        let knot = 2.0 * k as f64;
        let (a, b) = (spline.sample(knot - 1e-9), spline.sample(knot + 1e-9));
        assert!(a.point.distance(&b.point) < 1e-8, "C0 at knot {k}");
        assert!((a.velocity - b.velocity).norm() < 1e-7, "C1 at knot {k}");
        assert!(
            (a.acceleration - b.acceleration).norm() < 1e-7,
            "C2 at knot {k}"
        );
    }
}
