"""Loads as periodic functions of the crank angle that keep their jumps: piecewise linear between
grid angles, with a stroke-switched force's switch angles in the grid twice (the value just before
and just after), so a jump sits exactly where the force switches instead of being spread over a
grid step.

Both sides of the machine comparison use it: the ODE reads M(φ) from it (``at``), and MuJoCo
applies over each step the exact mean of the table over the crank angles the step sweeps
(``mean``), so a switch inside a step counts for the fraction of the step past it."""

from __future__ import annotations

import math

import numpy as np

from linkgen.model.strokes import stroke_active  # noqa: F401  (the convention the switch angles follow)

# The two values at a switch angle s are evaluated at s ∓ SIDE [rad]: the smooth part of the load
# moves by SIDE·M′ there, 1e-10 of a load that varies like cos φ.
SIDE = 1e-10


def switch_angles(mech, start: float) -> list[float]:
    """Crank angles in [start, start + 2π) [rad] where a stroke-switched force switches on or off
    (``stroke_active``: on over [from, to] modulo one turn)."""
    out = set()
    for f in mech.forces:
        if f.stroke is None or f.stroke[1] - f.stroke[0] >= 2 * math.pi:
            continue
        for s in f.stroke:
            out.add(start + (s - start) % (2 * math.pi))
    return sorted(out)


def jump_grid(start: float, cells: int, switches: list[float], span: float = 2 * math.pi
              ) -> tuple[np.ndarray, np.ndarray]:
    """The table's angles (m,) — ``cells`` equal cells over ``span`` [rad] (one turn by default)
    from ``start``, each switch angle within it added twice — and the angles (m,) to evaluate
    the load at (a switch's first copy just before it, its second just after)."""
    switches = [s for s in switches if start < s < start + span]
    base = start + np.linspace(0.0, span, cells + 1)
    base = base[~np.isin(base, switches)]  # a switch on a grid angle (90° of 32768 cells): twice, not three times
    grid = np.sort(np.concatenate([base, switches, switches]))
    where = grid.copy()
    for s in switches:
        k = int(np.searchsorted(grid, s, side="left"))
        where[k], where[k + 1] = s - SIDE, s + SIDE
    return grid, where


class PeriodicTable:
    """Values (m,) or (m, k) at non-decreasing angles (m,) spanning one turn [rad]; a repeated
    angle is a jump (the later value holds from it on)."""

    def __init__(self, phi: np.ndarray, values: np.ndarray):
        self.phi = np.asarray(phi, dtype=float)
        self.values = np.asarray(values, dtype=float)
        self.start, self.period = float(self.phi[0]), float(self.phi[-1] - self.phi[0])
        widths = np.diff(self.phi).reshape((-1,) + (1,) * (self.values.ndim - 1))
        cells = 0.5 * (self.values[1:] + self.values[:-1]) * widths
        self.cumulative = np.concatenate([np.zeros((1,) + self.values.shape[1:]), np.cumsum(cells, axis=0)])

    def _locate(self, phi):
        x = np.asarray(phi, dtype=float)
        turns = np.floor((x - self.start) / self.period)
        u = x - self.start - turns * self.period + self.start
        k = np.clip(np.searchsorted(self.phi, u, side="right") - 1, 0, self.phi.size - 2)
        return turns, u, k

    def at(self, phi):
        """The value at crank angles φ [rad] (any turn; right-continuous at a jump)."""
        _, u, k = self._locate(phi)
        width = self.phi[k + 1] - self.phi[k]
        w = np.where(width > 0, (u - self.phi[k]) / np.where(width > 0, width, 1.0), 1.0)
        w = w.reshape(np.shape(w) + (1,) * (self.values.ndim - 1))
        return (1.0 - w) * self.values[k] + w * self.values[k + 1]

    def integral(self, phi):
        """∫ from the table's start to φ [rad] of the values (over whole turns too) [value·rad]."""
        turns, u, k = self._locate(phi)
        v = self.at(u)
        part = self.cumulative[k] + 0.5 * (self.values[k] + v) * (u - self.phi[k]).reshape(
            np.shape(u) + (1,) * (self.values.ndim - 1))
        return np.reshape(turns, np.shape(turns) + (1,) * (self.values.ndim - 1)) * self.cumulative[-1] + part

    def mean(self, a: float, b: float):
        """The mean value over the crank angles from a to b [rad] (the value at a when a = b)."""
        if b == a:
            return self.at(a)
        return (self.integral(b) - self.integral(a)) / (b - a)


class SmoothTable:
    """The same values (m,) at the same angles as ``PeriodicTable``, through cubic splines
    between the jumps: a periodic spline over the turn where nothing jumps, else a not-a-knot
    spline from each jump (and the table's start) to the next. What the machine's equation
    reads: a table linear between its 32768 angles has a kink at each of them, which an ODE
    solver at a tolerance of 1e-12 must resolve one by one (a slider-crank's ten turns took
    112 s instead of 1 s), and errs by (2π/n)²/8·|M″| between them against the cubic's
    (2π/n)⁴·|M⁗|/384. ``periodic``: the angles span one turn and repeat beyond it; else
    (a drive's partial range) the end pieces extend past the ends."""

    def __init__(self, phi: np.ndarray, values: np.ndarray, periodic: bool = True):
        from scipy.interpolate import CubicSpline, PPoly

        x, v = np.asarray(phi, dtype=float), np.asarray(values, dtype=float)
        self.start, self.period, self.periodic = float(x[0]), float(x[-1] - x[0]), periodic
        cuts = np.flatnonzero(np.diff(x) == 0.0) + 1  # each jump's second copy starts a piece
        pieces = np.split(np.arange(x.size), cuts)
        if len(pieces) == 1 and periodic:
            self.poly = CubicSpline(x, v, bc_type="periodic")
        else:
            splines = [CubicSpline(x[k], v[k]) if k.size > 2 else CubicSpline(x[k], v[k], bc_type="natural")
                       for k in pieces]
            self.poly = PPoly(np.hstack([sp.c for sp in splines]), np.concatenate(
                [splines[0].x] + [sp.x[1:] for sp in splines[1:]]), extrapolate=True)
        self.anti = self.poly.antiderivative()
        self.total = float(self.anti(x[-1]) - self.anti(x[0]))

    def _unwrap(self, phi):
        x = np.asarray(phi, dtype=float)
        if not self.periodic:
            return np.zeros_like(x), x
        turns = np.floor((x - self.start) / self.period)
        return turns, x - turns * self.period

    def at(self, phi):
        """The value at crank angles φ [rad] (any turn; right-continuous at a jump)."""
        return self.poly(self._unwrap(phi)[1])

    def integral(self, phi):
        """∫ from the table's start to φ [rad] of the values (over whole turns too) [value·rad]."""
        turns, u = self._unwrap(phi)
        return turns * self.total + self.anti(u) - self.anti(self.start)


__all__ = ["PeriodicTable", "SIDE", "SmoothTable", "jump_grid", "switch_angles"]
