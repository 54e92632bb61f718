"""Velocities, accelerations and jerks from transfer functions, for a crank turning at ω with a
constant acceleration ε (dε/dt = 0): v = x′ω, a = x″ω² + x′ε, j = x‴ω³ + 3x″ωε."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from linkgen.families.planar.blocks import carve
from linkgen.errors import ArgumentError, MagnitudeError, angle_ranges
from linkgen.families.planar.primitives import constant_along

Triple = tuple[np.ndarray, np.ndarray, np.ndarray]
Series = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]  # x, dx/dφ, d²x/dφ², d³x/dφ³
KINDS = ("points", "links", "sliders")


@dataclass(frozen=True)
class Motion:
    """Time derivatives at crank speed ``omega`` and acceleration ``epsilon`` (each (n,)).

    ``points[name]`` = (position (n,2) [m], velocity [m/s], acceleration [m/s²]);
    ``links[name]`` = (angle (n,) [rad], angular velocity [rad/s], angular acceleration [rad/s²]);
    ``sliders[name]`` = (displacement [m], velocity [m/s], acceleration [m/s²]).
    ``jerk[kind][name]``, kind one of ``points``, ``links``, ``sliders``: the third time
    derivative, x‴ω³ + 3x″ωε (ε taken constant in time): (n, 2) [m/s³] for a point, (n,)
    [rad/s³] for a link's angle, (n,) [m/s³] for a slider.
    Quantities constant along φ are read-only zero-stride views. ``singular`` (n,) bool: True
    at angles marked singular (``on_singular="mark"``), where the velocities, accelerations
    and jerks are set to 0; None when not known.
    """

    def __repr__(self) -> str:
        return f"Motion({len(np.atleast_1d(self.phi))} angles, {len(self.points)} points, {len(self.links)} links)"


    phi: np.ndarray
    omega: np.ndarray
    epsilon: np.ndarray
    points: dict[str, Triple]
    links: dict[str, Triple]
    sliders: dict[str, Triple]
    singular: np.ndarray | None = None
    jerk: dict[str, dict[str, np.ndarray]] = field(default_factory=lambda: {k: {} for k in KINDS})


def rate(name: str, value, n: int, unit: str) -> float | np.ndarray:
    """A crank rate as a float or an (n,) array, checked: finite, scalar or one per angle."""
    a = np.asarray(value, dtype=float)
    if a.ndim != 0 and a.shape != (n,):
        raise ArgumentError(f"{name} must be a scalar or an array of shape ({n},) [{unit}], got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ArgumentError(f"{name} must be finite [{unit}], got {value if a.ndim == 0 else 'non-finite entries'}")
    return float(a) if a.ndim == 0 else a


def derivatives(phi: np.ndarray, series: dict[str, dict[str, Series]], omega, epsilon) -> Motion:
    """Motion from ``series[kind][name] = (x, dx/dφ, d²x/dφ², d³x/dφ³)`` for kinds points, links
    and sliders (arrays (n,) or (n, 2)), at ω [rad/s] and ε [rad/s²], scalars or (n,).

    Quantities constant along φ stay zero-stride views when ω and ε are scalars; the others
    share one allocation (``blocks.carve``); a scalar ε = 0 costs nothing.
    """
    n = phi.shape[0]
    return checked_derivatives(phi, series, rate("omega", omega, n, "rad/s"), rate("epsilon", epsilon, n, "rad/s²"))


@np.errstate(over="ignore", invalid="ignore")  # overflow is found and named below
def checked_derivatives(phi: np.ndarray, series: dict[str, dict[str, Series]],
                        omega: float | np.ndarray, epsilon: float | np.ndarray) -> Motion:
    """``derivatives`` for ω and ε already checked by ``rate`` (floats or (n,) arrays)."""
    n = phi.shape[0]
    scalar = np.ndim(omega) == 0 and np.ndim(epsilon) == 0
    items = [(kind, name, t) for kind, named in series.items() for name, t in named.items()]
    fixed = [scalar and all(constant_along(d) for d in t[1:]) for _, _, t in items]
    fresh = iter(carve(n, [d for (_, _, t), f in zip(items, fixed) if not f for d in t[1:]]))
    out: dict[str, dict[str, Triple]] = {kind: {} for kind in KINDS}
    jerks: dict[str, dict[str, np.ndarray]] = {kind: {} for kind in KINDS}
    for (kind, name, (x, d1, d2, d3)), f in zip(items, fixed):
        if f:  # one row, broadcast
            vel = np.broadcast_to(d1[0] * omega, d1.shape)
            acc = np.broadcast_to(d2[0] * (omega * omega) + d1[0] * epsilon, d2.shape)
            jerk = np.broadcast_to(d3[0] * (omega * omega * omega) + 3.0 * d2[0] * (omega * epsilon), d3.shape)
        else:
            vel, acc, jerk = next(fresh), next(fresh), next(fresh)
            _into(d1, d2, d3, omega, epsilon, vel, acc, jerk)
        for what, a in (("velocity", vel), ("acceleration", acc), ("jerk", jerk)):
            if not all_finite(a):
                bad = ~np.isfinite(a.reshape(n, -1)).all(axis=1) if not constant_along(a) else np.ones(n, bool)
                raise MagnitudeError(f"the {what} of {kind[:-1]} {name}", angle_ranges(phi, bad))
        out[kind][name] = (x, vel, acc)
        jerks[kind][name] = jerk
    return Motion(phi, np.broadcast_to(omega, (n,)), np.broadcast_to(epsilon, (n,)),
                  out["points"], out["links"], out["sliders"], jerk=jerks)


def all_finite(a: np.ndarray) -> bool:
    """All entries finite; one pass when they are (a sum of finite values can still overflow)."""
    a = a[:1] if constant_along(a) else a
    return bool(np.isfinite(a.sum()) or np.isfinite(a).all())


def _into(d1: np.ndarray, d2: np.ndarray, d3: np.ndarray, w, e, vel: np.ndarray, acc: np.ndarray,
          jerk: np.ndarray) -> None:
    """vel = d1·ω, acc = d2·ω² + d1·ε, jerk = d3·ω³ + 3·d2·ω·ε, with ω, ε floats or (n,) arrays."""
    if d1.ndim == 2 and np.ndim(w):
        w = w[:, None]
    if d1.ndim == 2 and np.ndim(e):
        e = e[:, None]
    np.multiply(d1, w, out=vel)
    np.multiply(d2, w * w, out=acc)
    np.multiply(d3, w * w * w, out=jerk)
    if np.ndim(e) or e != 0.0:
        acc += d1 * e
        jerk += d2 * (3.0 * w * e)
