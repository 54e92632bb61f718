"""Truncated derivative jets along the crank angle: a quantity and its first three derivatives
d/dφ, d²/dφ², d³/dφ³, carried through the arithmetic of the spatial closure in closed form.

A ``Jet`` holds an array ``d`` of shape (4, n) for a scalar or (4, n, 3) for a vector over n
crank angles; ``d[k]`` is the k-th derivative. Products follow Leibniz's rule and functions of
a jet follow Faà di Bruno's formula to third order, so every derivative is exact (no finite
differences); the tests compare them with central differences.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

ORDER = 3
_BINOMIAL = ((1,), (1, 1), (1, 2, 1), (1, 3, 3, 1))


@dataclass(frozen=True)
class Jet:
    """A scalar (4, n) or vector (4, n, 3) and its first three derivatives along φ."""

    d: np.ndarray

    @property
    def value(self) -> np.ndarray:
        return self.d[0]

    @property
    def is_vector(self) -> bool:
        return self.d.ndim == 3

    def __add__(self, o) -> "Jet":
        return Jet(self.d + _as(o, self).d)

    __radd__ = __add__

    def __sub__(self, o) -> "Jet":
        return Jet(self.d - _as(o, self).d)

    def __rsub__(self, o) -> "Jet":
        return Jet(_as(o, self).d - self.d)

    def __neg__(self) -> "Jet":
        return Jet(-self.d)

    def __mul__(self, o) -> "Jet":
        """Scalar × scalar, scalar × vector (either side), or a jet times a float."""
        if not isinstance(o, Jet):
            return Jet(self.d * float(o))
        return _leibniz(self, o, _times)

    __rmul__ = __mul__

    def __truediv__(self, o) -> "Jet":
        if not isinstance(o, Jet):
            return Jet(self.d / float(o))
        return self * o.reciprocal()

    def reciprocal(self) -> "Jet":
        f = self.d[0]
        return compose(self, 1.0 / f, -1.0 / f**2, 2.0 / f**3, -6.0 / f**4)

    def sqrt(self) -> "Jet":
        s = np.sqrt(self.d[0])
        return compose(self, s, 0.5 / s, -0.25 / s**3, 0.375 / s**5)

    def cos(self) -> "Jet":
        c, s = np.cos(self.d[0]), np.sin(self.d[0])
        return compose(self, c, -s, -c, s)

    def sin(self) -> "Jet":
        c, s = np.cos(self.d[0]), np.sin(self.d[0])
        return compose(self, s, c, -s, -c)

    def dot(self, o) -> "Jet":
        """Dot product of two vectors (or a vector and a constant (3,) vector)."""
        if not isinstance(o, Jet):
            return Jet(self.d @ np.asarray(o, dtype=float))
        return _leibniz(self, o, lambda a, b: np.einsum("...i,...i->...", a, b))

    def cross(self, o) -> "Jet":
        if not isinstance(o, Jet):
            return Jet(np.cross(self.d, np.asarray(o, dtype=float)))
        return _leibniz(self, o, np.cross)

    def norm(self) -> "Jet":
        return self.dot(self).sqrt()

    def unit(self) -> "Jet":
        return self * self.norm().reciprocal()


def _times(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    if a.ndim == b.ndim:
        return a * b
    return a[..., None] * b if a.ndim < b.ndim else a * b[..., None]


def _leibniz(f: Jet, g: Jet, op) -> Jet:
    out = [sum(c * op(f.d[i], g.d[k - i]) for i, c in enumerate(_BINOMIAL[k])) for k in range(ORDER + 1)]
    return Jet(np.stack(out))


def compose(f: Jet, g0, g1, g2, g3) -> Jet:
    """h = g(f) from g and its derivatives at f's value (each (n,)), f a scalar jet."""
    f1, f2, f3 = f.d[1], f.d[2], f.d[3]
    return Jet(np.stack([g0 + 0 * f1, g1 * f1, g2 * f1**2 + g1 * f2, g3 * f1**3 + 3 * g2 * f1 * f2 + g1 * f3]))


def _as(o, like: Jet) -> Jet:
    return o if isinstance(o, Jet) else constant(o, like.d.shape[1])


def constant(value, n: int) -> Jet:
    """A quantity fixed along φ: a float or a (3,) vector, broadcast to n angles."""
    v = np.asarray(value, dtype=float)
    d = np.zeros((ORDER + 1, n) + v.shape)
    d[0] = v
    return Jet(d)


def variable(value: np.ndarray, derivatives=(1.0, 0.0, 0.0)) -> Jet:
    """A scalar with the given value (n,) and derivatives (each a float or (n,))."""
    value = np.asarray(value, dtype=float)
    d = np.zeros((ORDER + 1,) + value.shape)
    d[0] = value
    for k, dk in enumerate(derivatives, start=1):
        d[k] = dk
    return Jet(d)


def rotate(axis: np.ndarray, v: np.ndarray, angle: Jet) -> Jet:
    """R(axis, angle)·v for a constant unit axis (3,) and constant vector v (3,) (Rodrigues)."""
    axis = np.asarray(axis, dtype=float)
    v = np.asarray(v, dtype=float)
    along = axis * float(axis @ v)
    perp = v - along
    c, s = angle.cos(), angle.sin()
    d = c.d[..., None] * perp + s.d[..., None] * np.cross(axis, perp)
    d[0] += along
    return Jet(d)


def stack_vector(x: Jet, y: Jet, z: Jet) -> Jet:
    return Jet(np.stack([x.d, y.d, z.d], axis=-1))


def motion(jet: Jet, omega: float, epsilon: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Value, velocity, acceleration and jerk in time of a quantity x(φ(t)) with the crank at
    speed ω [rad/s] and constant acceleration ε [rad/s²]: ẋ = x′ω, ẍ = x″ω² + x′ε,
    x⃛ = x‴ω³ + 3x″ωε (ε̇ = 0). ``omega``/``epsilon`` may be floats or per-angle arrays (n,)."""
    w = np.asarray(omega, dtype=float)
    e = np.asarray(epsilon, dtype=float)
    d = jet.d
    if jet.is_vector:
        w, e = (w[..., None] if w.ndim else w), (e[..., None] if e.ndim else e)
    return d[0], d[1] * w, d[2] * w**2 + d[1] * e, d[3] * w**3 + 3 * d[2] * w * e
