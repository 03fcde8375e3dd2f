"""A wall across the contour, from Python: PVFC against a timed tracker (the Rust twin is
`pvfc run scenarios/contact_wall.toml`, or `cargo run --release --example contact_wall`).

    python examples/python/contact_wall.py --out figures

Prints the peak contact force, the energy each controller pumped into the wall and the energy
audit, and draws the tool paths and the contact forces with matplotlib.
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import pvfc  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("figures"))
    ap.add_argument("--duration", type=float, default=15.0)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    d = pvfc.Scenario.preset("contact_wall").to_dict()
    d["duration"] = args.duration
    scenario = pvfc.Scenario.from_dict(d)
    pvfc_run = pvfc.simulate(scenario)
    timed = pvfc.simulate_timed(scenario, kp=[400.0, 400.0], kd=[40.0, 40.0], tau_rate=1.0)

    fig, (ax_path, ax_force) = plt.subplots(2, 1, figsize=(8, 9))
    for run, label in [(pvfc_run, "PVFC"), (timed, "timed tracker")]:
        s = run.contact_summary()
        c = run.contact
        print(f"{label}: peak force {s['peak_force']:.0f} N, energy pumped into the wall "
              f"{s['energy_pumped']:.1f} J, audit residual {s['audit']:.1e} of {s['energy_scale']:.1f} J")
        ax_path.plot(c["tool"][:, 0], c["tool"][:, 1], label=label)
        ax_force.plot(run.t, c["normal_force"], label=label)
    ax_path.axvline(0.68, color="grey", linestyle="--", label="wall")
    ax_path.set(xlabel="x [m]", ylabel="y [m]", title="tool path")
    ax_force.set(xlabel="t [s]", ylabel="contact force [N]")
    for ax in (ax_path, ax_force):
        ax.legend()
    fig.tight_layout()
    fig.savefig(args.out / "contact_wall_python.png", dpi=100)


if __name__ == "__main__":
    main()
