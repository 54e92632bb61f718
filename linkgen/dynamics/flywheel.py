"""Flywheel sizing by the energy method (Wittenbauer's energy–inertia relation).

Over a steady cycle driven by a constant torque equal to the mean resisting torque, the kinetic
energy theorem holds exactly along φ: ½·(J(φ) + J_f)·ω(φ)² = T0 + ΔE(φ), ΔE(φ) = ∫ (M_d + M(φ)) dφ
from the cycle's start (M the reduced moment of the loads, negative when it resists). For given
ω_max and ω_min = ω_m·(1 ± δ/2) (ω_m their mean, the classical definition) the flywheel J_f and
T0 follow from max_φ 2(T0 + ΔE)/(J + J_f) = ω_max² and min_φ … = ω_min²: T0 from the first for
each J_f, and J_f from the second by bisection (ω_min grows with J_f). No linearisation in δ.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from linkgen.dynamics.reduced import Reduced
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


def _cycle(red: Reduced):
    phi = red.moment_phi
    m = red.moment_grid
    m_d = -float(np.trapezoid(m, phi) / (phi[-1] - phi[0]))
    de = np.concatenate([[0.0], np.cumsum(0.5 * (m[1:] + m[:-1] + 2 * m_d) * np.diff(phi))])
    return phi, red.j(phi), de, m_d


def _speeds(j, de, jf: float, t0: float) -> np.ndarray:
    return np.sqrt(np.maximum(2.0 * (t0 + de) / (j + jf), 0.0))


def size_flywheel(red: Reduced, omega_mean: float, delta: float, added: float = 0.0) -> Flywheel:
    """The flywheel for speed fluctuation δ at mean speed ω_m [rad/s] (``added``: rotor inertia
    already on the crank [kg·m²], part of the total J the result is beyond)."""
    if not (omega_mean > 0 and 0 < delta < 2):
        raise SimulationError(f"need ω_mean > 0 and 0 < δ < 2, got {omega_mean!r}, {delta!r}")
    phi, j, de, m_d = _cycle(red)
    j = j + added
    w_hi, w_lo = omega_mean * (1 + delta / 2), omega_mean * (1 - delta / 2)

    def t0(jf):
        return float(np.min(0.5 * w_hi**2 * (j + jf) - de))

    def miss(jf):
        return float(_speeds(j, de, jf, t0(jf)).min()) - w_lo

    hi = max(float(np.ptp(de)) / (delta * omega_mean**2), 1e-12) * 4 + float(j.max())
    if miss(0.0) >= 0:
        jf = 0.0
    else:
        while miss(hi) < 0:
            hi *= 4
        jf = brentq(miss, 0.0, hi, xtol=1e-14 * hi, rtol=1e-14, maxiter=500)
    w = _speeds(j, de, jf, t0(jf))
    return Flywheel(jf, m_d, float(np.ptp(de)), float(w[0]), omega_mean, delta)


def fluctuation(red: Reduced, flywheel: float, omega_mean: float, added: float = 0.0) -> float:
    """δ = (ω_max − ω_min)/ω_m that a flywheel [kg·m²] gives at mean speed ω_m = (ω_max + ω_min)/2."""
    phi, j, de, m_d = _cycle(red)
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
