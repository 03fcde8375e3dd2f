//! PNG figures laid out like the paper's Figs. 1 and 6–10 (plotters, bundled DejaVu font).

use crate::canvas::{figure, panel, Series, Style};
use crate::report::window;
use crate::runs::Runs;
use pvfc_sim::contact::{ObstacleSpec, PlanarArm, ShapeSpec};
use pvfc_sim::error::{Result, SimError};
use pvfc_sim::scenario::preset_id::{Fig1Contour, PresetId};
use pvfc_sim::scenario::{Mode, RobotSpec};
use pvfc_sim::trace::metrics::last_pass;
use pvfc_sim::trace::{Trace, TIMED_SUFFIX};
use std::path::{Path, PathBuf};

/// A one-panel figure of paths in joint space (q1, q2).
fn joint_space_figure(path: &Path, title: &str, series: &[Series]) -> Result<()> {
    figure(path, 1, |_, a| {
        panel(a, path, title, "q1 [rad]", "q2 [rad]", series, false)
    })
}

fn desired(runs: &Runs, id: PresetId) -> Result<Series> {
    let (s, _) = runs.run(id)?;
    let c = s.contour()?;
    let period = s.contour.period();
    Ok(Series {
        label: "desired contour".into(),
        points: (0..=600)
            .map(|k| {
                let x = c.coordinates(period * k as f64 / 600.0)[0];
                (x[0], x[1])
            })
            .collect(),
        style: Style::Reference,
    })
}

fn path_of(t: &pvfc_sim::trace::Trace, range: std::ops::Range<usize>) -> Vec<(f64, f64)> {
    t.q.rows(range).map(|q| (q[0], q[1])).collect()
}

/// Figs. 8–10: contour traced, U against τ and τ̇ against τ over the last complete pass.
fn pass_figure(runs: &Runs, path: &Path, title: &str, ids: &[(PresetId, String)]) -> Result<()> {
    let first = ids
        .first()
        .ok_or_else(|| SimError::Setting(format!("{title}: no runs")))?;
    let reference = desired(runs, first.0)?;
    let mut traced = vec![reference];
    let (mut u, mut tdot) = (Vec::new(), Vec::new());
    for (id, label) in ids {
        let (s, t) = runs.run(*id)?;
        let period = s.contour.period();
        let r = last_pass(t, period)
            .ok_or_else(|| SimError::Setting(format!("run `{id}` does not cover a pass")))?;
        let tau0 = (t.tau[r.start] / period).floor() * period;
        traced.push(Series {
            label: label.clone(),
            points: path_of(t, r.clone()),
            style: Style::Line,
        });
        u.push(Series {
            label: label.clone(),
            points: r
                .clone()
                .map(|i| (t.tau[i] - tau0, t.potential[i].max(1e-8)))
                .collect(),
            style: Style::Line,
        });
        tdot.push(Series {
            label: label.clone(),
            points: r.map(|i| (t.tau[i] - tau0, t.tau_dot[i])).collect(),
            style: Style::Line,
        });
    }
    figure(path, 3, |i, a| match i {
        0 => panel(
            a,
            path,
            &format!("{title}: contour traced (one pass)"),
            "q1 [rad]",
            "q2 [rad]",
            &traced,
            false,
        ),
        1 => panel(
            a,
            path,
            "potential U(E) during one pass",
            "τ",
            "U(E)",
            &u,
            true,
        ),
        _ => panel(
            a,
            path,
            "rate of trajectory progression during one pass",
            "τ",
            "dτ/dt",
            &tdot,
            false,
        ),
    })
}

/// Writes every figure of a reproduction into `dir`; returns the files written.
pub fn all_figures(runs: &Runs, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let get = |id: PresetId| runs.trace(id);

    let p = dir.join("fig6_unforced.png");
    let f6 = get(PresetId::Fig6)?;
    let traced = vec![
        desired(runs, PresetId::Fig6)?,
        Series {
            label: "traced".into(),
            points: path_of(f6, 0..f6.len()),
            style: Style::Line,
        },
    ];
    figure(&p, 3, |i, a| match i {
        0 => panel(
            a,
            &p,
            "Fig. 6: unforced response, contour traced",
            "q1 [rad]",
            "q2 [rad]",
            &traced,
            false,
        ),
        1 => panel(
            a,
            &p,
            "potential U(E(t))",
            "t [s]",
            "U(E)",
            &[Series {
                label: "U".into(),
                points: f6
                    .t
                    .iter()
                    .zip(&f6.potential)
                    .map(|(t, u)| (*t, u.max(1e-8)))
                    .collect(),
                style: Style::Line,
            }],
            true,
        ),
        _ => panel(
            a,
            &p,
            "kinetic energy κ_a",
            "t [s]",
            "κ_a [J]",
            &[Series {
                label: "κ_a".into(),
                points: f6
                    .t
                    .iter()
                    .cloned()
                    .zip(f6.energy.iter().cloned())
                    .collect(),
                style: Style::Line,
            }],
            false,
        ),
    })?;
    files.push(p);

    let p = dir.join("fig7_self_pacing.png");
    let mut traced = vec![desired(runs, PresetId::Fig7 { pacing: 0 })?];
    for (pacing, l) in [(0, "R = 0"), (100, "R = 100")] {
        let t = get(PresetId::Fig7 { pacing })?;
        let end = t.t.iter().position(|&x| x >= 4.0).unwrap_or(t.len());
        traced.push(Series {
            label: l.into(),
            points: path_of(t, 0..end),
            style: Style::Line,
        });
    }
    joint_space_figure(&p, "Fig. 7: approach from (0, 0), first 4 s", &traced)?;
    files.push(p);

    // Figs. 8–10: file, title, the runs and their labels.
    let labelled = |symbol: &str, ids: &[(u32, PresetId)]| -> Vec<(PresetId, String)> {
        ids.iter()
            .map(|(v, id)| (*id, format!("{symbol} = {v}")))
            .collect()
    };
    let level_title = format!(
        "Fig. 10 at the energy levels (c = {}, no compensation)",
        pvfc_sim::scenario::presets::FIG10_LEVEL_GAIN
    );
    let pass_figures = [
        (
            "fig8_pacing_compensated.png",
            "Fig. 8 (friction compensation)",
            labelled(
                "R",
                &[0, 100, 200].map(|pacing| (pacing, PresetId::Fig8 { pacing })),
            ),
        ),
        (
            "fig9_pacing_uncompensated.png",
            "Fig. 9 (no compensation)",
            labelled(
                "R",
                &[0, 50, 100, 200].map(|pacing| (pacing, PresetId::Fig9 { pacing })),
            ),
        ),
        (
            "fig10_nominal_speed.png",
            "Fig. 10 (nominal speed, no compensation)",
            labelled(
                "r",
                &[1, 2, 3].map(|nominal_speed| (nominal_speed, PresetId::Fig10 { nominal_speed })),
            ),
        ),
        (
            "fig10_level.png",
            &level_title,
            labelled(
                "r",
                &[1, 2, 3]
                    .map(|nominal_speed| (nominal_speed, PresetId::Fig10Level { nominal_speed })),
            ),
        ),
    ];
    for (file, title, ids) in pass_figures {
        let p = dir.join(file);
        pass_figure(runs, &p, title, &ids)?;
        files.push(p);
    }

    let p = dir.join("fig1_pvfc_vs_timed.png");
    let (s1, pv) = runs.run(PresetId::Fig1)?;
    let tm = runs.timed(PresetId::Fig1)?;
    let last =
        |t: &pvfc_sim::trace::Trace| path_of(t, window(t, s1.duration - 12.0, f64::INFINITY));
    let traced = vec![
        desired(runs, PresetId::Fig1)?,
        Series {
            label: "PVFC".into(),
            points: last(pv),
            style: Style::Line,
        },
        Series {
            label: "timed trajectory (computed torque + PD)".into(),
            points: last(tm),
            style: Style::Line,
        },
    ];
    joint_space_figure(
        &p,
        "Fig. 1: PVFC versus a timed tracker, same friction and mean speed (last 12 s)",
        &traced,
    )?;
    files.push(p);

    // Fig. 1 as the paper draws it: on drives that saturate, the circle each controller
    // traces over its last 6 s (PVFC at the pace its drives allow, the trackers at r = 1.5).
    let id = PresetId::Fig1Saturated {
        contour: Fig1Contour::Circle,
        speed: 150,
    };
    if let Ok((s, pv)) = runs.run(id) {
        let p = dir.join("fig1_radial_reduction.png");
        let last =
            |t: &pvfc_sim::trace::Trace| path_of(t, window(t, s.duration - 6.0, f64::INFINITY));
        let traced = vec![
            desired(runs, id)?,
            Series {
                label: "PVFC (drive-limited pace)".into(),
                points: last(pv),
                style: Style::Line,
            },
            Series {
                label: "timed tracker (computed torque + PD)".into(),
                points: last(runs.timed(id)?),
                style: Style::Line,
            },
            Series {
                label: "speed-scaling tracker".into(),
                points: last(&runs.named(&id.scaled_name())?.1),
                style: Style::Line,
            },
        ];
        joint_space_figure(
            &p,
            "Fig. 1 on drives limited to 15 / 5 N·m: a circle demanded at r = 1.5 (last 6 s)",
            &traced,
        )?;
        files.push(p);
    }

    let p = dir.join("energy_sampled_vs_continuous.png");
    let series: Vec<Series> = [
        (Mode::Continuous, "continuous loop (RK4, 1 kHz)"),
        (Mode::Sampled, "sampled loop (1 kHz ZOH, plant 10 kHz)"),
    ]
    .iter()
    .map(|(mode, l)| {
        let t = get(PresetId::Energy(*mode))?;
        let e0 = t.energy[0];
        Ok(Series {
            label: (*l).into(),
            points: t
                .t
                .iter()
                .zip(&t.energy)
                .map(|(x, e)| (*x, (e - e0) / e0))
                .collect(),
            style: Style::Line,
        })
    })
    .collect::<Result<_>>()?;
    figure(&p, 1, |_, a| {
        panel(
            a,
            &p,
            "Frictionless: relative change of κ_a",
            "t [s]",
            "(κ_a − κ_a(0))/κ_a(0)",
            &series,
            false,
        )
    })?;
    files.push(p);
    files.push(crate::plot_digital::digital_figure(runs, dir)?);
    files.push(crate::speed_sweep::figure_saturated(runs, dir)?);
    files.push(crate::robustness::figure_robustness(runs, dir)?);
    for (name, (s, t)) in &runs.runs {
        if s.contact.is_some() && t.contact.is_some() && !t.is_timed() {
            let p = dir.join(format!("{name}.png"));
            contact_figure(runs, name, &p)?;
            files.push(p);
        }
    }
    // The UR5's runs on saturating drives are drawn together in `fig1_saturated.png` (each
    // keeps its log): twelve figures of their own would be 8 MB of the output's 100.
    let swept = |name: &str| {
        matches!(
            PresetId::from_name(name),
            Some(PresetId::Ur5Saturated { .. })
        )
    };
    files.extend(chain_figures_where(runs, dir, |name| !swept(name))?);
    files.extend(body_figures(runs, dir)?);
    Ok(files)
}

/// Draws the figure of every rigid body's run into `dir/NAME.png`; returns the files written.
pub fn body_figures(runs: &Runs, dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for (name, (s, t)) in &runs.runs {
        if let RobotSpec::RigidBody(_) = s.plant.robot {
            let p = dir.join(format!("{name}.png"));
            crate::body_plot::body_figure(s, t, &p)?;
            files.push(p);
        }
    }
    Ok(files)
}

/// Draws the figure of every URDF arm's run into `dir/NAME.png`, beside its timed baseline
/// when there is one; returns the files written.
pub fn chain_figures(runs: &Runs, dir: &Path) -> Result<Vec<PathBuf>> {
    chain_figures_where(runs, dir, |_| true)
}

/// [`chain_figures`] of the runs whose name passes `drawn`.
fn chain_figures_where(
    runs: &Runs,
    dir: &Path,
    drawn: impl Fn(&str) -> bool,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for (name, (s, t)) in &runs.runs {
        let RobotSpec::SerialChain(_) = s.plant.robot else {
            continue;
        };
        if !t.is_timed() && drawn(name) {
            let p = dir.join(format!("{name}.png"));
            let baseline = runs
                .runs
                .get(&format!("{name}{TIMED_SUFFIX}"))
                .map(|(_, b)| b);
            let system = runs.chain_system(s)?;
            crate::chain_plot::chain_figure(s, &system, t, baseline, &p)?;
            files.push(p);
        }
    }
    Ok(files)
}

/// The outline of an obstacle at time `t`, as a closed polyline.
fn outline(o: &ObstacleSpec, t: f64) -> Vec<(f64, f64)> {
    let (d, _) = o.motion_at(t);
    let (c, s) = (o.angle.cos(), o.angle.sin());
    let place = |x: f64, y: f64| {
        (
            o.position[0] + d.x + c * x - s * y,
            o.position[1] + d.y + s * x + c * y,
        )
    };
    let arc = |cx: f64, cy: f64, r: f64, from: f64, to: f64| {
        (0..=24).map(move |k| {
            let a = from + (to - from) * k as f64 / 24.0;
            (cx + r * a.cos(), cy + r * a.sin())
        })
    };
    let pts: Vec<(f64, f64)> = match o.shape {
        ShapeSpec::Box {
            half_extents: [hx, hy],
        } => vec![(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)],
        ShapeSpec::Ball { radius } => arc(0.0, 0.0, radius, 0.0, std::f64::consts::TAU).collect(),
        ShapeSpec::Capsule { a, b, radius } => {
            let th = (b[1] - a[1]).atan2(b[0] - a[0]);
            let half = std::f64::consts::FRAC_PI_2;
            let mut v: Vec<(f64, f64)> = arc(b[0], b[1], radius, th - half, th + half)
                .chain(arc(a[0], a[1], radius, th + half, th + 3.0 * half))
                .collect();
            v.push(v[0]);
            v
        }
    };
    pts.into_iter().map(|(x, y)| place(x, y)).collect()
}

/// A contact scenario's figure: the tool's path against the obstacles, the contact force,
/// the energy and the work of the environment, and the energy audit's residual; PVFC and
/// (if it ran) the timed baseline.
pub fn contact_figure(runs: &Runs, name: &str, p: &Path) -> Result<()> {
    let (s, t) = runs
        .runs
        .get(name)
        .ok_or_else(|| SimError::Setting(format!("run `{name}` is missing")))?;
    let timed = runs
        .runs
        .get(&format!("{name}{TIMED_SUFFIX}"))
        .map(|(_, t)| t);
    let spec = s
        .contact
        .as_ref()
        .ok_or_else(|| SimError::Setting(format!("run `{name}` has no contact")))?;
    let kin = PlanarArm::of(&s.scara()?)?;
    let contour = s.contour()?;
    let period = s.contour.period();
    let mut paths = vec![Series {
        label: "desired contour (tool)".into(),
        points: (0..=600)
            .map(|k| {
                let x = contour.coordinates(period * k as f64 / 600.0)[0];
                let tip = kin.tip(&pvfc_core::lie::Torus::new(x));
                (tip.x, tip.y)
            })
            .collect(),
        style: Style::Reference,
    }];
    let end = t.t.last().copied().unwrap_or(0.0);
    for (k, o) in spec.obstacles.iter().enumerate() {
        paths.push(Series {
            label: if k == 0 {
                "obstacles".into()
            } else {
                String::new()
            },
            points: outline(o, 0.0),
            style: Style::Reference,
        });
        if !o.motion.is_empty() {
            paths.push(Series {
                label: String::new(),
                points: outline(o, end),
                style: Style::Reference,
            });
        }
    }
    let runs_drawn: Vec<(&str, &Trace)> = std::iter::once(("PVFC", t))
        .chain(timed.map(|t| ("timed tracker", t)))
        .collect();
    let (mut force, mut energy, mut audit) = (Vec::new(), Vec::new(), Vec::new());
    for (label, tr) in &runs_drawn {
        let Some(c) = tr.contact.as_ref() else {
            continue;
        };
        paths.push(Series {
            label: (*label).into(),
            points: c.tool.iter().map(|x| (x[0], x[1])).collect(),
            style: Style::Line,
        });
        force.push(Series {
            label: (*label).into(),
            points: tr
                .t
                .iter()
                .zip(&c.normal_force)
                .map(|(a, b)| (*a, *b))
                .collect(),
            style: Style::Line,
        });
        let e0 = tr.energy[0];
        let scale = if e0 > 0.0 {
            e0
        } else {
            tr.energy.iter().cloned().fold(f64::MIN_POSITIVE, f64::max)
        };
        audit.push(Series {
            label: format!("{label} (of {scale:.3} J)"),
            points: tr
                .t
                .iter()
                .zip(c.audit_residual(&tr.energy))
                .map(|(a, r)| (*a, (r.abs() / scale).max(1e-16)))
                .collect(),
            style: Style::Line,
        });
        energy.push(Series {
            label: format!("energy pumped into the contact ({label})"),
            points: tr
                .t
                .iter()
                .zip(&c.work_contact)
                .map(|(a, w)| (*a, -w))
                .collect(),
            style: Style::Line,
        });
    }
    // PVFC's own energy after the per-run curves, so that every panel colours PVFC and the
    // baseline alike.
    if let Some(c) = t.contact.as_ref() {
        let e0 = t.energy[0];
        energy.push(Series {
            label: "κ_a (PVFC)".into(),
            points: t.t.iter().zip(&t.energy).map(|(a, b)| (*a, *b)).collect(),
            style: Style::Line,
        });
        energy.push(Series {
            label: "κ_a(0) + W_add-ons: what PVFC may give".into(),
            points: t
                .t
                .iter()
                .zip(&c.work_controller)
                .map(|(a, w)| (*a, e0 + w))
                .collect(),
            style: Style::Reference,
        });
    }
    figure(p, 4, |i, a| match i {
        0 => panel(
            a,
            p,
            &format!("{}: tool path", s.name),
            "x [m]",
            "y [m]",
            &paths,
            false,
        ),
        1 => panel(a, p, "contact force", "t [s]", "Σ f_n [N]", &force, false),
        2 => panel(
            a,
            p,
            "energy: PVFC never gives more than it has",
            "t [s]",
            "[J]",
            &energy,
            false,
        ),
        _ => panel(
            a,
            p,
            "energy audit residual |κ(t) − κ(0) − ΣW| / scale",
            "t [s]",
            "relative",
            &audit,
            true,
        ),
    })
}
