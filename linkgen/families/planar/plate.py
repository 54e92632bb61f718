"""Mass properties of a uniform plate over the convex hull of a link's points."""

from __future__ import annotations

import numpy as np


def convex_hull(points) -> np.ndarray:
    """The convex hull (k, 2) of 2-D points, counter-clockwise (Andrew's monotone chain)."""
    pts = sorted({(float(x), float(y)) for x, y in points})
    if len(pts) < 3:
        return np.array(pts, dtype=float).reshape(-1, 2)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1], dtype=float)


def hull_area(points) -> float:
    """Area [m²] of the convex hull of the points (0 when they are fewer than 3 or collinear)."""
    h = convex_hull(points)
    if len(h) < 3:
        return 0.0
    x, y = h[:, 0], h[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def plate_properties(points, areal_density: float) -> tuple[float, tuple[float, float], float]:
    """Mass [kg], centre of mass [m] and planar moment of inertia about it [kg·m²] of a plate of
    areal density ρ [kg/m²] over the convex hull of ``points`` (the polygon formulas: sums over
    the edges of cross products, with the parallel-axis theorem for the centre)."""
    h = convex_hull(points)
    x, y = h[:, 0], h[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    area = 0.5 * float(c.sum())
    cx = float(((x + xn) * c).sum()) / (6 * area)
    cy = float(((y + yn) * c).sum()) / (6 * area)
    i_origin = float(((x * x + x * xn + xn * xn + y * y + y * yn + yn * yn) * c).sum()) / 12.0  # polar, ρ = 1
    mass = areal_density * area
    return mass, (cx, cy), areal_density * i_origin - mass * (cx * cx + cy * cy)
