"""The balancing torque and the loop force by MuJoCo's inverse dynamics at closed-form states.

At each crank angle the closed form gives q, q̇ and q̈ of every MuJoCo joint (the ball's q̇ and q̈
are the coupler's angular velocity relative to the crank in the coupler's frame and its time
derivative). ``mj_inverse`` returns the generalised force the state needs; the loop force λ at
the closing ``connect`` and the drive torque τ follow from

    qfrc_inverse + qfrc_constraint − Jᵀ·xfrc = J_loopᵀ·λ + e_drive·τ,

solved by least squares (a coupler's idle spin adds a row 0 = 0; a 4R chain's loop has a
redundant row, so λ is then not unique but τ is). Independent of the Newton–Euler solution in
``forces``: MuJoCo's own recursive dynamics on its own model. The description's loads enter as
body wrenches at MuJoCo's positions (``spatial.mjloads``); ``mj_inverse`` returns the force the
motion needs, so their generalised force Jᵀ·xfrc is taken off.
"""

from __future__ import annotations

import mujoco
import numpy as np

from linkgen.mujoco.forces import applied_generalized
from linkgen.mujoco.log import no_log_file
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.kinematics import assembled_chain, solve
from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf
from linkgen.mujoco.spatial_loads import loads_at_state
from linkgen.mujoco.spatial_state import cylinder_state, joint_state, loop_name


def _joint_acceleration(model, chain, motion, k, omega, epsilon) -> np.ndarray:
    """q̈ at sample k for the crank at ω, ε (constant)."""
    qacc = np.zeros(model.nv)
    sp, fr = motion.spin, motion.frames
    qacc[model.joint(chain.drive).dofadr[0]] = epsilon
    w1c, w2c = sp[chain.coupler][0][k], sp[chain.coupler][1][k]
    w1k, w2k = sp[chain.crank][0][k], sp[chain.crank][1][k]
    om_c, om_k = w1c * omega, w1k * omega
    al_c, al_k = w2c * omega**2 + w1c * epsilon, w2k * omega**2 + w1k * epsilon
    j = model.joint(chain.pair_a)
    if chain.ua is None:  # d/dt (R_cᵀ·(Ω_c − Ω_k)) = R_cᵀ·(α_c − α_k − Ω_c × (Ω_c − Ω_k))
        rc = fr[chain.coupler][k]
        qacc[j.dofadr[0]:j.dofadr[0] + 3] = rc.T @ (al_c - al_k - np.cross(om_c, om_c - om_k))
    else:  # the relative angle about the crank-carried axis u_A, u_A′ = k_a × u_A
        ua = fr[chain.crank][k] @ chain.ua
        d1 = (w1c - w1k) @ ua
        d2 = (w2c - w2k) @ ua + (w1c - w1k) @ np.cross(chain.ka, ua)
        qacc[j.dofadr[0]] = d2 * omega**2 + d1 * epsilon
    t = motion.turn.d
    qacc[model.joint(chain.pair_out).dofadr[0]] = t[2][k] * omega**2 + t[1][k] * epsilon
    return qacc


@no_log_file()
def inverse_torque(mech: SpatialMechanism, phi, omega: float | None = None, epsilon: float | None = None,
                   settings=None) -> tuple[np.ndarray, np.ndarray]:
    """Balancing torque (n,) [N·m] and the loop force on the output at the closing pair (n, 3) [N]
    (an RCCC's weld: the force the coupler's half of the output passes to the other half)
    by MuJoCo's inverse dynamics at the closed-form states (rotor inertia excluded)."""
    w = mech.drive.omega if omega is None else float(omega)
    e = mech.drive.epsilon if epsilon is None else float(epsilon)
    chain = assembled_chain(mech)
    model = mujoco.MjModel.from_xml_string(write_spatial_mjcf(mech, settings, chain))
    model.dof_armature[model.joint(chain.drive).dofadr[0]] = 0.0
    data = mujoco.MjData(model)
    motion = solve(mech, np.atleast_1d(np.asarray(phi, dtype=float)), chain)
    n = motion.phi.shape[0]
    cyl = chain.kind == "RCCC"
    eq = model.equality(loop_name(chain)).id
    drive = model.joint(chain.drive).dofadr[0]
    torque, loop = np.zeros(n), np.zeros((n, 3))
    jac_p1, jac_p2 = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    jac_r1, jac_r2 = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    b1, b2 = model.eq_obj1id[eq], model.eq_obj2id[eq]
    for k in range(n):
        if cyl:
            data.qpos[:], data.qvel[:], data.qacc[:] = cylinder_state(model, chain, motion, k, w, e)
        else:
            data.qpos[:], data.qvel[:] = joint_state(model, chain, motion, k, w)
            data.qacc[:] = _joint_acceleration(model, chain, motion, k, w, e)
        loads_at_state(mech, model, data, float(motion.phi[k]))
        mujoco.mj_inverse(model, data)
        point = motion.points[chain.pair_b].d[0][k]
        mujoco.mj_jac(model, data, jac_p1, jac_r1, point, b1)
        mujoco.mj_jac(model, data, jac_p2, jac_r2, point, b2)
        jl = jac_p1 - jac_p2  # λ on body 1 (the coupler), −λ on body 2
        if cyl:  # a weld: a force and a moment
            jl = np.vstack([jl, jac_r1 - jac_r2])
        a = np.column_stack([jl.T, np.eye(model.nv)[:, drive]])
        rhs = data.qfrc_inverse + data.qfrc_constraint - applied_generalized(model, data)
        x = np.linalg.lstsq(a, rhs, rcond=1e-12)[0]
        loop[k], torque[k] = -x[:3], x[-1]
    return torque, loop


__all__ = ["inverse_torque"]
