//! Typed names of the built-in scenarios ([`crate::scenario::presets`]): the presets take their names
//! from here, and the report and the figures find their runs by these ids, so that a run's
//! name is spelled in one place.

use crate::scenario::Mode;
use std::fmt;

/// The planar contact scenarios (the wall, the deburring, the push, the obstacle).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ContactCase {
    /// `contact_wall`: the arm meets a wall on its contour.
    Wall,
    /// `contact_wall_sampled`: the wall with `Controller::step` at 1 kHz.
    WallSampled,
    /// `contact_deburr`: deburring with the force-scheduled nominal speed.
    Deburr,
    /// `contact_deburr_unscheduled`: the same without the schedule.
    DeburrUnscheduled,
    /// `contact_push`: a ball pushes the arm off its contour.
    Push,
    /// `contact_obstacle`: a block in the way.
    Obstacle,
}

/// The cases of the digital-controller comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DigitalCase {
    /// Frictionless free motion.
    Free,
    /// The wall.
    Wall,
    /// The push.
    Push,
    /// The obstacle.
    Obstacle,
}

impl DigitalCase {
    /// Every case, in the report's order.
    pub const ALL: [DigitalCase; 4] = [
        DigitalCase::Free,
        DigitalCase::Wall,
        DigitalCase::Push,
        DigitalCase::Obstacle,
    ];

    /// Its name in a run's name (`free`, `wall`, …).
    pub fn label(self) -> &'static str {
        match self {
            DigitalCase::Free => "free",
            DigitalCase::Wall => "wall",
            DigitalCase::Push => "push",
            DigitalCase::Obstacle => "obstacle",
        }
    }
}

/// Which sampled controller a digital run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Digital {
    /// `Controller::step` under a zero-order hold.
    Zoh,
    /// The passive digital controller (`pvfc_core::passive`).
    Passive,
}

impl Digital {
    /// Its name in a run's name.
    pub fn label(self) -> &'static str {
        match self {
            Digital::Zoh => "zoh",
            Digital::Passive => "passive",
        }
    }
}

/// The UR5's 3-D contact scenarios (`scenarios/ur5_*.toml`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Arm3dCase {
    /// `ur5_press`: the tool pressed 3 mm into a workpiece's compliant top along the path.
    Press,
    /// `ur5_wall`.
    Wall,
    /// `ur5_push`.
    Push,
    /// `ur5_press_continuous`: the press run in continuous time.
    PressContinuous,
}

impl Arm3dCase {
    /// The cases read from files, each beside its timed baseline, the press first.
    pub const FILES: [Arm3dCase; 3] = [Arm3dCase::Press, Arm3dCase::Wall, Arm3dCase::Push];

    /// Its short name (`press`, `wall`, `push`, `press_continuous`).
    pub fn label(self) -> &'static str {
        match self {
            Arm3dCase::Press => "press",
            Arm3dCase::Wall => "wall",
            Arm3dCase::Push => "push",
            Arm3dCase::PressContinuous => "press_continuous",
        }
    }
}

/// The UR5's tool paths at machining accuracy (`scenarios/ur5_cartesian.toml`,
/// `scenarios/ur5_deburr.toml`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ToolPathCase {
    /// `ur5_cartesian`: the rounded rectangle in free space, with joint friction.
    Free,
    /// `ur5_deburr`: the rounded rectangle 0.5 mm into a workpiece, at machining accuracy.
    Deburr,
}

impl ToolPathCase {
    /// Every case, in the report's order.
    pub const ALL: [ToolPathCase; 2] = [ToolPathCase::Free, ToolPathCase::Deburr];

    /// Its short name (`free`, `deburr`).
    pub fn label(self) -> &'static str {
        match self {
            ToolPathCase::Free => "free",
            ToolPathCase::Deburr => "deburr",
        }
    }
}

/// The SCARA's contour of Fig. 1 on saturating drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fig1Contour {
    /// A circle of 1 rad in joint space (the paper's Lissajous curve with equal periods):
    /// leaving it is a radial reduction.
    Circle,
    /// The paper's Lissajous curve (amplitudes 1 and 1.5 rad, periods 3 and 6), as in `fig1`.
    Lissajous,
}

impl Fig1Contour {
    /// Every contour, in the report's order.
    pub const ALL: [Fig1Contour; 2] = [Fig1Contour::Circle, Fig1Contour::Lissajous];
}

/// The UR5's tool path of Fig. 1 on saturating drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SaturatedPath {
    /// `ur5_cartesian`'s rounded rectangle (87 mm/s at `r = 1`).
    Rectangle,
    /// `ur5_circle`'s circle of 10 cm radius (52 mm/s at `r = 1`): leaving it is a radial
    /// reduction, as in the paper's Fig. 1.
    Circle,
}

impl SaturatedPath {
    /// Every path, in the report's order.
    pub const ALL: [SaturatedPath; 2] = [SaturatedPath::Rectangle, SaturatedPath::Circle];

    /// The demanded speeds `r` of its sweep (times the path's nominal speed).
    pub fn speeds(self) -> [u32; 6] {
        match self {
            SaturatedPath::Rectangle => [1, 2, 4, 6, 8, 10],
            SaturatedPath::Circle => [4, 8, 12, 16, 20, 24],
        }
    }

    /// The free run it starts from (a scenario of `scenarios/`): the rectangle's is the tool
    /// path [`ToolPathCase::Free`]'s.
    pub fn base(self) -> String {
        match self {
            SaturatedPath::Rectangle => PresetId::ToolPath(ToolPathCase::Free).name(),
            SaturatedPath::Circle => "ur5_circle".into(),
        }
    }
}

/// A built-in scenario. [`name`](Self::name) is the scenario's (and its run's, log's and
/// figure's) name; its timed baseline's run is `NAME-timed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum PresetId {
    /// Fig. 6: the unforced response.
    Fig6,
    /// Fig. 7: the approach from `(0, 0)` with self-pacing `R`.
    Fig7 {
        /// `R` of eq. (21).
        pacing: u32,
    },
    /// Fig. 8: self-pacing `R` with friction compensation.
    Fig8 {
        /// `R` of eq. (21).
        pacing: u32,
    },
    /// Fig. 9: self-pacing `R` without friction compensation.
    Fig9 {
        /// `R` of eq. (21).
        pacing: u32,
    },
    /// Fig. 10: nominal speed `r`.
    Fig10 {
        /// `r` of eq. (36).
        nominal_speed: u32,
    },
    /// Fig. 10 at its energy level: nominal speed `r` with the gain
    /// [`FIG10_LEVEL_GAIN`](crate::scenario::presets::FIG10_LEVEL_GAIN), so that `β` reaches `r`.
    Fig10Level {
        /// `r` of eq. (36).
        nominal_speed: u32,
    },
    /// Figs. 8 and 9 on a plant whose friction has a Stribeck peak
    /// ([`presets::stribeck`](crate::scenario::presets::stribeck)).
    Stribeck {
        /// With the friction compensation (35) (Fig. 8) or without (Fig. 9).
        compensated: bool,
        /// `R` of eq. (21).
        pacing: u32,
    },
    /// Fig. 1: PVFC beside a timed-trajectory tracker.
    Fig1,
    /// The frictionless energy check, continuous or sampled.
    Energy(Mode),
    /// A planar contact scenario.
    Contact(ContactCase),
    /// A digital-controller run: a case at a rate (Hz) with a controller.
    Digital {
        /// The case.
        case: DigitalCase,
        /// The controller's rate (Hz).
        rate: u32,
        /// The controller.
        controller: Digital,
    },
    /// The wall at 1 kHz on a realistic drive (limits, encoders, positions only).
    DigitalDrive,
    /// Fig. 8 (`R = 100`) with the passive controller at 1 kHz.
    Fig8Passive,
    /// Fig. 8 (`R = 100`) with the continuous-time controller.
    Fig8Continuous,
    /// Fig. 1 on drives that saturate: PVFC asked for the nominal speed `r` and the timed
    /// tracker running at `τ̇ = r`, on a circle or the paper's Lissajous curve.
    Fig1Saturated {
        /// The contour.
        contour: Fig1Contour,
        /// The demanded speed `r`, in hundredths.
        speed: u32,
    },
    /// Section II's robustness: the frictionless Pelican under a disturbance torque
    /// ([`presets::robustness`](crate::scenario::presets::robustness)).
    Robustness {
        /// `γĒ` (s⁻¹): the coupling's gain `γ` times the energy `Ē`.
        gamma_energy: u32,
    },
    /// Section IV-B's satellite: a rigid body's attitude on SO(3)
    /// ([`presets::satellite`](crate::scenario::presets::satellite)).
    Satellite,
    /// A UR5 3-D contact scenario.
    Arm3d(Arm3dCase),
    /// A UR5 tool path at machining accuracy.
    ToolPath(ToolPathCase),
    /// The same tool path followed with the task-space field (`NAME_task`).
    ToolPathTask(ToolPathCase),
    /// Fig. 1 on the UR5's saturating drives: a tool path at `r` times its speed.
    Ur5Saturated {
        /// The path.
        path: SaturatedPath,
        /// The demanded speed `r` (times the path's nominal speed).
        speed: u32,
    },
}

/// The demanded speeds of Fig. 1 on saturating drives (`r`, in hundredths).
pub const FIG1_SATURATED_SPEEDS: [u32; 6] = [50, 100, 150, 200, 300, 400];

/// The gains `γĒ` of the robustness runs (s⁻¹).
pub const ROBUSTNESS_GAINS: [u32; 6] = [1, 2, 5, 10, 20, 40];

/// The self-pacing gains `R` of the Stribeck runs.
pub const STRIBECK_PACINGS: [u32; 3] = [0, 100, 200];

/// The rates of the digital comparison (Hz).
pub const DIGITAL_RATES: [u32; 3] = [1000, 250, 100];

impl PresetId {
    /// The scenario's name.
    pub fn name(&self) -> String {
        match *self {
            PresetId::Fig6 => "fig6_unforced".into(),
            PresetId::Fig7 { pacing } => format!("fig7_R{pacing}"),
            PresetId::Fig8 { pacing } => format!("fig8_R{pacing}"),
            PresetId::Fig9 { pacing } => format!("fig9_R{pacing}"),
            PresetId::Fig10 { nominal_speed } => format!("fig10_r{nominal_speed}"),
            PresetId::Fig10Level { nominal_speed } => format!("fig10_level_r{nominal_speed}"),
            PresetId::Stribeck {
                compensated,
                pacing,
            } => format!("fig{}_stribeck_R{pacing}", if compensated { 8 } else { 9 }),
            PresetId::Fig1 => "fig1_pvfc_vs_timed".into(),
            PresetId::Energy(Mode::Continuous) => "energy_continuous".into(),
            PresetId::Energy(Mode::Sampled) => "energy_sampled".into(),
            PresetId::Contact(c) => match c {
                ContactCase::Wall => "contact_wall",
                ContactCase::WallSampled => "contact_wall_sampled",
                ContactCase::Deburr => "contact_deburr",
                ContactCase::DeburrUnscheduled => "contact_deburr_unscheduled",
                ContactCase::Push => "contact_push",
                ContactCase::Obstacle => "contact_obstacle",
            }
            .into(),
            PresetId::Digital {
                case,
                rate,
                controller,
            } => format!("digital_{}_{rate}hz_{}", case.label(), controller.label()),
            PresetId::DigitalDrive => "digital_wall_1000hz_drive".into(),
            PresetId::Fig8Passive => "fig8_R100_passive".into(),
            PresetId::Fig8Continuous => "fig8_R100_continuous".into(),
            PresetId::Fig1Saturated { contour, speed } => format!(
                "fig1_saturated_{}r{}",
                match contour {
                    Fig1Contour::Circle => "",
                    Fig1Contour::Lissajous => "lissajous_",
                },
                f64::from(speed) / 100.0
            ),
            PresetId::Robustness { gamma_energy } => format!("robustness_g{gamma_energy}"),
            PresetId::Satellite => "satellite".into(),
            PresetId::Arm3d(a) => format!("ur5_{}", a.label()),
            PresetId::ToolPath(ToolPathCase::Free) => "ur5_cartesian".into(),
            PresetId::ToolPath(ToolPathCase::Deburr) => "ur5_deburr".into(),
            PresetId::ToolPathTask(case) => format!("{}_task", PresetId::ToolPath(case).name()),
            PresetId::Ur5Saturated {
                path: SaturatedPath::Rectangle,
                speed,
            } => format!("ur5_saturated_r{speed}"),
            PresetId::Ur5Saturated {
                path: SaturatedPath::Circle,
                speed,
            } => format!("ur5_circle_saturated_r{speed}"),
        }
    }

    /// The name of its timed baseline's run (`NAME-timed`).
    pub fn timed_name(&self) -> String {
        format!("{}{}", self.name(), super::TIMED_SUFFIX)
    }

    /// The name of the preset's speed-scaling tracker's run (`[baseline.speed_scaling]`).
    pub fn scaled_name(&self) -> String {
        format!("{}{}", self.name(), super::SCALED_SUFFIX)
    }

    /// Every preset, in the order `pvfc reproduce` runs them (the built-in ones of
    /// [`presets::all`](crate::scenario::presets::all), then the UR5's of
    /// [`presets::arms_3d`](crate::scenario::presets::arms_3d) and
    /// [`presets::tool_paths`](crate::scenario::presets::tool_paths)).
    pub fn all() -> Vec<PresetId> {
        let mut v = vec![
            PresetId::Fig6,
            PresetId::Fig7 { pacing: 0 },
            PresetId::Fig7 { pacing: 100 },
        ];
        v.extend([0, 100, 200].map(|pacing| PresetId::Fig8 { pacing }));
        v.extend([0, 50, 100, 200].map(|pacing| PresetId::Fig9 { pacing }));
        v.extend([1, 2, 3].map(|nominal_speed| PresetId::Fig10 { nominal_speed }));
        v.extend([1, 2, 3].map(|nominal_speed| PresetId::Fig10Level { nominal_speed }));
        for compensated in [true, false] {
            v.extend(STRIBECK_PACINGS.map(|pacing| PresetId::Stribeck {
                compensated,
                pacing,
            }));
        }
        v.push(PresetId::Fig1);
        v.push(PresetId::Energy(Mode::Continuous));
        v.push(PresetId::Energy(Mode::Sampled));
        v.extend(
            [
                ContactCase::Wall,
                ContactCase::WallSampled,
                ContactCase::Deburr,
                ContactCase::DeburrUnscheduled,
                ContactCase::Push,
                ContactCase::Obstacle,
            ]
            .map(PresetId::Contact),
        );
        for case in DigitalCase::ALL {
            for rate in DIGITAL_RATES {
                for controller in [Digital::Passive, Digital::Zoh] {
                    v.push(PresetId::Digital {
                        case,
                        rate,
                        controller,
                    });
                }
            }
        }
        v.extend([
            PresetId::DigitalDrive,
            PresetId::Fig8Passive,
            PresetId::Fig8Continuous,
        ]);
        for contour in Fig1Contour::ALL {
            v.extend(FIG1_SATURATED_SPEEDS.map(|speed| PresetId::Fig1Saturated { contour, speed }));
        }
        v.extend(ROBUSTNESS_GAINS.map(|gamma_energy| PresetId::Robustness { gamma_energy }));
        v.push(PresetId::Satellite);
        v.extend(Arm3dCase::FILES.map(PresetId::Arm3d));
        v.push(PresetId::Arm3d(Arm3dCase::PressContinuous));
        v.extend(ToolPathCase::ALL.map(PresetId::ToolPath));
        v.extend(ToolPathCase::ALL.map(PresetId::ToolPathTask));
        for path in SaturatedPath::ALL {
            v.extend(
                path.speeds()
                    .map(|speed| PresetId::Ur5Saturated { path, speed }),
            );
        }
        v
    }

    /// The preset of this name, if any.
    pub fn from_name(name: &str) -> Option<PresetId> {
        PresetId::all().into_iter().find(|id| id.name() == name)
    }
}

impl fmt::Display for PresetId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}
