#!/usr/bin/env python3
"""The fair study of PVFC and the trackers users would pick, at the drives' limit (issue 51).

    python3 scripts/fair_study.py [--pvfc target/release/pvfc] [--out results/fair] [--check]

For each setting (the UR5 rectangle at 8 times its speed and the UR5 circle at 20 times its
speed, on saturating drives with Stribeck friction: examples/studies/bases/):

1. Tunes each baseline on the tuning set (four model errors): the timed tracker's PD gains
   (examples/studies/tune_timed_ur5.toml, on the setting's base) and the speed-scaling
   tracker's threshold and time constant (tune_speed_scaling_ur5.toml). A setting that fails on any tuning condition is
   out. The timed tracker keeps the gains with the least mean distance along the surface; the
   speed-scaling tracker is kept twice: tuned for accuracy (the least mean distance) and tuned
   for pace (the least mean lap ÷ least lap, ties broken by distance).
2. Runs PVFC and each tuned tracker on the held-out conditions (heldout_ur5.toml: 32 plants
   with other link masses and friction levels), each through `pvfc sweep --controller` with
   the tuned settings as the study's `set`.
3. Prints, per controller, over the held-out runs: mean and largest distance along the
   surface (mm), the mean and largest lap ÷ the least lap any controller can make on that
   plant at that demand, the mean share of samples at a torque limit, and failures; then
   issue 51's verdicts on this setting. With --check, exits 1 if a verdict fails.
"""

import argparse
import csv
import statistics
import subprocess
import sys
from collections import defaultdict
from pathlib import Path
from typing import Dict, List, Optional, Tuple

REPO = Path(__file__).resolve().parents[1]
STUDIES = REPO / "examples" / "studies"
SETTINGS = {
    "ur5_rectangle": "ur5_rectangle_saturated.toml",
    "ur5_circle": "ur5_circle_saturated.toml",
}


def sweep(pvfc: str, study: Path, out: Path) -> None:
    cmd = [pvfc, "sweep", str(study), "--out", str(out), "--no-figures"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def rows(path: Path) -> List[Dict[str, str]]:
    with path.open(encoding="utf-8") as f:
        return list(csv.DictReader(f))


def value(row: Dict[str, str], key: str) -> Optional[float]:
    text = row.get(key, "")
    return float(text) if text not in ("", None) and not row.get("error") else None


def settings(table: List[Dict[str, str]], keys: Tuple[str, ...]) -> Dict[Tuple[float, ...], dict]:
    """Per setting of `keys`: mean distance, mean lap ratio, and whether every tuning
    condition ran."""
    groups: Dict[Tuple[float, ...], List[Dict[str, str]]] = defaultdict(list)
    for r in table:
        groups[tuple(float(r[k]) for k in keys)].append(r)
    out = {}
    for k, group in groups.items():
        errors = [e for e in (value(r, "tool_surface_mean") for r in group) if e is not None]
        laps = [x for x in (value(r, "lap_ratio") for r in group) if x is not None]
        ok = len(errors) == len(group) and len(laps) == len(group)
        out[k] = {
            "ok": ok,
            "error": statistics.mean(errors) if ok else float("inf"),
            "lap": statistics.mean(laps) if ok else float("inf"),
        }
    return out


def study_copy(
    out: Path,
    template: str,
    name: str,
    base: str,
    controller: Optional[str] = None,
    assignments: Optional[Dict[str, float]] = None,
) -> Path:
    """examples/studies/`template` as study `name` on the base `base` (in bases/), with
    `controller` and `assignments` set on every run if given: written into `out`."""
    text = (STUDIES / template).read_text(encoding="utf-8")
    lines = []
    for line in text.splitlines():
        if line.startswith("name = "):
            line = f'name = "{name}"'
        elif line.startswith("base = "):
            line = f'base = "{(STUDIES / "bases" / base).as_posix()}"'
        elif line.startswith("controller = ") and controller:
            continue
        lines.append(line)
        if line.startswith("metrics = "):
            if controller:
                lines.append(f'controller = "{controller}"')
            if assignments:
                pairs = ", ".join(f'"{k}" = {v!r}' for k, v in assignments.items())
                lines.append(f"set = {{ {pairs} }}")
    study = out / f"{name}.toml"
    study.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return study


def summary(table: List[Dict[str, str]]) -> dict:
    ran = [r for r in table if value(r, "tool_surface_mean") is not None]
    def col(k: str) -> List[float]:
        return [v for v in (value(r, k) for r in ran) if v is not None]
    return {
        "runs": len(table),
        "failed": len(table) - len(ran),
        "mean": statistics.mean(col("tool_surface_mean")) * 1e3 if ran else float("nan"),
        "max": max(col("tool_surface_max")) * 1e3 if ran else float("nan"),
        "lap": statistics.mean(col("lap_ratio")) if ran else float("nan"),
        "lap_max": max(col("lap_ratio")) if ran else float("nan"),
        "limit": statistics.mean(col("limit_share")) if ran else float("nan"),
    }


def setting(pvfc: str, out: Path, label: str, base: str) -> List[Tuple[str, bool]]:
    """Tunes, runs the held-out plants and prints the table of one setting; its verdicts."""
    tune_t = study_copy(out, "tune_timed_ur5.toml", f"tune_timed_{label}", base)
    tune_s = study_copy(out, "tune_speed_scaling_ur5.toml", f"tune_speed_scaling_{label}", base)
    sweep(pvfc, tune_t, out)
    sweep(pvfc, tune_s, out)
    timed = settings(rows(out / f"tune_timed_{label}.csv"), ("baseline.kp[0]", "baseline.kd[0]"))
    scaled = settings(
        rows(out / f"tune_speed_scaling_{label}.csv"),
        ("baseline.speed_scaling.threshold", "baseline.speed_scaling.time_constant"),
    )
    usable_t = {k: v for k, v in timed.items() if v["ok"]}
    usable_s = {k: v for k, v in scaled.items() if v["ok"]}
    if not usable_t or not usable_s:
        print(f"{label}: no tuning setting ran on every tuning condition")
        return [(f"{label}: a tuning setting of each tracker ran on every condition", False)]
    kp, kd = min(usable_t, key=lambda k: usable_t[k]["error"])
    accurate = min(usable_s, key=lambda k: usable_s[k]["error"])
    fast = min(usable_s, key=lambda k: (usable_s[k]["lap"], usable_s[k]["error"]))
    print(f"\n{label} ({base}): tuning set of {len(timed)} timed and {len(scaled)} speed-scaling settings, 4 conditions each")
    print(f"  timed: kp = {kp:g}, kd = {kd:g} (tuning mean {usable_t[(kp, kd)]['error'] * 1e3:.3f} mm)")
    for what, k in (("accuracy", accurate), ("pace", fast)):
        v = usable_s[k]
        print(
            f"  speed-scaling, tuned for {what}: threshold {k[0]:g}, time constant {k[1]:g} s (tuning mean {v['error'] * 1e3:.3f} mm, lap {v['lap']:.3f}× the least)"
        )
    gains = {f"baseline.kp[{i}]": kp for i in range(6)}
    gains.update({f"baseline.kd[{i}]": kd for i in range(6)})

    def scaling(k: Tuple[float, ...]) -> Dict[str, float]:
        return {"baseline.speed_scaling.threshold": k[0], "baseline.speed_scaling.time_constant": k[1]}

    runs = {
        "PVFC": ("pvfc", {}),
        "timed (tuned gains)": ("timed", gains),
        "speed-scaling (tuned for accuracy)": ("speed_scaling", scaling(accurate)),
        "speed-scaling (tuned for pace)": ("speed_scaling", scaling(fast)),
    }
    s: Dict[str, dict] = {}
    for i, (name, (controller, assignments)) in enumerate(runs.items()):
        study = study_copy(out, "heldout_ur5.toml", f"heldout_{label}_{i}", base, controller, assignments)
        sweep(pvfc, study, out)
        s[name] = summary(rows(out / f"heldout_{label}_{i}.csv"))
    print("  held-out conditions (32 plants), distance along the surface in mm:")
    print(f"    {'controller':36} {'mean':>8} {'max':>8} {'lap/least':>10} {'lap max':>8} {'at limit':>9} {'failed':>7}")
    for name, v in s.items():
        print(
            f"    {name:36} {v['mean']:8.4f} {v['max']:8.3f} {v['lap']:10.3f} {v['lap_max']:8.3f} {100 * v['limit']:8.1f}% {v['failed']:7d}"
        )
    pv = s["PVFC"]
    return [
        (f"{label}: PVFC ran every held-out plant", pv["failed"] == 0),
        (
            f"{label}: PVFC's mean distance ≤ each speed-scaling tracker's",
            all(pv["mean"] <= v["mean"] for n, v in s.items() if n.startswith("speed")),
        ),
        (f"{label}: PVFC's mean distance ≤ ⅓ of the timed tracker's", pv["mean"] <= s["timed (tuned gains)"]["mean"] / 3),
        (f"{label}: PVFC's laps within 1.25× the least lap on every plant", pv["lap_max"] <= 1.25),
    ]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pvfc", default=str(REPO / "target" / "release" / "pvfc"))
    p.add_argument("--out", default="results/fair")
    p.add_argument("--check", action="store_true")
    a = p.parse_args()
    out = Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    verdicts: List[Tuple[str, bool]] = []
    for label, base in SETTINGS.items():
        verdicts += setting(a.pvfc, out, label, base)
    print()
    for what, ok in verdicts:
        print(f"  [{'holds' if ok else 'FAILS'}] {what}")
    return 1 if a.check and not all(ok for _, ok in verdicts) else 0


if __name__ == "__main__":
    sys.exit(main())
