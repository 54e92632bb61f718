"""Figures of a machine run, as the textbook draws them: ω(t) and the motor torque M(t), the
phase portrait ω(M), and δ against the flywheel inertia."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from linkgen.machine.machine import MachineRun
from linkgen.outputs import save_figure


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_run(name: str, run: MachineRun, path: Path, mujoco=None) -> None:
    """ω(t), M(t) and ω(M) in one figure; MuJoCo's ω(t) dashed when given."""
    plt = _plt()
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(16, 4.8), constrained_layout=True)
    a1.plot(run.t, run.omega, lw=2, label="closed form (one-mass ODE)")
    if mujoco is not None:
        a1.plot(mujoco.t, mujoco.omega, "k--", lw=0.9, label="MuJoCo (full linkage)")
    if run.steady is not None:
        for w in (run.steady.omega_min, run.steady.omega_max):
            a1.axhline(w, color="gray", lw=0.6, ls=":")
        a1.axvline(run.steady.t_start, color="gray", lw=0.6, ls=":", label="steady cycle from here")
    a1.set(title="crank speed ω(t)", xlabel="t [s]", ylabel="ω [rad/s]")
    a1.legend(fontsize=8, loc="lower right")
    a2.plot(run.t, run.motor_torque, color="tab:red", lw=1.5)
    a2.set(title="motor torque M(t) (motor shaft)", xlabel="t [s]", ylabel="M [N·m]")
    a3.plot(run.motor_torque, run.omega, color="tab:green", lw=1.2)
    a3.set(title="phase portrait ω(M)", xlabel="M [N·m]", ylabel="ω [rad/s]")
    fig.suptitle(f"{name}: machine start-up and steady running")
    save_figure(fig, path, dpi=90)
    plt.close(fig)


def plot_flywheel(name: str, inertias: np.ndarray, deltas: np.ndarray, sized: tuple[float, float], path: Path) -> None:
    """δ against the flywheel inertia, with the sized point."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4.8), constrained_layout=True)
    ax.loglog(inertias, deltas, lw=2)
    ax.plot(*sized, "o", color="tab:red", label=f"sized: J = {sized[0]:.4g} kg·m², δ = {sized[1]:.4g}")
    ax.set(title=f"{name}: speed fluctuation δ against flywheel inertia", xlabel="flywheel inertia [kg·m²]",
           ylabel="δ = (ω_max − ω_min)/ω_mean")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    save_figure(fig, path, dpi=90)
    plt.close(fig)


__all__ = ["plot_flywheel", "plot_run"]
