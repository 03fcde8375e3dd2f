//! What several test modules share.

/// A table under the UR5's rectangle (`ur5_cartesian`, the path at z = 0.30 m): its top 3 mm
/// above the lowest point of a tool ball of 1 cm radius, a stiff contact with friction.
#[cfg(feature = "contact")]
#[allow(dead_code)] // not every build of the tests has contact
pub fn table_under_the_rectangle() -> pvfc_sim::contact::spatial::SpatialContactSpec {
    use pvfc_sim::contact::spatial::{SpatialContactSpec, SpatialObstacle, SpatialShape};
    SpatialContactSpec {
        arm: Default::default(),
        packages: Default::default(),
        force_schedule: None,
        link_radius: 0.0,
        link_radii: vec![],
        tool_radius: 0.01,
        obstacles: vec![SpatialObstacle {
            frame: Default::default(),
            shape: SpatialShape::Box {
                half_extents: [0.3, 0.4, 0.05],
            },
            position: [0.55, 0.0, 0.30 - 0.01 + 0.003 - 0.05],
            rpy: [0.0; 3],
            law: None,
            motion: vec![],
        }],
        law: pvfc_sim::contact::ContactLaw {
            stiffness: 2.0e4,
            damping: 0.5,
            friction: 0.2,
            slip_velocity: 0.01,
        },
    }
}

/// The small rotation from `a` to `b` (the vee of the skew part of `aᵀb`): accurate near the
/// identity, where an angle from the trace is not.
#[allow(dead_code)] // not every build of the tests has contact
pub fn small_rotation(
    a: &nalgebra::Matrix3<f64>,
    b: &nalgebra::Matrix3<f64>,
) -> nalgebra::Vector3<f64> {
    let m = a.transpose() * b;
    nalgebra::Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    ) * 0.5
}
