"""A disc cam with a translating roller follower, by inversion: the pitch curve (the roller
centre's path in the cam's frame), the cam profile (the pitch curve offset inwards by the roller
radius), the pressure angle and the radius of curvature, and the smallest base circle for a
largest pressure angle.

Geometry (cam turning counter-clockwise about the origin, follower moving along +y on the line
x = e): the roller centre sits at (e, d + s), d = √((r_b + r_r)² − e²), r_b the base circle,
r_r the roller radius. In the cam's frame that point is turned by −θ. The pressure angle α
between the follower's direction and the normal to the pitch curve obeys
tan α = (ds/dθ − e)/(d + s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.cam.laws import Program


@dataclass(frozen=True)
class TranslatingCam:
    """Base circle radius r_b [m], roller radius r_r [m] (0: knife edge), offset e [m]."""

    program: Program
    base_radius: float
    roller_radius: float = 0.0
    offset: float = 0.0

    @property
    def lift_origin(self) -> float:
        """d: the roller centre's height above the cam centre at s = 0 [m]."""
        r0 = self.base_radius + self.roller_radius
        if abs(self.offset) >= r0:
            raise ValueError(f"offset {self.offset} m must be smaller than base + roller radius {r0} m")
        return math.sqrt(r0 * r0 - self.offset**2)

    def pitch_curve(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Roller centre in the cam's frame (n, 2) [m] with its first and second derivatives
        with respect to θ."""
        th = np.asarray(theta, dtype=float)
        s, s1, s2, _ = self.program.displacement(th)
        e, y = self.offset, self.lift_origin + s
        c, sn = np.cos(th), np.sin(th)
        # rotate (e, y) by −θ: (e·c + y·sn, −e·sn + y·c)
        p = np.column_stack([e * c + y * sn, -e * sn + y * c])
        dp = np.column_stack([-e * sn + s1 * sn + y * c, -e * c + s1 * c - y * sn])
        ddp = np.column_stack([-e * c + s2 * sn + 2 * s1 * c - y * sn, e * sn + s2 * c - 2 * s1 * sn - y * c])
        return p, dp, ddp

    def pressure_angle(self, theta) -> np.ndarray:
        """α [rad] at cam angles θ."""
        s, s1, _, _ = self.program.displacement(theta)
        return np.arctan2(s1 - self.offset, self.lift_origin + s)

    def pitch_curvature_radius(self, theta) -> np.ndarray:
        """Signed radius of curvature of the pitch curve [m] (> 0 where the curve is convex)."""
        _, d1, d2 = self.pitch_curve(theta)
        cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
        return -np.hypot(d1[:, 0], d1[:, 1]) ** 3 / cross  # the pitch curve runs clockwise

    def profile(self, theta) -> np.ndarray:
        """The cam's working surface (n, 2) [m]: the pitch curve moved by the roller radius
        along its inward normal."""
        p, d1, _ = self.pitch_curve(theta)
        n = np.column_stack([-d1[:, 1], d1[:, 0]]) / np.hypot(d1[:, 0], d1[:, 1])[:, None]
        inward = np.where((np.sum(n * p, axis=1) > 0)[:, None], -n, n)
        return p + self.roller_radius * inward

    def undercut(self, theta) -> np.ndarray:
        """True where the roller is larger than the pitch curve's convex radius of curvature:
        the profile would cross itself (undercutting)."""
        rho = self.pitch_curvature_radius(theta)
        return (rho > 0) & (rho < self.roller_radius)


def min_base_radius(program: Program, max_pressure_angle: float, roller_radius: float = 0.0,
                    offset: float = 0.0, samples: int = 4096) -> float:
    """The smallest base circle [m] whose pressure angle stays within ±max_pressure_angle [rad]
    over the program (bisection; the largest |α| falls as the base circle grows)."""
    theta = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)

    def worst(rb):
        return float(np.abs(TranslatingCam(program, rb, roller_radius, offset).pressure_angle(theta)).max())

    lo = max(abs(offset) - roller_radius, 0.0) + 1e-12
    hi = max(2 * lo, program.stroke, 1e-3)
    while worst(hi) > max_pressure_angle:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if worst(mid) > max_pressure_angle:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-12 * hi:
            break
    return hi


__all__ = ["TranslatingCam", "min_base_radius"]
