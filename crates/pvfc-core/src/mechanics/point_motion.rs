//! The motion of a point fixed on one link of a serial chain: its position, its Jacobian
//! `J_p(q)` and the Jacobian's rate `J̇_p(q, q̇)` (what a task-space barrier needs for its
//! gradient and the gradient's rate, [`crate::obstacle`]).

use super::serial_chain::{ChainKinematics, SerialChain};
use super::spatial::Spatial;
use crate::Real;
use nalgebra::{SMatrix, SVector, Vector3};

/// The world position of a point fixed on a link, its Jacobian and the Jacobian's rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMotion<T: Real, const N: usize> {
    /// The point in the world frame, `p(q)`.
    pub position: Vector3<T>,
    /// `J_p = ∂p/∂q` (3 × N): `ṗ = J_p q̇`. Columns of joints after the point's link are 0.
    pub jacobian: SMatrix<T, 3, N>,
    /// `J̇_p` along the motion `q̇`.
    pub jacobian_rate: SMatrix<T, 3, N>,
    /// `ṗ = J_p q̇`.
    pub velocity: Vector3<T>,
}

/// The rates of the joints' spatial axes along a motion `q̇`, with the kinematics they belong
/// to: computed once per state, shared by every point of a set.
///
/// Joint `j`'s axis is fixed in its parent link, which moves with the spatial velocity
/// `V_{j−1} = Σ_{k<j} S_k q̇_k`, so `Ṡ_j = V_{j−1} ×_m S_j` (Featherstone's motion cross
/// product, in the world-origin representation of [`ChainKinematics::axes`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainMotion<T: Real, const N: usize> {
    /// The kinematics at `q`.
    pub kinematics: ChainKinematics<T, N>,
    /// `Ṡ_j` for every joint.
    pub axis_rates: [Spatial<T>; N],
    /// `q̇`.
    pub joint_velocity: SVector<T, N>,
}

/// `V ×_m S` for spatial motion vectors `[ω; v]`: `[ω × a; ω × b + v × a]` for `S = [a; b]`.
#[inline]
fn motion_cross_apply<T: Real>(v: &Spatial<T>, s: &Spatial<T>) -> Spatial<T> {
    let (w, u) = split(v);
    let (a, b) = split(s);
    let top = w.cross(&a);
    let bottom = w.cross(&b) + u.cross(&a);
    Spatial::new(top.x, top.y, top.z, bottom.x, bottom.y, bottom.z)
}

#[inline]
fn split<T: Real>(s: &Spatial<T>) -> (Vector3<T>, Vector3<T>) {
    (
        Vector3::new(s[0], s[1], s[2]),
        Vector3::new(s[3], s[4], s[5]),
    )
}

impl<T: Real, const N: usize> SerialChain<T, N> {
    /// The chain's kinematics at `q` and its axes' rates along `q̇`.
    pub fn motion(&self, q: &SVector<T, N>, v: &SVector<T, N>) -> ChainMotion<T, N> {
        let kinematics = self.kinematics(q);
        let mut axis_rates = [Spatial::zeros(); N];
        let mut velocity = Spatial::zeros();
        for j in 0..N {
            axis_rates[j] = motion_cross_apply(&velocity, &kinematics.axes[j]);
            velocity += kinematics.axes[j] * v[j];
        }
        ChainMotion {
            kinematics,
            axis_rates,
            joint_velocity: *v,
        }
    }
}

impl<T: Real, const N: usize> ChainMotion<T, N> {
    /// The motion of the point at `offset` in link `link`'s frame (links numbered from 0,
    /// joint `i` moving link `i`). A `link ≥ N` is read as the last link.
    ///
    /// Column `j ≤ link` of `J_p` is `S_j`'s velocity at `p`, `b_j + a_j × p`; its rate is
    /// `ḃ_j + ȧ_j × p + a_j × ṗ`.
    pub fn point(&self, link: usize, offset: &Vector3<T>) -> PointMotion<T, N> {
        let count = (link + 1).min(N);
        let position = match count.checked_sub(1) {
            Some(last) => self.kinematics.link_poses[last].transform_point(offset),
            None => *offset,
        };
        let mut jacobian = SMatrix::<T, 3, N>::zeros();
        let mut velocity = Vector3::zeros();
        for j in 0..count {
            let (a, b) = split(&self.kinematics.axes[j]);
            let col = b + a.cross(&position);
            velocity += col * self.joint_velocity[j];
            jacobian.set_column(j, &col);
        }
        let mut jacobian_rate = SMatrix::<T, 3, N>::zeros();
        for j in 0..count {
            let (a, _) = split(&self.kinematics.axes[j]);
            let (a_dot, b_dot) = split(&self.axis_rates[j]);
            let col = b_dot + a_dot.cross(&position) + a.cross(&velocity);
            jacobian_rate.set_column(j, &col);
        }
        PointMotion {
            position,
            jacobian,
            jacobian_rate,
            velocity,
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::lie::JointKind;
    use crate::mechanics::{ChainJoint, Pose, RigidInertia};

    fn chain() -> SerialChain<f64, 3> {
        let j = |xyz: [f64; 3], rpy: [f64; 3], axis: [f64; 3], kind| ChainJoint {
            origin: Pose::from_xyz_rpy(xyz, rpy),
            axis: Vector3::new(axis[0], axis[1], axis[2]),
            kind,
        };
        let l = RigidInertia::from_urdf(1.0, &Pose::identity(), [0.1, 0.0, 0.0, 0.1, 0.0, 0.1]);
        SerialChain::new(
            [
                j(
                    [0.0, 0.0, 0.3],
                    [0.0, 0.0, 0.0],
                    [0.0, 0.0, 1.0],
                    JointKind::Circular,
                ),
                j(
                    [0.1, 0.0, 0.2],
                    [0.3, 0.0, 0.1],
                    [0.0, 1.0, 0.0],
                    JointKind::Circular,
                ),
                j(
                    [0.4, 0.05, 0.0],
                    [0.0, 0.2, 0.0],
                    [1.0, 0.0, 0.0],
                    JointKind::Linear,
                ),
            ],
            [l; 3],
        )
        .unwrap()
    }

    /// `J_p` against central differences of `p(q)`, and `J̇_p` against those of `J_p(q + t q̇)`.
    #[test]
    fn jacobian_and_its_rate_match_finite_differences() {
        let c = chain();
        let q = SVector::<f64, 3>::new(0.4, -0.7, 0.15);
        let v = SVector::<f64, 3>::new(0.9, -1.3, 0.6);
        let offset = Vector3::new(0.05, -0.02, 0.1);
        let h = 1e-6;
        for link in 0..3 {
            let m = c.motion(&q, &v).point(link, &offset);
            for i in 0..3 {
                let mut dq = SVector::<f64, 3>::zeros();
                dq[i] = h;
                let plus = c.motion(&(q + dq), &v).point(link, &offset).position;
                let minus = c.motion(&(q - dq), &v).point(link, &offset).position;
                let fd = (plus - minus) / (2.0 * h);
                assert!(
                    (fd - m.jacobian.column(i)).norm() < 1e-8,
                    "link {link} joint {i}"
                );
            }
            let plus = c.motion(&(q + v * h), &v).point(link, &offset).jacobian;
            let minus = c.motion(&(q - v * h), &v).point(link, &offset).jacobian;
            let fd = (plus - minus) / (2.0 * h);
            assert!((fd - m.jacobian_rate).norm() < 1e-7, "link {link}: J̇");
            assert!((m.velocity - m.jacobian * v).norm() < 1e-15);
        }
    }
}
