"""Figures of the mechanism itself: its skeleton at one crank angle, and a position plan (several
positions overlaid, numbered, with every moving point's path over the drive's range)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from linkgen.families.planar.positions import Positions, drive_angles, positions
from linkgen.draw.skeleton import CRANK, Frame, draw_skeleton, frame_of, set_limits
from linkgen.families.planar.description import GROUND, Mechanism

FIGSIZE = (8.0, 6.0)  # inches
DPI = 110


def plt_module():
    """matplotlib's pyplot on the file-only Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def moving_points(mech: Mechanism) -> list[str]:
    """Points that move: not on the ground and not the crank's pivot."""
    fixed = set(mech.link(GROUND).points)
    return [p for p in mech.points if p not in fixed]


def draw_paths(ax, paths: Positions, *, lw: float = 0.9) -> None:
    """Every moving point's path over the drive's range, one colour each, with a legend entry."""
    plt = plt_module()
    names = moving_points(paths.mechanism)
    cmap = plt.get_cmap("tab10" if len(names) <= 10 else "turbo")
    for k, name in enumerate(names):
        xy = paths.points[name]
        color = cmap(k % 10) if len(names) <= 10 else cmap(k / max(len(names) - 1, 1))
        ax.plot(xy[:, 0], xy[:, 1], ls=(0, (4, 2)), lw=lw, color=color, zorder=5.5, label=f"path of {name}")


def title_of(mech: Mechanism, width: int = 90) -> str:
    """The mechanism's title wrapped at ``width`` characters, drawn as written: each ``$`` escaped,
    which matplotlib would otherwise take for the start of a formula (and fail to parse)."""
    import textwrap

    return "\n".join(textwrap.wrap(mech.title or mech.name, width)).replace("$", r"\$")


def slides_in(mech) -> bool:
    """The input is a stroke s [m] (a planar prismatic drive, a PSSR/PSSP slider), not an angle φ."""
    return bool(getattr(mech, "slide_drive", False) or getattr(getattr(mech, "drive", None), "slides", False))


def input_at(mech, phi: float) -> str:
    """The input's value as a drawing's title says it: ``φ = 30°`` or ``s = 0.8 m``."""
    return f"s = {float(phi):.4g} m" if slides_in(mech) else f"φ = {math.degrees(float(phi)):.4g}°"


def rates_of(mech, omega: float, epsilon: float | None = None) -> str:
    """The input's rate (and its derivative): ``ω = 10 rad/s, ε = 0 rad/s²`` or ``ṡ = 0.1 m/s, s̈ = 0 m/s²``."""
    w, e, u = ("ṡ", "s̈", "m") if slides_in(mech) else ("ω", "ε", "rad")
    return f"{w} = {omega:.4g} {u}/s" + (f", {e} = {epsilon:.4g} {u}/s²" if epsilon is not None else "")


def skeleton_figure(mech: Mechanism, phi: float, out: Path | None = None, *, paths: Positions | None = None):
    """The skeleton at crank angle ``phi`` [rad]; saved to ``out`` (png/svg/pdf) when given.
    Returns the matplotlib figure (closed when saved)."""
    plt = plt_module()
    paths = paths if paths is not None else positions(mech, drive_angles(mech))
    frame = frame_of(paths)
    pos = positions(mech, [phi])
    fig, ax = plt.subplots(figsize=FIGSIZE, dpi=DPI, layout="constrained")
    draw_skeleton(ax, pos, frame, 0)
    set_limits(ax, paths, frame)
    ax.set_title(f"{title_of(mech)}\n" + (f"s = {phi:.4g} m" if mech.slide_drive else f"φ = {np.degrees(phi):.4g}°"),
                 fontsize=10)
    return _finish(fig, out)


def plan_figure(mech: Mechanism, angles, out: Path | None = None, *, paths: Positions | None = None):
    """A position plan: the mechanism at each of ``angles`` [rad] (numbered 0, 1, … at the crank
    pin), the first drawn solid and the others paler, over the point paths of the whole range."""
    plt = plt_module()
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    paths = paths if paths is not None else positions(mech, drive_angles(mech))
    frame = frame_of(paths)
    pos = positions(mech, angles)
    fig, ax = plt.subplots(figsize=FIGSIZE, dpi=DPI, layout="constrained")
    draw_paths(ax, paths)
    tip = mech.link(mech.crank).points[1] if len(mech.link(mech.crank).points) > 1 else None
    for i in range(len(pos)):
        draw_skeleton(ax, pos, frame, i, alpha=1.0 if i == 0 else 0.35, labels=i == 0, arrow=i == 0)
        if mech.slide_drive:  # numbered beside the slider's point, off its guide line
            _, u = pos.guide_line(mech.drive.joint, i)
            q = pos.points[mech.prismatic(mech.drive.joint).point][i] - 0.05 * frame.size * np.array([-u[1], u[0]])
            ax.text(q[0], q[1], str(i), fontsize=8, color=CRANK, ha="center", va="center", zorder=8)
        elif tip is not None:
            p = pos.points[tip][i]
            c = pos.points[mech.link(mech.crank).points[0]][i]
            d = p - c
            n = float(np.hypot(*d)) or 1.0
            q = p + 0.07 * frame.size * d / n  # ringed, clear of the pin's name: "0" beside "A" reads "A0"
            ax.text(q[0], q[1], str(i), fontsize=7, color=CRANK, ha="center", va="center", zorder=8,
                    bbox=dict(boxstyle="circle,pad=0.15", fc="white", ec=CRANK, lw=0.6))
    set_limits(ax, paths, frame)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, frameon=False)
    if mech.slide_drive:
        step = np.diff(angles)
        spacing = f", every {step[0]:.4g} m" if len(step) and np.allclose(step, step[0]) else ""
        first = f"s = {angles[0]:.4g} m"
    else:
        step = np.degrees(np.diff(angles))
        spacing = f", every {step[0]:.4g}°" if len(step) and np.allclose(step, step[0]) else ""
        first = f"φ = {np.degrees(angles[0]):.4g}°"
    ax.set_title(f"{title_of(mech)}\nposition plan: {len(angles)} positions from {first}{spacing} (0 solid)",
                 fontsize=10)
    return _finish(fig, out)


def _finish(fig, out: Path | None):
    if out is None:
        return fig
    save(fig, out)
    return fig


def save(fig, out: Path, dpi: float = DPI) -> None:
    """Write ``fig`` to ``out`` in the format its suffix names (png, svg, pdf) and close it."""
    from linkgen.outputs import save_figure

    plt = plt_module()
    try:
        save_figure(fig, out, dpi=dpi)  # atomic, never through a symlink, no date in svg/pdf
    finally:
        plt.close(fig)


__all__ = ["DPI", "FIGSIZE", "draw_paths", "moving_points", "plan_figure", "plt_module", "save", "skeleton_figure"]
