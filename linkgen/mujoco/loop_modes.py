"""How fast MuJoCo's soft loops settle: the share of the soft model each loop direction gets.

A ``connect`` row answers with a1 = P·a0 + Q·aref, Q = A·(A + R)⁻¹ (``mujoco.accuracy``), so
the gap obeys ṡ = Q·(K·d·(r_λ − r) − B·s). Along an eigenvector of Q with eigenvalue ρ the loop
is an oscillator s² + ρ·B·s + ρ·K·d = 0: where A is as large as its diagonal (ρ ≈ d) it is the
critically damped loop of rate 1/τ the settings aim at; where MuJoCo's regularisation R =
(1 − d)/d·diagApprox outweighs A in some direction (a heavy body on light rods: A's smallest
eigenvalue far below its diagonal) ρ is small, that mode's damping ratio is √(ρ/d), and a
start-up or a load step rings for about 1/ρ time constants instead of one. ``slowest_share``
finds the smallest ρ over the closed-form poses; ``decay_rate`` turns it into the slowest mode's
decay rate at given settings, which sets how long a run's lead-in and a load step's settling
window must last (``mujoco.timing.settle_window``).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.loop_terms import diag_approx
from linkgen.mujoco.loops import closure_jacobian
from linkgen.mujoco.options import Settings

# Eigenvalues of Q below this fraction of its largest belong to directions no force moves
# (dependent loop rows: A and R both nil there, pinv's null space), not to a slow mode.
NULL_SHARE = 1e-9


def slowest_share(asm: Assembly, model: mujoco.MjModel, qpos: np.ndarray, qvel: np.ndarray, impedance: float) -> float:
    """The smallest eigenvalue ρ of Q = A·(A + R)⁻¹ over the states (qpos, qvel), each (n, ·),
    with R = (1 − d)/d·diagApprox at impedance d; 1.0 where there is no loop."""
    data = mujoco.MjData(model)
    share = 1.0
    m_inv_jt = None
    for k in range(qpos.shape[0]):
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        mujoco.mj_forward(model, data)
        jac = closure_jacobian(asm, model, data)
        if jac.shape[0] == 0:
            continue
        if m_inv_jt is None or m_inv_jt.shape != jac.shape:
            m_inv_jt = np.zeros(jac.shape)
        mujoco.mj_solveM(model, data, m_inv_jt, jac)
        a = jac @ m_inv_jt.T
        r = (1.0 - impedance) / impedance * diag_approx(asm, model, data)
        rho = np.linalg.eigvals(a @ np.linalg.pinv(a + np.diag(r))).real
        live = rho[rho > NULL_SHARE * max(float(rho.max()), 1e-300)]
        if live.size:
            share = min(share, float(live.min()))
    return share


def decay_rate(settings: Settings, share: float) -> float:
    """The decay rate [1/s] of the slowest loop mode, ρ = ``share``, at ``settings``: the
    slower root's real part of s² + ρ·B·s + ρ·K·d = 0, K = 1/(d²·τ²·ζ²), B = 2/(d·τ)."""
    d = settings.solimp[1] if settings.solimp else settings.impedance
    tau, zeta = settings.timeconst, settings.dampratio
    b, kd = share * 2.0 / (d * tau), share / (d * tau * tau * zeta * zeta)
    disc = b * b - 4.0 * kd
    return 0.5 * (b - math.sqrt(disc)) if disc > 0 else 0.5 * b


__all__ = ["NULL_SHARE", "decay_rate", "slowest_share"]
