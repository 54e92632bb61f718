"""The report's figures of a stand-alone cam: the cam and its follower, the follower's
displacement, velocity and acceleration, and the contact force and cam torque over the compared
turn — closed form (wide line) against MuJoCo (thin line at every step; the acceleration and forces,
a train of small impacts on the faceted profile, also as the means over the windows
``validate`` compares, dots)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from linkgen.families.cam.kinetics import state
from linkgen.report.figures import DPI, _plt
from linkgen.mujoco.cam import WINDOWS
from linkgen.mujoco.cam_run import window_means

# The y axis spans the closed form's range and this fraction of it either side; MuJoCo's impacts
# beyond it (the faceted contact's, up to twice the peak) run off the axis.
CLIP = 0.5


def _pair(ax, deg, cf, mj, title: str, unit: str, means: bool = False) -> None:
    ax.plot(deg, mj, color="tab:red", lw=0.4, alpha=0.3 if means else 1.0, zorder=1, label="MuJoCo, every step")
    ax.plot(deg, cf, color="tab:blue", lw=3, alpha=0.6, zorder=2, label="closed form")
    lo, hi = float(cf.min()), float(cf.max())
    pad = CLIP * max(hi - lo, abs(hi), abs(lo), 1e-300)
    if mj.min() < lo - pad or mj.max() > hi + pad:  # the contact's impacts would flatten the closed form
        ax.set_ylim(lo - pad, hi + pad)
        title += " (MuJoCo's impacts clipped)"
    if means:
        n = (deg.shape[0] // WINDOWS) * WINDOWS
        ax.plot(window_means(deg[:n], WINDOWS), window_means(mj[:n], WINDOWS), "k.", ms=3, zorder=3,
                label=f"MuJoCo, {360 / WINDOWS:g}° means")
    ax.set_ylabel(f"{title} [{unit}]", fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, frameon=False)


def plot_cam(cm, run, out: Path) -> list[str]:
    """The cam's drawing, its follower's motion and its forces into ``out`` (PNG); returns the
    file names, the drawing first."""
    from linkgen.draw.cam import cam_figure, default_cam_angle

    plt = _plt()
    names = [f"{cm.name}_drawing.png", f"{cm.name}_motion.png", f"{cm.name}_forces.png"]
    plt.close(cam_figure(cm, default_cam_angle(cm), out / names[0]))
    order = np.argsort(run.theta % (2 * math.pi), kind="stable")  # one turn, from θ = 0
    th = (run.theta % (2 * math.pi))[order]
    deg = np.degrees(th)
    ref = state(cm, th, float(np.mean(run.omega)))
    unit = "m" if cm.follower.kind == "translating" else "rad"
    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    for ax, title, u, cf, mj in ((axes[0], "displacement", unit, ref.displacement, run.displacement),
                                 (axes[1], "velocity", f"{unit}/s", ref.velocity, run.velocity),
                                 (axes[2], "acceleration", f"{unit}/s²", ref.acceleration, run.acceleration)):
        _pair(ax, deg, cf, mj[order], title, u, means=title == "acceleration")
    axes[0].set_title(f"{cm.name}: the follower, closed form against MuJoCo", fontsize=9)
    axes[-1].set_xlabel("cam angle φ [°]")
    fig.tight_layout()
    fig.savefig(out / names[1], dpi=DPI)
    plt.close(fig)
    fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    _pair(axes[0], deg, ref.contact_force, run.contact_force[order], "contact force", "N", means=True)
    _pair(axes[1], deg, ref.cam_torque, run.cam_torque[order], "cam torque", "N·m", means=True)
    axes[0].set_title(f"{cm.name}: the contact, closed form against MuJoCo", fontsize=9)
    axes[-1].set_xlabel("cam angle φ [°]")
    fig.tight_layout()
    fig.savefig(out / names[2], dpi=DPI)
    plt.close(fig)
    return names


__all__ = ["plot_cam"]
