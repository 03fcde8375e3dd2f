//! The pace learned lap over lap (`[controller.passive.pace_learning]`) on the fair study's
//! Lissajous curve (`examples/studies/bases/scara_lissajous_saturated.toml`, drives of
//! 15 / 5 N·m, friction compensated at 2 / 3 N·m) on its heaviest held-out plant (second link
//! +14 %, Coulomb friction 3.71 N·m on the second joint): the throttle's single scale lets the
//! drives saturate at one corner once a lap and `τ̇` all but stops there; the learned pace
//! slows that stretch only, and PVFC stays on the contour without stopping, at the lap.

use pvfc_sim::run::simulate;
use pvfc_sim::scenario::{Scenario, SpeedScaling};
use pvfc_sim::study::metrics::{metric, RunView};
use std::path::Path;

fn heavy() -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies/bases");
    let mut s = Scenario::from_file(&dir.join("scara_lissajous_saturated.toml")).expect("the base");
    s.plant.mass_scale = Some(vec![1.01, 1.14]);
    s.plant.friction.coulomb = vec![2.2, 3.71];
    s
}

/// The study's metrics of a run: mean and largest distance to the contour over the last
/// pass (rad), its lap ÷ the least lap, and its least `τ̇` ÷ the mean.
fn measure(s: &Scenario) -> [f64; 4] {
    s.validate().expect("valid");
    let t = simulate(s, &mut |_| {}).expect("the run");
    let view = RunView::new(s, &t, None);
    let names = [
        "contour_distance_mean",
        "contour_distance_max",
        "lap_ratio",
        "tau_dot_least_ratio",
    ];
    names.map(|n| metric(n).expect(n).of(&view).expect(n))
}

#[test]
fn the_learned_pace_slows_one_corner_where_the_throttle_stops_and_goes() {
    let learned = heavy();
    assert!(
        learned
            .controller
            .passive
            .as_ref()
            .unwrap()
            .pace_learning
            .is_some(),
        "the base learns its pace"
    );
    let mut throttled = learned.clone();
    let p = throttled.controller.passive.as_mut().unwrap();
    p.pace_learning = None;
    p.pace_throttle = Some(SpeedScaling {
        threshold: 0.97,
        time_constant: 2.0,
        floor: 0.05,
    });
    let [mean_l, max_l, lap_l, least_l] = measure(&learned);
    let [mean_t, max_t, lap_t, least_t] = measure(&throttled);
    let report = format!(
        "learned: {mean_l:.2e} / {max_l:.2e} rad, lap {lap_l:.3}, least τ̇ {least_l:.2}; \
         throttled: {mean_t:.2e} / {max_t:.2e} rad, lap {lap_t:.3}, least τ̇ {least_t:.2}"
    );
    // The throttle's stop-and-go, as the fair study measures it.
    assert!(least_t < 0.15 && max_t > 0.05, "{report}");
    // Learned: never near a stop, ten times nearer at worst, within 1.25× the least lap.
    assert!(least_l > 0.4, "{report}");
    assert!(mean_l < 0.2 * mean_t && max_l < 0.1 * max_t, "{report}");
    assert!(lap_l < 1.25, "{report}");
}

#[test]
fn a_learned_pace_is_checked_before_anything_runs() {
    let mut s = heavy();
    s.controller
        .passive
        .as_mut()
        .unwrap()
        .pace_learning
        .as_mut()
        .unwrap()
        .fall = 1.0;
    let e = s.validate().unwrap_err().to_string();
    assert!(e.contains("controller.passive.pace_learning.fall"), "{e}");
    for bad in [-0.1, 1.5, f64::NAN] {
        let mut s = heavy();
        let l = s.controller.passive.as_mut().unwrap();
        l.pace_learning.as_mut().unwrap().miss = bad;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("controller.passive.pace_learning.miss"), "{e}");
    }
    // Learned beside the controller built alone too; without a pace it is refused by name.
    let mut s = heavy();
    let l = s.controller.passive.as_mut().unwrap();
    l.pace_learning.as_mut().unwrap().miss = 0.5;
    s.validate().expect("valid for a run");
    let alone = s.passive_controller().expect("built").expect("passive");
    assert!(alone.miss_learner().is_some());
    let mut options = s
        .controller
        .passive
        .clone()
        .unwrap()
        .options(&[true; 2])
        .unwrap();
    options.pace_learning.as_mut().unwrap().miss = 0.0;
    let plain = s.passive_controller_with(&options).expect("built");
    assert!(plain.miss_learner().is_none());
    let mut s = heavy();
    s.controller.passive.as_mut().unwrap().torque_limit.clear();
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.contains("pace_learning") && e.contains("torque_limit"),
        "{e}"
    );
    let mut s = heavy();
    s.controller.pace = None;
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.contains("pace_learning") && e.contains("[controller.pace]"),
        "{e}"
    );
}

/// `pace_learning.miss` is learned beside an arm's passive controller built alone from the
/// scenario (Python's and C's path) as beside a run's, on the pace of the settings it was
/// built from; without a pace it is refused by name, and without the miss none is learned.
#[test]
fn an_arm_controller_built_alone_learns_the_missed_torque() {
    use pvfc_sim::scenario::ArmSystem;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies/bases");
    let mut s = Scenario::from_file(&dir.join("ur5_circle_saturated.toml")).expect("the base");
    let spec = s.controller.passive.as_mut().unwrap();
    spec.pace_learning.as_mut().unwrap().miss = 0.5;
    s.validate().expect("valid for a run");
    let system = ArmSystem::build(&s).expect("the system");
    let spec = s.controller.passive.clone().unwrap();
    let mut options = spec.options(&[true; 6]).expect("the options");
    let alone = system.controller.passive(&options, &system.settings);
    assert!(alone.expect("built with it").learns_miss());
    let mut unpaced = system.settings.clone();
    unpaced.pace = None;
    let e = system.controller.passive(&options, &unpaced).map(|_| ());
    let e = e.unwrap_err().to_string();
    assert!(
        e.contains("pace_learning.miss") && e.contains("pace"),
        "{e}"
    );
    options.pace_learning.as_mut().unwrap().miss = 0.0;
    let plain = system.controller.passive(&options, &system.settings);
    assert!(!plain.expect("built without it").learns_miss());
}
