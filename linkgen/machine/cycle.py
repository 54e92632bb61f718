"""What a machine run yields beyond its samples, all from the solver's dense output (never from
the output samples): the turns, the steady cycle, the end of the start-up and the peak motor
torque, each refined between the solver's own steps (bisection, Brent).

The steady cycle is the first turn whose ω(φ) repeats the previous turn's to within what the
integration itself resolves: STEADY_TOL of the mean speed (100× the solver's tolerance RTOL),
or, over many steps, the steps' local errors (each within RTOL) added up as independent errors
over the two turns compared, RTOL·√steps, if that is larger. The turn-to-turn noise this has to
cover is kept small at its cause: the solver's steps are bounded to a 64th of a turn
(``machine.STEPS_PER_TURN``), for over a step that crosses hundreds of the load table's kinks
its error estimate does not see them: flywheel_sine, at 8 steps per turn, differed from turn to
turn by 1.4e-8 to 4.5e-8 and never passed 1e-8; at 64 steps per turn it differs by 3e-9 to 6e-9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

# Two successive turns are the same cycle when ω(φ) differs by less than this fraction of the
# mean speed (100× the integration's tolerance) at every one of CYCLE_POINTS crank angles, or
# by RTOL·√steps of the two turns if that is larger (module docstring).
STEADY_TOL = 1e-8
CYCLE_POINTS = 256
# The start-up ends where ω enters, for good, the steady cycle's band widened by this fraction
# of the mean speed.
STARTUP_BAND = 0.01
# Points of the dense output looked at between two solver steps before a root or a maximum is
# refined there (a solver step holds at most a few extrema of a smooth ω(t)).
SUBSTEPS = 16


@dataclass(frozen=True)
class SteadyCycle:
    """One steady turn: start time [s], period [s], mean speed ±2π/period (negative for a crank
    turning the negative way), ω_min, ω_max [rad/s], δ = (ω_max − ω_min)/|ω_mean|; ``tolerance``: the relative turn-to-turn difference accepted."""

    t_start: float
    period: float
    omega_mean: float
    omega_min: float
    omega_max: float
    tolerance: float = STEADY_TOL

    @property
    def delta(self) -> float:
        return (self.omega_max - self.omega_min) / abs(self.omega_mean)

    def to_json(self) -> dict:
        return {"t_start": self.t_start, "period": self.period, "omega_mean": self.omega_mean,
                "omega_min": self.omega_min, "omega_max": self.omega_max, "delta": self.delta,
                "repeat_tolerance": self.tolerance}


def fine_times(sol, a: float, b: float) -> np.ndarray:
    """The solver's step times within [a, b] with SUBSTEPS points between each two."""
    steps = sol.t[(sol.t > a) & (sol.t < b)]
    knots = np.concatenate([[a], steps, [b]])
    return np.concatenate([np.linspace(knots[i], knots[i + 1], SUBSTEPS, endpoint=False)
                           for i in range(knots.size - 1)] + [[b]])


def direction(sol, phi0: float) -> float:
    """+1 for a crank that ends the run ahead of φ0, −1 for one that ends behind it (turning the
    negative way)."""
    return 1.0 if sol.y[0][-1] >= phi0 else -1.0


def turn_times(sol, phi0: float) -> np.ndarray:
    """Times [s] at which the crank has turned by 2π·k from φ0 (k = 1, 2, …) the way it runs
    (``direction``), from the dense output (root of ±(φ(t) − φ0) − 2πk by bisection between the
    solver's steps)."""
    d = direction(sol, phi0)
    turns = d * (sol.y[0] - phi0) / (2 * math.pi)
    out = []
    for k in range(1, int(math.floor(turns.max())) + 1):
        j = int(np.argmax(turns >= k))
        a, b = sol.t[j - 1], sol.t[j]
        for _ in range(100):
            mid = 0.5 * (a + b)
            if d * (sol.sol(mid)[0] - phi0) / (2 * math.pi) >= k:
                b = mid
            else:
                a = mid
        out.append(0.5 * (a + b))
    return np.array(out)


def _extrema(sol, a: float, b: float) -> tuple[float, float]:
    """ω_min and ω_max over [a, b] [rad/s], refined by Brent around the best of the fine points."""
    ts = fine_times(sol, a, b)
    w = sol.sol(ts)[1]
    out = []
    for sign in (1.0, -1.0):  # minimum, then maximum
        k = int(np.argmin(sign * w))
        lo, hi = ts[max(k - 1, 0)], ts[min(k + 1, ts.size - 1)]
        best = sign * w[k]
        if hi > lo:
            r = minimize_scalar(lambda x: sign * sol.sol(x)[1], bounds=(lo, hi), method="bounded",
                                options={"xatol": 1e-12 * max(abs(hi), 1.0)})
            best = min(best, float(r.fun))
        out.append(sign * best)
    return out[0], out[1]


def steady_cycle(sol, phi0: float, rtol: float) -> SteadyCycle | None:
    """The first turn whose ω(φ) repeats the previous turn's (module docstring), or None."""
    times = turn_times(sol, phi0)
    d = direction(sol, phi0)
    prev = None
    for k in range(len(times) - 1):
        a, b = times[k], times[k + 1]
        ts = np.linspace(a, b, 8 * CYCLE_POINTS)
        y = sol.sol(ts)
        grid = 2 * math.pi * (k + 1) + np.linspace(0.0, 2 * math.pi, CYCLE_POINTS, endpoint=False)
        w = np.interp(grid, d * (y[0] - phi0), y[1])  # over the turn the way the crank runs
        if prev is not None:
            mean = d * 2 * math.pi / (b - a)
            steps = int(((sol.t > times[k - 1]) & (sol.t <= b)).sum())
            tol = max(STEADY_TOL, rtol * math.sqrt(steps))
            if np.abs(w - prev).max() <= tol * abs(mean):
                lo, hi = _extrema(sol, a, b)
                return SteadyCycle(float(a), float(b - a), mean, lo, hi, float(tol))
        prev = w
    return None


def startup_time(sol, steady: SteadyCycle, t_end: float) -> float | None:
    """The time [s] from which ω stays within the steady band widened by STARTUP_BAND of the
    mean speed (0 if it always was, None if it is outside at the end), as a root of the dense
    output between the solver's steps."""
    band = STARTUP_BAND * abs(steady.omega_mean)
    lo, hi = steady.omega_min - band, steady.omega_max + band

    def outside(t):
        w = sol.sol(t)[1]
        return np.maximum(lo - w, w - hi)

    ts = fine_times(sol, 0.0, t_end)
    g = outside(ts)
    out = np.flatnonzero(g > 0)
    if out.size == 0:
        return 0.0
    k = int(out[-1])
    if k + 1 >= ts.size:
        return None
    a, b = ts[k], ts[k + 1]
    if outside(b) == 0.0:
        return float(b)
    return float(brentq(lambda x: float(outside(x)), a, b, xtol=1e-14 * max(b, 1.0), rtol=4 * np.finfo(float).eps))


def peak(sol, f, t_end: float) -> tuple[float, float]:
    """The largest |f(states, times)| over [0, t_end] and its time [s] (f of the dense output's
    states (n, k) and their times (k,) → (k,)), refined by Brent around the best of the fine points."""
    ts = fine_times(sol, 0.0, t_end)
    v = np.abs(f(sol.sol(ts), ts))
    k = int(np.argmax(v))
    best, at = float(v[k]), float(ts[k])
    lo, hi = ts[max(k - 1, 0)], ts[min(k + 1, ts.size - 1)]
    if hi > lo:
        r = minimize_scalar(lambda x: -float(np.abs(f(sol.sol(np.array([x])), np.array([x])))[0]), bounds=(lo, hi),
                            method="bounded", options={"xatol": 1e-12 * max(abs(hi), 1.0)})
        if -float(r.fun) > best:
            best, at = -float(r.fun), float(r.x)
    return best, at


__all__ = ["CYCLE_POINTS", "STARTUP_BAND", "STEADY_TOL", "SteadyCycle", "peak", "startup_time", "steady_cycle",
           "turn_times"]
