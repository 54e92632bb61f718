"""Extrema of a quantity over a drive coordinate (a crank or cam angle [rad], or time [s]) — the
one routine every family's summary uses.

A drive's range is either a whole period (a full turn: the quantity repeats, so the interval from
the last sample round to the first is searched too) or a partial range, whose two ends are
extremes of the quantity on it.

- ``stationary``: where a quantity with a known derivative has its minima and maxima (limit
  positions): every sign change of the derivative between samples, the wrap interval
  [last sample, first + period] included, refined by Brent's root finder to XTOL; a derivative
  that is exactly 0 at a sample counts once, where the signs on its two sides differ; and the
  ends of a partial range.
- ``peak``: the largest (or least) value of a quantity known only by its values (a peak force,
  the least transmission angle): every sample that is a local best within MARGIN of the best
  sample (at most MAX_REFINED), refined by Brent's bounded minimiser inside its two neighbours
  (round the wrap for a period); the ends of a partial range are samples like the others.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

# A root of the derivative is refined to this drive coordinate (Brent's method on a smooth
# derivative: the bracket closes to a few ulps of 2π).
XTOL = 1e-13
# Brent's bounded minimiser stops within this, plus its own floor √eps·u (u ≤ two sample steps
# from the bracket's start: 2.6e-11 rad for 0.1° samples), of the best point. At a smooth peak
# the value is then exact to rounding (the curve is flat there); at a kink or a jump it is off
# by the slope times that distance.
PEAK_XTOL = 1e-12

Curve = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Extremum:
    """Where a quantity is least ("min") or greatest ("max") about ``x`` (the drive coordinate);
    ``end`` is True at an end of a partial range (an extreme on the range, not a stationary
    point)."""

    x: float
    kind: str
    end: bool = False


def samples(start: float, stop: float, n: int, periodic: bool) -> np.ndarray:
    """``n`` equally spaced drive coordinates: over [start, stop) for a period (stop − start),
    over [start, stop] with both ends for a partial range."""
    if periodic:
        return start + (stop - start) * np.arange(n) / n
    return np.linspace(start, stop, n)


def _scalar(fun: Curve) -> Callable[[float], float]:
    return lambda x: float(np.asarray(fun(np.array([x])), dtype=float)[0])


def _root(d: Callable[[float], float], a: float, b: float, xtol: float) -> float:
    """A root of ``d`` in [a, b], whose ends the samples gave opposite signs."""
    from scipy.optimize import brentq

    da, db = d(a), d(b)
    if da == 0.0:
        return a
    if db == 0.0:
        return b
    if (da > 0) == (db > 0):  # re-evaluated at the wrap end, the sign is rounding's: take the nearer to 0
        return a if abs(da) <= abs(db) else b
    return float(brentq(d, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps))


def stationary(d: Curve, x: np.ndarray, dx: np.ndarray, *, period: float | None = None,
               xtol: float = XTOL) -> tuple[Extremum, ...]:
    """The minima and maxima of a quantity whose derivative is ``d`` (vectorised: (m,) → (m,)),
    given its values ``dx`` at the increasing samples ``x`` (``samples``). With ``period`` the
    quantity repeats after it (x spans [x[0], x[0] + period)); otherwise the range is [x[0],
    x[-1]] and its ends are reported with ``end=True``. Sorted by ``x``, each in the range."""
    x = np.asarray(x, dtype=float)
    start = float(x[0])
    s = np.sign(np.asarray(dx, dtype=float))
    d1 = _scalar(d)
    if period is not None:
        nz = np.flatnonzero(s)
        if nz.size == 0:  # constant: no extremum
            return ()
        r = int(nz[0])  # start the cycle at a sample whose sign is known, end it there a period later
        x = np.concatenate([x[r:], x[:r] + period, [x[r] + period]])
        s = np.concatenate([s[r:], s[:r], [s[r]]])
    found: list[Extremum] = []
    for k in np.flatnonzero(s[:-1] * s[1:] < 0):
        found.append(Extremum(_root(d1, float(x[k]), float(x[k + 1]), xtol), "max" if s[k] > 0 else "min"))
    # runs of samples where the derivative is exactly 0: an extremum where the signs around differ
    zero = np.flatnonzero(s == 0)
    runs = np.split(zero, np.flatnonzero(np.diff(zero) > 1) + 1) if zero.size else []
    for run in runs:
        i, j = int(run[0]), int(run[-1])
        if i == 0 or j == len(s) - 1:
            continue  # at an end of a partial range: the ends are handled below
        before, after = s[i - 1], s[j + 1]
        if before != after:
            found.append(Extremum(float(0.5 * (x[i] + x[j])), "max" if before > 0 else "min"))
    if period is not None:
        found = [Extremum(start + (e.x - start) % period, e.kind) for e in found]
    else:  # a stationary point at an end of the range is that end's extreme, reported once as the end
        found = [e for e in found if min(e.x - x[0], x[-1] - e.x) > xtol]
        nz = np.flatnonzero(s)
        if nz.size:
            first, last = s[nz[0]], s[nz[-1]]
            found.append(Extremum(float(x[0]), "max" if first < 0 else "min", True))
            found.append(Extremum(float(x[-1]), "max" if last > 0 else "min", True))
    return tuple(sorted(found, key=lambda e: e.x))


# Samples within this of the best one (in units of the largest second difference of the
# samples, which bounds how far a sample next to a smooth peak falls below it: (Δx)²·|f''|/8)
# are refined too, so that a peak whose nearest sample happens to fall lower is not missed.
MARGIN = 1.0
# At most this many of them, best first: more are rounding noise on a flat curve (an arcsine
# near 90°), which refinement cannot improve beyond the noise itself.
MAX_REFINED = 8


def peak(f: Curve, x: np.ndarray, fx: np.ndarray, *, kind: str = "max", period: float | None = None,
         xtol: float = PEAK_XTOL) -> tuple[float, float]:
    """(x, value) where the quantity ``f`` (vectorised: (m,) → (m,)), sampled as ``fx`` at the
    increasing samples ``x``, is greatest (``kind`` "max") or least ("min") over the range: over
    a period if ``period`` is given, else over [x[0], x[-1]] ends included."""
    from scipy.optimize import minimize_scalar

    sign = 1.0 if kind == "max" else -1.0
    x = np.asarray(x, dtype=float)
    g = sign * np.asarray(fx, dtype=float)
    n = len(g)
    if period is not None:
        left, right = np.roll(g, 1), np.roll(g, -1)
    else:
        left = np.concatenate([[-np.inf], g[:-1]])
        right = np.concatenate([g[1:], [-np.inf]])
    with np.errstate(invalid="ignore"):  # a quantity may be ±inf where undefined (a cam's hold/pull)
        d2 = np.abs(right - 2 * g + left)
    finite = np.isfinite(d2)
    margin = MARGIN * (float(np.max(d2[finite])) if finite.any() else 0.0)
    best = int(np.argmax(g))
    at, value = float(x[best]), float(g[best])
    fs = _scalar(f)
    # local bests (a plateau counts at its edges, whose value it keeps exactly)
    local = (g >= left) & (g >= right) & ((g > left) | (g > right))
    near = np.flatnonzero(local & (g >= value - margin))
    for k in near[np.argsort(-g[near], kind="stable")][:MAX_REFINED]:
        if period is not None:
            a = float(x[k - 1] if k > 0 else x[-1] - period)
            b = float(x[k + 1] if k + 1 < n else x[0] + period)
        else:
            a, b = float(x[max(k - 1, 0)]), float(x[min(k + 1, n - 1)])
        if not b > a:
            continue
        # searched as a + u, u in [0, b − a]: the minimiser's own floor, √eps·|u|, is then a
        # fraction of the bracket, not of the coordinate (a peak at a kink or jump at t = 100 s)
        with np.errstate(invalid="ignore", over="ignore"):
            r = minimize_scalar(lambda u, a=a: -sign * fs(a + u), bounds=(0.0, b - a), method="bounded",
                                options={"xatol": xtol})
        if np.isfinite(r.fun) and -r.fun > value:
            at, value = a + float(r.x), float(-r.fun)
    if period is not None:
        at = float(x[0]) + (at - float(x[0])) % period
    return at, sign * value


__all__ = ["Extremum", "MARGIN", "MAX_REFINED", "PEAK_XTOL", "XTOL", "peak", "samples", "stationary"]
