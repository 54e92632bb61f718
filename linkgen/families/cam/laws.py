"""Cam motion programs: rise–dwell–return–dwell segments with the classical laws, as follower
displacement s(θ) [m] and its derivatives with respect to the cam angle θ [rad] (s′, s″, s‴);
the time derivatives follow as v = s′·ω, a = s″·ω² + s′·ε, j = s‴·ω³ (+ terms in ε, ε̇).

Each law is a rise of height h over a span β, in x = (θ − θ0)/β ∈ [0, 1]:
    harmonic:   s = h/2·(1 − cos πx)
    cycloidal:  s = h·(x − sin 2πx / 2π)
    poly345:    s = h·(10x³ − 15x⁴ + 6x⁵)
A return is the rise mirrored (h − s of the same law); a dwell keeps s. Angles are radians, the
cam angle is measured from the program's start and taken modulo the sum of the spans (2π).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

LAWS = ("harmonic", "cycloidal", "poly345", "modtrap")
KINDS = ("rise", "dwell", "return")


def rise(law: str, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A unit rise over a unit span: s and its first three derivatives in x, each like x."""
    x = np.asarray(x, dtype=float)
    if law == "harmonic":
        p = math.pi
        return (0.5 * (1 - np.cos(p * x)), 0.5 * p * np.sin(p * x), 0.5 * p * p * np.cos(p * x),
                -0.5 * p**3 * np.sin(p * x))
    if law == "cycloidal":
        p = 2 * math.pi
        return x - np.sin(p * x) / p, 1 - np.cos(p * x), p * np.sin(p * x), p * p * np.cos(p * x)
    if law == "modtrap":
        return _modtrap(x)
    if law == "poly345":
        return (10 * x**3 - 15 * x**4 + 6 * x**5, 30 * x**2 - 60 * x**3 + 30 * x**4,
                60 * x - 180 * x**2 + 120 * x**3, 60 - 360 * x + 360 * x**2)
    raise ValueError(f"unknown law {law!r}; known: {LAWS}")


_W = 4 * math.pi  # the modified trapezoid's sine ramps last 1/8 of the span


def _modtrap_piece(k: int, u, s0: float, v0: float, a: float):
    """Piece k (0..4) of the modified trapezoid at u = x − its start, from s0, v0, peak acceleration a."""
    w = _W
    if k == 0:  # a·sin(wu): the ramp up
        return (s0 + v0 * u + a * (u / w - np.sin(w * u) / w**2), v0 + a * (1 - np.cos(w * u)) / w,
                a * np.sin(w * u), a * w * np.cos(w * u))
    if k in (1, 3):  # constant ±a
        c = a if k == 1 else -a
        return s0 + v0 * u + 0.5 * c * u * u, v0 + c * u, c + 0 * u, 0 * u
    sign = 1.0 if k == 2 else -1.0  # k = 2: a·cos(wu) from +a to −a; k = 4: −a·cos(wu) from −a to 0
    return (s0 + v0 * u + sign * a * (1 - np.cos(w * u)) / w**2, v0 + sign * a * np.sin(w * u) / w,
            sign * a * np.cos(w * u), -sign * a * w * np.sin(w * u))


_MT_EDGES = (0.0, 0.125, 0.375, 0.625, 0.875, 1.0)


def _modtrap_starts(a: float) -> list[tuple[float, float]]:
    out, s0, v0 = [], 0.0, 0.0
    for k in range(5):
        out.append((s0, v0))
        s0, v0, _, _ = (float(x) for x in _modtrap_piece(k, np.float64(_MT_EDGES[k + 1] - _MT_EDGES[k]), s0, v0, a))
    return out + [(s0, v0)]


# The peak acceleration of a unit rise over a unit span (4.888…): the one that ends the rise at 1.
_MT_PEAK = 1.0 / _modtrap_starts(1.0)[-1][0]
_MT_STARTS = _modtrap_starts(_MT_PEAK)


def _modtrap(x: np.ndarray):
    """The modified trapezoidal law: acceleration a sine ramp over the first eighth, constant over
    the next quarter, a cosine through zero over the middle quarter, then the mirror image."""
    out = [np.zeros_like(x) for _ in range(4)]
    for k in range(5):
        lo, hi = _MT_EDGES[k], _MT_EDGES[k + 1]
        inside = (x >= lo) & ((x < hi) if k < 4 else (x <= hi))
        s0, v0 = _MT_STARTS[k]
        for i, val in enumerate(_modtrap_piece(k, x[inside] - lo, s0, v0, _MT_PEAK)):
            out[i][inside] = val
    return tuple(out)


@dataclass(frozen=True)
class Segment:
    """One part of the program: ``kind`` rise/dwell/return, its ``law`` (not for a dwell), the
    cam angle it spans [rad] and, for a rise or return, its height [m]."""

    kind: str
    span: float
    law: str = ""
    height: float = 0.0


@dataclass(frozen=True)
class Program:
    """Segments in order; their spans add up to one turn."""

    segments: tuple[Segment, ...]

    def __post_init__(self):
        total = sum(s.span for s in self.segments)
        if abs(total - 2 * math.pi) > 1e-9:
            raise ValueError(f"the segments span {math.degrees(total):.6g}°, not 360°")
        for s in self.segments:
            if s.kind not in KINDS or not s.span > 0 or (s.kind != "dwell" and s.law not in LAWS):
                raise ValueError(f"bad segment {s}")

    @property
    def stroke(self) -> float:
        """The largest displacement [m] over the program."""
        return float(self.displacement(np.linspace(0, 2 * math.pi, 4097))[0].max())

    @property
    def lowest(self) -> float:
        """The lowest displacement (a rise–dwell–return program starts at its lowest, 0)."""
        return 0.0

    def displacement(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """s [m], ds/dθ [m/rad], d²s/dθ² [m/rad²], d³s/dθ³ [m/rad³] at cam angles θ (n,)."""
        th = np.mod(np.asarray(theta, dtype=float), 2 * math.pi)
        out = [np.zeros_like(th) for _ in range(4)]
        start, level = 0.0, 0.0
        for seg in self.segments:
            inside = (th >= start) & (th < start + seg.span)
            if seg.kind == "dwell":
                out[0][inside] = level
            else:
                sign = 1.0 if seg.kind == "rise" else -1.0
                x = (th[inside] - start) / seg.span
                d = rise(seg.law, x)
                for k in range(4):
                    out[k][inside] = sign * seg.height * d[k] / seg.span**k
                out[0][inside] += level
                level += sign * seg.height
            start += seg.span
        return tuple(out)


def motion(program: Program, theta, omega: float, epsilon: float = 0.0):
    """Follower displacement [m], velocity [m/s], acceleration [m/s²] and jerk [m/s³] at cam
    angles θ, cam speed ω [rad/s] and constant cam acceleration ε [rad/s²]."""
    s, s1, s2, s3 = program.displacement(theta)
    return s, s1 * omega, s2 * omega**2 + s1 * epsilon, s3 * omega**3 + 3 * s2 * omega * epsilon




@dataclass(frozen=True)
class SineProgram:
    """A law given as a function over the whole turn: y = mean + amplitude·sin(θ + phase) (the
    textbook's h = h_max·sin φ), with the same ``displacement`` interface as ``Program``
    (y in m for a translating follower, rad for an oscillating one)."""

    amplitude: float
    mean: float = 0.0
    phase: float = 0.0

    @property
    def stroke(self) -> float:
        """The largest displacement above the lowest position."""
        return 2.0 * abs(self.amplitude)

    def displacement(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        x = np.asarray(theta, dtype=float) + self.phase
        a, s, c = self.amplitude, np.sin(x), np.cos(x)
        return self.mean + a * s, a * c, -a * s, -a * c

    @property
    def lowest(self) -> float:
        return self.mean - abs(self.amplitude)


__all__ = ["KINDS", "LAWS", "Program", "Segment", "SineProgram", "motion", "rise"]
