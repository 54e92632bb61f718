"""Motor laws on the motor shaft: torque [N·m] from the shaft speed ω [rad/s] (and, for the DC
motor, the armature current i [A], whose rate is ``dc_current_rate``).

- none: M = 0 (no motor: free motion under the loads).
- constant: M = torque.
- linear static characteristic: M = M0·(1 − ω/ω0).
- induction motor, Kloss's formula from catalogue data: synchronous speed ω_s, rated slip s_n,
  rated power P (rated torque M_n = P/(ω_s·(1 − s_n))), breakdown ratio λ = M_k/M_n; the
  breakdown slip s_k = s_n·(λ + √(λ² − 1)) and M = 2·M_k/(s/s_k + s_k/s), s = (ω_s − ω)/ω_s.
- DC motor with electrical lag: L·di/dt = U − R·i − k_e·ω, M = k_t·i. (The textbook's scaled
  ``D``/``Dvig`` classes are this circuit with U = Uo, R = Rpr, L = Lpr in units where k_e = 1,
  the rotor speed divided by ``kw`` and the torque multiplied by ``km``: k_e = 1/kw, k_t = km.)
"""

from __future__ import annotations

import math

import numpy as np

from linkgen.model.machine import Motor


def kloss_constants(m: Motor) -> tuple[float, float]:
    """Breakdown torque M_k [N·m] and breakdown slip s_k of an induction motor."""
    ws, sn, lam = m.synchronous_speed, m.rated_slip, m.breakdown_ratio
    m_rated = m.rated_power / (ws * (1.0 - sn))
    return lam * m_rated, sn * (lam + math.sqrt(lam * lam - 1.0))


def torque(m: Motor, omega, current=None):
    """Motor torque [N·m] at shaft speed ω [rad/s] (scalar or array); ``current`` [A] for dc."""
    omega = np.asarray(omega, dtype=float)
    if m.kind == "none":
        return np.zeros_like(omega)
    if m.kind == "constant":
        return np.full_like(omega, m.torque)
    if m.kind == "linear":
        return m.stall_torque * (1.0 - omega / m.no_load_speed)
    if m.kind == "induction":
        mk, sk = kloss_constants(m)
        s = (m.synchronous_speed - omega) / m.synchronous_speed
        return 2.0 * mk * s * sk / (s * s + sk * sk)  # = 2·M_k/(s/s_k + s_k/s), finite at s = 0
    if m.kind == "dc":
        return m.torque_constant * np.asarray(current, dtype=float)
    raise ValueError(m.kind)


def dc_current_rate(m: Motor, omega, current):
    """di/dt [A/s] of the DC motor's armature at shaft speed ω and current i."""
    return (m.voltage - m.resistance * current - m.emf_constant * omega) / m.inductance


def has_current(m: Motor) -> bool:
    """Whether the motor carries a current state (a DC motor with inductance > 0)."""
    return m.kind == "dc" and m.inductance > 0.0


def dc_static_current(m: Motor, omega):
    """The armature current without inductance: (U − k_e·ω)/R."""
    return (m.voltage - m.emf_constant * np.asarray(omega, dtype=float)) / m.resistance


__all__ = ["dc_current_rate", "dc_static_current", "has_current", "kloss_constants", "torque"]
