//! Robots from URDF files (urdf-rs), with the checks urdf-rs does not make: any serial chain
//! ([`chain`]) and the paper's planar two-link arm in closed form ([`scara`]).

pub mod chain;
pub mod collision;
mod locate;
pub mod scara;

pub use chain::{ChainDescription, JointDescription, JointLimits};
pub use collision::{CollisionGeometry, LinkCollision};
pub use scara::{scara_from_urdf, scara_from_urdf_str};

use crate::error::SimError;
use std::path::Path;

/// A [`SimError::Urdf`] naming the file and the element at fault.
pub(crate) fn err(path: &Path, element: impl Into<String>, message: impl Into<String>) -> SimError {
    SimError::Urdf {
        path: path.to_path_buf(),
        element: element.into(),
        message: message.into(),
    }
}

/// Parses URDF text with urdf-rs; when it refuses the text, the error names the element,
/// attribute and line at fault ([`locate`]). Empty `<texture/>` elements (no `filename`: invalid URDF,
/// and only ever visual, which pvfc never reads; iCub's and Romeo's files have them) are
/// dropped first, since urdf-rs refuses them with a message that names no element.
pub(crate) fn parse(text: &str, path: &Path) -> crate::error::Result<urdf_rs::Robot> {
    urdf_rs::read_from_string(&without_empty_textures(text)).map_err(|e| {
        // urdf-rs names no element: find it (the element, its line, the attribute).
        match locate::locate(text) {
            Some((element, message)) => err(path, element, format!("{message} ({e})")),
            None => err(path, "robot", e.to_string()),
        }
    })
}

/// `text` without its `<texture/>` elements that have no attribute.
fn without_empty_textures(text: &str) -> std::borrow::Cow<'_, str> {
    const OPEN: &str = "<texture";
    if !text.contains(OPEN) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find(OPEN) {
        let after = &rest[i + OPEN.len()..];
        // An empty element: `<texture/>`, `<texture />` or `<texture></texture>`.
        let inner = after.trim_start();
        let end = if let Some(tail) = inner.strip_prefix("/>") {
            Some(after.len() - tail.len())
        } else if let Some(tail) = inner.strip_prefix('>') {
            tail.trim_start()
                .strip_prefix("</texture>")
                .map(|t| after.len() - t.len())
        } else {
            None
        };
        match end {
            Some(n) => {
                out.push_str(&rest[..i]);
                rest = &after[n..];
            }
            None => {
                out.push_str(&rest[..i + OPEN.len()]);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    std::borrow::Cow::Owned(out)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::without_empty_textures;

    #[test]
    fn only_empty_textures_are_dropped() {
        let text = r#"<material name="m"><texture /><color rgba="1 0 0 1"/></material>
<material name="n"><texture/></material><material name="o"><texture></texture></material>
<material name="p"><texture filename="wood.png"/></material><texturex/>"#;
        let out = without_empty_textures(text);
        assert_eq!(
            out,
            r#"<material name="m"><color rgba="1 0 0 1"/></material>
<material name="n"></material><material name="o"></material>
<material name="p"><texture filename="wood.png"/></material><texturex/>"#
        );
        assert!(matches!(
            without_empty_textures("<robot/>"),
            std::borrow::Cow::Borrowed(_)
        ));
    }
}
