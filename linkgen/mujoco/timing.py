"""The timing of a MuJoCo run: when the crank reaches an angle, where loads switch, and how
long the loops take to settle after a start or a load step."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import SimulationError
from linkgen.mujoco.loop_modes import decay_rate
from linkgen.mujoco.loops import acceleration_scale
from linkgen.mujoco.options import Settings
from linkgen.mujoco.settings import Scales

# The error a settling window must decay to, relative to the quantity's scale: a tenth of the
# comparison tolerance (compare.REL_TOL = 1e-6).
SETTLE_TARGET = 1e-7
# The lead-in before each segment costs only steps, no samples: it is aimed 1000× lower, which
# near an assembly limit the start transient needs (seven-link 5° from its limit, τ = 0.1 ms:
# first sample 1.9e-6 with a lead-in for 1e-7, 7.1e-7 with one for 1e-10).
LEAD_TARGET = 1e-10


def settle_window(settings: Settings, scales: Scales | None, epsilon: float, target: float = SETTLE_TARGET,
                  gravity: float = 0.0) -> float:
    """Time [s] after a start or a load step until the loop's transient has decayed to
    SETTLE_TARGET of the quantities' scales.

    A connect answers a step in its load like a critically damped oscillator of time constant
    τ: the error right after the step is (1 − d) times the loop acceleration a0 (the part the
    soft constraint lets through), and it decays as (1 + t/τ)·e^(−t/τ). Relative to the
    accelerations' scale size·(ω² + |ε|) + |g|, and amplified by 1/σ where the loops are
    ill-conditioned, this gives e0; the window is the t where the envelope brings e0 down to
    SETTLE_TARGET (at least 1 τ). Where a loop direction gets only a share ρ of the soft model
    (``Scales.loop_share``, ``mujoco.loop_modes``) its mode decays at the slower rate
    ``loop_modes.decay_rate``, and the window is counted in that mode's time constants."""
    d = settings.solimp[0] if settings.solimp else settings.impedance
    if scales is None:
        e0 = 1.0 - d
    else:
        a_scale = acceleration_scale(scales.size, scales.omega, epsilon, gravity)
        e0 = (1.0 - d) * max(1.0, scales.loop_acceleration / max(a_scale, 1e-300)) / min(1.0, scales.sigma_min)
    target = target / e0
    x = 1.0
    if target < 1.0:
        lo, hi = 0.0, 200.0
        for _ in range(100):  # (1 + x)·e^(−x) decreases monotonically for x > 0
            x = 0.5 * (lo + hi)
            lo, hi = (x, hi) if (1 + x) * math.exp(-x) > target else (lo, x)
        x = hi
    share = getattr(scales, "loop_share", 1.0) if scales is not None else 1.0
    slowest = min(decay_rate(settings, share), 1.0 / settings.timeconst) if share < 1.0 else 1.0 / settings.timeconst
    return max(1.0, x) / slowest


def crank_time(phi: np.ndarray, phi0: float, omega: float, eps: float) -> np.ndarray:
    """Time [s] at which the crank, at φ0 with speed ω at t = 0 and acceleration ε, reaches φ."""
    dphi = np.asarray(phi, dtype=float) - phi0
    if eps == 0.0:
        return dphi / omega
    disc = omega * omega + 2.0 * eps * dphi
    if np.any(disc <= 0):
        raise SimulationError(f"with ε = {eps:g} rad/s² the crank stops before it covers the range")
    return (np.sqrt(disc) - omega) / eps


def crank_phi(t, phi0: float, omega: float, eps: float):
    return phi0 + omega * np.asarray(t) + 0.5 * eps * np.asarray(t) ** 2


def switch_angles(mech, phi_a: float, phi_b: float) -> list[float]:
    """Crank angles in [φa, φb] where a stroke-limited force switches on or off."""
    out = []
    for f in mech.forces:
        if f.stroke is None or f.stroke[1] - f.stroke[0] >= 2 * math.pi:
            continue
        for edge in f.stroke:
            k = math.ceil((phi_a - edge) / (2 * math.pi))
            a = edge + 2 * math.pi * k
            while a <= phi_b:
                out.append(a)
                a += 2 * math.pi
    return sorted(out)


__all__ = ["LEAD_TARGET", "SETTLE_TARGET", "crank_phi", "crank_time", "settle_window", "switch_angles"]
