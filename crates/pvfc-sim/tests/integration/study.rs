//! Studies: a spec's axes over dotted scenario keys expand into validated scenarios (grids,
//! random draws, Latin hypercubes), reproducibly from a seed; bad keys and values are errors
//! that name them before anything runs.

use pvfc_sim::error::SimError;
use pvfc_sim::scenario::{presets, Scenario};
use pvfc_sim::study::sample::{latin_hypercube, normal_quantile, SplitMix64};
use pvfc_sim::study::spec::{Axis, Draw, Range, StudyController, StudySpec};

fn axis(key: &str) -> Axis {
    Axis {
        key: key.into(),
        also: Vec::new(),
        values: None,
        range: None,
        draw: None,
    }
}

fn spec(axes: Vec<Axis>) -> StudySpec {
    StudySpec {
        name: "s".into(),
        base: "fig8_R100.toml".into(),
        axes,
        points: Vec::new(),
        samples: None,
        seed: 0,
        latin_hypercube: false,
        metrics: Vec::new(),
        set: Default::default(),
        controller: Default::default(),
    }
}

fn error(s: &StudySpec, base: &Scenario) -> String {
    match s.runs(base) {
        Err(SimError::Setting(m)) => m,
        other => panic!("expected a setting error, got {:?}", other.map(|r| r.len())),
    }
}

#[test]
fn a_grid_is_every_combination_the_last_axis_fastest() {
    let base = presets::fig8(100);
    let mut a = axis("controller.self_pacing");
    a.values = Some(vec![0.0, 50.0, 100.0]);
    let mut b = axis("plant.friction.coulomb[1]");
    b.range = Some(Range {
        from: 1.0,
        to: 4.0,
        steps: 4,
        log: false,
    });
    let runs = spec(vec![a, b]).runs(&base).unwrap();
    assert_eq!(runs.len(), 12);
    for (i, r) in runs.iter().enumerate() {
        let (p, c) = ([0.0, 50.0, 100.0][i / 4], [1.0, 2.0, 3.0, 4.0][i % 4]);
        assert_eq!(r.index, i);
        assert_eq!(r.scenario.name, format!("s_{i:04}"));
        assert_eq!(r.scenario.controller.self_pacing, p);
        assert_eq!(r.scenario.plant.friction.coulomb, vec![2.5, c]);
        assert_eq!(
            r.parameters,
            vec![
                ("controller.self_pacing".to_string(), p),
                ("plant.friction.coulomb[1]".to_string(), c)
            ]
        );
        // Everything else is the base's.
        assert_eq!(r.scenario.controller.energy, base.controller.energy);
        assert_eq!(r.scenario.contour, base.contour);
    }
    // A log range is geometric.
    let mut g = axis("controller.energy");
    g.range = Some(Range {
        from: 100.0,
        to: 10_000.0,
        steps: 3,
        log: true,
    });
    let e: Vec<f64> = spec(vec![g])
        .runs(&base)
        .unwrap()
        .iter()
        .map(|r| r.scenario.controller.energy)
        .collect();
    assert!((e[1] - 1000.0).abs() < 1e-9 && e[0] == 100.0, "{e:?}");
}

#[test]
fn bad_keys_and_values_name_them_before_anything_runs() {
    let base = presets::fig8(100);
    let one = |key: &str, v: f64| {
        let mut a = axis(key);
        a.values = Some(vec![v]);
        spec(vec![a])
    };
    let m = error(&one("controller.self_pacng", 1.0), &base);
    assert!(
        m.contains("self_pacng") && m.contains("self_pacing") && m.contains("controller"),
        "{m}"
    );
    let m = error(&one("plant.friction.coulomb[2]", 1.0), &base);
    assert!(m.contains("coulomb[2]") && m.contains("2 entries"), "{m}");
    let m = error(&one("plant.friction.coulomb[x]", 1.0), &base);
    assert!(m.contains("name[index]"), "{m}");
    let m = error(&one("simulation.plant_substeps", 2.5), &base);
    assert!(m.contains("plant_substeps") && m.contains("integer"), "{m}");
    let m = error(&one("name", 1.0), &base);
    assert!(m.contains("not a number"), "{m}");
    let m = error(&one("controller.energy.level", 1.0), &base);
    assert!(m.contains("not a table"), "{m}");
    // A value the scenario rejects names the run and the values it was given.
    let m = error(&one("controller.energy", -5.0), &base);
    assert!(
        m.contains("run 0") && m.contains("controller.energy = -5"),
        "{m}"
    );
    // Axes: one kind of values each; draws need samples; no mixing grid and draws.
    let mut a = axis("controller.energy");
    a.values = Some(vec![1.0]);
    a.range = Some(Range {
        from: 1.0,
        to: 2.0,
        steps: 2,
        log: false,
    });
    assert!(error(&spec(vec![a]), &base).contains("exactly one"));
    let mut d = axis("controller.energy");
    d.draw = Some(Draw::Uniform {
        low: 100.0,
        high: 200.0,
    });
    assert!(error(&spec(vec![d.clone()]), &base).contains("samples"));
    let mut v = axis("controller.self_pacing");
    v.values = Some(vec![1.0]);
    assert!(error(&spec(vec![d.clone(), v]), &base).contains("all drawn"));
    d.draw = Some(Draw::Normal {
        mean: 1.0,
        std: 0.0,
    });
    let mut s = spec(vec![d]);
    s.samples = Some(3);
    assert!(error(&s, &base).contains("std > 0"));
    assert!(error(&spec(Vec::new()), &base).contains("no axis"));
    let mut nan = axis("controller.energy");
    nan.values = Some(vec![f64::NAN]);
    assert!(error(&spec(vec![nan]), &base).contains("finite"));
}

#[test]
fn random_studies_are_reproducible_from_their_seed() {
    let base = presets::fig8(100);
    let mut e = axis("controller.energy");
    e.draw = Some(Draw::Uniform {
        low: 1000.0,
        high: 3000.0,
    });
    let mut c = axis("plant.friction.coulomb[0]");
    c.draw = Some(Draw::Normal {
        mean: 2.5,
        std: 0.25,
    });
    let mut s = spec(vec![e, c]);
    s.samples = Some(400);
    s.seed = 7;
    let draws = |s: &StudySpec| -> Vec<Vec<f64>> {
        s.runs(&base)
            .unwrap()
            .iter()
            .map(|r| r.parameters.iter().map(|p| p.1).collect())
            .collect()
    };
    let first = draws(&s);
    assert_eq!(first.len(), 400);
    assert_eq!(first, draws(&s), "the same seed gives the same runs");
    s.seed = 8;
    assert_ne!(first, draws(&s), "another seed gives other runs");
    assert!(first.iter().all(|p| (1000.0..3000.0).contains(&p[0])));
    let n = first.len() as f64;
    let mean = first.iter().map(|p| p[1]).sum::<f64>() / n;
    let std = (first.iter().map(|p| (p[1] - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // 400 draws: the mean within 4 standard errors, the std within 15 %.
    assert!((mean - 2.5).abs() < 4.0 * 0.25 / n.sqrt(), "mean {mean}");
    assert!((std / 0.25 - 1.0).abs() < 0.15, "std {std}");
    // A Latin hypercube puts exactly one run in each of the `samples` strata of every axis.
    s.latin_hypercube = true;
    s.samples = Some(50);
    let lhs = draws(&s);
    let mut strata: Vec<usize> = lhs
        .iter()
        .map(|p| ((p[0] - 1000.0) / 2000.0 * 50.0).floor() as usize)
        .collect();
    strata.sort_unstable();
    assert_eq!(strata, (0..50).collect::<Vec<_>>());
}

#[test]
fn the_generator_and_the_quantile_are_the_published_ones() {
    // SplitMix64's first output from seed 0 (the reference implementation's).
    assert_eq!(SplitMix64::new(0).next_u64(), 0xE220_A839_7B1D_CDAF);
    for (p, x) in [
        (0.5, 0.0),
        (0.975, 1.959_963_984_540_054),
        (0.8413447460685429, 1.0),
        (1e-6, -4.753_424_308_822_899),
        (1.0 - 1e-9, 5.997_807_015_007_882),
    ] {
        let q = normal_quantile(p);
        assert!(
            (q - x).abs() < 1e-8 * (1.0 + x.abs()),
            "Φ⁻¹({p}) = {q}, not {x}"
        );
    }
    let mut rng = SplitMix64::new(3);
    let pts = latin_hypercube(10, 3, &mut rng);
    for k in 0..3 {
        let mut s: Vec<usize> = pts.iter().map(|p| (p[k] * 10.0) as usize).collect();
        s.sort_unstable();
        assert_eq!(s, (0..10).collect::<Vec<_>>());
    }
}

#[test]
fn a_study_file_names_its_base_relative_to_itself() {
    let dir = std::env::temp_dir().join(format!("pvfc-study-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("base.toml"), presets::fig8(100).to_toml().unwrap()).unwrap();
    std::fs::write(
        dir.join("study.toml"),
        "name = \"pacing\"\nbase = \"base.toml\"\n[[axis]]\nkey = \"controller.self_pacing\"\nvalues = [0, 100]\n",
    )
    .unwrap();
    let (spec, base) = StudySpec::from_file(&dir.join("study.toml")).unwrap();
    let runs = spec.runs(&base).unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[1].scenario.controller.self_pacing, 100.0);
    std::fs::write(
        dir.join("bad.toml"),
        "name = \"x\"\nbase = \"base.toml\"\n[[axis]]\nkey = \"a\"\nvalue = [1]\n",
    )
    .unwrap();
    match StudySpec::from_file(&dir.join("bad.toml")) {
        Err(SimError::Scenario { message, .. }) => assert!(message.contains("value"), "{message}"),
        other => panic!("an unknown field is an error: {:?}", other.map(|_| ())),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

fn a_values(key: &str, values: Vec<f64>) -> Axis {
    let mut a = axis(key);
    a.values = Some(values);
    a
}

#[test]
fn nested_lists_shared_settings_and_metrics_by_name() {
    let ur5 = Scenario::from_file(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/ur5_cartesian.toml"),
    )
    .expect("the UR5 preset");
    // A corner of the Cartesian path, by `points[i][j]`: reachable, then out of reach, which
    // the validation names by its waypoint before anything runs.
    let mut a = axis("contour.cartesian.points[1][0]");
    a.values = Some(vec![0.66]);
    let runs = spec(vec![a.clone()])
        .runs(&ur5)
        .expect("a reachable corner");
    let c = runs[0].scenario.contour.cartesian().expect("a path");
    assert_eq!(c.points[1], [0.66, -0.15, 0.30]);
    a.values = Some(vec![3.0]);
    let m = error(&spec(vec![a]), &ur5);
    assert!(
        m.contains("points[1][0] = 3") && m.contains("waypoint"),
        "{m}"
    );
    // Settings every run shares: applied before the axes, checked like them.
    let mut shared = spec(vec![a_values("controller.gamma", vec![0.01, 0.02])]);
    shared.set.insert("duration".into(), 45.0);
    shared
        .set
        .insert("contour.cartesian.corner_radius".into(), 0.02);
    let runs = shared.runs(&ur5).expect("shared settings");
    assert!(runs.iter().all(|r| r.scenario.duration == 45.0));
    shared.set.insert("duraton".into(), 1.0);
    let m = error(&shared, &ur5);
    assert!(m.contains("set `duraton`") && !m.contains("axis"), "{m}");
    // Metrics by name: all by default, in the documented order; an unknown one named.
    let mut s = spec(vec![]);
    let all = s.metrics().expect("all");
    assert_eq!(all.len(), pvfc_sim::study::metrics::METRICS.len());
    s.metrics = vec!["peak_force".into(), "mean_u".into()];
    let names: Vec<&str> = s.metrics().expect("two").iter().map(|m| m.name).collect();
    assert_eq!(names, ["peak_force", "mean_u"]);
    s.metrics.push("peak_force".into());
    assert!(s.metrics().is_err_and(|e| e.to_string().contains("twice")));
    s.metrics = vec!["peak".into()];
    let e = s.metrics().expect_err("unknown").to_string();
    assert!(e.contains("`peak`") && e.contains("tool_path_max"), "{e}");
}

#[test]
fn the_arrow_table_is_an_ipc_file_of_the_rows() {
    use pvfc_sim::study::{arrow, runner::StudyRow};
    let keys = vec!["controller.energy".to_string()];
    let metrics = ["mean_u", "peak_force"];
    let rows: Vec<StudyRow> = (0..3)
        .map(|i| StudyRow {
            index: i,
            parameters: vec![800.0 + 0.1 * i as f64],
            metrics: vec![Some(1.0 / (i + 1) as f64), None],
            error: (i == 1).then(|| "the run diverged".to_string()),
        })
        .collect();
    let bytes = arrow::encode(&keys, &metrics, &rows).unwrap();
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    // The magic, padded, then the schema message: a continuation marker and a metadata
    // length that keeps the body 8-byte aligned.
    assert_eq!(&bytes[..8], b"ARROW1\0\0");
    assert_eq!(word(8), u32::MAX);
    let schema = word(12) as usize;
    assert_eq!(schema % 8, 0);
    // The record batch's message follows the schema's (which has no body).
    assert_eq!(word(16 + schema), u32::MAX);
    assert_eq!(word(20 + schema) % 8, 0);
    // The footer, its length, and the magic at the end.
    let n = bytes.len();
    assert_eq!(&bytes[n - 6..], b"ARROW1");
    let footer = word(n - 10) as usize;
    assert!(footer > 0 && footer < n - 10 - 24 - schema);
    // The end-of-stream marker before the footer.
    assert_eq!(word(n - 10 - footer - 8), u32::MAX);
    assert_eq!(word(n - 10 - footer - 4), 0);
    // Each column's values, contiguous, little-endian, bit for bit.
    let find = |needle: &[u8]| bytes.windows(needle.len()).any(|w| w == needle);
    let column = |f: &dyn Fn(&StudyRow) -> Vec<u8>| rows.iter().flat_map(f).collect::<Vec<u8>>();
    assert!(find(&column(&|r| (r.index as i64).to_le_bytes().to_vec())));
    assert!(find(&column(&|r| r.parameters[0].to_le_bytes().to_vec())));
    assert!(find(&column(&|r| r.metrics[0]
        .unwrap()
        .to_le_bytes()
        .to_vec())));
    assert!(find(b"the run diverged"));
    for name in ["run", "controller.energy", "mean_u", "peak_force", "error"] {
        assert!(find(name.as_bytes()), "{name}");
    }
    // A row that is not the table's shape is an error naming it.
    let mut bad = rows.clone();
    bad[2].metrics.pop();
    let e = arrow::encode(&keys, &metrics, &bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("row 2"), "{e}");
}

#[test]
fn a_failing_tool_path_analysis_is_the_runs_error_not_an_absent_metric() {
    use pvfc_sim::study::metrics::{select, RunView};
    use pvfc_sim::trace::{series::JointSeries, Trace};
    let ur5 = Scenario::from_file(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/ur5_cartesian.toml"),
    )
    .expect("the UR5 preset");
    let robot = ur5.robot().expect("robot");
    // Three passes of a trace whose joint angles are not numbers: the tool's forward
    // kinematics fails on them.
    let n = 300;
    let period = ur5.period();
    let tau: Vec<f64> = (0..n)
        .map(|k| 3.0 * period * k as f64 / (n - 1) as f64)
        .collect();
    let mut trace = Trace {
        t: tau.clone(),
        tau,
        q: JointSeries::from_flat(6, vec![f64::NAN; 6 * n]).expect("6 joints"),
        ..Trace::default()
    };
    let metrics = select(&["final_beta".into(), "tool_path_mean".into()]).expect("metrics");
    let e = RunView::new(&ur5, &trace, Some(&robot))
        .values(&metrics)
        .expect_err("the tool path of NaN joint angles");
    assert!(e.to_string().contains("NaN"), "{e}");
    // Without a tool-path metric the analysis is not run, and nothing fails.
    let beta = select(&["final_beta".into()]).expect("metrics");
    assert_eq!(
        RunView::new(&ur5, &trace, Some(&robot))
            .values(&beta)
            .expect("no tool path asked for"),
        vec![None]
    );
    // With finite joint angles at the contour's start the metric is there.
    trace.q = JointSeries::from_flat(6, ur5.initial.q.repeat(n)).expect("6 joints");
    let ok = RunView::new(&ur5, &trace, Some(&robot))
        .values(&metrics)
        .expect("a tool path");
    assert!(ok[1].is_some_and(|d| d.is_finite()), "{ok:?}");
}

/// An integer draw (a fault's joint) takes every integer of its range, each about as often,
/// and sets an integer key; a range with `low > high` is named.
#[test]
fn integer_draws_cover_their_range_and_set_integer_keys() {
    let base = Scenario::from_file(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/scara_faults.toml"),
    )
    .unwrap();
    let mut j = axis("faults[0].joint");
    j.draw = Some(Draw::Integer { low: 0, high: 1 });
    let mut s = spec(vec![j.clone()]);
    s.samples = Some(200);
    let runs = s.runs(&base).unwrap();
    let ones = runs
        .iter()
        .filter(|r| r.scenario.faults[0].joint == 1)
        .count();
    assert!(
        runs.iter().all(|r| r.scenario.faults[0].joint <= 1),
        "a joint outside 0..=1"
    );
    assert!((70..=130).contains(&ones), "{ones} of 200 draws are 1");
    j.draw = Some(Draw::Integer { low: 2, high: 1 });
    let mut s = spec(vec![j]);
    s.samples = Some(3);
    assert!(error(&s, &base).contains("low ≤ high"));
}

/// An axis's tied keys (`also`) take its value on every run; its column is its key's.
#[test]
fn an_axis_sets_its_tied_keys_to_the_same_value() {
    let base = presets::fig8(100);
    let mut a = a_values("plant.friction.coulomb[0]", vec![1.0, 4.0]);
    a.also = vec!["plant.friction.coulomb[1]".into()];
    let runs = spec(vec![a]).runs(&base).unwrap();
    assert_eq!(runs.len(), 2);
    for (r, c) in runs.iter().zip([1.0, 4.0]) {
        assert_eq!(r.scenario.plant.friction.coulomb, vec![c, c]);
        assert_eq!(
            r.parameters,
            vec![("plant.friction.coulomb[0]".to_string(), c)]
        );
    }
    let mut bad = a_values("controller.energy", vec![1.0]);
    bad.also = vec!["controller.no_such_key".into()];
    assert!(error(&spec(vec![bad]), &base).contains("no_such_key"));
}

fn point(entries: &[(&str, f64)]) -> std::collections::BTreeMap<String, f64> {
    entries.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// Design points multiply the runs, the points fastest: each run of the axes at every point,
/// each point's keys set and in the run's parameters after the axes'; a study of points alone
/// runs each once; points that set different keys, a key an axis sets too, a non-finite value
/// or an unknown key are errors naming the point and the key.
#[test]
fn design_points_multiply_the_runs_the_points_fastest() {
    let base = presets::fig8(100);
    let mut s = spec(vec![a_values("controller.self_pacing", vec![0.0, 50.0])]);
    // A fractional design: the friction high where the masses differ.
    s.points = vec![
        point(&[
            ("plant.friction.coulomb[0]", 2.0),
            ("plant.friction.coulomb[1]", 2.8),
        ]),
        point(&[
            ("plant.friction.coulomb[0]", 3.0),
            ("plant.friction.coulomb[1]", 4.2),
        ]),
        point(&[
            ("plant.friction.coulomb[0]", 2.5),
            ("plant.friction.coulomb[1]", 3.5),
        ]),
    ];
    assert_eq!(
        s.keys(),
        [
            "controller.self_pacing",
            "plant.friction.coulomb[0]",
            "plant.friction.coulomb[1]"
        ]
    );
    let runs = s.runs(&base).unwrap();
    assert_eq!(runs.len(), 6);
    let frictions = [[2.0, 2.8], [3.0, 4.2], [2.5, 3.5]];
    for (i, r) in runs.iter().enumerate() {
        let (pace, c) = ([0.0, 50.0][i / 3], frictions[i % 3]);
        assert_eq!(r.scenario.controller.self_pacing, pace);
        assert_eq!(r.scenario.plant.friction.coulomb, c.to_vec());
        assert_eq!(
            r.parameters,
            vec![
                ("controller.self_pacing".to_string(), pace),
                ("plant.friction.coulomb[0]".to_string(), c[0]),
                ("plant.friction.coulomb[1]".to_string(), c[1]),
            ]
        );
    }
    // Read from a study's TOML the same.
    let text = r#"
name = "s"
[[axis]]
key = "controller.self_pacing"
values = [0.0, 50.0]
[[point]]
"plant.friction.coulomb[0]" = 2.0
"plant.friction.coulomb[1]" = 2.8
[[point]]
"plant.friction.coulomb[0]" = 3.0
"plant.friction.coulomb[1]" = 4.2
[[point]]
"plant.friction.coulomb[0]" = 2.5
"plant.friction.coulomb[1]" = 3.5
"#;
    let read = StudySpec::from_toml(text, "s.toml".as_ref()).unwrap();
    assert_eq!(read.points, s.points);
    let again = StudySpec::from_toml(&read.to_toml().unwrap(), "s.toml".as_ref()).unwrap();
    assert_eq!(again, read);
    // Points alone: one run each.
    let mut alone = spec(Vec::new());
    alone.points = s.points.clone();
    let runs = alone.runs(&base).unwrap();
    assert_eq!(runs.len(), 3);
    assert_eq!(runs[1].scenario.plant.friction.coulomb, vec![3.0, 4.2]);
    // Random draws: every draw at every point.
    let mut drawn = axis("controller.energy");
    drawn.draw = Some(Draw::Uniform {
        low: 500.0,
        high: 1000.0,
    });
    let mut r = spec(vec![drawn]);
    r.samples = Some(4);
    r.points = s.points.clone();
    let runs = r.runs(&base).unwrap();
    assert_eq!(runs.len(), 12);
    for k in 0..4 {
        let e = runs[3 * k].scenario.controller.energy;
        assert!((500.0..1000.0).contains(&e));
        for j in 0..3 {
            assert_eq!(runs[3 * k + j].scenario.controller.energy, e);
            assert_eq!(
                runs[3 * k + j].scenario.plant.friction.coulomb,
                frictions[j].to_vec()
            );
        }
    }
    // Errors.
    let mut differ = alone.clone();
    differ.points[2] = point(&[
        ("plant.friction.coulomb[0]", 1.0),
        ("controller.energy", 900.0),
    ]);
    let m = error(&differ, &base);
    assert!(
        m.contains("point 2") && m.contains("controller.energy"),
        "{m}"
    );
    let mut nan = alone.clone();
    nan.points[1].insert("plant.friction.coulomb[1]".into(), f64::NAN);
    let m = error(&nan, &base);
    assert!(m.contains("point 1") && m.contains("not finite"), "{m}");
    let mut both = s.clone();
    both.axes[0].key = "plant.friction.coulomb[1]".into();
    assert!(error(&both, &base).contains("both an axis's key and a point's"));
    let mut unknown = alone.clone();
    for p in &mut unknown.points {
        p.insert("controller.no_such_key".into(), 1.0);
    }
    let m = error(&unknown, &base);
    assert!(m.contains("point 0") && m.contains("no_such_key"), "{m}");
    let mut empty = alone;
    empty.points = vec![Default::default()];
    assert!(error(&empty, &base).contains("sets no key"));
    assert!(error(&spec(Vec::new()), &base).contains("no axis and no point"));
}

/// `controller = "timed"` / `"speed_scaling"` runs the base's tracker at its `tau_rate`: a
/// base without `[baseline]`, without `tau_rate`, or (for the speed-scaling one) without
/// `speed_scaling` is named before anything runs; the tracker's run has its trace, the
/// tracker's share of samples at a limit and the distance to the contour.
#[test]
fn a_study_runs_a_baseline_tracker_on_the_same_runs() {
    use pvfc_sim::study::metrics::select;
    use pvfc_sim::study::runner::run_one;
    let base = presets::fig1_saturated(pvfc_sim::scenario::preset_id::Fig1Contour::Circle, 300);
    let mut s = spec(vec![a_values("controller.self_pacing", vec![100.0])]);
    s.metrics = vec![
        "limit_share".into(),
        "contour_distance_mean".into(),
        "pass_duration".into(),
    ];
    let metrics = s.metrics().unwrap();
    let mut shares = Vec::new();
    for c in [
        StudyController::Pvfc,
        StudyController::Timed,
        StudyController::SpeedScaling,
    ] {
        s.controller = c;
        let runs = s.runs(&base).unwrap();
        assert_eq!(runs[0].controller, c);
        let row = run_one(&runs[0], &metrics);
        assert!(row.error.is_none(), "{c:?}: {:?}", row.error);
        let [share, distance, lap] = [row.metrics[0], row.metrics[1], row.metrics[2]]
            .map(|m| m.unwrap_or_else(|| panic!("{c:?}: a metric is absent: {row:?}")));
        assert!((0.0..=1.0).contains(&share) && distance >= 0.0 && lap > 0.0);
        shares.push((share, distance));
    }
    // At r = 3 on 15 / 5 N·m (fig1.saturated): the timed tracker is at its limits nearly
    // always and leaves the contour; PVFC never is, and stays on it.
    let (pvfc, timed) = (shares[0], shares[1]);
    assert!(pvfc.0 < 0.05 && timed.0 > 0.5, "shares {pvfc:?} {timed:?}");
    assert!(timed.1 > 10.0 * pvfc.1, "distances {pvfc:?} {timed:?}");
    // What a tracker's study needs.
    let mut no_rate = base.clone();
    no_rate.baseline.as_mut().unwrap().tau_rate = None;
    s.controller = StudyController::Timed;
    assert!(error(&s, &no_rate).contains("tau_rate"));
    let mut no_scaling = base.clone();
    no_scaling.baseline.as_mut().unwrap().speed_scaling = None;
    s.controller = StudyController::SpeedScaling;
    assert!(error(&s, &no_scaling).contains("speed_scaling"));
    let mut none = base;
    none.baseline = None;
    assert!(error(&s, &none).contains("[baseline]"));
    assert!("tracker".parse::<StudyController>().is_err());
    assert_eq!(
        "speed_scaling".parse::<StudyController>().unwrap(),
        StudyController::SpeedScaling
    );
    let _ = select(&["limit_share".into()]).unwrap();
}
