"""Spring symbols on the kinematic skeleton: a zig-zag between a spring's two points (with a
damper's dashpot beside it where it has damping) and a spiral about a torsion spring's joint.
Sizes are fractions of the mechanism's extent, as in ``skeleton``."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.positions import Positions

SPRING_COLOR = (0.8, 0.6, 0.05)  # the MJCF's tendon colour, darker on white
ZIGZAG_WIDTH = 0.018  # half-width of the zig-zag
ZIGZAG_TEETH = 8
LEAD = 0.15  # fraction of the spring's length drawn straight at each end
SPIRAL_RADII = (0.018, 0.04)  # inner, outer radius of a torsion spring's spiral
SPIRAL_TURNS = 2.25


def zigzag(p: np.ndarray, q: np.ndarray, width: float, teeth: int = ZIGZAG_TEETH) -> np.ndarray:
    """The zig-zag polyline (k, 2) from p to q: straight leads, then ``teeth`` teeth of half-width
    ``width`` across the line."""
    d = q - p
    length = float(np.hypot(*d))
    if length == 0.0:
        return np.array([p, q])
    u = d / length
    nrm = np.array([-u[1], u[0]])
    a, b = p + LEAD * d, q - LEAD * d
    t = np.linspace(0.0, 1.0, 2 * teeth + 1)
    side = np.where(np.arange(t.size) % 2 == 1, 1.0, 0.0) * np.where((np.arange(t.size) // 2) % 2 == 0, 1.0, -1.0)
    body = a + t[:, None] * (b - a) + (side * width)[:, None] * nrm
    return np.vstack([p, body, q])


def spiral(c: np.ndarray, start: float, r0: float, r1: float, turns: float = SPIRAL_TURNS) -> np.ndarray:
    """An Archimedean spiral (k, 2) about c from radius r0 to r1 over ``turns`` turns."""
    s = np.linspace(0.0, 1.0, 160)
    a = start + 2 * math.pi * turns * s
    r = r0 + (r1 - r0) * s
    return c + np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


def draw_springs(ax, pos: Positions, size: float, i: int, alpha: float = 1.0) -> None:
    """Every spring and torsion spring of ``pos``'s mechanism at index ``i`` (data units: metres)."""
    mech = pos.mechanism
    for s in mech.springs:
        p, q = (np.asarray(pos.points[n][i], dtype=float) for n in s.points)
        xy = zigzag(p, q, ZIGZAG_WIDTH * size)
        ax.plot(xy[:, 0], xy[:, 1], color=SPRING_COLOR, lw=1.3, alpha=alpha, zorder=3.2)
        if s.damping:  # a dashpot beside the spring: a cylinder and its rod
            d = q - p
            nrm = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), np.finfo(float).tiny)
            off = 2.5 * ZIGZAG_WIDTH * size * nrm
            m = 0.5 * (p + q)
            cup = 0.6 * ZIGZAG_WIDTH * size * nrm
            ax.plot(*np.array([p + off, m + off]).T, color=SPRING_COLOR, lw=1.0, alpha=alpha, zorder=3.2)
            ax.plot(*np.array([m + off - cup, m + off + cup]).T, color=SPRING_COLOR, lw=1.6, alpha=alpha, zorder=3.2)
            box = np.array([m + off - 1.6 * cup + 0.2 * d, m + off - 1.6 * cup - 0.1 * d,
                            m + off + 1.6 * cup - 0.1 * d, m + off + 1.6 * cup + 0.2 * d])
            ax.plot(*box.T, color=SPRING_COLOR, lw=1.0, alpha=alpha, zorder=3.2)
            ax.plot(*np.array([m + off + 0.2 * d, q + off]).T, color=SPRING_COLOR, lw=1.0, alpha=alpha, zorder=3.2)
    for t in mech.torsion_springs:
        c = np.asarray(pos.points[mech.revolute(t.joint).point][i], dtype=float)
        start = float(pos.angles[t.links[1]][i]) if t.links[1] in pos.angles else 0.0
        xy = spiral(c, start, SPIRAL_RADII[0] * size, SPIRAL_RADII[1] * size)
        ax.plot(xy[:, 0], xy[:, 1], color=SPRING_COLOR, lw=1.2, alpha=alpha, zorder=4.5)


__all__ = ["SPRING_COLOR", "draw_springs", "spiral", "zigzag"]
