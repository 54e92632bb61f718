"""Flywheel sizing by the energy method (Wittenbauer's energy–inertia relation).

Over a steady cycle driven by a constant torque equal to the mean resisting torque, the kinetic
energy theorem holds exactly along φ: ½·(J(φ) + J_f)·ω(φ)² = T0 + ΔE(φ), ΔE(φ) = ∫ (M_d + M(φ)) dφ
from the cycle's start (M the reduced moment of the loads, negative when it resists). For given
ω_max and ω_min = ω_m·(1 ± δ/2) (ω_m their mean, the classical definition) the flywheel J_f and
T0 follow from max_φ 2(T0 + ΔE)/(J + J_f) = ω_max² and min_φ … = ω_min²: T0 from the first for
each J_f, and J_f from the second by bisection (ω_min grows with J_f). No linearisation in δ.
Dampers (``[[spring]]``/``[[torsion_spring]]`` damping) make M depend on ω: they are taken at ω_m,
which their work over the cycle matches to within the fluctuation δ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from linkgen.machine.reduced import Reduced
from linkgen.errors import SimulationError


@dataclass(frozen=True)
class Flywheel:
    """The flywheel inertia [kg·m², at the crank, beyond the mechanism's own and the rotor's
    given ``added``], the mean driving torque [N·m], the largest energy swing ΔE_max [J], and the
    crank speed at the cycle's start [rad/s] for the periodic motion."""

    inertia: float
    driving_torque: float
    energy_swing: float
    start_speed: float
    omega_mean: float
    delta: float


def _cycle(red: Reduced, omega_mean: float):
    phi = red.moment_phi
    m = red.moment_grid
    if red.damping_grid is not None:  # dampers at the mean speed (``Reduced.moment``'s M₀ + C·ω)
        m = m + red.damping_grid * omega_mean
    m_d = -float(np.trapezoid(m, phi) / (phi[-1] - phi[0]))
    de = np.concatenate([[0.0], np.cumsum(0.5 * (m[1:] + m[:-1] + 2 * m_d) * np.diff(phi))])
    return phi, red.j(phi), de, m_d


def _speeds(j, de, jf: float, t0: float) -> np.ndarray:
    return np.sqrt(np.maximum(2.0 * (t0 + de) / (j + jf), 0.0))


def size_flywheel(red: Reduced, omega_mean: float, delta: float, added: float = 0.0) -> Flywheel:
    """The flywheel for speed fluctuation δ at mean speed ω_m [rad/s] (``added``: rotor inertia
    already on the crank [kg·m²], part of the total J the result is beyond).

    Solved in speeds relative to ω_m and energies over ω_m² [kg·m²] (the answer scales so), so
    that no square of a small or large speed leaves float range on the way; SimulationError if
    the flywheel itself is beyond it."""
    if not (omega_mean > 0 and 0 < delta < 2):
        raise SimulationError(f"need ω_mean > 0 and 0 < δ < 2, got {omega_mean!r}, {delta!r}")
    phi, j, de, m_d = _cycle(red, omega_mean)
    j = j + added
    with np.errstate(over="ignore", under="ignore"):
        e = de / omega_mean / omega_mean  # ΔE/ω_m² [kg·m²]
    if not (np.isfinite(e).all() and np.isfinite(j).all()):
        raise SimulationError(f"the flywheel for δ = {delta:g} at ω_mean = {omega_mean:g} rad/s is beyond float64's "
                              f"range: the energy swing {float(np.ptp(de)):.3g} J over ω_mean² = {omega_mean:g}² "
                              "rad²/s² does not fit; give a mean speed nearer the machine's (--omega)")
    w_hi, w_lo = 1 + delta / 2, 1 - delta / 2

    def t0(jf):
        return float(np.min(0.5 * w_hi**2 * (j + jf) - e))

    def miss(jf):
        return float(_speeds(j, e, jf, t0(jf)).min()) - w_lo

    hi = max(float(np.ptp(e)) / delta, 1e-12 * max(float(j.max()), 1e-300)) * 4 + float(j.max())
    if miss(0.0) >= 0:
        jf = 0.0
    else:
        while miss(hi) < 0 and math.isfinite(hi):
            hi *= 4
        if not math.isfinite(hi):
            raise SimulationError(f"no finite flywheel gives δ = {delta:g} at ω_mean = {omega_mean:g} rad/s")
        jf = brentq(miss, 0.0, hi, xtol=1e-14 * hi, rtol=1e-14, maxiter=500)
    w = _speeds(j, e, jf, t0(jf)) * omega_mean
    return Flywheel(jf, m_d, float(np.ptp(de)), float(w[0]), omega_mean, delta)


def fluctuation(red: Reduced, flywheel: float, omega_mean: float, added: float = 0.0) -> float:
    """δ = (ω_max − ω_min)/ω_m that a flywheel [kg·m²] gives at mean speed ω_m = (ω_max + ω_min)/2."""
    phi, j, de, m_d = _cycle(red, omega_mean)
    j = j + added + flywheel

    def mean(t0):
        w = _speeds(j, de, 0.0, t0)
        return 0.5 * (w.max() + w.min()) - omega_mean

    lo = float(-de.min()) + 1e-300
    hi = 0.5 * omega_mean**2 * float(j.max()) * 4 + float(np.ptp(de))
    t0 = brentq(mean, lo, hi, xtol=1e-15 * hi, rtol=1e-15, maxiter=500)
    w = _speeds(j, de, 0.0, t0)
    return float((w.max() - w.min()) / (0.5 * (w.max() + w.min())))


__all__ = ["Flywheel", "fluctuation", "size_flywheel"]
