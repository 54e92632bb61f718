"""A cam mechanism drawn as a textbook draws it: the cam's profile turned to the cam angle, its
base circle and pitch curve, the roller on the follower (a stem on its guide, or an arm on its
pivot), the supports hatched; and a position plan by inversion (the cam held still, the follower
placed around it at each angle, as the profile is built)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from linkgen.draw.plan import DPI, FIGSIZE, plt_module, save, title_of
from linkgen.draw.skeleton import CRANK, INK, LINK, hatch_line

PROFILE_POINTS = 721
# A single drawing's default cam angle: the first on a grid of this step [°] where the follower moves
# at least this fraction of its fastest (at 0 the programs dwell, and every vector on the follower
# vanishes).
DEFAULT_STEP_DEG, MOVING = 15.0, 0.5


def default_cam_angle(cm) -> float:
    """The cam angle [rad] a single drawing shows by default (DEFAULT_STEP_DEG, MOVING)."""
    grid = np.radians(np.arange(0.0, 360.0, DEFAULT_STEP_DEG))
    speed = np.abs(cm.follower.output(grid)[1])
    return float(grid[np.flatnonzero(speed >= MOVING * speed.max())[0]]) if speed.max() > 0.0 else 0.0


def _rot(xy: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return xy @ np.array([[c, s], [-s, c]])


def _support(ax, p, size: float) -> None:
    from matplotlib.patches import Polygon

    w, h = 0.05 * size, 0.04 * size
    ax.add_patch(Polygon([p, p + (-0.5 * w, -h), p + (0.5 * w, -h)], closed=True, facecolor="white", edgecolor=INK,
                         lw=1.0, zorder=4))
    hatch_line(ax, p + (-0.8 * w, -h), p + (0.8 * w, -h), np.array([0.0, -1.0]), size, z=4)


def _follower(ax, cm, centre: np.ndarray, frame_angle: float, size: float, alpha: float = 1.0) -> None:
    """The roller at ``centre`` and the follower's stem or arm, in a frame turned by frame_angle."""
    from matplotlib.patches import Circle

    f = cm.follower
    if f.flat:  # the face square to the motion, the stem on the follower's axis
        up = _rot(np.array([[0.0, 1.0]]), frame_angle)[0]
        side = np.array([up[1], -up[0]])
        foot = centre + side * (f.offset - float(np.dot(centre, side)))
        reach = 0.22 * size
        a, b = foot - side * reach, foot + side * reach
        ax.plot([a[0], b[0]], [a[1], b[1]], color=LINK, lw=3.0, alpha=alpha, zorder=5, solid_capstyle="butt")
        top = foot + up * 0.35 * size
        ax.plot([foot[0], top[0]], [foot[1], top[1]], color=LINK, lw=3.0, alpha=alpha, zorder=4)
        ax.plot(*centre, "o", ms=3, color=INK, alpha=alpha, zorder=6)  # the contact point
        return
    rr = max(f.roller_radius, 0.006 * size)
    ax.add_patch(Circle(centre, rr, facecolor=(*LINK, 0.25 * alpha), edgecolor=(*LINK, alpha), lw=1.6, zorder=5))
    if f.kind == "translating":
        up = _rot(np.array([[0.0, 1.0]]), frame_angle)[0]
        top = centre + up * 0.35 * size
        ax.plot([centre[0], top[0]], [centre[1], top[1]], color=LINK, lw=3.0, alpha=alpha, zorder=4,
                solid_capstyle="round")
    else:
        pivot = _rot(np.array([[f.pivot_distance, 0.0]]), frame_angle)[0]
        ax.plot([centre[0], pivot[0]], [centre[1], pivot[1]], color=LINK, lw=3.0, alpha=alpha, zorder=4,
                solid_capstyle="round")


def _omega_arrow(ax, theta: float, omega: float, radius: float) -> None:
    """The sense of the cam's turn: an arc arrow about O, a quarter turn ahead of the angle mark."""
    from matplotlib.patches import FancyArrowPatch

    sense = 1.0 if omega >= 0.0 else -1.0
    a0, a1 = theta + sense * 0.6, theta + sense * 1.6
    p0, p1 = (radius * np.array([math.cos(a), math.sin(a)]) for a in (a0, a1))
    ax.add_patch(FancyArrowPatch(tuple(p0), tuple(p1), connectionstyle=f"arc3,rad={0.3 * sense}", arrowstyle="-|>",
                                 mutation_scale=12, color=CRANK, lw=1.4, zorder=6))
    q = 1.2 * radius * np.array([math.cos(0.5 * (a0 + a1)), math.sin(0.5 * (a0 + a1))])
    ax.text(q[0], q[1], "ω", color=CRANK, fontsize=11, ha="center", va="center", zorder=6)


def cam_figure(cm, theta: float, out: Path | None = None, arrows=None):
    """The cam at cam angle θ [rad] with its follower, the sense of its turn (ω) and ``arrows``
    (``draw.vectors.Arrows``, or None) to one scale; saved to ``out`` when given."""
    plt = plt_module()
    f = cm.follower
    th = np.linspace(0.0, 2 * math.pi, PROFILE_POINTS)
    profile = _rot(f.profile(th), theta)
    pitch = _rot(f.pitch_curve(th)[0], theta)
    centre = f.centre(np.array([theta]))[0][0]
    size = 2.2 * float(np.hypot(*pitch.T).max()) + (f.pivot_distance if f.kind == "oscillating" else 0.0)
    fig, ax = plt.subplots(figsize=FIGSIZE, dpi=DPI, layout="constrained")
    ax.fill(profile[:, 0], profile[:, 1], facecolor=(*CRANK, 0.2), edgecolor=CRANK, lw=2.0, zorder=2)
    ax.plot(pitch[:, 0], pitch[:, 1], ls=(0, (4, 2)), lw=0.8, color="tab:blue", zorder=1, label="pitch curve")
    base = f.base_radius * np.column_stack([np.cos(th), np.sin(th)])
    ax.plot(base[:, 0], base[:, 1], ls=":", lw=0.8, color="gray", zorder=1, label="base circle")
    ax.plot([0, 0.9 * f.base_radius * math.cos(theta)], [0, 0.9 * f.base_radius * math.sin(theta)], color=CRANK,
            lw=1.0, zorder=3)  # the cam's angle mark
    _support(ax, np.zeros(2), size)
    _follower(ax, cm, centre, 0.0, size)
    if f.kind == "translating":
        guide_y = centre[1] + 0.2 * size
        centre = np.array([f.offset, centre[1]]) if f.flat else centre
        for s in (-1, 1):
            x = f.offset + s * 0.03 * size
            hatch_line(ax, (x, guide_y - 0.05 * size), (x, guide_y + 0.05 * size), np.array([s, 0.0]), size, z=3)
    else:
        _support(ax, np.array([f.pivot_distance, 0.0]), size)
    back = theta + math.pi + math.radians(40.0)  # O's name away from the angle mark (along θ) and the support (below)
    ax.text(0.06 * size * math.cos(back), 0.06 * size * math.sin(back) + 0.01 * size, "O", fontsize=10, ha="center",
            va="center", zorder=6, bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8))
    _omega_arrow(ax, theta, cm.omega, 0.55 * f.base_radius)
    what = ""
    if arrows is not None and arrows.arrows:
        from linkgen.draw.teaching import draw_arrows

        mu = draw_arrows(ax, arrows, size)
        what = f", {arrows.what}: 1 m of drawing = {mu:g} {arrows.unit}"
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, lw=0.3, alpha=0.4)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_title(f"{title_of(cm)}\nφ = {math.degrees(theta):.4g}°, ω = {cm.omega:.4g} rad/s{what}", fontsize=10)
    if out is not None:
        save(fig, out)
    return fig


def cam_plan_figure(cm, angles, out: Path | None = None):
    """A position plan by inversion: the cam at θ = 0, the follower placed at each cam angle
    turned back by −θ (numbered), over the pitch curve."""
    plt = plt_module()
    f = cm.follower
    th = np.linspace(0.0, 2 * math.pi, PROFILE_POINTS)
    profile, pitch = f.profile(th), f.pitch_curve(th)[0]
    size = 2.2 * float(np.hypot(*pitch.T).max()) + (f.pivot_distance if f.kind == "oscillating" else 0.0)
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    fig, ax = plt.subplots(figsize=FIGSIZE, dpi=DPI, layout="constrained")
    ax.fill(profile[:, 0], profile[:, 1], facecolor=(*CRANK, 0.2), edgecolor=CRANK, lw=2.0, zorder=2)
    ax.plot(pitch[:, 0], pitch[:, 1], ls=(0, (4, 2)), lw=0.8, color="tab:blue", zorder=1, label="pitch curve")
    _support(ax, np.zeros(2), size)
    centres = f.pitch_curve(angles)[0]
    for i, (a, c) in enumerate(zip(angles, centres)):
        _follower(ax, cm, c, -a, size, alpha=1.0 if i == 0 else 0.4)
        q = c * (1 + 0.06 * size / max(float(np.hypot(*c)), 1e-12))
        ax.text(q[0], q[1], str(i), fontsize=8, color=CRANK, ha="center", va="center")
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m] (the cam's frame)")
    ax.set_ylabel("y [m]")
    ax.grid(True, lw=0.3, alpha=0.4)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_title(f"{title_of(cm)}\nposition plan by inversion: {len(angles)} cam angles from "
                 f"{math.degrees(angles[0]):.4g}° (0 solid)", fontsize=10)
    if out is not None:
        save(fig, out)
    return fig


__all__ = ["cam_figure", "cam_plan_figure", "default_cam_angle"]
