"""The closed-form state in MuJoCo's coordinates: qpos, qvel, qacc of the tree joints."""

from __future__ import annotations

import mujoco
import numpy as np

from linkgen.families.planar.description import Mechanism
from linkgen.families.planar.geometry import guide_shapes, link_shapes
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.pose import LinkStates, reference_pose, state
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.spring_loads import winding
from linkgen.mujoco.tree import spanning_tree


def joint_states(asm: Assembly, model: mujoco.MjModel, phi: np.ndarray, omega: np.ndarray,
                 epsilon: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model's qpos (m, nq), qvel (m, nv) and qacc (m, nv) from the closed form at crank
    angles φ (m,) [rad], speeds ω (m,) [rad/s] and accelerations ε (m,) [rad/s²]; a hinge's angle
    counted from the reference pose along the motion (``spring_loads.winding``), as in a run."""
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
            # continuous from the reference pose as MuJoCo's own hinge is (a torsion spring on it
            # winds): the turns the child makes against the parent per crank turn, times the turn
            turned = winding(asm, parent, child) * (phi - asm.sketch_phi)
            qpos[:, j.qposadr[0]] = np.remainder(rel[:m] - rel[m] - turned + np.pi, 2 * np.pi) - np.pi + turned
        else:
            sign = 1.0 if child == asm.guides[pair.name].slider else -1.0
            s = kin.sliders[pair.name]
            qpos[:, j.qposadr[0]] = sign * (s.v[:m] - s.v[m])
            d1, d2 = sign * s.d1[:m], sign * s.d2[:m]
        qvel[:, j.dofadr[0]] = d1 * omega
        qacc[:, j.dofadr[0]] = d2 * omega * omega + d1 * epsilon
    _unwrap_gears(asm.mechanism, model, qpos, phi - asm.sketch_phi)
    return qpos, qvel, qacc


def _unwrap_gears(mech: Mechanism, model: mujoco.MjModel, qpos: np.ndarray, turned: np.ndarray) -> None:
    """A gear coupling ties the raw hinge angles, q_pin = (k − 1)·q_crank: the crank's q is
    the angle turned from the reference pose (not wrapped), and each planet's pin follows it."""
    if not mech.gears:
        return
    drive = model.joint(mech.drive.joint).qposadr[0]
    qpos[:, drive] = turned
    for g in mech.gears:
        pin = next(r.name for r in mech.revolutes
                   if r.point == mech.link(g.planet).points[0] and set(r.links) == {mech.crank, g.planet})
        qpos[:, model.joint(pin).qposadr[0]] = (g.ratio - 1.0) * turned


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


def tree_state(mech: Mechanism, model, phi, omega=0.0) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo qpos (m, nq) and qvel (m, nv) of ``write_mjcf(mech)``'s model at crank angles φ (m,)
    [rad] and speeds ω [rad/s], from ``state``: the initial state of a run for any structure class.
    A hinge's q is the child's angle less the parent's, from the reference pose; a slide's q the
    slider's displacement along the guide line from the reference (negated when the guide is the
    child body, as the joint then moves the guide)."""
    st, ref = state(mech, phi, omega), reference_pose(mech)
    m = st.phi.shape[0]
    qpos, qvel = np.tile(model.qpos0, (m, 1)), np.zeros((m, model.nv))
    guides = guide_shapes(mech, link_shapes(mech))
    turns = _turns(mech)
    for parent, child, pair in spanning_tree(mech).tree:
        j = model.joint(pair.name)
        if pair.kind == "R":
            rel = st.angle[child] - st.angle[parent] - (ref.angle[child][0] - ref.angle[parent][0])
            turned = turns(parent, child) * (st.phi - ref.phi[0])  # continuous, as joint_states and a run count it
            q = np.remainder(rel - turned + np.pi, 2 * np.pi) - np.pi + turned
            qd = st.angular_velocity[child] - st.angular_velocity[parent]
        else:
            g = guides[pair.name]
            sign = 1.0 if child == g.slider else -1.0
            q0, _ = _slide(ref, g)
            s, sd = _slide(st, g)
            q, qd = sign * (s - q0[0]), sign * sd
        qpos[:, j.qposadr[0]], qvel[:, j.dofadr[0]] = q, qd
    _unwrap_gears(mech, model, qpos, st.phi - ref.phi[0])
    return qpos, qvel


def _turns(mech: Mechanism):
    """(parent, child) → the turns the child makes against the parent per crank turn
    (``spring_loads.winding``) for a class-II mechanism; 0 where it has no Assur groups (class
    III: its hinges are counted within ±π of the reference)."""
    from linkgen.errors import LinkgenError
    from linkgen.families.planar.assembly import assemble

    try:
        asm = assemble(mech)
    except LinkgenError:
        return lambda parent, child: 0
    return lambda parent, child: winding(asm, parent, child)


def _slide(st: LinkStates, g) -> tuple[np.ndarray, np.ndarray]:
    """A prismatic pair's displacement along its guide line [m] and its rate [m/s], (m,) each."""
    th = st.angle[g.guide] + g.alpha
    u = np.column_stack([np.cos(th), np.sin(th)])
    d = st.point(g.slider, g.point) - st.point(g.guide, g.base)
    dv = st.point_velocity(g.slider, g.point) - st.point_velocity(g.guide, g.base)
    w = st.angular_velocity[g.guide]
    return np.sum(d * u, axis=1), np.sum(dv * u, axis=1) + w * (d[:, 1] * u[:, 0] - d[:, 0] * u[:, 1])
