"""Joint reactions and the driving torque read from MuJoCo, by two routes.

Forward route (a simulated state after ``mj_forward`` + ``mj_rnePostConstraint``):
    * a tree joint's reaction is its child body's ``cfrc_int`` (the parent's force on the
      child, a torque:force pair about the tree root's subtree centre of mass, world axes);
      for a slide joint the torque is shifted to the slider's point to give the moment;
    * a loop-closing revolute's reaction is its ``connect`` row block of ``efc_force``
      (world frame; the force on body1, minus it on body2);
    * the balancing torque is the motor's force minus the driven joint's armature·q̈ (the
      rotor's share).

Inverse route (the closed-form q, q̇, q̈ through ``mj_inverse``): the constraints hold
exactly, so ``efc_force`` ≈ 0 and ``qfrc_inverse`` carries nearly everything; the loop forces λ
and the motor torque follow from qfrc_inverse + qfrc_constraint − Jᵀ·xfrc = J_loopᵀ·λ + e_drive·τ
(a square n × n system), and the
tree reactions from ``mj_rnePostConstraint`` with λ applied as body forces.

Springs and dampers (``mujoco.springs``) are MuJoCo's own passive forces: ``mj_inverse`` leaves
``qfrc_passive`` out of ``qfrc_inverse`` and the forward run integrates it, so λ and the motor's
torque are the closed form's with the springs as loads; a torsion spring's joint torques are put
on its links for the tree reactions (``spring_wrenches``).

Planar loops closed by ``connect`` leave the force along the parallel hinge axes (z)
undetermined, so only in-plane components are read. External loads enter MuJoCo as
``xfrc_applied`` computed from MuJoCo's own positions (``apply_loads``).

Results use the sign conventions of ``linkgen.kinetostatics``.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.loads import applied_loads, stroke_active
from linkgen.mujoco.tree import DRIVE_ACTUATOR, TreeInfo, body_name, link_name, site_name, spanning_tree
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.loops import closure_jacobian
from linkgen.mujoco.springs import has_springs, spring_wrenches


@dataclass(frozen=True)
class StateForces:
    """Forces at one state: balancing torque [N·m], revolute reactions {name: (2,) [N]},
    prismatic normal forces {name: N [N]} and moments {name: M [N·m]}."""

    balancing_torque: float
    reactions: dict[str, np.ndarray]
    normal_force: dict[str, float]
    moment: dict[str, float]


def apply_loads(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData, phi: float, epsilon=None) -> None:
    """Set ``xfrc_applied`` from the description's forces and torques at crank angle φ [rad]
    (the stroke test), at MuJoCo's current positions (needs ``mj_kinematics`` done), and the
    pairs' friction (``mujoco.friction``: the closed form's at φ, MuJoCo's crank speed and
    ``epsilon``, default the drive's)."""
    mech = asm.mechanism
    data.xfrc_applied[:] = 0.0
    if mech.frictions:
        from linkgen.mujoco.friction import add_friction, friction_at

        w = float(data.qvel[model.joint(mech.drive.joint).dofadr[0]])
        e = mech.drive.epsilon if epsilon is None else epsilon
        add_friction(asm, model, data, {k: v[0] for k, v in friction_at(asm, phi, w, e).items()})
    for f in mech.forces:
        if f.link == GROUND or not stroke_active(f, np.array([phi]))[0]:
            continue
        add_force(data, model.body(body_name(f.link)).id, data.site(site_name(asm, f.link, f.point)).xpos,
                   np.array([f.force[0], f.force[1], 0.0]))
    for t in mech.torques:
        if t.link != GROUND:
            data.xfrc_applied[model.body(body_name(t.link)).id, 5] += t.torque


def add_force(data: mujoco.MjData, body: int, point: np.ndarray, force: np.ndarray) -> None:
    """Add a force (3,) [N] acting at a world point to the body's ``xfrc_applied`` (at its COM)."""
    data.xfrc_applied[body, :3] += force
    data.xfrc_applied[body, 3:] += np.cross(point - data.xipos[body], force)


def applied_generalized(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Jᵀ·xfrc_applied (nv,): the generalised force of the body wrenches now set (positions and
    ``mj_comPos`` done)."""
    out = np.zeros(model.nv)
    for b in range(1, model.nbody):
        if np.any(data.xfrc_applied[b]):
            mujoco.mj_applyFT(model, data, data.xfrc_applied[b, :3], data.xfrc_applied[b, 3:], data.xipos[b], b, out)
    return out


def has_loads(asm: Assembly) -> bool:
    m = asm.mechanism
    return any(f.link != GROUND for f in m.forces) or any(t.link != GROUND for t in m.torques) or bool(m.frictions)


def forward_forces(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData) -> StateForces:
    """Forces at the current state; ``mj_forward`` and ``mj_rnePostConstraint`` must have run."""
    info = spanning_tree(asm)
    if has_springs(asm.mechanism):  # the springs' passive forces on the bodies, for cfrc_int (mujoco.springs)
        given = data.xfrc_applied.copy()
        data.xfrc_applied[:] += spring_wrenches(asm.mechanism, model, data)
        mujoco.mj_rnePostConstraint(model, data)
        data.xfrc_applied[:] = given
    reactions, normal, moment = _tree_reactions(asm, model, data, info)
    for pair in info.closures:
        eq = model.equality(pair.name).id
        rows = np.flatnonzero((data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY) & (data.efc_id == eq))
        lam = data.efc_force[rows[:2]]
        reactions[pair.name] = _on_first(asm, model, eq, pair.name, lam)
    crank = model.joint(asm.mechanism.drive.joint)
    rotor = model.dof_armature[crank.dofadr[0]]
    torque = float(data.actuator(DRIVE_ACTUATOR).force[0] - rotor * data.qacc[crank.dofadr[0]])
    return StateForces(torque, reactions, normal, moment)


@no_log_file()
def inverse_forces(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData, phi: float,
                   qpos: np.ndarray, qvel: np.ndarray, qacc: np.ndarray) -> StateForces:
    """Forces from inverse dynamics at the given (closed-form) state; see the module docstring."""
    info = spanning_tree(asm)
    data.qpos[:], data.qvel[:], data.qacc[:] = qpos, qvel, qacc
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    apply_loads(asm, model, data, phi, float(qacc[model.joint(asm.mechanism.drive.joint).dofadr[0]]))
    mujoco.mj_inverse(model, data)
    applied = applied_generalized(model, data)
    crank = model.joint(asm.mechanism.drive.joint)
    cols = list(closure_jacobian(asm, model, data))
    anchors = []
    for pair in info.closures:
        eq = model.equality(pair.name).id
        b1, b2 = model.eq_obj1id[eq], model.eq_obj2id[eq]
        point = data.site(site_name(asm, link_name(model.body(b1).name), asm.mechanism.revolute(pair.name).point)).xpos.copy()
        anchors.append((pair, eq, b1, b2, point))
    drive = np.zeros(model.nv)
    drive[crank.dofadr[0]] = 1.0
    for g in asm.mechanism.gears:  # a gear coupling: q_pin − (k − 1)·q_crank = 0, a torque pair
        col = np.zeros(model.nv)
        col[model.joint(model.eq_obj1id[model.equality(f"gear:{g.name}").id]).dofadr[0]] = 1.0
        col[crank.dofadr[0]] -= g.ratio - 1.0
        cols.append(col)
    k = np.column_stack(cols + [drive])
    # qfrc_inverse excludes what the soft constraints push (efc_force ≈ 0, not exactly 0 with
    # R > 0): add it back so that λ carries all of the loop's force.
    x = np.linalg.solve(k, data.qfrc_inverse + data.qfrc_constraint - applied)
    # Tree reactions: the loop forces become body forces, the constraint solver's share is zero.
    data.efc_force[:] = 0.0
    reactions = {}
    for i, (pair, eq, b1, b2, point) in enumerate(anchors):
        lam = x[2 * i:2 * i + 2]
        f = np.array([lam[0], lam[1], 0.0])
        add_force(data, b1, point, f)
        if b2 > 0:
            add_force(data, b2, point, -f)
        reactions[pair.name] = _on_first(asm, model, eq, pair.name, lam)
    if has_springs(asm.mechanism):  # the springs' passive forces on the bodies, for cfrc_int (mujoco.springs)
        data.xfrc_applied[:] += spring_wrenches(asm.mechanism, model, data)
    mujoco.mj_rnePostConstraint(model, data)
    tree_r, normal, moment = _tree_reactions(asm, model, data, info)
    reactions |= tree_r
    torque = float(x[-1] - model.dof_armature[crank.dofadr[0]] * qacc[crank.dofadr[0]])
    return StateForces(torque, reactions, normal, moment)


def _on_first(asm: Assembly, model, eq: int, name: str, lam: np.ndarray) -> np.ndarray:
    """A connect's force on body1 as the force of the pair's second link on its first."""
    first = asm.mechanism.revolute(name).links[0]
    body1 = link_name(model.body(model.eq_obj1id[eq]).name)
    return np.array(lam[:2], dtype=float) * (1.0 if body1 == first else -1.0)


def _tree_reactions(asm: Assembly, model, data, info: TreeInfo):
    mech = asm.mechanism
    reactions, normal, moment = {}, {}, {}
    for parent, child, pair in info.tree:
        b = model.body(body_name(child)).id
        torque, force = data.cfrc_int[b, :3], data.cfrc_int[b, 3:]
        if pair.kind == "R":
            sign = 1.0 if mech.revolute(pair.name).links[0] == child else -1.0
            reactions[pair.name] = sign * force[:2].copy()
            continue
        g = asm.guides[pair.name]
        u = data.joint(pair.name).xaxis[:2]
        nrm = np.array([-u[1], u[0]])
        point = data.site(site_name(asm, g.slider, mech.prismatic(pair.name).point)).xpos
        c0 = data.subtree_com[model.body_rootid[b]]
        d = c0 - point
        m_point = torque[2] + d[0] * force[1] - d[1] * force[0]  # the couple about the slider's point
        sign = 1.0 if child == g.slider else -1.0
        normal[pair.name] = float(sign * (force[:2] @ nrm))
        moment[pair.name] = float(sign * m_point)
    return reactions, normal, moment


@dataclass(frozen=True)
class ForceSamples:
    """StateForces over m samples: balancing_torque (m,), reactions {name: (m, 2)},
    normal_force and moment {name: (m,)}."""

    balancing_torque: np.ndarray
    reactions: dict[str, np.ndarray]
    normal_force: dict[str, np.ndarray]
    moment: dict[str, np.ndarray]

    @staticmethod
    def stack(states: list[StateForces]) -> "ForceSamples":
        first = states[0]
        return ForceSamples(
            np.array([s.balancing_torque for s in states]),
            {k: np.array([s.reactions[k] for s in states]) for k in first.reactions},
            {k: np.array([s.normal_force[k] for s in states]) for k in first.normal_force},
            {k: np.array([s.moment[k] for s in states]) for k in first.moment},
        )


def load_schedule(asm: Assembly, model: mujoco.MjModel, phi: np.ndarray, omega=None, epsilon=None,
                  friction: bool = True) -> np.ndarray:
    """``xfrc_applied`` rows (n, 6·nbody) for crank angles φ (n,) [rad], from the closed-form
    positions: the open-loop input ``rollout`` needs. Per-sample values are recomputed from MuJoCo's
    own positions by ``apply_loads``; this only feeds the stepping. Gravity and the springs
    (tendons, joint springs: ``mujoco.springs``) are MuJoCo's own; the pairs' friction
    (``mujoco.friction``) is the closed form's at crank speed ``omega`` (scalar or (n,)) and
    ``epsilon`` (default the drive's); ``friction`` False leaves it out (a machine applies its
    own at each state: ``mujoco.machine``)."""
    mech = asm.mechanism
    out = np.zeros((phi.shape[0], model.nbody, 6))
    # marked: a run's lead-in may start a little before a range that ends at a dead centre (its
    # steps there only settle the run, their loads are not compared)
    for name, load in applied_loads(asm, solve(asm, phi, on_singular="mark"), gravity=False, springs=False).items():
        b = model.body(body_name(name)).id
        out[:, b, 0:2], out[:, b, 5] = load.force, load.moment
    if mech.frictions and friction:  # added to the loads just set
        from linkgen.mujoco.friction import friction_schedule

        w = mech.drive.omega if omega is None else omega
        out += friction_schedule(asm, model, phi, w, mech.drive.epsilon if epsilon is None else epsilon)
    return out.reshape(phi.shape[0], -1)


__all__ = ["ForceSamples", "StateForces", "add_force", "applied_generalized", "apply_loads", "forward_forces",
           "has_loads", "inverse_forces", "load_schedule"]
