"""MuJoCo joint state (qpos, qvel) of a spatial four-bar from the closed form, and MuJoCo
settings derived from the mechanism the same way as for planar linkages
(``linkgen.mujoco.settings``): the loop's time constant from the loop force it must carry and
the crank speed, the timestep from the time constant, the rotor from the peak reduced inertia."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from linkgen.mujoco.options import IMPEDANCE, Settings
from linkgen.mujoco.settings import ARMATURE_RATIO, GAP_TARGET, PHASE, STEPS_PER_TAU, round_down
from linkgen.families.spatial.chain import Chain
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.kinematics import SpatialMotion
from linkgen.families.spatial.forces import check_line_moments
from linkgen.families.spatial.mass import link_body
from linkgen.mujoco.spatial_loads import loads_at_state
from linkgen.mujoco.spatial_names import closing_body, slide_joint, weld_lever

# Crank angles scanned for the peak reduced inertia and loop force.
SCAN = 73


def _hinge_angle(rel: np.ndarray, axis: np.ndarray) -> float:
    """The angle of a rotation ``rel`` (3, 3) about ``axis`` (a rotation about that axis)."""
    vee = np.array([rel[2, 1] - rel[1, 2], rel[0, 2] - rel[2, 0], rel[1, 0] - rel[0, 1]]) / 2
    return math.atan2(float(vee @ axis), (float(np.trace(rel)) - 1) / 2)


def cylinder_state(model: mujoco.MjModel, chain: Chain, motion: SpatialMotion, k: int, omega: float,
                   epsilon: float = 0.0) -> tuple:
    """qpos, qvel, qacc of an RCCC at sample ``k`` with the crank at ω [rad/s] and ε [rad/s²]:
    each cylindrical pair's hinge (the relative turn about its axis: q′ = (Ω′_C − Ω′_P)·u,
    q″ = (Ω″_C − Ω″_P)·u + (Ω′_C − Ω′_P)·(Ω′_P × u), the axis u carried by the parent P) and
    slide (the pair's slide jet)."""
    qpos, qvel, qacc = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
    fr, sp = motion.frames, motion.spin
    j = model.joint(chain.drive)
    qpos[j.qposadr[0]], qvel[j.dofadr[0]], qacc[j.dofadr[0]] = motion.phi[k] - chain.phi_s, omega, epsilon
    eye, zero = np.eye(3), (np.zeros((motion.phi.shape[0], 3)),) * 2
    for pair, parent, child, axis in ((chain.pair_a, chain.crank, chain.coupler, chain.ua),
                                      (chain.pair_b, chain.coupler, chain.output, chain.ub),
                                      (chain.pair_out, None, chain.output, chain.kb)):
        rp = fr[parent][k] if parent else eye
        u = rp @ axis
        (p1, p2), (c1, c2) = (sp[parent] if parent else zero), sp[child]
        d1 = float((c1[k] - p1[k]) @ u)
        d2 = float((c2[k] - p2[k]) @ u + (c1[k] - p1[k]) @ np.cross(p1[k], u))
        h = model.joint(pair)
        qpos[h.qposadr[0]] = _hinge_angle(rp.T @ fr[child][k], axis)
        qvel[h.dofadr[0]], qacc[h.dofadr[0]] = d1 * omega, d2 * omega**2 + d1 * epsilon
        t = motion.slides[pair].d
        s = model.joint(slide_joint(pair))
        qpos[s.qposadr[0]] = t[0][k]
        qvel[s.dofadr[0]], qacc[s.dofadr[0]] = t[1][k] * omega, t[2][k] * omega**2 + t[1][k] * epsilon
    return qpos, qvel, qacc


def joint_state(model: mujoco.MjModel, chain: Chain, motion: SpatialMotion, k: int, omega: float) -> tuple:
    """qpos, qvel at sample ``k`` of ``motion`` with the crank at ω [rad/s]."""
    if chain.kind == "RCCC":
        return cylinder_state(model, chain, motion, k, omega)[:2]
    qpos, qvel = np.zeros(model.nq), np.zeros(model.nv)
    fr, sp = motion.frames, motion.spin
    j = model.joint(chain.drive)
    qpos[j.qposadr[0]] = motion.phi[k] - chain.phi_s
    qvel[j.dofadr[0]] = omega
    rk, rc = fr[chain.crank][k], fr[chain.coupler][k]
    rel = rk.T @ rc
    w_rel = (sp[chain.coupler][0][k] - sp[chain.crank][0][k]) * omega  # world axes
    j = model.joint(chain.pair_a)
    if chain.ua is None:  # ball: quaternion of the coupler in the crank's frame; qvel in the coupler's frame
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, rel.reshape(-1))
        qpos[j.qposadr[0]:j.qposadr[0] + 4] = quat
        qvel[j.dofadr[0]:j.dofadr[0] + 3] = rc.T @ w_rel
    else:
        qpos[j.qposadr[0]] = _hinge_angle(rel, chain.ua)
        qvel[j.dofadr[0]] = float(w_rel @ (rk @ chain.ua))
    j = model.joint(chain.pair_out)
    qpos[j.qposadr[0]] = motion.turn.d[0][k]
    qvel[j.dofadr[0]] = motion.turn.d[1][k] * omega
    return qpos, qvel


def loop_name(chain: Chain) -> str:
    """The equality that closes the loop: the connect at B, or an RCCC's weld."""
    return closing_body(chain) if chain.kind == "RCCC" else chain.pair_b


def reduced_inertia(mech: SpatialMechanism, motion: SpatialMotion) -> np.ndarray:
    """J(φ) = 2T/ω² (n,) [kg·m²]: Σ m·|c′|² + Ω′ᵀ·I·Ω′ over the moving links."""
    chain = motion.chain
    out = np.zeros(motion.phi.shape[0])
    for link in (chain.crank, chain.coupler, chain.output):
        mass, c, inertia = link_body(mech, motion, link)
        w1 = motion.spin[link][0]
        out += mass * np.einsum("ij,ij->i", c.d[1], c.d[1]) + np.einsum("ni,nij,nj->n", w1, inertia, w1)
    return out


def phase_time(mech: SpatialMechanism, chain: Chain, omega: float) -> float:
    """τ_phase [s]: PHASE radians of crank at |ω| (a slider input: PHASE of its input unit, the
    chain's size, at its speed); at ω = 0 PHASE of the time the mechanism
    falls by its size under gravity, √(size/|g|); with neither, PHASE of a second (nothing
    moves or loads the loop: any time constant holds it)."""
    if omega != 0.0:
        return PHASE * chain.input_unit / abs(omega)
    g = float(np.linalg.norm(mech.gravity))
    return PHASE * math.sqrt(chain.size / g) if g > 0.0 else PHASE * 1.0


def derive_settings(mech: SpatialMechanism, chain: Chain, scan: SpatialMotion, model: mujoco.MjModel,
                    omega: float) -> tuple[Settings, dict]:
    """Settings for a run at crank speed ω: τ = min(τ_gap, τ_phase) (``phase_time``) with τ_gap putting the
    predicted loop gap (1 − d)·d·τ²·a0 at GAP_TARGET of the size (a0 the peak of MuJoCo's
    A_diag·λ over the scanned closed-form states), dt = τ/STEPS_PER_TAU, the rotor
    ARMATURE_RATIO times the peak reduced inertia. Returns the settings and what they came from."""
    check_line_moments(mech, scan)  # a load MuJoCo's coupler would spin on: refused before any model is used
    j_peak = float(reduced_inertia(mech, scan).max())
    armature = round_down(ARMATURE_RATIO * max(j_peak, 1e-300))
    model.dof_armature[model.joint(chain.drive).dofadr[0]] = armature
    data = mujoco.MjData(model)
    a0 = 0.0
    eq = model.equality(loop_name(chain)).id
    lever = max(float(np.linalg.norm(chain.B - chain.b0)), weld_lever(mech, chain)) if chain.kind == "RCCC" else 0.0
    for k in range(scan.phi.shape[0]):
        data.qpos[:], data.qvel[:] = joint_state(model, chain, scan, k, omega)
        loads_at_state(mech, model, data, float(scan.phi[k]))  # the loop carries the loads as well
        mujoco.mj_forward(model, data)
        rows = np.flatnonzero((data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY) & (data.efc_id == eq))
        # an RCCC's weld: its translation at the anchor and its rotation over the output's lever
        a = np.abs(data.efc_diagA[rows] * data.efc_force[rows])
        a0 = max(a0, float(a[:3].max(initial=0.0)) + lever * float(a[3:].max(initial=0.0)))
    tau_phase = phase_time(mech, chain, omega)
    tau_gap = math.sqrt(GAP_TARGET * chain.size / ((1 - IMPEDANCE) * IMPEDANCE * a0)) if a0 > 0 else math.inf
    tau = round_down(min(tau_phase, tau_gap))
    dt = round_down(tau / STEPS_PER_TAU)
    settings = Settings(timestep=dt, timeconst=tau, armature=armature)
    return settings, {"reduced_inertia": j_peak, "loop_acceleration": a0, "tau_gap": tau_gap, "tau_phase": tau_phase}


__all__ = ["cylinder_state", "derive_settings", "joint_state", "loop_name", "phase_time", "reduced_inertia"]
