//! The coupling law's products for a [`SerialChain`] by one recursion, O(N), without forming
//! `M` or `C`: Newton–Euler passes in the style of Niemeyer & Slotine's reference-torque
//! algorithm, with the Christoffel-consistent bias of Echeandia & Wensing (2021), so that
//! `M a + C(q, v) x` is the product with the very `C` that [`SerialChain::dynamics`] forms.

use super::{ChainKinematics, LawProducts, Pose, RigidInertia, SerialChain, Spatial};
use crate::scalar::cast;
use crate::Real;
use core::ops::{Add, Mul, Sub};
use nalgebra::{Matrix3, SVector, Vector3};

/// A spatial vector `[angular; linear]` kept as its two halves (no 6-vector indexing on the
/// hot path).
#[derive(Clone, Copy, Debug)]
struct Halves<T: Real> {
    ang: Vector3<T>,
    lin: Vector3<T>,
}

impl<T: Real> Halves<T> {
    fn zero() -> Self {
        Halves {
            ang: Vector3::zeros(),
            lin: Vector3::zeros(),
        }
    }

    #[inline(always)]
    fn of(s: &Spatial<T>) -> Self {
        Halves {
            ang: Vector3::new(s[0], s[1], s[2]),
            lin: Vector3::new(s[3], s[4], s[5]),
        }
    }

    /// `self × m`, the motion cross product (Featherstone eq. 2.31).
    #[inline(always)]
    fn motion_cross(&self, m: &Self) -> Self {
        Halves {
            ang: self.ang.cross(&m.ang),
            lin: self.ang.cross(&m.lin) + self.lin.cross(&m.ang),
        }
    }

    /// `self ×* f`, the force cross product (Featherstone eq. 2.32).
    #[inline(always)]
    fn force_cross(&self, f: &Self) -> Self {
        Halves {
            ang: self.ang.cross(&f.ang) + self.lin.cross(&f.lin),
            lin: self.ang.cross(&f.lin),
        }
    }

    #[inline(always)]
    fn dot(&self, o: &Self) -> T {
        self.ang.dot(&o.ang) + self.lin.dot(&o.lin)
    }
}

impl<T: Real> Add for Halves<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Halves {
            ang: self.ang + o.ang,
            lin: self.lin + o.lin,
        }
    }
}

impl<T: Real> Sub for Halves<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Halves {
            ang: self.ang - o.ang,
            lin: self.lin - o.lin,
        }
    }
}

impl<T: Real> Mul<T> for Halves<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, k: T) -> Self {
        Halves {
            ang: self.ang * k,
            lin: self.lin * k,
        }
    }
}

/// A link's inertia in the base frame, compact: mass, centre of mass and rotational inertia
/// about it. Applying it (Featherstone eq. 2.63 multiplied out) costs about 30 operations,
/// against 36 for the 6×6 matrix, which also costs its forming.
struct BaseInertia<T: Real> {
    mass: T,
    com: Vector3<T>,
    rotational: Matrix3<T>,
}

impl<T: Real> BaseInertia<T> {
    #[inline(always)]
    fn of(link: &RigidInertia<T>, pose: &super::Pose<T>) -> Self {
        let r = &pose.rotation;
        BaseInertia {
            mass: link.mass,
            com: pose.transform_point(&link.com),
            rotational: r * link.inertia * r.transpose(),
        }
    }

    /// `I m`: the linear momentum `mass (u + ω × c)` and the angular one about the origin,
    /// `I_c ω + c × l`.
    #[inline(always)]
    fn apply(&self, m: &Halves<T>) -> Halves<T> {
        let lin = (m.lin + m.ang.cross(&self.com)) * self.mass;
        Halves {
            ang: self.rotational * m.ang + self.com.cross(&lin),
            lin,
        }
    }

    /// `I [0; −g]`: the force of Featherstone's gravity trick (the base accelerating up).
    #[inline(always)]
    fn gravity_force(&self, g: &Vector3<T>) -> Halves<T> {
        let lin = g * (-self.mass);
        Halves {
            ang: self.com.cross(&lin),
            lin,
        }
    }
}

impl<T: Real, const N: usize> SerialChain<T, N> {
    /// The products that the coupling law needs (see
    /// [`MechanicalSystem::law_products`](super::MechanicalSystem::law_products)), by one
    /// forward and one backward pass over the chain:
    /// - forward, link by link: the velocities `v_i = Σ_{j≤i} S_j q̇_j` and
    ///   `x_i = Σ_{j≤i} S_j x_j`, the reference acceleration
    ///   `α_i = Σ_{j≤i} (S_j a_j + Ṡ_j x_j)` with `Ṡ_j = v_j × S_j`, and the link forces
    ///   `I_i v_i`, `I_i x_i`, `I_i α_i + B_i(v_i) x_i` with
    ///   `B(v) x = ½(v ×* I x − I (v × x) + x ×* I v)` (Echeandia & Wensing's
    ///   Christoffel-consistent bias; `B(v) v = v ×* I v`), and `I_i [0; −g]`;
    /// - backward: each joint's torque `S_iᵀ Σ_{l≥i} f_l`.
    ///
    /// The result equals the products with [`crba`](Self::crba)'s `M` and
    /// [`dynamics`](Self::dynamics)' `C` to rounding (tested), at O(N) cost instead of O(N²)
    /// 6-vector products and 6×6 matrices.
    pub fn law_products(
        &self,
        q: &SVector<T, N>,
        v: &SVector<T, N>,
        x: &SVector<T, N>,
        a: &SVector<T, N>,
        with_gravity: bool,
    ) -> LawProducts<T, N> {
        // The kinematics on the fly (no arrays of poses).
        self.products_along(self.joint_steps(q), v, x, a, with_gravity)
    }

    /// [`law_products`](Self::law_products) from the chain's forward kinematics at `q`,
    /// already computed ([`kinematics`](Self::kinematics)) for a velocity field that needs
    /// them too (the task-space field): the same operations on the same poses and axes, so
    /// the same result to the bit.
    pub fn law_products_with_kinematics(
        &self,
        kinematics: &ChainKinematics<T, N>,
        v: &SVector<T, N>,
        x: &SVector<T, N>,
        a: &SVector<T, N>,
        with_gravity: bool,
    ) -> LawProducts<T, N> {
        self.products_along(
            |i, _| (kinematics.link_poses[i], kinematics.axes[i]),
            v,
            x,
            a,
            with_gravity,
        )
    }

    /// The two passes of [`law_products`](Self::law_products), with link `i`'s pose and joint
    /// `i`'s axis from `joint(i, parent's pose)`.
    #[inline(always)]
    fn products_along(
        &self,
        joint: impl Fn(usize, &Pose<T>) -> (Pose<T>, Spatial<T>),
        v: &SVector<T, N>,
        x: &SVector<T, N>,
        a: &SVector<T, N>,
        with_gravity: bool,
    ) -> LawProducts<T, N> {
        let half: T = cast(0.5);
        let gravity = *self.gravity_vector();
        let mut parent = *self.base();
        let mut vel = Halves::zero();
        let mut vel_x = Halves::zero();
        let mut acc_x = Halves::zero();
        // Per link: its axis, and I v, I x, I α + B(v) x, I [0; −g], in arrays of 6-vectors
        // (one array of tuples of all five was zero-filled by N − 1 calls to `memcpy` of an
        // entry, 5 % of a UR5 step, measured; `array::from_fn` was slower still).
        let mut axes = [Halves::zero(); N];
        let mut forces = [[Halves::zero(); N]; 4];
        for i in 0..N {
            let (pose, axis) = joint(i, &parent);
            parent = pose;
            let s = Halves::of(&axis);
            vel = vel + s * v[i];
            vel_x = vel_x + s * x[i];
            acc_x = acc_x + s * a[i] + vel.motion_cross(&s) * x[i];
            let inertia = BaseInertia::of(&self.links()[i], &pose);
            let h = inertia.apply(&vel);
            let hx = inertia.apply(&vel_x);
            // I α + B(v) x = I (α − ½ v × x) + ½ (v ×* I x + x ×* I v).
            let f = inertia.apply(&(acc_x - vel.motion_cross(&vel_x) * half))
                + (vel.force_cross(&hx) + vel_x.force_cross(&h)) * half;
            let fg = if with_gravity {
                inertia.gravity_force(&gravity)
            } else {
                Halves::zero()
            };
            axes[i] = s;
            for (k, fk) in [h, hx, f, fg].into_iter().enumerate() {
                forces[k][i] = fk;
            }
        }
        let (mut momentum, mut field_momentum, mut w, mut gravity) = (
            SVector::zeros(),
            SVector::zeros(),
            SVector::zeros(),
            SVector::zeros(),
        );
        let mut sums = [Halves::zero(); 4];
        for i in (0..N).rev() {
            let s = &axes[i];
            for (sum, f) in sums.iter_mut().zip(&forces) {
                *sum = *sum + f[i];
            }
            momentum[i] = s.dot(&sums[0]);
            field_momentum[i] = s.dot(&sums[1]);
            w[i] = s.dot(&sums[2]);
            gravity[i] = s.dot(&sums[3]);
        }
        LawProducts {
            momentum,
            field_momentum,
            w,
            gravity,
        }
    }
}
