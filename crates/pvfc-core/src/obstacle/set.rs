//! A set of obstacles of both kinds, of fixed capacity, with the composition's parameters.

use super::{Barrier, BodySphere, Composition, JointRegion, Obstacles, WorldObstacle};
use crate::contour::VectorGroup;
use crate::error::{Error, ErrorKind, Result};
use crate::lie::Tangent;
use crate::mechanics::SerialChain;
use crate::Real;
use nalgebra::SVector;

/// The most joint-space regions a set holds.
pub const MAX_JOINT_REGIONS: usize = 8;
/// The most spheres on the robot a set holds.
pub const MAX_BODY_SPHERES: usize = 16;
/// The most world obstacles a set holds.
pub const MAX_WORLD_OBSTACLES: usize = 8;

/// Obstacles of an `N`-joint robot: regions of its joint space and, with its kinematic chain,
/// spheres on its links kept away from shapes in the world. The barrier is the product of
/// every region's and every (sphere, world obstacle) pair's. An empty set is the contour's
/// field exactly ([`Obstacles::barrier`] gives `None`).
///
/// ```
/// use pvfc_core::obstacle::{Composition, JointRegion, ObstacleSet, Obstacles};
/// use pvfc_core::lie::Torus;
/// use nalgebra::Vector2;
/// let mut set = ObstacleSet::<f64, 2>::new(Composition::new(2.0, 4.0, None)?);
/// set.add_region(JointRegion::ball(Vector2::new(1.0, 0.0), 0.3, 0.2)?)?;
/// let q = Torus::new(Vector2::new(1.4, 0.0)); // 0.1 from the ball
/// let (b, _) = Obstacles::<f64, Torus<f64, 2>, 2>::barrier(&set, &q, &Vector2::zeros()).unwrap();
/// assert!(b.value > 0.0 && b.value < 1.0);
/// assert!((set.clearance(&Vector2::new(1.4, 0.0)).unwrap() - 0.1).abs() < 1e-12);
/// # Ok::<(), pvfc_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstacleSet<T: Real, const N: usize> {
    composition: Composition<T>,
    regions: [Option<JointRegion<T, N>>; MAX_JOINT_REGIONS],
    chain: Option<SerialChain<T, N>>,
    spheres: [Option<BodySphere<T>>; MAX_BODY_SPHERES],
    world: [Option<WorldObstacle<T>>; MAX_WORLD_OBSTACLES],
}

fn push<X>(slots: &mut [Option<X>], x: X, what: &'static str) -> Result<()> {
    match slots.iter_mut().find(|s| s.is_none()) {
        Some(slot) => {
            *slot = Some(x);
            Ok(())
        }
        None => Err(Error::new(ErrorKind::InvalidParameter, what)),
    }
}

impl<T: Real, const N: usize> ObstacleSet<T, N> {
    /// An empty set with the composition's parameters.
    pub fn new(composition: Composition<T>) -> Self {
        ObstacleSet {
            composition,
            regions: [None; MAX_JOINT_REGIONS],
            chain: None,
            spheres: [None; MAX_BODY_SPHERES],
            world: [None; MAX_WORLD_OBSTACLES],
        }
    }

    /// The empty set: the field is the contour's, exactly (its composition is never used).
    pub fn empty() -> Self {
        Self::new(Composition {
            kappa: T::one(),
            scale: T::one(),
            speed: None,
        })
    }

    /// Adds a region of the joint space.
    pub fn add_region(&mut self, region: JointRegion<T, N>) -> Result<()> {
        push(
            &mut self.regions,
            region,
            "ObstacleSet: more than MAX_JOINT_REGIONS (8) joint-space regions",
        )
    }

    /// The robot's kinematic chain, which places its spheres in the world.
    pub fn set_chain(&mut self, chain: SerialChain<T, N>) {
        self.chain = Some(chain);
    }

    /// Adds a sphere on the robot (its link must exist).
    pub fn add_body_sphere(&mut self, sphere: BodySphere<T>) -> Result<()> {
        if sphere.link >= N {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "ObstacleSet: a body sphere's link is beyond the chain's last link",
            ));
        }
        push(
            &mut self.spheres,
            sphere,
            "ObstacleSet: more than MAX_BODY_SPHERES (16) spheres on the robot",
        )
    }

    /// Adds an obstacle in the world.
    pub fn add_world_obstacle(&mut self, obstacle: WorldObstacle<T>) -> Result<()> {
        push(
            &mut self.world,
            obstacle,
            "ObstacleSet: more than MAX_WORLD_OBSTACLES (8) world obstacles",
        )
    }

    /// The composition's parameters.
    pub fn composition(&self) -> &Composition<T> {
        &self.composition
    }

    /// The world obstacles.
    pub fn world_obstacles(&self) -> impl Iterator<Item = &WorldObstacle<T>> {
        self.world.iter().flatten()
    }

    /// The spheres on the robot.
    pub fn body_spheres(&self) -> impl Iterator<Item = &BodySphere<T>> {
        self.spheres.iter().flatten()
    }

    /// `true` when world obstacles act: a chain, spheres on it and shapes.
    fn has_world(&self) -> bool {
        self.chain.is_some() && self.spheres[0].is_some() && self.world[0].is_some()
    }

    /// `true` when no obstacle acts: the field is the contour's.
    pub fn is_empty(&self) -> bool {
        self.regions[0].is_none() && !self.has_world()
    }

    /// The smallest clearance at the joint coordinates `q`: to the joint-space regions (in
    /// joint units) and between the robot's spheres and the world obstacles (in metres);
    /// `None` for an empty set.
    pub fn clearance(&self, q: &SVector<T, N>) -> Option<T> {
        let mut smallest: Option<T> = None;
        let mut keep = |c: T| smallest = Some(smallest.map_or(c, |s: T| s.min(c)));
        for r in self.regions.iter().flatten() {
            keep(r.clearance(q));
        }
        if let (true, Some(chain)) = (self.has_world(), &self.chain) {
            let motion = chain.motion(q, &SVector::zeros());
            for s in self.spheres.iter().flatten() {
                let p = motion.point(s.link, &s.offset).position;
                for o in self.world.iter().flatten() {
                    keep(o.clearance(&p, s));
                }
            }
        }
        smallest
    }
}

impl<T: Real, G: VectorGroup<T, N>, const N: usize> Obstacles<T, G, N> for ObstacleSet<T, N> {
    fn barrier(&self, q: &G, v: &Tangent<T, N>) -> Option<(Barrier<T, N>, Composition<T>)> {
        if self.is_empty() {
            return None;
        }
        let x = q.coordinates();
        let mut b = Barrier::free();
        for r in self.regions.iter().flatten() {
            b = b.product(&r.barrier(&x, v));
        }
        if let (true, Some(chain)) = (self.has_world(), &self.chain) {
            let motion = chain.motion(&x, v);
            for s in self.spheres.iter().flatten() {
                let m = motion.point(s.link, &s.offset);
                for o in self.world.iter().flatten() {
                    b = b.product(&o.barrier(&m, s));
                }
            }
        }
        Some((b, self.composition))
    }
}
