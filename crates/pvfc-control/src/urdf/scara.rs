//! A two-link SCARA from a URDF file (urdf-rs), with the checks urdf-rs does not make.

use super::err;
use crate::error::{Result, SimError};
use pvfc_core::mechanics::ScaraParameters;
use std::path::Path;

/// Reads a planar two-link arm from a URDF: a chain `base → (revolute) link1 → (revolute)
/// link2 → (fixed) tool`, both revolute axes along `z`, every moving link with an
/// `<inertial>` whose centre of mass lies on the link's x axis.
///
/// Gives `m_i` and `I_i = izz` from the `<inertial>`s, `lc_i` from their origins, `l1` from
/// joint 2's origin and `l2` from the tool joint's origin. urdf-rs silently defaults a missing
/// `<inertial>` to mass 0 and a missing `<axis>` to x; both are reported here as errors that
/// name the element.
pub fn scara_from_urdf(path: &Path) -> Result<ScaraParameters<f64>> {
    let text = std::fs::read_to_string(path).map_err(|e| SimError::io(path, e))?;
    scara_from_urdf_str(&text, path)
}

/// As [`scara_from_urdf`], from the file's text (`path` only names it in errors).
pub fn scara_from_urdf_str(text: &str, path: &Path) -> Result<ScaraParameters<f64>> {
    let robot = super::parse(text, path)?;
    let moving: Vec<&urdf_rs::Joint> = robot
        .joints
        .iter()
        .filter(|j| !matches!(j.joint_type, urdf_rs::JointType::Fixed))
        .collect();
    if moving.len() != 2 {
        return Err(err(
            path,
            "robot",
            format!(
                "a SCARA has exactly 2 moving joints, found {}",
                moving.len()
            ),
        ));
    }
    // Order the chain: joint 1's child is joint 2's parent.
    let (j1, j2) = if moving[0].child.link == moving[1].parent.link {
        (moving[0], moving[1])
    } else if moving[1].child.link == moving[0].parent.link {
        (moving[1], moving[0])
    } else {
        return Err(err(
            path,
            "robot",
            "the two moving joints do not form a chain",
        ));
    };
    for j in [j1, j2] {
        let element = format!("joint {}", j.name);
        if !matches!(
            j.joint_type,
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous
        ) {
            return Err(err(path, element, "must be revolute or continuous"));
        }
        let a = j.axis.xyz.0;
        if a[0].abs() > 1e-9 || a[1].abs() > 1e-9 || (a[2].abs() - 1.0).abs() > 1e-9 {
            return Err(err(
                path,
                element,
                format!(
                    "<axis> must be (0 0 ±1) for a planar arm, got {a:?} (a missing <axis> reads as x)"
                ),
            ));
        }
        let r = j.origin.rpy.0;
        if r[0].abs() > 1e-9 || r[1].abs() > 1e-9 {
            return Err(err(
                path,
                element,
                "<origin rpy> must not tilt the joint out of the plane",
            ));
        }
    }
    let link = |name: &str| robot.links.iter().find(|l| l.name == name);
    let inertial = |name: &str| -> Result<(f64, f64, f64)> {
        let element = format!("link {name}");
        let l = link(name).ok_or_else(|| err(path, element.clone(), "not found"))?;
        let i = &l.inertial;
        if !i.mass.value.is_finite() || i.mass.value <= 0.0 {
            return Err(err(
                path,
                element,
                "<inertial> missing or mass ≤ 0 (urdf-rs reads a missing one as mass 0)",
            ));
        }
        let o = i.origin.xyz.0;
        if o[1].abs() > 1e-9 {
            return Err(err(
                path,
                element,
                "centre of mass must lie on the link's x axis (y = 0)",
            ));
        }
        let izz = i.inertia.izz;
        if !izz.is_finite() || izz <= 0.0 {
            return Err(err(path, element, "<inertia izz> must be > 0"));
        }
        Ok((i.mass.value, o[0], izz))
    };
    let (m1, lc1, i1) = inertial(&j1.child.link)?;
    let (m2, lc2, i2) = inertial(&j2.child.link)?;
    let o2 = j2.origin.xyz.0;
    if o2[1].abs() > 1e-9 {
        return Err(err(
            path,
            format!("joint {}", j2.name),
            "<origin> must lie on link 1's x axis",
        ));
    }
    let l1 = o2[0];
    let tool = robot
        .joints
        .iter()
        .find(|j| {
            matches!(j.joint_type, urdf_rs::JointType::Fixed) && j.parent.link == j2.child.link
        })
        .ok_or_else(|| {
            err(
                path,
                format!("link {}", j2.child.link),
                "needs a fixed tool joint whose origin gives l2",
            )
        })?;
    let l2 = tool.origin.xyz.0[0];
    let params = ScaraParameters {
        m1,
        m2,
        l1,
        l2,
        lc1,
        lc2,
        i1,
        i2,
    };
    pvfc_core::mechanics::Scara::new(params)?;
    Ok(params)
}
