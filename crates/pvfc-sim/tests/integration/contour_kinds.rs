//! A contour in one place: `[contour]` holds one table named for its kind (`lissajous`,
//! `waypoints`, `ellipse`, `cartesian`, `attitude`). The form before kinds still reads, as the
//! same scenario, with a deprecation message; errors name the kind and the key.

use pvfc_sim::model::arm::JointContourSpec;
use pvfc_sim::scenario::{ContourSpec, Scenario};
use std::path::Path;

fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn shipped(name: &str) -> (String, Scenario) {
    let path = repo().join("scenarios").join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let s = Scenario::from_file(&path).unwrap();
    assert!(s.deprecations.is_empty(), "{name}: {:?}", s.deprecations);
    (text, s)
}

fn parse(text: &str, base: &Scenario) -> Result<Scenario, String> {
    Scenario::parse(text, Path::new("c.toml"), base.base_dir.clone()).map_err(|e| e.to_string())
}

/// A rewrite of a file's text into an older form.
type Rewrite = dyn Fn(&str) -> String;

/// Each way a contour was written before kinds reads as the contour its new form gives, and
/// is named in a deprecation message.
#[test]
fn the_form_before_kinds_reads_as_the_new_one() {
    let cases: [(&str, &Rewrite); 5] = [
        // The SCARA's Lissajous keys directly under [contour].
        ("fig8_R100.toml", &|t| {
            t.replace("[contour.lissajous]", "[contour]")
        }),
        // A URDF arm's waypoints array and spacing beside it.
        ("ur5_waypoints.toml", &|t| {
            t.replace("[contour.waypoints]", "[contour]")
                .replace("\npoints = [", "\nwaypoints = [")
        }),
        // A Cartesian path's spacing (fixed samples) outside its table.
        ("ur5_press.toml", &|t| {
            t.replace(
                "[contour.cartesian]\nspacing = 0.5    # τ between waypoints: one pass is τ = 12\n",
                "[contour]\nspacing = 0.5\n\n[contour.cartesian]\n",
            )
        }),
        // A Cartesian path's period (adaptive sampling) outside its table.
        ("ur5_cartesian.toml", &|t| {
            t.replace(
                "[contour.cartesian]\nperiod = 12.0    # τ per pass of the path\n",
                "[contour]\nperiod = 12.0\n\n[contour.cartesian]\n",
            )
        }),
        // A joint-space table with the SCARA's unused keys beside it (what the serializer of
        // the form before kinds wrote for every URDF arm).
        ("panda_lissajous.toml", &|t| {
            t.replace(
                "[contour.lissajous]",
                "[contour]\namplitude = [1.0, 1.5]\nperiods = [3.0, 6.0]\nphase = [0.0, 0.0]\nperiod = 6.0\n\n[contour.lissajous]",
            )
        }),
    ];
    for (name, old_form) in cases {
        let (text, s) = shipped(name);
        let old = old_form(&text);
        assert_ne!(old, text, "{name}: the rewrite applies");
        let o = parse(&old, &s).unwrap();
        assert_eq!(o.contour, s.contour, "{name}");
        assert_eq!(o.period(), s.period(), "{name}");
        assert!(
            o.deprecations.iter().any(|d| d.starts_with("contour:")),
            "{name}: {:?}",
            o.deprecations
        );
    }
    // The SCARA's keys left out were the paper's: only the period given.
    let (_, base) = shipped("fig8_R100.toml");
    let text = base.to_toml().unwrap();
    let at = text.find("[contour.lissajous]").unwrap();
    let end = text[at..].find("\n\n").map_or(text.len(), |e| at + e);
    let old = format!("{}[contour]\nperiod = 12.0{}", &text[..at], &text[end..]);
    let o = parse(&old, &base).unwrap();
    assert_eq!(o.period(), 12.0);
    let ContourSpec::Joint(JointContourSpec::Lissajous {
        amplitude, phase, ..
    }) = &o.contour
    else {
        panic!("{:?}", o.contour);
    };
    assert_eq!(
        (amplitude.as_slice(), phase[1]),
        (&[1.0, 1.5][..], std::f64::consts::FRAC_PI_2)
    );
}

/// A contour read from a Python dict (JSON) is the one read from TOML.
#[test]
fn a_dict_and_a_file_give_one_contour() {
    for name in [
        "fig8_R100.toml",
        "ur5_waypoints.toml",
        "ur5_cartesian.toml",
        "satellite.toml",
    ] {
        let (_, s) = shipped(name);
        let json = serde_json::to_value(&s.contour).unwrap();
        assert_eq!(ContourSpec::from_value(json).unwrap(), s.contour, "{name}");
    }
}

/// Bad contours are refused naming the kind and the key.
#[test]
fn bad_contours_are_named() {
    let (text, scara) = shipped("fig8_R100.toml");
    let (chain_text, chain) = shipped("ur5_waypoints.toml");
    let cases: [(&str, &Scenario, String); 6] = [
        (
            "unknown variant `spiral`",
            &scara,
            text.replace("[contour.lissajous]", "[contour.spiral]"),
        ),
        (
            "`cartesian`, `attitude`",
            &scara,
            text.replace("[contour.lissajous]", "[contour.spiral]"),
        ),
        (
            "contour.lissajous: missing field `periods`",
            &scara,
            text.replace("periods = [3.0, 6.0]\n", ""),
        ),
        (
            "contour.lissajous: unknown field `amplitudes`",
            &scara,
            text.replace("amplitude = ", "amplitudes = "),
        ),
        (
            "one kind of contour",
            &chain,
            format!("{chain_text}\n[contour.ellipse]\ncenter = [0.0]\nu = [1.0]\nw = [0.0]\nperiod = 1.0\n"),
        ),
        (
            "contour.cartesian.period is needed",
            &chain,
            shipped("ur5_cartesian.toml")
                .0
                .replace("period = 12.0    # τ per pass of the path\n", ""),
        ),
    ];
    for (expected, base, text) in cases {
        let e = match parse(&text, base) {
            Ok(s) => panic!("{expected}: accepted {:?}", s.contour),
            Err(e) => e,
        };
        assert!(e.contains(expected), "{expected}: {e}");
    }
    // The SCARA on waypoints: its contour is a Lissajous curve.
    let mut s = scara.clone();
    s.contour = ContourSpec::Joint(JointContourSpec::Waypoints {
        points: vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![0.0, 1.0]],
        spacing: 1.0,
    });
    let e = s.validate().unwrap_err().to_string();
    assert!(e.contains("the SCARA follows a Lissajous curve"), "{e}");
    // An empty [contour] says what to write.
    let at = text.find("[contour.lissajous]").unwrap();
    let end = text[at..].find("\n\n").map_or(text.len(), |e| at + e);
    let empty = format!("{}[contour]{}", &text[..at], &text[end..]);
    let e = parse(&empty, &scara).unwrap_err();
    assert!(e.contains("say its kind"), "{e}");
}
