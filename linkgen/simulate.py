"""MuJoCo run of the driven crank: batch stepping with ``mujoco.rollout``, then a sampled
post-pass (``mj_forward`` + ``mj_rnePostConstraint``) that reads every quantity by name."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from .assembly import Assembly
from .errors import SimulationError
from .kinematics import solve
from .loads import stroke_active
from .mjcf import ARMATURE, DRIVE_ACTUATOR, TIMESTEP, body_name, sensor_name, spanning_tree, write_mjcf
from .mjforces import (
    ForceSamples,
    apply_loads,
    forward_forces,
    has_loads,
    load_schedule,
)
from .mjlog import no_log_file

# A run whose loop-closure gap exceeds this at any step is an error, not a result [m]:
# 100× the accuracy target of 1e-8 m, so a result is reported (and judged) up to there.
VIOLATION_LIMIT = 1e-6
WARMUP_FRACTION = 0.05  # of the run's steps, excluded from comparisons
# A load that switches on or off (a stroke's ends) is a step the soft loop closures answer
# with a transient of a few time constants (1 ms, mjcf.CONNECT_SOLREF): right after a switch the
# four-bar's accelerations are off by 1e-6, 2° of crank later by 1e-7. Samples this long after
# a switch are left out of comparisons, like the warm-up.
SETTLE_TIME = 0.005  # s


@dataclass(frozen=True)
class Samples:
    """MuJoCo quantities at sampled steps (m samples).

    ``crank`` = (φ, ω, ε) each (m,); ``points[name]`` = (pos, vel, acc) each (m, 2);
    ``links[name]`` = (angle, ang. velocity, ang. acceleration) each (m,);
    ``sliders[name]`` = (s, v, a) each (m,); ``violation`` (m,) [m]; ``drive_torque`` (m,) [N·m];
    ``forces``: joint reactions and the balancing torque (forward route, see ``linkgen.mjforces``);
    ``reduced_inertia`` (m,) [kg·m²]: q̇ᵀ·M·q̇ / ω² less the rotor's armature (kinetic energy route).
    """

    step: np.ndarray
    time: np.ndarray
    crank: tuple[np.ndarray, np.ndarray, np.ndarray]
    points: dict
    links: dict
    sliders: dict
    violation: np.ndarray
    drive_torque: np.ndarray
    forces: ForceSamples
    reduced_inertia: np.ndarray


@dataclass(frozen=True)
class Run:
    """A whole MuJoCo run: every step's time (n,), qpos (n, nq), qvel (n, nv), closure gap (n,) [m],
    and the sampled quantities."""

    model: mujoco.MjModel
    time: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    violation: np.ndarray
    samples: Samples


@no_log_file()
def build_model(asm: Assembly, timestep: float = TIMESTEP) -> mujoco.MjModel:
    if not (math.isfinite(timestep) and timestep > 0):
        raise SimulationError(f"timestep must be > 0 s, got {timestep!r}")
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm))
    model.opt.timestep = timestep
    return model


def initial_state(asm: Assembly, model: mujoco.MjModel, phi0: float, omega: float) -> tuple[np.ndarray, np.ndarray]:
    """qpos, qvel putting the mechanism at crank angle φ0 moving at ω (closed-form assembly)."""
    qpos, qvel, _ = joint_state(asm, model, phi0, omega, 0.0)
    return qpos, qvel


def joint_state(asm: Assembly, model: mujoco.MjModel, phi: float, omega: float,
                epsilon: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model's qpos (nq,), qvel (nv,) and qacc (nv,) from the closed form at crank angle
    φ [rad], speed ω [rad/s] and acceleration ε [rad/s²]."""
    qpos, qvel, qacc = joint_states(asm, model, np.array([phi]), np.array([omega]), np.array([epsilon]))
    return qpos[0], qvel[0], qacc[0]


def joint_states(asm: Assembly, model: mujoco.MjModel, phi: np.ndarray, omega: np.ndarray,
                 epsilon: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``joint_state`` for m crank states at once: φ, ω, ε each (m,) → qpos (m, nq),
    qvel (m, nv), qacc (m, nv)."""
    m = phi.shape[0]
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


def simulate(asm: Assembly, *, revolutions: float = 1.0, omega: float | None = None,
             epsilon: float | None = None, timestep: float = TIMESTEP, samples: int = 360) -> Run:
    """Drive the crank from the start of its range and record the run (see Run)."""
    return simulate_batch(asm, omegas=[omega], revolutions=revolutions, epsilon=epsilon,
                          timestep=timestep, samples=samples)[0]


@no_log_file()
def simulate_batch(asm: Assembly, *, omegas, revolutions: float = 1.0, epsilon: float | None = None,
                   timestep: float = TIMESTEP, samples: int = 360, nthread: int = 2) -> list[Run]:
    """Several crank speeds of one mechanism in one ``mujoco.rollout`` call on ``nthread`` threads.

    The run lasts until the slowest variant has covered ``revolutions`` of the drive range.
    """
    mech = asm.mechanism
    omegas = [mech.drive.omega if w is None else float(w) for w in omegas]
    eps = mech.drive.epsilon if epsilon is None else float(epsilon)
    for w in omegas:
        if not (math.isfinite(w) and w > 0):
            raise SimulationError(f"omega must be > 0 rad/s to drive the crank through its range, got {w!r}")
    span = mech.drive.stop - mech.drive.start
    full = span >= 2 * math.pi - 1e-12
    if not full and revolutions != 1.0:
        raise SimulationError(f"the crank turns only over its range of {math.degrees(span):.6g}°: revolutions must be 1")
    angle = span * revolutions
    durations = [_duration(angle, w, eps) for w in omegas]
    model = build_model(asm, timestep)
    nstep = int(math.ceil(max(durations) / timestep))
    nstate = mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    init = np.zeros((len(omegas), nstate))
    datas = [mujoco.MjData(model) for _ in range(max(1, nthread))]
    for i, w in enumerate(omegas):
        d = datas[0]
        d.qpos[:], d.qvel[:] = initial_state(asm, model, mech.drive.start, w)
        d.time = 0.0
        mujoco.mj_getState(model, d, init[i], mujoco.mjtState.mjSTATE_FULLPHYSICS)
    ctrl = np.full((len(omegas), 1, model.nu), ARMATURE * eps)
    spec = mujoco.mjtState.mjSTATE_CTRL
    switches = [np.zeros(0, dtype=int) for _ in omegas]
    if has_loads(asm):  # external loads as per-step xfrc_applied at the crank angle expected then
        t = np.arange(nstep) * timestep
        phis = [mech.drive.start + w * t + 0.5 * eps * t * t for w in omegas]
        xfrc = np.stack([load_schedule(asm, model, p) for p in phis])
        switches = [np.flatnonzero(_stroke_steps(asm, p)) + 1 for p in phis]
        ctrl = np.concatenate([np.broadcast_to(ctrl, (len(omegas), nstep, model.nu)), xfrc], axis=2)
        spec |= mujoco.mjtState.mjSTATE_XFRC_APPLIED
    state, sensordata = rollout.rollout(model, datas, init, ctrl, control_spec=spec, nstep=nstep)
    runs = []
    for i, w in enumerate(omegas):
        steps = int(math.ceil(durations[i] / timestep))
        time = state[i, :steps, 0]
        qpos = state[i, :steps, 1:1 + model.nq]
        qvel = state[i, :steps, 1 + model.nq:1 + model.nq + model.nv]
        gap = _closure_gap(asm, model, sensordata[i, :steps])
        _check(time, qpos, qvel, gap)
        runs.append(Run(model, time, qpos, qvel, gap, _sample(asm, model, time, qpos, qvel, eps, samples,
                                                                        switches[i])))
    for d in datas:
        for w in d.warning:
            if w.number:
                raise SimulationError(f"MuJoCo warned during the run ({w.number} times, last at step {w.lastinfo})")
    return runs


def _duration(angle: float, omega: float, eps: float) -> float:
    if eps == 0.0:
        return angle / omega
    disc = omega * omega + 2 * eps * angle
    if disc < 0:
        raise SimulationError(f"with ε = {eps} rad/s² the crank stops before turning {angle} rad")
    return (-omega + math.sqrt(disc)) / eps


def _closure_gap(asm: Assembly, model: mujoco.MjModel, sensordata: np.ndarray) -> np.ndarray:
    mech = asm.mechanism
    gap = np.zeros(sensordata.shape[0])
    for pair in spanning_tree(asm).closures:
        point = mech.revolute(pair.name).point
        a, b = (model.sensor(sensor_name(asm, link, point)) for link in pair.links)
        pa = sensordata[:, a.adr[0]:a.adr[0] + 3]
        pb = sensordata[:, b.adr[0]:b.adr[0] + 3]
        gap = np.maximum(gap, np.linalg.norm(pa - pb, axis=1))
    return gap


def _check(time, qpos, qvel, gap) -> None:
    bad = ~np.all(np.isfinite(qpos), axis=1) | ~np.all(np.isfinite(qvel), axis=1)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise SimulationError(f"the run diverged at step {i} (t = {time[i]:.6g} s)")
    over = gap > VIOLATION_LIMIT
    if np.any(over):
        i = int(np.argmax(over))
        raise SimulationError(
            f"a loop-closing constraint opened by {gap[i]:.3g} m (limit {VIOLATION_LIMIT:g} m) at step {i} "
            f"(t = {time[i]:.6g} s); use a smaller timestep"
        )


def _stroke_steps(asm: Assembly, phi: np.ndarray) -> np.ndarray:
    """(n-1,) True between steps where some stroke-limited force switches on or off."""
    out = np.zeros(max(phi.shape[0] - 1, 0), dtype=bool)
    for f in asm.mechanism.forces:
        if f.stroke is not None:
            on = stroke_active(f, phi)
            out |= on[1:] != on[:-1]
    return out


def _sample(asm: Assembly, model, time, qpos, qvel, eps: float, samples: int, switches: np.ndarray) -> Samples:
    mech = asm.mechanism
    first = int(len(time) * WARMUP_FRACTION)
    idx = np.unique(np.linspace(first, len(time) - 1, samples).astype(int))
    for k in switches:  # leave out the transient after a load step (SETTLE_TIME)
        idx = idx[(idx < k) | (time[idx] > time[min(k, len(time) - 1)] + SETTLE_TIME)]
    d = mujoco.MjData(model)
    crank_j = model.joint(mech.drive.joint)
    g = np.array(mech.gravity)
    out_pts = {p: np.zeros((len(idx), 3, 2)) for p in _moving_points(mech)}
    out_lnk = {l: np.zeros((len(idx), 3)) for l in mech.moving_links}
    out_sld = {n: np.zeros((len(idx), 3)) for n in asm.guides}
    crank = np.zeros((len(idx), 3))
    viol, torque = np.zeros(len(idx)), np.zeros(len(idx))
    tree = spanning_tree(asm)
    ref = solve(asm, np.array([asm.sketch_phi]))
    r6 = np.zeros(6)
    states, mv, inertia = [], np.zeros(model.nv), np.zeros(len(idx))
    for k, i in enumerate(idx):
        d.qpos[:], d.qvel[:], d.time = qpos[i], qvel[i], time[i]
        d.ctrl[:] = ARMATURE * eps
        mujoco.mj_kinematics(model, d)
        mujoco.mj_comPos(model, d)
        crank_b = d.body(body_name(mech.crank))
        apply_loads(asm, model, d, math.atan2(crank_b.xmat[3], crank_b.xmat[0]))
        mujoco.mj_forward(model, d)
        mujoco.mj_rnePostConstraint(model, d)
        states.append(forward_forces(asm, model, d))
        mujoco.mj_mulM(model, d, mv, d.qvel)
        w = d.qvel[crank_j.dofadr[0]]
        inertia[k] = float(d.qvel @ mv) / (w * w) - ARMATURE
        for p in out_pts:
            sid = model.site(p).id
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_SITE, sid, r6, 0)
            v = r6[3:5].copy()
            mujoco.mj_objectAcceleration(model, d, mujoco.mjtObj.mjOBJ_SITE, sid, r6, 0)
            out_pts[p][k] = (d.site(p).xpos[:2], v, r6[3:5] + g)  # MuJoCo reports a - g
        for l in out_lnk:
            b = d.body(body_name(l))
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_BODY, b.id, r6, 0)
            w = r6[2]
            mujoco.mj_objectAcceleration(model, d, mujoco.mjtObj.mjOBJ_BODY, b.id, r6, 0)
            out_lnk[l][k] = (math.atan2(b.xmat[3], b.xmat[0]), w, r6[2])
        for parent, child, pair in tree.tree:
            if pair.kind == "P":
                j = model.joint(pair.name)
                sign = 1.0 if child == asm.guides[pair.name].slider else -1.0
                s0 = ref.sliders[pair.name].v[0]
                out_sld[pair.name][k] = (s0 + sign * d.qpos[j.qposadr[0]], sign * d.qvel[j.dofadr[0]],
                                         sign * d.qacc[j.dofadr[0]])
        crank[k] = (out_lnk[mech.crank][k][0], d.qvel[crank_j.dofadr[0]], d.qacc[crank_j.dofadr[0]])
        viol[k] = np.abs(d.efc_pos[: d.ne]).max() if d.ne else 0.0
        torque[k] = d.actuator(DRIVE_ACTUATOR).force[0] - ARMATURE * d.qacc[crank_j.dofadr[0]]
    phi = np.unwrap(crank[:, 0])  # continuous over the run; the closed form is 2π-periodic
    return Samples(idx, time[idx], (phi, crank[:, 1], crank[:, 2]),
                   {p: tuple(a[:, j] for j in range(3)) for p, a in out_pts.items()},
                   {l: tuple(a[:, j] for j in range(3)) for l, a in out_lnk.items()},
                   {n: tuple(a[:, j] for j in range(3)) for n, a in out_sld.items()},
                   viol, torque, ForceSamples.stack(states), inertia)


def _moving_points(mech) -> list[str]:
    ground = set(mech.link("ground").points)
    return [p for p in mech.points if p not in ground]
