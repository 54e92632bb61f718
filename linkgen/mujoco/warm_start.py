"""A run's first state with its loops open by the gap they settle to, not closed.

Held by the closed form's loop force λ, a soft ``connect`` settles on the gap r = −R·λ/(K·d)
(``mujoco.gap_dynamics.quasi_static_gap``). A run that starts with its loops closed has to open
them first: that start-up transient rings in the loops' slowest mode (``mujoco.loop_modes``),
which a heavy body on light rods or a slow crank under gravity keeps for many time constants,
and a large settled gap (a run coarsened to its step budget) also drags the free crank rotor
off its speed while it opens. ``settled_start`` moves the non-driven joints by J_nc⁺·r (J_nc the
loop Jacobian without the crank column) so that the run starts where the loops settle; the
transient left is the quasi-static model's own error (the gap's lag, ~2·ζ·τ·ω of the gap).
"""

from __future__ import annotations

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinetostatics import forces
from linkgen.mujoco.gap_dynamics import quasi_static_gap, reference_gains
from linkgen.mujoco.loop_terms import diag_approx
from linkgen.mujoco.loops import closure_forces, closure_jacobian
from linkgen.mujoco.options import Settings


def settled_start(asm: Assembly, model: mujoco.MjModel, settings: Settings, phi: float, omega: float,
                  epsilon: float, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """qpos of the closed-form state (``qpos``, ``qvel`` at crank angle φ [rad], speed ω [rad/s]
    and acceleration ε [rad/s²]) with every loop open by its quasi-static gap at ``settings``
    (``model`` has them applied: ``mujoco.settings.apply``)."""
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(model, data)
    jac = closure_jacobian(asm, model, data)
    if jac.shape[0] == 0:
        return np.array(qpos, dtype=float)
    cf = forces(asm, np.array([phi]), np.array([omega]), np.array([epsilon]))
    lam = closure_forces(asm, model, cf.reactions, 0)
    k_ref, b_ref, solimp = reference_gains(settings)
    gap, _ = quasi_static_gap(lam, diag_approx(asm, model, data), np.zeros_like(lam), k_ref, b_ref, solimp)
    if not np.all(np.isfinite(gap)):
        return np.array(qpos, dtype=float)
    drive = model.joint(asm.mechanism.drive.joint).dofadr[0]
    cols = [i for i in range(model.nv) if i != drive]  # hinge and slide joints: qpos and qvel share indices
    out = np.array(qpos, dtype=float)
    out[cols] += np.linalg.lstsq(jac[:, cols], gap, rcond=None)[0]
    return out


__all__ = ["settled_start"]
