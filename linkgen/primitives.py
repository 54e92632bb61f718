"""Vectorised planar primitives carrying closed-form first and second transfer functions.

Every quantity is a triple (value, d/dφ, d²/dφ²) over an array of crank angles φ:
points and vectors have shape (n, 2), angles and scalars shape (n,). The derivative
formulas come from differentiating each constraint twice (seed 000's method written in
vector form); finite differences appear only in the tests.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True, slots=True)
class Vec:
    """A point or vector and its first and second transfer functions, each (n, 2) [m]."""

    p: np.ndarray
    d1: np.ndarray
    d2: np.ndarray

    def __add__(self, o: "Vec") -> "Vec":
        return Vec(self.p + o.p, self.d1 + o.d1, self.d2 + o.d2)

    def __sub__(self, o: "Vec") -> "Vec":
        return Vec(self.p - o.p, self.d1 - o.d1, self.d2 - o.d2)


@dataclass(frozen=True, slots=True)
class Scalar:
    """An angle [rad] or a length [m] and its transfer functions, each (n,).

    ``cos_sin()`` caches cos and sin of the value: a link's angle turns many local vectors.
    """

    v: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    cs: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False, compare=False)

    def shifted(self, c: float) -> "Scalar":
        cs = None
        if self.cs is not None:  # cos(v + c), sin(v + c) from the cached pair: no new trigonometry
            cc, sc = math.cos(c), math.sin(c)
            cs = (self.cs[0] * cc - self.cs[1] * sc, self.cs[1] * cc + self.cs[0] * sc)
        return Scalar(self.v + c, self.d1, self.d2, cs)

    def cos_sin(self) -> tuple[np.ndarray, np.ndarray]:
        if self.cs is None:
            object.__setattr__(self, "cs", (np.cos(self.v), np.sin(self.v)))
        return self.cs


@dataclass(frozen=True, slots=True)
class Line:
    """A moving line: a base point and a unit direction, both Vec."""

    base: Vec
    u: Vec


@dataclass(frozen=True, slots=True)
class Result:
    """A primitive's output: the solved quantity, where it failed, its normalised
    transfer-function denominator (a sine or cosine of a transmission angle; 0 = singular)."""

    value: object
    fail: np.ndarray
    denominator: np.ndarray


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def perp(a: np.ndarray) -> np.ndarray:
    """a rotated by +90°."""
    return np.stack((-a[..., 1], a[..., 0]), axis=-1)


def col(x: np.ndarray) -> np.ndarray:
    return x[..., None]


def rotvec(theta: Scalar, w: np.ndarray) -> Vec:
    """R(θ)·w for a constant local vector w (2,): a vector turning with a link."""
    n = theta.v.shape[0]
    if w[0] == 0.0 and w[1] == 0.0:
        zero = np.zeros((n, 2))
        return Vec(zero, zero, zero)
    c, s = theta.cos_sin()
    v = np.empty((n, 2))
    if w[1] == 0.0:
        np.multiply(c, w[0], out=v[:, 0])
        np.multiply(s, w[0], out=v[:, 1])
    else:
        v[:, 0] = c * w[0] - s * w[1]
        v[:, 1] = s * w[0] + c * w[1]
    pv = perp(v)
    return Vec(v, col(theta.d1) * pv, col(theta.d2) * pv - col(theta.d1**2) * v)


def constant(p: np.ndarray, n: int) -> Vec:
    """A fixed point (2,) broadcast to n angles."""
    pts = np.broadcast_to(np.asarray(p, dtype=float), (n, 2))
    zero = np.zeros((n, 2))
    return Vec(pts, zero, zero)


def angle_between_points(a: Vec, b: Vec) -> Scalar:
    """Direction angle of b - a [rad] and its transfer functions (|b - a| need not be fixed
    along φ for the angle, but the formulas assume it is, as on a rigid link)."""
    e = b - a
    l2 = dot(e.p, e.p)
    return Scalar(np.arctan2(e.p[:, 1], e.p[:, 0]), cross(e.p, e.d1) / l2, cross(e.p, e.d2) / l2)


def circle_circle(a: Vec, ra: float, c: Vec, rc: float, m: int) -> Result:
    """Point B with |B - A| = ra and |B - C| = rc (RRR). m = +1 puts B left of A→C."""
    d = c.p - a.p
    dd = dot(d, d)
    dist = np.sqrt(dd)
    along = (ra * ra - rc * rc + dd) / (2.0 * dist)
    h2 = ra * ra - along * along
    fail = ~(h2 >= 0.0)
    h = np.sqrt(np.where(fail, 0.0, h2))
    b = a.p + col(along / dist) * d + col(m * h / dist) * perp(d)
    ba, bc = b - a.p, b - c.p
    det = cross(ba, bc)
    b1 = _solve2(ba, bc, dot(ba, a.d1), dot(bc, c.d1), det)
    r1a, r1c = b1 - a.d1, b1 - c.d1
    b2 = _solve2(ba, bc, dot(ba, a.d2) - dot(r1a, r1a), dot(bc, c.d2) - dot(r1c, r1c), det)
    return Result(Vec(b, b1, b2), fail, det / (ra * rc))


def _solve2(r1: np.ndarray, r2: np.ndarray, y1: np.ndarray, y2: np.ndarray, det: np.ndarray) -> np.ndarray:
    """Solve [r1ᵀ; r2ᵀ]·x = [y1; y2] for x (n, 2) by Cramer's rule."""
    x = (y1 * r2[:, 1] - y2 * r1[:, 1]) / det
    y = (r1[:, 0] * y2 - r2[:, 0] * y1) / det
    return np.stack((x, y), axis=-1)


def line_circle(line: Line, a: Vec, r: float, m: int) -> Result:
    """Point B on ``line`` with |B - A| = r (RRP). m = +1 takes the larger line parameter."""
    q, u = line.base, line.u
    qa = q.p - a.p
    b_ = dot(u.p, qa)
    disc = b_ * b_ - (dot(qa, qa) - r * r)
    fail = ~(disc >= 0.0)
    s = -b_ + m * np.sqrt(np.where(fail, 0.0, disc))
    bp = q.p + col(s) * u.p
    w = bp - a.p
    den = dot(w, u.p)
    s1 = -dot(w, q.d1 + col(s) * u.d1 - a.d1) / den
    b1 = q.d1 + col(s1) * u.p + col(s) * u.d1
    r1 = b1 - a.d1
    s2 = -(dot(w, q.d2 + 2.0 * col(s1) * u.d1 + col(s) * u.d2 - a.d2) + dot(r1, r1)) / den
    b2 = q.d2 + col(s2) * u.p + 2.0 * col(s1) * u.d1 + col(s) * u.d2
    return Result(Vec(bp, b1, b2), fail, den / r)


def pivot_line(ps: Vec, pg: Vec, k: float, m: int) -> Result:
    """Direction ψ of a line through PG that passes at signed distance k from PS:
    cross(e(ψ), PS - PG) = k (RPR, the coulisse). m = +1 points the line towards PS."""
    d = ps - pg
    dist = np.sqrt(dot(d.p, d.p))
    ratio = k / dist
    fail = ~(np.abs(ratio) <= 1.0)
    asin = np.arcsin(np.clip(ratio, -1.0, 1.0))
    alpha = np.arctan2(d.p[:, 1], d.p[:, 0])
    psi = alpha - asin if m > 0 else alpha - np.pi + asin
    e = np.stack((np.cos(psi), np.sin(psi)), axis=-1)
    den = dot(e, d.p)
    psi1 = cross(e, d.d1) / den
    psi2 = (cross(e, d.d2) - 2.0 * dot(e, d.d1) * psi1 - k * psi1**2) / den
    return Result(Scalar(psi, psi1, psi2), fail, den / dist)


def line_line(l1: Line, l2: Line) -> Result:
    """Intersection of two moving lines (PRP, RPP). Unique; singular when parallel."""
    q1, u1, q2, u2 = l1.base, l1.u, l2.base, l2.u
    det = cross(u1.p, u2.p)
    r0 = q2.p - q1.p
    s1 = cross(r0, u2.p) / det
    s2 = cross(r0, u1.p) / det
    r1 = q2.d1 + col(s2) * u2.d1 - q1.d1 - col(s1) * u1.d1
    s1d = cross(r1, u2.p) / det
    s2d = cross(r1, u1.p) / det
    r2 = (q2.d2 + 2.0 * col(s2d) * u2.d1 + col(s2) * u2.d2) - (q1.d2 + 2.0 * col(s1d) * u1.d1 + col(s1) * u1.d2)
    s1dd = cross(r2, u2.p) / det
    b = q1.p + col(s1) * u1.p
    b1 = q1.d1 + col(s1d) * u1.p + col(s1) * u1.d1
    b2 = q1.d2 + col(s1dd) * u1.p + 2.0 * col(s1d) * u1.d1 + col(s1) * u1.d2
    return Result(Vec(b, b1, b2), np.zeros(det.shape, dtype=bool), det)
