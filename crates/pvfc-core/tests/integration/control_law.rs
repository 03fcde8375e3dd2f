//! The properties of the manual's control law, `docs/src/reference/control-law.md` §6, over random states, for every kind of system and for
//! both scalar types: skew-symmetry of G and R, passivity q̇_aᵀT_a = 0, wᵀV_a = 0, G V_a = w,
//! ½V_aᵀM_aV_a = Ē, invariance of q̇_a = βV_a, Proposition 1, and V̇ against finite
//! differences.

use crate::common;

use common::setups::*;
use common::{close, close_vec, f, vec, Tolerance, CASES};
use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;
use pvfc_core::obstacle::Obstacles;
use pvfc_core::prelude::*;
use pvfc_core::scalar::cast;
use std::result::Result;

/// A random state of the closed loop, as `f64` numbers (converted to each scalar type).
#[derive(Clone, Copy, Debug)]
struct Inputs<const D: usize> {
    q: [f64; D],
    v: [f64; D],
    tau: f64,
    tau_dot: f64,
    flywheel: f64,
    beta: f64,
    w: [f64; D],
    w_tau: f64,
}

fn inputs<const D: usize>(q_range: f64) -> impl Strategy<Value = Inputs<D>> {
    (
        proptest::array::uniform(-q_range..q_range),
        proptest::array::uniform(-3.0..3.0),
        -10.0..10.0,
        -2.0..2.0,
        -12.0..12.0,
        0.1..3.0,
        proptest::array::uniform(-2.0..2.0),
        -2.0..2.0,
    )
        .prop_map(|(q, v, tau, tau_dot, flywheel, beta, w, w_tau)| Inputs {
            q,
            v,
            tau,
            tau_dot,
            flywheel,
            beta,
            w,
            w_tau,
        })
}

fn params() -> impl Strategy<Value = Params> {
    (0.0..200.0, 0.0..2.0, proptest::array::uniform(0.3..3.0)).prop_map(|(r, gamma, h)| Params {
        r,
        gamma,
        h,
    })
}

fn state<T: Real, G: LieGroup<T, D>, const D: usize>(i: &Inputs<D>) -> AugmentedState<T, G, D> {
    AugmentedState {
        q: G::exp(&vec(i.q)),
        v: vec(i.v),
        tau: cast(i.tau),
        tau_dot: cast(i.tau_dot),
        flywheel_speed: cast(i.flywheel),
    }
}

fn skew_error<T: Real, const A: usize>(m: &SMatrix<T, A, A>) -> f64 {
    f((m + m.transpose()).norm()) / f(m.norm()).max(1e-300)
}

/// The algebraic properties of the coupling at one state.
fn coupling_properties<T, G, Sys, F, const D: usize, const A: usize>(
    law: &PvfcLaw<T, G, Sys, F, D>,
    s: &AugmentedState<T, G, D>,
    paced: bool,
) -> Result<(), String>
where
    T: Tolerance,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    F: VelocityField<T, G, D>,
{
    let tol = T::ROUNDING;
    let out = law.evaluate(s).map_err(|e| format!("evaluate: {e}"))?;
    let (g, r) = out.coupling_matrices::<A>().map_err(|e| e.to_string())?;
    let qa_aug = s.velocity();
    let qa = qa_aug.to_column::<A>().ok_or("A ≠ D + 2")?;
    let va = out.field_velocity.to_column::<A>().ok_or("A")?;
    let w = out.w.to_column::<A>().ok_or("A")?;
    let gamma = law.gamma();

    // Skew-symmetry of G and R (eq. 7).
    if skew_error(&g) > tol || skew_error(&r) > tol {
        return Err(format!(
            "G or R not skew: {:e} {:e}",
            skew_error(&g),
            skew_error(&r)
        ));
    }
    // The rank-two evaluation of the control step equals G q̇_a + γ R q̇_a.
    let t_mat = g * qa + r * qa * gamma;
    let t = out.torque.to_column::<A>().ok_or("A")?;
    let t_scale = f((g * qa).norm() + (r * qa).norm() * gamma) + 1e-300;
    close_vec(&t, &t_mat, tol * 10.0, t_scale, "T_a = G q̇_a + γ R q̇_a")?;
    // Passivity: q̇_aᵀ T_a = 0, relative to the size of the products that cancel in
    // q̇ᵀ(w Pᵀq̇ − P wᵀq̇)/2Ē + γ q̇ᵀ(P pᵀq̇ − p Pᵀq̇).
    let power = f(out.torque.dot(&qa_aug));
    let (nw, np, nm, nq) = (
        f(out.w.norm()),
        f(out.desired_momentum.norm()),
        f(out.momentum.norm()),
        f(qa.norm()),
    );
    let cancel = nq * nq * (nw * np / (2.0 * f(out.energy_level)) + f(gamma) * np * nm);
    close(power, 0.0, tol, cancel, "q̇_aᵀ T_a")?;
    // wᵀ V_a = 0 and G V_a = w.
    close(
        f(w.dot(&va)),
        0.0,
        tol * 10.0,
        f(w.norm() * va.norm()),
        "wᵀ V_a",
    )?;
    close_vec(
        &(g * va),
        &w,
        tol * 10.0,
        f(w.norm()) + f(g.norm() * va.norm()),
        "G V_a = w",
    )?;
    // The augmented field has energy Ē (eq. 6): ½ Pᵀ V_a = Ē.
    let e_field = f(out.desired_momentum.dot(&out.field_velocity)) * 0.5;
    close(
        e_field,
        f(out.energy_level),
        tol,
        f(out.energy_level),
        "½ V_aᵀ M_a V_a = Ē",
    )?;
    // κ_a and β. The law's momentum comes from the model's products (a serial chain's O(n)
    // recursion), the reference from `M(q)` (CRBA): two formula paths, so ten roundings.
    close(
        f(out.kinetic_energy),
        f(law.kinetic_energy(s)),
        tol * 10.0,
        f(out.kinetic_energy),
        "κ_a",
    )?;
    close(
        f(out.beta * out.beta * out.energy_level),
        f(out.kinetic_energy),
        tol * 10.0,
        f(out.kinetic_energy),
        "β² Ē = κ_a",
    )?;
    // W_β of eq. (12) from κ_a, β and Pᵀq̇_a equals ½ e_βᵀ M_a e_β = ½ (q̇_a − βV_a)ᵀ(p − βP),
    // and μ of eq. (13) is in [0, 1].
    let e = qa_aug - out.field_velocity * out.beta;
    let me = out.momentum - out.desired_momentum * out.beta;
    let w_direct = f(e.dot(&me)) * 0.5;
    close(
        f(out.velocity_field_error_energy()),
        w_direct,
        tol * 10.0,
        f(out.kinetic_energy) * 4.0,
        "W_β = ½‖q̇_a − βV_a‖²_a",
    )?;
    let mu = f(out.convergence_factor());
    if !(-tol..=1.0 + tol).contains(&mu) {
        return Err(format!("μ = {mu} outside [0, 1]"));
    }
    // The augmented field carries the field's V_I (scaled by the law's bound on the field's
    // energy, if it has one), and the self-pacing gains.
    close(
        f(out.field_velocity.tau),
        f(out.field.velocity_tau * out.field_scale),
        tol,
        1.0,
        "V_a's τ entry = V_I",
    )?;
    // Eq. (21)'s gains; a pace profile scales λ₁ alone (its own test below).
    if !paced {
        close(
            f(out.field.lambda1 + out.field.lambda2),
            2.0,
            tol,
            1.0,
            "λ₁ + λ₂ = 2",
        )?;
    }
    Ok(())
}

/// Proposition 1 at one state: E_*V = −λ₂ grad U, and U decreases along the field.
fn proposition_1<T, G, X, N, S, Sys, const D: usize>(
    law: &PvfcLaw<T, G, Sys, SuspendedField<T, G, X, N, S, D>, D>,
    s: &AugmentedState<T, G, D>,
) -> Result<(), String>
where
    T: Tolerance,
    G: LieGroup<T, D>,
    X: Contour<T, G, D>,
    N: NavigationFunction<T, G, D>,
    S: SelfPacing<T>,
    Sys: MechanicalSystem<T, G, D>,
{
    let field = law.field();
    let fs = field.evaluate(&s.q, &s.v, s.tau, s.tau_dot);
    close(
        f(fs.velocity_tau),
        f(fs.lambda1),
        T::ROUNDING,
        1.0,
        "V_I = λ₁",
    )?;
    let ev = field.error_pushforward(&s.q, s.tau, &fs.velocity, fs.velocity_tau);
    let scale = 1.0 + f(fs.velocity.norm()) + f(fs.contour.velocity.norm());
    close_vec(
        &ev,
        &(fs.gradient * -fs.lambda2),
        T::ROUNDING * 10.0,
        scale,
        "E_*V = −λ₂ grad U",
    )?;
    let nav = field.navigation().evaluate(&fs.error, &ev);
    let k = field.navigation().metric_weight();
    // d/dt U(E) along the field = −λ₂ ⟨⟨grad U, grad U⟩⟩_V ≤ 0 (eq. 20).
    close(
        f(nav.value_rate),
        f(-fs.lambda2 * k * fs.gradient.norm_squared()),
        T::ROUNDING * 10.0,
        scale * (1.0 + f(nav.differential.norm())),
        "U̇ = −λ₂‖grad U‖²",
    )?;
    if f(nav.value_rate) > T::ROUNDING * scale {
        return Err(format!(
            "U increases along the field: {:e}",
            f(nav.value_rate)
        ));
    }
    Ok(())
}

/// Fourth-order central difference (Richardson) of a vector function of one variable.
fn derivative<const N: usize>(g: impl Fn(f64) -> SVector<f64, N>, h: f64) -> SVector<f64, N> {
    let d = |h: f64| (g(h) - g(-h)) / (2.0 * h);
    (d(h / 2.0) * 4.0 - d(h)) / 3.0
}

/// The paper's field around obstacles `O` (none by default), in `f64`.
type Field<G, X, N, S, O, const D: usize> = SuspendedField<f64, G, X, N, S, D, O>;

/// The analytic derivatives against finite differences (f64): V̇, E_*, the navigation
/// function's differential and gradient rate, and the invariance of q̇_a = βV_a with the
/// required torque computed independently from the plant model.
fn derivatives<G, X, N, S, O, Sys, const D: usize>(
    law: &PvfcLaw<f64, G, Sys, Field<G, X, N, S, O, D>, D>,
    s: &AugmentedState<f64, G, D>,
    i: &Inputs<D>,
) -> Result<(), String>
where
    G: LieGroup<f64, D>,
    X: Contour<f64, G, D>,
    N: NavigationFunction<f64, G, D>,
    S: SelfPacing<f64>,
    O: Obstacles<f64, G, D>,
    Sys: MechanicalSystem<f64, G, D>,
{
    let field = law.field();
    let h = 1e-4;
    let tol = 1e-7;
    let fs = field.evaluate(&s.q, &s.v, s.tau, s.tau_dot);
    // V̄̇ along q̄̇ = (v, τ̇).
    let along = |t: f64| {
        let q = s.q.retract(&s.v, t);
        let x = field.evaluate(&q, &s.v, s.tau + t * s.tau_dot, s.tau_dot);
        let mut out = SVector::<f64, 8>::zeros();
        out.fixed_rows_mut::<D>(0).copy_from(&x.velocity);
        out[D] = x.velocity_tau;
        out
    };
    let fd = derivative(along, h);
    // The finite difference's own error, from a second step size: near a knot of a spline
    // contour (C², x_d''' jumps) Richardson's extrapolation loses its order.
    let fd_error = (fd - derivative(along, h / 4.0)).norm();
    let allowed = tol * (1.0 + fd.norm()) + 10.0 * fd_error;
    close_vec(
        &fd.fixed_rows::<D>(0).into_owned(),
        &fs.rate,
        1.0,
        allowed,
        "V̇_G vs finite differences",
    )?;
    close(
        fd[D],
        fs.rate_tau,
        1.0,
        allowed,
        "V̇_I vs finite differences",
    )?;

    // E_* against the derivative of E along a random direction W.
    let w = vec::<f64, D>(i.w);
    let e0 = fs.error;
    let err_along = |t: f64| {
        let q = s.q.retract(&w, t);
        e0.inverse()
            .compose(&field.error(&q, s.tau + t * i.w_tau))
            .log()
    };
    let fd = derivative(err_along, h);
    let fd_error = (fd - derivative(err_along, h / 4.0)).norm();
    let an = field.error_pushforward(&s.q, s.tau, &w, i.w_tau);
    close_vec(
        &fd,
        &an,
        1.0,
        tol * (1.0 + fd.norm()) + 10.0 * fd_error,
        "E_*W vs finite differences (Lemma 1)",
    )?;

    // The navigation function: dU and the rate of grad U along the error's motion.
    let nav = field.navigation();
    let eps = fs.error_velocity;
    let ns = nav.evaluate(&e0, &eps);
    let u_along = |t: f64| SVector::<f64, 1>::new(nav.value(&e0.retract(&eps, t)));
    close(
        derivative(u_along, h)[0],
        ns.value_rate,
        tol,
        1.0 + ns.differential.norm() * eps.norm(),
        "dU·ε vs finite differences",
    )?;
    let g_along = |t: f64| nav.gradient(&e0.retract(&eps, t));
    close_vec(
        &derivative(g_along, h),
        &ns.gradient_rate,
        tol,
        1.0 + ns.gradient_rate.norm(),
        "d/dt grad U vs finite differences",
    )?;
    close_vec(
        &(ns.differential / nav.metric_weight()),
        &ns.gradient,
        1e-12,
        1.0 + ns.gradient.norm(),
        "grad U = dU / k",
    )?;

    // Invariance: at q̇_a = βV_a the coupling torque is exactly the torque that keeps it
    // there, M_a d/dt(βV_a) + C_a βV_a, with d/dt V_a by finite differences and M, C from the
    // plant model.
    let out0 = law.evaluate(s).map_err(|e| e.to_string())?;
    let va = out0.field_velocity;
    let beta = i.beta;
    let on_field = AugmentedState {
        q: s.q,
        v: va.robot * beta,
        tau: s.tau,
        tau_dot: va.tau * beta,
        flywheel_speed: va.flywheel * beta,
    };
    let out = law.evaluate(&on_field).map_err(|e| e.to_string())?;
    close(out.beta, beta, 1e-12, beta, "β on the field")?;
    let va_along = |t: f64| {
        let st = AugmentedState {
            q: s.q.retract(&va.robot, beta * t),
            tau: s.tau + va.tau * beta * t,
            ..on_field
        };
        let o = law
            .evaluate(&st)
            .map(|o| o.field_velocity)
            .unwrap_or(AugmentedVector::zeros());
        let mut col = SVector::<f64, 8>::zeros();
        col.fixed_rows_mut::<D>(0).copy_from(&o.robot);
        col[D] = o.tau;
        col[D + 1] = o.flywheel;
        col
    };
    let dva = derivative(va_along, h);
    // The finite difference's own error, estimated from a second step size: where the flow
    // crosses a knot of a spline contour (C², so x_d''' jumps) Richardson's extrapolation loses
    // its order, and the reference is only as good as this estimate.
    let fd_error = (dva - derivative(va_along, h / 4.0)).norm();
    let sys = law.system();
    let m = sys.inertia(&s.q);
    let c = sys.coriolis(&s.q, &on_field.v);
    let required_robot = m * dva.fixed_rows::<D>(0).into_owned() * beta + c * va.robot * beta;
    let required_tau = dva[D] * beta;
    let required_fly = law.flywheel().inertia() * dva[D + 1] * beta;
    let scale = 1.0 + required_robot.norm() + required_tau.abs() + required_fly.abs();
    let allowed =
        tol * scale + 10.0 * fd_error * beta * (1.0 + m.norm() + law.flywheel().inertia());
    close_vec(
        &out.torque.robot,
        &required_robot,
        1.0,
        allowed,
        "invariance: robot torque",
    )?;
    close(
        out.torque.tau,
        required_tau,
        1.0,
        allowed,
        "invariance: τ torque",
    )?;
    close(
        out.torque.flywheel,
        required_fly,
        1.0,
        allowed,
        "invariance: flywheel torque",
    )?;

    // The plant: Ṁ − 2C is skew, with Ṁ by finite differences.
    let m_along = |t: f64| {
        let mt = sys.inertia(&s.q.retract(&s.v, t));
        SVector::<f64, 16>::from_fn(|k, _| if k < D * D { mt[(k / D, k % D)] } else { 0.0 })
    };
    let md = derivative(m_along, h);
    let m_dot = SMatrix::<f64, D, D>::from_fn(|r, cc| md[r * D + cc]);
    let cc = sys.coriolis(&s.q, &s.v);
    let skew = m_dot - cc * 2.0;
    close(
        (skew + skew.transpose()).norm(),
        0.0,
        tol,
        1.0 + m_dot.norm() + cc.norm(),
        "Ṁ − 2C skew",
    )?;
    close_vec(
        &(sys.inertia_rate(&s.q, &s.v) * s.v),
        &(m_dot * s.v),
        tol,
        1.0 + m_dot.norm() * s.v.norm(),
        "inertia_rate",
    )?;
    Ok(())
}

/// The f32 implementation agrees with the f64 one at the same inputs.
fn f32_matches_f64<const D: usize>(
    a: &CouplingOutput<f32, impl Sized, D>,
    b: &CouplingOutput<f64, impl Sized, D>,
) -> Result<(), String> {
    let tol = 2e-3;
    let ta: SVector<f64, D> = a.torque.robot.map(|x| x as f64);
    let scale = 1.0 + b.torque.norm();
    close_vec(&ta, &b.torque.robot, tol, scale, "f32 vs f64: robot torque")?;
    close(
        a.torque.tau as f64,
        b.torque.tau,
        tol,
        scale,
        "f32 vs f64: τ torque",
    )?;
    close(
        a.torque.flywheel as f64,
        b.torque.flywheel,
        tol,
        scale,
        "f32 vs f64: flywheel torque",
    )?;
    let ra: SVector<f64, D> = a.field.rate.map(|x| x as f64);
    close_vec(
        &ra,
        &b.field.rate,
        tol,
        1.0 + b.field.rate.norm(),
        "f32 vs f64: V̇",
    )?;
    close(
        a.field.potential as f64,
        b.field.potential,
        tol,
        1.0,
        "f32 vs f64: U",
    )?;
    Ok(())
}

/// Every state is admissible for a system without obstacles.
fn anywhere<const D: usize>(_: &Inputs<D>) -> bool {
    true
}

macro_rules! law_suite {
    ($module:ident, $build:ident, $g64:ty, $g32:ty, $d:literal, $a:literal, $qrange:expr) => {
        law_suite!($module, $build, $g64, $g32, $d, $a, $qrange, anywhere, proposition_1, false);
    };
    ($module:ident, $build:ident, $g64:ty, $g32:ty, $d:literal, $a:literal, $qrange:expr, $admit:ident, $field_property:ident) => {
        law_suite!($module, $build, $g64, $g32, $d, $a, $qrange, $admit, $field_property, false);
    };
    ($module:ident, $build:ident, $g64:ty, $g32:ty, $d:literal, $a:literal, $qrange:expr, $admit:ident, $field_property:ident, $paced:expr) => {
        mod $module {
            use super::*;
            proptest! {
                #![proptest_config(ProptestConfig { max_global_rejects: CASES * 4, ..ProptestConfig::with_cases(CASES) })]

                #[test]
                fn coupling_f64(i in inputs::<$d>($qrange), p in params()) {
                    prop_assume!($admit(&i));
                    let law = $build::<f64>(p);
                    let s = state::<f64, $g64, $d>(&i);
                    let r = coupling_properties::<f64, _, _, _, $d, $a>(&law, &s, $paced).and_then(|_| $field_property(&law, &s));
                    prop_assert!(r.is_ok(), "{}", r.unwrap_err());
                }

                #[test]
                fn coupling_f32(i in inputs::<$d>($qrange), p in params()) {
                    prop_assume!($admit(&i));
                    let law = $build::<f32>(p);
                    let s = state::<f32, $g32, $d>(&i);
                    let r = coupling_properties::<f32, _, _, _, $d, $a>(&law, &s, $paced).and_then(|_| $field_property(&law, &s));
                    prop_assert!(r.is_ok(), "{}", r.unwrap_err());
                }

                #[test]
                fn derivatives_and_invariance_f64(i in inputs::<$d>($qrange), p in params()) {
                    prop_assume!($admit(&i));
                    let law = $build::<f64>(p);
                    let s = state::<f64, $g64, $d>(&i);
                    let r = derivatives(&law, &s, &i);
                    prop_assert!(r.is_ok(), "{}", r.unwrap_err());
                }

                #[test]
                fn f32_agrees_with_f64(i in inputs::<$d>($qrange), p in params()) {
                    prop_assume!($admit(&i));
                    let a = $build::<f32>(p).evaluate(&state::<f32, $g32, $d>(&i));
                    let b = $build::<f64>(p).evaluate(&state::<f64, $g64, $d>(&i));
                    let r = match (a, b) {
                        (Ok(a), Ok(b)) => f32_matches_f64(&a, &b),
                        (a, b) => Err(format!("{:?} / {:?}", a.err(), b.err())),
                    };
                    prop_assert!(r.is_ok(), "{}", r.unwrap_err());
                }
            }
        }
    };
}

const PI: f64 = std::f64::consts::PI;
law_suite!(scara_lissajous_right, scara_lissajous, Torus<f64, 2>, Torus<f32, 2>, 2, 4, PI);
// The pace profile along the contour (`pvfc_core::pace`): every property above, Proposition 1
// included, for λ₁ = σ(τ) λ₁(U), and V̇ with its ∂λ₁/∂τ term against finite differences.
law_suite!(
    scara_paced,
    scara_paced,
    Torus<f64, 2>,
    Torus<f32, 2>,
    2,
    4,
    PI,
    anywhere,
    proposition_1,
    true
);
// The field bounded in energy (the bound bites at most of these states): every coupling
// property, the invariance of q̇_a = βV_a with the bounded field's rate against finite
// differences, and the bound itself.
law_suite!(
    scara_bounded_field,
    scara_bounded,
    Torus<f64, 2>,
    Torus<f32, 2>,
    2,
    4,
    PI,
    anywhere,
    bounded_field
);
law_suite!(scara_spline_left, scara_spline, Torus<f64, 2>, Torus<f32, 2>, 2, 4, PI);
law_suite!(
    rigid_body_spin_right,
    body_spin,
    So3<f64>,
    So3<f32>,
    3,
    5,
    1.8
);
law_suite!(
    rigid_body_spline_left,
    body_spline,
    So3<f64>,
    So3<f32>,
    3,
    5,
    1.8
);
law_suite!(linear_stage, stage, Rn<f64, 3>, Rn<f32, 3>, 3, 5, 2.0);
law_suite!(
    rail_arm_mixed_joints,
    rail_arm_ellipse,
    JointSpace<f64, 4>,
    JointSpace<f32, 4>,
    4,
    6,
    2.5
);

/// A field bounded in energy (`PvfcLaw::set_field_energy_bound`): its kinetic energy
/// `½V̄ᵀM̄V̄` at most the bound, on it wherever the field was scaled, and the flywheel's part
/// `(1 − share)Ē`; unscaled, the law's output equals the unbounded law's to the bit. (Its
/// rate, with the scale's own rate, is checked by the invariance of `q̇_a = βV_a` above,
/// against finite differences of the bounded field.)
fn bounded_field<T, G>(law: &ScaraLissajous<T>, s: &AugmentedState<T, G, 2>) -> Result<(), String>
where
    T: Real + Tolerance,
    G: LieGroup<T, 2>,
    ScaraLissajous<T>: BoundedFieldLaw<T, G>,
{
    law.check_bound(s)
}

/// The bounded law's check, on the SCARA's torus (the suite's group).
trait BoundedFieldLaw<T: Real, G> {
    fn check_bound(&self, s: &AugmentedState<T, G, 2>) -> Result<(), String>;
}

impl<T: Real + Tolerance> BoundedFieldLaw<T, Torus<T, 2>> for ScaraLissajous<T> {
    fn check_bound(&self, s: &AugmentedState<T, Torus<T, 2>, 2>) -> Result<(), String> {
        let share = self.field_energy_bound().ok_or("no bound")?;
        let e_bar = self.flywheel().energy();
        let out = self.evaluate(s).map_err(|e| e.to_string())?;
        let va = out.field_velocity;
        let p = out.desired_momentum;
        let kappa = f(p.robot.dot(&va.robot) + va.tau * va.tau) * 0.5;
        let cap = f(share * e_bar);
        let tol = T::ROUNDING * 100.0;
        if kappa > cap * (1.0 + tol) {
            return Err(format!("½V̄ᵀM̄V̄ = {kappa} above the bound {cap}"));
        }
        let scale = f(out.field_scale);
        if !(scale > 0.0 && scale <= 1.0) {
            return Err(format!("field scale {scale}"));
        }
        let unbounded = PvfcLaw::new(
            *self.system(),
            *self.field(),
            *self.flywheel(),
            self.gamma(),
        )
        .map_err(|e| e.to_string())?;
        match unbounded.evaluate(s) {
            Ok(free) if scale == 1.0 => {
                if free.torque != out.torque || free.field_velocity != va {
                    return Err(
                        "within the bound the output differs from the unbounded law's".into(),
                    );
                }
            }
            // The unbounded field may be beyond Ē itself (EnergyTooLow): then it was scaled.
            _ => {
                close(kappa, cap, tol, cap, "½V̄ᵀM̄V̄ on the bound")?;
                let fly = f(self.flywheel().inertia() * va.flywheel * va.flywheel) * 0.5;
                close(
                    fly,
                    f(e_bar) - cap,
                    tol,
                    f(e_bar),
                    "the flywheel's (1 − share)Ē",
                )?;
                close(
                    f(out.w.flywheel),
                    0.0,
                    tol,
                    1.0 + f(out.w.norm()),
                    "w_F on the bound",
                )?;
            }
        }
        Ok(())
    }
}

/// Around obstacles the field is not eq. (30)'s: its own properties are the derivatives
/// (above) and the composition's, tested in `obstacles.rs`.
fn around_obstacles<T: Real, G: LieGroup<T, D>, Law, const D: usize>(
    _: &Law,
    _: &AugmentedState<T, G, D>,
) -> Result<(), String> {
    Ok(())
}

/// States clear of the obstacles (inside one, the barrier is clamped at 0).
fn clear_of_scara_obstacles(i: &Inputs<2>) -> bool {
    scara_obstacle_set::<f64>()
        .clearance(&vec(i.q))
        .is_some_and(|c| c > 0.02)
}

fn clear_of_rail_arm_obstacles(i: &Inputs<4>) -> bool {
    rail_arm_obstacle_set::<f64>()
        .clearance(&vec(i.q))
        .is_some_and(|c| c > 0.02)
}

law_suite!(
    scara_around_obstacles,
    scara_obstacles,
    Torus<f64, 2>,
    Torus<f32, 2>,
    2,
    4,
    PI,
    clear_of_scara_obstacles,
    around_obstacles
);
law_suite!(
    rail_arm_around_obstacles,
    rail_arm_obstacles,
    JointSpace<f64, 4>,
    JointSpace<f32, 4>,
    4,
    6,
    2.5,
    clear_of_rail_arm_obstacles,
    around_obstacles
);
