"""A disc cam and its follower by inversion, for a translating or an oscillating roller follower
(a knife edge is a roller of radius 0).

Fixed frame: the cam turns counter-clockwise about the origin by the cam angle θ [rad].
    translating: the roller centre moves along +y on the line x = e (the offset):
        C(θ) = (e, d + s(θ)), d = √((r_b + r_r)² − e²);
    oscillating: the arm of length l turns about the pivot O1 = (a, 0); ψ is the angle at O1
        from O1→O to the arm, on the +y side: C(θ) = (a − l·cos ψ, l·sin ψ), ψ = ψ0 + s(θ)
        with ψ0 from the base circle (|C| = r_b + r_r where s = 0 is the program's lowest).
In the cam's frame the roller centre traces the pitch curve P(θ) = R(−θ)·C(θ); the cam's
profile is the pitch curve moved inwards by r_r. The contact normal in the fixed frame is
n ∝ perp(C′ − J·C) (J: a quarter turn), and the pressure angle α is the angle between n and
the direction the follower's roller centre moves (u ∝ dC/ds)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def _perp(v: np.ndarray) -> np.ndarray:
    return np.column_stack([-v[:, 1], v[:, 0]])


@dataclass(frozen=True)
class Follower:
    """``kind`` "translating" (``offset`` e [m]) or "oscillating" (``pivot_distance`` a [m],
    ``arm_length`` l [m]); ``roller_radius`` r_r [m]; the cam's ``base_radius`` r_b [m] and the
    motion ``program`` (``cams.laws``: s in m, or ψ − ψ0 in rad)."""

    kind: str
    program: object
    base_radius: float
    roller_radius: float = 0.0
    offset: float = 0.0
    pivot_distance: float = 0.0
    arm_length: float = 0.0
    face: str = "roller"  # "roller" (a knife edge is a roller of radius 0) or "flat" (translating only)

    @property
    def flat(self) -> bool:
        return self.face == "flat"

    @property
    def prime_radius(self) -> float:
        return self.base_radius + self.roller_radius

    @property
    def lift_origin(self) -> float:
        """Translating: d [m], the roller centre's height at the lowest position (a flat face's
        height, r_b)."""
        if self.flat:
            return self.base_radius
        r0 = self.prime_radius
        if abs(self.offset) >= r0:
            raise ValueError(f"the offset {self.offset:g} m must be below base + roller radius {r0:g} m")
        return math.sqrt(r0 * r0 - self.offset**2)

    @property
    def psi0(self) -> float:
        """Oscillating: ψ at the lowest position [rad] (law of cosines in O, O1, C)."""
        a, l, r0 = self.pivot_distance, self.arm_length, self.prime_radius
        c = (a * a + l * l - r0 * r0) / (2 * a * l)
        if not -1.0 < c < 1.0:
            raise ValueError(f"an arm of {l:g} m about a pivot {a:g} m away cannot reach the base circle of "
                             f"{r0:g} m (base + roller radius)")
        return math.acos(c)

    def output(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The follower's coordinate measured from its lowest position (m, or rad) and its first
        three derivatives in θ, each (n,)."""
        y = self.program.displacement(theta)
        return (y[0] - self.program.lowest, y[1], y[2], y[3])

    def centre(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Roller centre C (n, 2) [m] in the fixed frame with dC/dθ, d²C/dθ², and the unit
        direction u (n, 2) in which it moves as the follower rises."""
        q, q1, q2, q3 = self.output(theta)
        if self.flat:  # the contact point on the face: x = ds/dθ (the envelope of the face's lines)
            n = q.shape[0]
            c = np.column_stack([q1, self.base_radius + q])
            return c, np.column_stack([q2, q1]), np.column_stack([q3, q2]), np.column_stack([np.zeros(n), np.ones(n)])
        if self.kind == "translating":
            n = q.shape[0]
            c = np.column_stack([np.full(n, self.offset), self.lift_origin + q])
            c1 = np.column_stack([np.zeros(n), q1])
            c2 = np.column_stack([np.zeros(n), q2])
            u = np.column_stack([np.zeros(n), np.ones(n)])
            return c, c1, c2, u
        a, l = self.pivot_distance, self.arm_length
        psi = self.psi0 + q
        cs, sn = np.cos(psi), np.sin(psi)
        c = np.column_stack([a - l * cs, l * sn])
        d = np.column_stack([l * sn, l * cs])  # dC/dψ
        dd = np.column_stack([l * cs, -l * sn])  # d²C/dψ²
        c1 = d * q1[:, None]
        c2 = dd * (q1 * q1)[:, None] + d * q2[:, None]
        return c, c1, c2, d / l

    def pitch_curve(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """P (n, 2) [m] in the cam's frame with dP/dθ and d²P/dθ²."""
        th = np.asarray(theta, dtype=float)
        c, c1, c2, _ = self.centre(th)
        cs, sn = np.cos(th)[:, None], np.sin(th)[:, None]

        def rot(v):  # R(−θ)·v
            return np.column_stack([cs[:, 0] * v[:, 0] + sn[:, 0] * v[:, 1], -sn[:, 0] * v[:, 0] + cs[:, 0] * v[:, 1]])

        w1 = c1 - _perp(c)  # C′ − J·C
        w2 = c2 - 2 * _perp(c1) - c  # d/dθ of R(−θ)(C′ − JC) = R(−θ)(C″ − 2JC′ − C) (J² = −1)
        return rot(c), rot(w1), rot(w2)

    def normal(self, theta) -> np.ndarray:
        """Unit contact normal (n, 2) in the fixed frame, pointing from the cam to the roller."""
        if self.flat:
            return self.centre(theta)[3]
        c, c1, _, _ = self.centre(theta)
        n = _perp(c1 - _perp(c))
        n /= np.hypot(n[:, 0], n[:, 1])[:, None]
        return np.where((np.sum(n * c, axis=1) < 0)[:, None], -n, n)

    def pressure_angle(self, theta) -> np.ndarray:
        """α [rad] between the contact normal and the roller centre's direction of motion, signed
        (positive when the normal leans towards +θ... as the cross product u × n)."""
        _, _, _, u = self.centre(theta)
        n = self.normal(theta)
        return np.arctan2(u[:, 0] * n[:, 1] - u[:, 1] * n[:, 0], np.sum(u * n, axis=1))

    def pitch_curvature_radius(self, theta) -> np.ndarray:
        """Signed radius of curvature of the pitch curve [m] (> 0 where it is convex); for a flat
        face, of the profile itself, r_b + s + s″."""
        if self.flat:
            q, _, q2, _ = self.output(theta)
            return self.base_radius + q + q2
        _, d1, d2 = self.pitch_curve(theta)
        cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
        return -np.hypot(d1[:, 0], d1[:, 1]) ** 3 / cross  # the pitch curve runs clockwise

    def profile(self, theta, radius: float | None = None) -> np.ndarray:
        """The cam's working surface (n, 2) [m] in its own frame; ``radius``: the roller radius
        it is offset by, if not the follower's (MuJoCo gives a knife edge a small roller)."""
        if self.flat:
            return self.pitch_curve(theta)[0]  # the contact point itself
        p, d1, _ = self.pitch_curve(theta)
        n = np.column_stack([-d1[:, 1], d1[:, 0]]) / np.hypot(d1[:, 0], d1[:, 1])[:, None]
        inward = np.where((np.sum(n * p, axis=1) > 0)[:, None], -n, n)
        return p + (self.roller_radius if radius is None else radius) * inward

    def profile_curvature_radius(self, theta) -> np.ndarray:
        """Signed radius of curvature of the profile [m]: the pitch curve's less r_r where convex."""
        return self.pitch_curvature_radius(theta) - self.roller_radius

    def undercut(self, theta) -> np.ndarray:
        """True where the roller is larger than the pitch curve's convex radius of curvature."""
        rho = self.pitch_curvature_radius(theta)
        return (rho > 0) & (rho < self.roller_radius)





def smallest_base_radius(follower: Follower, max_pressure_angle: float, samples: int = 3600) -> float:
    """The smallest base circle [m] for which the follower's pressure angle stays within
    ±max_pressure_angle [rad] over the turn, everything else kept (bisection: the largest |α|
    falls as the base circle grows); the largest |α| of each trial is refined between the
    samples (``linkgen.extrema``)."""
    from dataclasses import replace

    from linkgen.extrema import peak

    theta = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)

    def worst(rb: float) -> float:
        try:
            alpha = replace(follower, base_radius=rb).pressure_angle
            return peak(lambda th: np.abs(alpha(th)), theta, np.abs(alpha(theta)), period=2 * math.pi)[1]
        except ValueError:  # the follower cannot reach a base circle this small
            return math.inf

    hi = max(follower.base_radius, 1e-6)
    while worst(hi) > max_pressure_angle:
        hi *= 2
        if hi > 1e6 * max(follower.base_radius, 1e-6):
            raise ValueError(f"no base circle keeps the pressure angle within {math.degrees(max_pressure_angle):g}°")
    lo = 0.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if worst(mid) > max_pressure_angle:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-12 * hi:
            break
    return hi
__all__ = ["Follower", "smallest_base_radius"]
