//! The systems the property tests run on, generic over the scalar.
#![allow(dead_code)]

use super::vec;
use nalgebra::{Matrix3, Vector2, Vector3};
use pvfc_core::obstacle::{
    BodySphere, Composition, JointRegion, ObstacleSet, WorldObstacle, WorldShape,
};
use pvfc_core::pace::{PaceTable, Paced};
use pvfc_core::prelude::*;
use pvfc_core::scalar::cast;

/// Law parameters drawn at random by the tests.
#[derive(Clone, Copy, Debug)]
pub struct Params {
    pub r: f64,
    pub gamma: f64,
    pub h: [f64; 3],
}

pub type ScaraLissajous<T> = PvfcLaw<
    T,
    Torus<T, 2>,
    Scara<T>,
    SuspendedField<T, Torus<T, 2>, Lissajous<T, 2>, TorusNavigation<T, 2>, ExponentialPacing<T>, 2>,
    2,
>;

/// The paper's setting: Pelican SCARA, Lissajous contour, eq. (17) navigation, eq. (21) pacing.
pub fn scara_lissajous<T: Real>(p: Params) -> ScaraLissajous<T> {
    paper_law(p, ExponentialPacing::new(cast(p.r)).unwrap())
}

/// The paper's SCARA, Lissajous contour and navigation function with the self-pacing `S`.
pub type PaperLaw<T, S> = PvfcLaw<
    T,
    Torus<T, 2>,
    Scara<T>,
    SuspendedField<T, Torus<T, 2>, Lissajous<T, 2>, TorusNavigation<T, 2>, S, 2>,
    2,
>;

/// The paper's setting with the self-pacing `pacing`.
fn paper_law<T: Real, S: SelfPacing<T>>(p: Params, pacing: S) -> PaperLaw<T, S> {
    let field = SuspendedField::new(
        Lissajous::paper(),
        TorusNavigation::paper(vec([p.h[0], p.h[1]])).unwrap(),
        pacing,
    );
    PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(T::one(), cast(50.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

/// The paper's setting with a pace profile along the contour (`pvfc_core::pace`): twelve
/// knots between 0.3 and 1.2 over the Lissajous curve's period of 6.
pub type ScaraPaced<T> = PaperLaw<T, Paced<ExponentialPacing<T>, PaceTable<T, 16>>>;

/// The pace profile of [`scara_paced`].
pub fn test_pace<T: Real>() -> PaceTable<T, 16> {
    let knots = [1.0, 0.8, 0.3, 0.5, 1.2, 0.9, 0.6, 0.7, 1.0, 0.4, 0.45, 1.1].map(cast::<T>);
    PaceTable::new(&knots, cast(6.0)).unwrap()
}

/// [`scara_lissajous`] with the pace profile [`test_pace`].
pub fn scara_paced<T: Real>(p: Params) -> ScaraPaced<T> {
    paper_law(
        p,
        Paced::new(ExponentialPacing::new(cast(p.r)).unwrap(), test_pace()),
    )
}

pub type ScaraSpline<T> = PvfcLaw<
    T,
    Torus<T, 2>,
    Scara<T>,
    SuspendedField<
        T,
        Torus<T, 2>,
        PeriodicBSpline<T, Torus<T, 2>, 2, 5>,
        TorusNavigation<T, 2>,
        ExponentialPacing<T>,
        2,
    >,
    2,
>;

/// The waypoints of the test splines on T², one every spacing in τ.
pub fn waypoints<T: Real>() -> [Torus<T, 2>; 5] {
    [
        (0.0, 0.0),
        (0.8, 0.3),
        (0.5, 1.2),
        (-0.4, 0.9),
        (-0.6, -0.2),
    ]
    .map(|(a, b)| Torus::new(Vector2::new(cast(a), cast(b))))
}

/// SCARA on a waypoint spline, with the *left* error and eq. (28)'s convention.
pub fn scara_spline<T: Real>(p: Params) -> ScaraSpline<T> {
    let pts = waypoints::<T>();
    let field = SuspendedField::new(
        PeriodicBSpline::through(pts, cast(1.3)).unwrap(),
        TorusNavigation::new(vec([p.h[0], p.h[1]]), TorusConvention::Sum).unwrap(),
        ExponentialPacing::new(cast(p.r)).unwrap(),
    )
    .with_convention(ErrorConvention::Left);
    PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(cast(0.5), cast(80.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

/// A navigation matrix P with eigenvalues built from the h's (always valid: π₁ + π₂ > 0).
pub fn so3_p<T: Real>(h: [f64; 3]) -> Matrix3<T> {
    let (a, b, c) = (h[0], h[0] + h[1], h[0] + h[1] + h[2]);
    let rot = So3::<f64>::exp(&Vector3::new(0.3, -0.7, 0.2));
    let p =
        rot.matrix() * Matrix3::from_diagonal(&Vector3::new(a, b, c)) * rot.matrix().transpose();
    p.map(cast)
}

pub type BodySpin<T> = PvfcLaw<
    T,
    So3<T>,
    RigidBody<T>,
    SuspendedField<
        T,
        So3<T>,
        ConstantRate<T, So3<T>, 3>,
        So3Navigation<T>,
        ExponentialPacing<T>,
        3,
    >,
    3,
>;

/// A rigid body asked to spin at a constant rate (SO(3), eq. 26 navigation).
pub fn body_spin<T: Real>(p: Params) -> BodySpin<T> {
    let j = Matrix3::from_diagonal(&vec([1.0, 2.0, 3.0]));
    let field = SuspendedField::new(
        ConstantRate::new(So3::exp(&vec([0.1, 0.2, 0.3])), vec([0.3, -0.2, 0.5])).unwrap(),
        So3Navigation::new(so3_p(p.h)).unwrap(),
        ExponentialPacing::new(cast(p.r)).unwrap(),
    );
    PvfcLaw::new(
        RigidBody::new(j).unwrap(),
        field,
        Flywheel::new(T::one(), cast(50.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

pub type BodySpline<T> = PvfcLaw<
    T,
    So3<T>,
    RigidBody<T>,
    SuspendedField<
        T,
        So3<T>,
        PeriodicBSpline<T, So3<T>, 3, 6>,
        So3Navigation<T>,
        ExponentialPacing<T>,
        3,
    >,
    3,
>;

/// Key orientations of an attitude manoeuvre.
pub fn key_orientations<T: Real>() -> [So3<T>; 6] {
    core::array::from_fn(|k| {
        let t = k as f64 * std::f64::consts::TAU / 6.0;
        So3::exp(&vec([0.8 * t.cos(), 0.8 * t.sin(), 0.3 * (2.0 * t).sin()]))
    })
}

/// A rigid body through key orientations, with the left error.
pub fn body_spline<T: Real>(p: Params) -> BodySpline<T> {
    let j = Matrix3::new(2.0, 0.1, 0.0, 0.1, 1.5, -0.2, 0.0, -0.2, 1.0).map(cast);
    let field = SuspendedField::new(
        PeriodicBSpline::through(key_orientations(), cast(2.0)).unwrap(),
        So3Navigation::new(so3_p(p.h)).unwrap(),
        ExponentialPacing::new(cast(p.r)).unwrap(),
    )
    .with_convention(ErrorConvention::Left);
    PvfcLaw::new(
        RigidBody::new(j).unwrap(),
        field,
        Flywheel::new(cast(2.0), cast(40.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

pub type Stage<T> = PvfcLaw<
    T,
    Rn<T, 3>,
    LinearStage<T, 3>,
    SuspendedField<T, Rn<T, 3>, Ellipse<T, 3>, QuadraticNavigation<T, 3>, ExponentialPacing<T>, 3>,
    3,
>;

/// A three-axis linear stage on a tilted ellipse in ℝ³.
pub fn stage<T: Real>(p: Params) -> Stage<T> {
    let field = SuspendedField::new(
        Ellipse::new(
            vec([0.1, -0.2, 0.3]),
            vec([1.0, 0.0, 0.2]),
            vec([0.0, 0.7, -0.1]),
            cast(5.0),
        )
        .unwrap(),
        QuadraticNavigation::new(vec(p.h)).unwrap(),
        ExponentialPacing::new(cast(p.r / 10.0)).unwrap(),
    );
    PvfcLaw::new(
        LinearStage::new(vec([1.0, 2.0, 3.0])).unwrap(),
        field,
        Flywheel::new(T::one(), cast(5000.0)).unwrap(),
        cast(p.gamma / 100.0),
    )
    .unwrap()
}

/// A rail (prismatic) carrying a three-joint arm: a mixed joint space `ℝ × T³`.
pub fn rail_arm<T: Real>() -> SerialChain<T, 4> {
    use pvfc_core::mechanics::{ChainJoint, Pose, RigidInertia};
    let joint = |kind, xyz: [f64; 3], rpy: [f64; 3], axis: [f64; 3]| ChainJoint {
        kind,
        origin: Pose::from_xyz_rpy(xyz.map(cast), rpy.map(cast)),
        axis: vec(axis),
    };
    let link = |m: f64, com: [f64; 3], i: [f64; 3]| RigidInertia {
        mass: cast(m),
        com: vec(com),
        inertia: Matrix3::from_diagonal(&vec(i)),
    };
    SerialChain::new(
        [
            joint(JointKind::Linear, [0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]),
            joint(
                JointKind::Circular,
                [0.0, 0.0, 0.2],
                [0.0; 3],
                [0.0, 0.0, 1.0],
            ),
            joint(
                JointKind::Circular,
                [0.1, 0.0, 0.3],
                [0.3, 0.0, 0.0],
                [0.0, 1.0, 0.0],
            ),
            joint(
                JointKind::Circular,
                [0.4, 0.0, 0.0],
                [0.0, 0.2, 0.0],
                [0.0, 1.0, 0.0],
            ),
        ],
        [
            link(8.0, [0.0, 0.0, 0.1], [0.1, 0.1, 0.1]),
            link(4.0, [0.0, 0.0, 0.15], [0.05, 0.05, 0.02]),
            link(3.0, [0.2, 0.0, 0.0], [0.01, 0.05, 0.05]),
            link(1.5, [0.15, 0.02, 0.0], [0.005, 0.02, 0.02]),
        ],
    )
    .unwrap()
}

pub type RailArm<T> = PvfcLaw<
    T,
    JointSpace<T, 4>,
    SerialChain<T, 4>,
    SuspendedField<
        T,
        JointSpace<T, 4>,
        Ellipse<T, 4>,
        JointNavigation<T, 4>,
        ExponentialPacing<T>,
        4,
    >,
    4,
>;

/// The rail arm on an ellipse in its joint space, with the mixed navigation function.
pub fn rail_arm_ellipse<T: Real>(p: Params) -> RailArm<T> {
    let arm = rail_arm::<T>();
    let field = SuspendedField::new(
        Ellipse::new(
            vec([0.1, 0.2, -0.3, 0.5]),
            vec([0.3, 0.5, 0.2, -0.4]),
            vec([0.0, -0.6, 0.4, 0.3]),
            cast(4.0),
        )
        .unwrap(),
        JointNavigation::new(vec([p.h[0], p.h[1], p.h[2], p.h[0]]), arm.kinds()).unwrap(),
        ExponentialPacing::new(cast(p.r)).unwrap(),
    );
    PvfcLaw::new(
        arm,
        field,
        Flywheel::new(T::one(), cast(3000.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

/// The Pelican's kinematics as a chain, to place spheres on its links.
pub fn pelican_chain<T: Real>() -> SerialChain<T, 2> {
    ScaraParameters::pelican().chain().unwrap()
}

/// Obstacles of both kinds for the Pelican: a rounded box of joint space, and a post and a
/// ball in its plane kept from two spheres on the forearm.
pub fn scara_obstacle_set<T: Real>() -> ObstacleSet<T, 2> {
    let mut set =
        ObstacleSet::new(Composition::new(cast(4.0), cast(4.0), Some(cast(3.0))).unwrap());
    set.add_region(JointRegion::new(vec([-1.6, 0.0]), vec([0.3, 0.4]), 2, cast(0.5)).unwrap())
        .unwrap();
    set.set_chain(pelican_chain());
    set.add_body_sphere(BodySphere::new(1, vec([0.26, 0.0, 0.0]), cast(0.02)).unwrap())
        .unwrap();
    set.add_body_sphere(BodySphere::new(1, vec([0.13, 0.0, 0.0]), cast(0.03)).unwrap())
        .unwrap();
    let post = WorldShape::Cylinder {
        point: vec([-0.1, 0.33, 0.0]),
        axis: vec([0.0, 0.0, 1.0]),
        radius: cast(0.05),
    };
    let ball = WorldShape::Sphere {
        center: vec([-0.1, -0.33, 0.0]),
        radius: cast(0.04),
    };
    set.add_world_obstacle(WorldObstacle::new(post, cast(0.01), cast(0.1)).unwrap())
        .unwrap();
    set.add_world_obstacle(WorldObstacle::new(ball, cast(0.01), cast(0.08)).unwrap())
        .unwrap();
    set
}

pub type ScaraObstacles<T> = PvfcLaw<
    T,
    Torus<T, 2>,
    Scara<T>,
    SuspendedField<
        T,
        Torus<T, 2>,
        Lissajous<T, 2>,
        TorusNavigation<T, 2>,
        ExponentialPacing<T>,
        2,
        ObstacleSet<T, 2>,
    >,
    2,
>;

/// The paper's setting around [`scara_obstacle_set`].
pub fn scara_obstacles<T: Real>(p: Params) -> ScaraObstacles<T> {
    let law = scara_lissajous::<T>(p);
    let field = (*law.field()).with_obstacles(scara_obstacle_set());
    PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(T::one(), cast(50.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

/// Obstacles for the rail arm: a ball of its joint space and a ball in the world kept from
/// two spheres on its last two links.
pub fn rail_arm_obstacle_set<T: Real>() -> ObstacleSet<T, 4> {
    let mut set =
        ObstacleSet::new(Composition::new(cast(3.0), cast(2.0), Some(cast(4.0))).unwrap());
    set.add_region(JointRegion::ball(vec([0.5, 0.5, 0.5, 0.5]), cast(0.4), cast(0.4)).unwrap())
        .unwrap();
    set.set_chain(rail_arm());
    set.add_body_sphere(BodySphere::new(3, vec([0.3, 0.0, 0.0]), cast(0.05)).unwrap())
        .unwrap();
    set.add_body_sphere(BodySphere::new(2, vec([0.2, 0.0, 0.0]), cast(0.05)).unwrap())
        .unwrap();
    let ball = WorldShape::Sphere {
        center: vec([0.4, 0.3, 0.5]),
        radius: cast(0.1),
    };
    set.add_world_obstacle(WorldObstacle::new(ball, cast(0.02), cast(0.2)).unwrap())
        .unwrap();
    set
}

pub type RailArmObstacles<T> = PvfcLaw<
    T,
    JointSpace<T, 4>,
    SerialChain<T, 4>,
    SuspendedField<
        T,
        JointSpace<T, 4>,
        Ellipse<T, 4>,
        JointNavigation<T, 4>,
        ExponentialPacing<T>,
        4,
        ObstacleSet<T, 4>,
    >,
    4,
>;

/// The rail arm's ellipse around [`rail_arm_obstacle_set`].
pub fn rail_arm_obstacles<T: Real>(p: Params) -> RailArmObstacles<T> {
    let law = rail_arm_ellipse::<T>(p);
    let field = (*law.field()).with_obstacles(rail_arm_obstacle_set());
    PvfcLaw::new(
        rail_arm(),
        field,
        Flywheel::new(T::one(), cast(3000.0)).unwrap(),
        cast(p.gamma),
    )
    .unwrap()
}

/// A sphere world in the Pelican's joint space (Rimon–Koditschek's setting): five balls
/// clear of the paper's contour, two inside its loops (the contour passes within their
/// influence), one on the far side of the torus.
pub fn scara_ball_world<T: Real>(kappa: f64) -> ObstacleSet<T, 2> {
    let mut set =
        ObstacleSet::new(Composition::new(cast(kappa), cast(4.0), Some(cast(3.0))).unwrap());
    for (c, r, w) in [
        ([0.55, 0.0], 0.18, 0.2),
        ([-0.55, 0.0], 0.18, 0.2),
        ([-1.8, 0.5], 0.4, 0.4),
        ([1.9, -0.6], 0.5, 0.4),
        ([0.0, -2.6], 0.3, 0.4),
    ] {
        set.add_region(JointRegion::ball(vec(c), cast(r), cast(w)).unwrap())
            .unwrap();
    }
    set
}

/// The paper's setting with the field's kinetic energy bounded at 2 % of `Ē` (1 J): scaled
/// onto the bound at most random states (`PvfcLaw::set_field_energy_bound`).
pub fn scara_bounded<T: Real>(p: Params) -> ScaraLissajous<T> {
    let mut law = scara_lissajous(p);
    law.set_field_energy_bound(cast(0.02)).unwrap();
    law
}
