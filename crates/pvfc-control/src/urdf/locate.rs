//! Where a URDF is wrong. urdf-rs refuses a bad file with a message that names no element
//! ("robot: custom: invalid float literal"); this reads the same text with an XML reader that
//! keeps positions (roxmltree) and finds the first element or attribute at fault: malformed
//! XML, a number that is not one, a list of the wrong length, a joint without its type or its
//! links. The message names the element (and the link or joint it belongs to), the attribute,
//! its value and the line.

use roxmltree::{Document, Node};

/// The numeric attributes of URDF elements and how many numbers each holds.
const NUMBERS: &[(&str, &str, usize)] = &[
    ("origin", "xyz", 3),
    ("origin", "rpy", 3),
    ("axis", "xyz", 3),
    ("mass", "value", 1),
    ("inertia", "ixx", 1),
    ("inertia", "ixy", 1),
    ("inertia", "ixz", 1),
    ("inertia", "iyy", 1),
    ("inertia", "iyz", 1),
    ("inertia", "izz", 1),
    ("limit", "lower", 1),
    ("limit", "upper", 1),
    ("limit", "effort", 1),
    ("limit", "velocity", 1),
    ("dynamics", "damping", 1),
    ("dynamics", "friction", 1),
    ("box", "size", 3),
    ("cylinder", "radius", 1),
    ("cylinder", "length", 1),
    ("sphere", "radius", 1),
    ("capsule", "radius", 1),
    ("capsule", "length", 1),
    ("mesh", "scale", 3),
    ("color", "rgba", 4),
    ("mimic", "multiplier", 1),
    ("mimic", "offset", 1),
    ("safety_controller", "soft_lower_limit", 1),
    ("safety_controller", "soft_upper_limit", 1),
    ("safety_controller", "k_position", 1),
    ("safety_controller", "k_velocity", 1),
    ("calibration", "rising", 1),
    ("calibration", "falling", 1),
];

/// The joint types URDF has.
const JOINT_TYPES: &[&str] = &[
    "revolute",
    "continuous",
    "prismatic",
    "fixed",
    "floating",
    "planar",
    "spherical",
];

/// The element at fault in `text` and what is wrong with it, as (element, message); `None`
/// if nothing is found (the caller keeps urdf-rs's message).
pub(crate) fn locate(text: &str) -> Option<(String, String)> {
    let doc = match Document::parse(text) {
        Ok(d) => d,
        Err(e) => {
            let p = e.pos();
            return Some((
                format!("line {}, column {}", p.row, p.col),
                format!("not well-formed XML: {e}"),
            ));
        }
    };
    doc.descendants()
        .filter(Node::is_element)
        .find_map(|n| bad_numbers(&doc, n).or_else(|| bad_joint(&doc, n)))
}

/// The element's name for a message: `<origin>` of joint `elbow`, line 12.
fn element(doc: &Document, n: Node) -> String {
    let line = doc.text_pos_at(n.range().start).row;
    let owner = n
        .ancestors()
        .find(|a| matches!(a.tag_name().name(), "link" | "joint"))
        .map(|a| {
            format!(
                " of {} {}",
                a.tag_name().name(),
                a.attribute("name").unwrap_or("(unnamed)")
            )
        })
        .unwrap_or_default();
    match n.tag_name().name() {
        "link" | "joint" => format!(
            "{} {}, line {line}",
            n.tag_name().name(),
            n.attribute("name").unwrap_or("(unnamed)")
        ),
        tag => format!("<{tag}>{owner}, line {line}"),
    }
}

fn bad_numbers(doc: &Document, n: Node) -> Option<(String, String)> {
    let tag = n.tag_name().name();
    NUMBERS
        .iter()
        .filter(|(t, _, _)| *t == tag)
        .find_map(|(_, attribute, count)| {
            let value = n.attribute(*attribute)?;
            let parts: Vec<&str> = value.split_whitespace().collect();
            let numbers = parts.iter().all(|p| p.parse::<f64>().is_ok());
            let what = match (parts.len() == *count, numbers) {
                (true, true) => return None,
                (_, false) => "is not a number",
                (false, true) => "has the wrong number of entries",
            };
            Some((
                element(doc, n),
                format!(
                    "{attribute}=\"{value}\" {what} (it holds {count} number{})",
                    if *count == 1 { "" } else { "s" }
                ),
            ))
        })
}

fn bad_joint(doc: &Document, n: Node) -> Option<(String, String)> {
    if n.tag_name().name() != "joint" || n.parent_element()?.tag_name().name() != "robot" {
        return None;
    }
    let problem = match n.attribute("type") {
        None => "has no type attribute".to_string(),
        Some(t) if !JOINT_TYPES.contains(&t) => {
            format!(
                "type=\"{t}\" is not a joint type ({})",
                JOINT_TYPES.join(", ")
            )
        }
        Some(_) => {
            let link = |tag: &str| {
                n.children()
                    .find(|c| c.tag_name().name() == tag)
                    .and_then(|c| c.attribute("link"))
            };
            match (link("parent"), link("child")) {
                (None, _) => "has no <parent link=\"…\">".into(),
                (_, None) => "has no <child link=\"…\">".into(),
                _ => return None,
            }
        }
    };
    Some((element(doc, n), problem))
}
