"""The closed-form state in MuJoCo's coordinates: qpos, qvel, qacc of the tree joints."""

from __future__ import annotations

import mujoco
import numpy as np

from .assembly import Assembly
from .kinematics import solve
from .mjcf import spanning_tree


def joint_states(asm: Assembly, model: mujoco.MjModel, phi: np.ndarray, omega: np.ndarray,
                 epsilon: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model's qpos (m, nq), qvel (m, nv) and qacc (m, nv) from the closed form at crank
    angles φ (m,) [rad], speeds ω (m,) [rad/s] and accelerations ε (m,) [rad/s²]."""
    phi = np.asarray(phi, dtype=float)
    m = phi.shape[0]
    omega = np.broadcast_to(np.asarray(omega, dtype=float), (m,))
    epsilon = np.broadcast_to(np.asarray(epsilon, dtype=float), (m,))
    kin = solve(asm, np.append(phi, asm.sketch_phi))  # the last angle is the reference pose (qpos0)
    qpos = np.tile(model.qpos0, (m, 1))
    qvel, qacc = np.zeros((m, model.nv)), np.zeros((m, model.nv))
    for parent, child, pair in spanning_tree(asm).tree:
        j = model.joint(pair.name)
        if pair.kind == "R":
            a, b = kin.links[child].angle, kin.links[parent].angle
            rel, d1, d2 = a.v - b.v, (a.d1 - b.d1)[:m], (a.d2 - b.d2)[:m]
            qpos[:, j.qposadr[0]] = np.remainder(rel[:m] - rel[m] + np.pi, 2 * np.pi) - np.pi
        else:
            sign = 1.0 if child == asm.guides[pair.name].slider else -1.0
            s = kin.sliders[pair.name]
            qpos[:, j.qposadr[0]] = sign * (s.v[:m] - s.v[m])
            d1, d2 = sign * s.d1[:m], sign * s.d2[:m]
        qvel[:, j.dofadr[0]] = d1 * omega
        qacc[:, j.dofadr[0]] = d2 * omega * omega + d1 * epsilon
    return qpos, qvel, qacc


def joint_state(asm: Assembly, model: mujoco.MjModel, phi: float, omega: float,
                epsilon: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``joint_states`` at one crank state: qpos (nq,), qvel (nv,), qacc (nv,)."""
    qpos, qvel, qacc = joint_states(asm, model, np.array([phi]), np.array([omega]), np.array([epsilon]))
    return qpos[0], qvel[0], qacc[0]


def initial_state(asm: Assembly, model: mujoco.MjModel, phi0: float, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """qpos, qvel putting the mechanism at crank angle φ0 moving at ω (closed-form assembly)."""
    qpos, qvel, _ = joint_state(asm, model, phi0, omega, 0.0)
    return qpos, qvel


__all__ = ["initial_state", "joint_state", "joint_states"]
