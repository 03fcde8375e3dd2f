//! `SerialChain`: the rigid-body algorithms against identities and finite differences, over
//! random chains (mixed revolute and prismatic joints, arbitrary frames) and random states.
//! (Pinocchio checks the same quantities on real URDFs from Python: `test_pinocchio.py`.)

use crate::common;

use common::{close, f};
use nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;
use pvfc_core::lie::{JointKind, Torus};
use pvfc_core::mechanics::{
    ChainJoint, MechanicalSystem, Pose, RigidInertia, Scara, ScaraParameters, SerialChain,
};
use pvfc_core::scalar::cast;
use pvfc_core::ErrorKind;

const CASES: u32 = 500;

/// Numbers in `[-1, 1)` drawn by proptest, turned into a chain and a state.
#[derive(Clone, Debug)]
struct Draw(Vec<f64>);

impl Draw {
    fn take(&mut self) -> f64 {
        self.0.pop().unwrap_or(0.3)
    }
    fn v3(&mut self, scale: f64) -> Vector3<f64> {
        Vector3::new(self.take(), self.take(), self.take()) * scale
    }
}

/// A random chain with `N` joints: random origins, axes, kinds (about one in four prismatic,
/// or none), masses, centres of mass and physically consistent inertias.
fn random_chain<const N: usize>(d: &mut Draw, prismatic: bool) -> SerialChain<f64, N> {
    let joints = core::array::from_fn(|_| {
        let kind = if prismatic && d.take() > 0.5 {
            JointKind::Linear
        } else {
            JointKind::Circular
        };
        let xyz = d.v3(0.3);
        let rpy = d.v3(3.0);
        let mut axis = d.v3(1.0);
        if axis.norm() < 0.1 {
            axis = Vector3::z();
        }
        ChainJoint {
            kind,
            origin: Pose::from_xyz_rpy(xyz.into(), rpy.into()),
            axis,
        }
    });
    let links = core::array::from_fn(|_| {
        let mass = 0.5 + 5.0 * (d.take() + 1.0);
        // Principal moments satisfying the triangle inequality, in a random orientation.
        let (a, b) = (0.02 + 0.1 * (d.take() + 1.0), 0.02 + 0.1 * (d.take() + 1.0));
        let c = (a - b).abs() + 0.01 + 0.1 * (d.take() + 1.0) * (a + b - (a - b).abs()) / 3.0;
        let r = Pose::<f64>::from_xyz_rpy([0.0; 3], d.v3(3.0).into()).rotation;
        RigidInertia {
            mass,
            com: d.v3(0.2),
            inertia: r * Matrix3::from_diagonal(&Vector3::new(a, b, c)) * r.transpose(),
        }
    });
    SerialChain::new(joints, links)
        .unwrap()
        .with_tool(Pose::from_xyz_rpy(d.v3(0.1).into(), d.v3(3.0).into()))
        .unwrap()
}

fn state<const N: usize>(d: &mut Draw) -> (SVector<f64, N>, SVector<f64, N>) {
    (
        SVector::from_fn(|_, _| 3.0 * d.take()),
        SVector::from_fn(|_, _| 2.0 * d.take()),
    )
}

fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / (1.0 + b.amax())
}

/// `Ṁ` by a 4th-order central difference of `M(q + h v)`.
fn inertia_rate_fd<const N: usize>(
    chain: &SerialChain<f64, N>,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> SMatrix<f64, N, N> {
    let m = |t: f64| chain.dynamics(&(q + v * t), &SVector::zeros()).0;
    let h = 1e-3;
    (m(-2.0 * h) - m(-h) * 8.0 + m(h) * 8.0 - m(2.0 * h)) / (12.0 * h)
}

/// All the identities at one chain and state.
fn identities<const N: usize>(d: &mut Draw, prismatic: bool) -> Result<(), String> {
    let chain = random_chain::<N>(d, prismatic);
    let (q, v) = state::<N>(d);
    let (m, c, g) = chain.dynamics(&q, &v);
    // CRBA alone gives the same M as the combined pass.
    close(
        rel(&chain.crba(&q), &m),
        0.0,
        1e-14,
        1.0,
        "crba = dynamics' M",
    )?;
    // M symmetric positive definite.
    close(rel(&m, &m.transpose()), 0.0, 1e-14, 1.0, "M symmetric")?;
    if m.cholesky().is_none() {
        return Err("M not positive definite".into());
    }
    // Ṁ = C + Cᵀ against finite differences (the FD error is ~h⁴).
    close(
        rel(&(c + c.transpose()), &inertia_rate_fd(&chain, &q, &v)),
        0.0,
        1e-8,
        1.0,
        "Ṁ = C + Cᵀ",
    )?;
    // C is linear in v with symmetric Christoffel symbols: C(q, e_k) e_j = C(q, e_j) e_k.
    let unit = |i: usize| SVector::<f64, N>::from_fn(|r, _| if r == i { 1.0 } else { 0.0 });
    let cols: [SMatrix<f64, N, N>; N] = core::array::from_fn(|k| chain.dynamics(&q, &unit(k)).1);
    let mut c_lin = SMatrix::<f64, N, N>::zeros();
    for k in 0..N {
        c_lin += cols[k] * v[k];
        for j in 0..N {
            let a = cols[k] * unit(j);
            let b = cols[j] * unit(k);
            close((a - b).amax(), 0.0, 1e-12, 1.0 + a.amax(), "Γ_ijk = Γ_ikj")?;
        }
    }
    close(rel(&c, &c_lin), 0.0, 1e-12, 1.0, "C linear in v")?;
    // RNEA: C v + g = rnea(q, v, 0), M a = rnea(q, 0, a) − g.
    let zero = SVector::zeros();
    let a: SVector<f64, N> = SVector::from_fn(|i, _| (i as f64 * 0.7).sin());
    let rnea_v = chain.rnea(&q, &v, &zero);
    close(
        (c * v + g - rnea_v).amax(),
        0.0,
        1e-12,
        1.0 + rnea_v.amax(),
        "C v + g = RNEA(q, v, 0)",
    )?;
    // The forward dynamics' pass: CRBA's M and RNEA's bias, each to the bit.
    let (m_fd, h) = chain.mass_and_bias(&q, &v);
    if m_fd != chain.crba(&q) || h != rnea_v {
        return Err("mass_and_bias is not (CRBA, RNEA(q, v, 0)) to the bit".into());
    }
    let rnea_a = chain.rnea(&q, &zero, &a);
    close(
        (m * a + g - rnea_a).amax(),
        0.0,
        1e-12,
        1.0 + rnea_a.amax(),
        "M a + g = RNEA(q, 0, a)",
    )?;
    // g = ∂V/∂q with V = −Σ m_i gᵀ c_i.
    let potential = |q: &SVector<f64, N>| {
        let k = chain.kinematics(q);
        (0..N)
            .map(|i| {
                let l = &chain.links()[i];
                -l.mass
                    * chain
                        .gravity_vector()
                        .dot(&k.link_poses[i].transform_point(&l.com))
            })
            .sum::<f64>()
    };
    let h = 1e-5;
    for i in 0..N {
        let dq = unit(i) * h;
        let fd = (potential(&(q + dq)) - potential(&(q - dq))) / (2.0 * h);
        close(g[i], fd, 1e-7, 1.0 + g.amax(), "g = ∂V/∂q")?;
    }
    close(
        (chain.gravity_torque(&q) - g).amax(),
        0.0,
        1e-13,
        1.0 + g.amax(),
        "gravity_torque = dynamics' g",
    )?;
    // The Jacobian against finite differences of the tool pose along v.
    let jac = chain.tool_jacobian_world(&q);
    let pose = |t: f64| chain.tool_pose(&(q + v * t));
    let (p0, pp, pm) = (pose(0.0), pose(h), pose(-h));
    let lin = (pp.translation - pm.translation) / (2.0 * h);
    let rdot = (pp.rotation - pm.rotation) / (2.0 * h);
    let w = rdot * p0.rotation.transpose(); // ω̂ in world axes
    let ang = Vector3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
    let jv = jac * v;
    let scale = 1.0 + jv.amax();
    close(
        (jv.fixed_rows::<3>(0) - lin).amax(),
        0.0,
        1e-7,
        scale,
        "J_world v: linear",
    )?;
    close(
        (jv.fixed_rows::<3>(3) - ang).amax(),
        0.0,
        1e-7,
        scale,
        "J_world v: angular",
    )?;
    let body = chain.tool_jacobian_body(&q) * v;
    let rt = p0.rotation.transpose();
    close(
        (body.fixed_rows::<3>(0) - rt * lin).amax(),
        0.0,
        1e-7,
        scale,
        "J_body v: linear",
    )?;
    // The coupling law's products by the O(N) recursion equal those with M, C and g, at a
    // reference velocity x and rate a unrelated to v.
    let (x, a) = state::<N>(d);
    for with_gravity in [false, true] {
        let p = chain.law_products(&q, &v, &x, &a, with_gravity);
        let scale = 1.0 + m.amax() * (1.0 + v.amax() + x.amax() + a.amax());
        close(
            (p.momentum - m * v).amax(),
            0.0,
            1e-13,
            scale,
            "law products: M v",
        )?;
        close(
            (p.field_momentum - m * x).amax(),
            0.0,
            1e-13,
            scale,
            "law products: M x",
        )?;
        let w = m * a + c * x;
        close(
            (p.w - w).amax(),
            0.0,
            1e-13,
            scale * (1.0 + v.amax()),
            "law products: M a + C x",
        )?;
        let expect = if with_gravity { g } else { SVector::zeros() };
        close(
            (p.gravity - expect).amax(),
            0.0,
            1e-13,
            1.0 + g.amax(),
            "law products: g",
        )?;
    }
    // Kinetic energy from the links' spatial velocities, ½ Σ v_iᵀ I_i v_i = ½ q̇ᵀ M q̇.
    let k = chain.kinematics(&q);
    let mut vel = SVector::<f64, 6>::zeros();
    let mut ke = 0.0;
    for i in 0..N {
        vel += k.axes[i] * v[i];
        let inertia = chain.links()[i].transformed(&k.link_poses[i]).spatial();
        ke += 0.5 * vel.dot(&(inertia * vel));
    }
    close(ke, 0.5 * v.dot(&(m * v)), 1e-12, 1.0 + ke, "½ q̇ᵀ M q̇")?;
    Ok(())
}

fn draws(n: usize) -> impl Strategy<Value = Draw> {
    proptest::collection::vec(-1.0f64..1.0, n).prop_map(Draw)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, ..ProptestConfig::default() })]

    #[test]
    fn identities_revolute_6(mut d in draws(230)) {
        identities::<6>(&mut d, false).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn identities_mixed_7(mut d in draws(280)) {
        identities::<7>(&mut d, true).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn identities_mixed_3(mut d in draws(140)) {
        identities::<3>(&mut d, true).map_err(TestCaseError::fail)?;
    }
}

/// The SCARA of `models/scara.urdf`'s shape, built as a chain, against the closed form.
#[test]
fn scara_chain_matches_the_closed_form() {
    let p = ScaraParameters::<f64>::pelican();
    let chain = p.chain().unwrap();
    let scara = Scara::new(p).unwrap();
    for k in 0..200 {
        let t = k as f64 * 0.37;
        let q = Torus::new(Vector2::new(t.sin() * 3.0, (1.3 * t).cos() * 3.0));
        let v = Vector2::new((0.7 * t).cos() * 2.0, t.sin() * 5.0);
        let (m1, c1) = scara.inertia_and_coriolis(&q, &v);
        let (m2, c2) =
            MechanicalSystem::<f64, Torus<f64, 2>, 2>::inertia_and_coriolis(&chain, &q, &v);
        assert!((m1 - m2).amax() <= 1e-12 * m1.amax(), "M {m1} vs {m2}");
        assert!(
            (c1 - c2).amax() <= 1e-12 * (1.0 + c1.amax()),
            "C {c1} vs {c2}"
        );
        // The axis is vertical: gravity does no work.
        assert!(chain.gravity_torque(q.angles()).amax() < 1e-12);
    }
}

/// f32 agrees with f64 to single precision.
#[test]
fn f32_chain_agrees_with_f64() {
    let mut d = Draw((0..200).map(|i| ((i as f64) * 1.618).sin()).collect());
    let c64 = random_chain::<6>(&mut d, true);
    let conv = |x: f64| cast::<f32>(x);
    let joints = c64.joints().map(|j| ChainJoint {
        kind: j.kind,
        origin: Pose {
            rotation: j.origin.rotation.map(conv),
            translation: j.origin.translation.map(conv),
        },
        axis: j.axis.map(conv),
    });
    let links = c64.links().map(|l| RigidInertia {
        mass: conv(l.mass),
        com: l.com.map(conv),
        inertia: l.inertia.map(conv),
    });
    let c32 = SerialChain::new(joints, links).unwrap();
    let (q, v) = state::<6>(&mut d);
    let (m64, cc64, g64) = c64.dynamics(&q, &v);
    let (m32, cc32, g32) = c32.dynamics(&q.map(conv), &v.map(conv));
    let up = |m: SMatrix<f32, 6, 6>| m.map(f);
    assert!(rel(&up(m32), &m64) < 1e-5);
    assert!(rel(&up(cc32), &cc64) < 1e-5);
    assert!((g32.map(f) - g64).amax() < 1e-4 * (1.0 + g64.amax()));
}

#[test]
fn bad_chains_are_typed_errors() {
    let good_joint = ChainJoint {
        kind: JointKind::Circular,
        origin: Pose::<f64>::identity(),
        axis: Vector3::z(),
    };
    let good_link = RigidInertia {
        mass: 1.0,
        com: Vector3::zeros(),
        inertia: Matrix3::identity(),
    };
    let zero_axis = ChainJoint {
        axis: Vector3::zeros(),
        ..good_joint
    };
    let e = SerialChain::new([good_joint, zero_axis], [good_link; 2]).unwrap_err();
    assert_eq!(
        (e.kind(), e.value()),
        (ErrorKind::InvalidParameter, Some(1.0))
    );
    let nan = ChainJoint {
        axis: Vector3::new(f64::NAN, 0.0, 1.0),
        ..good_joint
    };
    assert_eq!(
        SerialChain::new([nan], [good_link]).unwrap_err().kind(),
        ErrorKind::NonFinite
    );
    let massless = RigidInertia {
        mass: 0.0,
        ..good_link
    };
    assert_eq!(
        SerialChain::new([good_joint], [massless])
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidParameter
    );
    let indefinite = RigidInertia {
        inertia: Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0)),
        ..good_link
    };
    assert_eq!(
        SerialChain::new([good_joint], [indefinite])
            .unwrap_err()
            .kind(),
        ErrorKind::SingularInertia
    );
    let skewed = ChainJoint {
        origin: Pose {
            rotation: Matrix3::identity() * 2.0,
            translation: Vector3::zeros(),
        },
        ..good_joint
    };
    assert_eq!(
        SerialChain::new([skewed], [good_link]).unwrap_err().kind(),
        ErrorKind::InvalidParameter
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    /// The ten-number world inertia is the 6×6 spatial inertia of Featherstone eq. 2.63 of the
    /// body moved to its pose; applying it is the matrix product; `v ×* f` without forming
    /// `v×*` is the 6×6 product.
    #[test]
    fn the_world_inertia_is_the_spatial_inertia(mut d in draws(40)) {
        let chain = random_chain::<1>(&mut d, false);
        let body = chain.links()[0];
        let pose = Pose { rotation: pvfc_core::mechanics::axis_angle(&d.v3(1.0).normalize(), d.take() * 3.0), translation: d.v3(1.0) };
        let w = pvfc_core::mechanics::WorldInertia::of(&body, &pose);
        let reference = body.transformed(&pose).spatial();
        let scale = 1.0 + reference.amax();
        prop_assert!((w.matrix() - reference).amax() <= 1e-14 * scale);
        let v = SVector::<f64, 6>::from_fn(|_, _| d.take());
        let f6 = SVector::<f64, 6>::from_fn(|_, _| d.take());
        prop_assert!((w.apply(&v) - reference * v).amax() <= 1e-14 * scale);
        let fx = pvfc_core::mechanics::force_cross_apply(&v, &f6);
        prop_assert!((fx - pvfc_core::mechanics::force_cross(&v) * f6).amax() <= 1e-15 * 4.0);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    /// The forward kinematics, which takes every joint's sine and cosine first on a host (and
    /// joint by joint on a microcontroller), is the plain pose recursion with Rodrigues'
    /// `axis_angle` inside it, to the bit: the same operations on the same values.
    #[test]
    fn the_kinematics_is_the_pose_recursion_to_the_bit(mut d in draws(200)) {
        let chain = random_chain::<5>(&mut d, true);
        let (q, _) = state::<5>(&mut d);
        let k = chain.kinematics(&q);
        let mut parent = Pose::identity();
        for (i, j) in chain.joints().iter().enumerate() {
            let pre = parent.compose(&j.origin);
            let a = pre.rotation * j.axis;
            let p = pre.translation;
            let (pose, axis) = match j.kind {
                JointKind::Circular => (
                    Pose {
                        rotation: pre.rotation * pvfc_core::mechanics::axis_angle(&j.axis, q[i]),
                        translation: p,
                    },
                    {
                        let m = p.cross(&a);
                        SVector::<f64, 6>::new(a[0], a[1], a[2], m[0], m[1], m[2])
                    },
                ),
                JointKind::Linear => (
                    Pose {
                        rotation: pre.rotation,
                        translation: p + a * q[i],
                    },
                    SVector::<f64, 6>::new(0.0, 0.0, 0.0, a[0], a[1], a[2]),
                ),
            };
            prop_assert_eq!(k.link_poses[i], pose, "link {}", i);
            prop_assert_eq!(k.axes[i], axis, "axis {}", i);
            parent = pose;
        }
    }
}
