"""Reproduce the figures of the paper's section V (Figs. 6–10) from Python with matplotlib.

    python examples/python/reproduce_paper.py --out figures

The same scenarios as `pvfc reproduce` (the built-in presets), run in parallel in Rust.
"""

import argparse
import pathlib

import pvfc
import pvfc.plot


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("figures"))
    ap.add_argument("--quick", action="store_true", help="shorter runs (for tests)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    names = ["fig6_unforced", "fig7_R0", "fig7_R100", "fig8_R0", "fig8_R100", "fig8_R200",
             "fig9_R0", "fig9_R50", "fig9_R100", "fig9_R200", "fig10_r1", "fig10_r2", "fig10_r3"]
    scenarios = []
    for n in names:
        d = pvfc.Scenario.preset(n).to_dict()
        if args.quick:
            d["duration"] = min(d["duration"], 14.0)
        scenarios.append(pvfc.Scenario.from_dict(d))
    runs = {r.name: r for r in pvfc.simulate_many(scenarios)}

    figures = {
        "fig6_unforced.png": pvfc.plot.unforced_figure(runs["fig6_unforced"]),
        "fig7_self_pacing.png": pvfc.plot.approach_figure([runs["fig7_R0"], runs["fig7_R100"]], ["R = 0", "R = 100"]),
        "fig8_pacing_compensated.png": pvfc.plot.contour_figure(
            [runs[f"fig8_R{r}"] for r in ("0", "100", "200")], ["R = 0", "R = 100", "R = 200"], "Fig. 8"),
        "fig9_pacing_uncompensated.png": pvfc.plot.contour_figure(
            [runs[f"fig9_R{r}"] for r in ("0", "50", "100", "200")], ["R = 0", "R = 50", "R = 100", "R = 200"], "Fig. 9"),
        "fig10_nominal_speed.png": pvfc.plot.contour_figure(
            [runs[f"fig10_r{r}"] for r in ("1", "2", "3")], ["r = 1", "r = 2", "r = 3"], "Fig. 10"),
    }
    for name, fig in figures.items():
        fig.savefig(args.out / name, dpi=100)
        print("wrote", args.out / name)
    for name, r in runs.items():
        u = r.mean_potential_over_pass()
        print(f"{name:16s} mean U over the last pass: {u:.3e}" if u is not None else f"{name:16s} (no complete pass)")


if __name__ == "__main__":
    main()
