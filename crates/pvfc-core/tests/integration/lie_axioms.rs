//! One generic axiom suite for every Lie group, run for `f32` and `f64` over random elements.

use crate::common;

use common::{close_vec, f, Tolerance, CASES};
use nalgebra::SVector;
use proptest::prelude::*;
use pvfc_core::lie::{JointKind, JointSpace, LieGroup, Rn, So3, Tangent, Torus};
use pvfc_core::scalar::cast;

/// The axioms every `LieGroup` satisfies, for three random elements `exp(a)`, `exp(b)`,
/// `exp(c)` and a random algebra element `v`.
fn axioms<T: Tolerance, G: LieGroup<T, D>, const D: usize>(
    a: Tangent<T, D>,
    b: Tangent<T, D>,
    c: Tangent<T, D>,
    v: Tangent<T, D>,
) -> Result<(), String> {
    let tol = T::LOOSE;
    let (x, y, z) = (G::exp(&a), G::exp(&b), G::exp(&c));
    let id = G::identity();
    let dist = |p: &G, q: &G| f(p.distance(q));
    let check = |d: f64, what: &str| {
        if d <= tol * 10.0 && d.is_finite() {
            Ok(())
        } else {
            Err(format!("{what}: distance {d:e}"))
        }
    };
    check(
        dist(&x.compose(&y).compose(&z), &x.compose(&y.compose(&z))),
        "associativity",
    )?;
    check(dist(&x.compose(&id), &x), "right identity")?;
    check(dist(&id.compose(&x), &x), "left identity")?;
    check(dist(&x.compose(&x.inverse()), &id), "right inverse")?;
    check(dist(&x.inverse().compose(&x), &id), "left inverse")?;
    // exp ∘ log = id (log picks some preimage; exp of it must give the element back).
    check(dist(&G::exp(&x.log()), &x), "exp(log g) = g")?;
    // log ∘ exp = id on the ball where exp is injective (|a| < π by construction).
    close_vec(
        &x.log(),
        &a,
        tol * 10.0,
        1.0 + f(a.norm()),
        "log(exp v) = v",
    )?;
    // Adjoint: g exp(v) g⁻¹ = exp(Ad_g v).
    let lhs = x.compose(&G::exp(&v)).compose(&x.inverse());
    check(
        dist(&lhs, &G::exp(&x.adjoint_apply(&v))),
        "g exp(v) g⁻¹ = exp(Ad_g v)",
    )?;
    close_vec(
        &x.adjoint_inverse_apply(&x.adjoint_apply(&v)),
        &v,
        tol,
        1.0 + f(v.norm()),
        "Ad_{g⁻¹} Ad_g = I",
    )?;
    close_vec(
        &(x.adjoint() * v),
        &x.adjoint_apply(&v),
        tol,
        1.0 + f(v.norm()),
        "adjoint matrix",
    )?;
    // Ad is a homomorphism: Ad_{xy} = Ad_x Ad_y.
    close_vec(
        &x.compose(&y).adjoint_apply(&v),
        &x.adjoint_apply(&y.adjoint_apply(&v)),
        tol,
        1.0 + f(v.norm()),
        "Ad_xy = Ad_x Ad_y",
    )?;
    // Bracket: antisymmetric, Jacobi, and the derivative of Ad: d/dt Ad_{exp(ta)} b = [a, b].
    close_vec(
        &G::lie_bracket(&a, &b),
        &(-G::lie_bracket(&b, &a)),
        tol,
        1.0,
        "[a,b] = −[b,a]",
    )?;
    let jac = G::lie_bracket(&a, &G::lie_bracket(&b, &c))
        + G::lie_bracket(&b, &G::lie_bracket(&c, &a))
        + G::lie_bracket(&c, &G::lie_bracket(&a, &b));
    close_vec(
        &jac,
        &Tangent::zeros(),
        tol * 10.0,
        1.0 + f(a.norm() * b.norm() * c.norm()),
        "Jacobi",
    )?;
    let h: T = cast(if T::ROUNDING < 1e-10 { 1e-5 } else { 1e-2 });
    let fd = (G::exp(&(a * h)).adjoint_apply(&b) - G::exp(&(a * -h)).adjoint_apply(&b)) / (h + h);
    close_vec(
        &fd,
        &G::lie_bracket(&a, &b),
        if T::ROUNDING < 1e-10 { 1e-8 } else { 2e-3 },
        1.0 + f(a.norm() * b.norm()),
        "d/dt Ad_exp(ta) b = [a,b]",
    )?;
    // Pushforwards in body coordinates against finite differences of the translations:
    // (L_x)_* at y along v: body velocity of x·y·exp(tv) at x·y is v.
    // (R_x)_* at y along v: body velocity of y·exp(tv)·x at y·x is Ad_{x⁻¹} v.
    let yx = y.compose(&x);
    let fwd = yx
        .inverse()
        .compose(&y.compose(&G::exp(&(v * h))).compose(&x))
        .log();
    let bwd = yx
        .inverse()
        .compose(&y.compose(&G::exp(&(v * -h))).compose(&x))
        .log();
    let fd_right = (fwd - bwd) / (h + h);
    close_vec(
        &fd_right,
        &x.right_translation_pushforward(&v),
        if T::ROUNDING < 1e-10 { 1e-8 } else { 2e-3 },
        1.0 + f(v.norm()),
        "(R_x)_*",
    )?;
    let xy = x.compose(&y);
    let fwd = xy
        .inverse()
        .compose(&x.compose(&y.compose(&G::exp(&(v * h)))))
        .log();
    let bwd = xy
        .inverse()
        .compose(&x.compose(&y.compose(&G::exp(&(v * -h)))))
        .log();
    close_vec(
        &((fwd - bwd) / (h + h)),
        &x.left_translation_pushforward(&v),
        if T::ROUNDING < 1e-10 { 1e-8 } else { 2e-3 },
        1.0 + f(v.norm()),
        "(L_x)_*",
    )?;
    // Retraction moves along the body velocity.
    check(
        dist(&x.retract(&v, h), &x.compose(&G::exp(&(v * h)))),
        "retract",
    )?;
    if !x.is_finite() {
        return Err("is_finite on a finite element".into());
    }
    Ok(())
}

/// A random algebra element inside the injectivity ball of `exp` (norm < 0.95 π for SO(3),
/// components in (−π, π) for the torus).
fn tangent<const D: usize>(radius: f64) -> impl Strategy<Value = [f64; D]> {
    proptest::array::uniform(-radius..radius).prop_map(move |mut x: [f64; D]| {
        let n = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if n > radius {
            for v in x.iter_mut() {
                *v *= radius / n * 0.999;
            }
        }
        x
    })
}

fn to<T: Tolerance, const D: usize>(x: [f64; D]) -> SVector<T, D> {
    common::vec(x)
}

macro_rules! suite {
    ($name:ident, $group:ty, $t:ty, $d:literal, $radius:expr) => {
        proptest! {
            #![proptest_config(ProptestConfig::with_cases(CASES))]
            #[test]
            fn $name(a in tangent::<$d>($radius), b in tangent::<$d>($radius),
                     c in tangent::<$d>($radius), v in tangent::<$d>(2.0)) {
                let r = axioms::<$t, $group, $d>(to(a), to(b), to(c), to(v));
                prop_assert!(r.is_ok(), "{}", r.unwrap_err());
            }
        }
    };
}

const PI_BALL: f64 = 0.95 * std::f64::consts::PI;

suite!(torus2_f64, Torus<f64, 2>, f64, 2, PI_BALL);
suite!(torus2_f32, Torus<f32, 2>, f32, 2, PI_BALL);
suite!(torus6_f64, Torus<f64, 6>, f64, 6, PI_BALL);
suite!(torus6_f32, Torus<f32, 6>, f32, 6, PI_BALL);
suite!(so3_f64, So3<f64>, f64, 3, PI_BALL);
suite!(so3_f32, So3<f32>, f32, 3, PI_BALL);
suite!(rn3_f64, Rn<f64, 3>, f64, 3, 10.0);
suite!(rn3_f32, Rn<f32, 3>, f32, 3, 10.0);
suite!(joint7_f64, JointSpace<f64, 7>, f64, 7, PI_BALL);
suite!(joint7_f32, JointSpace<f32, 7>, f32, 7, PI_BALL);

/// The kinds of a mixed joint space: circular coordinates wrap in `log`, linear ones do not,
/// and the kinds survive composition with kind-less elements (identity, `exp`).
#[test]
fn joint_space_wraps_only_its_circular_coordinates() {
    use nalgebra::Vector3;
    let kinds = [JointKind::Circular, JointKind::Linear, JointKind::Circular];
    let q = JointSpace::new(Vector3::new(4.0, 4.0, -4.0), kinds);
    let two_pi = std::f64::consts::TAU;
    let expect = Vector3::new(4.0 - two_pi, 4.0, -4.0 + two_pi);
    assert!((q.log() - expect).norm() < 1e-12);
    let x_d = JointSpace::exp(&Vector3::new(1.0, 1.0, 1.0));
    let e = q.compose(&x_d.inverse());
    assert_eq!(e.kinds(), kinds);
    assert!((e.log() - Vector3::new(3.0, 3.0, -5.0 + two_pi)).norm() < 1e-12);
    assert_eq!(JointSpace::identity().compose(&q).kinds(), kinds);
    // Two configurations a full turn apart on a circular joint are the same element...
    let turned = JointSpace::new(Vector3::new(4.0 + two_pi, 4.0, -4.0), kinds);
    assert!(q.distance(&turned) < 1e-12);
    // ...but not on a linear one.
    let shifted = JointSpace::new(Vector3::new(4.0, 4.0 + two_pi, -4.0), kinds);
    assert!((q.distance(&shifted) - two_pi).abs() < 1e-12);
}

#[test]
fn so3_log_is_accurate_near_the_half_turn_and_near_identity() {
    for axis in [
        nalgebra::Vector3::new(1.0, 0.0, 0.0),
        nalgebra::Vector3::new(0.3, -0.5, 0.8),
    ] {
        let axis = axis.normalize();
        for angle in [1e-12, 1e-7, 1e-3, 1.0, std::f64::consts::PI - 1e-9] {
            let r = So3::<f64>::exp(&(axis * angle));
            let back = r.log();
            assert!(
                (back - axis * angle).norm() < 1e-12 * (1.0 + angle),
                "angle {angle}: {back:?}"
            );
            assert!(r.orthogonality_error() < 1e-14);
        }
    }
}

#[test]
fn so3_from_matrix_rejects_non_rotations() {
    use pvfc_core::ErrorKind;
    let m = nalgebra::Matrix3::new(1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert_eq!(
        So3::from_matrix(m, 1e-9).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    let reflect = nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, -1.0));
    assert_eq!(
        So3::from_matrix(reflect, 1e-9).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
    let nan = nalgebra::Matrix3::from_element(f64::NAN);
    assert_eq!(
        So3::from_matrix(nan, 1e-9).unwrap_err().kind(),
        ErrorKind::NonFinite
    );
    // A slightly drifted rotation is accepted and cleaned up.
    let drifted = So3::<f64>::exp(&nalgebra::Vector3::new(0.3, 0.2, 0.1)).matrix() * 1.000_000_1;
    let r = So3::from_matrix(drifted, 1e-5).unwrap();
    assert!(r.orthogonality_error() < 1e-13);
}
