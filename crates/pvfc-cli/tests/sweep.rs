//! `pvfc sweep` as a user runs it: a grid into its table, the same table from 1 and 2
//! threads, an interrupted sweep resumed to the same bytes, failed runs as rows, bad
//! metrics named before anything runs, and a figure per metric.

use pvfc_cli::study_plot::study_figures;
use pvfc_cli::sweep::sweep;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pvfc_sweep_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a scratch directory");
    d
}

/// A study over Fig. 8's run shortened to 13 s (two passes of the 6-s contour).
fn study(dir: &Path, axes: &str, metrics: &str) -> PathBuf {
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/fig8_R100.toml"),
    )
    .expect("the preset")
    .replace("duration = 40.0", "duration = 13.0");
    std::fs::write(dir.join("base.toml"), base).expect("write base");
    let path = dir.join("study.toml");
    std::fs::write(
        &path,
        format!("name = \"s\"\nbase = \"base.toml\"\nmetrics = {metrics}\n{axes}"),
    )
    .expect("write study");
    path
}

const GRID: &str = "[[axis]]\nkey = \"controller.self_pacing\"\nvalues = [0, 200]\n\
                    [[axis]]\nkey = \"controller.energy\"\nvalues = [800, 2000, 3200]\n";
const METRICS: &str = "[\"mean_u\", \"mean_tau_rate\", \"peak_force\", \"final_beta\"]";

fn quiet(_: usize, _: usize) {}

#[test]
fn a_grid_runs_into_one_table_the_same_from_one_and_two_threads() {
    let dir = scratch("grid");
    let path = study(&dir, GRID, METRICS);
    let one = sweep(&path, &dir.join("one"), 1, None, &mut quiet).expect("sweep");
    let two = sweep(&path, &dir.join("two"), 2, None, &mut quiet).expect("sweep");
    assert_eq!((one.ran, one.resumed, one.failed()), (6, 0, 0));
    let text = std::fs::read_to_string(&one.csv).expect("table");
    assert_eq!(text, std::fs::read_to_string(&two.csv).expect("table"));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "run,controller.self_pacing,controller.energy,mean_u,mean_tau_rate,peak_force,final_beta,error"
    );
    assert_eq!(lines.len(), 7);
    // The last axis fastest; no contact, so no peak force; every run has U and τ̇.
    assert!(lines[2].starts_with("1,0.0,2000.0,"), "{}", lines[2]);
    for r in &one.rows {
        assert!(r.metrics[0].is_some_and(|u| u > 0.0 && u < 0.1), "{r:?}");
        assert!(r.metrics[1].is_some_and(|v| v > 0.1), "{r:?}");
        assert_eq!(r.metrics[2], None);
    }
    // More energy, less contour error (Fig. 9's ordering) at either self-pacing gain.
    for row in [0, 3] {
        let u: Vec<f64> = (row..row + 3)
            .map(|i| one.rows[i].metrics[0].expect("U"))
            .collect();
        assert!(u[0] > u[1] && u[1] > u[2], "{u:?}");
    }
    // The numbers read back bit for bit.
    let cells: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(
        cells[3].parse::<f64>().expect("a number").to_bits(),
        one.rows[0].metrics[0].expect("U").to_bits()
    );
}

#[test]
fn an_interrupted_sweep_resumes_to_the_same_table() {
    let dir = scratch("resume");
    let path = study(&dir, GRID, METRICS);
    let whole = sweep(&path, &dir.join("whole"), 2, None, &mut quiet).expect("sweep");
    let expected = std::fs::read(&whole.csv).expect("table");
    let out = dir.join("cut");
    let first = sweep(&path, &out, 2, Some(2), &mut quiet).expect("sweep");
    assert_eq!((first.ran, first.rows.len()), (2, 2));
    let partial = std::fs::read(&first.arrow).expect("the partial table's Arrow file");
    // A run cut short while its row was being written.
    let mut text = std::fs::read_to_string(&first.csv).expect("table");
    text.push_str("5,200.0,32");
    std::fs::write(&first.csv, text).expect("write");
    let rest = sweep(&path, &out, 2, None, &mut quiet).expect("resume");
    assert_eq!((rest.resumed, rest.ran, rest.rows.len()), (2, 4, 6));
    assert_eq!(std::fs::read(&rest.csv).expect("table"), expected);
    // The Arrow file holds the whole table too, resumed rows and new alike.
    assert_eq!(
        std::fs::read(&rest.arrow).expect("arrow"),
        std::fs::read(&whole.arrow).expect("arrow")
    );
    assert_ne!(partial, std::fs::read(&whole.arrow).expect("arrow"));
    // Nothing left: a third sweep runs nothing.
    let again = sweep(&path, &out, 2, None, &mut quiet).expect("again");
    assert_eq!((again.resumed, again.ran), (6, 0));
    // Another study's table in the same place is an error, not overwritten.
    let other = study(&dir, GRID, "[\"mean_u\"]");
    let e = sweep(&other, &out, 1, None, &mut quiet).expect_err("another study's table");
    assert!(e.to_string().contains("not this study's"), "{e}");
}

#[test]
fn failed_runs_are_rows_and_bad_metrics_are_named() {
    let dir = scratch("fail");
    let path = study(&dir, GRID, "[\"mean_u\", \"contour_eror\"]");
    let e = sweep(&path, &dir.join("out"), 1, None, &mut quiet).expect_err("a bad metric");
    let m = e.to_string();
    assert!(m.contains("contour_eror") && m.contains("mean_u"), "{m}");
    assert!(!dir.join("out").exists(), "nothing ran");
    // A coupling gain far beyond what a 1 kHz controller can sample diverges: that run
    // fails when it runs, the others do not, and the sweep goes on.
    let p = study(
        &dir,
        "[[axis]]\nkey = \"controller.gamma\"\nvalues = [1e5, 0.025, 1e8]\n",
        "[\"mean_u\"]",
    );
    let o = sweep(&p, &dir.join("gamma"), 2, None, &mut quiet).expect("the sweep itself");
    assert_eq!((o.rows.len(), o.failed()), (3, 2));
    for i in [0, 2] {
        let why = o.rows[i].error.as_deref().unwrap_or("");
        assert!(why.contains("not finite"), "{why}");
        assert_eq!(o.rows[i].metrics, vec![None]);
    }
    assert!(o.rows[1].error.is_none() && o.rows[1].metrics[0].is_some());
    let text = std::fs::read_to_string(&o.csv).expect("table");
    assert_eq!(text.lines().count(), 4);
    assert!(text
        .lines()
        .nth(1)
        .is_some_and(|l| l.starts_with("0,100000.0,,")));
}

#[test]
fn figures_per_metric_a_heat_map_a_line_and_a_histogram() {
    let dir = scratch("figures");
    let two = sweep(
        &study(&dir, GRID, METRICS),
        &dir.join("a"),
        2,
        None,
        &mut quiet,
    )
    .expect("sweep");
    let files = study_figures(&two.spec, &two.rows, &dir.join("a")).expect("figures");
    // peak_force has no value without contact: no figure.
    let names: Vec<String> = files
        .iter()
        .map(|f| {
            f.file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    assert_eq!(
        names,
        ["s_mean_u.png", "s_mean_tau_rate.png", "s_final_beta.png"]
    );
    let one_axis =
        "[[axis]]\nkey = \"controller.gamma\"\nrange = { from = 0.01, to = 0.04, steps = 3 }\n";
    let drawn = "samples = 6\nseed = 7\n[[axis]]\nkey = \"controller.energy\"\n\
                 draw = { normal = { mean = 2000, std = 200 } }\n";
    for (name, axes) in [("line", one_axis), ("random", drawn)] {
        let d = dir.join(name);
        std::fs::create_dir_all(&d).expect("dir");
        let o = sweep(&study(&d, axes, "[\"mean_u\"]"), &d, 2, None, &mut quiet).expect("sweep");
        let f = study_figures(&o.spec, &o.rows, &d).expect("figures");
        assert_eq!(f.len(), 1);
        assert!(std::fs::metadata(&f[0]).expect("a file").len() > 5_000);
    }
}

#[test]
fn the_example_studies_expand_into_valid_runs() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies");
    let mut seen = 0;
    for e in std::fs::read_dir(&dir).expect("examples/studies") {
        let p = e.expect("an entry").path();
        if p.extension().is_some_and(|x| x == "toml") {
            let (spec, base) =
                pvfc_sim::study::spec::StudySpec::from_file(&p).expect("a study file");
            let runs = spec.runs(&base).expect("valid runs");
            assert!(runs.len() >= 32, "{}: {} runs", p.display(), runs.len());
            seen += 1;
        }
    }
    assert_eq!(seen, 4);
}
