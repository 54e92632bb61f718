"""Reading every compared quantity from MuJoCo at sampled states, by name.

At each sampled state (time, qpos, qvel) of a run: ``mj_forward`` + ``mj_rnePostConstraint``
with the run's drive torque and loads, then point, link and slider motion, the loop gap, the
forces of the forward route (``linkgen.mujoco.forces``) and the reduced inertia (kinetic energy).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.tree import DRIVE_ACTUATOR, body_name, spanning_tree
from linkgen.mujoco.forces import ForceSamples, apply_loads, forward_forces


@dataclass(frozen=True)
class Samples:
    """MuJoCo quantities at m sampled states, in crank-angle order.

    ``time`` (m,) [s]; ``qpos`` (m, nq), ``qvel`` (m, nv); ``crank`` = (φ, ω, ε) each (m,);
    ``points[name]`` = (pos, vel, acc) each (m, 2); ``links[name]`` = (angle, angular velocity,
    angular acceleration) each (m,); ``sliders[name]`` = (s, v, a) each (m,); ``violation``
    (m,) [m] the largest loop gap; ``drive_torque`` (m,) [N·m]; ``forces``: reactions and the
    balancing torque (forward route); ``reduced_inertia`` (m,) [kg·m²]: q̇ᵀ·M·q̇/ω² less the
    rotor's armature.
    """

    time: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    crank: tuple[np.ndarray, np.ndarray, np.ndarray]
    points: dict
    links: dict
    sliders: dict
    violation: np.ndarray
    drive_torque: np.ndarray
    forces: ForceSamples
    reduced_inertia: np.ndarray

    def arrays(self) -> dict[str, np.ndarray]:
        """Every sampled quantity by name, in SI units (``linkgen simulate -o``'s NPZ keys), named
        as ``analyze`` and ``forces`` name them: t, qpos, qvel, loop_gap, phi, omega, epsilon,
        drive_torque (the actuator's), balancing_torque and reduced_inertia (as ``forces``),
        P.position|velocity|acceleration (m, 2), L.angle|angular_velocity|angular_acceleration,
        S.displacement|velocity|acceleration, the forward route's J.force (m, 2) and, for a
        prismatic pair S, S.normal_force and S.moment."""
        f = self.forces  # forward route, the kinetostatics' sign conventions
        out = {"t": self.time, "qpos": self.qpos, "qvel": self.qvel, "loop_gap": self.violation,
               "phi": self.crank[0], "omega": self.crank[1], "epsilon": self.crank[2], "drive_torque": self.drive_torque,
               "balancing_torque": f.balancing_torque, "reduced_inertia": self.reduced_inertia}
        for p, (x, v, a) in self.points.items():
            out |= {f"{p}.position": x, f"{p}.velocity": v, f"{p}.acceleration": a}
        for n, (x, v, a) in self.links.items():
            out |= {f"{n}.angle": x, f"{n}.angular_velocity": v, f"{n}.angular_acceleration": a}
        for n, (x, v, a) in self.sliders.items():
            out |= {f"{n}.displacement": x, f"{n}.velocity": v, f"{n}.acceleration": a}
        out |= {f"{k}.force": v for k, v in f.reactions.items()}
        out |= {f"{k}.normal_force": v for k, v in f.normal_force.items()}
        out |= {f"{k}.moment": v for k, v in f.moment.items()}
        return out

    def columns(self) -> dict[str, np.ndarray]:
        """``arrays()`` as CSV columns (``linkgen simulate -o FILE.csv``), the headers as
        ``analyze`` and ``forces`` write them: "name [unit]", a vector's components as .x, .y;
        qpos and qvel (MuJoCo's own coordinates) only in the NPZ."""
        cols = {}
        for k, v in self.arrays().items():
            if k in ("qpos", "qvel"):
                continue
            unit = SAMPLE_UNITS[k.rsplit(".", 1)[-1]]
            if v.ndim == 2:
                cols |= {f"{k}.{axis} [{unit}]": v[:, i] for i, axis in enumerate("xy")}
            else:
                cols[f"{k} [{unit}]"] = v
        return cols


# The unit of each quantity ``Samples.arrays`` names (the last part of its key).
SAMPLE_UNITS = {"t": "s", "loop_gap": "m", "phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "drive_torque": "N·m",
                "balancing_torque": "N·m", "reduced_inertia": "kg·m²", "position": "m", "velocity": "m/s",
                "acceleration": "m/s²", "angle": "rad", "angular_velocity": "rad/s", "angular_acceleration": "rad/s²",
                "displacement": "m", "force": "N", "normal_force": "N", "moment": "N·m"}


def moving_points(mech) -> list[str]:
    ground = set(mech.link("ground").points)
    return [p for p in mech.points if p not in ground]


def read_samples(asm: Assembly, model: mujoco.MjModel, time: np.ndarray, qpos: np.ndarray, qvel: np.ndarray,
                 drive_ctrl: float, slider_ref: dict[str, float]) -> Samples:
    """Every compared quantity at the states (time (m,), qpos (m, nq), qvel (m, nv)); the
    motor pushes ``drive_ctrl`` [N·m]; ``slider_ref`` [m] is each slider's displacement at the
    reference pose (``mujoco.posed.slider_reference``)."""
    mech = asm.mechanism
    m = time.shape[0]
    d = mujoco.MjData(model)
    crank_j = model.joint(mech.drive.joint)
    armature = float(model.dof_armature[crank_j.dofadr[0]])  # the rotor
    g = np.array(mech.gravity)
    out_pts = {p: np.zeros((m, 3, 2)) for p in moving_points(mech)}
    out_lnk = {n: np.zeros((m, 3)) for n in mech.moving_links}
    out_sld = {n: np.zeros((m, 3)) for n in asm.guides}
    crank = np.zeros((m, 3))
    viol, torque, inertia = np.zeros(m), np.zeros(m), np.zeros(m)
    tree = spanning_tree(asm)
    r6, mv, states = np.zeros(6), np.zeros(model.nv), []
    # an equality row's violation as a length [m]: a connect's is one; a gear coupling's is an
    # angle [rad], times the planet's reach from its centre
    lever = np.ones(max(model.neq, 1))
    for gear in mech.gears:
        lever[model.equality(f"gear:{gear.name}").id] = max(asm.shapes[gear.planet].span(), 1e-300)

    def drive_value(crank_body) -> float:
        """The crank's angle [rad], or a prismatic drive's stroke [m] (its slide joint's q from the
        reference pose's)."""
        if mech.slide_drive:
            return slider_ref[mech.drive.joint] + float(d.qpos[crank_j.qposadr[0]])
        return math.atan2(crank_body.xmat[3], crank_body.xmat[0])

    for k in range(m):
        d.qpos[:], d.qvel[:], d.time = qpos[k], qvel[k], time[k]
        d.ctrl[:] = drive_ctrl
        mujoco.mj_kinematics(model, d)
        mujoco.mj_comPos(model, d)
        crank_body = d.body(body_name(mech.crank))
        at = drive_value(crank_body)
        apply_loads(asm, model, d, at)
        mujoco.mj_forward(model, d)
        if mech.frictions:  # the friction at the state's own crank acceleration (mujoco.friction)
            apply_loads(asm, model, d, at, float(d.qacc[crank_j.dofadr[0]]))
            mujoco.mj_forward(model, d)
        mujoco.mj_rnePostConstraint(model, d)
        states.append(forward_forces(asm, model, d))
        mujoco.mj_mulM(model, d, mv, d.qvel)
        w = d.qvel[crank_j.dofadr[0]]
        inertia[k] = float(d.qvel @ mv) / (w * w) - armature
        for p in out_pts:
            sid = model.site(p).id
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_SITE, sid, r6, 0)
            v = r6[3:5].copy()
            mujoco.mj_objectAcceleration(model, d, mujoco.mjtObj.mjOBJ_SITE, sid, r6, 0)
            out_pts[p][k] = (d.site(p).xpos[:2], v, r6[3:5] + g)  # MuJoCo reports a - g
        for n in out_lnk:
            b = d.body(body_name(n))
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_BODY, b.id, r6, 0)
            w = r6[2]
            mujoco.mj_objectAcceleration(model, d, mujoco.mjtObj.mjOBJ_BODY, b.id, r6, 0)
            out_lnk[n][k] = (math.atan2(b.xmat[3], b.xmat[0]), w, r6[2])
        for parent, child, pair in tree.tree:
            if pair.kind == "P":
                j = model.joint(pair.name)
                sign = 1.0 if child == asm.guides[pair.name].slider else -1.0
                s0 = slider_ref[pair.name]
                out_sld[pair.name][k] = (s0 + sign * d.qpos[j.qposadr[0]], sign * d.qvel[j.dofadr[0]],
                                         sign * d.qacc[j.dofadr[0]])
        crank[k] = (drive_value(crank_body), d.qvel[crank_j.dofadr[0]], d.qacc[crank_j.dofadr[0]])
        viol[k] = float(np.max(np.abs(d.efc_pos[: d.ne]) * lever[d.efc_id[: d.ne]])) if d.ne else 0.0
        torque[k] = d.actuator(DRIVE_ACTUATOR).force[0] - armature * d.qacc[crank_j.dofadr[0]]
    # continuous over the run (the closed form is 2π-periodic); a stroke needs no unwrapping
    phi = crank[:, 0] if mech.slide_drive else np.unwrap(crank[:, 0])
    return Samples(time, qpos, qvel, (phi, crank[:, 1], crank[:, 2]),
                   {p: tuple(a[:, j] for j in range(3)) for p, a in out_pts.items()},
                   {n: tuple(a[:, j] for j in range(3)) for n, a in out_lnk.items()},
                   {n: tuple(a[:, j] for j in range(3)) for n, a in out_sld.items()},
                   viol, torque, ForceSamples.stack(states), inertia)


__all__ = ["Samples", "moving_points", "read_samples"]
