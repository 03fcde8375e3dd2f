"""The figures of the paper's section V from simulation results (needs matplotlib:
``pip install "pvfc[plot]"``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Optional, Sequence

import numpy as np

from ._pvfc import Lissajous, SimulationResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def _pyplot() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - exercised only without matplotlib
        raise ImportError('pvfc.plot needs matplotlib: pip install "pvfc[plot]"') from e
    return plt


def desired_contour(contour: Optional[Lissajous] = None, points: int = 600) -> np.ndarray:
    """Points of a contour over one period, shape (points + 1, 2) (default: the paper's)."""
    c = contour if contour is not None else Lissajous.paper()
    period = c.period or 6.0
    return np.array([c.sample(period * k / points)[0] for k in range(points + 1)])


def last_pass(result: SimulationResult) -> slice:
    """The samples of the last complete pass of the contour (τ ∈ [kP, (k+1)P))."""
    tau, period = result.tau, result.period
    k = np.floor(tau[-1] / period) - 1
    if k < 0:
        return slice(0, len(tau))
    start = int(np.searchsorted(tau, k * period))
    stop = int(np.searchsorted(tau, (k + 1) * period))
    return slice(start, stop + 1)


def contour_figure(
    results: Sequence[SimulationResult],
    labels: Sequence[str],
    title: str = "",
    contour: Optional[Lissajous] = None,
) -> "Figure":
    """Like Figs. 8–10: the contour traced over one pass, U(E) and dτ/dt against τ."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(8, 10))
    ref = desired_contour(contour)
    axes[0].plot(ref[:, 0], ref[:, 1], "k--", lw=0.8, label="desired contour")
    for r, label in zip(results, labels):
        s = last_pass(r)
        q = r.q[s]
        tau0 = np.floor(r.tau[s][0] / r.period) * r.period
        axes[0].plot(q[:, 0], q[:, 1], label=label)
        axes[1].semilogy(r.tau[s] - tau0, np.maximum(r.potential[s], 1e-12), label=label)
        axes[2].plot(r.tau[s] - tau0, r.tau_dot[s], label=label)
    axes[0].set(xlabel="q1 [rad]", ylabel="q2 [rad]", title=f"{title}: contour traced (one pass)")
    axes[1].set(xlabel="τ", ylabel="U(E)", title="potential during one pass")
    axes[2].set(xlabel="τ", ylabel="dτ/dt", title="rate of trajectory progression")
    for a in axes:
        a.legend(loc="upper right", fontsize=8)
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def unforced_figure(result: SimulationResult) -> "Figure":
    """Like Fig. 6: the contour traced, U(E(t)) and the kinetic energy."""
    plt = _pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(8, 10))
    ref = desired_contour()
    axes[0].plot(ref[:, 0], ref[:, 1], "k--", lw=0.8, label="desired contour")
    axes[0].plot(result.q[:, 0], result.q[:, 1], label="traced")
    axes[0].set(xlabel="q1 [rad]", ylabel="q2 [rad]", title="Fig. 6: contour traced")
    axes[0].legend(loc="upper right", fontsize=8)
    axes[1].semilogy(result.t, np.maximum(result.potential, 1e-8))
    axes[1].set(xlabel="t [s]", ylabel="U(E)", title="potential U(E(t))")
    axes[2].plot(result.t, result.energy)
    axes[2].set(xlabel="t [s]", ylabel="κ_a [J]", title="kinetic energy")
    for a in axes:
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def approach_figure(results: Sequence[SimulationResult], labels: Sequence[str], seconds: float = 4.0) -> "Figure":
    """Like Fig. 7: the path from the initial position over the first seconds."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 4))
    ref = desired_contour()
    ax.plot(ref[:, 0], ref[:, 1], "k--", lw=0.8, label="desired contour")
    for r, label in zip(results, labels):
        n = int(np.searchsorted(r.t, seconds))
        ax.plot(r.q[:n, 0], r.q[:n, 1], label=label)
    ax.set(xlabel="q1 [rad]", ylabel="q2 [rad]", title=f"Fig. 7: approach, first {seconds:g} s")
    ax.legend(loc="upper right", fontsize=8)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig
