"""MuJoCo's loop terms at one state, for the accuracy prediction (``mujoco.accuracy``): the
regularisation's diagApprox, J̇·q̇ and J̇·q̈ of each loop-closing revolute's in-plane rows, and the
forces MuJoCo reports where the loops' acceleration is imposed."""

from __future__ import annotations

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.forces import StateForces, apply_loads, forward_forces
from linkgen.mujoco.tree import link_name, site_name, spanning_tree


def forces_at(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData, qpos: np.ndarray, qvel: np.ndarray,
               a1: np.ndarray, ctrl: float, phi: float) -> StateForces:
    """MuJoCo's forces at the state (qpos, qvel) where each loop row's acceleration J·q̈ + J̇·q̇
    is ``a1`` (2·closures,) [m/s²]: the loop forces f = A⁻¹·(a1 − a0), A = J·M⁻¹·Jᵀ and a0 =
    J·q̈_smooth + J̇·q̇ from MuJoCo's forward pass there, put back into its data (q̈ = q̈_smooth +
    M⁻¹·Jᵀ·f) and read as every run's forces are read. The soft model's answer to the state's
    gap and gap velocity is what ``a1`` carries: computed from the gap's dynamics, where it is
    not amplified by the loop's stiffness (K·r, B·ṙ)."""
    data.qpos[:], data.qvel[:], data.ctrl[:] = qpos, qvel, ctrl
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    apply_loads(asm, model, data, phi)
    mujoco.mj_forward(model, data)
    closures = spanning_tree(asm).closures
    if not closures:  # nothing to impose: the tree's own forces
        mujoco.mj_rnePostConstraint(model, data)
        return forward_forces(asm, model, data)
    k, b, imp = data.efc_KBIP[:, 0], data.efc_KBIP[:, 1], data.efc_KBIP[:, 2]
    rows = np.concatenate([np.flatnonzero((data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
                                          & (data.efc_id == model.equality(pair.name).id))[:2]
                           for pair in closures])
    jac = data.efc_J.reshape(data.nefc, model.nv)[rows]
    m_inv_jt = np.zeros((rows.size, model.nv))
    mujoco.mj_solveM(model, data, m_inv_jt, jac)
    # MuJoCo puts −J̇·q̇ into the reference acceleration: aref = −B·ṙ − K·d·r − J̇·q̇
    jdv = -b[rows] * data.efc_vel[rows] - k[rows] * imp[rows] * data.efc_pos[rows] - data.efc_aref[rows]
    a0 = jac @ data.qacc_smooth + jdv
    # least squares: at a state where the loops have come apart (a predicted gap of the size's order)
    # two closure rows can be parallel, and the minimum-norm force is the one MuJoCo's solver finds
    f = np.linalg.lstsq(jac @ m_inv_jt.T, a1 - a0, rcond=None)[0]
    data.efc_force[:] = 0.0
    data.efc_force[rows] = f
    data.qfrc_constraint[:] = jac.T @ f
    data.qacc[:] = data.qacc_smooth + m_inv_jt.T @ f
    mujoco.mj_rnePostConstraint(model, data)
    return forward_forces(asm, model, data)


def diag_approx(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """MuJoCo's diagApprox of each closure's in-plane rows (2·closures,) [1/kg], recovered from
    R = (1 − d)/d·diagApprox as ``mj_makeImpedance`` set it."""
    out = []
    for pair in spanning_tree(asm).closures:
        eq = model.equality(pair.name).id
        idx = np.flatnonzero((data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY) & (data.efc_id == eq))[:2]
        imp = data.efc_KBIP[idx, 2]
        out += list(data.efc_R[idx] * imp / (1.0 - imp))
    return np.array(out, dtype=float)


def jdot(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData, qacc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """J̇·q̇ and J̇·q̈ of each closure's in-plane rows, each (2·closures,) [m/s²] (``mj_jacDot``
    at the data's velocity, body1 − body2): J̇·q̈ = H(q̇, q̈), J's second derivative along q̇ and q̈."""
    out, out_a = [], []
    j1, j2 = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    for pair in spanning_tree(asm).closures:
        eq = model.equality(pair.name).id
        b1, b2 = model.eq_obj1id[eq], model.eq_obj2id[eq]
        point = data.site(site_name(asm, link_name(model.body(b1).name), asm.mechanism.revolute(pair.name).point)).xpos
        mujoco.mj_jacDot(model, data, j1, None, point, b1)
        j2[:] = 0.0
        if b2 > 0:
            mujoco.mj_jacDot(model, data, j2, None, point, b2)
        out += list(((j1 - j2) @ data.qvel)[:2])
        out_a += list(((j1 - j2) @ qacc)[:2])
    return np.array(out, dtype=float), np.array(out_a, dtype=float)


__all__ = ["diag_approx", "forces_at", "jdot"]
