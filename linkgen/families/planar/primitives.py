"""Vectorised planar primitives carrying closed-form first, second and third transfer functions.

Every quantity is a quadruple (value, d/dφ, d²/dφ², d³/dφ³) over an array of crank angles φ:
points and vectors have shape (n, 2), angles and scalars shape (n,). The derivative
formulas come from differentiating each constraint three times (the method of the closed-form
Assur-group formulas, written in vector form); finite differences appear only in the tests.

Layout, for speed: (n, 2) arrays are column-major (``x[:, 0]`` and ``x[:, 1]`` are
contiguous), so per-component arithmetic and (n, 1)·(n, 2) products run on contiguous
memory. Quantities constant along φ (fixed points, their zero derivatives, the crank's
dφ/dφ = 1) are zero-stride broadcast views: no memory, and products with them are skipped.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np


def pair(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Column-major (n, 2) array from components x, y (n,)."""
    out = np.empty((2, x.shape[0])).T
    out[:, 0] = x
    out[:, 1] = y
    return out


def constant_along(a: np.ndarray) -> bool:
    """True for a zero-stride view: the same value at every crank angle by construction."""
    return a.ndim > 0 and a.strides[0] == 0


@functools.lru_cache(maxsize=64)
def zeros(n: int, *tail: int) -> np.ndarray:
    """A read-only zero array (n, *tail) that takes no memory (one shared view per shape)."""
    return np.broadcast_to(np.zeros(tail), (n, *tail))


def is_zero(a: np.ndarray) -> bool:
    """True for an array known to be zero at every angle (a zero-stride view of zeros)."""
    if a.strides[0] != 0:
        return False
    row = a[0]
    return not (row.any() if row.ndim else row)


def _sum(*terms: np.ndarray) -> np.ndarray:
    """The sum of the terms, skipping those known to be zero."""
    live = [t for t in terms if not is_zero(t)]
    if not live:
        return terms[0]
    out = live[0]
    if len(live) > 1:
        out = out + live[1]  # a new array: the further terms are added in place
        for t in live[2:]:
            out += t
    return out


def _minus(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a if is_zero(b) else -b if is_zero(a) else a - b


def scale(c: np.ndarray, v: np.ndarray) -> np.ndarray:
    """c (n,) times v (n, 2), with no work where either is constant along φ."""
    if constant_along(c):
        k = float(c[0])
        return zeros(v.shape[0], 2) if k == 0.0 or is_zero(v) else v if k == 1.0 else k * v
    return zeros(v.shape[0], 2) if is_zero(v) else c[:, None] * v


def _ks(k: float, c: np.ndarray, v: np.ndarray) -> np.ndarray:
    """k·c·v for a number k, c (n,) and v (n, 2), with no work where v is known to be zero."""
    return zeros(v.shape[0], 2) if is_zero(v) else scale(k * c, v)


@dataclass(frozen=True, slots=True)
class Vec:
    """A point or vector and its first, second and third transfer functions, each (n, 2) [m]."""

    p: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray

    def __add__(self, o: "Vec") -> "Vec":
        return Vec(self.p + o.p, _sum(self.d1, o.d1), _sum(self.d2, o.d2), _sum(self.d3, o.d3))

    def __sub__(self, o: "Vec") -> "Vec":
        return Vec(self.p - o.p, _minus(self.d1, o.d1), _minus(self.d2, o.d2), _minus(self.d3, o.d3))


@dataclass(frozen=True, slots=True)
class Scalar:
    """An angle [rad] or a length [m] and its transfer functions, each (n,).

    ``cos_sin()`` caches cos and sin of the value: a link's angle turns many local vectors.
    """

    v: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    cs: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False, compare=False)

    def shifted(self, c: float) -> "Scalar":
        if c == 0.0:
            return self
        cs = None
        if self.cs is not None:  # cos(v + c), sin(v + c) from the cached pair: no new trigonometry
            cc, sc = math.cos(c), math.sin(c)
            cs = (self.cs[0] * cc - self.cs[1] * sc, self.cs[1] * cc + self.cs[0] * sc)
        return Scalar(self.v + c, self.d1, self.d2, self.d3, cs)

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
    return pair(-a[:, 1], a[:, 0])


def col(x: np.ndarray) -> np.ndarray:
    return x[..., None]


def rotvec(theta: Scalar, w: np.ndarray) -> Vec:
    """R(θ)·w for a constant local vector w (2,): a vector turning with a link. With v = R(θ)w
    and J the quarter turn, v′ = θ′Jv, v″ = θ″Jv − θ′²v, v‴ = (θ‴ − θ′³)Jv − 3θ′θ″v."""
    n = theta.v.shape[0]
    if w[0] == 0.0 and w[1] == 0.0:
        zero = zeros(n, 2)
        return Vec(zero, zero, zero, zero)
    c, s = theta.cos_sin()
    if w[1] == 0.0:
        v = pair(c * w[0], s * w[0])
    else:
        v = pair(c * w[0] - s * w[1], s * w[0] + c * w[1])
    pv = perp(v)
    t1, t2, t3 = theta.d1, theta.d2, theta.d3
    if constant_along(t1) and is_zero(t2) and is_zero(t3):  # θ′ = k along φ: a crank, a gear planet
        k = float(t1[0])
        if k == 0.0:
            zero = zeros(n, 2)
            return Vec(v, zero, zero, zero)
        return Vec(v, pv if k == 1.0 else k * pv, -v if k * k == 1.0 else (-k * k) * v,
                   -pv if k == 1.0 else (-k * k * k) * pv)
    t1sq = t1 * t1
    c3 = -(t1sq * t1) if is_zero(t3) else t3 - t1sq * t1
    if is_zero(t2):
        d3 = scale(c3, pv)
    else:  # c3·Jv − c2·v by components
        c2 = 3.0 * t1 * t2
        d3 = pair(-c3 * v[:, 1] - c2 * v[:, 0], c3 * v[:, 0] - c2 * v[:, 1])
    return Vec(v, scale(t1, pv), _minus(scale(t2, pv), scale(t1sq, v)), d3)


def constant(p: np.ndarray, n: int) -> Vec:
    """A fixed point (2,) broadcast to n angles."""
    zero = zeros(n, 2)
    return Vec(np.broadcast_to(np.asarray(p, dtype=float), (n, 2)), zero, zero, zero)


def angle_between_points(a: Vec, b: Vec) -> Scalar:
    """Direction angle θ of e = b - a [rad] and its transfer functions (|b - a| need not be fixed
    along φ for the angle, but the formulas assume it is, as on a rigid link: then
    θ′ = e×e′/|e|², θ″ = e×e″/|e|², θ‴ = (e×e‴ + e′×e″)/|e|² = e×e‴/|e|² + θ′³, as
    e′ = θ′Je and e″ = θ″Je − θ′²e). Caches the angle's cos and sin, (b - a)/|b - a|."""
    e = b - a
    l2 = dot(e.p, e.p)
    inv = 1.0 / np.sqrt(l2)
    inv2 = inv * inv
    cs = (e.p[:, 0] * inv, e.p[:, 1] * inv)
    d1 = cross(e.p, e.d1) * inv2
    return Scalar(np.arctan2(e.p[:, 1], e.p[:, 0]), d1, cross(e.p, e.d2) * inv2,
                  _cross(e.p, e.d3) * inv2 + d1 * d1 * d1, cs)


def _sq(v: np.ndarray) -> np.ndarray | float:
    return 0.0 if is_zero(v) else dot(v, v)


def _dot(r: np.ndarray, v: np.ndarray) -> np.ndarray | float:
    return 0.0 if is_zero(v) else dot(r, v)


def _cross(r: np.ndarray, v: np.ndarray) -> np.ndarray | float:
    return 0.0 if is_zero(v) else cross(r, v)


def circle_circle(a: Vec, ra, c: Vec, rc: float, m: int) -> Result:
    """Point B with |B - A| = ra and |B - C| = rc (RRR). m = +1 puts B left of A→C.

    Differentiating (B - A)·(B - A) = ra² three times, with r = B - A:
    r·r′ = 0, r·r″ + r′·r′ = 0, r·r‴ + 3r′·r″ = 0; the same for C. Each order is one 2×2
    system in B′, B″, B‴ with the rows B - A and B - C. ``ra`` may be a Scalar, a side that
    changes along the input (an actuator's, set by its stroke): its rows then gain ra·ra′,
    ra·ra″ + ra′² and ra·ra‴ + 3ra′·ra″ on the right."""
    if isinstance(ra, Scalar):
        grow = (ra.v * ra.d1, ra.v * ra.d2 + ra.d1 * ra.d1, ra.v * ra.d3 + 3.0 * ra.d1 * ra.d2)
        ra = ra.v
    else:
        grow = (0.0, 0.0, 0.0)
    d = c.p - a.p
    dd = dot(d, d)
    inv = 1.0 / np.sqrt(dd)
    along = (dd + (ra * ra - rc * rc)) * (0.5 * inv)
    h2 = ra * ra - along * along
    # NaN (overflowed inputs) is not a failure to assemble: it shows as a non-finite denominator
    fail = (h2 < 0.0) | (dd == 0.0)  # coincident centres: no circle crossing (or all of them)
    h = np.sqrt(np.where(fail, 0.0, h2))
    ka, kh = along * inv, (m * inv) * h
    b = pair(a.p[:, 0] + ka * d[:, 0] - kh * d[:, 1], a.p[:, 1] + ka * d[:, 1] + kh * d[:, 0])
    ba, bc = b - a.p, b - c.p
    det = cross(ba, bc)
    inv_det = 1.0 / det
    b1 = _solve2(ba, bc, _dot(ba, a.d1) + grow[0], _dot(bc, c.d1), inv_det)
    r1a, r1c = _minus(b1, a.d1), _minus(b1, c.d1)
    b2 = _solve2(ba, bc, _dot(ba, a.d2) - _sq(r1a) + grow[1], _dot(bc, c.d2) - _sq(r1c), inv_det)
    r2a, r2c = _minus(b2, a.d2), _minus(b2, c.d2)
    b3 = _solve2(ba, bc, _dot(ba, a.d3) - 3.0 * dot(r1a, r2a) + grow[2], _dot(bc, c.d3) - 3.0 * dot(r1c, r2c),
                 inv_det)
    return Result(Vec(b, b1, b2, b3), fail, det * (1.0 / (ra * rc)))


def _solve2(r1: np.ndarray, r2: np.ndarray, y1, y2, inv_det: np.ndarray) -> np.ndarray:
    """Solve [r1ᵀ; r2ᵀ]·x = [y1; y2] for x (n, 2) by Cramer's rule, given 1/det."""
    return pair((y1 * r2[:, 1] - y2 * r1[:, 1]) * inv_det, (r1[:, 0] * y2 - r2[:, 0] * y1) * inv_det)


def line_circle(line: Line, a: Vec, r: float, m: int) -> Result:
    """Point B on ``line`` with |B - A| = r (RRP). m = +1 takes the larger line parameter.

    B = Q + s·u; differentiating w·w = r² (w = B - A) three times: w·w′ = 0,
    w·w″ + w′·w′ = 0, w·w‴ + 3w′·w″ = 0, where w⁽ᵏ⁾ holds s⁽ᵏ⁾·u plus known terms
    (Leibniz: B‴ = Q‴ + s‴u + 3s″u′ + 3s′u″ + s·u‴); each is solved for s⁽ᵏ⁾ over w·u."""
    q, u = line.base, line.u
    qa = q.p - a.p
    b_ = dot(u.p, qa)
    disc = b_ * b_ - (dot(qa, qa) - r * r)
    fail = disc < 0.0  # NaN (overflowed inputs) shows as a non-finite denominator instead
    s = m * np.sqrt(np.where(fail, 0.0, disc)) - b_
    bp = q.p + col(s) * u.p
    w = bp - a.p
    den = dot(w, u.p)
    inv = 1.0 / den
    t1 = _sum(q.d1, scale(s, u.d1))  # B′ without its s′·u term
    s1 = -_dot(w, _minus(t1, a.d1)) * inv
    b1 = _sum(t1, col(s1) * u.p)
    r1 = _minus(b1, a.d1)
    t2 = _sum(q.d2, _ks(2.0, s1, u.d1), scale(s, u.d2))
    s2 = -(_dot(w, _minus(t2, a.d2)) + dot(r1, r1)) * inv
    b2 = _sum(t2, col(s2) * u.p)
    r2 = _minus(b2, a.d2)
    t3 = _sum(q.d3, _ks(3.0, s2, u.d1), _ks(3.0, s1, u.d2), scale(s, u.d3))
    s3 = -(_dot(w, _minus(t3, a.d3)) + 3.0 * dot(r1, r2)) * inv
    b3 = _sum(t3, col(s3) * u.p)
    return Result(Vec(bp, b1, b2, b3), fail, den * (1.0 / r))


def pivot_line(ps: Vec, pg: Vec, k: float, m: int) -> Result:
    """Direction ψ of a line through PG that passes at signed distance k from PS:
    cross(e(ψ), PS - PG) = k (RPR, the coulisse). m = +1 points the line towards PS.

    With d = PS - PG, D = e·d and e′ = ψ′Je (so (e·d)′ = ψ′k + e·d′, (e×d′)′ = e×d″ - ψ′e·d′),
    differentiating e×d = k three times gives ψ′D = e×d′, ψ″D = e×d″ - 2ψ′e·d′ - kψ′², and
    ψ‴D = e×d‴ - 3ψ′e·d″ - 3ψ″e·d′ - 3kψ′ψ″ - 2ψ′³D."""
    d = ps - pg
    dist = np.sqrt(dot(d.p, d.p))
    ratio = k / dist
    fail = (np.abs(ratio) > 1.0) | (dist == 0.0)  # NaN from overflow: a non-finite denominator
    asin = np.arcsin(np.clip(ratio, -1.0, 1.0))
    alpha = np.arctan2(d.p[:, 1], d.p[:, 0])
    psi = alpha - asin if m > 0 else alpha - np.pi + asin
    cs = (np.cos(psi), np.sin(psi))
    e = pair(*cs)
    den = dot(e, d.p)
    inv = 1.0 / den
    psi1 = cross(e, d.d1) * inv
    ed1 = dot(e, d.d1)
    psi2 = (cross(e, d.d2) - 2.0 * ed1 * psi1 - k * psi1**2) * inv
    psi3 = ((_cross(e, d.d3) - 3.0 * (psi1 * _dot(e, d.d2) + psi2 * (ed1 + k * psi1))) * inv
            - 2.0 * (psi1 * psi1 * psi1))  # not psi1**3: NumPy's pow is several times slower
    return Result(Scalar(psi, psi1, psi2, psi3, cs), fail, den / dist)


def line_line(l1: Line, l2: Line) -> Result:
    """Intersection of two moving lines (PRP, RPP). Unique; singular when parallel.

    Q1 + s1·u1 = Q2 + s2·u2; its k-th derivative reads s1⁽ᵏ⁾u1 - s2⁽ᵏ⁾u2 = r_k, the known
    Leibniz terms (r3 = [Q2‴ + 3s2″u2′ + 3s2′u2″ + s2·u2‴] - [the same for line 1]); crossing
    with u2 and u1 gives s1⁽ᵏ⁾ and s2⁽ᵏ⁾ over u1×u2."""
    q1, u1, q2, u2 = l1.base, l1.u, l2.base, l2.u
    det = cross(u1.p, u2.p)
    inv = 1.0 / det
    r0 = q2.p - q1.p
    s1 = cross(r0, u2.p) * inv
    s2 = cross(r0, u1.p) * inv
    r1 = _minus(_sum(q2.d1, scale(s2, u2.d1)), _sum(q1.d1, scale(s1, u1.d1)))
    s1d = cross(r1, u2.p) * inv
    s2d = cross(r1, u1.p) * inv
    t2 = _sum(q1.d2, _ks(2.0, s1d, u1.d1), scale(s1, u1.d2))  # B″ without its s1″·u1 term
    r2 = _minus(_sum(q2.d2, _ks(2.0, s2d, u2.d1), scale(s2, u2.d2)), t2)
    s1dd = cross(r2, u2.p) * inv
    s2dd = zeros(det.shape[0]) if is_zero(u2.d1) else cross(r2, u1.p) * inv
    t3 = _sum(q1.d3, _ks(3.0, s1dd, u1.d1), _ks(3.0, s1d, u1.d2), scale(s1, u1.d3))
    r3 = _minus(_sum(q2.d3, _ks(3.0, s2dd, u2.d1), _ks(3.0, s2d, u2.d2), scale(s2, u2.d3)), t3)
    s1ddd = cross(r3, u2.p) * inv
    b = q1.p + col(s1) * u1.p
    b1 = _sum(q1.d1, col(s1d) * u1.p, scale(s1, u1.d1))
    b2 = _sum(t2, col(s1dd) * u1.p)
    b3 = _sum(t3, col(s1ddd) * u1.p)
    return Result(Vec(b, b1, b2, b3), np.zeros(det.shape, dtype=bool), det)
