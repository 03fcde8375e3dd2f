//! The `<collision>` elements of a chain's links, as geometry placed on the chain's bodies
//! (for pvfc-sim's 3-D contact, `contact::spatial`). Reading them never opens a mesh file: a mesh
//! is kept by name and resolved only when a contact world asks for it ([`resolve_mesh`]).

use crate::error::{Result, SimError};
use pvfc_core::mechanics::Pose;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The shape of a URDF `<collision>` element, in its own frame (URDF's conventions: a box
/// centred, a cylinder and a capsule along z, centred).
#[derive(Clone, Debug, PartialEq)]
pub enum CollisionGeometry {
    /// `<box size>`: full side lengths (m).
    Box {
        /// Side lengths along x, y, z (m).
        size: [f64; 3],
    },
    /// `<cylinder>` along z (m).
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length (m).
        length: f64,
    },
    /// `<capsule>` along z: `length` between the centres of its end caps (m).
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Length of the cylindrical part (m).
        length: f64,
    },
    /// `<sphere>` (m).
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// `<mesh filename scale>`: the file name as the URDF gives it (`package://…`, relative,
    /// `file://…`) and its scale per axis.
    Mesh {
        /// The file name, unresolved.
        filename: String,
        /// Scale along x, y, z.
        scale: [f64; 3],
    },
}

/// One `<collision>` element of a link that moves with the chain body `body` (a joint's
/// child link, or a link fixed to it or folded into it).
#[derive(Clone, Debug, PartialEq)]
pub struct LinkCollision {
    /// The index of the body (0 for the first joint's child), as in
    /// [`ChainDescription::links`](super::ChainDescription::links).
    pub body: usize,
    /// The URDF link the element belongs to.
    pub link: String,
    /// The element's frame in the body's frame (its `<origin>` composed with the link's
    /// placement on the body).
    pub origin: Pose<f64>,
    /// Its shape.
    pub geometry: CollisionGeometry,
}

/// The collision elements of `link`, placed at `at` on body `body`. Their sizes are checked
/// when a contact world uses them ([`CollisionGeometry::check`]), not here: a malformed
/// `<collision>` must not stop the dynamics of a chain that never touches anything.
pub(crate) fn link_collisions(
    link: &urdf_rs::Link,
    body: usize,
    at: &Pose<f64>,
) -> Vec<LinkCollision> {
    link.collision
        .iter()
        .map(|c| {
            let geometry = match &c.geometry {
                urdf_rs::Geometry::Box { size } => CollisionGeometry::Box { size: size.0 },
                urdf_rs::Geometry::Cylinder { radius, length } => CollisionGeometry::Cylinder {
                    radius: *radius,
                    length: *length,
                },
                urdf_rs::Geometry::Capsule { radius, length } => CollisionGeometry::Capsule {
                    radius: *radius,
                    length: *length,
                },
                urdf_rs::Geometry::Sphere { radius } => {
                    CollisionGeometry::Sphere { radius: *radius }
                }
                urdf_rs::Geometry::Mesh { filename, scale } => CollisionGeometry::Mesh {
                    filename: filename.clone(),
                    scale: scale.map_or([1.0; 3], |s| s.0),
                },
            };
            let origin = Pose::from_xyz_rpy(c.origin.xyz.0, c.origin.rpy.0);
            LinkCollision {
                body,
                link: link.name.clone(),
                origin: at.compose(&origin),
                geometry,
            }
        })
        .collect()
}

impl CollisionGeometry {
    /// The shape's sizes (a box's sides, a radius and a length, a mesh's scale).
    pub fn sizes(&self) -> Vec<f64> {
        match self {
            CollisionGeometry::Box { size } => size.to_vec(),
            CollisionGeometry::Cylinder { radius, length }
            | CollisionGeometry::Capsule { radius, length } => vec![*radius, *length],
            CollisionGeometry::Sphere { radius } => vec![*radius],
            CollisionGeometry::Mesh { scale, .. } => scale.to_vec(),
        }
    }

    /// Checks that every size is finite and > 0; the error names `link`'s `<collision>`.
    pub fn check(&self, link: &str) -> Result<()> {
        let sizes = self.sizes();
        if sizes.iter().all(|x| x.is_finite() && *x > 0.0) {
            Ok(())
        } else {
            Err(SimError::Setting(format!(
                "link {link} <collision>: sizes {sizes:?} must be finite and > 0"
            )))
        }
    }
}

/// The file of a mesh's `filename`: `package://NAME/REST` is `packages[NAME]/REST` (as ROS
/// resolves it, with the package directories given), `file:///abs` is that path, and any
/// other name is relative to the URDF's directory `urdf_dir`. Errors name the link and the
/// file, and say what to give.
pub fn resolve_mesh(
    filename: &str,
    link: &str,
    urdf_dir: &Path,
    packages: &BTreeMap<String, PathBuf>,
) -> Result<PathBuf> {
    let missing =
        |message: String| SimError::Setting(format!("link {link}: mesh {filename}: {message}"));
    let path = if let Some(rest) = filename.strip_prefix("package://") {
        let (name, inner) = rest.split_once('/').unwrap_or((rest, ""));
        let dir = packages.get(name).ok_or_else(|| {
            missing(format!(
                "package `{name}` is not known: give its directory in contact_3d.packages"
            ))
        })?;
        dir.join(inner)
    } else if let Some(abs) = filename.strip_prefix("file://") {
        PathBuf::from(abs)
    } else {
        urdf_dir.join(filename)
    };
    if path.is_file() {
        Ok(path)
    } else {
        Err(missing(format!("{} does not exist", path.display())))
    }
}
